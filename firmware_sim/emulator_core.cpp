#include "emulator_core.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace swum::emu {

Reason SharedState::submit(Command command) {
  // Amplifier limits are checked by the transports with validate(); here only the queue.
  command.sequence = next_sequence.fetch_add(1, std::memory_order_relaxed);
  if (!commands.try_push(command)) {
    queue_full.fetch_add(1, std::memory_order_relaxed);
    rejects.record(Reason::queue_full, command.source);
    return Reason::queue_full;
  }
  return Reason::none;
}

EmulatorCore::EmulatorCore(const MotorModel& model, CoreConfig config, SharedState& shared)
    : model_(model),
      config_([&] {
        if (!(config.tick_hz > 0.0) || !std::isfinite(config.tick_hz))
          throw std::invalid_argument("tick rate must be positive");
        config.amplifier.tick_s = 1.0 / config.tick_hz;
        return config;
      }()),
      shared_(shared),
      amplifier_(config_.amplifier),
      simulator_(model),
      tick_s_(1.0 / config_.tick_hz) {
  const double dt = model.time_step_s();
  if (tick_s_ < dt) throw std::invalid_argument("tick period shorter than the model time step");
  steps_per_tick_ = static_cast<std::uint64_t>(std::llround(tick_s_ / dt));
  const auto window_ticks = static_cast<std::size_t>(std::max(1.0, std::round(config_.speed_window_s / tick_s_)));
  position_ring_.assign(window_ticks + 1, simulator_.state().mover_position_m);
  config_.sample_stride = std::max(1U, config_.sample_stride);
  simulator_.set_drive(amplifier_.output());
  telemetry_.position_m = simulator_.state().mover_position_m;
  telemetry_.external_clock = config_.external_clock;
}

void EmulatorCore::shut_down() {
  Command off;
  off.fields = Command::kAction;
  off.action = Action::disable;
  amplifier_.apply(off, tick_);
  DriveInput drive = amplifier_.tick(tick_, shared_.enable_line.load(std::memory_order_relaxed));
  simulator_.set_drive(drive);
  telemetry_.state = amplifier_.state();
  telemetry_.output = drive_values(drive);
  shared_.telemetry.store(telemetry_);
}

const Telemetry& EmulatorCore::tick() {
  // 1. Commands accepted since the last boundary, in order.
  Command command;
  accepted_count_ = 0;
  while (shared_.commands.try_pop(command)) {
    if (accepted_count_ < accepted_ns_.size() && command.accepted_ns != 0)
      accepted_ns_[accepted_count_++] = command.accepted_ns;
    if (observer_ != nullptr) observer_->on_command(tick_, command);
    const Reason reason = amplifier_.apply(command, tick_);
    if (reason != Reason::none) shared_.rejects.record(reason, command.source);
    telemetry_.last_sequence = command.sequence;
  }
  // 2. Amplifier: enable line, watchdog, slew -> drive for this tick.
  const bool enable_line = shared_.enable_line.load(std::memory_order_relaxed);
  if (observer_ != nullptr && last_enable_line_ != static_cast<int>(enable_line)) {
    observer_->on_enable_line(tick_, enable_line);
    last_enable_line_ = static_cast<int>(enable_line);
  }
  const DriveInput drive = amplifier_.tick(tick_, enable_line);
  simulator_.set_drive(drive);

  // 3. Integrate over the tick in fixed sub-steps (sampling the tip every stride steps).
  const double start_position = simulator_.state().mover_position_m;
  const std::uint64_t target_steps = static_cast<std::uint64_t>(
      std::llround(static_cast<double>(tick_ + 1) * tick_s_ / model_.time_step_s()));
  std::uint64_t steps = target_steps - steps_done_;
  double un_min = 1e300, un_max = -1e300, ut_min = 1e300, ut_max = -1e300;
  const std::uint64_t stride = config_.sample_stride;
  for (std::uint64_t done = 0; done < steps;) {
    const std::uint64_t n = std::min(stride, steps - done);
    simulator_.advance(n);
    done += n;
    const MotorState& s = simulator_.state();
    const double un = MotorModel::tip_normal_m(s);
    const double ut = model_.tip_tangential_m(s);
    un_min = std::min(un_min, un);
    un_max = std::max(un_max, un);
    ut_min = std::min(ut_min, ut);
    ut_max = std::max(ut_max, ut);
  }
  steps_done_ = target_steps;
  ++tick_;

  // 4. Blow-up guard: the simulator resets itself to rest on NaN/runaway; we latch a fault.
  const MotorState& s = simulator_.state();
  const bool finite = std::isfinite(s.mover_position_m) && std::isfinite(s.mover_velocity_m_s) &&
                      std::isfinite(un_max - un_min) && std::isfinite(ut_max - ut_min);
  if (simulator_.diverged() || !finite) {
    simulator_.clear_diverged();
    if (!finite) simulator_.reset();
    amplifier_.raise_fault(FaultCode::numerical);
    simulator_.set_drive(amplifier_.output());
    ++telemetry_.divergences;
    un_min = un_max = ut_min = ut_max = 0.0;
  }

  // 5. Telemetry.
  const double position = simulator_.state().mover_position_m;
  position_ring_[ring_index_] = position;
  const std::size_t n = position_ring_.size();
  ring_index_ = (ring_index_ + 1) % n;
  ring_filled_ = std::min(ring_filled_ + 1, n - 1);
  const std::size_t oldest = (ring_index_ + n - 1 - ring_filled_) % n;
  // ring_index_ now points to the slot after the newest; oldest = ring_filled_ ticks back.
  telemetry_.tick = tick_;
  telemetry_.sim_time_s = simulator_.state().time_s;
  telemetry_.state = amplifier_.state();
  telemetry_.fault = amplifier_.fault();
  telemetry_.enable_line = amplifier_.enable_line();
  telemetry_.at_setpoint = amplifier_.at_setpoint();
  telemetry_.setpoints = amplifier_.setpoints();
  telemetry_.output = drive_values(amplifier_.output());
  telemetry_.position_m = position;
  telemetry_.tick_speed_m_s = (position - start_position) / tick_s_;
  telemetry_.speed_m_s = ring_filled_
                             ? (position - position_ring_[oldest]) / (static_cast<double>(ring_filled_) * tick_s_)
                             : telemetry_.tick_speed_m_s;
  telemetry_.tip_normal_um = 0.5e6 * (un_max - un_min);
  telemetry_.tip_tangential_um = 0.5e6 * (ut_max - ut_min);
  telemetry_.applied_commands = amplifier_.applied_commands();
  telemetry_.amplifier_rejects = amplifier_.rejected_commands();
  shared_.telemetry.store(telemetry_);
  if (observer_ != nullptr) observer_->on_telemetry(telemetry_);
  return telemetry_;
}

}  // namespace swum::emu
