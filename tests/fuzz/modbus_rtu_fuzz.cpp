// Fuzz target: bytes arriving on a Modbus RTU line, framed the way swum-emu's RTU server frames
// them (firmware_sim/transports/modbus_rtu_server.cpp with protocol/modbus_rtu.h:
// rtu::request_length decides how many bytes to read next, rtu::crc16 checks the frame, the PDU between unit id and CRC
// goes to parse_request/decide). Input: byte 0 = options (bit 0: put the right CRC on each frame, so the fuzzer reaches
// the PDU checks without solving CRC-16), then the line's bytes. Invariants: request_length never asks for fewer bytes
// than the server already holds (the server reads need - have bytes: less would be a huge read), stays within 2..256 or
// says -1, and says the same length again once the frame is complete; CRC-16/MODBUS of a frame with its own CRC
// appended (low byte first) is 0; each framed PDU meets modbus_pdu_check.h.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fuzz_check.h"
#include "modbus_pdu_check.h"
#include "modbus_rtu.h"

namespace {

namespace rtu = swum::protocol::modbus::rtu;
constexpr int kMaxAdu = rtu::kMaxAduLength;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool fix_crc = (data[0] & 1U) != 0;
  std::span<const std::uint8_t> line(data + 1, size - 1);
  while (!line.empty()) {
    std::vector<std::uint8_t> adu;
    int need = 0;
    for (;;) {
      need = rtu::request_length(adu);
      if (need < 0) break;
      FUZZ_CHECK(need >= 2 && need <= kMaxAdu, "request_length %d", need);
      FUZZ_CHECK(static_cast<std::size_t>(need) >= adu.size(), "request_length %d below the %zu bytes held", need,
                 adu.size());
      if (static_cast<std::size_t>(need) == adu.size() || line.empty()) break;
      const std::size_t take = std::min(line.size(), static_cast<std::size_t>(need) - adu.size());
      adu.insert(adu.end(), line.begin(), line.begin() + static_cast<std::ptrdiff_t>(take));
      line = line.subspan(take);
    }
    if (need < 0) {
      // The server discards the frame (bad length) and drains the line: nothing further to frame.
      return 0;
    }
    if (static_cast<std::size_t>(need) != adu.size()) return 0;  // partial frame at the end
    FUZZ_CHECK(rtu::request_length(adu) == need, "complete frame of %d bytes re-measured as %d", need,
               rtu::request_length(adu));
    const std::size_t body = adu.size() - 2;
    const std::uint16_t crc = rtu::crc16(std::span<const std::uint8_t>(adu.data(), body));
    std::vector<std::uint8_t> sealed(adu.begin(), adu.begin() + static_cast<std::ptrdiff_t>(body));
    sealed.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
    sealed.push_back(static_cast<std::uint8_t>(crc >> 8));
    FUZZ_CHECK(rtu::crc16(sealed) == 0, "CRC residue 0x%04X", rtu::crc16(sealed));
    if (fix_crc) adu = sealed;
    if (adu[body] != (crc & 0xFFU) || adu[body + 1] != (crc >> 8)) continue;  // bad CRC: discarded
    if (body >= 2) swum::fuzz::check_pdu(std::span<const std::uint8_t>(adu.data() + 1, body - 1));
  }
  return 0;
}
