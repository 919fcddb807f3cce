// firmware_sim/http/http_recording.h: one CSV row per tick (the header's columns, numbers that read
// back exactly) and TelemetryRecorder: the header, one row per tick pushed while on (by hand
// or by EmulatorCore), status, refusals, the next recording replacing the file. No sleeps:
// stop() drains the ring before it returns.
#include "http/http_recording.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "../emu_test_support.h"
#include "core/emulator_core.h"

namespace swum::emu {
namespace {

// A fresh directory under gtest's temporary directory (the recording's name has only the PID).
class TempDirectory {
 public:
  TempDirectory() {
    std::string pattern = testing::TempDir() + "swum-recording-XXXXXX";
    if (::mkdtemp(pattern.data()) != nullptr) path_ = pattern;
    EXPECT_FALSE(path_.empty()) << "mkdtemp " << pattern;
  }
  ~TempDirectory() {
    std::error_code ignored;
    if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
  }
  TempDirectory(const TempDirectory&) = delete;
  TempDirectory& operator=(const TempDirectory&) = delete;
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::string::size_type start = 0;
  for (;;) {
    const auto end = line.find(separator, start);
    fields.push_back(line.substr(start, end - start));
    if (end == std::string::npos) return fields;
    start = end + 1;
  }
}

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

double to_double(const std::string& text) {
  double v = std::numeric_limits<double>::quiet_NaN();
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  EXPECT_TRUE(r.ec == std::errc{} && r.ptr == text.data() + text.size()) << text;
  return v;
}

Telemetry telemetry_at(std::uint64_t tick) {
  Telemetry t;
  t.tick = tick;
  t.sim_time_s = static_cast<double>(tick) / 10000.0;
  t.speed_m_s = 0.1 + 1e-6 * static_cast<double>(tick);
  return t;
}

// A recorder on the heap (its ring holds 16384 telemetry snapshots: megabytes).
struct Recording {
  TempDirectory directory;
  SharedState shared;
  std::unique_ptr<TelemetryRecorder> recorder = std::make_unique<TelemetryRecorder>(shared, directory.path());
  // Pushes ticks first..last as the loop would while the recording is on.
  void push(std::uint64_t first, std::uint64_t last) {
    ASSERT_NE(shared.recording, nullptr);
    ASSERT_TRUE(shared.recording->on.load());
    for (std::uint64_t k = first; k <= last; ++k) ASSERT_TRUE(shared.recording->ring.try_push(telemetry_at(k)));
  }
  std::vector<std::string> rows() {
    std::vector<std::string> lines = lines_of(recorder->path());
    if (lines.empty()) {
      ADD_FAILURE() << "no header in " << recorder->path();
      return lines;
    }
    EXPECT_EQ(lines.front(), kRecordingHeader);
    lines.erase(lines.begin());
    return lines;
  }
};

std::uint64_t tick_of(const std::string& row) { return std::stoull(split(row, ',').at(0)); }

// --- recording_row -------------------------------------------------------------------------------

TEST(HttpRecording, RowHasOneFieldPerHeaderColumnAndEndsTheLine) {
  const std::vector<std::string> columns = split(kRecordingHeader, ',');
  EXPECT_EQ(columns.size(), 32U);
  EXPECT_EQ(columns.front(), "tick");
  EXPECT_EQ(columns.back(), "lateness_p99_ns");
  const std::string row = recording_row(telemetry_at(7));
  ASSERT_FALSE(row.empty());
  EXPECT_EQ(row.back(), '\n');
  EXPECT_EQ(row.find('\n'), row.size() - 1);
  EXPECT_EQ(split(row.substr(0, row.size() - 1), ',').size(), columns.size());
}

TEST(HttpRecording, RowValuesAreInTheirColumnsAndReadBackExactly) {
  Telemetry t = telemetry_at(123456789);
  t.sim_time_s = 0.1 + 0.2;  // 0.30000000000000004: the shortest form must keep every bit
  t.state = AmpState::fault;
  t.fault = FaultCode::over_current;
  t.enable_line = false;
  t.at_setpoint = true;
  t.setpoints.frequency_hz = 40123.5;
  t.output.load_n = -1.25;
  t.speed_m_s = 0.6123456789012345;
  t.position_m = -3.5e-7;
  t.electrical.current_b_a = 0.0;
  t.electrical.power_b_w = 1.0 / 3.0;
  t.stator_temperature_c = 20.0;
  t.applied_commands = 42;
  t.stats.overruns = 3;
  t.stats.lateness_p99_ns = 98765;
  const std::string row = recording_row(t);
  const std::vector<std::string> columns = split(kRecordingHeader, ',');
  const std::vector<std::string> fields = split(row.substr(0, row.size() - 1), ',');
  ASSERT_EQ(fields.size(), columns.size());
  const auto field = [&](const std::string& name) {
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] == name) return fields[i];
    ADD_FAILURE() << "no column " << name;
    return std::string();
  };
  EXPECT_EQ(field("tick"), "123456789");
  EXPECT_EQ(to_double(field("sim_time_s")), 0.1 + 0.2);
  EXPECT_EQ(field("state"), to_string(AmpState::fault));
  EXPECT_EQ(field("fault"), "over_current");  // the identifier, as the API names it
  EXPECT_EQ(field("enable_line"), "0");
  EXPECT_EQ(field("at_setpoint"), "1");
  EXPECT_EQ(to_double(field("setpoint_frequency_hz")), 40123.5);
  EXPECT_EQ(to_double(field("output_load_n")), -1.25);
  EXPECT_EQ(to_double(field("speed_m_s")), 0.6123456789012345);
  EXPECT_EQ(to_double(field("position_m")), -3.5e-7);
  EXPECT_EQ(to_double(field("current_b_a")), 0.0);
  EXPECT_EQ(to_double(field("power_b_w")), 1.0 / 3.0);
  EXPECT_EQ(to_double(field("stator_temperature_c")), 20.0);
  EXPECT_EQ(field("applied_commands"), "42");
  EXPECT_EQ(field("overruns"), "3");
  EXPECT_EQ(field("lateness_p99_ns"), "98765");
}

