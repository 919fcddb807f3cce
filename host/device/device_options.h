// The device options every live subcommand takes: --modbus | --can | --canopen (with the CANopen
// node's --sync-ticks), --connect-timeout-ms, --timeout-ms.
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "device/device.h"

namespace swum::host {

struct DeviceOptions {
  DeviceAddress address;
  int connect_timeout_ms = 1000;
  int response_timeout_ms = 500;
  DeviceTimeouts timeouts() const {
    return {std::chrono::milliseconds(connect_timeout_ms), std::chrono::milliseconds(response_timeout_ms)};
  }
  // open_device() of the address given, the CANopen node's settings completed from the options.
  // `tick_hz`: the device's tick rate (--tick-hz), the length of a lockstep SYNC cycle.
  std::unique_ptr<Device> open(double tick_hz) const;
};

// Adds --modbus, --can, --canopen (one of them: open_device() refuses two), --sync-ticks,
// --connect-timeout-ms, --timeout-ms. With `tick_hz` (the commands that
// have no --tick-hz of their own: log, sweep, pick) also --tick-hz, bound to it.
void add_device_options(CLI::App& sub, DeviceOptions& options, double* tick_hz = nullptr);

}  // namespace swum::host
