// `swum band --config F --vpp LIST [--load LIST] [--temperature-rise-k LIST]`: the band of drive
// frequencies an amplifier's oscillator must cover, from the model: a continuous down-sweep per
// (voltage, load, stator temperature rise), the drift-aware pick on each
// (src/analysis/operating_point/operating_band.h); rows to --out (CSV, written atomically) or --json, the band on
// stdout (docs/host.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands/command_error.h"
#include "commands/commands.h"
#include "formats/number_format.h"
#include "offline/band_run.h"
#include "offline/motor_config.h"
#include "output/progress_bar.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct BandOptions {
  std::string config_path;
  std::string vpp_list;
  std::string load_list = "0";
  std::string rise_list = "0";
  double margin_hz = 100.0;
  std::string frequency_range = "38000:41500:25";
  std::string out_path;
  bool json = false;
  int jobs = 0;
};

constexpr const char* kBandHeader =
    "vpp,load_n,temperature_rise_k,decided,frequency_hz,speed_mm_s,peak_frequency_hz,peak_speed_mm_s,margin_hz,"
    "collapse_hz,reason\n";

// The reasons are prose with commas; the table has no quoting.
std::string csv_text(std::string text) {
  std::replace(text.begin(), text.end(), ',', ';');
  return text;
}

std::string band_csv(const std::vector<BandRow>& rows) {
  std::string csv = kBandHeader;
  for (const BandRow& row : rows) {
    const PickResult& p = row.pick;
    csv += format_number(row.vpp) + "," + format_number(row.load_n) + "," + format_number(row.temperature_rise_k) +
           "," + (p.decided ? "1" : "0") + ",";
    if (p.decided) {
      csv += format_number(p.frequency_hz, "%.10g") + "," + format_number(p.speed_mm_s) + "," +
             format_number(p.peak_frequency_hz, "%.10g") + "," + format_number(p.peak_speed_mm_s) + "," +
             format_number(p.margin_hz) + "," + (p.collapse_hz ? format_number(*p.collapse_hz, "%.10g") : "");
    } else {
      csv += ",,,,,";
    }
    csv += "," + csv_text(p.reason) + "\n";
  }
  return csv;
}

using Json = nlohmann::ordered_json;

Json range_json(const std::optional<FrequencyRange>& range) {
  if (!range) return Json(nullptr);
  return Json{{"low_hz", range->low_hz}, {"high_hz", range->high_hz}, {"width_hz", range->high_hz - range->low_hz}};
}

// As `swum pick --json`: numbers as JSON numbers, null where undecided.
std::string band_json(const std::vector<BandRow>& rows, const BandSummary& s, double margin_hz) {
  auto number_or_null = [](bool known, double v) { return known && std::isfinite(v) ? Json(v) : Json(nullptr); };
  Json list = Json::array();
  for (const BandRow& row : rows) {
    const PickResult& p = row.pick;
    Json j;
    j["vpp"] = row.vpp;
    j["load_n"] = row.load_n;
    j["temperature_rise_k"] = row.temperature_rise_k;
    j["decided"] = p.decided;
    j["frequency_hz"] = number_or_null(p.decided, p.frequency_hz);
    j["speed_mm_s"] = number_or_null(p.decided, p.speed_mm_s);
    j["peak_frequency_hz"] = number_or_null(p.decided, p.peak_frequency_hz);
    j["peak_speed_mm_s"] = number_or_null(p.decided, p.peak_speed_mm_s);
    j["margin_hz"] = number_or_null(p.decided, p.margin_hz);
    j["collapse_hz"] = number_or_null(p.decided && p.collapse_hz.has_value(), p.collapse_hz.value_or(NAN));
    j["reason"] = p.reason;
    list.push_back(j);
  }
  Json j;
  j["min_margin_hz"] = margin_hz;
  j["decided"] = s.decided;
  j["undecided"] = s.undecided;
  j["band"] = range_json(s.band);
  j["peak"] = range_json(s.peak);
  j["rows"] = list;
  return j.dump(2) + "\n";
}

