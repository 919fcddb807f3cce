// Fuzz target: one Modbus request PDU (function code + data) as swum-emu's TCP and RTU servers
// hand it to protocol::modbus::parse_request and decide() (modbus_pdu_check.h), and the MBAP
// header check the TCP server makes first (mbap_header_consistent).
// Invariants: an accepted request re-serialises to the same bytes; a refused one has a reason;
// decide() refusing yields no command; an accepted write yields one command that passes
// validate() and that the host tool's encoders turn back into the registers written. The PDU
// under a correct MBAP header is consistent; with any other protocol id or length it is not.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "modbus_pdu_check.h"

namespace {

void check_mbap(std::span<const std::uint8_t> pdu) {
  if (pdu.empty() || pdu.size() > 253) return;  // a TCP ADU carries at most 253 PDU bytes
  const auto length = static_cast<unsigned>(pdu.size() + 1);
  std::vector<std::uint8_t> adu{
      0x00, 0x07, 0, 0, static_cast<std::uint8_t>(length >> 8), static_cast<std::uint8_t>(length), 0x01};
  adu.insert(adu.end(), pdu.begin(), pdu.end());
  FUZZ_CHECK(swum::protocol::modbus::mbap_header_consistent(adu), "a correct MBAP header was refused");
  const std::uint8_t flip = static_cast<std::uint8_t>(1U << (pdu[0] % 8));
  for (const std::size_t at : {2U, 3U, 4U, 5U}) {  // protocol id, length field
    adu[at] ^= flip;
    FUZZ_CHECK(!swum::protocol::modbus::mbap_header_consistent(adu), "a changed MBAP byte %zu was accepted", at);
    adu[at] ^= flip;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> pdu(data, size);
  swum::fuzz::check_pdu(pdu);
  check_mbap(pdu);
  return 0;
}
