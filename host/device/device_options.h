// The device options every live subcommand takes: --modbus | --can, --timeout-ms.
#pragma once

#include <CLI/CLI.hpp>

#include "device/device.h"

namespace swum::host {

struct DeviceOptions {
  DeviceAddress address;
  int connect_timeout_ms = 1000;
  int response_timeout_ms = 500;
  DeviceTimeouts timeouts() const {
    return {std::chrono::milliseconds(connect_timeout_ms), std::chrono::milliseconds(response_timeout_ms)};
  }
};

// Adds --modbus, --can, --connect-timeout-ms, --timeout-ms (mutually exclusive device forms).
void add_device_options(CLI::App& sub, DeviceOptions& options);

}  // namespace swum::host
