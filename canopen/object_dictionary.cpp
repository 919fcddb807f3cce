#include "object_dictionary.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace swum::canopen {

namespace {

constexpr std::uint32_t kInvalidBit = 0x80000000u;   // COB-ID bit 31: the object does not exist
constexpr std::uint32_t kExtendedBit = 0x20000000u;  // COB-ID bit 29: 29-bit identifier
constexpr std::uint32_t kCanIdMask = 0x7FFu;
constexpr std::uint32_t kReservedIdBits = 0x1FFFF800u;  // bits 11-28: only with a 29-bit identifier
constexpr std::uint8_t kMaxMappedEntries = 8;           // CiA 301: 8 bytes, byte granularity
constexpr std::uint32_t kMaxPdoBits = 64;

std::uint32_t mask_of(DataType type) {
  switch (size_of(type)) {
    case 1: return 0xFFu;
    case 2: return 0xFFFFu;
    case 4: return 0xFFFFFFFFu;
    default: return 0;
  }
}

// The value a raw bit pattern stands for in its type.
std::int64_t value_of(DataType type, std::uint32_t raw) {
  switch (type) {
    case DataType::integer8: return static_cast<std::int8_t>(raw & 0xFFu);
    case DataType::integer16: return static_cast<std::int16_t>(raw & 0xFFFFu);
    case DataType::integer32: return static_cast<std::int32_t>(raw);
    default: return raw & mask_of(type);
  }
}

std::pair<std::int64_t, std::int64_t> type_range(DataType type) {
  switch (type) {
    case DataType::boolean: return {0, 1};
    case DataType::integer8: return {INT8_MIN, INT8_MAX};
    case DataType::integer16: return {INT16_MIN, INT16_MAX};
    case DataType::integer32: return {INT32_MIN, INT32_MAX};
    case DataType::unsigned8: return {0, UINT8_MAX};
    case DataType::unsigned16: return {0, UINT16_MAX};
    case DataType::unsigned32: return {0, UINT32_MAX};
    default: return {INT64_MIN, INT64_MAX};  // real32: bit patterns, no range
  }
}

bool known_type(DataType type) {
  const auto code = static_cast<std::uint16_t>(type);
  return code >= 0x0001 && code <= 0x0009;
}

std::string where(const ObjectDescription& d) {
  char text[32];
  std::snprintf(text, sizeof text, "0x%04X sub %u", d.index, static_cast<unsigned>(d.sub));
  return text;
}

bool is_rpdo_communication(std::uint16_t index) { return index >= 0x1400 && index <= 0x15FF; }
bool is_tpdo_communication(std::uint16_t index) { return index >= 0x1800 && index <= 0x19FF; }
bool is_rpdo_mapping(std::uint16_t index) { return index >= 0x1600 && index <= 0x17FF; }
bool is_tpdo_mapping(std::uint16_t index) { return index >= 0x1A00 && index <= 0x1BFF; }

// CiA 301 7.3.5 (Table 43): identifiers a PDO or EMCY may not use, as they belong to NMT, SYNC,
// the default SDO channels, NMT error control and LSS.
bool restricted_can_id(std::uint32_t id) {
  return id == 0x000 || (id >= 0x001 && id <= 0x07F) || (id >= 0x101 && id <= 0x180) || (id >= 0x581 && id <= 0x5FF) ||
         (id >= 0x601 && id <= 0x67F) || (id >= 0x6E0 && id <= 0x6FF) || (id >= 0x701 && id <= 0x77F) ||
         (id >= 0x780 && id <= 0x7FF);
}

// A COB-ID this slave can use: an 11-bit identifier (bits 11-28 clear, no 29-bit frames).
bool plain_cob_id(std::uint32_t raw) { return (raw & (kExtendedBit | kReservedIdBits)) == 0; }

}  // namespace

std::size_t size_of(DataType type) {
  switch (type) {
    case DataType::boolean:
    case DataType::integer8:
    case DataType::unsigned8: return 1;
    case DataType::integer16:
    case DataType::unsigned16: return 2;
    case DataType::integer32:
    case DataType::unsigned32:
    case DataType::real32: return 4;
    case DataType::visible_string: return 0;
  }
  return 0;
}

