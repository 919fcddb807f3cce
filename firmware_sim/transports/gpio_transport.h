// GPIO transport on the GpioLines interface (GpiodLines on a real chip, FakeGpioLines in tests):
//  - enable input: high = drive allowed; low = drive off regardless of commands (the amplifier
//    goes to `disabled` and refuses `enable` while low). Edge events, read at every event.
//  - fault output: high while the amplifier is in `fault` (refreshed every 1 ms).
//  - optional quadrature encoder outputs A/B: one count per `resolution` of mover travel (one
//    edge per count, A leads B when moving in +y), at most `max_edge_rate_hz` edges per second;
//    beyond that the count lags and catches up (it never loses counts).
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "core/shared_state.h"
#include "gpio_lines.h"

namespace swum::emu {

struct GpioConfig {
  std::string chip;
  int enable = -1;  // line offsets; -1 = not used
  int fault = -1;
  int encoder_a = -1;
  int encoder_b = -1;
  double encoder_resolution_m = 10e-6;
  double max_edge_rate_hz = 20000.0;
};
// "CHIP:enable=N,fault=M[,a=K,b=L]". Returns an error text, empty when fine.
std::string parse_gpio_spec(const std::string& text, GpioConfig& out);

struct GpioStats {
  std::atomic<std::uint64_t> enable_edges{0};
  std::atomic<std::int64_t> encoder_count{0};
  std::atomic<std::uint64_t> encoder_edges{0};
  // Line operations the kernel refused (chip gone, line released under us): counted, the loop
  // goes on; the enable input reads as low (drive off) while it cannot be read.
  std::atomic<std::uint64_t> line_errors{0};
};

class GpioTransport {
 public:
  // Requests the lines and reads the enable input once (throws io::GpioError with a clear
  // message: load time).
  GpioTransport(io::GpioLines& lines, GpioConfig config, SharedState& shared);
  ~GpioTransport();
  GpioTransport(const GpioTransport&) = delete;
  GpioTransport& operator=(const GpioTransport&) = delete;
  void start();
  void stop();
  [[nodiscard]] const GpioStats& stats() const { return stats_; }
  // The first failed line operation, as stop() reports it ("GPIO chip 'gpiochip0' line 3: set
  // failed: Input/output error"); empty if none. Only after stop().
  [[nodiscard]] std::string first_error() const;

 private:
  void io_loop();
  void encoder_loop();
  // A line operation that failed on the line at `offset`: counted (the result kept if it is the
  // first; its text is made by stop()), then a pause, so that a failing line is retried at most
  // once per ms. The loops go on; nothing allocates.
  void line_failed(const io::GpioResult& result, int offset);
  io::GpioLineConfig line_config(int offset) const;
  GpioConfig config_;
  SharedState& shared_;
  std::unique_ptr<io::GpioInputLine> enable_;
  std::unique_ptr<io::GpioOutputLine> fault_;
  std::unique_ptr<io::GpioOutputLine> a_, b_;
  std::atomic<bool> stopping_{false};
  double encoder_origin_m_ = 0.0;
  std::thread io_thread_, encoder_thread_;
  GpioStats stats_;
  // Written only by the thread whose failure was the first counted, read by stop() after the
  // threads are joined: no lock on the loops' paths.
  io::GpioResult first_error_;
  int first_error_offset_ = -1;
};

}  // namespace swum::emu
