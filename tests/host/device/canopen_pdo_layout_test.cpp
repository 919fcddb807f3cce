// The host's PDO layout (host/device/canopen_pdo_layout.h) against config/swum.eds, object by
// object (mappable, readable for a TPDO, writable for an RPDO, the entry's length the object's),
// and its bytes both ways: RPDOs exactly, TPDOs into DeviceTelemetry's units.
#include "device/canopen_pdo_layout.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "cia402.h"
#include "object_dictionary.h"

namespace swum::host::canopen_layout {
namespace {

using Bytes = std::vector<std::uint8_t>;
Bytes bytes_of(const protocol::CanFrame& f) { return {f.data.begin(), f.data.begin() + f.dlc}; }

protocol::CanFrame frame(std::uint32_t id, Bytes bytes) {
  protocol::CanFrame f;
  f.id = id;
  f.dlc = static_cast<std::uint8_t>(bytes.size());
  std::copy(bytes.begin(), bytes.end(), f.data.begin());
  return f;
}

const canopen::ObjectDescription* describe(std::uint32_t entry) {
  for (const auto& d : canopen::swum_eds_objects())
    if (d.index == entry >> 16 && d.sub == ((entry >> 8) & 0xFF)) return &d;
  return nullptr;
}

void expect_mappable(const Pdo& pdo, bool receive) {
  EXPECT_LE(pdo.bytes(), 8U) << "PDO " << pdo.number;
  for (const std::uint32_t e : pdo.entries) {
    const canopen::ObjectDescription* d = describe(e);
    ASSERT_NE(d, nullptr) << std::hex << e;
    EXPECT_TRUE(d->pdo_mappable) << d->name;
    EXPECT_EQ(e & 0xFF, 8 * canopen::size_of(d->type)) << d->name;
    if (receive) EXPECT_TRUE(d->access == canopen::Access::rw || d->access == canopen::Access::wo) << d->name;
    else EXPECT_NE(d->access, canopen::Access::wo) << d->name;
  }
}

TEST(CanopenPdoLayout, EveryEntryIsMappableAsTheEdsDescribesIt) {
  ASSERT_EQ(tpdos().size(), 4U);
  ASSERT_EQ(rpdos().size(), 2U);
  std::set<std::uint32_t> cob_ids;
  for (const Pdo& pdo : tpdos()) {
    expect_mappable(pdo, false);
    EXPECT_EQ(pdo.transmission_type, 1) << "synchronous: sampled at every SYNC";
    EXPECT_EQ(pdo.cob_id(3), 0x180U + 0x100U * (pdo.number - 1) + 3);  // CiA 301's predefined set
    cob_ids.insert(pdo.cob_id(3));
  }
  for (const Pdo& pdo : rpdos()) {
    expect_mappable(pdo, true);
    EXPECT_EQ(pdo.transmission_type, 255) << "event-driven: acted on when received";
    EXPECT_EQ(pdo.cob_id(3), 0x200U + 0x100U * (pdo.number - 1) + 3);
    cob_ids.insert(pdo.cob_id(3));
  }
  EXPECT_EQ(cob_ids.size(), 6U);
  EXPECT_EQ(tpdos()[0].bytes() + tpdos()[1].bytes() + tpdos()[2].bytes() + tpdos()[3].bytes(), 26U);
}

TEST(CanopenPdoLayout, RpdosCarryTheSetpointsInTheBussUnits) {
  DriveSetpoint s;
  s.frequency_hz = 40321.5;
  s.amplitude_v = 150.0;
  s.phase_deg = -90.0;
  Setpoints out;
  ASSERT_EQ(encode_setpoints(s, out), "");  // amplitude_v is 0x2002's terminal amplitude, one to one
  EXPECT_EQ(out.frequency_mhz, 40321500U);
  EXPECT_EQ(out.amplitude_mv, 150000U);
  EXPECT_EQ(out.phase_cdeg, -9000);
  const protocol::CanFrame one = rpdo1(3, out);
  EXPECT_EQ(one.id, 0x203U);
  EXPECT_EQ(bytes_of(one), (Bytes{0xDC, 0x41, 0x67, 0x02, 0xF0, 0x49, 0x02, 0x00}));
  const protocol::CanFrame two = rpdo2(3, 0x000F, out);
  EXPECT_EQ(two.id, 0x303U);
  EXPECT_EQ(bytes_of(two), (Bytes{0x0F, 0x00, 0xD8, 0xDC}));
}

TEST(CanopenPdoLayout, SetpointsTheObjectsCannotHoldAreNamed) {
  Setpoints out;
  DriveSetpoint s;
  s.phase_deg = 190.0;
  EXPECT_EQ(encode_setpoints(s, out), "phase_deg 190 is outside what the CiA 402 drive takes (0x2003: -180..180 deg)");
  s = DriveSetpoint{};
  s.amplitude_v = -1.0;
  EXPECT_EQ(encode_setpoints(s, out), "amplitude_v -1 is outside what the CiA 402 drive takes (0x2002: UNSIGNED32 mV)");
  s = DriveSetpoint{};
  s.frequency_hz = std::nan("");
  EXPECT_NE(encode_setpoints(s, out).find("frequency_hz nan"), std::string::npos);
}

TEST(CanopenPdoLayout, TpdosBecomeTelemetry) {
  Actuals a;
  // TPDO1: statusword 0x0237 (operation enabled), no error, 123456 µm/s.
  EXPECT_EQ(decode_tpdo(1, frame(0x183, {0x37, 0x02, 0x00, 0x00, 0x40, 0xE2, 0x01, 0x00}), a), "");
  // TPDO2: 40123.456 Hz, 100.5 V.
  EXPECT_EQ(decode_tpdo(2, frame(0x283, {0x40, 0x3C, 0x64, 0x02, 0x94, 0x88, 0x01, 0x00}), a), "");
  // TPDO3: -2500 µm, 90.00°.
  EXPECT_EQ(decode_tpdo(3, frame(0x383, {0x3C, 0xF6, 0xFF, 0xFF, 0x28, 0x23}), a), "");
  // TPDO4: 25.31 °C.
  EXPECT_EQ(decode_tpdo(4, frame(0x483, {0xE3, 0x09, 0x00, 0x00}), a), "");
  const DeviceTelemetry t = telemetry_of(a);
  EXPECT_EQ(t.state, static_cast<int>(protocol::AmpState::enabled));
  EXPECT_TRUE(t.drive_on);
  EXPECT_EQ(t.fault_code, 0);
  EXPECT_DOUBLE_EQ(t.speed_mm_s, 123.456);
  EXPECT_DOUBLE_EQ(t.frequency_hz, 40123.456);
  EXPECT_DOUBLE_EQ(t.amplitude_v, 100.5);  // 0x2011, one to one
  EXPECT_DOUBLE_EQ(t.position_mm, -2.5);
  EXPECT_DOUBLE_EQ(t.phase_deg, 90.0);
  ASSERT_TRUE(t.stator_temperature_c);
  EXPECT_DOUBLE_EQ(*t.stator_temperature_c, 25.31);
  EXPECT_FALSE(t.electrical) << "the electrical port is not mapped";
  EXPECT_FALSE(t.device_time_s);
  // A fault: statusword 0x0208, error code 0x4310 -> over_temperature (4).
  EXPECT_EQ(decode_tpdo(1, frame(0x183, {0x08, 0x02, 0x10, 0x43, 0, 0, 0, 0}), a), "");
  const DeviceTelemetry f = telemetry_of(a);
  EXPECT_EQ(f.state, static_cast<int>(protocol::AmpState::fault));
  EXPECT_EQ(f.fault_code, 4);
  EXPECT_FALSE(f.drive_on);
}

// 0x603F into DeviceTelemetry's fault code: each swum fault's code (the codec's table, tested
// both ways in tests/canopen/cia402_test.cpp) as that fault, any other code as it is.
TEST(CanopenPdoLayout, ErrorCodesBecomeSwumFaultCodesOrStayAsTheyAre) {
  using protocol::FaultCode;
  Actuals a;
  a.statusword = 0x0208;  // fault
  for (const FaultCode fault : {FaultCode::none, FaultCode::command_timeout, FaultCode::numerical,
                                FaultCode::over_current, FaultCode::over_temperature}) {
    a.error_code = canopen::error_code(fault);
    EXPECT_EQ(telemetry_of(a).fault_code, static_cast<int>(fault)) << protocol::to_string(fault);
  }
  for (const std::uint16_t code : {0x8130, 0x1000, 0x8210, 0xFFFF}) {  // heartbeat, generic, PDO length, any
    a.error_code = code;
    EXPECT_EQ(telemetry_of(a).fault_code, code) << std::hex << code;
  }
}

TEST(CanopenPdoLayout, ATpdoOfAnotherLengthIsRefused) {
  Actuals a;
  EXPECT_EQ(decode_tpdo(1, frame(0x183, {0x37, 0x02}), a),
            "TPDO1 has 2 bytes, its mapping 8 (did another master remap it?)");
  EXPECT_EQ(decode_tpdo(4, frame(0x483, {1, 2, 3, 4, 5}), a),
            "TPDO4 has 5 bytes, its mapping 4 (did another master remap it?)");
  EXPECT_EQ(decode_tpdo(5, frame(0x583, {}), a), "no TPDO5");
  EXPECT_EQ(a.statusword, 0) << "nothing taken from a refused frame";
}

}  // namespace
}  // namespace swum::host::canopen_layout