const char* describe(SdoAbort code) {
  switch (code) {
    case SdoAbort::none: return "no abort";
    case SdoAbort::toggle_bit: return "toggle bit not alternated";
    case SdoAbort::timeout: return "SDO protocol timed out";
    case SdoAbort::bad_command: return "client/server command specifier not valid or unknown";
    case SdoAbort::out_of_memory: return "out of memory";
    case SdoAbort::unsupported_access: return "unsupported access to an object";
    case SdoAbort::write_only: return "attempt to read a write only object";
    case SdoAbort::read_only: return "attempt to write a read only object";
    case SdoAbort::no_object: return "object does not exist in the object dictionary";
    case SdoAbort::not_mappable: return "object cannot be mapped to the PDO";
    case SdoAbort::pdo_too_long: return "the number and length of the objects to be mapped would exceed PDO length";
    case SdoAbort::general_incompatibility: return "general parameter incompatibility";
    case SdoAbort::length_mismatch: return "data type does not match, length of service parameter does not match";
    case SdoAbort::length_too_high: return "data type does not match, length of service parameter too high";
    case SdoAbort::length_too_low: return "data type does not match, length of service parameter too low";
    case SdoAbort::no_sub_index: return "sub-index does not exist";
    case SdoAbort::value_range: return "invalid value for parameter (download only)";
    case SdoAbort::value_too_high: return "value of parameter written too high (download only)";
    case SdoAbort::value_too_low: return "value of parameter written too low (download only)";
    case SdoAbort::general: return "general error";
    case SdoAbort::state: return "data cannot be transferred or stored because of the present device state";
  }
  return "unknown abort code";
}

ObjectDictionary::ObjectDictionary(std::span<const ObjectDescription> objects, std::uint8_t node_id)
    : objects_(objects), node_id_(node_id), values_(objects.size(), 0) {
  if (node_id < 1 || node_id > 127)
    throw std::invalid_argument("CANopen node id " + std::to_string(node_id) + " is outside 1..127");
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    const ObjectDescription& d = objects_[i];
    if (i > 0) {
      const ObjectDescription& p = objects_[i - 1];
      if (p.index > d.index || (p.index == d.index && p.sub >= d.sub))
        throw std::invalid_argument("object dictionary: " + where(d) + " is not after " + where(p) +
                                    " (the table must be sorted by index and sub-index, each once)");
    }
    if (d.name == nullptr || !known_type(d.type))
      throw std::invalid_argument("object dictionary: " + where(d) + " has no name or an unknown data type");
    if (d.type == DataType::visible_string) {
      if (d.default_string == nullptr)
        throw std::invalid_argument("object dictionary: " + where(d) + " is a string without its text");
      if (d.access != Access::ro && d.access != Access::const_)
        throw std::invalid_argument("object dictionary: " + where(d) + " is a writable string (not supported)");
      continue;
    }
    const auto [type_low, type_high] = type_range(d.type);
    if (d.has_limits && (d.type == DataType::real32 || d.low_limit > d.high_limit || d.low_limit < type_low ||
                         d.high_limit > type_high))
      throw std::invalid_argument("object dictionary: " + where(d) + " has limits outside its type");
    const std::int64_t value = d.default_value + (d.default_plus_node_id ? node_id : 0);
    const std::int64_t low = d.has_limits ? d.low_limit : type_low;
    const std::int64_t high = d.has_limits ? d.high_limit : type_high;
    if (value < low || value > high)
      throw std::invalid_argument("object dictionary: " + where(d) + "'s default " + std::to_string(value) +
                                  " is outside " + std::to_string(low) + ".." + std::to_string(high));
    values_[i] = default_raw(i);
  }
}

