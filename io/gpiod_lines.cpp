#include "gpiod_lines.h"

#include <gpiod.hpp>

#include <cerrno>
#include <cstring>
#include <exception>
#include <system_error>

namespace swum::io {
namespace {

gpiod::line open_line(const GpioLineConfig& c) {
  gpiod::chip chip;
  try {
    chip.open(c.chip, gpiod::chip::OPEN_LOOKUP);
  } catch (const std::system_error& e) {
    const int code = e.code().value();
    throw GpioError("no such GPIO chip '" + c.chip + "' (looked up as name, path, label and number): " + e.what(),
                    code ? code : ENODEV);
  }
  if (!chip) throw GpioError("no such GPIO chip '" + c.chip + "'", ENODEV);
  const unsigned lines = chip.num_lines();
  if (c.offset >= lines) {
    throw GpioError(line_name(c) + ": offset out of range, chip " + chip.name() + " [" + chip.label() + "] has " +
                        std::to_string(lines) + " lines (0.." + std::to_string(lines ? lines - 1 : 0) + ")",
                    EINVAL);
  }
  try {
    return chip.get_line(c.offset);
  } catch (const std::exception& e) {
    throw GpioError(line_name(c) + ": " + e.what(), EINVAL);
  }
}

[[noreturn]] void request_failed(const GpioLineConfig& c, const gpiod::line& line, const std::system_error& e) {
  const int code = e.code().value();
  if (code == EBUSY) {
    std::string holder;
    try {
      line.update();
      holder = line.consumer();
    } catch (const std::exception&) {
    }
    throw GpioError(line_name(c) + " is busy (already requested" + (holder.empty() ? "" : " by '" + holder + "'") + ")",
                    code);
  }
  throw GpioError(line_name(c) + ": request failed: " + e.what(), code);
}

// Both line kinds read a value the same way; libgpiod throws, the caller gets a status. The
// status keeps libgpiod's errno, not its text: no allocation of ours on a failure (describe()
// makes the text where it is reported). libgpiod's C++ calls allocate a line_bulk themselves and
// may throw std::bad_alloc: every exception becomes a status, none leaves a per-event call.
GpioResult read_value(const gpiod::line& line, bool& value) {
  try {
    value = line.get_value() != 0;
  } catch (const std::system_error& e) {
    return gpio_failure("get", e.code().value());
  } catch (const std::exception&) {
    return gpio_failure("get", ENOMEM);
  }
  return {};
}

class GpiodOutput final : public GpioOutputLine {
 public:
  explicit GpiodOutput(gpiod::line line) : line_(std::move(line)) {}
  ~GpiodOutput() override { line_.release(); }
  GpioResult set(bool value) override {
    try {
      line_.set_value(value ? 1 : 0);
    } catch (const std::system_error& e) {
      return gpio_failure("set", e.code().value());
    } catch (const std::exception&) {
      return gpio_failure("set", ENOMEM);
    }
    return {};
  }
  GpioResult get(bool& value) const override { return read_value(line_, value); }

 private:
  gpiod::line line_;
};

class GpiodInput final : public GpioInputLine {
 public:
  GpiodInput(gpiod::line line, bool events) : line_(std::move(line)), events_(events) {}
  ~GpiodInput() override { line_.release(); }
  GpioResult get(bool& value) const override { return read_value(line_, value); }
  GpioResult wait_edge(GpioEvent& event, std::chrono::milliseconds timeout) override {
    if (!events_) return gpio_failure(kWaitWithoutEdges, EINVAL);
    try {
      if (!line_.event_wait(timeout)) return GpioResult{GpioStatus::timeout, 0, "wait_edge"};
      const gpiod::line_event e = line_.event_read();
      event.rising = e.event_type == gpiod::line_event::RISING_EDGE;
      event.timestamp = e.timestamp;
      return {};
    } catch (const std::system_error& e) {
      return gpio_failure("wait_edge", e.code().value());
    } catch (const std::exception&) {
      return gpio_failure("wait_edge", ENOMEM);
    }
  }

 private:
  gpiod::line line_;
  bool events_;
};

std::bitset<32> bias_flags(GpioBias bias) {
  switch (bias) {
    case GpioBias::as_is: return {};
    case GpioBias::disabled: return gpiod::line_request::FLAG_BIAS_DISABLE;
    case GpioBias::pull_up: return gpiod::line_request::FLAG_BIAS_PULL_UP;
    case GpioBias::pull_down: return gpiod::line_request::FLAG_BIAS_PULL_DOWN;
  }
  return {};
}

}  // namespace

std::unique_ptr<GpioOutputLine> GpiodLines::request_output(const GpioLineConfig& config, bool initial_value) {
  gpiod::line line = open_line(config);
  try {
    line.request({config.consumer, gpiod::line_request::DIRECTION_OUTPUT, {}}, initial_value ? 1 : 0);
  } catch (const std::system_error& e) {
    request_failed(config, line, e);
  }
  return std::make_unique<GpiodOutput>(std::move(line));
}

std::unique_ptr<GpioInputLine> GpiodLines::request_input(const GpioLineConfig& config, GpioEdge edge, GpioBias bias) {
  gpiod::line line = open_line(config);
  int type = gpiod::line_request::DIRECTION_INPUT;
  switch (edge) {
    case GpioEdge::none: break;
    case GpioEdge::rising: type = gpiod::line_request::EVENT_RISING_EDGE; break;
    case GpioEdge::falling: type = gpiod::line_request::EVENT_FALLING_EDGE; break;
    case GpioEdge::both: type = gpiod::line_request::EVENT_BOTH_EDGES; break;
  }
  try {
    line.request({config.consumer, type, bias_flags(bias)});
  } catch (const std::system_error& e) {
    request_failed(config, line, e);
  }
  return std::make_unique<GpiodInput>(std::move(line), edge != GpioEdge::none);
}

}  // namespace swum::io
