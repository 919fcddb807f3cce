// `swum pick --sweep sweep.csv --vpp LIST`: the operating frequency per voltage from a sweep
// table (offline model sweep or live device sweep), by pick_operating_point.
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "command_error.h"
#include "commands.h"
#include "operating_point.h"
#include "text_files.h"
#include "value_lists.h"

namespace swum::host {
namespace {

struct PickCommandOptions {
  std::string sweep_path;
  std::string vpp_list;
  double load_n = 0.0;
  double margin_hz = 0.0;
  bool json = false;
  std::string schedule_path;
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// vpp -> curve at the chosen load.
std::map<double, std::vector<CurveSample>> read_curves(const std::string& path, double load_n) {
  std::stringstream in(read_text_file(path));
  std::string line;
  if (!std::getline(in, line)) throw CommandError(path + ": empty file");
  const auto header = split(line);
  auto column = [&](const std::string& name) {
    for (std::size_t i = 0; i < header.size(); ++i) if (header[i] == name) return static_cast<int>(i);
    return -1;
  };
  const int cv = column("vpp"), cf = column("frequency_hz"), cl = column("load_n"),
            cs = column("speed_mm_s"), cst = column("status"), csp = column("speed_spread_mm_s");
  if (cv < 0 || cf < 0 || cs < 0) throw CommandError(path + ": not a sweep table (needs vpp, frequency_hz, speed_mm_s)");
  std::map<double, std::vector<CurveSample>> curves;
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    const auto cells = split(line);
    auto cell = [&](int c) { return c >= 0 && c < static_cast<int>(cells.size()) ? cells[c] : std::string(); };
    const std::string where = path + " line " + std::to_string(number);
    const double vpp = parse_finite_number(cell(cv), where + " vpp");
    const double f = parse_finite_number(cell(cf), where + " frequency_hz");
    if (cl >= 0 && std::abs(parse_finite_number(cell(cl), where + " load_n") - load_n) > 1e-9) continue;
    CurveSample s;
    s.frequency_hz = f;
    s.ok = (cst < 0 || cell(cst) == "ok") && !cell(cs).empty();
    if (s.ok) s.speed_mm_s = parse_finite_number(cell(cs), where + " speed_mm_s");
    if (csp >= 0 && !cell(csp).empty()) s.spread_mm_s = parse_finite_number(cell(csp), where + " speed_spread_mm_s");
    curves[vpp].push_back(s);
  }
  return curves;
}

void run_pick(const PickCommandOptions& o) {
  const std::vector<double> voltages = parse_number_list(o.vpp_list, "--vpp");
  if (o.margin_hz < 0.0) throw std::invalid_argument("--margin-hz: must be >= 0");
  const auto curves = read_curves(o.sweep_path, o.load_n);
  PickOptions options;
  options.min_margin_hz = o.margin_hz;
  std::vector<std::pair<double, PickResult>> results;
  for (double v : voltages) {
    auto it = curves.end();
    for (auto c = curves.begin(); c != curves.end(); ++c) if (std::abs(c->first - v) < 1e-6) it = c;
    if (it == curves.end()) throw CommandError(o.sweep_path + ": no rows at " + std::to_string(v) + " Vpp");
    results.emplace_back(v, pick_operating_point(it->second, options));
  }
  // Drift: from the peak of the lowest decided voltage.
  double base = NAN;
  double base_vpp = INFINITY;
  for (const auto& [v, r] : results) if (r.decided && v < base_vpp) { base_vpp = v; base = r.peak_frequency_hz; }

  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  std::string schedule = "vpp,frequency_hz\n";
  bool any_undecided = false;
  for (const auto& [v, r] : results) {
    nlohmann::ordered_json j;
    j["vpp"] = v;
    j["decided"] = r.decided;
    j["frequency_hz"] = r.decided ? nlohmann::ordered_json(r.frequency_hz) : nullptr;
    j["speed_mm_s"] = r.decided ? nlohmann::ordered_json(r.speed_mm_s) : nullptr;
    j["naive_speed_mm_s"] = r.naive_speed_mm_s ? nlohmann::ordered_json(*r.naive_speed_mm_s) : nullptr;
    j["peak_frequency_hz"] = r.decided ? nlohmann::ordered_json(r.peak_frequency_hz) : nullptr;
    j["drift_hz"] = r.decided && std::isfinite(base) ? nlohmann::ordered_json(r.peak_frequency_hz - base) : nullptr;
    j["margin_hz"] = r.margin_hz;
    j["reason"] = r.reason;
    list.push_back(j);
    if (r.decided) {
      char line[64];
      std::snprintf(line, sizeof line, "%.6g,%.6g\n", v, r.frequency_hz);
      schedule += line;
    } else {
      any_undecided = true;
    }
    if (!o.json) {
      if (r.decided) {
        std::printf("%6g Vpp: run at %.0f Hz, %.1f mm/s (naive 40.4 kHz: %s), drift %+.0f Hz; %s\n", v,
                    r.frequency_hz, r.speed_mm_s,
                    r.naive_speed_mm_s ? std::to_string(*r.naive_speed_mm_s).c_str() : "n/a",
                    r.peak_frequency_hz - base, r.reason.c_str());
      } else {
        std::printf("%6g Vpp: undecided: %s\n", v, r.reason.c_str());
      }
    }
  }
  if (o.json) std::printf("%s\n", list.dump(2).c_str());
  if (!o.schedule_path.empty()) write_text_file_atomically(o.schedule_path, schedule);
  if (any_undecided) throw CommandError("no frequency picked for some voltages (see reason)", kExitFailure);
}

}  // namespace

void add_pick_command(CLI::App& app) {
  auto o = std::make_shared<PickCommandOptions>();
  CLI::App* sub = app.add_subcommand("pick", "Operating frequency per voltage from a sweep table");
  sub->add_option("--sweep", o->sweep_path, "sweep CSV (swum sweep --out)")->required();
  sub->add_option("--vpp", o->vpp_list, "voltages, comma list (Vpp)")->required();
  sub->add_option("--load", o->load_n, "load of the rows to use (N)")->capture_default_str();
  sub->add_option("--margin-hz", o->margin_hz, "minimum margin above the peak (Hz)")->capture_default_str();
  sub->add_flag("--json", o->json, "JSON list on stdout");
  sub->add_option("--schedule", o->schedule_path, "write vpp,frequency_hz CSV");
  sub->callback([o] { run_pick(*o); });
}

}  // namespace swum::host
