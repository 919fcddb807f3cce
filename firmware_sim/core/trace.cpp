#include "core/trace.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <stdexcept>
#include <string_view>

#include "formats/csv_cells.h"
#include "formats/number_format.h"

namespace swum::emu {
namespace {

constexpr std::size_t kColumns = 30;
constexpr std::size_t kFirstTelemetryColumn = 12;  // enable_line

void put(std::string& out, double value) { append_shortest_decimal(out, value); }  // shortest round trip
void put(std::string& out, std::uint64_t value) { out += std::to_string(value); }
void put_empty(std::string& out, std::size_t count) { out.append(count, ','); }

// The cells of a trace row, byte for byte (a replayed row is compared with the recorded one).
std::vector<std::string_view> split(std::string_view line) { return split_csv_cells(line, CsvCellTrim::none); }

std::vector<std::string_view> column_names() { return split(kTraceHeader); }

}  // namespace

std::string TraceSettings::line() const {
  std::string out = "# swum-emu trace 1";
  for (const auto& [name, value] : values) out += "; " + name + "=" + value;
  return out;
}

std::string fnv1a_hex(const std::string& text) {
  std::uint64_t h = 14695981039346656037ULL;
  for (const unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(h));
  return buffer;
}

std::string command_row(std::uint64_t tick, const Command& c) {
  std::string out = "command,";
  put(out, tick);
  out += ',';
  put(out, c.sequence);
  out += ',';
  put(out, std::uint64_t{static_cast<std::uint8_t>(c.source)});
  out += ',';
  put(out, std::uint64_t{c.fields});
  out += ',';
  put(out, std::uint64_t{static_cast<std::uint8_t>(c.action)});
  for (const double v :
       {c.frequency_hz, c.amplitude_v, c.phase_deg, c.load_n, c.frequency_slew_hz_per_s, c.amplitude_slew_v_per_s}) {
    out += ',';
    put(out, v);
  }
  put_empty(out, kColumns - kFirstTelemetryColumn);
  return out;
}

std::string enable_line_row(std::uint64_t tick, bool enable_line) {
  std::string out = "line,";
  put(out, tick);
  put_empty(out, kFirstTelemetryColumn - 1);
  out += enable_line ? '1' : '0';
  put_empty(out, kColumns - kFirstTelemetryColumn - 1);
  return out;
}

std::string telemetry_row(const Telemetry& t) {
  std::string out = "telemetry,";
  put(out, t.tick);
  put_empty(out, kFirstTelemetryColumn - 1);
  const std::uint64_t codes[] = {t.enable_line ? 1U : 0U, static_cast<std::uint8_t>(t.state),
                                 static_cast<std::uint8_t>(t.fault), t.at_setpoint ? 1U : 0U};
  for (std::size_t i = 0; i < std::size(codes); ++i) {
    if (i) out += ',';
    put(out, codes[i]);
  }
  for (const double v : {t.output.amplitude_v, t.output.frequency_hz, t.output.phase_deg, t.output.load_n, t.speed_m_s,
                         t.tick_speed_m_s, t.position_m, t.tip_normal_um, t.tip_tangential_um}) {
    out += ',';
    put(out, v);
  }
  for (const std::uint64_t v : {t.applied_commands, t.amplifier_rejects, t.last_sequence, t.divergences}) {
    out += ',';
    put(out, v);
  }
  out += ',';
  put(out, t.sim_time_s);
  return out;
}

TraceRecorder::TraceRecorder(const std::string& path, const TraceSettings& settings) : path_(path) {
  file_ = std::fopen(path.c_str(), "w");
  if (file_ == nullptr) throw std::runtime_error("--record " + path + ": " + std::strerror(errno));
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
  write(settings.line());
  write(kTraceHeader);
}

TraceRecorder::~TraceRecorder() {
  if (file_ != nullptr) std::fclose(file_);
}

void TraceRecorder::write(const std::string& row) {
  if (std::fwrite(row.data(), 1, row.size(), file_) != row.size() || std::fputc('\n', file_) == EOF) {
    if (first_error_ == 0) first_error_ = errno != 0 ? errno : EIO;
    return;
  }
  ++rows_;
}

void TraceRecorder::on_command(std::uint64_t tick, const Command& command) { write(command_row(tick, command)); }
void TraceRecorder::on_enable_line(std::uint64_t tick, bool enable_line) { write(enable_line_row(tick, enable_line)); }
void TraceRecorder::on_telemetry(const Telemetry& telemetry) { write(telemetry_row(telemetry)); }

std::string TraceRecorder::close() {
  if (file_ == nullptr) return {};
  const bool flushed = std::fflush(file_) == 0;
  const int flush_errno = errno;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (first_error_ != 0) return "--record " + path_ + ": write failed: " + std::strerror(first_error_);
  if (!flushed || !closed) return "--record " + path_ + ": " + std::strerror(flush_errno);
  return {};
}

namespace {

// Control characters (from the file's bytes) written as \xNN: the message is always one line.
std::string printable(const std::string& text) {
  std::string out;
  for (const unsigned char c : text) {
    if (c < 0x20 || c == 0x7F) {
      char buffer[5];
      std::snprintf(buffer, sizeof buffer, "\\x%02X", c);
      out += buffer;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

[[noreturn]] void fail(const std::string& file, std::size_t line, const std::string& what) {
  throw TraceError(printable(file + ":" + std::to_string(line) + ": " + what));
}

template <typename T>
T parse_number(std::string_view text, const std::string& file, std::size_t line, std::string_view column) {
  T value{};
  const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size() || text.empty())
    fail(file, line, std::string(column) + " '" + std::string(text) + "' is not a number");
  return value;
}

}  // namespace

Trace read_trace(std::istream& in, const std::string& file) {
  Trace trace;
  std::string text;
  std::size_t line = 0;
  if (!std::getline(in, text) || text.rfind("# swum-emu trace 1", 0) != 0)
    fail(file, 1, "not a swum-emu trace (first line must be '# swum-emu trace 1; ...')");
  ++line;
  for (std::string_view rest = std::string_view(text).substr(18); !rest.empty();) {
    if (rest.substr(0, 2) != "; ") fail(file, 1, "settings must be '; name=value' pairs");
    rest.remove_prefix(2);
    const std::size_t end = std::min(rest.find("; "), rest.size());
    const std::string_view pair = rest.substr(0, end);
    const std::size_t eq = pair.find('=');
    if (eq == std::string_view::npos || eq == 0) fail(file, 1, "setting '" + std::string(pair) + "' is not name=value");
    trace.settings.add(std::string(pair.substr(0, eq)), std::string(pair.substr(eq + 1)));
    rest.remove_prefix(end);
  }
  if (!std::getline(in, text) || text != kTraceHeader) fail(file, 2, "the column header is not the trace header");
  ++line;
  const auto names = column_names();
  std::uint64_t last_tick = 0;
  while (std::getline(in, text)) {
    ++line;
    if (text.empty()) continue;
    const auto f = split(text);
    if (f.size() != kColumns)
      fail(file, line, "has " + std::to_string(f.size()) + " columns, the header " + std::to_string(kColumns));
    const auto tick = parse_number<std::uint64_t>(f[1], file, line, "tick");
    if (tick < last_tick)
      fail(file, line, "tick " + std::to_string(tick) + " goes back (after " + std::to_string(last_tick) + ")");
    last_tick = tick;
    if (f[0] == "command") {
      RecordedInput input;
      input.tick = tick;
      Command& c = input.command;
      c.sequence = parse_number<std::uint64_t>(f[2], file, line, names[2]);
      const auto source = parse_number<unsigned>(f[3], file, line, names[3]);
      const auto fields = parse_number<std::uint32_t>(f[4], file, line, names[4]);
      const auto action = parse_number<unsigned>(f[5], file, line, names[5]);
      if (source > static_cast<unsigned>(CommandSource::internal))
        fail(file, line, "unknown source " + std::string(f[3]));
      if (action > kMaxAction) fail(file, line, "unknown action " + std::string(f[5]));
      if (fields >= (1U << 7)) fail(file, line, "unknown field bits " + std::string(f[4]));
      c.source = static_cast<CommandSource>(source);
      c.fields = fields;
      c.action = static_cast<Action>(action);
      double* values[] = {&c.frequency_hz,          &c.amplitude_v, &c.phase_deg, &c.load_n, &c.frequency_slew_hz_per_s,
                          &c.amplitude_slew_v_per_s};
      for (std::size_t i = 0; i < std::size(values); ++i)
        *values[i] = parse_number<double>(f[6 + i], file, line, names[6 + i]);
      trace.inputs.push_back(input);
    } else if (f[0] == "line") {
      RecordedInput input;
      input.tick = tick;
      input.is_command = false;
      const auto value = parse_number<unsigned>(f[kFirstTelemetryColumn], file, line, "enable_line");
      if (value > 1) fail(file, line, "enable_line must be 0 or 1");
      input.enable_line = value == 1;
      trace.inputs.push_back(input);
    } else if (f[0] == "telemetry") {
      if (trace.telemetry.empty() && tick != 1)  // a recording starts with the start-up tick
        fail(file, line,
             "the first telemetry row is of tick " + std::to_string(tick) + ", a recording starts at tick 1");
      if (!trace.telemetry.empty() && tick != trace.telemetry.back().tick + 1)
        fail(file, line,
             "telemetry of tick " + std::to_string(tick) + " follows tick " +
                 std::to_string(trace.telemetry.back().tick) + " (one row per tick)");
      trace.telemetry.push_back({tick, line, text});
    } else {
      fail(file, line, "unknown row kind '" + std::string(f[0]) + "' (command, line, telemetry)");
    }
  }
  if (trace.telemetry.empty()) fail(file, line, "no telemetry rows");
  return trace;
}

std::string compare_settings(const TraceSettings& recorded, const TraceSettings& now) {
  for (const auto& setting : now.values) {
    const std::string& name = setting.first;
    const std::string& value = setting.second;
    const auto it = std::find_if(recorded.values.begin(), recorded.values.end(),
                                 [&](const auto& p) { return p.first == name; });
    if (it == recorded.values.end()) return "the trace does not record " + name + " (this run: " + value + ")";
    if (it->second != value) return "recorded with " + name + "=" + it->second + ", this run has " + value;
  }
  return {};
}

ReplayResult replay(const Trace& trace, EmulatorCore& core, SharedState& shared, const std::atomic<bool>* stop) {
  ReplayResult result;
  const auto names = column_names();
  std::size_t next = 0;
  for (const RecordedTelemetry& expected : trace.telemetry) {
    if (stop != nullptr && stop->load(std::memory_order_relaxed)) {
      result.stopped = true;
      return result;
    }
    while (core.ticks() < expected.tick) {
      const std::uint64_t tick = core.ticks();
      for (; next < trace.inputs.size() && trace.inputs[next].tick <= tick; ++next) {
        const RecordedInput& input = trace.inputs[next];
        if (!input.is_command) {
          shared.enable_line.store(input.enable_line);
        } else if (!shared.commands.try_push(input.command)) {
          result.identical = false;
          result.difference = "tick " + std::to_string(tick) + ": more commands in one tick than the queue holds";
          return result;
        } else {
          ++result.commands;
        }
      }
      core.tick();
    }
    const std::string row = telemetry_row(core.telemetry());
    ++result.ticks;
    if (row != expected.row) {
      const auto a = split(expected.row);
      const auto b = split(row);
      std::size_t column = 0;
      while (column < a.size() && column < b.size() && a[column] == b[column]) ++column;
      result.identical = false;
      result.difference = "tick " + std::to_string(expected.tick) + " (line " + std::to_string(expected.line) +
                          "), column " + (column < names.size() ? std::string(names[column]) : "?") + ": recorded " +
                          (column < a.size() ? std::string(a[column]) : "") + ", replayed " +
                          (column < b.size() ? std::string(b[column]) : "");
      return result;
    }
  }
  return result;
}

}  // namespace swum::emu
