// swum-emu's control and inspection API and its dashboard (--http HOST:PORT; docs/http-api.md,
// docs/openapi.yaml): cpp-httplib on threads of its own. It never runs in, waits for or locks
// the loop: it reads the loop's lock-free snapshots (SharedState::telemetry, active_faults) and
// hands run-time faults to it through a lock-free queue drained at the next tick boundary, as
// bus commands are. Lockstep steps go through the same LockstepClock as a Modbus advance.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "core/shared_state.h"
#include "http/http_recording.h"
#include "http/resonance_peak.h"
#include "model/motor_model.h"

namespace httplib {
class Server;
class Request;
class Response;
}  // namespace httplib

namespace swum::emu {

struct HttpConfig {
  std::string host = "127.0.0.1";
  int port = 0;                       // 0: any free port (the ready line names it)
  std::string token;                  // empty: none needed
  double stream_default_hz = 20.0;    // /api/v1/stream without ?rate_hz=
  double stream_max_hz = 100.0;       // highest rate a client may ask for
  int max_stream_clients = 4;         // more get 503
  std::size_t max_body_bytes = 4096;  // larger get 413
  int read_timeout_ms = 2000;         // a request (headers, body) slower than this: 400 / closed
  int write_timeout_ms = 2000;        // a client that does not read for this long is dropped
  std::string recording_directory;    // where recordings are written
  bool trace_recording = false;       // --record: run-time faults refused (the trace could not replay them)
};

// Counters for /api/v1/stats and the exit report.
struct HttpStats {
  std::atomic<std::uint64_t> requests{0};
  std::atomic<std::uint64_t> refused{0};  // answered 4xx/5xx
  std::atomic<std::uint64_t> stream_clients{0};
  std::atomic<std::uint64_t> stream_refused{0};
  std::atomic<std::uint64_t> stream_events{0};
  std::atomic<std::uint64_t> faults_queued{0};
};

// True for the names of this machine's loopback: "localhost", 127.0.0.0/8 and ::1. Bound there,
// the API is reachable only from here, and a request's Host must name it (DNS rebinding).
bool is_loopback_host(const std::string& host);

class HttpApi {
 public:
  // Binds HOST:PORT now (throws std::runtime_error "--http HOST:PORT: why" when it cannot);
  // serves nothing until start().
  HttpApi(HttpConfig config, SharedState& shared, const MotorModel& model);
  ~HttpApi();
  HttpApi(const HttpApi&) = delete;
  HttpApi& operator=(const HttpApi&) = delete;

  void start();
  // Stops the recording, ends the streams and the listening thread and waits for them up to
  // `wait`. False when a connection still holds its thread then (a client sending its request a
  // byte at a time): the threads are left running on this object, which must then never be
  // destroyed (the caller exits the process). Idempotent.
  bool stop(std::chrono::milliseconds wait = std::chrono::milliseconds(3000));
  [[nodiscard]] int port() const { return port_; }
  [[nodiscard]] const HttpStats& stats() const { return stats_; }

 private:
  void routes();     // the handlers of every request: token, errors
  void endpoints();  // the page and /api/v1
  void error_text(const httplib::Request& request, httplib::Response& response);
  // Why a request is refused before routing (foreign Host or Origin, Range on the API, a POST
  // not declared JSON), with its status; empty when it may go on.
  std::string refusal(const httplib::Request& request, int& status) const;
  bool authorized(const httplib::Request& request, httplib::Response& response);
  void state(const httplib::Request& request, httplib::Response& response);
  void stream(const httplib::Request& request, httplib::Response& response);
  void step(const httplib::Request& request, httplib::Response& response);
  void queue_fault(const RuntimeEvent& event, httplib::Response& response);
  std::string state_text();

  HttpConfig config_;
  SharedState& shared_;
  ResonancePeak resonance_;
  TelemetryRecorder recorder_;
  std::unique_ptr<httplib::Server> server_;
  int port_ = 0;
  bool loopback_ = true;  // bound to 127.0.0.1, localhost or ::1: Host must name this server
  std::thread thread_;
  std::mutex listen_mutex_;
  std::condition_variable listen_ended_cv_;
  bool listen_ended_ = false;
  bool abandoned_ = false;
  std::atomic<bool> stopping_{false};
  HttpStats stats_;
  std::mutex state_cache_mutex_;  // the last state text, shared by requests within 1 ms
  std::string state_cache_;
  std::chrono::steady_clock::time_point state_cache_at_;
};

}  // namespace swum::emu