std::optional<std::size_t> ObjectDictionary::find(std::uint16_t index, std::uint8_t sub) const {
  const auto key = [](const ObjectDescription& d) { return (std::uint32_t{d.index} << 8) | d.sub; };
  const std::uint32_t wanted = (std::uint32_t{index} << 8) | sub;
  const auto it = std::lower_bound(objects_.begin(), objects_.end(), wanted,
                                   [&](const ObjectDescription& d, std::uint32_t k) { return key(d) < k; });
  if (it == objects_.end() || key(*it) != wanted) return std::nullopt;
  return static_cast<std::size_t>(it - objects_.begin());
}

std::size_t ObjectDictionary::slot(std::uint16_t index, std::uint8_t sub) const {
  if (const auto found = find(index, sub)) return *found;
  char text[64];
  std::snprintf(text, sizeof text, "object dictionary: no object 0x%04X sub %u", index, static_cast<unsigned>(sub));
  throw std::out_of_range(text);
}

bool ObjectDictionary::has_index(std::uint16_t index) const {
  const auto it = std::lower_bound(objects_.begin(), objects_.end(), index,
                                   [](const ObjectDescription& d, std::uint16_t i) { return d.index < i; });
  return it != objects_.end() && it->index == index;
}

const ObjectDescription& ObjectDictionary::description(std::size_t slot) const { return objects_[slot]; }

std::size_t ObjectDictionary::size() const { return objects_.size(); }

std::uint32_t ObjectDictionary::u32(std::size_t slot) const { return values_[slot]; }

std::int32_t ObjectDictionary::i32(std::size_t slot) const {
  return static_cast<std::int32_t>(value_of(objects_[slot].type, values_[slot]));
}

std::string_view ObjectDictionary::string(std::size_t slot) const {
  const ObjectDescription& d = objects_[slot];
  return d.type == DataType::visible_string ? std::string_view(d.default_string) : std::string_view();
}

void ObjectDictionary::set(std::size_t slot, std::uint32_t raw) { values_[slot] = raw & mask_of(objects_[slot].type); }

std::uint32_t ObjectDictionary::default_raw(std::size_t slot) const {
  const ObjectDescription& d = objects_[slot];
  const std::int64_t value = d.default_value + (d.default_plus_node_id ? node_id_ : 0);
  return static_cast<std::uint32_t>(value) & mask_of(d.type);
}

std::uint32_t ObjectDictionary::value_at(std::uint16_t index, std::uint8_t sub) const {
  const auto found = find(index, sub);
  return found ? values_[*found] : 0;
}

SdoAbort ObjectDictionary::write(std::size_t slot, std::span<const std::uint8_t> bytes) {
  const ObjectDescription& d = objects_[slot];
  if (d.access == Access::ro || d.access == Access::const_) return SdoAbort::read_only;
  const std::size_t size = size_of(d.type);
  if (size == 0) return SdoAbort::unsupported_access;  // no writable strings (the constructor refuses them)
  if (bytes.size() > size) return SdoAbort::length_too_high;
  if (bytes.size() < size) return SdoAbort::length_too_low;
  std::uint32_t raw = 0;
  for (std::size_t i = 0; i < size; ++i) raw |= std::uint32_t{bytes[i]} << (8 * i);
  if (d.type != DataType::real32) {
    const std::int64_t value = value_of(d.type, raw);
    if (d.type == DataType::boolean && value > 1) return SdoAbort::value_range;
    if (d.has_limits && value < d.low_limit) return SdoAbort::value_too_low;
    if (d.has_limits && value > d.high_limit) return SdoAbort::value_too_high;
  }
  if (const SdoAbort rule = check_communication_rules(slot, raw); rule != SdoAbort::none) return rule;
  if (observer_ != nullptr) {
    if (const SdoAbort veto = observer_->check(slot, raw); veto != SdoAbort::none) return veto;
  }
  values_[slot] = raw;
  if (d.index == 0x1003 && d.sub == 0) {  // CiA 301 7.5.2.4: writing 0 deletes the history
    for (std::size_t i = slot + 1; i < objects_.size() && objects_[i].index == 0x1003; ++i) values_[i] = 0;
  }
  if (observer_ != nullptr) observer_->written(slot);
  return SdoAbort::none;
}

