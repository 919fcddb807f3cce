// Receiving on a CAN bus as the host's CAN devices do (can_device.cpp, canopen_device.cpp): the
// next data frame before a deadline, the bus's warnings passed over, a bus-off or a failed
// receive reported as the DeviceError of the device that waits.
#pragma once

#include <chrono>
#include <string>

#include "can_bus.h"

namespace swum::host {

// The next frame before `deadline` into `frame`: false when the deadline passes first. Error
// frames are skipped (warnings, arbitration: the bus keeps going); bus-off and a failed receive
// throw DeviceError("<device>: ...").
bool receive_until(io::CanBus& bus, std::chrono::steady_clock::time_point deadline, io::CanFrame& frame,
                   const std::string& device);

}  // namespace swum::host
