#include "sync.h"

namespace swum::canopen {

SyncDecode decode_sync(const protocol::CanFrame& frame, std::uint32_t sync_cob_id, std::uint8_t& counter) {
  const bool extended = (sync_cob_id & (1U << 29)) != 0;
  const std::uint32_t id = sync_cob_id & (extended ? protocol::kCanExtendedIdMax : protocol::kCanStandardIdMax);
  if (frame.extended != extended || frame.id != id) return SyncDecode::not_sync;
  if (frame.dlc > 1) return SyncDecode::malformed;
  counter = frame.dlc == 1 ? frame.data[0] : 0;
  return SyncDecode::sync;
}

}  // namespace swum::canopen