SdoAbort ObjectDictionary::check_communication_rules(std::size_t slot, std::uint32_t raw) const {
  const ObjectDescription& d = objects_[slot];
  const std::uint32_t old = values_[slot];
  if (d.index == 0x1003 && d.sub == 0) return raw == 0 ? SdoAbort::none : SdoAbort::value_range;
  if (d.index == 0x1005) {
    // CiA 301 7.5.2.5: bit 30 asks this node to produce SYNC, which it cannot; 11-bit ids only.
    return plain_cob_id(raw) && (raw & 0x40000000u) == 0 ? SdoAbort::none : SdoAbort::value_range;
  }
  if (d.index == 0x1014) {
    // CiA 301 7.5.2.17: bit 30 reserved; the identifier may not change while the EMCY object
    // exists (bit 31 clear).
    if (!plain_cob_id(raw) || (raw & 0x40000000u) != 0) return SdoAbort::value_range;
    const bool valid = (raw & kInvalidBit) == 0;
    if (valid && (old & kInvalidBit) == 0 && (raw & kCanIdMask) != (old & kCanIdMask)) return SdoAbort::value_range;
    if (valid && restricted_can_id(raw & kCanIdMask)) return SdoAbort::value_range;
    return SdoAbort::none;
  }
  if (d.index == 0x1016 && d.sub >= 1) {
    // CiA 301 7.5.2.31: bits 24-31 reserved; one monitored node per entry: two active entries
    // for the same node are a general parameter incompatibility.
    if ((raw & 0xFF000000u) != 0) return SdoAbort::value_range;
    const std::uint32_t node = (raw >> 16) & 0xFFu;
    const bool active = (raw & 0xFFFFu) != 0 && node != 0;
    if (active && node > 127) return SdoAbort::value_range;
    if (!active) return SdoAbort::none;
    std::size_t first = slot;
    while (first > 0 && objects_[first - 1].index == d.index) --first;
    for (std::size_t i = first; i < objects_.size() && objects_[i].index == d.index; ++i) {
      if (i == slot || objects_[i].sub == 0) continue;
      const std::uint32_t other = values_[i];
      if ((other & 0xFFFFu) != 0 && ((other >> 16) & 0xFFu) == node) return SdoAbort::general_incompatibility;
    }
    return SdoAbort::none;
  }
  if (is_rpdo_communication(d.index) || is_tpdo_communication(d.index)) {
    const bool valid_now = (value_at(d.index, 1) & kInvalidBit) == 0;
    if (d.sub == 1) {
      // CiA 301 7.5.2.35/37: bits 0-29 may not change while the PDO exists; only 11-bit ids,
      // and none of the identifiers CiA 301 7.3.5 restricts. Bit 30 (RTR) is ignored: this
      // slave answers no remote frames.
      if (!plain_cob_id(raw & ~0x40000000u)) return SdoAbort::value_range;
      const bool valid = (raw & kInvalidBit) == 0;
      if (valid && valid_now && (raw & kCanIdMask) != (old & kCanIdMask)) return SdoAbort::value_range;
      if (valid && restricted_can_id(raw & kCanIdMask)) return SdoAbort::value_range;
      return SdoAbort::none;
    }
    if (d.sub == 2) {
      // CiA 301 Table 72/73: 0-240 synchronous, 254/255 event-driven; 241-251 are reserved
      // and 252/253 (remote request) are not offered here.
      return raw > 240 && raw < 254 ? SdoAbort::value_range : SdoAbort::none;
    }
    if (d.sub == 3 && is_tpdo_communication(d.index)) {
      // CiA 301 7.5.2.37: the inhibit time may not change while the PDO exists.
      return valid_now && raw != old ? SdoAbort::value_range : SdoAbort::none;
    }
    return SdoAbort::none;
  }
  if (is_rpdo_mapping(d.index) || is_tpdo_mapping(d.index)) {
    // CiA 301 7.5.2.36/38, the mapping procedure: invalidate the PDO (COB-ID bit 31), write
    // sub 0 = 0, write the entries (each checked: 0x06020000 or 0x06040041), write sub 0 = n
    // (the whole mapping checked: 0x06020000 or 0x06040042), validate the PDO. CiA 301 names
    // no code for a change out of order (PDO valid, or an entry while sub 0 is not 0); as Lely's
    // stack does, it is 0x06090030, and a write of the value already there is no change.
    if (raw == old) return SdoAbort::none;
    const auto communication = static_cast<std::uint16_t>(d.index - 0x200);
    if ((value_at(communication, 1) & kInvalidBit) == 0) return SdoAbort::value_range;
    const bool receive = is_rpdo_mapping(d.index);
    if (d.sub == 0) return raw == 0 ? SdoAbort::none : check_pdo_mapping(d.index, static_cast<std::uint8_t>(raw));
    if (value_at(d.index, 0) != 0) return SdoAbort::value_range;
    return raw == 0 ? SdoAbort::none : check_mapping_entry(raw, receive);  // 0: an empty entry
  }
  return SdoAbort::none;
}

