#include "device/device_options.h"

namespace swum::host {

void add_device_options(CLI::App& sub, DeviceOptions& o) {
  auto* modbus = sub.add_option("--modbus", o.address.modbus,
                                "live device over Modbus: tcp://HOST:PORT or rtu:DEVICE:BAUD");
  auto* can = sub.add_option("--can", o.address.can, "live device over CAN: IFACE[:NODE] (node 1..127, default 1)");
  modbus->excludes(can);
  sub.add_option("--connect-timeout-ms", o.connect_timeout_ms, "connect / first answer timeout (ms)")
      ->check(CLI::Range(1, 600000))
      ->capture_default_str();
  sub.add_option("--timeout-ms", o.response_timeout_ms, "response timeout per request (ms)")
      ->check(CLI::Range(1, 600000))
      ->capture_default_str();
}

}  // namespace swum::host
