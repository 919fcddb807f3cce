#include "device/device_sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <string>
#include <thread>

#include "analysis/measurements/measurements.h"  // fault_status_word
#include "can_codec.h"                           // the CAN slew step (the coarser of the two protocols)
#include "commands/command_error.h"
#include "device/stop_signal.h"

namespace swum::host {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kFrequencyReachedHz = 0.5;
constexpr double kAmplitudeReachedV = 0.5;

// One conversation with the device: timing on the device clock when it has one, keep-alives,
// and a watch on the device's reject counter so a rejected command never passes silently.
class Session {
 public:
  Session(Device& device, double poll_interval_s) : device_(device), poll_interval_s_(poll_interval_s) {
    const DeviceTelemetry t = device_.read();
    origin_ = Clock::now();
    reject_count_ = t.reject_count;
    last_ = t;
    last_command_host_ = Clock::now();
    last_command_device_s_ = time_of(t);
    start_s_ = time_of(t);
  }

  double time_of(const DeviceTelemetry& t) const {
    if (t.device_time_s) return *t.device_time_s;
    return std::chrono::duration<double>(t.received - origin_).count();
  }

  // Device time since the session began (the first telemetry read).
  double session_time() const { return time_of(last_) - start_s_; }

  void noted_command() {
    last_command_host_ = Clock::now();
    last_command_device_s_ = time_of(last_);
  }
  void set_drive(const DriveSetpoint& s) {
    check_stop();
    device_.set_drive(s);
    noted_command();
  }
  void command(DeviceAction a) {
    check_stop();
    device_.command(a);
    noted_command();
  }

  // Reads one sample, keeps the watchdog fed, raises on rejects and Ctrl-C.
  const DeviceTelemetry& read(double keep_alive_s) {
    check_stop();
    // Polled devices (Modbus) are paced; streamed ones (CAN) pace themselves, and sleeping
    // would only let their telemetry sets queue up.
    if (!last_.sample_counter) {
      std::this_thread::sleep_until(last_.received + std::chrono::duration_cast<Clock::duration>(
                                                         std::chrono::duration<double>(poll_interval_s_)));
    }
    keep_alive_if_due(keep_alive_s);  // before a read that may block for a while ...
    try {
      last_ = device_.read();
    } catch (const DeviceError&) {
      check_stop();  // a call cut short by Ctrl-C is the stop, not a device failure
      throw;
    }
    keep_alive_if_due(keep_alive_s);  // ... and after it
    if (last_.reject_count != reject_count_) {
      reject_count_ = last_.reject_count;
      // A keep-alive that crossed a fault is refused with "fault active": the fault itself is
      // what the caller handles.
      if (!last_.rejected_for(protocol::Reason::fault_active) && !last_.is(protocol::AmpState::fault)) {
        throw DeviceError(
            device_.name() + ": the device rejected a command: " + reject_reason_name(last_.last_reject) +
            (last_.rejected_for(protocol::Reason::enable_line_low) ? " (the hardware enable input is low)" : ""));
      }
    }
    return last_;
  }

  // Reads until `done(sample)` or `timeout_s` of device time; false on timeout.
  bool read_until(const std::function<bool(const DeviceTelemetry&)>& done, double timeout_s, double keep_alive_s) {
    const double start = time_of(last_);
    const auto host_start = Clock::now();
    for (;;) {
      const DeviceTelemetry& t = read(keep_alive_s);
      if (done(t)) return true;
      if (t.is(protocol::AmpState::fault)) return false;
      // Host-side guard too: a device clock that stands still must not hang us.
      const double host_s = std::chrono::duration<double>(Clock::now() - host_start).count();
      if (time_of(t) - start > timeout_s || host_s > 10.0 * timeout_s + 5.0) return false;
    }
  }

  void keep_alive_if_due(double keep_alive_s) {
    const bool host_due = Clock::now() - last_command_host_ >= std::chrono::duration<double>(keep_alive_s);
    const bool device_due = time_of(last_) - last_command_device_s_ >= keep_alive_s;
    if (host_due || device_due) command(DeviceAction::keep_alive);
  }

