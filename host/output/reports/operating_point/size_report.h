// What `swum size` prints and writes (docs/sizing.md): the rows as CSV (--out), the sizing as JSON
// (--json) or a few lines of text, and a report folder (--report: report.md with the plots and
// summary.json).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "analysis/operating_point/operating_band.h"
#include "analysis/sizing/amplifier_sizing.h"
#include "analysis/sizing/series_in_loop.h"

namespace swum::host {

// What the report says the figures came from.
struct SizeContext {
  std::string config_path;  // the motor file ("" = none named)
  std::string command;      // the command line that made them
  double margin_hz = 0.0;
  double clamped_capacitance_f = 0.0;
  std::string spreads_path;  // a population was sized ("" = none)
  std::uint64_t seed = 0;
  std::optional<PopulationSizing> population;
  std::optional<SeriesInLoop> series_in_loop;  // the series design repeated in the simulator
};

/// One row per (voltage, load, temperature rise); cells of a row that was not sized are empty.
std::string size_csv(const SizingResult& s);

/// Numbers as JSON numbers, null where unknown (pretty, ordered keys, '\n' at the end).
std::string size_json(const SizingResult& s, const SizeContext& context);

/// The oscillator range, the worst cases, the network and what to buy, in a few lines.
std::string size_text(const SizingResult& s, const SizeContext& context, const std::string& out_path);

/// report.md: the same in prose and tables with the plots (file names relative to the folder).
std::string size_markdown(const SizingResult& s, const SizeContext& context, const std::vector<std::string>& plots);

/// PNG plots into `dir`: admittance at the design row's curve, RMS current and real power against
/// frequency per voltage (the design row's load and temperature rise), the operating frequency
/// and the worst current over the envelope. Returns the file names written.
std::vector<std::string> write_size_plots(const std::filesystem::path& dir, const std::vector<BandRow>& rows,
                                          const SizingResult& s);

}  // namespace swum::host
