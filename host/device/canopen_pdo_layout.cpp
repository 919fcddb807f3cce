#include "device/canopen_pdo_layout.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "cia402.h"
#include "device/cia402_master.h"

namespace swum::host::canopen_layout {

namespace {

constexpr std::uint32_t entry(std::uint16_t index, std::uint8_t sub, std::uint8_t bits) {
  return static_cast<std::uint32_t>(index) << 16 | static_cast<std::uint32_t>(sub) << 8 | bits;
}

constexpr std::uint8_t kSynchronous = 1;    // every SYNC (CiA 301 7.2.2.3.2)
constexpr std::uint8_t kEventDriven = 255;  // acted on when received
constexpr std::array<std::uint32_t, 3> kTpdo1{entry(0x6041, 0, 16), entry(0x603F, 0, 16), entry(0x606C, 0, 32)};
constexpr std::array<std::uint32_t, 2> kTpdo2{entry(0x2010, 0, 32), entry(0x2011, 0, 32)};
constexpr std::array<std::uint32_t, 2> kTpdo3{entry(0x6064, 0, 32), entry(0x2012, 0, 16)};
constexpr std::array<std::uint32_t, 1> kTpdo4{entry(0x2027, 0, 32)};
constexpr std::array<std::uint32_t, 2> kRpdo1{entry(0x2001, 0, 32), entry(0x2002, 0, 32)};
constexpr std::array<std::uint32_t, 2> kRpdo2{entry(0x6040, 0, 16), entry(0x2003, 0, 16)};

const std::array<Pdo, 4> kTpdos{Pdo{1, 0x180, kSynchronous, kTpdo1}, Pdo{2, 0x280, kSynchronous, kTpdo2},
                                Pdo{3, 0x380, kSynchronous, kTpdo3}, Pdo{4, 0x480, kSynchronous, kTpdo4}};
const std::array<Pdo, 2> kRpdos{Pdo{1, 0x200, kEventDriven, kRpdo1}, Pdo{2, 0x300, kEventDriven, kRpdo2}};

std::uint32_t u32(const protocol::CanFrame& f, std::size_t at) {
  return f.data[at] | f.data[at + 1] << 8 | f.data[at + 2] << 16 | static_cast<std::uint32_t>(f.data[at + 3]) << 24;
}
std::uint16_t u16(const protocol::CanFrame& f, std::size_t at) {
  return static_cast<std::uint16_t>(f.data[at] | f.data[at + 1] << 8);
}
void put(protocol::CanFrame& f, std::size_t at, std::uint32_t value, std::size_t bytes) {
  for (std::size_t i = 0; i < bytes; ++i) f.data[at + i] = static_cast<std::uint8_t>(value >> (8 * i));
}

std::string out_of_range(const char* field, double value, const char* limit) {
  char text[160];
  std::snprintf(text, sizeof text, "%s %g is outside what the CiA 402 drive takes (%s)", field, value, limit);
  return text;
}

}  // namespace

std::size_t Pdo::bytes() const {
  std::size_t bits = 0;
  for (const std::uint32_t e : entries) bits += e & 0xFF;
  return bits / 8;
}

std::span<const Pdo> tpdos() { return kTpdos; }
std::span<const Pdo> rpdos() { return kRpdos; }

std::string decode_tpdo(int number, const protocol::CanFrame& f, Actuals& out) {
  if (number < 1 || number > static_cast<int>(kTpdos.size())) return "no TPDO" + std::to_string(number);
  const Pdo& pdo = kTpdos[static_cast<std::size_t>(number - 1)];
  if (f.dlc != pdo.bytes()) {
    return "TPDO" + std::to_string(number) + " has " + std::to_string(f.dlc) + " bytes, its mapping " +
           std::to_string(pdo.bytes()) + " (did another master remap it?)";
  }
  switch (number) {
    case 1:
      out.statusword = u16(f, 0);
      out.error_code = u16(f, 2);
      out.velocity_um_s = static_cast<std::int32_t>(u32(f, 4));
      break;
    case 2:
      out.frequency_mhz = u32(f, 0);
      out.amplitude_mv = u32(f, 4);
      break;
    case 3:
      out.position_um = static_cast<std::int32_t>(u32(f, 0));
      out.phase_cdeg = static_cast<std::int16_t>(u16(f, 4));
      break;
    default: out.temperature_cdegc = static_cast<std::int32_t>(u32(f, 0)); break;
  }
  return {};
}

DeviceTelemetry telemetry_of(const Actuals& a) {
  DeviceTelemetry t;
  t.received = std::chrono::steady_clock::now();
  t.state = static_cast<int>(cia402::amp_state(canopen::state_of(a.statusword)));
  // As protocol::drive_on: enabled and driving a non-zero amplitude.
  t.drive_on = t.state == static_cast<int>(protocol::AmpState::enabled) && a.amplitude_mv > 0;
  // 0x603F as the swum fault it stands for (docs/canopen.md "Faults and EMCY codes"), any other
  // code as it is: above 255, so never taken for a swum code (e.g. 0x8130, the heartbeat error).
  const std::optional<protocol::FaultCode> fault = canopen::fault_of(a.error_code);
  t.fault_code = fault ? static_cast<int>(*fault) : static_cast<int>(a.error_code);
  t.speed_mm_s = a.velocity_um_s * 1e-3;
  t.position_mm = a.position_um * 1e-3;
  t.frequency_hz = a.frequency_mhz * 1e-3;
  t.amplitude_v = a.amplitude_mv * 1e-3;
  t.phase_deg = a.phase_cdeg * 0.01;
  t.stator_temperature_c = a.temperature_cdegc * 0.01;
  return t;
}

std::string encode_setpoints(const DriveSetpoint& s, Setpoints& out) {
  const double mhz = std::round(s.frequency_hz * 1e3);
  if (!(mhz >= 0.0 && mhz <= 4294967295.0))
    return out_of_range("frequency_hz", s.frequency_hz, "0x2001: UNSIGNED32 mHz");
  const double mv = std::round(s.amplitude_v * 1e3);
  if (!(mv >= 0.0 && mv <= 4294967295.0)) return out_of_range("amplitude_v", s.amplitude_v, "0x2002: UNSIGNED32 mV");
  const double cdeg = std::round(s.phase_deg * 100.0);
  if (!(cdeg >= -18000.0 && cdeg <= 18000.0)) return out_of_range("phase_deg", s.phase_deg, "0x2003: -180..180 deg");
  out.frequency_mhz = static_cast<std::uint32_t>(mhz);
  out.amplitude_mv = static_cast<std::uint32_t>(mv);
  out.phase_cdeg = static_cast<std::int16_t>(cdeg);
  return {};
}

protocol::CanFrame rpdo1(std::uint8_t node, const Setpoints& s) {
  protocol::CanFrame f;
  f.id = kRpdos[0].cob_id(node);
  f.dlc = 8;
  put(f, 0, s.frequency_mhz, 4);
  put(f, 4, s.amplitude_mv, 4);
  return f;
}

protocol::CanFrame rpdo2(std::uint8_t node, std::uint16_t controlword, const Setpoints& s) {
  protocol::CanFrame f;
  f.id = kRpdos[1].cob_id(node);
  f.dlc = 4;
  put(f, 0, controlword, 2);
  put(f, 2, static_cast<std::uint16_t>(s.phase_cdeg), 2);
  return f;
}

}  // namespace swum::host::canopen_layout
