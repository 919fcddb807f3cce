// The SYNC consumer's decoder (CiA 301 7.2.5): a frame on the identifier of 0x1005 (bits 0-10;
// bit 29 set: a 29-bit identifier in bits 0-28), with no data or with one byte, the SYNC counter
// (1..240 when the producer counts, 0x1019).
#pragma once

#include <cstdint>

#include "can_frame.h"

namespace swum::canopen {

// sync: `counter` is the frame's counter byte, 0 for a SYNC without data. not_sync: another
// identifier. malformed: the SYNC identifier with 2 or more bytes (the consumer may signal
// EMCY 0x8240 "unexpected SYNC data length"; the caller counts it).
enum class SyncDecode { sync, not_sync, malformed };
SyncDecode decode_sync(const protocol::CanFrame& frame, std::uint32_t sync_cob_id, std::uint8_t& counter);

}  // namespace swum::canopen