// --- TelemetryRecorder ----------------------------------------------------------------------------

TEST(HttpRecording, RecorderOffersItsRingToTheLoopForItsLifetime) {
  TempDirectory directory;
  SharedState shared;
  auto recorder = std::make_unique<TelemetryRecorder>(shared, directory.path());
  ASSERT_NE(shared.recording, nullptr);
  EXPECT_FALSE(shared.recording->on.load());  // nothing pushed until a start
  EXPECT_EQ(recorder->path(),
            directory.path() + "/swum-emu-recording-" + std::to_string(static_cast<long>(::getpid())) + ".csv");
  recorder.reset();
  EXPECT_EQ(shared.recording, nullptr);
}

TEST(HttpRecording, WritesTheHeaderAndOneRowPerTickPushedWhileOn) {
  Recording r;
  ASSERT_EQ(r.recorder->start(), "");
  r.push(100, 1099);
  ASSERT_EQ(r.recorder->stop(), "");
  EXPECT_FALSE(r.shared.recording->on.load());
  const std::vector<std::string> rows = r.rows();
  ASSERT_EQ(rows.size(), 1000U);
  for (std::size_t i = 0; i < rows.size(); ++i) ASSERT_EQ(tick_of(rows[i]), 100 + i) << "row " << i;
  EXPECT_EQ(rows[5] + "\n", recording_row(telemetry_at(105)));
}

TEST(HttpRecording, StatusCountsTheRowsAndTheirTicks) {
  Recording r;
  RecordingStatus before = r.recorder->status();
  EXPECT_FALSE(before.recording);
  EXPECT_FALSE(before.available);
  ASSERT_EQ(r.recorder->start(), "");
  EXPECT_TRUE(r.recorder->status().recording);
  EXPECT_FALSE(r.recorder->status().available);
  r.push(5000, 5299);
  ASSERT_EQ(r.recorder->stop(), "");
  const RecordingStatus s = r.recorder->status();
  EXPECT_FALSE(s.recording);
  EXPECT_TRUE(s.available);
  EXPECT_EQ(s.rows, 300U);
  EXPECT_EQ(s.dropped, 0U);
  EXPECT_EQ(s.first_tick, 5000U);
  EXPECT_EQ(s.last_tick, 5299U);
  EXPECT_EQ(s.error, "");
}

