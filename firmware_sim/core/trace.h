// Record and replay (swum-emu --record / --replay, docs/emulator.md "Record and replay"): a
// trace is every command the core applied, with the tick it was applied at, every change of
// the enable line, and the telemetry of every tick, as one CSV. Replaying feeds the recorded
// inputs at their ticks in lockstep and compares the telemetry text field by field: a
// regression test of a controller run without the controller.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <istream>
#include <string>
#include <vector>

#include "core/emulator_core.h"

namespace swum::emu {

// What a trace is recorded with: a replay refuses a different setting (the telemetry would
// differ for a reason that is not a regression).
struct TraceSettings {
  std::vector<std::pair<std::string, std::string>> values;  // name, text (in order)
  void add(const std::string& name, const std::string& value) { values.emplace_back(name, value); }
  [[nodiscard]] std::string line() const;  // "# swum-emu trace 1; name=value; ..."
};

// FNV-1a 64 of a text (the config and scenario files' contents in the settings), as 16 hex digits.
std::string fnv1a_hex(const std::string& text);

// The column header and the rows (shortest round-trip decimal for every double: the same
// values give the same bytes on any machine).
inline constexpr const char* kTraceHeader =
    "row,tick,sequence,source,fields,action,frequency_hz,amplitude_v,phase_deg,load_n,frequency_slew_hz_per_s,"
    "amplitude_slew_v_per_s,enable_line,state,fault,at_setpoint,output_amplitude_v,output_frequency_hz,output_phase_"
    "deg,"
    "output_load_n,speed_m_s,tick_speed_m_s,position_m,tip_normal_um,tip_tangential_um,applied_commands,"
    "amplifier_rejects,last_sequence,divergences,sim_time_s";
std::string command_row(std::uint64_t tick, const Command& command);
std::string enable_line_row(std::uint64_t tick, bool enable_line);
std::string telemetry_row(const Telemetry& t);

// Writes a trace as the core runs (an observer of EmulatorCore). Opens and writes the header at
// construction (throws std::runtime_error naming the file and errno); write errors are counted
// and reported by close().
class TraceRecorder final : public TickObserver {
 public:
  TraceRecorder(const std::string& path, const TraceSettings& settings);
  ~TraceRecorder() override;
  TraceRecorder(const TraceRecorder&) = delete;
  TraceRecorder& operator=(const TraceRecorder&) = delete;
  void on_command(std::uint64_t tick, const Command& command) override;
  void on_enable_line(std::uint64_t tick, bool enable_line) override;
  void on_telemetry(const Telemetry& telemetry) override;
  // Flushes and closes; empty when every row was written, else what failed.
  std::string close();
  [[nodiscard]] std::uint64_t rows() const { return rows_; }

 private:
  void write(const std::string& row);
  std::string path_;
  std::FILE* file_ = nullptr;
  std::uint64_t rows_ = 0;
  int first_error_ = 0;
};

// A trace read back: its settings and rows, split into the inputs to feed and the telemetry to
// compare. Throws TraceError "FILE:LINE: what" for a file that is not a trace.
struct TraceError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct RecordedInput {
  std::uint64_t tick = 0;
  bool is_command = true;
  Command command;
  bool enable_line = true;
};
struct RecordedTelemetry {
  std::uint64_t tick = 0;
  std::size_t line = 0;
  std::string row;
};
struct Trace {
  TraceSettings settings;
  std::vector<RecordedInput> inputs;
  std::vector<RecordedTelemetry> telemetry;
};
Trace read_trace(std::istream& in, const std::string& file_name);

// Compares the recorded settings with this run's: empty when equal, else the first difference.
std::string compare_settings(const TraceSettings& recorded, const TraceSettings& now);

struct ReplayResult {
  bool identical = true;
  bool stopped = false;        // `stop` was set before the end
  std::uint64_t ticks = 0;     // ticks compared
  std::uint64_t commands = 0;  // commands fed
  std::string difference;      // the first: "tick N (line L), column C: recorded X, replayed Y"
};
// Feeds the trace's inputs into `shared` at their ticks and runs `core` (which must be fresh:
// no tick run yet) until the last recorded telemetry row, comparing each tick's row.
// `stop` (SIGINT/SIGTERM) is polled once per recorded tick.
ReplayResult replay(const Trace& trace, EmulatorCore& core, SharedState& shared,
                    const std::atomic<bool>* stop = nullptr);

}  // namespace swum::emu
