// A device for tests that obeys the contract of host/device/device.h like swum-emu does: a device
// clock that advances per read, enable/disable/fault states, a command watchdog on the device
// clock, an amplitude slew limit, first-order speed response to a resonance curve whose peak
// drifts down with voltage, and silent rejection (counted, reason readable) like CAN.
// Fault injection: numerical fault at a frequency, rejections, a broken link after N reads,
// any fault code at a device time. Lockstep (step()) when lockstep_mode is set.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <vector>

#include "device/device.h"

namespace swum::host::test {

class FakeDevice : public Device {
 public:
  double read_step_s = 0.002;  // device time per read
  double watchdog_s = 0.1;     // 0 = off
  double speed_time_constant_s = 0.005;
  double max_frequency_hz = 50000.0;            // setpoints above are rejected (reason 1)
  std::optional<double> fault_at_frequency_hz;  // numerical fault when driven there (once)
  std::optional<int> fail_after_reads;          // the link breaks (DeviceError) after N reads
  std::function<void(int reads)> on_read;       // e.g. raise(SIGINT)
  // (device time, fault code): trips once, at the first read at or after that time while enabled.
  std::vector<std::pair<double, int>> fault_schedule;
  bool lockstep_mode = false;   // step() runs ticks / tick_hz of device time per call
  bool electrical_port = true;  // reports the electrical values and the stator temperature
  double tick_hz = 10000.0;

  // Resonance drift: peak at 40.4 kHz at 100 V, 1 Hz lower per V above.
  static double peak_hz(double amplitude_v) { return 40400.0 - (amplitude_v - 100.0); }
  static double steady_speed_mm_s(double frequency_hz, double amplitude_v) {
    const double detune = (frequency_hz - peak_hz(amplitude_v)) / 300.0;
    return 2.0 * amplitude_v / (1.0 + detune * detune);
  }

  std::string name() const override { return "fake"; }
  void set_drive(const DriveSetpoint& s) override {
    if (s.frequency_hz > max_frequency_hz) return reject(1);
    setpoint_ = s;
    setpoints.push_back(s);
    setpoint_times_s.push_back(time_s);
    commanded();
  }
  void set_slew(double, double amplitude_v_per_s) override {
    slew_v_per_s = amplitude_v_per_s;
    commanded();
  }
  void command(DeviceAction a) override {
    actions.push_back(a);
    commanded();
    switch (a) {
      case DeviceAction::keep_alive: break;
      case DeviceAction::enable:
        if (state == 2) return reject(12);
        state = 1;
        break;
      case DeviceAction::disable:
        if (state == 1) state = 0;
        break;
      case DeviceAction::reset_fault:
        if (state == 2) state = 0, fault = 0;
        break;
    }
  }
  bool lockstep() const override { return lockstep_mode; }
  DeviceTelemetry step(const DriveSetpoint& s, const DriveSlew& slew, DeviceAction a, std::uint32_t ticks) override {
    if (!lockstep_mode) return Device::step(s, slew, a, ticks);
    ++steps;
    if (a == DeviceAction::enable && state == 2) {
      reject(12);  // like swum-emu: the whole command is refused, the ticks still run
    } else {
      set_slew(slew.frequency_hz_per_s, slew.amplitude_v_per_s);
      set_drive(s);
      command(a);
    }
    const double per_read_s = read_step_s;
    read_step_s = ticks / tick_hz;
    DeviceTelemetry t = read();
    read_step_s = per_read_s;
    total_ticks += ticks;
    t.tick = total_ticks;
    return t;
  }
  DeviceTelemetry read() override {
    ++reads;
    if (fail_after_reads && reads > *fail_after_reads) throw DeviceError("fake: link down");
    if (on_read) on_read(reads);
    time_s += read_step_s;
    if (state == 1 && watchdog_s > 0.0 && time_s - last_command_s_ > watchdog_s) trip(1);
    if (state == 1 && fault_at_frequency_hz && std::abs(setpoint_.frequency_hz - *fault_at_frequency_hz) < 0.1) {
      fault_at_frequency_hz.reset();
      trip(2);
    }
    for (auto& [at_s, code] : fault_schedule) {
      if (state == 1 && code != 0 && time_s >= at_s - 1e-12) {
        trip(code);
        code = 0;
      }
    }
    const double target_amplitude_v = state == 1 ? setpoint_.amplitude_v : 0.0;
    const double max_step = slew_v_per_s > 0.0 ? slew_v_per_s * read_step_s : 1e9;
    amplitude_v_out += std::clamp(target_amplitude_v - amplitude_v_out, -max_step, max_step);
    const double direction = setpoint_.phase_deg < 0.0 ? -1.0 : 1.0;
    const double target_speed = state == 1 ? direction * steady_speed_mm_s(setpoint_.frequency_hz, amplitude_v_out)
                                           : 0.0;
    speed += (target_speed - speed) * (1.0 - std::exp(-read_step_s / speed_time_constant_s));
    max_amplitude_v_seen = std::max(max_amplitude_v_seen, amplitude_v_out);
    DeviceTelemetry t;
    t.device_time_s = time_s;
    t.lockstep = lockstep_mode;
    t.received = std::chrono::steady_clock::now();
    t.state = state;
    t.fault_code = fault;
    t.drive_on = state == 1 && amplitude_v_out > 0.0;
    t.last_reject = last_reject;
    t.reject_count = reject_count;
    t.speed_mm_s = speed;
    t.frequency_hz = setpoint_.frequency_hz;
    t.amplitude_v = amplitude_v_out;
    t.phase_deg = setpoint_.phase_deg;
    t.load_n = setpoint_.load_n;
    if (electrical_port) {
      // Current in proportion to the voltage, the motional phase crossing 0 at the peak.
      const double current_a = 6e-4 * amplitude_v_out;
      const double motional_deg = std::clamp((peak_hz(amplitude_v_out) - setpoint_.frequency_hz) / 10.0, -90.0, 90.0);
      t.electrical = protocol::ElectricalValues{current_a,
                                                0.98 * current_a,
                                                60.0,
                                                59.0,
                                                motional_deg,
                                                motional_deg,
                                                0.02 * amplitude_v_out,
                                                0.019 * amplitude_v_out};
      t.stator_temperature_c = 20.0 + 0.5 * time_s;
    }
    longest_command_gap_s = std::max(longest_command_gap_s, state == 1 ? time_s - last_command_s_ : 0.0);
    return t;
  }

  int state = 0;
  int fault = 0;
  int reads = 0;
  int last_reject = 0;
  std::uint32_t reject_count = 0;
  int faults_tripped = 0;
  int steps = 0;
  std::uint64_t total_ticks = 0;
  double time_s = 0.0;
  double amplitude_v_out = 0.0;
  double speed = 0.0;
  double slew_v_per_s = 0.0;
  double max_amplitude_v_seen = 0.0;
  double longest_command_gap_s = 0.0;
  std::vector<DriveSetpoint> setpoints;
  std::vector<double> setpoint_times_s;  // device clock when each setpoint arrived
  std::vector<DeviceAction> actions;

 private:
  void commanded() { last_command_s_ = time_s; }
  void reject(int reason) {
    last_reject = reason;
    ++reject_count;
  }
  void trip(int code) {
    state = 2;
    fault = code;
    amplitude_v_out = 0.0;
    ++faults_tripped;
  }
  DriveSetpoint setpoint_;
  double last_command_s_ = 0.0;
};

}  // namespace swum::host::test
