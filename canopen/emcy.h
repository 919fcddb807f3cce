// The emergency producer (CiA 301 7.2.7): the EMCY frame (error code, error register, five
// manufacturer bytes), the error register 0x1001 (7.5.2.2) and the pre-defined error field 0x1003
// (7.5.2.4) it keeps in the dictionary, the COB-ID 0x1014 and the inhibit time 0x1015 it honours.
// Pure: times are passed in; no allocation, no exception after construction.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "can_frame.h"
#include "frame_sink.h"
#include "object_dictionary.h"

namespace swum::canopen {

inline constexpr std::uint16_t kEmcyErrorReset = 0x0000;   // "error reset or no error" (Table 50)
inline constexpr std::uint32_t kCobIdNotValid = 1U << 31;  // bit 31 of a COB-ID: the object does not exist

// Bytes 0-1 the code (little-endian), byte 2 the error register, bytes 3-7 the manufacturer's
// field (7.2.7); identifier bits 0-10 of cob_id.
protocol::CanFrame emcy_frame(std::uint32_t cob_id, std::uint16_t error_code, std::uint8_t error_register,
                              std::span<const std::uint8_t, 5> manufacturer);

// The error register bits (0x1001, 7.5.2.2).
namespace error_register {
inline constexpr std::uint8_t kGeneric = 1U << 0;
inline constexpr std::uint8_t kCurrent = 1U << 1;
inline constexpr std::uint8_t kVoltage = 1U << 2;
inline constexpr std::uint8_t kTemperature = 1U << 3;
inline constexpr std::uint8_t kCommunication = 1U << 4;
inline constexpr std::uint8_t kDeviceProfile = 1U << 5;
inline constexpr std::uint8_t kManufacturer = 1U << 7;
}  // namespace error_register

// The bits an error code sets: the generic bit always (it is set at any error, 7.5.2.2), and the
// bit of the code's class (Table 50): 2xxx current, 3xxx voltage, 4xxx temperature, 8xxx
// monitoring (communication, protocol: the communication bit), FFxx device specific (the
// manufacturer bit). 1xxx generic, 5xxx hardware, 6xxx software, 7xxx modules, 9xxx external and
// F0xx additional functions have no bit of their own. 0x0000 sets none.
std::uint8_t error_register_bits(std::uint16_t error_code);

class EmcyProducer {
 public:
  // Binds 0x1001, 0x1003 sub 0-8, 0x1014 and 0x1015; throws std::out_of_range if one is missing.
  explicit EmcyProducer(ObjectDictionary& od);

  // An error occurred: its bits into 0x1001, its code at the head of 0x1003 (sub 1 newest, older
  // ones one down, at most 8, sub 0 the count), and an EMCY frame, unless 0x1014 bit 31 is set
  // (no EMCY: the dictionary still records). Within the inhibit time of the last EMCY the frame
  // waits (poll sends it); at most one waits: a newer one replaces it (counted in replaced()), so
  // the master sees the latest state, while 0x1003 keeps every code.
  void raise(std::uint16_t error_code, std::int64_t now_ns, FrameSink& out);
  // An error is gone: 0x1001 to the bits of the errors that remain (0: none) and the error
  // reset EMCY (code 0x0000 with that register, CiA 301 7.2.7); 0x1003 keeps its history (a
  // master clears it by writing 0 to sub 0).
  void clear(std::int64_t now_ns, FrameSink& out, std::uint8_t remaining_register = 0);
  // Sends the waiting EMCY once the inhibit time has passed.
  void poll(std::int64_t now_ns, FrameSink& out);
  // NMT reset communication: nothing waits, the inhibit time starts over.
  void reset();

  [[nodiscard]] std::uint64_t sent() const { return sent_; }
  [[nodiscard]] std::uint64_t replaced() const { return replaced_; }
  [[nodiscard]] bool waiting() const { return pending_; }

 private:
  void emit(std::uint16_t error_code, std::int64_t now_ns, FrameSink& out);
  void send(std::uint16_t error_code, std::int64_t now_ns, FrameSink& out);
  [[nodiscard]] bool inhibited(std::int64_t now_ns) const;

  ObjectDictionary& od_;
  std::size_t error_register_slot_;
  std::array<std::size_t, 9> history_slots_;  // 0x1003 sub 0..8
  std::size_t cob_id_slot_;
  std::size_t inhibit_slot_;
  bool pending_ = false;
  std::uint16_t pending_code_ = 0;
  bool has_sent_ = false;
  std::int64_t last_sent_ns_ = 0;
  std::uint64_t sent_ = 0;
  std::uint64_t replaced_ = 0;
};

}  // namespace swum::canopen
