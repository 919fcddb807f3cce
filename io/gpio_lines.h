// Narrow GPIO interface of the device side: request one output or input line of a chip,
// set/get its value, wait for edge events with a timeout. Requests fail with GpioError
// (clear text: no such chip, offset out of range, line busy): they are load-time calls. The
// per-event calls (set, get, wait_edge) run on the transport's loop and return a GpioResult
// instead, never throw (docs/architecture.md, "Errors: one rule"). A line is released when its
// object is destroyed.
#pragma once

#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>

namespace swum::io {

class GpioError : public std::runtime_error {
 public:
  GpioError(const std::string& what, int error_number) : std::runtime_error(what), error_number_(error_number) {}
  int error_number() const { return error_number_; }

 private:
  int error_number_;
};

enum class GpioBias { as_is, disabled, pull_up, pull_down };
enum class GpioEdge { none, rising, falling, both };

struct GpioLineConfig {
  std::string chip;      // chip name ("gpiochip0"), path ("/dev/gpiochip0"), label or number
  unsigned offset = 0;   // line offset within the chip
  std::string consumer;  // shown to other users of the chip (gpioinfo)
};

struct GpioEvent {
  bool rising = false;
  std::chrono::nanoseconds timestamp{0};  // kernel event timestamp (fake: steady clock)
};

// What a per-event line operation came to, as io::CanResult is for a bus call. It carries no
// text of ours (the transport's loops retry a failing line every millisecond): the human text is
// made only where a failure is reported, by describe(). (The real adapter's libgpiod 1.6 C++
// calls allocate inside libgpiod: docs/architecture.md, "Errors: one rule".)
enum class GpioStatus {
  ok,       // done (wait_edge: an event arrived)
  timeout,  // wait_edge only: no event within the timeout
  error,    // the kernel refused (chip gone, line released), or a misuse: errno + operation
};

struct GpioResult {
  GpioStatus status = GpioStatus::ok;
  int error_number = 0;  // errno, when there is one
  // A string literal naming what failed, for anything but ok: the call ("set", "get",
  // "wait_edge"), or the call and the misuse the adapter refused it for. Never owned.
  const char* operation = "";
  bool ok() const { return status == GpioStatus::ok; }
};

class GpioOutputLine {
 public:
  virtual ~GpioOutputLine() = default;
  virtual GpioResult set(bool value) = 0;
  virtual GpioResult get(bool& value) const = 0;  // `value` changed only when ok
};

class GpioInputLine {
 public:
  virtual ~GpioInputLine() = default;
  virtual GpioResult get(bool& value) const = 0;  // `value` changed only when ok
  // Waits up to `timeout` for the next edge event: ok with `event` filled, or timeout. A line
  // requested with GpioEdge::none gives error (EINVAL): a programming error, which the first test
  // that makes it sees. Events queue: none is lost between calls.
  virtual GpioResult wait_edge(GpioEvent& event, std::chrono::milliseconds timeout) = 0;
};

// A failed per-event operation, as the adapters report it: `operation` must be a string literal.
constexpr GpioResult gpio_failure(const char* operation, int error_number) {
  return GpioResult{GpioStatus::error, error_number, operation};
}

// wait_edge on a line requested with GpioEdge::none: the misuse both adapters refuse (EINVAL).
inline constexpr const char* kWaitWithoutEdges = "wait_edge (line requested without edge detection)";

// The one line that reports a result on `line`: "GPIO chip 'gpiochip0' line 3: set failed:
// Input/output error". For the reporting side (an exit report, a load-time error, a test), not
// for the loops: it allocates.
std::string describe(const GpioResult& result, const GpioLineConfig& line);

// "GPIO chip 'gpiochip0' line 4": how every message names a line (requests, failures).
std::string line_name(const GpioLineConfig& line);

class GpioLines {
 public:
  virtual ~GpioLines() = default;
  virtual std::unique_ptr<GpioOutputLine> request_output(const GpioLineConfig& config, bool initial_value) = 0;
  virtual std::unique_ptr<GpioInputLine> request_input(const GpioLineConfig& config, GpioEdge edge = GpioEdge::none,
                                                       GpioBias bias = GpioBias::as_is) = 0;
};

}  // namespace swum::io
