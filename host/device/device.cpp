#include "device/device.h"

#include <stdexcept>

#include "codes.h"
#include "device/can_device.h"
#include "device/canopen_device.h"
#include "device/modbus_device.h"

namespace swum::host {

std::unique_ptr<Device> open_device(const DeviceAddress& address, const DeviceTimeouts& timeouts) {
  if (!address.modbus.empty() + !address.can.empty() + !address.canopen.empty() > 1) {
    throw std::invalid_argument("give one device: --modbus, --can or --canopen, not two");
  }
  if (timeouts.connect.count() <= 0 || timeouts.response.count() <= 0) {
    throw std::invalid_argument("--timeout-ms: must be > 0");
  }
  if (!address.modbus.empty()) return std::make_unique<ModbusDevice>(address.modbus, timeouts);
  if (!address.can.empty()) return std::make_unique<CanDevice>(address.can, timeouts);
  if (!address.canopen.empty()) return std::make_unique<CanopenDevice>(address.canopen, address.canopen_node, timeouts);
  throw std::invalid_argument(
      "no device: give --modbus tcp://HOST:PORT | rtu:DEVICE:BAUD, --can IFACE[:NODE] or --canopen IFACE:NODE");
}

DeviceTelemetry Device::step(const DriveSetpoint&, const DriveSlew&, DeviceAction, std::uint32_t) {
  throw DeviceError(name() + ": lockstep stepping is not supported by this device");
}

std::string reject_reason_name(int code) {
  if (code < 0 || code > 255) return "reason " + std::to_string(code);
  const char* text = protocol::to_string(static_cast<protocol::Reason>(code));
  if (text == nullptr || std::string(text) == "?" || std::string(text).empty()) return "reason " + std::to_string(code);
  return text;
}

}  // namespace swum::host
