// Fuzz target: the PDOs of a CANopen slave (canopen/pdo.h) on the dictionary generated from
// config/swum.eds, fed arbitrary frames interleaved with SDO-like od.write() calls (remapping,
// COB-IDs, transmission types, timers, objects), SYNCs, polls and resets.
// Input: byte 0 = node id (1..127); then operations, each an opcode byte and its operands:
//   0 frame: flags (bit 7: 29-bit identifier, bits 0-3: DLC 0..15), identifier (2 bytes, little-
//     endian), 8 payload bytes;
//   1 write: object (1 byte: one of kObjects; 0xFF: the next 2 bytes are the index), sub, length
//     (0..4), value (4 bytes, little-endian: its first `length` bytes are written);
//   2 SYNC: counter; 3 poll: time step (2 bytes, in 100 µs); 4 reset (NMT start);
//   5 reset communication (the dictionary's defaults, then reset).
// Invariants: nothing crashes; every frame sent is a standard frame of at most 8 bytes with an
// identifier of at most 0x7FF; length_errors() grows by one exactly when receive() says
// length_error (by none otherwise), and SYNC, poll and reset count none; every object with limits
// stays within them whatever an RPDO wrote.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_check.h"
#include "object_dictionary.h"
#include "pdo.h"

namespace {

using swum::canopen::ObjectDictionary;
using swum::canopen::Pdos;
using swum::protocol::CanFrame;

// The objects a master writes to configure PDOs, and the objects the default mappings carry.
constexpr std::array<std::uint16_t, 27> kObjects{0x1400, 0x1401, 0x1402, 0x1403, 0x1600, 0x1601, 0x1602,
                                                 0x1603, 0x1800, 0x1801, 0x1802, 0x1803, 0x1A00, 0x1A01,
                                                 0x1A02, 0x1A03, 0x6040, 0x6060, 0x60FF, 0x2001, 0x2002,
                                                 0x2003, 0x6041, 0x6061, 0x6064, 0x606C, 0x1005};

struct Checked final : swum::canopen::FrameSink {
  std::size_t frames = 0;
  void send(const CanFrame& frame) override {
    FUZZ_CHECK(!frame.extended && frame.dlc <= 8 && frame.id <= swum::protocol::kCanStandardIdMax,
               "sent extended=%d dlc=%u id=0x%X", frame.extended, frame.dlc, frame.id);
    ++frames;
  }
};

class Input {
 public:
  Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  [[nodiscard]] bool empty() const { return at_ >= size_; }
  std::uint8_t byte() { return at_ < size_ ? data_[at_++] : 0; }
  std::uint16_t u16() { return static_cast<std::uint16_t>(byte() | (byte() << 8)); }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

void check_limits(const ObjectDictionary& od) {
  for (std::size_t slot = 0; slot < od.size(); ++slot) {
    const auto& d = od.description(slot);
    if (!d.has_limits) continue;
    const std::int64_t v = d.low_limit < 0 ? std::int64_t{od.i32(slot)} : std::int64_t{od.u32(slot)};
    FUZZ_CHECK(v >= d.low_limit && v <= d.high_limit, "0x%04X sub %u = %lld outside %lld..%lld", d.index, d.sub,
               static_cast<long long>(v), static_cast<long long>(d.low_limit), static_cast<long long>(d.high_limit));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  Input in(data, size);
  const auto node = static_cast<std::uint8_t>(in.byte() % 127 + 1);
  ObjectDictionary od(swum::canopen::swum_eds_objects(), node);
  Pdos pdos(od, node);
  Checked out;
  std::int64_t now_ns = 0;
  pdos.reset(now_ns);
  while (!in.empty()) {
    const std::uint64_t errors_before = pdos.length_errors();
    switch (in.byte() % 6) {
      case 0: {
        CanFrame frame;
        const std::uint8_t flags = in.byte();
        frame.extended = (flags & 0x80U) != 0;
        frame.dlc = static_cast<std::uint8_t>(flags & 0x0FU);
        frame.id = in.u16() & (frame.extended ? 0xFFFFU : swum::protocol::kCanStandardIdMax);
        for (std::uint8_t& b : frame.data) b = in.byte();
        const Pdos::RpdoStatus status = pdos.receive(frame);
        const std::uint64_t counted = pdos.length_errors() - errors_before;
        FUZZ_CHECK(counted == (status == Pdos::RpdoStatus::length_error ? 1U : 0U),
                   "receive gave status %d and counted %llu length errors", static_cast<int>(status),
                   static_cast<unsigned long long>(counted));
        FUZZ_CHECK(status == Pdos::RpdoStatus::not_rpdo || !frame.extended, "a 29-bit frame was taken as an RPDO");
        break;
      }
      case 1: {
        const std::uint8_t which = in.byte();
        const std::uint16_t index = which == 0xFF ? in.u16() : kObjects[which % kObjects.size()];
        const std::uint8_t sub = in.byte();
        const std::size_t length = in.byte() % 5;
        const std::array<std::uint8_t, 4> value{in.byte(), in.byte(), in.byte(), in.byte()};
        if (const auto slot = od.find(index, sub)) (void)od.write(*slot, std::span(value.data(), length));
        break;
      }
      case 2: pdos.on_sync(in.byte(), out); break;
      case 3:
        now_ns += std::int64_t{in.u16()} * 100'000;
        pdos.poll(now_ns, out);
        break;
      case 4: pdos.reset(now_ns); break;
      default:
        od.reset_communication();
        pdos.reset(now_ns);
        break;
    }
    FUZZ_CHECK(pdos.length_errors() - errors_before <= 1, "one operation counted several length errors");
    check_limits(od);
  }
  return 0;
}
