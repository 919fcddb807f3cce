// In-process GPIO chips for unit tests, with GpiodLines' contract: the same errors (no such
// chip, offset out of range, line busy), a line is released when its object goes, inputs read
// what the outside drives or else their pull (bias from the request, else the chip's pull),
// edge events queue on inputs requested with edge detection. The test plays the outside world.
#pragma once

#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "gpio_lines.h"

namespace swum::io {

class FakeGpioLines final : public GpioLines {
 public:
  FakeGpioLines();
  ~FakeGpioLines() override;
  void add_chip(const std::string& name, unsigned num_lines, const std::string& label = "fake");

  std::unique_ptr<GpioOutputLine> request_output(const GpioLineConfig& config, bool initial_value) override;
  std::unique_ptr<GpioInputLine> request_input(const GpioLineConfig& config, GpioEdge edge, GpioBias bias) override;

  // The outside world: drive a line (nullopt: stop driving, the pull decides), or set the pull
  // the line sees when nobody drives it (as gpio-sim's sysfs `pull`).
  void drive(const std::string& chip, unsigned offset, std::optional<bool> value);
  void set_pull(const std::string& chip, unsigned offset, bool up);
  // What the outside sees on the line (an output's value, else drive/pull).
  bool level(const std::string& chip, unsigned offset) const;
  // Consumer holding the line, empty when free.
  std::string consumer(const std::string& chip, unsigned offset) const;
  // Fault injection: while set, every set/get/wait_edge on the line returns an error (EIO), as
  // the real adapter does when the kernel refuses the operation.
  void fail_operations(const std::string& chip, unsigned offset, bool failing);

  struct State;

 private:
  std::shared_ptr<State> state_;
};

}  // namespace swum::io
