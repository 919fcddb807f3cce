// Narrow GPIO interface of the device side: request one output or input line of a chip,
// set/get its value, wait for edge events with a timeout. Requests fail with GpioError
// (clear text: no such chip, offset out of range, line busy); a line is released when its
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

enum class GpioWait { event, timeout };

class GpioOutputLine {
 public:
  virtual ~GpioOutputLine() = default;
  virtual void set(bool value) = 0;
  virtual bool get() const = 0;
};

class GpioInputLine {
 public:
  virtual ~GpioInputLine() = default;
  virtual bool get() const = 0;
  // Waits up to `timeout` for the next edge event (throws GpioError if requested with
  // GpioEdge::none). Events queue: none is lost between calls.
  virtual GpioWait wait_edge(GpioEvent& event, std::chrono::milliseconds timeout) = 0;
};

class GpioLines {
 public:
  virtual ~GpioLines() = default;
  virtual std::unique_ptr<GpioOutputLine> request_output(const GpioLineConfig& config, bool initial_value) = 0;
  virtual std::unique_ptr<GpioInputLine> request_input(const GpioLineConfig& config, GpioEdge edge = GpioEdge::none,
                                                       GpioBias bias = GpioBias::as_is) = 0;
};

}  // namespace swum::io
