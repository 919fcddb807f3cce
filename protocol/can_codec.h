// The CAN protocol of the device (pure encode/decode; config/swum.dbc describes the same frames
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
//   0x680+N  ElectricalA phase A current, phase, motional phase, real power (sent before Output)
//   0x780+N  ElectricalB the same for phase B (sent before Output; nodes 100 and 101 share
//                        0x7E4 / 0x7E5 with CANopen LSS: docs/protocols.md)
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

#include "can_frame.h"
#include "codes.h"
#include "command.h"
#include "telemetry.h"

namespace swum::protocol::can {

struct Ids {
  std::uint32_t command, aux, status, motion, drive, loop_stats, output, heartbeat, clock;
  std::uint32_t electrical_a, electrical_b;
};
inline constexpr std::uint8_t kMinNode = 1;
inline constexpr std::uint8_t kMaxNode = 127;
Ids ids_for_node(std::uint8_t node);

std::uint8_t crc8(std::uint32_t id, const std::uint8_t* data, std::size_t length = 7);

// Raw bit fields, little-endian (DBC "@1"): start = LSB position in the 64-bit payload.
std::uint64_t get_bits(const CanFrame& frame, unsigned start, unsigned length);
void put_bits(CanFrame& frame, unsigned start, unsigned length, std::uint64_t raw);

// One signal of a frame (the same start, length, sign and factor as config/swum.dbc):
// physical = raw * factor.
struct Signal {
  unsigned start;
  unsigned length;
  bool is_signed = false;
  double factor = 1.0;
};
std::uint64_t raw_value(const CanFrame& frame, Signal signal);
double physical_value(const CanFrame& frame, Signal signal);  // sign-extended * factor
void put_raw(CanFrame& frame, Signal signal, std::uint64_t raw);
void put_physical(CanFrame& frame, Signal signal, double physical);  // rounded, saturated

// The layout of every frame: the one place a bit position or a factor is written.
namespace signals {
// Command 0x200+N
inline constexpr Signal kCommandMode{0, 2};
inline constexpr Signal kCommandReservedLow{2, 2};
inline constexpr Signal kCommandAlive{4, 4};
inline constexpr Signal kCommandFrequency{8, 20, false, 0.1};    // Hz
inline constexpr Signal kCommandPhase{28, 12, true, 0.1};        // deg
inline constexpr Signal kCommandAmplitude{40, 12, false, 0.25};  // V
inline constexpr Signal kCommandReservedHigh{52, 4};
// AuxCommand 0x300+N
inline constexpr Signal kAuxReserved{0, 4};
inline constexpr Signal kAuxAlive{4, 4};
inline constexpr Signal kAuxLoad{8, 16, true, 0.001};             // N
inline constexpr Signal kAuxFrequencySlew{24, 16, false, 100.0};  // Hz/s
inline constexpr Signal kAuxAmplitudeSlew{40, 16, false, 10.0};   // V/s
// Status 0x180+N
inline constexpr Signal kStatusState{0, 2};
inline constexpr Signal kStatusEnableLine{2, 1};
inline constexpr Signal kStatusDriveOn{3, 1};
inline constexpr Signal kStatusAtSetpoint{4, 1};
inline constexpr Signal kStatusExternalClock{5, 1};  // lockstep: telemetry only at SYNC
inline constexpr Signal kStatusFault{8, 8};
inline constexpr Signal kStatusLastReject{16, 8};
inline constexpr Signal kStatusRejectCount{24, 8};                     // mod 256
inline constexpr Signal kStatusAppliedCount{32, 8};                    // mod 256
inline constexpr Signal kStatusCounter{40, 8};                         // mod 256
inline constexpr Signal kStatusStatorTemperature{48, 16, true, 0.01};  // degC
// Motion 0x280+N
inline constexpr Signal kMotionSpeed{0, 32, true, 1.0};      // um/s
inline constexpr Signal kMotionPosition{32, 32, true, 1.0};  // um
// Drive 0x380+N
inline constexpr Signal kDriveTipNormal{0, 16, false, 0.001};       // um
inline constexpr Signal kDriveTipTangential{16, 16, false, 0.001};  // um
inline constexpr Signal kDriveAmplitude{32, 16, false, 0.1};        // V
inline constexpr Signal kDrivePhase{48, 16, true, 0.01};            // deg
// LoopStats 0x480+N (us, saturating at 65535)
inline constexpr Signal kLoopLatenessP99{0, 16};
inline constexpr Signal kLoopLatenessP999{16, 16};
inline constexpr Signal kLoopLatenessMax{32, 16};
inline constexpr Signal kLoopOverruns{48, 16};
// Output 0x500+N
inline constexpr Signal kOutputFrequency{0, 32, false, 0.001};  // Hz
inline constexpr Signal kOutputLoad{32, 16, true, 0.001};       // N
inline constexpr Signal kOutputLatenessP50{48, 16};             // us
// Clock 0x580+N
inline constexpr Signal kClockTime{0, 32, false, 0.001};  // s (ms counts, mod 2^32)
inline constexpr Signal kClockTick{32, 32};               // mod 2^32
// ElectricalA 0x680+N (phase A) and ElectricalB 0x780+N (phase B): the same layout
inline constexpr Signal kElectricalCurrent{0, 16, false, 0.0001};      // A, peak of the drive-frequency component
inline constexpr Signal kElectricalPhase{16, 16, true, 0.01};          // deg, current vs voltage, + = leads
inline constexpr Signal kElectricalMotionalPhase{32, 16, true, 0.01};  // deg, C0 compensated
inline constexpr Signal kElectricalPower{48, 16, true, 0.01};          // W, real power
// Heartbeat 0x700+N: one byte
inline constexpr std::uint8_t kHeartbeatOperational = 0x05;  // CANopen "operational"
}  // namespace signals

// Command modes (Command.Mode): 0 disable, 1 enable, 2 reset fault; 3 is rejected.
namespace mode {
inline constexpr std::uint8_t kDisable = 0;
inline constexpr std::uint8_t kEnable = 1;
inline constexpr std::uint8_t kResetFault = 2;
}  // namespace mode
struct CommandFrame {
  std::uint8_t mode = 0;
  std::uint8_t alive = 0;
  double frequency_hz = 40000.0;  // 20 bits, 0.1 Hz
  double phase_deg = 90.0;        // 12 bits signed, 0.1 deg
  double amplitude_v = 0.0;       // 12 bits, 0.25 V
};
struct AuxFrame {
  std::uint8_t alive = 0;
  double load_n = 0.0;                   // 16 bits signed, 1 mN
  double frequency_slew_hz_per_s = 0.0;  // 16 bits, 100 Hz/s (0 = unlimited)
  double amplitude_slew_v_per_s = 0.0;   // 16 bits, 10 V/s (0 = unlimited)
};

CanFrame encode_command(const CommandFrame& c, std::uint32_t id);
CanFrame encode_aux(const AuxFrame& a, std::uint32_t id);
// Length, reserved bits, CRC, mode; not ranges (validate() does those on the Command).
Reason decode_command(const CanFrame& frame, CommandFrame& out);
Reason decode_aux(const CanFrame& frame, AuxFrame& out);
Command to_command(const CommandFrame& c);
Command to_command(const AuxFrame& a);

inline constexpr std::int64_t kAliveResyncNs = 1'000'000'000;
// The counter a sender puts in its next frame (4 bits, +1 mod 16).
inline std::uint8_t next_alive(std::uint8_t alive) { return static_cast<std::uint8_t>((alive + 1) & 0x0FU); }

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
CanFrame encode_status(const Telemetry& t, const RejectSnapshot& r, std::uint8_t counter, std::uint32_t id);
CanFrame encode_motion(const Telemetry& t, std::uint32_t id);
CanFrame encode_drive(const Telemetry& t, std::uint32_t id);
CanFrame encode_loop_stats(const Telemetry& t, std::uint32_t id);
CanFrame encode_output(const Telemetry& t, std::uint32_t id);
// Emulated time (ms, mod 2^32) and tick (mod 2^32): the device clock a controller times against.
CanFrame encode_clock(const Telemetry& t, std::uint32_t id);
// The electrical port of phase A / phase B over the last window (docs/protocols.md "Electrical port").
CanFrame encode_electrical_a(const Telemetry& t, std::uint32_t id);
CanFrame encode_electrical_b(const Telemetry& t, std::uint32_t id);
CanFrame encode_heartbeat(std::uint32_t id);

// CANopen SYNC (identifier 0x080 for every node; CiA 301): with --clock external each SYNC is one
// control cycle (docs/protocols.md, "Lockstep over CAN"). DLC 0, or 1 with the SYNC counter
// 1..240; anything else is refused (wrong_length, unknown_command).
inline constexpr std::uint32_t kSyncId = 0x080;
inline constexpr std::uint8_t kMaxSyncCounter = 240;
struct SyncFrame {
  bool has_counter = false;
  std::uint8_t counter = 0;
};
Reason decode_sync(const CanFrame& frame, SyncFrame& out);
// counter 0: no counter (DLC 0).
CanFrame encode_sync(std::uint8_t counter);

}  // namespace swum::protocol::can