SdoAbort ObjectDictionary::check_mapping_entry(std::uint32_t entry, bool receive) const {
  // No dummy entries ([DummyUsage] all 0): an entry names an object of the dictionary.
  const auto target = find(static_cast<std::uint16_t>(entry >> 16), static_cast<std::uint8_t>(entry >> 8));
  if (!target) return SdoAbort::no_object;
  const ObjectDescription& t = objects_[*target];
  const bool readable = t.access != Access::wo;
  const bool writable = t.access == Access::rw || t.access == Access::wo;
  if (!t.pdo_mappable || !(receive ? writable : readable)) return SdoAbort::not_mappable;
  // Granularity 8, whole objects only: the entry's length is the object's.
  if ((entry & 0xFFu) != 8 * size_of(t.type)) return SdoAbort::not_mappable;
  return SdoAbort::none;
}

SdoAbort ObjectDictionary::check_pdo_mapping(std::uint16_t mapping_index, std::uint8_t count) const {
  if (count > kMaxMappedEntries || !find(mapping_index, count)) return SdoAbort::pdo_too_long;
  const bool receive = is_rpdo_mapping(mapping_index);
  std::uint32_t bits = 0;
  for (std::uint8_t sub = 1; sub <= count; ++sub) {
    const std::uint32_t entry = value_at(mapping_index, sub);
    if (const SdoAbort problem = check_mapping_entry(entry, receive); problem != SdoAbort::none) return problem;
    bits += entry & 0xFFu;
  }
  return bits > kMaxPdoBits ? SdoAbort::pdo_too_long : SdoAbort::none;
}

SdoAbort ObjectDictionary::read(std::size_t slot, std::span<std::uint8_t, 4> out, std::size_t& length) const {
  const ObjectDescription& d = objects_[slot];
  length = 0;
  if (d.access == Access::wo) return SdoAbort::write_only;
  if (d.type == DataType::visible_string) {
    const std::string_view text(d.default_string);
    if (text.size() > out.size()) return SdoAbort::length_too_high;  // read_string gives all of it
    std::copy(text.begin(), text.end(), out.begin());
    length = text.size();
    return SdoAbort::none;
  }
  length = size_of(d.type);
  for (std::size_t i = 0; i < length; ++i) out[i] = static_cast<std::uint8_t>(values_[slot] >> (8 * i));
  return SdoAbort::none;
}

SdoAbort ObjectDictionary::read_string(std::size_t slot, std::string_view& text) const {
  const ObjectDescription& d = objects_[slot];
  text = {};
  if (d.access == Access::wo) return SdoAbort::write_only;
  if (d.type != DataType::visible_string) return SdoAbort::general_incompatibility;
  text = d.default_string;
  return SdoAbort::none;
}

void ObjectDictionary::set_observer(WriteObserver* observer) { observer_ = observer; }

void ObjectDictionary::reset_range(std::uint16_t first, std::uint16_t last) {
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    if (objects_[i].index >= first && objects_[i].index <= last) values_[i] = default_raw(i);
  }
}

void ObjectDictionary::reset_communication() { reset_range(0x1000, 0x1FFF); }

void ObjectDictionary::reset_application() { reset_range(0x2000, 0x9FFF); }

}  // namespace swum::canopen
