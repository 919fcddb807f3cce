// One motor of `swum population` (docs/population.md): its parameters drawn from the study's
// counter-based stream, the model swept over the grid and the operating frequency picked per
// voltage exactly as `swum pick --config` does (sweep_model's down-sweeps, then pick_voltages).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "formats/spread_file.h"
#include "model/parameters.h"

namespace swum::host {

struct PopulationStudy {
  MotorParameters nominal;
  std::vector<ParameterSpread> spreads;
  std::uint64_t seed = 1;
  std::uint64_t motors = 0;
  std::vector<double> voltages;
  std::vector<double> frequencies_hz;
  double load_n = 0.0;
  PickOptions pick;  // min_margin_hz as `swum pick --margin-hz`
};

struct VoltageOutcome {
  double amplitude_v = 0.0;
  bool decided = false;
  double frequency_hz = 0.0;  // the picked operating frequency (decided only)
  double speed_mm_s = 0.0;    // the speed there
  double peak_frequency_hz = 0.0;
  std::string reason;  // pick_operating_point's reason
};

struct MotorOutcome {
  std::uint64_t motor = 0;
  std::vector<double> values;            // drawn, one per spread
  bool rejected = false;                 // the drawn set was refused (validate_parameters): no sweep
  std::string rejection;                 // why
  std::vector<VoltageOutcome> voltages;  // one per study voltage (empty when rejected)

  bool decided_everywhere() const;
  std::string status() const;  // "ok", "undecided" (at some voltage) or "rejected"
};

/// Motor `motor` of the study: a pure function of (study, motor), whichever thread or rank
/// computes it. The model sweep runs on the calling thread.
MotorOutcome run_population_motor(const PopulationStudy& study, std::uint64_t motor);

/// Exact round trip (MessagePack through nlohmann/json): what a rank sends to rank 0, and
/// what the single process passes through too, so both see the same numbers.
std::string encode_motor_outcome(const MotorOutcome& outcome);
MotorOutcome decode_motor_outcome(const std::string& bytes);

}  // namespace swum::host
