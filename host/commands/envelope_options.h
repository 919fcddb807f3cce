// The envelope options `swum band` and `swum size` share (docs/host.md, "swum band"): the
// voltages, loads and stator temperature rises of the rows, the margin above the peak and the
// frequency grid of each row's down-sweep, registered and read in one place.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "analysis/operating_point/operating_band.h"
#include "analysis/operating_point/operating_point.h"

namespace swum::host {

struct EnvelopeOptions {
  std::string amplitude_v_list;
  std::string load_list = "0";
  std::string rise_list = "0";
  double margin_hz = kDefaultMarginHz;  // the operating point's defaults (operating_point.h), as swum pick
  std::string frequency_range = kDefaultFrequencyGrid;
};

// --amplitude-v (required), --load, --temperature-rise-k, --margin-hz, --frequency-hz.
void add_envelope_options(CLI::App& sub, EnvelopeOptions& o);

// The grid of the options; every bad value named (check_band_grid, with --jobs) before any file is
// read.
[[nodiscard]] BandGrid envelope_grid(const EnvelopeOptions& o, int jobs);

}  // namespace swum::host
