// Real GPIO adapter on libgpiod 1.6's C++ binding (gpiod.hpp), i.e. the kernel's GPIO character
// device. Thin: it maps requests and values, and turns libgpiod's exceptions (std::system_error)
// into GpioError at request time and into a GpioResult on every later call.
#pragma once

#include "gpio_lines.h"

namespace swum::io {

class GpiodLines final : public GpioLines {
 public:
  std::unique_ptr<GpioOutputLine> request_output(const GpioLineConfig& config, bool initial_value) override;
  std::unique_ptr<GpioInputLine> request_input(const GpioLineConfig& config, GpioEdge edge, GpioBias bias) override;
};

}  // namespace swum::io
