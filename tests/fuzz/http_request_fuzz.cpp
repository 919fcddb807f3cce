// Fuzz target: the HTTP API's request bodies (firmware_sim/http/http_json.h): a fault request, a
// lockstep step and a fault's name in DELETE /api/v1/faults/{type}, all from outside input.
// Invariants: the only error is HttpError with a 4xx status and a one-line message; an accepted
// fault is a fault (or a clear naming one) whose text form reads back the same; an accepted
// step is within [1, max]; every error body is one line of valid JSON.
#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "fuzz_check.h"
#include "http/http_json.h"

namespace {

using swum::emu::HttpError;

void check_error(const HttpError& e) {
  FUZZ_CHECK(e.status() >= 400 && e.status() < 500, "status %d", e.status());
  const std::string body = swum::emu::error_body(e.what());
  FUZZ_CHECK(body.find('\n') == body.size() - 1, "error body not one line: %s", swum::fuzz::printable(body).c_str());
  FUZZ_CHECK(nlohmann::json::accept(body), "error body not JSON: %s", swum::fuzz::printable(body).c_str());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = swum::fuzz::as_text(data, size);
  try {
    const swum::emu::RuntimeEvent event = swum::emu::parse_fault_request(text);
    const bool clear = event.type == swum::emu::EventType::clear;
    FUZZ_CHECK(swum::emu::is_fault(event.type) || (clear && swum::emu::is_fault(event.parameters.fault)),
               "accepted a non-fault: %s", swum::emu::to_string(event.type));
    swum::emu::ScenarioEvent e;
    e.type = event.type;
    e.parameters = event.parameters;
    const swum::emu::ScenarioEvent again = swum::emu::parse_injection(swum::emu::format_event(e));
    FUZZ_CHECK(again.type == e.type && again.parameters == e.parameters, "does not read back: %s",
               swum::emu::format_event(e).c_str());
  } catch (const HttpError& e) {
    check_error(e);
  }
  try {
    const std::uint64_t ticks = swum::emu::parse_step_request(text, 10000.0, 600000);
    FUZZ_CHECK(ticks >= 1 && ticks <= 600000, "step of %llu ticks", static_cast<unsigned long long>(ticks));
  } catch (const HttpError& e) {
    check_error(e);
  }
  try {
    const swum::emu::RuntimeEvent event = swum::emu::clear_request(text);
    FUZZ_CHECK(swum::emu::is_fault(event.parameters.fault), "clear of a non-fault");
  } catch (const HttpError& e) {
    check_error(e);
  }
  return 0;
}
