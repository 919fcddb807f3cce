// The parser of swum-emu's millisecond options (--modbus-idle-timeout-ms, --modbus-frame-timeout-ms,
// --modbus-evict-idle-ms; docs/emulator.md). Returns text and never throws (docs/architecture.md,
// "Errors: one rule", 3): parse_emu_options() throws it with the option's name.
#pragma once

#include <string>
#include <string_view>

namespace swum::emu {

// A whole decimal number of milliseconds in [min_ms, max_ms] ("250"; not "2.5e2", "250ms", "-1",
// " 250"). Returns an error text naming the bad text, empty when fine (`out` changed only then).
std::string parse_milliseconds(std::string_view text, int min_ms, int max_ms, int& out);

}  // namespace swum::emu
