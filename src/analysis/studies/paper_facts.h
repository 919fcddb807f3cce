// The paper's quantitative experimental facts (model_spec §8, E1-E12) as checks on a
// model: one place defines each criterion and its tolerance, used by the validation
// tests and by `swum validate` (docs/validation.md). Each check reports the paper's
// value, the model's value and whether the fact holds.
//
// Every voltage here is one the paper quotes, on its axis labelled "Vpp" (`paper_v`): the
// model is driven at the terminal amplitude its options.paper_voltage_axis reads from it
// (amplitude_v_of_paper_voltage, docs/validation.md "The amplitude reading").
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "analysis/steady_state/operating_curves.h"
#include "model/motor_model.h"

namespace swum {

struct FactResult {
  std::string id;         // e.g. "E8 dead zone"
  std::string statement;  // what the paper reports
  std::string paper_value;
  std::string model_value;  // the model's numbers behind the verdict
  bool holds = false;
};

class PaperFacts {
 public:
  // `nonlinear` is the model under test, `linear` its linearised variant; both must outlive
  // this object.
  PaperFacts(const MotorModel& nonlinear, const MotorModel& linear);

  FactResult natural_frequencies() const;                      // E1, within 0.2 %
  FactResult dead_zone();                                      // E8, 40 kHz
  FactResult saturation();                                     // E8, NL saturates, linear not
  FactResult peak_frequency(double paper_v, double paper_hz);  // E10, within ±200 Hz
  FactResult drift();                                          // E10/E11
  FactResult load_advantage(double paper_v, double aware_hz);  // E12 vs 40.4 kHz, 1-3 N
  std::vector<FactResult> all();

  // Frequency of maximum no-load speed (39-41 kHz, 100 Hz grid refined to 25 Hz), memoised.
  SpeedPeak peak(const MotorModel& model, double paper_v);
  double speed_mm_s(const MotorModel& model, double paper_v, double frequency_hz, double load_n = 0.0);

  static constexpr double kPeakToleranceHz = 200.0;
  static constexpr double kNaiveFrequencyHz = 40400.0;

 private:
  const MotorModel& nonlinear_;
  const MotorModel& linear_;
  std::map<std::pair<const MotorModel*, double>, SpeedPeak> peaks_;
};

// model_spec §9 cross-check of the literal reading: B2 friction-locked at 40 kHz up to
// 200 Vpp, and the frequency of maximum speed does not rise from 250 to 400 Vpp.
FactResult literal_reading_cross_check(const MotorModel& literal);

}  // namespace swum
