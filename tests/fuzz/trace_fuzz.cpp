// Fuzz target: a record/replay trace (firmware_sim/core/trace.h read_trace), swum-emu's --replay.
// Invariants: the only error is TraceError, with a one-line message; an accepted trace has
// telemetry rows on consecutive ticks and inputs in tick order, and (when short) replays into a
// fresh emulator core without crashing or throwing (identical or not).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "core/trace.h"
#include "formats/parameter_file.h"
#include "fuzz_check.h"

namespace {

const swum::MotorModel& model() {
  // The parameter file's defaults (an empty text): no file access inside the fuzzer.
  static const swum::MotorModel m(swum::parse_motor_parameters("", "defaults"));
  return m;
}

bool one_line(const char* message) {
  for (const char* c = message; *c != '\0'; ++c) {
    if (static_cast<unsigned char>(*c) < 0x20 || *c == 0x7F) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(swum::fuzz::as_text(data, size)));
  swum::emu::Trace trace;
  try {
    trace = swum::emu::read_trace(in, "fuzz.csv");
  } catch (const swum::emu::TraceError& e) {
    FUZZ_CHECK(one_line(e.what()), "message not one line: %s", swum::fuzz::printable(e.what()).c_str());
    return 0;
  }
  for (std::size_t k = 1; k < trace.telemetry.size(); ++k)
    FUZZ_CHECK(trace.telemetry[k].tick == trace.telemetry[k - 1].tick + 1, "telemetry ticks not consecutive at %zu", k);
  for (std::size_t k = 1; k < trace.inputs.size(); ++k)
    FUZZ_CHECK(trace.inputs[k - 1].tick <= trace.inputs[k].tick, "inputs out of order at %zu", k);
  if (trace.telemetry.back().tick <= 64) {
    swum::emu::SharedState shared;
    swum::emu::EmulatorCore core(model(), {}, shared);
    (void)swum::emu::replay(trace, core, shared);
  }
  return 0;
}