  static void check_stop() {
    if (StopSignal::requested()) throw CommandError("interrupted: drive switched off", kExitInterrupted);
  }

  Device& device() { return device_; }
  const DeviceTelemetry& last() const { return last_; }

 private:
  Device& device_;
  double poll_interval_s_;
  Clock::time_point origin_;
  std::uint32_t reject_count_ = 0;
  DeviceTelemetry last_;
  Clock::time_point last_command_host_;
  double last_command_device_s_ = 0.0;
  double start_s_ = 0.0;
};

// The drive goes off however the sweep ends (normal end, device error, Ctrl-C).
class DriveOffGuard {
 public:
  explicit DriveOffGuard(Device& device) : device_(device) {}
  ~DriveOffGuard() {
    try {
      device_.command(DeviceAction::disable);
    } catch (...) {
      // The device is gone or broken: nothing more we can do; the caller reports the cause.
    }
  }
  DriveOffGuard(const DriveOffGuard&) = delete;
  DriveOffGuard& operator=(const DriveOffGuard&) = delete;

 private:
  Device& device_;
};

class Sweeper {
 public:
  Sweeper(Device& device, const DeviceSweepPlan& plan, const DeviceSweepStart& start)
      : session_(device, plan.poll_interval_s),
        plan_(plan),
        sweep_id_(start.first_sweep_id - 1),
        time_offset_s_(start.time_offset_s) {}

  // Drive on at `amplitude_v`, reached by the device's slew limit, at `frequency_hz`.
  bool ramp_to(double amplitude_v, double frequency_hz, double load_n) {
    DriveSetpoint s{frequency_hz, amplitude_v, plan_.phase_deg, load_n};
    session_.set_drive(s);
    const double ramp_s = std::abs(amplitude_v - session_.last().amplitude_v) /
                          std::max(plan_.amplitude_slew_v_per_s, 1e-9);
    return session_.read_until(
        [&](const DeviceTelemetry& t) {
          return std::abs(t.amplitude_v - amplitude_v) <= kAmplitudeReachedV &&
                 std::abs(t.frequency_hz - frequency_hz) <= kFrequencyReachedHz;
        },
        2.0 * ramp_s + 1.0, plan_.keep_alive_s);
  }

  // Starts the drive from rest: the points measured after it are a new continuous sweep.
  bool start_voltage(double amplitude_v, double frequency_hz, double load_n) {
    ++sweep_id_;
    if (session_.last().is(protocol::AmpState::fault)) session_.command(DeviceAction::reset_fault);
    session_.set_drive({frequency_hz, 0.0, plan_.phase_deg, load_n});
    session_.command(DeviceAction::enable);
    if (!session_.read_until([](const DeviceTelemetry& t) { return t.is(protocol::AmpState::enabled); }, 1.0,
                             plan_.keep_alive_s)) {
      throw DeviceError(session_.device().name() + ": the drive did not enable (state " +
                        std::to_string(session_.last().state) + ", fault " +
                        std::to_string(session_.last().fault_code) +
                        (session_.last().enable_line ? "" : ", enable input low") + ")");
    }
    return ramp_to(amplitude_v, frequency_hz, load_n);
  }

