#include "http/http_api.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <httplib.h>

#include "core/lockstep_clock.h"
#include "http/api_thread_priority.h"
#include "http/dashboard_assets.h"
#include "http/http_json.h"
#include "http/http_range.h"

namespace swum::emu {
namespace {

using nlohmann::json;
constexpr const char* kJson = "application/json";
// Connections served at once besides the streams: 48 clients stalled mid-request (each holding
// a thread up to the read timeout) still leave others served at once. Idle threads cost a stack.
constexpr int kRequestThreads = 48;
// Stream rates: at least one event per 10 s; between events a comment line every second, so a
// client that left is found (the write fails) within about a second plus the write timeout.
constexpr double kMinStreamHz = 0.1;
constexpr std::size_t kMaxPathBytes = 256;
constexpr auto kStreamHeartbeat = std::chrono::seconds(1);

// cpp-httplib calls a content provider outside its try: a throw there (an allocation in the
// state's JSON, say) would end the process. One that throws ends its transfer instead.
template <typename Provider>
auto no_throw(Provider provider) {
  return [provider = std::move(provider)](auto&&... args) mutable noexcept {
    try {
      return provider(std::forward<decltype(args)>(args)...);
    } catch (...) {
      return false;
    }
  };
}

void send_json(httplib::Response& response, const json& body, int status = 200) {
  response.status = status;
  response.set_content(body.dump() + "\n", kJson);
}

void send_error(httplib::Response& response, int status, const std::string& message) {
  response.status = status;
  response.set_content(error_body(message), kJson);
}

// Compares without leaving the position of the first difference in the timing.
bool same_token(const std::string& given, const std::string& expected) {
  unsigned char difference = given.size() == expected.size() ? 0 : 1;
  for (std::size_t i = 0; i < given.size(); ++i)
    difference |= static_cast<unsigned char>(given[i] ^ expected[i % std::max<std::size_t>(1, expected.size())]);
  return difference == 0;
}

// The query's rate_hz, or the default; HttpError 400 when not a number in (0, max].
double stream_rate(const httplib::Request& request, double default_hz, double max_hz) {
  if (!request.has_param("rate_hz")) return default_hz;
  const std::string text = request.get_param_value("rate_hz");
  double value = 0.0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(value))
    throw HttpError(400, "rate_hz '" + text + "' is not a number");
  if (!(value >= kMinStreamHz) || value > max_hz)
    throw HttpError(400, "rate_hz " + text + " out of range [" + json(kMinStreamHz).dump() + ", " +
                             json(max_hz).dump() + "]");
  return value;
}

// cpp-httplib's pool, its threads lowered before their first task.
class ApiThreadPool final : public httplib::TaskQueue {
 public:
  explicit ApiThreadPool(std::size_t threads) : pool_(threads) {}
  void enqueue(std::function<void()> task) override {
    pool_.enqueue([task = std::move(task)] {
      lower_api_thread_priority();
      task();
    });
  }
  void shutdown() override { pool_.shutdown(); }

 private:
  httplib::ThreadPool pool_;
};

// One stream client's slot: held as long as any copy of its provider lives.
struct StreamSlot {
  explicit StreamSlot(std::atomic<std::uint64_t>& count) : count_(count) {}
  ~StreamSlot() { count_.fetch_sub(1); }
  StreamSlot(const StreamSlot&) = delete;
  StreamSlot& operator=(const StreamSlot&) = delete;
  std::atomic<std::uint64_t>& count_;
};

}  // namespace

