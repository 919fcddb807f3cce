#include "device/can_receive.h"

#include "device/device.h"

namespace swum::host {

bool receive_until(io::CanBus& bus, std::chrono::steady_clock::time_point deadline, io::CanFrame& frame,
                   const std::string& device) {
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline -
                                                                            std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    const io::CanResult r = bus.receive(frame, left);
    if (r.status == io::CanStatus::timeout) return false;
    if (r.status == io::CanStatus::error_frame) {
      const io::CanErrorInfo e = io::decode_error_frame(frame);
      if (e.bus_off) throw DeviceError(device + ": controller is bus-off (" + e.describe() + ")");
      continue;
    }
    if (!r.ok()) throw DeviceError(device + ": receive failed: " + r.message);
    return true;
  }
}

}  // namespace swum::host
