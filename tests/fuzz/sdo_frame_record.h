// The input record of the SDO fuzz targets (sdo_server_fuzz, sdo_client_fuzz): 9 bytes, byte 0 =
// flags (bits 0-3: DLC 0..15, bit 4: `other_id` instead of `id`, bit 5: a 29-bit identifier, bits
// 6-7: the time step before the frame: 0, 1 ms, 0.6 s or 2 s), bytes 1-8 = the payload.
#pragma once

#include <cstddef>
#include <cstdint>

#include "can_frame.h"

namespace swum::fuzz {

inline constexpr std::size_t kSdoRecordBytes = 9;

// The frame of the record at `record`; `now_ns` advanced by its time step.
inline protocol::CanFrame sdo_record_frame(const std::uint8_t* record, std::uint32_t id, std::uint32_t other_id,
                                           std::int64_t& now_ns) {
  static constexpr std::int64_t kSteps[] = {0, 1'000'000, 600'000'000, 2'000'000'000};
  const std::uint8_t flags = record[0];
  protocol::CanFrame frame;
  frame.dlc = flags & 0x0F;
  frame.id = (flags & 0x10) != 0 ? other_id : id;
  frame.extended = (flags & 0x20) != 0;
  for (std::size_t i = 0; i < 8; ++i) frame.data[i] = record[1 + i];
  now_ns += kSteps[flags >> 6];
  return frame;
}

}  // namespace swum::fuzz
