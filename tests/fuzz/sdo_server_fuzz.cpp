// Fuzz target: a sequence of CAN frames at one CANopen SDO server (canopen/sdo_server.h) of node 5
// over the swum dictionary (config/swum.eds), with time passing between them (timeouts).
// Input: records of 9 bytes: byte 0 = flags (bits 0-3: DLC 0..15, bit 4: identifier 0x606 instead
// of the server's 0x605, bit 5: 29-bit identifier, bits 6-7: time step before the frame: 0, 1 ms,
// 0.6 s or 2 s), bytes 1-8 = payload. After each frame the server is polled for its timeout.
// Invariants: every answer is an 8-byte standard frame on 0x585; it is either an abort (byte 0
// 0x80, a code of SdoAbort, counted once in aborts_sent and kept as last_abort) or a response of a
// CiA 301 server command specifier with its reserved bytes zero, never both; no answer for a frame
// that is not the server's, or a client's abort, and nothing counted then; a poll answers only
// with the timeout abort. The dictionary stays within its limits, its read-only objects keep their
// defaults, and every enabled PDO mapping names mappable objects of at most 64 bits.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_check.h"
#include "object_dictionary.h"
#include "sdo_frame_record.h"
#include "sdo_server.h"

namespace {

using swum::canopen::Access;
using swum::canopen::DataType;
using swum::canopen::ObjectDictionary;
using swum::canopen::SdoAbort;
using swum::protocol::CanFrame;

constexpr std::uint8_t kNode = 5;

bool known_code(std::uint32_t code) {
  static constexpr std::uint32_t kCodes[] = {0x05030000, 0x05040000, 0x05040001, 0x05040005, 0x06010000,
                                             0x06010001, 0x06010002, 0x06020000, 0x06040041, 0x06040042,
                                             0x06040043, 0x06070010, 0x06070012, 0x06070013, 0x06090011,
                                             0x06090030, 0x06090031, 0x06090032, 0x08000000, 0x08000022};
  for (const std::uint32_t known : kCodes) {
    if (known == code) return true;
  }
  return false;
}

std::uint32_t u32_at(const CanFrame& frame, std::size_t at) {
  return static_cast<std::uint32_t>(frame.data[at] | (frame.data[at + 1] << 8) | (frame.data[at + 2] << 16) |
                                    (static_cast<std::uint32_t>(frame.data[at + 3]) << 24));
}

bool zero_from(const CanFrame& frame, std::size_t first) {
  for (std::size_t i = first; i < 8; ++i) {
    if (frame.data[i] != 0) return false;
  }
  return true;
}

// An answer is an abort or a server response of CiA 301 7.2.4.3, never a mixture.
void check_answer(const CanFrame& answer, const swum::canopen::SdoServer& server, std::uint64_t aborts_before) {
  FUZZ_CHECK(answer.id == 0x580u + kNode && answer.dlc == 8 && !answer.extended, "answer id 0x%X dlc %u",
             static_cast<unsigned>(answer.id), answer.dlc);
  const std::uint8_t command = answer.data[0];
  if (command == 0x80) {
    FUZZ_CHECK(server.aborts_sent() == aborts_before + 1, "an abort counted %llu times",
               static_cast<unsigned long long>(server.aborts_sent() - aborts_before));
    FUZZ_CHECK(known_code(u32_at(answer, 4)), "abort code 0x%08X", u32_at(answer, 4));
    FUZZ_CHECK(static_cast<std::uint32_t>(server.last_abort()) == u32_at(answer, 4), "last_abort 0x%08X, sent 0x%08X",
               static_cast<unsigned>(server.last_abort()), u32_at(answer, 4));
    return;
  }
  FUZZ_CHECK(server.aborts_sent() == aborts_before, "a response counted as an abort");
  switch (command >> 5) {
    case 3:  // initiate download response
      FUZZ_CHECK(command == 0x60 && zero_from(answer, 4), "download response 0x%02X", command);
      break;
    case 1:  // download segment response
      FUZZ_CHECK((command & 0x0F) == 0 && zero_from(answer, 1), "segment response 0x%02X", command);
      break;
    case 2:  // initiate upload response: expedited with its size, or segmented with the size in bytes 4-7
      FUZZ_CHECK(command == 0x41 || command == 0x43 || command == 0x47 || command == 0x4B || command == 0x4F,
                 "upload response 0x%02X", command);
      break;
    case 0: {  // upload segment: the unused bytes are zero
      const std::size_t unused = (command >> 1) & 0x07;
      FUZZ_CHECK(zero_from(answer, 8 - unused), "upload segment 0x%02X with data in its unused bytes", command);
      break;
    }
    default: FUZZ_CHECK(false, "server command specifier %u", command >> 5);
  }
}

void check_dictionary(const ObjectDictionary& od, const std::vector<std::uint32_t>& defaults) {
  for (std::size_t slot = 0; slot < od.size(); ++slot) {
    const swum::canopen::ObjectDescription& d = od.description(slot);
    if (d.type == DataType::visible_string) continue;
    if (d.access == Access::ro || d.access == Access::const_)
      FUZZ_CHECK(od.u32(slot) == defaults[slot], "read-only 0x%04X sub %u changed", d.index, d.sub);
    if (d.has_limits) {
      const std::int64_t value = d.type == DataType::unsigned32 ? std::int64_t{od.u32(slot)} : od.i32(slot);
      FUZZ_CHECK(value >= d.low_limit && value <= d.high_limit, "0x%04X sub %u = %lld outside its limits", d.index,
                 d.sub, static_cast<long long>(value));
    }
  }
  for (std::uint16_t mapping : {0x1600, 0x1601, 0x1602, 0x1603, 0x1A00, 0x1A01, 0x1A02, 0x1A03}) {
    const std::uint32_t count = od.u32(od.slot(mapping, 0));
    FUZZ_CHECK(count <= 8, "0x%04X maps %u objects", mapping, count);
    std::uint32_t bits = 0;
    for (std::uint8_t sub = 1; sub <= count; ++sub) {
      const std::uint32_t entry = od.u32(od.slot(mapping, sub));
      const auto target = od.find(static_cast<std::uint16_t>(entry >> 16), static_cast<std::uint8_t>(entry >> 8));
      FUZZ_CHECK(target && od.description(*target).pdo_mappable, "0x%04X sub %u maps 0x%08X", mapping, sub, entry);
      FUZZ_CHECK((entry & 0xFF) == 8 * swum::canopen::size_of(od.description(*target).type), "entry 0x%08X", entry);
      bits += entry & 0xFF;
    }
    FUZZ_CHECK(bits <= 64, "0x%04X maps %u bits", mapping, bits);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ObjectDictionary od(swum::canopen::swum_eds_objects(), kNode);
  std::vector<std::uint32_t> defaults(od.size());
  for (std::size_t slot = 0; slot < od.size(); ++slot) defaults[slot] = od.u32(slot);
  swum::canopen::SdoServer server(od, kNode);
  std::int64_t now_ns = 0;
  for (std::size_t at = 0; at + swum::fuzz::kSdoRecordBytes <= size; at += swum::fuzz::kSdoRecordBytes) {
    const CanFrame frame = swum::fuzz::sdo_record_frame(data + at, 0x605, 0x606, now_ns);

    CanFrame answer;
    std::uint64_t before = server.aborts_sent();
    if (server.receive(frame, now_ns, answer)) {
      FUZZ_CHECK(frame.id == 0x605 && !frame.extended, "answered a frame that is not the server's");
      check_answer(answer, server, before);
    } else {
      const bool mine = frame.id == 0x605 && !frame.extended;
      FUZZ_CHECK(!mine || (frame.dlc >= 1 && (frame.data[0] >> 5) == 4), "no answer to request 0x%02X dlc %u",
                 frame.data[0], frame.dlc);
      FUZZ_CHECK(server.aborts_sent() == before, "an abort counted but not sent");
    }
    before = server.aborts_sent();
    if (server.poll(now_ns, answer)) {
      check_answer(answer, server, before);
      FUZZ_CHECK(server.last_abort() == SdoAbort::timeout, "poll sent 0x%08X", u32_at(answer, 4));
      FUZZ_CHECK(!server.transfer_in_progress(), "a transfer under way after its timeout");
    }
    check_dictionary(od, defaults);
  }
  return 0;
}
