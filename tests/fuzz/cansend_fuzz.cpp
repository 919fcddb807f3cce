// Fuzz target: can-utils' cansend text ("123#DEADBEEF", "1ABCDEF0#00.11") as `swum` and the
// tests take it (protocol/can_frame.h parse_cansend).
// Invariants: an accepted text prints back (to_cansend) as itself without the '.' separators,
// in upper case; the printed frame parses back to the same frame; a refused text leaves the
// output frame as it was and says so in a message beginning "bad CAN frame '".
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <string>

#include "can_frame.h"
#include "fuzz_check.h"

using swum::protocol::CanFrame;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = swum::fuzz::as_text(data, size);
  CanFrame sentinel;
  sentinel.id = 0x5A5;
  sentinel.dlc = 3;
  sentinel.data = {1, 2, 3, 4, 5, 6, 7, 8};
  CanFrame frame = sentinel;
  const std::string error = swum::protocol::parse_cansend(text, frame);
  if (!error.empty()) {
    FUZZ_CHECK(same_content(frame, sentinel), "refused text changed the frame");
    FUZZ_CHECK(error.rfind("bad CAN frame '", 0) == 0, "message: %s", error.c_str());
    return 0;
  }
  FUZZ_CHECK(swum::protocol::validate(frame).empty(), "accepted an invalid frame");
  std::string expected;
  for (const char c : text) {
    if (c != '.') expected += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  const std::string printed = swum::protocol::to_cansend(frame);
  FUZZ_CHECK(printed == expected, "'%s' prints back as '%s'", swum::fuzz::printable(text).c_str(), printed.c_str());
  CanFrame again;
  FUZZ_CHECK(swum::protocol::parse_cansend(printed, again).empty() && same_content(again, frame),
             "'%s' does not parse back to the same frame", printed.c_str());
  return 0;
}