TEST(HttpRecording, EmptyRecordingIsTheHeaderAlone) {
  Recording r;
  ASSERT_EQ(r.recorder->start(), "");
  ASSERT_EQ(r.recorder->stop(), "");
  EXPECT_TRUE(r.rows().empty());
  EXPECT_EQ(r.recorder->status().rows, 0U);
  EXPECT_TRUE(r.recorder->status().available);
}

TEST(HttpRecording, StartWhileRecordingAndStopWhileNotAreRefused) {
  Recording r;
  EXPECT_EQ(r.recorder->stop(), "no recording is running");
  ASSERT_EQ(r.recorder->start(), "");
  EXPECT_EQ(r.recorder->start(), "a recording is already running (stop it first)");
  r.push(1, 10);
  ASSERT_EQ(r.recorder->stop(), "");
  EXPECT_EQ(r.recorder->stop(), "no recording is running");
  EXPECT_EQ(r.rows().size(), 10U);  // the refused start changed nothing
}

TEST(HttpRecording, NextRecordingReplacesTheFile) {
  Recording r;
  ASSERT_EQ(r.recorder->start(), "");
  r.push(1, 50);
  ASSERT_EQ(r.recorder->stop(), "");
  ASSERT_EQ(r.recorder->start(), "");
  EXPECT_EQ(r.recorder->status().rows, 0U);
  r.push(900, 902);
  ASSERT_EQ(r.recorder->stop(), "");
  const std::vector<std::string> rows = r.rows();
  ASSERT_EQ(rows.size(), 3U);
  EXPECT_EQ(tick_of(rows.front()), 900U);
  EXPECT_EQ(r.recorder->status().first_tick, 900U);
  EXPECT_EQ(r.recorder->status().last_tick, 902U);
}

TEST(HttpRecording, TicksLeftInTheRingBeforeAStartAreNotWritten) {
  Recording r;
  for (std::uint64_t k = 1; k <= 20; ++k) ASSERT_TRUE(r.shared.recording->ring.try_push(telemetry_at(k)));
  ASSERT_EQ(r.recorder->start(), "");
  r.push(21, 25);
  ASSERT_EQ(r.recorder->stop(), "");
  const std::vector<std::string> rows = r.rows();
  ASSERT_EQ(rows.size(), 5U);
  EXPECT_EQ(tick_of(rows.front()), 21U);
}

TEST(HttpRecording, DirectoryThatCannotBeWrittenIsRefusedOnStart) {
  SharedState shared;
  auto recorder = std::make_unique<TelemetryRecorder>(shared, "/nonexistent-swum-directory");
  const std::string error = recorder->start();
  EXPECT_EQ(error.rfind("cannot create /nonexistent-swum-directory/swum-emu-recording-", 0), 0U) << error;
  EXPECT_NE(error.find(".csv.XXXXXX: No such file or directory"), std::string::npos) << error;
  EXPECT_FALSE(recorder->status().recording);
  EXPECT_FALSE(shared.recording->on.load());  // the loop pushes nothing
  EXPECT_EQ(recorder->stop(), "no recording is running");
}

