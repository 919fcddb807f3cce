#include "transports/gpio_transport.h"

#include "core/monotonic_clock.h"

#include <time.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "formats/name_list.h"
#include "whole_number.h"

namespace swum::emu {

std::string parse_gpio_spec(const std::string& text, GpioConfig& out) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) return "expected CHIP:enable=N,fault=M[,a=K,b=L], got '" + text + "'";
  out.chip = text.substr(0, colon);
  std::vector<std::string> items;
  if (auto problem = split_name_list(std::string_view(text).substr(colon + 1), items); !problem.empty()) return problem;
  for (const std::string& item : items) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) return "expected NAME=OFFSET in '" + item + "'";
    const std::string name = item.substr(0, eq);
    const auto parsed = protocol::parse_whole_number(item.substr(eq + 1), 0, std::numeric_limits<int>::max());
    if (!parsed) return "bad line offset in '" + item + "'";
    const int offset = static_cast<int>(*parsed);
    if (name == "enable") out.enable = offset;
    else if (name == "fault") out.fault = offset;
    else if (name == "a") out.encoder_a = offset;
    else if (name == "b") out.encoder_b = offset;
    else return "unknown GPIO line '" + name + "' (enable, fault, a, b)";
  }
  if ((out.encoder_a < 0) != (out.encoder_b < 0)) return "the encoder needs both a= and b=";
  return {};
}

GpioTransport::GpioTransport(io::GpioLines& lines, GpioConfig config, SharedState& shared)
    : config_(std::move(config)), shared_(shared) {
  if (config_.enable >= 0) {
    enable_ = lines.request_input(line_config(config_.enable), io::GpioEdge::both, io::GpioBias::as_is);
    bool level = false;
    if (const io::GpioResult r = enable_->get(level); !r.ok())
      throw io::GpioError(io::describe(r, line_config(config_.enable)), r.error_number);
    shared_.enable_line.store(level);
  }
  if (config_.fault >= 0) fault_ = lines.request_output(line_config(config_.fault), false);
  if (config_.encoder_a >= 0) {
    a_ = lines.request_output(line_config(config_.encoder_a), false);
    b_ = lines.request_output(line_config(config_.encoder_b), false);
  }
}

GpioTransport::~GpioTransport() { stop(); }

void GpioTransport::start() {
  io_thread_ = std::thread([this] { io_loop(); });
  encoder_origin_m_ = shared_.telemetry.load().position_m;  // count 0 = position at start
  if (a_) encoder_thread_ = std::thread([this] { encoder_loop(); });
}

void GpioTransport::stop() {
  stopping_.store(true);
  if (io_thread_.joinable()) io_thread_.join();
  if (encoder_thread_.joinable()) encoder_thread_.join();
  shared_.enable_line.store(true);
  if (const auto errors = stats_.line_errors.load(); errors > 0) {
    std::fprintf(stderr, "swum-emu: GPIO: %llu line operations failed (first: %s)\n",
                 static_cast<unsigned long long>(errors), first_error().c_str());
  }
}

io::GpioLineConfig GpioTransport::line_config(int offset) const {
  return io::GpioLineConfig{config_.chip, static_cast<unsigned>(offset), "swum-emu"};
}

std::string GpioTransport::first_error() const {
  if (first_error_offset_ < 0) return {};
  return io::describe(first_error_, line_config(first_error_offset_));
}

void GpioTransport::line_failed(const io::GpioResult& result, int offset) {
  if (stats_.line_errors.fetch_add(1) == 0) {  // trivially copied: no allocation on the loop
    first_error_ = result;
    first_error_offset_ = offset;
  }
  const timespec pause{0, 1'000'000};  // a failing line is retried at most once per ms
  ::nanosleep(&pause, nullptr);
}

void GpioTransport::io_loop() {
  bool fault_level = false;
  while (!stopping_.load(std::memory_order_relaxed)) {
    if (enable_) {
      io::GpioEvent event;
      io::GpioResult r = enable_->wait_edge(event, std::chrono::milliseconds(1));
      if (r.ok()) stats_.enable_edges.fetch_add(1);
      bool level = false;
      if (r.status != io::GpioStatus::error) r = enable_->get(level);  // the level after the event(s)
      if (r.status == io::GpioStatus::error) {
        line_failed(r, config_.enable);
        level = false;  // cannot see the input: fail safe, drive off
      }
      shared_.enable_line.store(level);
    } else {
      const timespec pause{0, 1'000'000};
      ::nanosleep(&pause, nullptr);
    }
    if (fault_) {
      const bool level = shared_.telemetry.load().state == AmpState::fault;
      if (level != fault_level) {
        if (const io::GpioResult r = fault_->set(level); r.ok()) fault_level = level;
        else line_failed(r, config_.fault);
      }
    }
  }
}

void GpioTransport::encoder_loop() {
  // Quadrature states for count mod 4 (A leads B in the + direction).
  static constexpr bool kA[4] = {false, true, true, false};
  static constexpr bool kB[4] = {false, false, true, true};
  const auto period = static_cast<std::int64_t>(1e9 / config_.max_edge_rate_hz);
  const double origin = encoder_origin_m_;
  std::int64_t count = 0;
  std::int64_t next = monotonic_ns();
  while (!stopping_.load(std::memory_order_relaxed)) {
    const double position = shared_.telemetry.load().position_m;
    const auto target = static_cast<std::int64_t>(std::floor((position - origin) / config_.encoder_resolution_m));
    if (target != count) {
      const std::int64_t old_state = ((count % 4) + 4) % 4;
      count += target > count ? 1 : -1;
      const std::int64_t state = ((count % 4) + 4) % 4;
      io::GpioResult r;
      int offset = config_.encoder_a;
      if (kA[state] != kA[old_state]) r = a_->set(kA[state]);
      if (r.ok() && kB[state] != kB[old_state]) {
        offset = config_.encoder_b;
        r = b_->set(kB[state]);
      }
      if (!r.ok()) line_failed(r, offset);
      stats_.encoder_count.store(count);
      stats_.encoder_edges.fetch_add(1);
      next += period;
    } else {
      next += 1'000'000;  // idle: look again in 1 ms
    }
    const std::int64_t n = monotonic_ns();
    if (next < n - 10'000'000) next = n;  // far behind: no burst
    const timespec ts = to_timespec(next);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
  }
}

}  // namespace swum::emu