std::string band_text(const std::vector<BandRow>& rows, const BandSummary& s, const BandOptions& o) {
  std::string t;
  if (s.band) {
    t += format_numbers("operating band %.0f .. %.0f Hz (%.0f Hz wide): the picked frequencies", s.band->low_hz,
                        s.band->high_hz, s.band->high_hz - s.band->low_hz) +
         format_numbers(", margin >= %g Hz above the peak\n", o.margin_hz) +
         format_numbers("peak range %.0f .. %.0f Hz (%.0f Hz wide)\n", s.peak->low_hz, s.peak->high_hz,
                        s.peak->high_hz - s.peak->low_hz);
  } else {
    t += "no operating band: no row decided\n";
  }
  t += format_numbers("rows: %.0f decided, %.0f undecided\n", static_cast<double>(s.decided),
                      static_cast<double>(s.undecided));
  for (const BandRow& row : rows) {
    if (row.pick.decided) continue;
    t += format_numbers("  %g Vpp, %g N, %g K rise: ", row.vpp, row.load_n, row.temperature_rise_k) + row.pick.reason +
         "\n";
  }
  if (!o.out_path.empty()) t += "rows -> " + o.out_path + "\n";
  return t;
}

void run_band(const BandOptions& o) {
  BandGrid grid;
  grid.voltages = parse_number_list(o.vpp_list, "--vpp");
  grid.loads_n = parse_number_list(o.load_list, "--load");
  grid.temperature_rises_k = parse_number_list(o.rise_list, "--temperature-rise-k");
  grid.frequencies_hz = parse_range_or_value(o.frequency_range, "--frequency");
  grid.margin_hz = o.margin_hz;
  check_band_grid(grid, o.jobs);  // every bad value named before the file is read
  const MotorParameters parameters = load_motor_parameters(o.config_path);
  check_band_thermal(grid, parameters, o.config_path);
  const MotorModel model(parameters);
  std::vector<BandRow> rows;
  {
    ProgressBar progress("band", grid.voltages.size() * grid.loads_n.size() * grid.temperature_rises_k.size() *
                                     grid.frequencies_hz.size());
    rows = run_operating_band(model, grid, o.jobs, [&] { progress.advance(); });
  }
  const BandSummary summary = summarize_band(rows);
  if (!o.out_path.empty()) write_text_file_atomically(o.out_path, band_csv(rows));
  const std::string text = o.json ? band_json(rows, summary, o.margin_hz) : band_text(rows, summary, o);
  std::fputs(text.c_str(), stdout);
  if (summary.undecided > 0) {
    throw CommandError(std::to_string(summary.undecided) + " of " + std::to_string(rows.size()) +
                       " rows undecided: the band may not cover them (see reason)");
  }
}

}  // namespace

void add_band_command(CLI::App& app) {
  auto o = std::make_shared<BandOptions>();
  CLI::App* sub = app.add_subcommand(
      "band", "Band of operating frequencies over voltages, loads and stator temperatures (model down-sweeps)");
  sub->add_option("--config", o->config_path, "motor parameter file (TOML)")->required();
  sub->add_option("--vpp", o->vpp_list, "voltages, comma list (Vpp)")->required();
  sub->add_option("--load", o->load_list, "loads, comma list (N)")->capture_default_str();
  sub->add_option("--temperature-rise-k", o->rise_list,
                  "stator temperature rises over ambient, comma list (K, 0..300; other than 0 needs [effects.thermal])")
      ->capture_default_str();
  sub->add_option("--margin-hz", o->margin_hz, "minimum margin above the peak (Hz), as swum pick")
      ->capture_default_str();
  sub->add_option("--frequency", o->frequency_range,
                  "START:STOP:STEP (Hz); every chain runs it from STOP down to START (default: 41500 down to 38000 Hz "
                  "in 25 Hz steps)")
      ->capture_default_str();
  sub->add_option("--out", o->out_path, "write the rows as CSV (atomically)");
  sub->add_flag("--json", o->json, "summary and rows as JSON on stdout");
  sub->add_option("--jobs", o->jobs, "worker threads (0: all cores)")->capture_default_str();
  sub->callback([o] { run_band(*o); });
}

}  // namespace swum::host
