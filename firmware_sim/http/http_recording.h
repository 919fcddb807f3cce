// The HTTP API's recording (docs/http-api.md "Recording"): while on, the loop pushes every
// tick's telemetry into SharedState's ring (TelemetryRecording) and a writer thread of its own
// drains it into a CSV file, one row per tick. A full ring (the writer more than 1.6 s behind
// at 10 kHz) drops ticks and counts them: the recording says so rather than hide a gap.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

#include "core/shared_state.h"

namespace swum::emu {

// The recording's columns and one row (shortest round-trip decimals; state and fault by name).
extern const char* const kRecordingHeader;
std::string recording_row(const Telemetry& t);

struct RecordingStatus {
  bool recording = false;
  bool available = false;     // a finished recording can be downloaded
  std::uint64_t rows = 0;     // written so far (this recording or the last)
  std::uint64_t dropped = 0;  // ticks lost to a full ring
  std::uint64_t first_tick = 0, last_tick = 0;
  std::string error;  // a write error (the recording stopped), else empty
};

class TelemetryRecorder {
 public:
  // `shared.recording` is set to this recorder's ring for its lifetime. A recording is written
  // to a new file of its own (DIRECTORY/swum-emu-recording-PID.csv.XXXXXX) and renamed to
  // DIRECTORY/swum-emu-recording-PID.csv when it stops (replacing the last one); both are
  // removed when the recorder is destroyed (the download is the way to keep one).
  TelemetryRecorder(SharedState& shared, std::string directory);
  ~TelemetryRecorder();
  TelemetryRecorder(const TelemetryRecorder&) = delete;
  TelemetryRecorder& operator=(const TelemetryRecorder&) = delete;

  // Empty when started; else why not (already recording, closed, the file cannot be created, no
  // writer thread).
  std::string start();
  // Stops at the next tick boundary and writes what the ring holds. Empty when stopped; else why not.
  std::string stop();
  // For good (the emulator is stopping): stops a recording under way, removes both files, and
  // refuses every later start. Idempotent; the destructor calls it.
  void close();
  [[nodiscard]] RecordingStatus status() const;
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  void drain();
  std::string stop_locked();
  SharedState& shared_;
  TelemetryRecording ring_;
  std::string path_;
  std::string part_path_;     // the recording under way
  mutable std::mutex mutex_;  // start/stop/status against each other
  std::FILE* file_ = nullptr;
  std::thread writer_;
  std::atomic<bool> writing_{false};
  std::atomic<std::uint64_t> rows_{0};
  std::atomic<std::uint64_t> first_tick_{0}, last_tick_{0};
  std::uint64_t dropped_at_start_ = 0;
  std::uint64_t dropped_ = 0;
  bool available_ = false;
  bool closed_ = false;
  std::string error_;
  int write_errno_ = 0;
};

}  // namespace swum::emu
