// Fuzz target: one Modbus request PDU (function code + data) as swum-emu's TCP and RTU servers
// hand it to protocol::modbus::parse_request and decide() (modbus_pdu_check.h), and the MBAP
// header check the TCP server makes first (check_mbap_header).
// Invariants: an accepted request re-serialises to the same bytes; a refused one has a reason;
// decide() refusing yields no command; an accepted write yields one command that passes
// validate() and that the host tool's encoders turn back into the registers written. The PDU
// under a correct MBAP header is valid with no surplus; with any other protocol id, or a length
// field shorter than its bytes, it is not; a longer one (within an ADU) announces the difference.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "modbus_pdu_check.h"

namespace {

namespace modbus = swum::protocol::modbus;

std::vector<std::uint8_t> with_header(std::span<const std::uint8_t> pdu, unsigned protocol_id, unsigned length) {
  std::vector<std::uint8_t> adu{0x00,
                                0x07,
                                static_cast<std::uint8_t>(protocol_id >> 8),
                                static_cast<std::uint8_t>(protocol_id),
                                static_cast<std::uint8_t>(length >> 8),
                                static_cast<std::uint8_t>(length),
                                0x01};
  for (const std::uint8_t b : pdu) adu.push_back(b);
  return adu;
}

void check_mbap(std::span<const std::uint8_t> pdu) {
  if (pdu.empty() || pdu.size() > 253) return;  // a TCP ADU carries at most 253 PDU bytes
  const auto length = static_cast<unsigned>(pdu.size() + 1);
  const modbus::MbapHeaderCheck right = modbus::check_mbap_header(with_header(pdu, 0, length));
  FUZZ_CHECK(right.valid && right.surplus_bytes == 0, "a correct MBAP header was refused or given a surplus");
  const unsigned other_protocol = 1U + pdu[0];
  FUZZ_CHECK(!modbus::check_mbap_header(with_header(pdu, other_protocol, length)).valid, "protocol id %u was accepted",
             other_protocol);
  const unsigned shorter = pdu[0] % length;  // 0 .. length - 1
  FUZZ_CHECK(!modbus::check_mbap_header(with_header(pdu, 0, shorter)).valid, "a length field %u < %u was accepted",
             shorter, length);
  const unsigned longer = length + 1U + pdu[pdu.size() - 1];  // length + 1 .. length + 256
  const modbus::MbapHeaderCheck more = modbus::check_mbap_header(with_header(pdu, 0, longer));
  if (6 + longer <= modbus::kTcpMaxAduBytes) {
    FUZZ_CHECK(more.valid && more.surplus_bytes == longer - length, "a length field %u > %u: surplus %zu", longer,
               length, more.surplus_bytes);
  } else {
    FUZZ_CHECK(!more.valid, "a length field %u beyond an ADU was accepted", longer);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> pdu(data, size);
  swum::fuzz::check_pdu(pdu);
  check_mbap(pdu);
  return 0;
}
