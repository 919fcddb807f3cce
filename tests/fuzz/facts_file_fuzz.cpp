// Fuzz target: a facts file (TOML; src/formats/facts_file.h parse_facts), the --facts of
// `swum calibrate`.
// Invariants: the only error is ParameterError, one line naming the source; accepted facts
// have a known kind, a finite tolerance > 0, a band min <= max that is target -/+ tolerance
// when a target is given (finite then), operating points inside the documented ranges, search
// ranges in order and not finer than 2000 grid points, increasing ratio voltages, and a centre
// inside the band (or on its one finite edge).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "formats/facts_file.h"
#include "fuzz_check.h"
#include "model/parameters.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<swum::Fact> facts;
  try {
    facts = swum::parse_facts(swum::fuzz::as_text(data, size), "fuzz.toml");
  } catch (const swum::ParameterError& e) {
    const std::string message = e.what();
    FUZZ_CHECK(message.rfind("fuzz.toml", 0) == 0, "error '%s' does not name the source", message.c_str());
    FUZZ_CHECK(message.find('\n') == std::string::npos, "error '%s' spans lines", message.c_str());
    return 0;
  }
  FUZZ_CHECK(!facts.empty(), "accepted a file without facts");
  for (const swum::Fact& f : facts) {
    FUZZ_CHECK(!swum::fact_kind_name(f.kind).empty(), "unknown kind");
    FUZZ_CHECK(std::isfinite(f.tolerance) && f.tolerance > 0.0, "tolerance %g", f.tolerance);
    FUZZ_CHECK(!std::isnan(f.min) && !std::isnan(f.max) && f.min <= f.max, "band %g..%g", f.min, f.max);
    if (f.target) {
      FUZZ_CHECK(std::isfinite(*f.target) && std::isfinite(f.min) && std::isfinite(f.max), "target %g", *f.target);
      FUZZ_CHECK(f.min == *f.target - f.tolerance && f.max == *f.target + f.tolerance, "band of a target");
    } else {
      FUZZ_CHECK(std::isfinite(f.min) || std::isfinite(f.max), "a band without an edge");
    }
    const double c = f.centre();
    FUZZ_CHECK(std::isfinite(c) && c >= f.min && c <= f.max, "centre %g outside %g..%g", c, f.min, f.max);
    FUZZ_CHECK(std::abs(f.load_n) <= 1000.0, "load %g", f.load_n);
    switch (f.kind) {
      case swum::FactKind::peak_frequency:
        FUZZ_CHECK(f.paper_v >= 1.0 && f.paper_v <= 10000.0, "paper_v %g", f.paper_v);
        FUZZ_CHECK(f.search_hz[0] >= 1000.0 && f.search_hz[0] < f.search_hz[1] && f.search_hz[1] <= 200000.0,
                   "search %g..%g", f.search_hz[0], f.search_hz[1]);
        FUZZ_CHECK(f.search_hz[2] > 0.0 && (f.search_hz[1] - f.search_hz[0]) / f.search_hz[2] <= 2000.0, "step %g",
                   f.search_hz[2]);
        break;
      case swum::FactKind::dead_zone_onset:
        FUZZ_CHECK(f.frequency_hz >= 1000.0 && f.frequency_hz <= 200000.0, "frequency %g", f.frequency_hz);
        FUZZ_CHECK(f.threshold_mm_s > 0.0 && f.threshold_mm_s <= 1e4, "threshold %g", f.threshold_mm_s);
        FUZZ_CHECK(f.search_paper_v[0] >= 1.0 && f.search_paper_v[1] > f.search_paper_v[0] + 10.0 &&
                       f.search_paper_v[1] <= 10000.0,
                   "search %g..%g", f.search_paper_v[0], f.search_paper_v[1]);
        break;
      case swum::FactKind::saturation_ratio:
        FUZZ_CHECK(f.frequency_hz >= 1000.0 && f.frequency_hz <= 200000.0, "frequency %g", f.frequency_hz);
        for (std::size_t k = 0; k < 4; ++k) {
          FUZZ_CHECK(f.ratio_paper_v[k] >= 1.0 && f.ratio_paper_v[k] <= 10000.0, "paper_v %g", f.ratio_paper_v[k]);
          FUZZ_CHECK(k == 0 || f.ratio_paper_v[k] > f.ratio_paper_v[k - 1], "ratio voltages do not increase");
        }
        break;
      case swum::FactKind::speed:
        FUZZ_CHECK(f.paper_v >= 1.0 && f.paper_v <= 10000.0, "paper_v %g", f.paper_v);
        FUZZ_CHECK(f.frequency_hz >= 1000.0 && f.frequency_hz <= 200000.0, "frequency %g", f.frequency_hz);
        break;
    }
  }
  return 0;
}