  SweepRow measure(double amplitude_v, double frequency_hz, double load_n) {
    SweepRow row = unmeasured(amplitude_v, frequency_hz, load_n, "timeout");
    session_.set_drive({frequency_hz, amplitude_v, plan_.phase_deg, load_n});
    const bool reached = session_.read_until(
        [&](const DeviceTelemetry& t) { return std::abs(t.frequency_hz - frequency_hz) <= kFrequencyReachedHz; }, 1.0,
        plan_.keep_alive_s);
    if (!reached) return failed(row);
    const double settle_end = session_.time_of(session_.last()) + plan_.settle_s;
    if (!session_.read_until([&](const DeviceTelemetry& t) { return session_.time_of(t) >= settle_end; },
                             plan_.settle_s + 1.0, plan_.keep_alive_s)) {
      return failed(row);
    }
    const double dwell_end = session_.time_of(session_.last()) + plan_.dwell_s;
    row.time_s = time_now();
    double sum = 0.0, sum2 = 0.0, normal = 0.0, tangential = 0.0;
    int n = 0;
    // The electrical port and the stator temperature: means over the samples that carry them.
    SweepElectrical electrical;
    double temperature = 0.0;
    int n_electrical = 0, n_temperature = 0;
    const bool dwelt = session_.read_until(
        [&](const DeviceTelemetry& t) {
          if (!t.is(protocol::AmpState::enabled)) return false;
          sum += t.speed_mm_s;
          sum2 += t.speed_mm_s * t.speed_mm_s;
          normal += t.tip_normal_um;
          tangential += t.tip_tangential_um;
          ++n;
          if (t.electrical) {
            const protocol::ElectricalValues& e = *t.electrical;
            electrical.current_a_a += e.current_a_a;
            electrical.current_b_a += e.current_b_a;
            electrical.phase_a_deg += e.phase_a_deg;
            electrical.phase_b_deg += e.phase_b_deg;
            electrical.motional_phase_a_deg += e.motional_phase_a_deg;
            electrical.motional_phase_b_deg += e.motional_phase_b_deg;
            electrical.power_w += e.power_w();
            ++n_electrical;
          }
          if (t.stator_temperature_c) {
            temperature += *t.stator_temperature_c;
            ++n_temperature;
          }
          return session_.time_of(t) >= dwell_end;
        },
        plan_.dwell_s + 1.0, plan_.keep_alive_s);
    if (!dwelt || n == 0) return failed(row);
    row.ok = true;
    row.status = "ok";
    row.speed_mm_s = sum / n;
    row.tip_normal_um = normal / n;
    row.tip_tangential_um = tangential / n;
    row.speed_spread_mm_s = n > 1 ? std::sqrt(std::max(0.0, (sum2 - sum * sum / n) / (n - 1))) : 0.0;
    if (n_electrical > 0) {
      for (double* v :
           {&electrical.current_a_a, &electrical.current_b_a, &electrical.phase_a_deg, &electrical.phase_b_deg,
            &electrical.motional_phase_a_deg, &electrical.motional_phase_b_deg, &electrical.power_w}) {
        *v /= n_electrical;
      }
      row.electrical = electrical;
    }
    if (n_temperature > 0) row.stator_temperature_c = temperature / n_temperature;
    return row;
  }

  // A row of the current sweep at the current device time, not (yet) measured.
  SweepRow unmeasured(double amplitude_v, double frequency_hz, double load_n, const std::string& status) const {
    SweepRow row{amplitude_v, frequency_hz, load_n, false, status};
    row.time_s = time_now();
    row.sweep = sweep_id_;
    return row;
  }

  Session& session() { return session_; }

 private:
  // time_s of a row: device time since the session began, after the rows of earlier runs.
  double time_now() const { return time_offset_s_ + session_.session_time(); }

  SweepRow failed(SweepRow row) {
    row.ok = false;
    row.time_s = time_now();  // when it was given up
    // One word per status (CSV column): fault_command_timeout, fault_numerical, timeout.
    row.status = session_.last().is(protocol::AmpState::fault) ? fault_status_word(session_.last().fault_code)
                                                               : "timeout";
    return row;
  }

  Session session_;
  const DeviceSweepPlan& plan_;
  int sweep_id_;  // id of the continuous sweep under way (the first one started is sweep_id_ + 1)
  double time_offset_s_;
};

// The frequencies in sweep order: from the highest down.
std::vector<double> downward(std::vector<double> frequencies) {
  std::sort(frequencies.begin(), frequencies.end(), std::greater<>());
  return frequencies;
}

}  // namespace

