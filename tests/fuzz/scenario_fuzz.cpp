// Fuzz target: a scenario file (TOML; firmware_sim/core/scenario.h parse_scenario), swum-emu's
// --scenario; the same bytes also as one --inject value (parse_injection).
// Invariants: the only error is ScenarioError, with a one-line message (no control
// characters); an accepted scenario's events are ordered by at_s, lie in [0, 1e6] s, and each
// written by format_event reads back through parse_injection as the same event.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/scenario.h"
#include "fuzz_check.h"

namespace {

bool one_line(const char* message) {
  for (const char* c = message; *c != '\0'; ++c) {
    if (static_cast<unsigned char>(*c) < 0x20 || *c == 0x7F) return false;
  }
  return true;
}

void check_round_trip(const swum::emu::ScenarioEvent& event) {
  FUZZ_CHECK(std::isfinite(event.at_s) && event.at_s >= 0.0 && event.at_s <= 1e6, "at_s %g", event.at_s);
  const std::string text = swum::emu::format_event(event);
  swum::emu::ScenarioEvent back;
  try {
    back = swum::emu::parse_injection(text);
  } catch (const swum::emu::ScenarioError& e) {
    FUZZ_CHECK(false, "format_event wrote '%s', refused: %s", text.c_str(), e.what());
  }
  back.origin = event.origin;
  FUZZ_CHECK(back == event, "'%s' read back as '%s'", text.c_str(), swum::emu::format_event(back).c_str());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto text = swum::fuzz::as_text(data, size);
  try {
    const auto scenario = swum::emu::parse_scenario(text, "fuzz.toml");
    for (std::size_t k = 0; k < scenario.events.size(); ++k) {
      if (k > 0) FUZZ_CHECK(scenario.events[k - 1].at_s <= scenario.events[k].at_s, "events out of order at %zu", k);
      check_round_trip(scenario.events[k]);
    }
  } catch (const swum::emu::ScenarioError& e) {
    FUZZ_CHECK(one_line(e.what()), "message not one line: %s", swum::fuzz::printable(e.what()).c_str());
  }
  try {
    check_round_trip(swum::emu::parse_injection(text));
  } catch (const swum::emu::ScenarioError& e) {
    FUZZ_CHECK(one_line(e.what()), "message not one line: %s", swum::fuzz::printable(e.what()).c_str());
  }
  return 0;
}
