#include "gpio_lines.h"

#include <system_error>

namespace swum::io {

std::string line_name(const GpioLineConfig& line) {
  return "GPIO chip '" + line.chip + "' line " + std::to_string(line.offset);
}

std::string describe(const GpioResult& result, const GpioLineConfig& line) {
  std::string text = line_name(line) + ": ";
  switch (result.status) {
    case GpioStatus::ok: return text + "ok";
    case GpioStatus::timeout: return text + result.operation + " timed out";
    case GpioStatus::error: break;
  }
  text += result.operation;
  text += " failed";
  // std::error_code's message, not strerror(): the reporting side may be any thread.
  if (result.error_number != 0) text += ": " + std::system_category().message(result.error_number);
  return text;
}

}  // namespace swum::io
