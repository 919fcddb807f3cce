// The command value every interface decodes into (Modbus writes, CAN Command/AuxCommand
// frames), the device's set-point limits and the static check each transport applies before
// queueing a command. Pure values: no threads, no clocks.
#pragma once

#include <cstdint>

#include "codes.h"

namespace swum::protocol {

// A (partial) command: only the fields flagged in `fields` are changed. Action `none` with no
// fields is a keep-alive (feeds the watchdog).
struct Command {
  static constexpr std::uint32_t kAction = 1U << 0;
  static constexpr std::uint32_t kFrequency = 1U << 1;
  static constexpr std::uint32_t kAmplitude = 1U << 2;
  static constexpr std::uint32_t kPhase = 1U << 3;
  static constexpr std::uint32_t kLoad = 1U << 4;
  static constexpr std::uint32_t kFrequencySlew = 1U << 5;
  static constexpr std::uint32_t kAmplitudeSlew = 1U << 6;

  std::uint32_t fields = 0;
  Action action = Action::none;
  CommandSource source = CommandSource::internal;
  double frequency_hz = 0.0;
  double amplitude_v = 0.0;
  double phase_deg = 0.0;
  double load_n = 0.0;
  double frequency_slew_hz_per_s = 0.0;  // 0 = unlimited
  double amplitude_slew_v_per_s = 0.0;   // 0 = unlimited
  std::uint64_t sequence = 0;            // set by the transport (for latency measurement)
  std::uint64_t accepted_ns = 0;         // CLOCK_MONOTONIC receive time: Modbus when the transport
                                         // accepted it, CAN the bus's (kernel's) rx timestamp
};

struct AmplifierLimits {
  double min_frequency_hz = 30000.0;
  double max_frequency_hz = 50000.0;
  double max_amplitude_v = 600.0;
  double max_abs_phase_deg = 180.0;
  double max_abs_load_n = 30.0;
  double max_frequency_slew_hz_per_s = 1.0e7;
  double max_amplitude_slew_v_per_s = 1.0e7;
};

// Static validation (ranges, codes): what every transport checks before queueing a command.
Reason validate(const Command& command, const AmplifierLimits& limits);

// The set-points the amplifier holds (what a command changes).
struct AmplifierSetpoints {
  double frequency_hz = 0.0;
  double amplitude_v = 0.0;
  double phase_deg = 0.0;
  double load_n = 0.0;
  double frequency_slew_hz_per_s = 0.0;
  double amplitude_slew_v_per_s = 0.0;
};

}  // namespace swum::protocol
