#include "device/device_options.h"

#include <stdexcept>

namespace swum::host {

void add_device_options(CLI::App& sub, DeviceOptions& o, double* tick_hz) {
  auto* modbus = sub.add_option("--modbus", o.address.modbus,
                                "live device over Modbus: tcp://HOST:PORT or rtu:DEVICE:BAUD");
  auto* can = sub.add_option("--can", o.address.can, "live device over CAN: IFACE[:NODE] (node 1..127, default 1)");
  modbus->excludes(can);
  auto* canopen = sub.add_option("--canopen", o.address.canopen,
                                 "live CiA 402 drive over CANopen: IFACE:NODE (node 1..127; swum is its master, "
                                 "docs/canopen.md)");
  sub.add_option("--sync-ticks", o.address.canopen_node.sync_ticks,
                 "--canopen: the node runs in lockstep (swum-emu --clock external --sync-ticks N), N ticks per SYNC")
      ->check(CLI::Range(1, 65535))
      ->needs(canopen);
  sub.add_option("--connect-timeout-ms", o.connect_timeout_ms, "connect / first answer timeout (ms)")
      ->check(CLI::Range(1, 600000))
      ->capture_default_str();
  sub.add_option("--timeout-ms", o.response_timeout_ms, "response timeout per request (ms)")
      ->check(CLI::Range(1, 600000))
      ->capture_default_str();
  if (tick_hz != nullptr) {
    sub.add_option("--tick-hz", *tick_hz, "lockstep (--canopen --sync-ticks): the device's tick rate")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
  }
}

std::unique_ptr<Device> DeviceOptions::open(double tick_hz) const {
  DeviceAddress a = address;
  a.canopen_node.tick_hz = tick_hz;
  return open_device(a, timeouts());
}

}  // namespace swum::host
