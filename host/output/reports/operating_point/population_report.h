// What `swum population` writes (docs/population.md): one CSV row per motor, and the summary
// of the study (per voltage the distribution of operating frequency and speed, and the
// oscillator range an amplifier must cover for a yield) as JSON and as text.
#pragma once

#include <string>
#include <vector>

#include "offline/population_study.h"

namespace swum::host {

/// motor,status,<each varied parameter>,frequency_hz_<V>amplitude_v,speed_mm_s_<V>amplitude_v,
/// peak_frequency_hz_<V>amplitude_v (per voltage),note
std::string population_csv_header(const PopulationStudy& study);
/// One line (with '\n'); cells of an undecided voltage or a rejected motor are empty, the note
/// says why (commas in it written as ';').
std::string population_csv_row(const PopulationStudy& study, const MotorOutcome& outcome);

struct PopulationSummaryInputs {
  std::string config_path;
  std::string spreads_path;
  std::string frequency_range;
  double yield = 0.95;
};

/// The summary as a JSON document (pretty, ordered keys, '\n' at the end). `outcomes` holds
/// every motor, indexed by motor number.
std::string population_summary_json(const PopulationStudy& study, const std::vector<MotorOutcome>& outcomes,
                                    const PopulationSummaryInputs& inputs);
/// The same as a few lines of text for the terminal.
std::string population_summary_text(const PopulationStudy& study, const std::vector<MotorOutcome>& outcomes,
                                    const PopulationSummaryInputs& inputs);
/// Whether the oscillator range of the summary reaches the yield.
bool population_yield_reached(const std::vector<MotorOutcome>& outcomes, double yield);

}  // namespace swum::host
