// The PDOs the host's CANopen master maps on a swum CiA 402 drive (docs/canopen.md, "The host tool
// as a master"), and their bytes both ways. Four TPDOs of 8 bytes (synchronous, transmission type
// 1: sampled at each SYNC) carry what DeviceTelemetry takes from a drive in mode -1:
//   TPDO1 0x180+N  statusword 0x6041 (16), error code 0x603F (16), velocity actual 0x606C (32)
//   TPDO2 0x280+N  frequency actual 0x2010 (32), phase voltage amplitude actual 0x2011 (32)
//   TPDO3 0x380+N  position actual 0x6064 (32), phase B - phase A actual 0x2012 (16)
//   TPDO4 0x480+N  stator temperature 0x2027 (32)
// The electrical port (0x2020-0x2026, 20 bytes for its seven values) does not fit beside these
// 26: DeviceTelemetry holds it whole or not at all, so it is not mapped (it stays readable by SDO).
// Two RPDOs (event-driven, transmission type 255: they act when received, in lockstep from the
// next cycle) carry the cycle's commands:
//   RPDO1 0x200+N  drive frequency set-point 0x2001 (32), phase voltage amplitude set-point 0x2002 (32)
//   RPDO2 0x300+N  controlword 0x6040 (16), phase B - phase A set-point 0x2003 (16)
// RPDO3 and RPDO4 are switched off (COB-ID bit 31). The slews (0x2004, 0x2005) are not mappable:
// they go by SDO.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "can_frame.h"
#include "device/device.h"

namespace swum::host::canopen_layout {

// One PDO: its number (1-4), the base of its COB-ID (+ node), its transmission type and mapping
// entries (CiA 301 7.4.7.2: index << 16 | sub << 8 | length in bits).
struct Pdo {
  int number;
  std::uint32_t cob_id_base;
  std::uint8_t transmission_type;
  std::span<const std::uint32_t> entries;
  [[nodiscard]] std::uint32_t cob_id(std::uint8_t node) const { return cob_id_base + node; }
  [[nodiscard]] std::size_t bytes() const;  // the sum of the entries' lengths
};
std::span<const Pdo> tpdos();
std::span<const Pdo> rpdos();
inline constexpr std::uint32_t kCobIdNotValid = 0x80000000;  // bit 31 (CiA 301 7.5.2.35)

// The actual values of one SYNC, in the bus's units (docs/canopen.md "Units").
struct Actuals {
  std::uint16_t statusword = 0;
  std::uint16_t error_code = 0;
  std::int32_t velocity_um_s = 0;
  std::uint32_t frequency_mhz = 0;
  std::uint32_t amplitude_mv = 0;
  std::int32_t position_um = 0;
  std::int16_t phase_cdeg = 0;
  std::int32_t temperature_cdegc = 0;
};
// TPDO `number`'s bytes into `out`: "" when they fit its mapping, else what is wrong (its length).
std::string decode_tpdo(int number, const protocol::CanFrame& frame, Actuals& out);
// The telemetry of one complete set (0x2011's terminal amplitude is the amplitude reported).
DeviceTelemetry telemetry_of(const Actuals& a);

// The set-points in the bus's units, checked against the objects' types and 0x2003's range.
struct Setpoints {
  std::uint32_t frequency_mhz = 0;
  std::uint32_t amplitude_mv = 0;
  std::int16_t phase_cdeg = 0;
};
// "" and `out` set, or what is out of range (the DriveSetpoint field and its limit).
std::string encode_setpoints(const DriveSetpoint& s, Setpoints& out);
protocol::CanFrame rpdo1(std::uint8_t node, const Setpoints& s);
protocol::CanFrame rpdo2(std::uint8_t node, std::uint16_t controlword, const Setpoints& s);

}  // namespace swum::host::canopen_layout
