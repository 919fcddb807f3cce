#include "analysis/studies/paper_facts.h"

#include <cmath>

#include "formats/number_format.h"

namespace swum {

PaperFacts::PaperFacts(const MotorModel& nonlinear, const MotorModel& linear)
    : nonlinear_(nonlinear), linear_(linear) {}

double PaperFacts::speed_mm_s(const MotorModel& model, double paper_v, double frequency_hz, double load_n) {
  OperatingPoint p;
  p.amplitude_v = amplitude_v_of_paper_voltage(model.parameters().options.paper_voltage_axis, paper_v);
  p.frequency_hz = frequency_hz;
  p.load_n = load_n;
  const SteadyStateResult r = run_to_steady_state(model, p);
  return r.diverged ? std::nan("") : r.speed_mm_s;
}

SpeedPeak PaperFacts::peak(const MotorModel& model, double paper_v) {
  const auto key = std::make_pair(&model, paper_v);
  if (auto it = peaks_.find(key); it != peaks_.end()) return it->second;
  const double amplitude_v = amplitude_v_of_paper_voltage(model.parameters().options.paper_voltage_axis, paper_v);
  return peaks_[key] = frequency_of_max_speed(model, amplitude_v, 39000.0, 41000.0, 100.0);
}

FactResult PaperFacts::natural_frequencies() const {
  const ModalConstants& c = nonlinear_.constants();
  FactResult r{"E1 natural frequencies", "stator L1 / B2 natural frequencies", "39516 / 39469 Hz",
               format_numbers("%.1f / %.1f Hz", c.f_l1_hz, c.f_b2_hz), false};
  r.holds = std::abs(c.f_l1_hz - 39516.0) <= 0.002 * 39516.0 && std::abs(c.f_b2_hz - 39469.0) <= 0.002 * 39469.0;
  return r;
}

FactResult PaperFacts::dead_zone() {
  // ~0 below 50 Vpp (|v| < 1 mm/s at 25 and 40 Vpp), moving at 75 Vpp (> 2 mm/s) and
  // rising through 100, 150, 200 Vpp.
  const double v25 = speed_mm_s(nonlinear_, 25, 40000), v40 = speed_mm_s(nonlinear_, 40, 40000);
  const double v75 = speed_mm_s(nonlinear_, 75, 40000), v100 = speed_mm_s(nonlinear_, 100, 40000);
  const double v150 = speed_mm_s(nonlinear_, 150, 40000), v200 = speed_mm_s(nonlinear_, 200, 40000);
  FactResult r{"E8 dead zone", "no-load speed at 40 kHz ~0 below ~50 Vpp, rising above", "dead zone below ~50 Vpp", "",
               false};
  r.model_value = format_numbers("%.1f / %.1f / %.1f / %.1f mm/s", v25, v40, v75, v100) +
                  format_numbers(" / %.1f / %.1f mm/s at 25/40/75/100/150/200 Vpp", v150, v200);
  r.holds = std::abs(v25) < 1.0 && std::abs(v40) < 1.0 && v75 > 2.0 && v100 > v75 && v150 > v100 && v200 > v150;
  return r;
}

FactResult PaperFacts::saturation() {
  auto gains = [this](const MotorModel& m) {
    const double v100 = speed_mm_s(m, 100, 40000), v200 = speed_mm_s(m, 200, 40000);
    const double v300 = speed_mm_s(m, 300, 40000), v400 = speed_mm_s(m, 400, 40000);
    return std::make_pair(v200 - v100, v400 - v300);
  };
  const auto [low_nl, high_nl] = gains(nonlinear_);
  const auto [low_lin, high_lin] = gains(linear_);
  FactResult r{"E8 saturation", "at 40 kHz speed saturates above ~250 Vpp; the linear model does not",
               "gain 300->400 Vpp < 1/2 gain 100->200 Vpp (non-linear only)", "", false};
  r.model_value = format_numbers("non-linear gains %.1f -> %.1f mm/s (ratio %.2f); ", low_nl, high_nl,
                                 high_nl / low_nl) +
                  format_numbers("linear %.1f -> %.1f mm/s (ratio %.2f)", low_lin, high_lin, high_lin / low_lin);
  r.holds = low_nl > 0.0 && high_nl < 0.5 * low_nl && low_lin > 0.0 && high_lin >= 0.5 * low_lin;
  return r;
}

FactResult PaperFacts::peak_frequency(double paper_v, double paper_hz) {
  const SpeedPeak p = peak(nonlinear_, paper_v);
  const SpeedPeak lin = peak(linear_, paper_v);
  FactResult r{format_numbers("E10 peak at %.0f Vpp", paper_v), "frequency of maximum no-load speed",
               format_numbers("%.2f kHz (±0.2)", paper_hz / 1000.0), "", false};
  r.model_value = (p.found ? format_numbers("%.3f kHz (%.1f mm/s)", p.frequency_hz / 1000.0, p.speed_mm_s)
                           : std::string("no forward motion")) +
                  (lin.found ? format_numbers("; linear %.3f kHz", lin.frequency_hz / 1000.0)
                             : std::string("; linear: no forward motion"));
  r.holds = p.found && std::abs(p.frequency_hz - paper_hz) <= kPeakToleranceHz;
  return r;
}

FactResult PaperFacts::drift() {
  const SpeedPeak p100 = peak(nonlinear_, 100), p250 = peak(nonlinear_, 250), p400 = peak(nonlinear_, 400);
  const SpeedPeak l100 = peak(linear_, 100), l400 = peak(linear_, 400);
  FactResult r{"E11 drift", "peak frequency falls with voltage; the linear model drifts less",
               "40.4 -> 40.2 -> 39.6 kHz (0.8 kHz drift)", "", false};
  const double nl_drift = p100.frequency_hz - p400.frequency_hz;
  const double lin_drift = l100.frequency_hz - l400.frequency_hz;
  r.model_value = format_numbers("%.3f -> %.3f -> %.3f kHz", p100.frequency_hz / 1000, p250.frequency_hz / 1000,
                                 p400.frequency_hz / 1000) +
                  format_numbers(" (drift %.0f Hz); linear drift %.0f Hz", nl_drift, lin_drift);
  r.holds = p100.found && p250.found && p400.found && l100.found && l400.found &&
            p100.frequency_hz >= p250.frequency_hz && p250.frequency_hz > p400.frequency_hz && lin_drift < nl_drift;
  return r;
}

FactResult PaperFacts::load_advantage(double paper_v, double aware_hz) {
  FactResult r{format_numbers("E12 load at %.0f Vpp", paper_v),
               "under load the drift-aware frequency is faster than 40.4 kHz",
               format_numbers("%.2f kHz better than 40.4 kHz", aware_hz / 1000.0), "", true};
  for (double load_n : {1.0, 2.0, 3.0}) {
    const double aware = speed_mm_s(nonlinear_, paper_v, aware_hz, load_n);
    const double naive = speed_mm_s(nonlinear_, paper_v, kNaiveFrequencyHz, load_n);
    if (!r.model_value.empty()) r.model_value += "; ";
    r.model_value += format_numbers("%.0f N: %.1f vs %.1f mm/s", load_n, aware, naive);
    r.holds = r.holds && aware > naive;
  }
  return r;
}

std::vector<FactResult> PaperFacts::all() {
  return {natural_frequencies(),
          dead_zone(),
          saturation(),
          peak_frequency(100, 40400),
          peak_frequency(250, 40200),
          peak_frequency(400, 39600),
          drift(),
          load_advantage(300, 40060),
          load_advantage(400, 39600)};
}

FactResult literal_reading_cross_check(const MotorModel& literal) {
  PaperFacts facts(literal, literal);
  FactResult r{"literal reading", "model_spec §9: friction lock at low voltage, downward drift",
               "0 mm/s at 40 kHz up to 200 Vpp; peak(400) <= peak(250)", "", false};
  const double v50 = facts.speed_mm_s(literal, 50, 40000), v100 = facts.speed_mm_s(literal, 100, 40000);
  const double v200 = facts.speed_mm_s(literal, 200, 40000);
  const SpeedPeak p250 = facts.peak(literal, 250), p400 = facts.peak(literal, 400);
  r.model_value = format_numbers("%.2f / %.2f / %.2f mm/s at 50/100/200 Vpp; ", v50, v100, v200) +
                  format_numbers("peak %.3f kHz (%.1f mm/s) at 250, %.3f kHz (%.1f mm/s) at 400 Vpp",
                                 p250.frequency_hz / 1000, p250.speed_mm_s, p400.frequency_hz / 1000, p400.speed_mm_s);
  r.holds = std::abs(v50) < 1.0 && std::abs(v100) < 1.0 && std::abs(v200) < 1.0 && p250.found && p400.found &&
            p400.frequency_hz <= p250.frequency_hz;
  return r;
}

}  // namespace swum
