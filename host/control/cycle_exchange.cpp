#include "control/cycle_exchange.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>

namespace swum::host {
namespace {

using Clock = std::chrono::steady_clock;

// The device time has the register's resolution (1 ms over Modbus): a tick rate that does not
// match the device shows as a drift beyond it within a few cycles.
constexpr double kDeviceTimeResolutionS = 1.5e-3;

}  // namespace

std::string format_seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6f", s);
  return text;
}

CycleExchange::CycleExchange(Device& device, double cycle_s, double tick_hz, const DriveSlew& slew)
    : device_(device), cycle_s_(cycle_s), tick_hz_(tick_hz), slew_(slew) {
  lockstep_ = device.lockstep();
  if (lockstep_) {
    const double ticks = cycle_s * tick_hz;
    ticks_per_cycle_ = static_cast<std::uint32_t>(std::llround(ticks));
    if (std::abs(ticks - ticks_per_cycle_) > 1e-9 * ticks || ticks_per_cycle_ < 1 || ticks_per_cycle_ > 65535) {
      throw std::invalid_argument("--cycle-ms: " + format_seconds(cycle_s * 1e3) +
                                  " ms is not a whole number of ticks in 1..65535 at --tick-hz " +
                                  format_seconds(tick_hz));
    }
  } else {
    device.set_slew(slew.frequency_hz_per_s, slew.amplitude_v_per_s);
  }
  start_ = Clock::now();
}

double CycleExchange::host_seconds(const DeviceTelemetry& t) const {
  return std::chrono::duration<double>(t.received - start_).count();
}

DeviceTelemetry CycleExchange::exchange(const DriveSetpoint& setpoint, DeviceAction action) {
  if (lockstep_) {
    DeviceTelemetry t = device_.step(setpoint, slew_, action, ticks_per_cycle_);
    check_tick_rate(t);
    return t;
  }
  const auto deadline = start_ + std::chrono::duration_cast<Clock::duration>(
                                     std::chrono::duration<double>(cycle_s_ * cycles_++));
  std::this_thread::sleep_until(deadline);
  device_.set_drive(setpoint);
  if (action != DeviceAction::keep_alive) device_.command(action);
  return device_.read();
}

void CycleExchange::drive_off(DriveSetpoint setpoint) {
  setpoint.amplitude_v = 0.0;
  (void)exchange(setpoint, DeviceAction::disable);
}

void CycleExchange::check_tick_rate(const DeviceTelemetry& t) const {
  if (!t.tick || !t.device_time_s) return;
  const double expected_s = static_cast<double>(*t.tick) / tick_hz_;
  if (std::abs(expected_s - *t.device_time_s) > kDeviceTimeResolutionS) {
    throw DeviceError(device_.name() + ": --tick-hz " + format_seconds(tick_hz_) + " does not match the device: tick " +
                      std::to_string(*t.tick) + " at device time " + format_seconds(*t.device_time_s) + " s");
  }
}

}  // namespace swum::host
