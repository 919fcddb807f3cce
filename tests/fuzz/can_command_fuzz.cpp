// Fuzz target: a CAN frame arriving at swum-emu's Command (0x200+N) and AuxCommand (0x300+N)
// decoders (protocol/can_codec.h decode_command, decode_aux).
// Input: byte 0 = flags (bit 7: 29-bit identifier, bit 6: seal the CRC so the fuzzer reaches the
// field checks, bits 0-3: DLC 0..15), bytes 1-2 = identifier (little-endian), bytes 3-10 = payload.
// Invariants, for each decoder: an accepted frame is a standard 8-byte frame with zero reserved
// bits, and encoding what was decoded gives the same bytes (encode∘decode round trip); any
// single flipped bit of an accepted frame is refused (CRC-8/SAE-J1850 catches it); a refusal
// gives one of the reasons the decoder documents. The same frames also go to the host's decoder
// of the ElectricalA/B telemetry frames (can_telemetry_decode.h decode_electrical): every
// standard 8-byte frame decodes (no CRC), encoding the decoded values as phase A and as phase B
// gives the same bytes, anything else is wrong_length.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "can_codec.h"
#include "can_telemetry_decode.h"
#include "fuzz_check.h"

namespace {

using swum::protocol::CanFrame;
using swum::protocol::Reason;
namespace can = swum::protocol::can;

// One decoder (decode_command or decode_aux) with its encoder and the reasons it may refuse with.
template <typename Frame>
struct Codec {
  const char* name;
  Reason (*decode)(const CanFrame&, Frame&);
  CanFrame (*encode)(const Frame&, std::uint32_t);
  std::vector<Reason> refusals;
};

template <typename Frame>
void check(const CanFrame& frame, const Codec<Frame>& codec) {
  Frame out;
  const Reason why = codec.decode(frame, out);
  if (why != Reason::none) {
    FUZZ_CHECK(std::find(codec.refusals.begin(), codec.refusals.end(), why) != codec.refusals.end(),
               "%s refused with reason %s", codec.name, swum::protocol::to_string(why));
    return;
  }
  FUZZ_CHECK(!frame.extended && frame.dlc == 8, "%s accepted extended=%d dlc=%u", codec.name, frame.extended,
             frame.dlc);
  const CanFrame again = codec.encode(out, frame.id);
  FUZZ_CHECK(same_content(again, frame), "%s: %s re-encodes as %s", codec.name,
             swum::protocol::to_cansend(frame).c_str(), swum::protocol::to_cansend(again).c_str());
  // Every single-bit corruption of the payload is refused.
  for (unsigned bit = 0; bit < 64; ++bit) {
    CanFrame corrupt = frame;
    corrupt.data[bit / 8] = static_cast<std::uint8_t>(corrupt.data[bit / 8] ^ (1U << (bit % 8)));
    Frame ignored;
    FUZZ_CHECK(codec.decode(corrupt, ignored) != Reason::none, "%s: frame with bit %u flipped accepted", codec.name,
               bit);
  }
  const swum::protocol::Command command = can::to_command(out);
  (void)swum::protocol::validate(command, swum::protocol::AmplifierLimits{});
  if constexpr (std::is_same_v<Frame, can::CommandFrame>) {
    FUZZ_CHECK(out.mode <= can::mode::kResetFault && out.alive <= 15, "mode %u alive %u", out.mode, out.alive);
  }
}

const Codec<can::CommandFrame> kCommand{"decode_command",
                                        can::decode_command,
                                        can::encode_command,
                                        {Reason::wrong_length, Reason::bad_checksum, Reason::reserved_bits,
                                         Reason::unknown_command}};
const Codec<can::AuxFrame> kAux{"decode_aux",
                                can::decode_aux,
                                can::encode_aux,
                                {Reason::wrong_length, Reason::bad_checksum, Reason::reserved_bits}};

void check_electrical(const CanFrame& frame) {
  can::ElectricalFields e;
  const Reason why = can::decode_electrical(frame, e);
  FUZZ_CHECK((why == Reason::none) == (!frame.extended && frame.dlc == 8), "decode_electrical: %s for %s",
             swum::protocol::to_string(why), swum::protocol::to_cansend(frame).c_str());
  if (why != Reason::none) {
    FUZZ_CHECK(why == Reason::wrong_length, "decode_electrical refused with reason %s", swum::protocol::to_string(why));
    return;
  }
  swum::protocol::Telemetry t;
  t.electrical = {e.current_a,          e.current_a,          e.phase_deg, e.phase_deg,
                  e.motional_phase_deg, e.motional_phase_deg, e.power_w,   e.power_w};
  for (const CanFrame& again : {can::encode_electrical_a(t, frame.id), can::encode_electrical_b(t, frame.id)}) {
    FUZZ_CHECK(same_content(again, frame), "decode_electrical: %s re-encodes as %s",
               swum::protocol::to_cansend(frame).c_str(), swum::protocol::to_cansend(again).c_str());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 3) return 0;
  CanFrame frame;
  frame.extended = (data[0] & 0x80U) != 0;
  frame.dlc = static_cast<std::uint8_t>(data[0] & 0x0FU);
  frame.id = static_cast<std::uint32_t>(data[1] | (data[2] << 8)) & (frame.extended ? 0xFFFFU : 0x7FFU);
  for (std::size_t i = 0; i < 8 && 3 + i < size; ++i) frame.data[i] = data[3 + i];
  if ((data[0] & 0x40U) != 0) frame.data[7] = can::crc8(frame.id, frame.data.data());
  check(frame, kCommand);
  check(frame, kAux);
  check_electrical(frame);
  return 0;
}
