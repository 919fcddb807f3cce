// The Modbus register map and both directions of its encoding (pure: no sockets). The device
// (swum-emu's server) uses parse_request / decide / fill_*; a controller (the host tool's
// client) uses encode_* / decode_input. config/modbus_registers.json is the machine-readable
// description; tests keep the two in agreement.
//  - Holding registers (FC 03 read, FC 06 / FC 16 write): setpoints and commands. A write is
//    validated here and becomes one Command (all registers of one request apply together).
//  - Input registers (FC 04): telemetry, refreshed from the latest tick's snapshot.
//  - 32-bit values: two registers, high word first (at the lower address), each word big-endian
//    on the wire ("ABCD"). A request that covers only one half of a 32-bit value is rejected
//    with ILLEGAL DATA ADDRESS.
//  - Exceptions: 01 ILLEGAL FUNCTION, 02 ILLEGAL DATA ADDRESS, 03 ILLEGAL DATA VALUE (bad
//    quantity / byte count, setpoint out of range, unknown command), 06 SERVER DEVICE BUSY
//    (command queue full). The reason of the last reject is readable at input register 3.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "codes.h"
#include "command.h"
#include "telemetry.h"

namespace swum::protocol::modbus {

enum Exception : std::uint8_t {
  kNoException = 0,
  kIllegalFunction = 0x01,
  kIllegalDataAddress = 0x02,
  kIllegalDataValue = 0x03,
  kServerDeviceFailure = 0x04,
  kServerDeviceBusy = 0x06,
};

enum Function : std::uint8_t {
  kReadHoldingRegisters = 0x03,
  kReadInputRegisters = 0x04,
  kWriteSingleRegister = 0x06,
  kWriteMultipleRegisters = 0x10,
};

// Holding register addresses (0-based PDU addresses).
namespace holding {
inline constexpr std::uint16_t kCommand = 0;        // u16: 0 keep-alive, 1 enable, 2 disable, 3 reset fault
inline constexpr std::uint16_t kFrequency = 1;      // u32 (1-2): mHz
inline constexpr std::uint16_t kAmplitude = 3;      // u16: 0.1 V
inline constexpr std::uint16_t kPhase = 4;          // i16: 0.01 deg
inline constexpr std::uint16_t kLoad = 5;           // i16: mN
inline constexpr std::uint16_t kFrequencySlew = 6;  // u32 (6-7): Hz/s, 0 = unlimited
inline constexpr std::uint16_t kAmplitudeSlew = 8;  // u32 (8-9): V/s, 0 = unlimited
// u16: lockstep (--clock external) only: run this many ticks after applying the other registers
// of the same request, and reply when they are done; 0 = none. Reads 0.
inline constexpr std::uint16_t kAdvance = 10;
inline constexpr std::uint16_t kCount = 11;
}  // namespace holding

namespace input {
inline constexpr std::uint16_t kStatus = 0;       // bits: 0 enabled, 1 fault, 2 enable line, 3 drive on, 4 at setpoint
inline constexpr std::uint16_t kState = 1;        // 0 disabled, 1 enabled, 2 fault
inline constexpr std::uint16_t kFault = 2;        // FaultCode
inline constexpr std::uint16_t kLastReject = 3;   // Reason of the last rejected command (any interface)
inline constexpr std::uint16_t kRejectCount = 4;  // u32 (4-5)
inline constexpr std::uint16_t kAppliedCommands = 6;  // u32 (6-7)
inline constexpr std::uint16_t kSpeed = 8;            // i32 (8-9): um/s, mean over 10 ms
inline constexpr std::uint16_t kPosition = 10;        // i32 (10-11): um
inline constexpr std::uint16_t kTipNormal = 12;       // u16: nm
inline constexpr std::uint16_t kTipTangential = 13;   // u16: nm
inline constexpr std::uint16_t kFrequencyOut = 14;    // u32 (14-15): mHz
inline constexpr std::uint16_t kAmplitudeOut = 16;    // u16: 0.1 V
inline constexpr std::uint16_t kPhaseOut = 17;        // i16: 0.01 deg
inline constexpr std::uint16_t kLoadOut = 18;         // i16: mN
inline constexpr std::uint16_t kTick = 19;            // u32 (19-20)
inline constexpr std::uint16_t kSimTime = 21;         // u32 (21-22): ms
inline constexpr std::uint16_t kLatenessP50 = 23;     // u16: us (saturating)
inline constexpr std::uint16_t kLatenessP99 = 24;
inline constexpr std::uint16_t kLatenessP999 = 25;
inline constexpr std::uint16_t kLatenessMax = 26;
inline constexpr std::uint16_t kComputeP99 = 27;
inline constexpr std::uint16_t kComputeMax = 28;
inline constexpr std::uint16_t kOverruns = 29;      // u32 (29-30)
inline constexpr std::uint16_t kTickSpeed = 31;     // i32 (31-32): um/s, mean over the last tick
inline constexpr std::uint16_t kLastSequence = 33;  // u32 (33-34): sequence of the last command applied
inline constexpr std::uint16_t kClock = 35;         // u16: 0 internal (wall time), 1 external (lockstep)
// The electrical port over the last window (docs/protocols.md "Electrical port"; 0 before a full one):
inline constexpr std::uint16_t kCurrentA = 36;           // u16: 0.1 mA, peak of the drive-frequency component
inline constexpr std::uint16_t kCurrentB = 37;           // u16: 0.1 mA
inline constexpr std::uint16_t kPhaseA = 38;             // i16: 0.01 deg, current vs voltage, + = current leads
inline constexpr std::uint16_t kPhaseB = 39;             // i16: 0.01 deg
inline constexpr std::uint16_t kMotionalPhaseA = 40;     // i16: 0.01 deg, the motional current (C0 compensated)
inline constexpr std::uint16_t kMotionalPhaseB = 41;     // i16: 0.01 deg
inline constexpr std::uint16_t kPowerA = 42;             // i16: 0.01 W, real power
inline constexpr std::uint16_t kPowerB = 43;             // i16: 0.01 W
inline constexpr std::uint16_t kStatorTemperature = 44;  // i16: 0.01 degC
// The amplifier's output through its network (docs/amplifier.md), mean over the last window:
inline constexpr std::uint16_t kAmplifierCurrentA = 45;   // u16: 0.1 mA, peak
inline constexpr std::uint16_t kAmplifierCurrentB = 46;   // u16: 0.1 mA
inline constexpr std::uint16_t kAmplifierPhaseA = 47;     // i16: 0.01 deg, vs the source voltage, + = leads
inline constexpr std::uint16_t kAmplifierPhaseB = 48;     // i16: 0.01 deg
inline constexpr std::uint16_t kTerminalAmplitudeA = 49;  // u16: 0.1 V
inline constexpr std::uint16_t kTerminalAmplitudeB = 50;  // u16: 0.1 V
inline constexpr std::uint16_t kCount = 51;
}  // namespace input

// Scales (docs/protocols.md): physical = register * unit_per_count, register = physical *
// count_per_unit (both written out so each direction is one exact multiplication).
struct Scale {
  double unit_per_count;
  double count_per_unit;
};
inline constexpr Scale kFrequencyScale{1e-3, 1e3};      // mHz
inline constexpr Scale kAmplitudeScale{0.1, 10.0};      // 0.1 V
inline constexpr Scale kPhaseScale{0.01, 100.0};        // 0.01 deg
inline constexpr Scale kLoadScale{1e-3, 1e3};           // mN
inline constexpr Scale kSlewScale{1.0, 1.0};            // Hz/s, V/s
inline constexpr Scale kMicroScale{1e-6, 1e6};          // speed um/s, position um (from m)
inline constexpr Scale kTipScale{1e-3, 1e3};            // nm (from um)
inline constexpr Scale kSimTimeScale{1e-3, 1e3};        // ms
inline constexpr Scale kCurrentScale{1e-4, 1e4};        // 0.1 mA (from A)
inline constexpr Scale kPowerScale{0.01, 100.0};        // 0.01 W
inline constexpr Scale kTemperatureScale{0.01, 100.0};  // 0.01 degC
inline constexpr double kTimingNsPerCount = 1000.0;     // lateness / compute registers: us

// 32-bit values: high word at `index`, low word at index + 1 ("ABCD").
std::uint32_t get_u32(std::span<const std::uint16_t> registers, std::size_t index);
void put_u32(std::span<std::uint16_t> registers, std::size_t index, std::uint32_t value);

// 32-bit registers: the address of their first (high) word.
bool is_u32_start_holding(std::uint16_t address);
bool is_u32_start_input(std::uint16_t address);

inline constexpr std::size_t kMaxValues = 125;

struct Request {
  std::uint8_t function = 0;
  std::uint16_t address = 0;
  std::uint16_t quantity = 0;
  std::array<std::uint16_t, kMaxValues> values{};  // writes
};

// Modbus TCP: the MBAP header of an ADU as libmodbus framed it (header + PDU, read by what the
// function code implies; a code libmodbus does not know gets no body). The header's length
// field counts unit id + PDU and is what frames the request on the wire (Modbus Messaging on
// TCP/IP Implementation Guide, 3.1.3), so:
//  * protocol id not 0, or a length field shorter than the framed bytes, or one announcing more
//    than an ADU holds (260 bytes): not valid: the stream's framing is lost, close;
//  * a length field longer than the framed bytes: valid, and `surplus_bytes` more belong to
//    this request (e.g. the body of a function code libmodbus does not know): read them before
//    the next request.
struct MbapHeaderCheck {
  bool valid = false;
  std::size_t surplus_bytes = 0;
};
inline constexpr std::size_t kTcpMaxAduBytes = 260;
MbapHeaderCheck check_mbap_header(std::span<const std::uint8_t> adu);

// PDU = function code + data (no MBAP header, no CRC). Checks the function code and the
// quantity / byte-count consistency; 0 on success, else the exception code (reason in *reason).
std::uint8_t parse_request(std::span<const std::uint8_t> pdu, Request& request, Reason* reason);

struct Decision {
  std::uint8_t exception = kNoException;
  Reason reason = Reason::none;
  bool has_command = false;
  Command command;
  std::uint16_t advance_ticks = 0;  // holding kAdvance written: ticks to run after the command
};
// Address ranges and, for writes, value ranges -> one Command.
Decision decide(const Request& request, const AmplifierLimits& limits);

void fill_holding(const Telemetry& t, std::span<std::uint16_t, holding::kCount> registers);
void fill_input(const Telemetry& t, const RejectSnapshot& rejects, std::span<std::uint16_t, input::kCount> registers);

// Controller side. The register image of a drive set-point write (holding kFrequency ..
// kLoad, 5 registers): empty when every value fits its register, else what does not (the
// device checks the ranges of its own limits on top).
inline constexpr std::uint16_t kDriveWriteCount = holding::kLoad + 1 - holding::kFrequency;
std::string encode_drive_write(double frequency_hz, double amplitude_v, double phase_deg, double load_n,
                               std::span<std::uint16_t, kDriveWriteCount> registers);
// Slew limits (holding kFrequencySlew .. kAmplitudeSlew + 1, 4 registers), rounded down but
// never to 0 (0 = unlimited): the device must never ramp faster than asked.
inline constexpr std::uint16_t kSlewWriteCount = holding::kAmplitudeSlew + 2 - holding::kFrequencySlew;
std::string encode_slew_write(double frequency_hz_per_s, double amplitude_v_per_s,
                              std::span<std::uint16_t, kSlewWriteCount> registers);
// A lockstep step (holding kAdvance), written as the last register of a set-point write so that
// one request sets and steps: ticks in [1, 65535]; empty when it fits, else why not.
std::string encode_advance(std::uint64_t ticks, std::uint16_t& register_value);
// The command register's value for an action.
inline std::uint16_t command_code(Action action) { return static_cast<std::uint16_t>(action); }
// One lockstep control cycle as ONE write of every holding register (kCommand .. kAdvance):
// the action, the drive set-points, the slew limits (0 = unlimited) and the ticks to run after
// them. Empty when every value fits its register, else what does not.
std::string encode_step_write(Action action, const AmplifierSetpoints& setpoints, std::uint64_t ticks,
                              std::span<std::uint16_t, holding::kCount> registers);

// The input registers read back into physical units (the inverse of fill_input, to the
// registers' resolution).
struct InputImage {
  std::uint16_t status_bits = 0;  // kStatus* (telemetry.h)
  Telemetry telemetry;
  RejectSnapshot rejects;
  // The code registers as they were read (the enums above hold 8 bits: a device that sends a
  // code this build does not know must be reported as it is, not wrapped).
  std::uint16_t state_code = 0, fault_code = 0, last_reject_code = 0;
  // Speed and position in the controller's units, counts * 1e-3 as the CAN decoder computes
  // them (can_telemetry_decode.h MotionFields): one value per raw count on both buses.
  double speed_mm_s = 0.0, position_mm = 0.0;
};
InputImage decode_input(std::span<const std::uint16_t, input::kCount> registers);

}  // namespace swum::protocol::modbus
