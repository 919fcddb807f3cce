#include "emcy.h"

#include <algorithm>

namespace swum::canopen {

namespace {
constexpr std::int64_t kNsPer100Us = 100'000;  // 0x1015's unit
constexpr std::size_t kHistoryDepth = 8;
}  // namespace

protocol::CanFrame emcy_frame(std::uint32_t cob_id, std::uint16_t error_code, std::uint8_t error_register,
                              std::span<const std::uint8_t, 5> manufacturer) {
  protocol::CanFrame frame;
  frame.id = cob_id & protocol::kCanStandardIdMax;
  frame.dlc = 8;
  frame.data[0] = static_cast<std::uint8_t>(error_code);
  frame.data[1] = static_cast<std::uint8_t>(error_code >> 8);
  frame.data[2] = error_register;
  std::copy(manufacturer.begin(), manufacturer.end(), frame.data.begin() + 3);
  return frame;
}

std::uint8_t error_register_bits(std::uint16_t error_code) {
  if (error_code == kEmcyErrorReset) return 0;
  const std::uint8_t generic = error_register::kGeneric;
  if ((error_code & 0xFF00U) == 0xFF00U) return generic | error_register::kManufacturer;
  switch (error_code >> 12) {
    case 0x2: return generic | error_register::kCurrent;
    case 0x3: return generic | error_register::kVoltage;
    case 0x4: return generic | error_register::kTemperature;
    case 0x8: return generic | error_register::kCommunication;
    default: return generic;
  }
}

EmcyProducer::EmcyProducer(ObjectDictionary& od)
    : od_(od),
      error_register_slot_(od.slot(0x1001, 0)),
      history_slots_{},
      cob_id_slot_(od.slot(0x1014, 0)),
      inhibit_slot_(od.slot(0x1015, 0)) {
  for (std::size_t sub = 0; sub < history_slots_.size(); ++sub) {
    history_slots_[sub] = od.slot(0x1003, static_cast<std::uint8_t>(sub));
  }
}

void EmcyProducer::raise(std::uint16_t error_code, std::int64_t now_ns, FrameSink& out) {
  od_.set(error_register_slot_, od_.u32(error_register_slot_) | error_register_bits(error_code));
  for (std::size_t sub = kHistoryDepth; sub > 1; --sub) od_.set(history_slots_[sub], od_.u32(history_slots_[sub - 1]));
  od_.set(history_slots_[1], error_code);
  const std::uint32_t count = od_.u32(history_slots_[0]);
  od_.set(history_slots_[0], std::min<std::uint32_t>(count + 1, kHistoryDepth));
  emit(error_code, now_ns, out);
}

void EmcyProducer::clear(std::int64_t now_ns, FrameSink& out, std::uint8_t remaining_register) {
  od_.set(error_register_slot_, remaining_register);
  emit(kEmcyErrorReset, now_ns, out);
}

void EmcyProducer::poll(std::int64_t now_ns, FrameSink& out) {
  if (!pending_ || inhibited(now_ns)) return;
  pending_ = false;
  // 0x1014 may have been made not valid while the EMCY waited: then it is not sent.
  if ((od_.u32(cob_id_slot_) & kCobIdNotValid) == 0) send(pending_code_, now_ns, out);
}

void EmcyProducer::reset() {
  pending_ = false;
  has_sent_ = false;
}

void EmcyProducer::emit(std::uint16_t error_code, std::int64_t now_ns, FrameSink& out) {
  if ((od_.u32(cob_id_slot_) & kCobIdNotValid) != 0) return;
  if (inhibited(now_ns)) {
    if (pending_) ++replaced_;
    pending_ = true;
    pending_code_ = error_code;
    return;
  }
  send(error_code, now_ns, out);
}

void EmcyProducer::send(std::uint16_t error_code, std::int64_t now_ns, FrameSink& out) {
  constexpr std::array<std::uint8_t, 5> kNoManufacturerField{};
  out.send(emcy_frame(od_.u32(cob_id_slot_), error_code, static_cast<std::uint8_t>(od_.u32(error_register_slot_)),
                      kNoManufacturerField));
  has_sent_ = true;
  last_sent_ns_ = now_ns;
  ++sent_;
}

bool EmcyProducer::inhibited(std::int64_t now_ns) const {
  const std::int64_t inhibit_ns = static_cast<std::int64_t>(od_.u32(inhibit_slot_)) * kNsPer100Us;
  // No inhibit time: never held (a caller's clock that reads a little earlier than the last send,
  // e.g. a frame's receive stamp, must not hold an EMCY back either).
  return inhibit_ns > 0 && has_sent_ && now_ns - last_sent_ns_ < inhibit_ns;
}

}  // namespace swum::canopen
