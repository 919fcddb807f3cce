// The facts file of `swum calibrate --facts` (docs/calibration.md): a few things known about a
// motor instead of, or besides, a measured sweep, each with its tolerance. TOML text in, no
// file I/O; validated once here. One [[fact]] table per fact:
//   [[fact]]
//   id = "E10 peak at 250 Vpp"        # optional (default: kind and operating point)
//   kind = "peak_frequency"            # frequency of maximum no-load speed, Hz
//   paper_v = 250                      # load_n = 0, search_hz = [39000, 41000, 100] by default
//   target = 40200                     # or min = ... and/or max = ... (a band)
//   tolerance = 200                    # target +- tolerance; with min/max: the unit of a miss
// Voltages (`paper_v`, `search_paper_v`) are as the facts' source quotes them (config/li2019_facts.toml:
// the paper's axis, labelled "Vpp"); the model is driven at the terminal amplitude the motor's
// options.paper_voltage_axis reads from them (amplitude_v_of_paper_voltage). The retired keys
// vpp and search_vpp fail naming these.
// Kinds and their keys:
//   peak_frequency   paper_v, [load_n], [search_hz = [start, stop, step]]    value in Hz
//   dead_zone_onset  frequency_hz, [load_n], [threshold_mm_s = 2], [search_paper_v = [lo, hi]]
//                    the lowest voltage whose speed exceeds the threshold, in V as quoted
//   saturation_ratio frequency_hz, [paper_v = [100, 200, 300, 400]]
//                    (v(V4) - v(V3)) / (v(V2) - v(V1)), no unit
//   speed            paper_v, frequency_hz, [load_n]                          value in mm/s
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace swum {

enum class FactKind { peak_frequency, dead_zone_onset, saturation_ratio, speed };

struct Fact {
  std::string id;
  FactKind kind = FactKind::speed;
  double paper_v = 0.0;  // as quoted (see above)
  double frequency_hz = 0.0;
  double load_n = 0.0;
  std::array<double, 3> search_hz{39000.0, 41000.0, 100.0};  // peak_frequency: start, stop, step
  double threshold_mm_s = 2.0;                               // dead_zone_onset
  std::array<double, 2> search_paper_v{10.0, 200.0};         // dead_zone_onset
  std::array<double, 4> ratio_paper_v{100.0, 200.0, 300.0, 400.0};
  // The fact holds when the value lies in [min, max] (target +- tolerance when a target is
  // given); a miss counts (distance outside the band) / tolerance.
  std::optional<double> target;
  double min = 0.0;
  double max = 0.0;
  double tolerance = 0.0;
  int line = 0;

  // The value a fit aims at: the target, or the middle of a closed band, or its one edge.
  [[nodiscard]] double centre() const;
  [[nodiscard]] std::string_view unit() const;  // "Hz", "V" (as quoted), "", "mm/s"
};

[[nodiscard]] std::string_view fact_kind_name(FactKind kind);

// Throws ParameterError "SOURCE:LINE: what" for a TOML error, no [[fact]] table, an unknown
// kind or key, a missing or non-numeric required key, a non-positive tolerance, both target and
// min/max or neither, min > max, a voltage or frequency outside 1..10000 V / 1000..200000 Hz, a
// search range that is empty or in the wrong order, a ratio whose voltages are not increasing.
[[nodiscard]] std::vector<Fact> parse_facts(std::string_view toml_text, std::string_view source_name);

}  // namespace swum
