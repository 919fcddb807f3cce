// Fuzz target: one Modbus request PDU (function code + data) as swum-emu's TCP and RTU servers
// hand it to protocol::modbus::parse_request and decide() (modbus_pdu_check.h).
// Invariants: an accepted request re-serialises to the same bytes; a refused one has a reason;
// decide() refusing yields no command; an accepted write yields one command that passes
// validate() and that the host tool's encoders turn back into the registers written.
#include <cstddef>
#include <cstdint>
#include <span>

#include "modbus_pdu_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  swum::fuzz::check_pdu(std::span<const std::uint8_t>(data, size));
  return 0;
}
