#include "track/track_report.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "formats/csv_cells.h"
#include "formats/csv_table.h"
#include "formats/number_format.h"

namespace swum::host {
namespace {

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  if (x.empty()) return std::nan("");
  if (at <= x.front()) return y.front();
  if (at >= x.back()) return y.back();
  const auto hi = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), at) - x.begin());
  const double w = (at - x[hi - 1]) / (x[hi] - x[hi - 1]);
  return y[hi - 1] + w * (y[hi] - y[hi - 1]);
}

// A swum track or band CSV read back (CsvLines::hand_written): cells by column name, one-line
// errors naming file:line.
class TrackTable {
 public:
  explicit TrackTable(const std::string& path) : path_(path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    text_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    table_ = read_csv_table(text_);
    if (!table_.header) throw std::runtime_error(path + ": empty (no header)");
    if (std::string retired = csv_retired_column_message(table_, path); !retired.empty()) {
      throw std::runtime_error(retired);
    }
    const std::size_t width = table_.header->cells.size();
    for (const CsvRow& row : table_.rows) {
      if (row.cells.size() != width) {
        throw std::runtime_error(csv_message(
            path, row.line, 0, std::to_string(row.cells.size()) + " cells, the header has " + std::to_string(width)));
      }
    }
  }
  TrackTable(const TrackTable&) = delete;  // the table views text_
  TrackTable& operator=(const TrackTable&) = delete;
  [[nodiscard]] std::size_t size() const { return table_.rows.size(); }
  [[nodiscard]] std::size_t column(const std::string& name) const {
    const int index = table_.column(name);
    if (index < 0) throw std::runtime_error(path_ + ": no column " + name);
    return static_cast<std::size_t>(index);
  }
  [[nodiscard]] std::string_view cell(std::size_t row, std::size_t column) const {
    return table_.rows[row].cells[column];
  }
  [[nodiscard]] double number(std::size_t row, std::size_t column, const std::string& name) const {
    double value = 0.0;
    const std::string_view text = cell(row, column);
    if (const char* problem = parse_number_cell(text, value)) {
      throw std::runtime_error(
          csv_message(path_, table_.rows[row].line, 0, name + " '" + std::string(text) + "' " + problem));
    }
    return value;
  }

 private:
  std::string path_;
  std::string text_;
  CsvTable table_;
};

}  // namespace

double BestSpeedCurve::speed_at(double rise_k) const { return interpolate(temperature_rise_k, speed_mm_s, rise_k); }
double BestSpeedCurve::frequency_at(double rise_k) const {
  return interpolate(temperature_rise_k, frequency_hz, rise_k);
}
double BestSpeedCurve::peak_frequency_at(double rise_k) const {
  return interpolate(temperature_rise_k, peak_frequency_hz, rise_k);
}

TrackRunSummary summarise_track(const TrackSeries& run, const BestSpeedCurve& best, double ambient_c, double skip_s,
                                double block_s) {
  const std::size_t n = best.temperature_rise_k.size();
  if (n < 2) throw std::runtime_error("the band has fewer than two decided rises");
  if (best.speed_mm_s.size() != n || best.frequency_hz.size() != n || best.peak_frequency_hz.size() != n)
    throw std::runtime_error("the band's columns differ in length");
  if (!(block_s > 0.0 && block_s <= 1e6)) throw std::invalid_argument("--block-s: must be in (0, 1e6]");
  if (!(skip_s >= 0.0 && skip_s <= 1e6)) throw std::invalid_argument("--skip-s: must be in 0..1e6");
  if (!(std::abs(ambient_c) <= 1000.0))
    throw std::invalid_argument("--ambient-c: must be a temperature in -1000..1000");
  TrackRunSummary s;
  s.name = run.name;
  TrackBlock block;
  double best_sum = 0.0, speed_sum = 0.0, rise_sum = 0.0, margin_sum = 0.0;
  int count = 0;
  auto close_block = [&] {
    if (count == 0) return;
    block.mean_speed_mm_s = speed_sum / count;
    block.best_speed_mm_s = best_sum / count;
    block.mean_rise_k = rise_sum / count;
    block.share = block.mean_speed_mm_s / block.best_speed_mm_s;
    block.margin_hz = margin_sum / count;
    s.blocks.push_back(block);
    best_sum = speed_sum = rise_sum = margin_sum = 0.0;
    count = 0;
  };
  for (std::size_t i = 0; i < run.time_s.size(); ++i) {
    const double t = run.time_s[i];
    if (std::isnan(run.stator_temperature_c[i]))
      throw std::runtime_error(run.name + ": row " + std::to_string(i + 1) + " has no stator temperature");
    const double rise = run.stator_temperature_c[i] - ambient_c;
    s.max_rise_k = std::max(s.max_rise_k, rise);
    if (t < skip_s) continue;
    if (!(rise >= best.temperature_rise_k.front() - 1e-9 && rise <= best.temperature_rise_k.back() + 1e-9)) {
      throw std::runtime_error(run.name + ": temperature rise " + format_number(rise) +
                               " K at t = " + format_number(t) + " s outside the band's " +
                               format_number(best.temperature_rise_k.front()) + ".." +
                               format_number(best.temperature_rise_k.back()) + " K");
    }
    if (count > 0 && t >= block.start_s + block_s) close_block();
    if (count == 0) block.start_s = t;
    block.end_s = t;
    best_sum += best.speed_at(rise);
    speed_sum += run.speed_mm_s[i];
    rise_sum += rise;
    margin_sum += run.frequency_hz[i] - best.peak_frequency_at(rise);
    ++count;
    s.final_frequency_hz = run.frequency_hz[i];
    s.final_rise_k = rise;
  }
  close_block();
  if (s.blocks.empty()) throw std::runtime_error(run.name + ": no rows after --skip-s");
  s.min_share = 1e300;
  for (const TrackBlock& b : s.blocks) s.min_share = std::min(s.min_share, b.share);
  s.final_share = s.blocks.back().share;
  s.final_margin_hz = s.blocks.back().margin_hz;
  return s;
}

