#include "command.h"

#include <cmath>

namespace swum::protocol {

namespace {
bool in_range(double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; }
}  // namespace

Reason validate(const Command& c, const AmplifierLimits& l) {
  if ((c.fields & Command::kAction) && static_cast<std::uint8_t>(c.action) > kMaxAction) return Reason::unknown_command;
  if ((c.fields & Command::kFrequency) && !in_range(c.frequency_hz, l.min_frequency_hz, l.max_frequency_hz))
    return Reason::frequency_out_of_range;
  if ((c.fields & Command::kAmplitude) && !in_range(c.amplitude_v, 0.0, l.max_amplitude_v))
    return Reason::amplitude_out_of_range;
  if ((c.fields & Command::kPhase) && !in_range(c.phase_deg, -l.max_abs_phase_deg, l.max_abs_phase_deg))
    return Reason::phase_out_of_range;
  if ((c.fields & Command::kLoad) && !in_range(c.load_n, -l.max_abs_load_n, l.max_abs_load_n))
    return Reason::load_out_of_range;
  if ((c.fields & Command::kFrequencySlew) && !in_range(c.frequency_slew_hz_per_s, 0.0, l.max_frequency_slew_hz_per_s))
    return Reason::slew_out_of_range;
  if ((c.fields & Command::kAmplitudeSlew) && !in_range(c.amplitude_slew_v_per_s, 0.0, l.max_amplitude_slew_v_per_s))
    return Reason::slew_out_of_range;
  return Reason::none;
}

}  // namespace swum::protocol