void check_plan(const DeviceSweepPlan& plan) {
  if (plan.voltages.empty() || plan.frequencies_hz.empty() || plan.loads_n.empty()) {
    throw std::invalid_argument("sweep: need at least one voltage, frequency and load");
  }
  // Finite and bounded: a settle of "inf" would wait forever.
  if (!(plan.settle_s >= 0.0 && plan.settle_s <= 60.0))
    throw std::invalid_argument("--settle-ms: must be within 0..60000");
  if (!(plan.dwell_s > 0.0 && plan.dwell_s <= 60.0))
    throw std::invalid_argument("--dwell-ms: must be within (0, 60000]");
  // The protocols carry the slew limit in 1 V/s (Modbus) and 10 V/s (CAN) steps and read 0
  // as "unlimited": a slower ramp would silently become a voltage step.
  if (!(plan.amplitude_slew_v_per_s >= protocol::can::signals::kAuxAmplitudeSlew.factor &&
        plan.amplitude_slew_v_per_s <= 1e6)) {
    throw std::invalid_argument("--amplitude-slew-v-per-s: must be within 10..1000000 (0 would mean no ramp at all)");
  }
  if (!(plan.keep_alive_s > 0.0 && plan.keep_alive_s <= 0.05))
    throw std::invalid_argument("keep-alive interval must be within (0, 50] ms");
  if (!(plan.poll_interval_s >= 0.0 && plan.poll_interval_s < plan.keep_alive_s)) {
    throw std::invalid_argument("poll interval must be >= 0 and shorter than the keep-alive interval");
  }
}

std::vector<SweepRow> device_sweep_points(const DeviceSweepPlan& plan) {
  const std::vector<double> frequencies = downward(plan.frequencies_hz);
  std::vector<SweepRow> points;
  for (double load : plan.loads_n) {
    for (double amplitude_v : plan.voltages) {
      for (double f : frequencies) points.push_back(SweepRow{amplitude_v, f, load});
    }
  }
  return points;
}

DeviceSweepStart device_sweep_start(const DeviceSweepPlan& plan, const std::vector<SweepRow>& finished,
                                    std::size_t& kept) {
  const std::size_t curve = std::max<std::size_t>(plan.frequencies_hz.size(), 1);
  DeviceSweepStart start;
  start.curves_done = finished.size() / curve;
  kept = start.curves_done * curve;
  for (std::size_t i = 0; i < kept; ++i) {
    start.first_sweep_id = std::max(start.first_sweep_id, finished[i].sweep.value_or(-1) + 1);
    start.time_offset_s = std::max(start.time_offset_s, finished[i].time_s.value_or(0.0));
  }
  return start;
}

void sweep_device(Device& device, const DeviceSweepPlan& plan, std::vector<SweepRow>& rows, const PointDone& point_done,
                  const DeviceSweepStart& start) {
  check_plan(plan);
  const std::vector<double> frequencies = downward(plan.frequencies_hz);
  DriveOffGuard drive_off(device);
  Sweeper sweeper(device, plan, start);
  sweeper.session().command(DeviceAction::disable);
  device.set_slew(0.0, plan.amplitude_slew_v_per_s);
  std::size_t curve = 0;
  for (double load : plan.loads_n) {
    for (double amplitude_v : plan.voltages) {
      if (curve++ < start.curves_done) continue;  // measured by the run this one resumes
      // Each voltage starts above resonance at zero amplitude and ramps up there: a softening
      // resonator is approached from the high-frequency side (it can jump down below the peak).
      bool on = sweeper.start_voltage(amplitude_v, frequencies.front(), load);
      for (double f : frequencies) {
        if (!on) on = sweeper.start_voltage(amplitude_v, f, load);  // after a fault: reset and ramp again here
        SweepRow row;
        if (on) {
          row = sweeper.measure(amplitude_v, f, load);
        } else {
          row = sweeper.unmeasured(amplitude_v, f, load, "no_drive");
        }
        if (!row.ok) on = false;
        rows.push_back(row);
        if (point_done) point_done(row);
      }
      // Down to zero before moving to the next voltage's start frequency.
      sweeper.ramp_to(0.0, frequencies.back(), load);
    }
  }
  sweeper.session().command(DeviceAction::disable);
}

}  // namespace swum::host