TrackSeries read_track_csv(const std::string& path, const std::string& name) {
  const TrackTable table(path);
  TrackSeries run;
  run.name = name;
  const std::size_t time = table.column("time_s"), frequency = table.column("frequency_hz"),
                    speed = table.column("speed_mm_s"), temperature = table.column("stator_temperature_c");
  for (std::size_t r = 0; r < table.size(); ++r) {
    run.time_s.push_back(table.number(r, time, "time_s"));
    run.frequency_hz.push_back(table.number(r, frequency, "frequency_hz"));
    run.speed_mm_s.push_back(table.number(r, speed, "speed_mm_s"));
    run.stator_temperature_c.push_back(
        table.cell(r, temperature).empty() ? std::nan("") : table.number(r, temperature, "stator_temperature_c"));
  }
  if (run.time_s.empty()) throw std::runtime_error(path + ": no rows");
  return run;
}

BestSpeedCurve read_band_csv(const std::string& path, double amplitude_v, double load_n) {
  const TrackTable table(path);
  const std::size_t v = table.column("amplitude_v"), load = table.column("load_n"),
                    rise = table.column("temperature_rise_k"), decided = table.column("decided"),
                    speed = table.column("speed_mm_s"), frequency = table.column("frequency_hz"),
                    peak = table.column("peak_frequency_hz");
  struct Point {
    double rise, speed, frequency, peak;
    bool operator<(const Point& o) const { return rise < o.rise; }
  };
  std::vector<Point> points;
  for (std::size_t r = 0; r < table.size(); ++r) {
    if (table.number(r, v, "amplitude_v") != amplitude_v || table.number(r, load, "load_n") != load_n) continue;
    const std::string_view d = table.cell(r, decided);
    if (d != "1" && d != "true") continue;
    points.push_back({table.number(r, rise, "temperature_rise_k"), table.number(r, speed, "speed_mm_s"),
                      table.number(r, frequency, "frequency_hz"), table.number(r, peak, "peak_frequency_hz")});
  }
  std::sort(points.begin(), points.end());
  BestSpeedCurve curve;
  for (const Point& p : points) {
    if (!curve.temperature_rise_k.empty() && p.rise == curve.temperature_rise_k.back()) {
      throw std::runtime_error(path + ": two decided rows at a " + format_number(p.rise) + " K rise, " +
                               format_number(amplitude_v) + " V and " + format_number(load_n) + " N");
    }
    curve.temperature_rise_k.push_back(p.rise);
    curve.speed_mm_s.push_back(p.speed);
    curve.frequency_hz.push_back(p.frequency);
    curve.peak_frequency_hz.push_back(p.peak);
  }
  if (curve.temperature_rise_k.size() < 2) {
    throw std::runtime_error(path + ": fewer than two decided rows at " + format_number(amplitude_v) + " V and " +
                             format_number(load_n) + " N");
  }
  return curve;
}

}  // namespace swum::host