// The loop's side: EmulatorCore pushes every tick while the recording is on, none otherwise.
TEST(HttpRecording, EmulatorCoreTicksAreRecordedWhileOnAndOnlyThen) {
  TempDirectory directory;
  SharedState shared;
  CoreConfig config;
  config.tick_hz = 10000.0;
  config.amplifier.watchdog_s = 0.0;
  EmulatorCore core(test::li2019_model(), config, shared);
  auto recorder = std::make_unique<TelemetryRecorder>(shared, directory.path());
  for (int i = 0; i < 10; ++i) core.tick();  // telemetry ticks 1..10: before the start
  ASSERT_EQ(recorder->start(), "");
  for (int i = 0; i < 250; ++i) core.tick();  // 11..260
  ASSERT_EQ(recorder->stop(), "");
  for (int i = 0; i < 10; ++i) core.tick();  // after the stop
  EXPECT_EQ(shared.recording->dropped.load(), 0U);
  const std::vector<std::string> lines = lines_of(recorder->path());
  ASSERT_EQ(lines.size(), 251U);
  EXPECT_EQ(lines.front(), kRecordingHeader);
  for (std::size_t i = 1; i < lines.size(); ++i) ASSERT_EQ(tick_of(lines[i]), 10 + i) << "line " << i;
  const RecordingStatus s = recorder->status();
  EXPECT_EQ(s.rows, 250U);
  EXPECT_EQ(s.first_tick, 11U);
  EXPECT_EQ(s.last_tick, 260U);
  // sim_time_s of each row is its tick's end: tick / 10 kHz.
  const std::vector<std::string> last = split(lines.back(), ',');
  EXPECT_NEAR(to_double(last.at(1)), 260.0 / 10000.0, 1e-9);
}

// A download holds the last recording's file open: a new recording is written beside it and
// renamed over it at its stop, so the open file still reads whole; both go with the recorder.
TEST(HttpRecording, AnOpenDownloadKeepsTheLastRecordingWholeAndTheFilesGoWithTheRecorder) {
  char directory[] = "/tmp/swum_recording_rename_XXXXXX";
  ASSERT_NE(::mkdtemp(directory), nullptr);
  SharedState shared;
  std::string path;
  {
    TelemetryRecorder recorder(shared, directory);
    path = recorder.path();
    Telemetry t;
    ASSERT_EQ(recorder.start(), "");
    for (std::uint64_t k = 1; k <= 10; ++k) {
      t.tick = k;
      ASSERT_TRUE(shared.recording->ring.try_push(t));
    }
    ASSERT_EQ(recorder.stop(), "");
    std::ifstream download(path);  // the first recording, opened as a download opens it
    ASSERT_TRUE(download.good());
    ASSERT_EQ(recorder.start(), "");
    for (std::uint64_t k = 100; k < 103; ++k) {
      t.tick = k;
      ASSERT_TRUE(shared.recording->ring.try_push(t));
    }
    ASSERT_EQ(recorder.stop(), "");
    std::string line;
    std::size_t rows = 0;
    while (std::getline(download, line)) ++rows;
    EXPECT_EQ(rows, 11U);  // header + 10: the first recording, untouched
    std::ifstream latest(path);
    rows = 0;
    while (std::getline(latest, line)) ++rows;
    EXPECT_EQ(rows, 4U);  // header + 3
  }
  EXPECT_NE(::access(path.c_str(), F_OK), 0);  // removed with the recorder
  EXPECT_EQ(::rmdir(directory), 0) << "files left in " << directory;
}

TEST(HttpRecording, CloseStopsTheRecordingUnderWayRemovesItsFilesAndRefusesLaterStarts) {
  char directory[] = "/tmp/swum_recording_close_XXXXXX";
  ASSERT_NE(::mkdtemp(directory), nullptr);
  SharedState shared;
  {
    TelemetryRecorder recorder(shared, directory);
    ASSERT_EQ(recorder.start(), "");
    ASSERT_EQ(recorder.stop(), "");  // a finished recording
    ASSERT_EQ(::access(recorder.path().c_str(), F_OK), 0);
    ASSERT_EQ(recorder.start(), "");  // and one under way, in a file of its own
    Telemetry t;
    t.tick = 7;
    ASSERT_TRUE(shared.recording->ring.try_push(t));
    recorder.close();
    const RecordingStatus st = recorder.status();
    EXPECT_FALSE(st.recording);
    EXPECT_FALSE(st.available);
    EXPECT_FALSE(shared.recording->on.load());  // the loop pushes no more
    EXPECT_NE(::access(recorder.path().c_str(), F_OK), 0);
    EXPECT_EQ(::rmdir(directory), 0) << "files left in " << directory;  // nothing in it any more
    EXPECT_EQ(recorder.start(), "the emulator is stopping: no new recording");
    EXPECT_EQ(recorder.stop(), "no recording is running");
    recorder.close();  // idempotent
  }
}

}  // namespace
}  // namespace swum::emu