bool is_loopback_host(const std::string& host) {
  if (host == "localhost") return true;
  in_addr v4{};
  if (inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  return inet_pton(AF_INET6, host.c_str(), &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

HttpApi::HttpApi(HttpConfig config, SharedState& shared, const MotorModel& model)
    : config_(std::move(config)),
      shared_(shared),
      resonance_(model),
      recorder_(shared, config_.recording_directory),
      server_(std::make_unique<httplib::Server>()) {
  const std::string where = "--http " + config_.host + ":" + std::to_string(config_.port);
  // One thread per connection (cpp-httplib): the streams, plus room for requests and for clients
  // slow to send theirs (each holds its thread up to the read timeout; docs/http-api.md "Safety").
  server_->new_task_queue = [n = config_.max_stream_clients + kRequestThreads] { return new ApiThreadPool(n); };
  server_->set_payload_max_length(config_.max_body_bytes);
  server_->set_read_timeout(std::chrono::milliseconds(config_.read_timeout_ms));
  server_->set_write_timeout(std::chrono::milliseconds(config_.write_timeout_ms));
  // One request per connection. A request refused before routing (a foreign Origin, a POST not
  // declared JSON) leaves its body unread; on a kept-alive connection that body would be read as
  // the next request, and a page elsewhere could smuggle a fault past the refusal. Closing after
  // each answer discards it; on the loopback a new connection costs microseconds.
  server_->set_keep_alive_max_count(1);
  // A connection that sends nothing is closed after 2 s (cpp-httplib's default is 5 s, longer
  // than the 3 s stop() waits for connections to end).
  server_->set_keep_alive_timeout(2);
  routes();
  endpoints();
  loopback_ = is_loopback_host(config_.host);
  port_ = config_.port == 0 ? server_->bind_to_any_port(config_.host) : config_.port;
  if (port_ <= 0 || (config_.port != 0 && !server_->bind_to_port(config_.host, config_.port)))
    throw std::runtime_error(where + ": cannot listen there (" + std::strerror(errno) +
                             "; in use, or not an address of this machine)");
}

HttpApi::~HttpApi() {
  if (!stop(std::chrono::milliseconds(3000))) std::abort();  // the caller must not destroy an abandoned API
}

void HttpApi::start() {
  thread_ = std::thread([this] {
    lower_api_thread_priority();
    server_->listen_after_bind();
    const std::lock_guard lock(listen_mutex_);
    listen_ended_ = true;
    listen_ended_cv_.notify_all();
  });
  // Server::stop() does nothing before the server runs: wait, so that a stop right after the
  // start (a short --duration-s, an early SIGTERM) is not lost.
  for (int i = 0; i < 5000 && !server_->is_running(); ++i) {
    {
      const std::lock_guard lock(listen_mutex_);
      if (listen_ended_) break;  // listen failed at once
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

bool HttpApi::stop(std::chrono::milliseconds wait) {
  if (stopping_.exchange(true)) return !abandoned_;
  server_->stop();  // first: no request that arrives from now on starts a recording
  if (thread_.joinable()) {
    // The listening thread ends when the pool has finished every connection; a client still
    // sending its request (a byte now and then) holds its thread. Wait a little, not forever.
    std::unique_lock lock(listen_mutex_);
    if (listen_ended_cv_.wait_for(lock, wait, [this] { return listen_ended_; })) {
      lock.unlock();
      thread_.join();
    } else {
      thread_.detach();
      abandoned_ = true;
    }
  }
  // A recording under way is stopped and its files removed, also when a connection is left
  // running (the process then ends without destructors): a request it still completes cannot
  // start another.
  recorder_.close();
  return !abandoned_;
}

bool HttpApi::authorized(const httplib::Request& request, httplib::Response& response) {
  if (config_.token.empty()) return true;
  std::string given;
  const std::string header = request.get_header_value("Authorization");
  if (header.size() > 7 && strncasecmp(header.c_str(), "Bearer ", 7) == 0) {  // the scheme is case-insensitive
    given = header.substr(7);
  } else if (request.has_param("token")) {  // EventSource and download links cannot set a header
    given = request.get_param_value("token");
  } else {
    response.set_header("WWW-Authenticate", "Bearer");
    send_error(response, 401, "missing token: send 'Authorization: Bearer TOKEN' or ?token=TOKEN");
    return false;
  }
  if (!same_token(given, config_.token)) {
    response.set_header("WWW-Authenticate", "Bearer error=\"invalid_token\"");
    send_error(response, 401, "wrong token");
    return false;
  }
  return true;
}

std::string HttpApi::state_text() {
  // Requests within a millisecond of each other (streams on the same grid) share one text.
  const auto now = std::chrono::steady_clock::now();
  {
    const std::lock_guard lock(state_cache_mutex_);
    if (!state_cache_.empty() && now - state_cache_at_ < std::chrono::milliseconds(1)) return state_cache_;
  }
  const Telemetry t = shared_.telemetry.load();
  const RejectSnapshot rejects{static_cast<Reason>(shared_.rejects.last_reason.load(std::memory_order_relaxed)),
                               shared_.rejects.count.load(std::memory_order_acquire)};
  json body = state_json(t, rejects, resonance_.at(t.output.amplitude_v, t.stator_temperature_c),
                         shared_.canopen_nmt_state.load(std::memory_order_relaxed));
  const ActiveFaults faults = shared_.active_faults.load();
  json names = json::array();
  for (std::uint32_t i = 0; i < faults.count && i < faults.items.size(); ++i)
    names.push_back(to_string(faults.items[i].type));
  body["active_faults"] = std::move(names);
  std::string text = body.dump();
  const std::lock_guard lock(state_cache_mutex_);
  state_cache_ = text;
  state_cache_at_ = now;
  return text;
}

void HttpApi::state(const httplib::Request&, httplib::Response& response) {
  response.set_content(state_text() + "\n", kJson);
}

void HttpApi::queue_fault(const RuntimeEvent& event, httplib::Response& response) {
  if (config_.trace_recording) {
    send_error(response, 409,
               "run-time faults are off while --record writes a trace (a replay could not "
               "play them): give them as --inject or in a --scenario");
    return;
  }
  // The tick before the push: once queued, the loop may apply the fault before a later read.
  const std::uint64_t after_tick = shared_.telemetry.load().tick;
  if (!shared_.runtime_events.try_push(event)) {
    send_error(response, 503, "too many faults waiting for the next tick; try again");
    return;
  }
  stats_.faults_queued.fetch_add(1);
  // What was queued, in the --inject form without the time ("phase_open:phase=B,duration_s=0").
  std::string queued = "clear all";
  if (!(event.type == EventType::clear && event.parameters.fault == EventType::clear)) {
    ScenarioEvent e;
    e.type = event.type;
    e.parameters = event.parameters;
    queued = format_event(e);
    const auto at = queued.find('@');
    queued.erase(at, queued.find(':') == std::string::npos ? std::string::npos : queued.find(':') - at);
  }
  std::fprintf(stderr, "swum-emu: http: queued %s after tick %llu\n", queued.c_str(),
               static_cast<unsigned long long>(after_tick));
  const json body = {{"queued", queued}, {"applies_at", "the next tick boundary"}, {"after_tick", after_tick}};
  send_json(response, body, 202);
}

void HttpApi::step(const httplib::Request& request, httplib::Response& response) {
  if (shared_.lockstep == nullptr) {
    send_error(response, 409, "the clock is internal: steps need swum-emu --clock external");
    return;
  }
  const double tick_hz = shared_.tick_hz;
  const auto max_ticks = static_cast<std::uint64_t>(std::llround(60.0 * tick_hz));
  const std::uint64_t ticks = parse_step_request(request.body, tick_hz, max_ticks);
  if (!shared_.lockstep->advance(ticks)) {
    send_error(response, 503, "the emulator stopped before the ticks ran");
    return;
  }
  const Telemetry t = shared_.telemetry.load();
  send_json(response, {{"stepped_ticks", ticks}, {"tick", t.tick}, {"sim_time_s", t.sim_time_s}});
}

void HttpApi::stream(const httplib::Request& request, httplib::Response& response) {
  const double rate_hz = stream_rate(request, config_.stream_default_hz, config_.stream_max_hz);
  if (stats_.stream_clients.fetch_add(1) >= static_cast<std::uint64_t>(config_.max_stream_clients)) {
    stats_.stream_clients.fetch_sub(1);
    stats_.stream_refused.fetch_add(1);
    send_error(response, 503,
               "too many stream clients (" + std::to_string(config_.max_stream_clients) + "; --http-stream-clients)");
    return;
  }
  auto slot = std::make_shared<StreamSlot>(stats_.stream_clients);
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / rate_hz));
  // Events on a grid of whole periods of the steady clock: streams at the same rate fire together
  // and share one snapshot text (state_text's cache), whatever the number of clients.
  const auto now = std::chrono::steady_clock::now().time_since_epoch();
  auto next = std::make_shared<std::chrono::steady_clock::time_point>((now / period + 1) * period);
  response.set_header("Cache-Control", "no-store");
  auto last_write = std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
  response.set_chunked_content_provider(
      "text/event-stream", no_throw([this, slot, period, next, last_write](std::size_t, httplib::DataSink& sink) {
        // Sleep to the next event in short slices, so that stop() ends the stream promptly.
        for (;;) {
          if (stopping_.load()) return false;
          const auto now = std::chrono::steady_clock::now();
          if (now >= *next) break;
          if (now - *last_write >= kStreamHeartbeat) {
            static constexpr char kComment[] = ": keep-alive\n\n";
            if (!sink.write(kComment, sizeof kComment - 1)) return false;  // the client left
            *last_write = now;
          }
          std::this_thread::sleep_for(
              std::min<std::chrono::steady_clock::duration>(*next - now, std::chrono::milliseconds(50)));
        }
        *next += period;
        // Late (a slow write, a busy machine): the next grid point from now, not a burst.
        if (const auto now = std::chrono::steady_clock::now(); *next < now)
          *next = std::chrono::steady_clock::time_point((now.time_since_epoch() / period + 1) * period);
        const std::string event = "event: telemetry\ndata: " + state_text() + "\n\n";
        if (!sink.write(event.data(), event.size())) return false;  // the client left or stopped reading
        *last_write = std::chrono::steady_clock::now();
        stats_.stream_events.fetch_add(1, std::memory_order_relaxed);
        return true;
      }));
}

void HttpApi::routes() {
  httplib::Server& s = *server_;
  s.set_pre_routing_handler([this](const httplib::Request& request, httplib::Response& response) {
    stats_.requests.fetch_add(1, std::memory_order_relaxed);
    // Byte ranges are the download's own (http_range.h): cpp-httplib would apply them to every
    // reply, error bodies included. The request is the server's (non-const) object.
    const_cast<httplib::Request&>(request).ranges.clear();
    int status = 0;
    if (const std::string why = refusal(request, status); !why.empty()) {
      send_error(response, status, why);
      return httplib::Server::HandlerResponse::Handled;
    }
    if (request.path.rfind("/api/", 0) != 0) return httplib::Server::HandlerResponse::Unhandled;  // the page
    return authorized(request, response) ? httplib::Server::HandlerResponse::Unhandled
                                         : httplib::Server::HandlerResponse::Handled;
  });
  // Neither handler may throw: cpp-httplib calls them outside its own try, and a throw there
  // would end the process.
  s.set_exception_handler([](const httplib::Request&, httplib::Response& response, std::exception_ptr error) {
    try {
      try {
        std::rethrow_exception(error);
      } catch (const HttpError& e) {
        send_error(response, e.status(), e.what());
      } catch (const std::exception& e) {
        send_error(response, 500, std::string("internal error: ") + e.what());
      }
    } catch (...) {
      response.status = 500;
      response.set_content("{\"error\": \"internal error\"}\n", kJson);
    }
  });
  s.set_error_handler([this](const httplib::Request& request, httplib::Response& response) {
    // cpp-httplib's own refusals (a malformed Range among them) come before the pre-routing
    // handler: ranges it parsed part of would cut this error body.
    const_cast<httplib::Request&>(request).ranges.clear();
    stats_.refused.fetch_add(1, std::memory_order_relaxed);
    if (!response.body.empty()) return;  // a handler's own message
    try {
      error_text(request, response);
    } catch (...) {
      response.set_content("{\"error\": \"request refused\"}\n", kJson);
    }
  });
}

void HttpApi::error_text(const httplib::Request& request, httplib::Response& response) {
  switch (response.status) {
    case 404: send_error(response, 404, "no such endpoint: " + request.method + " " + request.path); break;
    case 413:
      send_error(response, 413, "request body over " + std::to_string(config_.max_body_bytes) + " bytes");
      break;
    case 400:
      send_error(response, 400,
                 "malformed request (request line, headers, or a body that stopped arriving for " +
                     std::to_string(config_.read_timeout_ms) + " ms)");
      break;
    case 416:  // cpp-httplib's own, before routing: a Range header it cannot parse
      send_error(response, 416,
                 "byte range not satisfiable: malformed Range header '" + request.get_header_value("Range") + "'");
      break;
    default: send_error(response, response.status, "request refused"); break;
  }
}

std::string HttpApi::refusal(const httplib::Request& request, int& status) const {
  // cpp-httplib matches routes with std::regex, whose matcher recurses once per character: a
  // path of thousands of bytes takes megabytes of stack. No path of this server is near this.
  if (request.path.size() > kMaxPathBytes) {
    status = 414;
    return "path over " + std::to_string(kMaxPathBytes) + " bytes";
  }
  // A page elsewhere must not drive the motor through the user's browser: with a loopback bind,
  // the Host must name this server (DNS rebinding), and an Origin must be this server's (CSRF).
  const std::string host = request.get_header_value("Host");
  if (loopback_ && !host.empty()) {
    const std::string port = ":" + std::to_string(port_);
    const std::string bound = config_.host.find(':') == std::string::npos ? config_.host : "[" + config_.host + "]";
    if (host != "127.0.0.1" + port && host != "localhost" + port && host != "[::1]" + port && host != bound + port) {
      status = 403;
      return "Host '" + host + "' is not this server (" + bound + port + ")";
    }
  }
  if (const std::string origin = request.get_header_value("Origin"); !origin.empty() && origin != "http://" + host) {
    status = 403;
    return "cross-origin request refused (Origin " + origin + ")";
  }
  const bool api = request.path.rfind("/api/", 0) == 0;
  if (api && request.has_header("Range") && request.path != "/api/v1/recording.csv") {
    status = 400;
    return "the API does not serve byte ranges (Range is for /api/v1/recording.csv)";
  }
  // A POST is JSON, declared: a form or a text/plain body (which a page elsewhere may send
  // without asking) is refused before anything runs.
  if (request.method == "POST") {
    const std::string type = request.get_header_value("Content-Type");
    std::string media = type.substr(0, type.find(';'));
    while (!media.empty() && media.back() == ' ') media.pop_back();
    for (char& c : media) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (media != "application/json") {
      status = 415;
      return type.empty() ? "Content-Type: application/json is required (even with an empty body)"
                          : "Content-Type must be application/json, not " + type;
    }
  }
  return {};
}

void HttpApi::endpoints() {
  httplib::Server& s = *server_;

  // The page and its files (no token: they hold no state; the page asks for one).
  for (const DashboardAsset& asset : dashboard_assets()) {
    const std::string path = asset.path == "index.html" ? "/" : "/" + std::string(asset.path);
    s.Get(path, [&asset](const httplib::Request&, httplib::Response& response) {
      response.set_header("Cache-Control", "no-cache");
      response.set_content(asset.body.data(), asset.body.size(), std::string(asset.content_type));
    });
  }

  s.Get("/api/v1/state", [this](const auto& q, auto& r) { state(q, r); });
  s.Get("/api/v1/stats", [this](const httplib::Request&, httplib::Response& response) {
    const Telemetry t = shared_.telemetry.load();
    send_json(response, {{"tick", t.tick},
                         {"sim_time_s", t.sim_time_s},
                         {"tick_hz", shared_.tick_hz},
                         {"clock", shared_.lockstep != nullptr ? "external" : "internal"},
                         {"speedup", shared_.speedup},
                         {"loop", loop_json(t.stats)},
                         {"commands",
                          {{"applied", t.applied_commands},
                           {"rejected", shared_.rejects.count.load()},
                           {"queue_full", shared_.queue_full.load()}}},
                         {"http",
                          {{"requests", stats_.requests.load()},
                           {"refused", stats_.refused.load()},
                           {"stream_clients", stats_.stream_clients.load()},
                           {"stream_clients_max", config_.max_stream_clients},
                           {"stream_refused", stats_.stream_refused.load()},
                           {"stream_events", stats_.stream_events.load()},
                           {"faults_queued", stats_.faults_queued.load()}}}});
  });
  s.Get("/api/v1/faults", [this](const httplib::Request&, httplib::Response& response) {
    const ActiveFaults faults = shared_.active_faults.load();
    send_json(response, {{"types", fault_types_json()},
                         {"active", active_faults_json(faults, shared_.tick_hz)},
                         {"active_total", faults.total},
                         {"refused", faults.refused}});
  });
  s.Post("/api/v1/faults", [this](const httplib::Request& request, httplib::Response& response) {
    queue_fault(parse_fault_request(request.body), response);
  });
  s.Delete("/api/v1/faults", [this](const httplib::Request&, httplib::Response& response) {
    RuntimeEvent all;
    all.type = EventType::clear;
    all.parameters.fault = EventType::clear;
    queue_fault(all, response);
  });
  s.Delete(R"(/api/v1/faults/([^/]+))", [this](const httplib::Request& request, httplib::Response& response) {
    queue_fault(clear_request(request.matches[1].str()), response);
  });
  s.Get("/api/v1/recording", [this](const httplib::Request&, httplib::Response& response) {
    const RecordingStatus st = recorder_.status();
    send_json(response, {{"recording", st.recording},
                         {"available", st.available},
                         {"rows", st.rows},
                         {"dropped", st.dropped},
                         {"first_tick", st.first_tick},
                         {"last_tick", st.last_tick},
                         {"error", st.error.empty() ? json(nullptr) : json(st.error)}});
  });
  s.Post("/api/v1/recording/start", [this](const httplib::Request&, httplib::Response& response) {
    if (const std::string e = recorder_.start(); !e.empty()) return send_error(response, 409, e);
    send_json(response, {{"recording", true}});
  });
  s.Post("/api/v1/recording/stop", [this](const httplib::Request&, httplib::Response& response) {
    if (const std::string e = recorder_.stop(); !e.empty())
      return send_error(response, e.rfind("no recording", 0) == 0 ? 409 : 500, e);
    const RecordingStatus st = recorder_.status();
    send_json(response, {{"recording", false}, {"rows", st.rows}, {"dropped", st.dropped}});
  });
  s.Get("/api/v1/recording.csv", [this](const httplib::Request& request, httplib::Response& response) {
    const RecordingStatus st = recorder_.status();
    if (st.recording) return send_error(response, 409, "the recording is still running: stop it first");
    if (!st.available) return send_error(response, 404, "no recording to download: start and stop one first");
    const int fd = ::open(recorder_.path().c_str(), O_RDONLY | O_CLOEXEC);
    struct stat info {};
    if (fd < 0 || ::fstat(fd, &info) != 0) {
      const int e = errno;
      if (fd >= 0) ::close(fd);
      return send_error(response, 500, "cannot read " + recorder_.path() + ": " + std::strerror(e));
    }
    auto file = std::shared_ptr<int>(new int(fd), [](int* f) {
      ::close(*f);
      delete f;
    });
    const auto size = static_cast<std::uint64_t>(info.st_size);
    // Each recording is a new file renamed over the last: its inode, time and size name it. A
    // resumed download sends it back (If-Range); when it names an older recording the whole new
    // file comes, never its bytes joined to the old one's (RFC 9110, section 13.1.5).
    const std::string etag = "\"" + std::to_string(info.st_ino) + "-" + std::to_string(info.st_mtim.tv_sec) + "." +
                             std::to_string(info.st_mtim.tv_nsec) + "-" + std::to_string(size) + "\"";
    response.set_header("ETag", etag);
    const bool same_recording = !request.has_header("If-Range") || request.get_header_value("If-Range") == etag;
    const ByteRange range = same_recording ? resolve_byte_range(request.get_header_value("Range"), size) : ByteRange{};
    if (range.kind == ByteRange::Kind::unsatisfiable) {
      response.set_header("Content-Range", "bytes */" + std::to_string(size));
      return send_error(response, 416,
                        "byte range not satisfiable: the recording has " + std::to_string(size) + " bytes");
    }
    std::uint64_t first = 0, length = size;
    if (range.kind == ByteRange::Kind::partial) {
      first = range.first;
      length = range.last - range.first + 1;
      response.status = 206;
      response.set_header("Content-Range", "bytes " + std::to_string(range.first) + "-" + std::to_string(range.last) +
                                               "/" + std::to_string(size));
    }
    response.set_header("Accept-Ranges", "bytes");
    response.set_header("Content-Disposition", "attachment; filename=\"swum-emu-recording.csv\"");
    response.set_content_provider(
        static_cast<std::size_t>(length), "text/csv",
        no_throw([file, first](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
          char buffer[65536];
          const ssize_t n = ::pread(*file, buffer, std::min(length, sizeof buffer), static_cast<off_t>(first + offset));
          if (n <= 0) return false;  // the file shrank or failed: the transfer ends short
          return sink.write(buffer, static_cast<std::size_t>(n));
        }));
  });
  s.Post("/api/v1/step",
         [this](const httplib::Request& request, httplib::Response& response) { step(request, response); });
  s.Get("/api/v1/stream", [this](const auto& q, auto& r) { stream(q, r); });
}

}  // namespace swum::emu
