// Fuzz target: swum-emu's --gpio "CHIP:enable=N,fault=M[,a=K,b=L]" (firmware_sim/transports/gpio_transport.h
// parse_gpio_spec).
// Invariants: an accepted spec names a chip, its line offsets were written as whole decimal
// numbers (no "enable=3x"), are >= 0 or unused, the encoder has both lines or neither; the
// configuration written back in canonical form parses to the same configuration.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "formats/name_list.h"
#include "fuzz_check.h"
#include "transports/gpio_transport.h"

namespace {

using swum::emu::GpioConfig;

std::string canonical(const GpioConfig& c) {
  std::string lines;
  auto add = [&](const char* name, int offset) {
    if (offset < 0) return;
    lines += (lines.empty() ? "" : ",") + std::string(name) + "=" + std::to_string(offset);
  };
  add("enable", c.enable);
  add("fault", c.fault);
  add("a", c.encoder_a);
  add("b", c.encoder_b);
  return c.chip + ":" + lines;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(swum::fuzz::as_text(data, size));
  GpioConfig config;
  if (!swum::emu::parse_gpio_spec(text, config).empty()) return 0;
  FUZZ_CHECK(!config.chip.empty(), "'%s' accepted without a chip", swum::fuzz::printable(text).c_str());
  for (const int offset : {config.enable, config.fault, config.encoder_a, config.encoder_b}) {
    FUZZ_CHECK(offset >= -1, "'%s' accepted with offset %d", swum::fuzz::printable(text).c_str(), offset);
  }
  FUZZ_CHECK((config.encoder_a < 0) == (config.encoder_b < 0), "'%s': encoder with one line",
             swum::fuzz::printable(text).c_str());
  // Every NAME=OFFSET item after the chip's colon (blanks around it dropped: formats/name_list.h)
  // has a whole decimal offset.
  for (const std::string_view item : swum::split_comma_list(std::string_view(text).substr(text.rfind(':') + 1))) {
    FUZZ_CHECK(swum::fuzz::whole_decimal(item.substr(item.find('=') + 1)), "'%s' accepted the offset in '%s'",
               swum::fuzz::printable(text).c_str(), swum::fuzz::printable(item).c_str());
  }
  GpioConfig again;
  const std::string written = canonical(config);
  const std::string error = swum::emu::parse_gpio_spec(written, again);
  FUZZ_CHECK(error.empty() && again.chip == config.chip && again.enable == config.enable &&
                 again.fault == config.fault && again.encoder_a == config.encoder_a &&
                 again.encoder_b == config.encoder_b,
             "'%s' accepted, its canonical form '%s' is not the same: %s", swum::fuzz::printable(text).c_str(),
             swum::fuzz::printable(written).c_str(), error.c_str());
  return 0;
}
