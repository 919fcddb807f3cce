// A live amplifier as the host tool sees it: a narrow command / telemetry interface with one
// adapter per protocol (Modbus: modbus_device.cpp, CAN: can_device.cpp, CANopen CiA 402:
// canopen_device.cpp). The sweep and log
// code only talks to this interface, so tests can drive it with a fake and a real board that
// speaks docs/protocols.md drops in for swum-emu.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "codes.h"
#include "telemetry.h"

namespace swum::host {

// Anything that went wrong talking to the device: the message names the device, what was
// attempted and why (errno text, exception code, timeout, rejection reason).
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DriveSetpoint {
  double frequency_hz = 40400.0;
  double amplitude_v = 0.0;
  double phase_deg = 90.0;  // B ahead of A; the sign selects the direction
  double load_n = 0.0;      // emulated load force (an emulator input; a real board ignores it)
};

// Slew limits of the drive set-points (0 = unlimited): the device never ramps faster.
struct DriveSlew {
  double frequency_hz_per_s = 0.0;
  double amplitude_v_per_s = 0.0;
};

// The action of a command: the wire's (keep_alive, enable, disable, reset_fault), one type on
// both ends.
using DeviceAction = protocol::Action;

// One telemetry sample, in physical units. Not protocol::Telemetry (the device's own snapshot):
// this is what the host learns of it through one protocol - the device clock, tick and sample
// counter only when that protocol carries them, the host's reception time, counters with their
// wire modulus - and the state, fault and reject codes as the wire sent them (ints: a board may
// send a code this build does not know, and a log records it as sent). The electrical port is
// the protocol's value type.
struct DeviceTelemetry {
  // Device clock (the emulator's emulated time) when the protocol carries one; the host
  // times settle/dwell on it so a sped-up emulator and a real board behave the same.
  std::optional<double> device_time_s;
  std::chrono::steady_clock::time_point received;  // host clock at reception
  // Ticks the device has completed, when the protocol carries the counter (Modbus; in lockstep
  // it counts exactly the ticks the host asked for).
  std::optional<std::uint64_t> tick;
  bool lockstep = false;  // the device's clock is external (Modbus input 35); false when not carried
  // Running sample counter of the device's telemetry (CAN status counter, mod 256), for gap
  // counting; absent when the protocol is polled (Modbus: every read is a fresh snapshot).
  std::optional<std::uint32_t> sample_counter;
  std::uint32_t sample_counter_modulus = 0;
  int state = 0;  // protocol::AmpState: 0 disabled, 1 enabled, 2 fault
  int fault_code = 0;
  bool drive_on = false;
  bool enable_line = true;
  int last_reject = 0;
  std::uint32_t reject_count = 0;  // modulo the protocol's counter width
  std::uint32_t reject_count_modulus = 0;
  double speed_mm_s = 0.0;
  double position_mm = 0.0;
  double tip_normal_um = 0.0;
  double tip_tangential_um = 0.0;
  double frequency_hz = 0.0;  // driven (after slew)
  double amplitude_v = 0.0;   // driven (0 when off)
  double phase_deg = 0.0;
  double load_n = 0.0;
  double lateness_p99_us = 0.0;
  double lateness_max_us = 0.0;
  std::uint32_t overruns = 0;
  // The electrical port as the wire carries it (docs/protocols.md "Electrical port"); absent when
  // the device did not report it (a CAN set without the ElectricalA/B frames).
  std::optional<protocol::ElectricalValues> electrical;
  std::optional<double> stator_temperature_c;

  bool is(protocol::AmpState s) const { return state == static_cast<int>(s); }
  bool rejected_for(protocol::Reason r) const { return last_reject == static_cast<int>(r); }
};

class Device {
 public:
  virtual ~Device() = default;
  // "modbus tcp://127.0.0.1:1502", "can vcan0 node 1", "canopen vcan0 node 3".
  virtual std::string name() const = 0;
  virtual void set_drive(const DriveSetpoint& setpoint) = 0;
  virtual void set_slew(double frequency_hz_per_s, double amplitude_v_per_s) = 0;
  virtual void command(DeviceAction action) = 0;
  // The next telemetry sample (Modbus: a fresh read; CAN: the next complete set of frames).
  virtual DeviceTelemetry read() = 0;

  // Lockstep (docs/protocols.md, "Lockstep"): true when the device's clock advances only when
  // the host steps it (swum-emu --clock external), as the device said when it was opened.
  virtual bool lockstep() const { return false; }
  // One lockstep control cycle in one exchange: apply the action, the set-points and the slew
  // limits together, run `ticks` device ticks (1..65535), and return the telemetry after them.
  // Throws DeviceError when the protocol cannot step or the device refuses (not in lockstep).
  virtual DeviceTelemetry step(const DriveSetpoint& setpoint, const DriveSlew& slew, DeviceAction action,
                               std::uint32_t ticks);
};

struct DeviceTimeouts {
  std::chrono::milliseconds connect{1000};
  std::chrono::milliseconds response{500};
};

// What a CANopen master is told of a swum CiA 402 node because its bus does not carry it
// (docs/canopen.md, "The host tool as a master"): no CiA 402 object says whether the node runs in
// lockstep, how long its SYNC cycle is, or how its amplifier reads a voltage.
struct CanopenNode {
  // swum-emu --clock external --sync-ticks N: the node is in lockstep, N ticks per SYNC; 0: it
  // runs on the wall clock.
  std::uint32_t sync_ticks = 0;
  double tick_hz = 10000.0;  // its --tick-hz: in lockstep a SYNC is sync_ticks / tick_hz of device time
};

// Where the device is: exactly one of the three forms of the command line.
struct DeviceAddress {
  std::string modbus;   // tcp://HOST:PORT or rtu:DEVICE:BAUD
  std::string can;      // IFACE[:NODE] (the swum frame set)
  std::string canopen;  // IFACE:NODE (a CiA 402 drive)
  CanopenNode canopen_node;
  bool empty() const { return modbus.empty() && can.empty() && canopen.empty(); }
};

// Opens and checks the connection (the device must answer within the timeouts).
std::unique_ptr<Device> open_device(const DeviceAddress& address, const DeviceTimeouts& timeouts);

// The name of a reject reason code (docs/protocols.md), "reason N" when unknown.
std::string reject_reason_name(int code);

}  // namespace swum::host
