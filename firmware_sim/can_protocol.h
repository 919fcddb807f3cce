// The CAN protocol of swum-emu (pure encode/decode; config/swum.dbc describes the same frames
// for node 1, and a test keeps the two in agreement). Classic CAN, 11-bit identifiers, every
// signal little-endian (Intel) at the bit positions below, physical = raw * factor.
//
//   0x200+N  Command   (to the emulator)  mode, alive counter, frequency, phase, amplitude, CRC
//   0x300+N  AuxCommand (to the emulator) alive counter, load force, slew limits, CRC
//   0x180+N  Status     state, flags, fault code, last reject reason, counters
//   0x280+N  Motion     mover speed and position
//   0x380+N  Drive      tip amplitudes, amplitude and phase driven
//   0x480+N  LoopStats  lateness p99 / p99.9 / max, overruns
//   0x500+N  Output     frequency driven, load force, lateness p50
//   0x580+N  Clock      emulated time and tick (sent before Output, which ends a telemetry set)
//   0x700+N  Heartbeat  1 byte, 0x05 (CANopen "operational")
//
// CRC: CRC-8/SAE-J1850 (poly 0x1D, init 0xFF, final xor 0xFF) over the identifier as two bytes
// (little-endian) followed by payload bytes 0..6; stored in byte 7.
// Alive counter (4 bits): each accepted frame's counter must be 1..7 ahead (mod 16) of the last
// accepted one of the same identifier; 0 ahead (repeat) or 8..15 ahead (older) is stale. The
// first frame after start, and the first after more than 1 s without an accepted frame of that
// identifier (a controller that restarted begins its own count), is accepted with any counter.
// Rejected frames change nothing.
#pragma once

#include <cstdint>

#include "amplifier.h"
#include "can_bus.h"
#include "register_map.h"
#include "telemetry.h"

namespace swum::emu::can {

struct Ids {
  std::uint32_t command, aux, status, motion, drive, loop_stats, output, heartbeat, clock;
};
inline constexpr std::uint8_t kMinNode = 1;
inline constexpr std::uint8_t kMaxNode = 127;
Ids ids_for_node(std::uint8_t node);

std::uint8_t crc8(std::uint32_t id, const std::uint8_t* data, std::size_t length = 7);

// Raw bit fields, little-endian (DBC "@1"): start = LSB position in the 64-bit payload.
std::uint64_t get_bits(const io::CanFrame& frame, unsigned start, unsigned length);
void put_bits(io::CanFrame& frame, unsigned start, unsigned length, std::uint64_t raw);

// Command modes (Command.Mode): 0 disable, 1 enable, 2 reset fault; 3 is rejected.
struct CommandFrame {
  std::uint8_t mode = 0;
  std::uint8_t alive = 0;
  double frequency_hz = 40000.0;  // 20 bits, 0.1 Hz
  double phase_deg = 90.0;        // 12 bits signed, 0.1 deg
  double amplitude_vpp = 0.0;     // 12 bits, 0.25 Vpp
};
struct AuxFrame {
  std::uint8_t alive = 0;
  double load_n = 0.0;                      // 16 bits signed, 1 mN
  double frequency_slew_hz_per_s = 0.0;     // 16 bits, 100 Hz/s (0 = unlimited)
  double amplitude_slew_vpp_per_s = 0.0;    // 16 bits, 10 Vpp/s (0 = unlimited)
};

io::CanFrame encode_command(const CommandFrame& c, std::uint32_t id);
io::CanFrame encode_aux(const AuxFrame& a, std::uint32_t id);
// Length, reserved bits, CRC, mode; not ranges (validate() does those on the Command).
Reason decode_command(const io::CanFrame& frame, CommandFrame& out);
Reason decode_aux(const io::CanFrame& frame, AuxFrame& out);
Command to_command(const CommandFrame& c);
Command to_command(const AuxFrame& a);

inline constexpr std::int64_t kAliveResyncNs = 1'000'000'000;

class AliveCounter {
 public:
  // now_ns: a monotonic clock (any epoch).
  [[nodiscard]] Reason check(std::uint8_t alive, std::int64_t now_ns) const;
  void accept(std::uint8_t alive, std::int64_t now_ns) {
    last_ = alive & 0x0FU;
    seen_ = true;
    last_ns_ = now_ns;
  }

 private:
  std::uint8_t last_ = 0;
  bool seen_ = false;
  std::int64_t last_ns_ = 0;
};

// Telemetry frames (counter: the sender's running count of status frames, mod 256).
io::CanFrame encode_status(const Telemetry& t, const modbus::RejectSnapshot& r, std::uint8_t counter, std::uint32_t id);
io::CanFrame encode_motion(const Telemetry& t, std::uint32_t id);
io::CanFrame encode_drive(const Telemetry& t, std::uint32_t id);
io::CanFrame encode_loop_stats(const Telemetry& t, std::uint32_t id);
io::CanFrame encode_output(const Telemetry& t, std::uint32_t id);
// Emulated time (ms, mod 2^32) and tick (mod 2^32): the device clock a controller times against.
io::CanFrame encode_clock(const Telemetry& t, std::uint32_t id);
io::CanFrame encode_heartbeat(std::uint32_t id);

}  // namespace swum::emu::can
