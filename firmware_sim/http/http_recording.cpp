#include "http/http_recording.h"

#include "http/api_thread_priority.h"

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>

#include "formats/number_format.h"

namespace swum::emu {
namespace {

void add(std::string& row, double value) {
  append_shortest_decimal(row, value);
  row += ',';
}
void add(std::string& row, std::uint64_t value) {
  row += std::to_string(value);
  row += ',';
}
void add(std::string& row, const char* text) {
  row += text;
  row += ',';
}

}  // namespace

const char* const kRecordingHeader =
    "tick,sim_time_s,state,fault,enable_line,at_setpoint,setpoint_frequency_hz,setpoint_amplitude_v,"
    "setpoint_phase_deg,setpoint_load_n,output_amplitude_v,output_frequency_hz,output_phase_deg,output_load_n,speed_m_"
    "s,"
    "position_m,tip_normal_um,tip_tangential_um,current_a_a,current_b_a,phase_a_deg,phase_b_deg,"
    "motional_phase_a_deg,motional_phase_b_deg,power_a_w,power_b_w,stator_temperature_c,applied_commands,"
    "amplifier_rejects,divergences,overruns,lateness_p99_ns";

std::string recording_row(const Telemetry& t) {
  std::string row;
  row.reserve(400);
  add(row, t.tick);
  add(row, t.sim_time_s);
  add(row, to_string(t.state));
  add(row, identifier(t.fault));
  add(row, std::uint64_t{t.enable_line});
  add(row, std::uint64_t{t.at_setpoint});
  for (const double v : {t.setpoints.frequency_hz,
                         t.setpoints.amplitude_v,
                         t.setpoints.phase_deg,
                         t.setpoints.load_n,
                         t.output.amplitude_v,
                         t.output.frequency_hz,
                         t.output.phase_deg,
                         t.output.load_n,
                         t.speed_m_s,
                         t.position_m,
                         t.tip_normal_um,
                         t.tip_tangential_um,
                         t.electrical.current_a_a,
                         t.electrical.current_b_a,
                         t.electrical.phase_a_deg,
                         t.electrical.phase_b_deg,
                         t.electrical.motional_phase_a_deg,
                         t.electrical.motional_phase_b_deg,
                         t.electrical.power_a_w,
                         t.electrical.power_b_w,
                         t.stator_temperature_c})
    add(row, v);
  for (const std::uint64_t v : {t.applied_commands, t.amplifier_rejects, t.divergences, t.stats.overruns}) add(row, v);
  row += std::to_string(t.stats.lateness_p99_ns);
  row += '\n';
  return row;
}

TelemetryRecorder::TelemetryRecorder(SharedState& shared, std::string directory)
    : shared_(shared),
      path_(std::move(directory) + "/swum-emu-recording-" + std::to_string(static_cast<long>(getpid())) + ".csv") {
  shared_.recording = &ring_;
}

TelemetryRecorder::~TelemetryRecorder() {
  close();
  shared_.recording = nullptr;
}

void TelemetryRecorder::close() {
  const std::lock_guard lock(mutex_);
  if (writing_.load()) static_cast<void>(stop_locked());
  closed_ = true;
  available_ = false;
  // The recording is the API's to hand out, not a file for later: gone with the process.
  if (!part_path_.empty()) ::unlink(part_path_.c_str());
  ::unlink(path_.c_str());
}

std::string TelemetryRecorder::start() {
  const std::lock_guard lock(mutex_);
  if (closed_) return "the emulator is stopping: no new recording";
  if (writing_.load()) return "a recording is already running (stop it first)";
  // The last recording's status, put back when no writer thread can start: its file is still
  // there to download.
  const std::uint64_t last_rows = rows_, last_first = first_tick_, last_last = last_tick_;
  const std::uint64_t last_dropped_at_start = dropped_at_start_, last_dropped = dropped_;
  const bool last_available = available_;
  std::string last_error = error_;
  // A new file of its own (O_EXCL: no symlink or older file is followed), renamed over the last
  // recording at the stop: a download still reading the last one keeps reading it whole.
  const std::string pattern = path_ + ".XXXXXX";
  std::string part = pattern;
  const int fd = ::mkstemp(part.data());
  if (fd < 0) return "cannot create " + pattern + ": " + std::strerror(errno);
  file_ = ::fdopen(fd, "w");
  if (file_ == nullptr) {
    const int e = errno;
    ::close(fd);
    ::unlink(part.c_str());
    return "cannot open " + part + ": " + std::strerror(e);
  }
  part_path_ = part;
  Telemetry stale;
  while (ring_.ring.try_pop(stale)) {
  }
  rows_ = 0;
  first_tick_ = last_tick_ = 0;
  dropped_at_start_ = ring_.dropped.load();
  dropped_ = 0;
  error_.clear();
  write_errno_ = 0;
  available_ = false;
  if (std::fputs(kRecordingHeader, file_) < 0 || std::fputc('\n', file_) < 0) write_errno_ = errno;
  writing_ = true;
  const auto roll_back = [&] {  // no thread: nothing started, nothing left behind
    writing_ = false;
    std::fclose(file_);
    file_ = nullptr;
    ::unlink(part_path_.c_str());
    part_path_.clear();
    rows_ = last_rows;
    first_tick_ = last_first;
    last_tick_ = last_last;
    dropped_at_start_ = last_dropped_at_start;
    dropped_ = last_dropped;
    available_ = last_available;
    error_ = std::move(last_error);
  };
  try {
    writer_ = std::thread([this] { drain(); });
  } catch (const std::exception& e) {
    roll_back();
    return std::string("cannot start the recording's writer thread: ") + e.what();
  } catch (...) {
    roll_back();
    return "cannot start the recording's writer thread";
  }
  ring_.on.store(true, std::memory_order_release);
  return {};
}

void TelemetryRecorder::drain() {
  lower_api_thread_priority();
  Telemetry t;
  const auto write_all = [&] {  // what the ring holds now; true when there was any
    bool any = false;
    while (ring_.ring.try_pop(t)) {
      any = true;
      const std::string row = recording_row(t);
      if (std::fwrite(row.data(), 1, row.size(), file_) != row.size() && write_errno_ == 0) write_errno_ = errno;
      if (rows_.load(std::memory_order_relaxed) == 0) first_tick_ = t.tick;
      last_tick_ = t.tick;
      rows_.fetch_add(1, std::memory_order_relaxed);
    }
    return any;
  };
  for (;;) {
    const bool any = write_all();
    if (!writing_.load(std::memory_order_acquire)) {
      write_all();  // the loop no longer pushes (stop() waited for it): the last rows
      return;
    }
    if (!any) std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the ring holds 1.6 s at 10 kHz
  }
}

std::string TelemetryRecorder::stop() {
  const std::lock_guard lock(mutex_);
  return stop_locked();
}

std::string TelemetryRecorder::stop_locked() {
  if (!writing_.load()) return "no recording is running";
  ring_.on.store(false, std::memory_order_seq_cst);
  // A tick that read `on` before the store may still push: wait until two more ticks have been
  // published (the second began after the store), or 50 ms where no tick runs (lockstep).
  const std::uint64_t version = shared_.telemetry.version();
  for (int i = 0; i < 50 && shared_.telemetry.version() < version + 2; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  writing_.store(false, std::memory_order_release);
  if (writer_.joinable()) writer_.join();
  dropped_ = ring_.dropped.load() - dropped_at_start_;
  if (std::fflush(file_) != 0 && write_errno_ == 0) write_errno_ = errno;
  if (std::fclose(file_) != 0 && write_errno_ == 0) write_errno_ = errno;
  file_ = nullptr;
  if (write_errno_ != 0) {
    error_ = "writing " + part_path_ + ": " + std::strerror(write_errno_);
  } else if (::rename(part_path_.c_str(), path_.c_str()) != 0) {
    error_ = "renaming " + part_path_ + " to " + path_ + ": " + std::strerror(errno);
  }
  if (!error_.empty()) ::unlink(part_path_.c_str());
  part_path_.clear();
  available_ = error_.empty();
  return error_;
}

RecordingStatus TelemetryRecorder::status() const {
  const std::lock_guard lock(mutex_);
  RecordingStatus s;
  s.recording = writing_.load();
  s.available = available_;
  s.rows = rows_.load();
  s.dropped = s.recording ? ring_.dropped.load() - dropped_at_start_ : dropped_;
  s.first_tick = first_tick_.load();
  s.last_tick = last_tick_.load();
  s.error = error_;
  return s;
}

}  // namespace swum::emu
