// CiA 402's power state machine as the host's master walks it (IEC 61800-7-201 / CiA 402-2,
// "statusword" and "controlword"): the one controlword that moves the drive a transition nearer
// to what the host asked for, and the drive's state as the host's DeviceTelemetry reports it.
// The wire codes (states and their statusword coding, command words, the faults' 0x603F codes)
// are canopen/cia402.h's, the codec the drive writes with (canopen::state_of reads a statusword). Pure: the CANopen
// device (canopen_device.cpp) sends the words and reads the states back, one transition per exchange, checking each.
#pragma once

#include <cstdint>

#include "cia402.h"
#include "codes.h"

namespace swum::host::cia402 {

using canopen::Cia402State;

// What the host last asked for (DeviceAction): the drive running (operation enabled), or off at
// rest in "ready to switch on" (from where "on" is two transitions away), after a fault reset
// when `reset`. `none`: nothing asked yet (a passive `swum log`): the controlword is left alone.
enum class Goal : std::uint8_t { none, on, off, reset };

// Whether the drive is where `goal` wants it.
[[nodiscard]] bool reached(Cia402State state, Goal goal);
// The controlword that takes the drive one transition nearer to `goal` from `state` (it repeats
// `last` when the goal is reached or none): enable 0x06 -> 0x07 -> 0x0F, disable 0x07 -> 0x06,
// a fault reset as the rising edge of bit 7 (0x00 first when the last word held it), nothing
// but 0x00 in fault reaction active (an edge there would be lost) or for a word of no state.
// Halt (bit 8) is never set.
[[nodiscard]] std::uint16_t next_controlword(Cia402State state, Goal goal, std::uint16_t last);

// The amplifier state of swum's other protocols: enabled while the drive function is on
// (operation enabled, quick stop active), fault in the two fault states, disabled otherwise.
[[nodiscard]] protocol::AmpState amp_state(Cia402State state);

}  // namespace swum::host::cia402
