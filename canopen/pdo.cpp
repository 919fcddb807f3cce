#include "pdo.h"

#include <optional>
#include <span>

namespace swum::canopen {

namespace {
constexpr std::uint16_t kRpdoCommunication = 0x1400;
constexpr std::uint16_t kRpdoMapping = 0x1600;
constexpr std::uint16_t kTpdoCommunication = 0x1800;
constexpr std::uint16_t kTpdoMapping = 0x1A00;
constexpr std::uint32_t kCobIdNotValid = 1U << 31;
constexpr std::uint32_t kCobIdExtended = 1U << 29;
constexpr std::uint32_t kLastSynchronousType = 240;  // 0: acyclic, 1-240: every n-th SYNC
constexpr std::uint32_t kEventDrivenManufacturer = 254;
constexpr std::uint32_t kEventDrivenProfile = 255;
constexpr std::int64_t kNsPer100Us = 100'000;  // inhibit time unit
constexpr std::int64_t kNsPerMs = 1'000'000;   // event timer unit

bool event_driven(std::uint32_t type) { return type == kEventDrivenManufacturer || type == kEventDrivenProfile; }
}  // namespace

Pdos::Pdos(ObjectDictionary& od, std::uint8_t node_id) : od_(od), node_id_(node_id) {
  for (std::size_t n = 0; n < kRpdos; ++n) {
    const auto offset = static_cast<std::uint16_t>(n);
    rpdos_[n].cob_id = od.slot(kRpdoCommunication + offset, 1);
    rpdos_[n].type = od.slot(kRpdoCommunication + offset, 2);
    rpdos_[n].mapping = bind_mapping(kRpdoMapping + offset);
  }
  for (std::size_t n = 0; n < kTpdos; ++n) {
    const auto offset = static_cast<std::uint16_t>(n);
    tpdos_[n].cob_id = od.slot(kTpdoCommunication + offset, 1);
    tpdos_[n].type = od.slot(kTpdoCommunication + offset, 2);
    tpdos_[n].inhibit = od.slot(kTpdoCommunication + offset, 3);
    tpdos_[n].event_timer = od.slot(kTpdoCommunication + offset, 5);
    tpdos_[n].mapping = bind_mapping(kTpdoMapping + offset);
  }
}

Pdos::MappingSlots Pdos::bind_mapping(std::uint16_t index) const {
  MappingSlots m;
  m.count = od_.slot(index, 0);
  for (std::size_t e = 0; e < kMaxEntries; ++e) m.entries[e] = od_.slot(index, static_cast<std::uint8_t>(e + 1));
  return m;
}

// A mapping entry is index << 16 | sub << 8 | length in bits (CiA 301 7.5.2.36).
bool Pdos::resolve(const MappingSlots& mapping, Layout& layout) const {
  layout.count = od_.u32(mapping.count);
  layout.total_bytes = 0;
  if (layout.count > kMaxEntries) return false;
  for (std::size_t e = 0; e < layout.count; ++e) {
    const std::uint32_t entry = od_.u32(mapping.entries[e]);
    const auto index = static_cast<std::uint16_t>(entry >> 16);
    const auto sub = static_cast<std::uint8_t>(entry >> 8);
    const std::uint32_t bits = entry & 0xFFU;
    const std::optional<std::size_t> slot = od_.find(index, sub);
    if (!slot) return false;
    const std::size_t bytes = size_of(od_.description(*slot).type);
    if (bytes == 0 || bits != 8 * bytes || bytes > 4) return false;
    layout.slots[e] = *slot;
    layout.bytes[e] = static_cast<std::uint8_t>(bytes);
    layout.total_bytes += bytes;
  }
  return layout.total_bytes <= 8;
}

bool Pdos::valid(std::size_t cob_id_slot) const {
  // 29-bit PDO identifiers (bit 29) are not supported: such a PDO is treated as not valid.
  return (od_.u32(cob_id_slot) & (kCobIdNotValid | kCobIdExtended)) == 0;
}

Pdos::RpdoStatus Pdos::receive(const protocol::CanFrame& frame) {
  if (frame.extended) return RpdoStatus::not_rpdo;
  for (Rpdo& rpdo : rpdos_) {
    if (!valid(rpdo.cob_id) || (od_.u32(rpdo.cob_id) & protocol::kCanStandardIdMax) != frame.id) continue;
    if (od_.u32(rpdo.type) > kLastSynchronousType) return apply(rpdo, frame);
    // Synchronous: checked now (the master learns of a bad length at once), written at SYNC.
    Layout layout;
    if (const std::optional<RpdoStatus> failed = misfit(rpdo, frame, layout)) return *failed;
    rpdo.latched = true;
    rpdo.latched_frame = frame;
    return RpdoStatus::latched;
  }
  return RpdoStatus::not_rpdo;
}

std::optional<Pdos::RpdoStatus> Pdos::misfit(const Rpdo& rpdo, const protocol::CanFrame& frame, Layout& layout) {
  if (!resolve(rpdo.mapping, layout)) {
    ++mapping_errors_;
    return RpdoStatus::refused;
  }
  if (frame.dlc < layout.total_bytes) {
    ++length_errors_;
    return RpdoStatus::length_error;
  }
  return std::nullopt;
}

Pdos::RpdoStatus Pdos::apply(const Rpdo& rpdo, const protocol::CanFrame& frame) {
  Layout layout;
  if (const std::optional<RpdoStatus> failed = misfit(rpdo, frame, layout)) return *failed;
  bool refused = false;
  std::size_t offset = 0;
  for (std::size_t e = 0; e < layout.count; ++e) {
    const std::span<const std::uint8_t> bytes(frame.data.data() + offset, layout.bytes[e]);
    if (od_.write(layout.slots[e], bytes) != SdoAbort::none) refused = true;
    offset += layout.bytes[e];
  }
  if (!refused) return RpdoStatus::applied;
  ++refused_writes_;
  return RpdoStatus::refused;
}

bool Pdos::sample(const Tpdo& tpdo, protocol::CanFrame& frame) {
  Layout layout;
  if (!resolve(tpdo.mapping, layout)) {
    ++mapping_errors_;
    return false;
  }
  if (layout.count == 0) return false;  // no object mapped (sub 0 = 0: being remapped)
  frame = protocol::CanFrame{};
  frame.id = od_.u32(tpdo.cob_id) & protocol::kCanStandardIdMax;
  frame.dlc = static_cast<std::uint8_t>(layout.total_bytes);
  std::size_t offset = 0;
  for (std::size_t e = 0; e < layout.count; ++e) {
    const std::uint32_t value = od_.u32(layout.slots[e]);
    for (std::size_t b = 0; b < layout.bytes[e]; ++b)
      frame.data[offset++] = static_cast<std::uint8_t>(value >> (8 * b));
  }
  return true;
}

void Pdos::transmit(Tpdo& tpdo, const protocol::CanFrame& frame, std::int64_t now_ns, FrameSink& out) {
  out.send(frame);
  tpdo.sent = true;
  tpdo.last = frame;
  tpdo.last_sent_ns = now_ns;
}

bool Pdos::active(Tpdo& tpdo) {
  if (valid(tpdo.cob_id)) return true;
  tpdo.sent = false;
  tpdo.syncs = 0;
  return false;
}

bool Pdos::same_as_last(const Tpdo& tpdo, const protocol::CanFrame& frame) {
  return tpdo.sent && protocol::same_content(frame, tpdo.last);
}

void Pdos::on_sync(std::uint8_t /*counter*/, FrameSink& out) {
  for (Rpdo& rpdo : rpdos_) {
    if (!rpdo.latched) continue;
    rpdo.latched = false;
    // Made not valid or event-driven since it was latched: dropped, as a new configuration voids it.
    if (valid(rpdo.cob_id) && od_.u32(rpdo.type) <= kLastSynchronousType) (void)apply(rpdo, rpdo.latched_frame);
  }
  for (Tpdo& tpdo : tpdos_) {
    if (!active(tpdo)) continue;
    const std::uint32_t type = od_.u32(tpdo.type);
    if (type > kLastSynchronousType) continue;
    if (type != 0 && ++tpdo.syncs < type) continue;
    protocol::CanFrame frame;
    if (!sample(tpdo, frame)) continue;
    if (type == 0 && same_as_last(tpdo, frame)) continue;
    tpdo.syncs = 0;
    transmit(tpdo, frame, tpdo.last_sent_ns, out);
  }
}

void Pdos::poll(std::int64_t now_ns, FrameSink& out) {
  for (Tpdo& tpdo : tpdos_) {
    if (!active(tpdo) || !event_driven(od_.u32(tpdo.type))) continue;
    const std::int64_t since_ns = now_ns - tpdo.last_sent_ns;
    if (tpdo.sent && since_ns < static_cast<std::int64_t>(od_.u32(tpdo.inhibit)) * kNsPer100Us) continue;
    protocol::CanFrame frame;
    if (!sample(tpdo, frame)) continue;
    const bool changed = !same_as_last(tpdo, frame);
    const std::int64_t event_ns = static_cast<std::int64_t>(od_.u32(tpdo.event_timer)) * kNsPerMs;
    const bool timer_ran_out = event_ns > 0 && since_ns >= event_ns;
    if (changed || timer_ran_out) transmit(tpdo, frame, now_ns, out);
  }
}

void Pdos::reset(std::int64_t now_ns) {
  for (Rpdo& rpdo : rpdos_) rpdo.latched = false;
  for (Tpdo& tpdo : tpdos_) {
    tpdo.sent = false;
    tpdo.syncs = 0;
    tpdo.last = protocol::CanFrame{};
    tpdo.last_sent_ns = now_ns;
  }
}

}  // namespace swum::canopen
