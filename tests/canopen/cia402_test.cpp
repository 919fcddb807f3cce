// canopen/cia402.h, the CiA 402 codec both ends share, against CiA 402-2's tables: each state's
// exact statusword and its coding under its mask, every statusword read back as its state with
// any flags and any don't-care bits, every controlword decoded, the modes, and the swum faults'
// 0x603F codes both ways for every value a FaultCode byte can hold.
#include "cia402.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace swum::canopen {
namespace {

using C = Cia402Command;
using S = Cia402State;

// CiA 402-2 Table "state coding" (bits 0-3, 5, 6 under their masks) and swum's drive's exact
// words (bit 4 voltage enabled where the amplifier may drive, bit 9 remote always).
struct Coding {
  S state;
  std::uint16_t mask;
  std::uint16_t coding;
  std::uint16_t word;
};
const std::vector<Coding> kTable = {
    {S::not_ready_to_switch_on, 0x004F, 0x0000, 0x0200}, {S::switch_on_disabled, 0x004F, 0x0040, 0x0240},
    {S::ready_to_switch_on, 0x006F, 0x0021, 0x0231},     {S::switched_on, 0x006F, 0x0023, 0x0233},
    {S::operation_enabled, 0x006F, 0x0027, 0x0237},      {S::quick_stop_active, 0x006F, 0x0007, 0x0217},
    {S::fault_reaction_active, 0x004F, 0x000F, 0x020F},  {S::fault, 0x004F, 0x0008, 0x0208},
};

TEST(Cia402Statusword, EachStateHasItsCodingAndItsExactWord) {
  for (const Coding& e : kTable) {
    EXPECT_EQ(state_statusword(e.state) & e.mask, e.coding) << to_string(e.state);
    EXPECT_EQ(state_statusword(e.state), e.word) << to_string(e.state);
  }
  // No state: only remote, as before the table (the drive never writes it).
  EXPECT_EQ(state_statusword(S::unknown), 0x0200);
  EXPECT_EQ(state_statusword(static_cast<S>(99)), 0x0200);
}

TEST(Cia402Statusword, EveryWordOfAStateIsReadBackAsThatState) {
  for (const Coding& e : kTable) {
    // Every value of the bits outside the state's mask (bit 5 outside the 0x4F mask, bit 4, 7-15):
    // with any flags a drive adds, the same state.
    for (std::uint32_t word = 0; word <= 0xFFFF; ++word) {
      if ((word & e.mask) != e.coding) continue;
      ASSERT_EQ(state_of(static_cast<std::uint16_t>(word)), e.state) << std::hex << word;
    }
    EXPECT_EQ(state_of(state_statusword(e.state)), e.state) << to_string(e.state);
  }
}

TEST(Cia402Statusword, EachMaskOfTheTable) {
  EXPECT_EQ(state_of(0x0000), S::not_ready_to_switch_on);
  EXPECT_EQ(state_of(0x0020), S::not_ready_to_switch_on);  // bit 5 is no part of the 0x4F states
  EXPECT_EQ(state_of(0x0040), S::switch_on_disabled);
  EXPECT_EQ(state_of(0x0060), S::switch_on_disabled);
  EXPECT_EQ(state_of(0x0021), S::ready_to_switch_on);
  EXPECT_EQ(state_of(0x0023), S::switched_on);
  EXPECT_EQ(state_of(0x0027), S::operation_enabled);
  EXPECT_EQ(state_of(0x0007), S::quick_stop_active);  // bit 5 clear: quick stop
  EXPECT_EQ(state_of(0x000F), S::fault_reaction_active);
  EXPECT_EQ(state_of(0x002F), S::fault_reaction_active);
  EXPECT_EQ(state_of(0x0008), S::fault);
  EXPECT_EQ(state_of(0x0028), S::fault);
  // Words of no state: ready to switch on without "quick stop" (bit 5), with switch on disabled's
  // bit 6, and switched on with bit 6.
  EXPECT_EQ(state_of(0x0001), S::unknown);
  EXPECT_EQ(state_of(0x0041), S::unknown);
  EXPECT_EQ(state_of(0x0063), S::unknown);
  EXPECT_EQ(state_of(0x0048), S::unknown);
  // Exactly the words of the 8 states are read as one: count them over bits 0-3, 5, 6.
  int coded = 0;
  for (std::uint16_t bits = 0; bits <= 0x7F; ++bits)
    if ((bits & 0x10) == 0 && state_of(bits) != S::unknown) ++coded;
  EXPECT_EQ(coded, 2 + 2 + 1 + 1 + 1 + 1 + 2 + 2);  // the 0x4F states count bit 5 both ways
}

TEST(Cia402Statusword, BitsOfTheStatusword) {
  EXPECT_EQ(kStatuswordVoltageEnabled, 0x0010);
  EXPECT_EQ(kStatuswordQuickStop, 0x0020);
  EXPECT_EQ(kStatuswordWarning, 0x0080);
  EXPECT_EQ(kStatuswordRemote, 0x0200);
  EXPECT_EQ(kStatuswordTargetReached, 0x0400);
  EXPECT_EQ(kStatuswordInternalLimit, 0x0800);
  EXPECT_EQ(kStatuswordModeBit12, 0x1000);
  EXPECT_EQ(kStatuswordModeBit13, 0x2000);
}

TEST(Cia402StateNames, NamesEveryState) {
  EXPECT_STREQ(to_string(S::not_ready_to_switch_on), "not ready to switch on");
  EXPECT_STREQ(to_string(S::switch_on_disabled), "switch on disabled");
  EXPECT_STREQ(to_string(S::ready_to_switch_on), "ready to switch on");
  EXPECT_STREQ(to_string(S::switched_on), "switched on");
  EXPECT_STREQ(to_string(S::operation_enabled), "operation enabled");
  EXPECT_STREQ(to_string(S::quick_stop_active), "quick stop active");
  EXPECT_STREQ(to_string(S::fault_reaction_active), "fault reaction active");
  EXPECT_STREQ(to_string(S::fault), "fault");
  EXPECT_STREQ(to_string(S::unknown), "no CiA 402 state");
  EXPECT_STREQ(to_string(static_cast<S>(99)), "?");
}

// CiA 402-2 Table "command coding": every pattern of bits 3-0 with bit 7 clear, and bit 7 set.
TEST(Cia402Controlword, DecodesEveryCommandOfTheTable) {
  const std::vector<std::pair<std::uint16_t, C>> table = {
      {0x0006, C::shutdown},
      {0x000E, C::shutdown},
      {0x0007, C::switch_on},
      {0x000F, C::enable_operation},
      {0x0000, C::disable_voltage},
      {0x0001, C::disable_voltage},
      {0x0004, C::disable_voltage},
      {0x0005, C::disable_voltage},
      {0x0008, C::disable_voltage},
      {0x000C, C::disable_voltage},
      {0x000D, C::disable_voltage},
      {0x0002, C::quick_stop},
      {0x0003, C::quick_stop},
      {0x000A, C::quick_stop},
      {0x000B, C::quick_stop},
      {0x0080, C::none},
      {0x0086, C::none},
      {0x008F, C::none},
      {0x010F, C::enable_operation},  // halt (bit 8) is no command of the state machine
      {0x7F76, C::shutdown},          // bits 4-6 and 9-15 are ignored
  };
  for (const auto& [word, command] : table) EXPECT_EQ(decode_controlword(word), command) << std::hex << word;
}

TEST(Cia402Controlword, TheCommandWordsAreTheTablesAndDecodeAsTheirCommands) {
  EXPECT_EQ(kControlwordShutdown, 0x0006);
  EXPECT_EQ(kControlwordSwitchOn, 0x0007);
  EXPECT_EQ(kControlwordEnableOperation, 0x000F);
  EXPECT_EQ(kControlwordDisableVoltage, 0x0000);
  EXPECT_EQ(kControlwordQuickStop, 0x0002);
  EXPECT_EQ(kControlwordFaultReset, 0x0080);
  EXPECT_EQ(kControlwordHalt, 0x0100);
  EXPECT_EQ(kControlwordSwitchOnBit | kControlwordEnableVoltageBit | kControlwordQuickStopBit |
                kControlwordEnableOperationBit,
            0x000F);
  EXPECT_EQ(decode_controlword(kControlwordShutdown), C::shutdown);
  EXPECT_EQ(decode_controlword(kControlwordSwitchOn), C::switch_on);
  EXPECT_EQ(decode_controlword(kControlwordEnableOperation), C::enable_operation);
  EXPECT_EQ(decode_controlword(kControlwordDisableVoltage), C::disable_voltage);
  EXPECT_EQ(decode_controlword(kControlwordQuickStop), C::quick_stop);
  EXPECT_EQ(decode_controlword(kControlwordFaultReset), C::none);
}

TEST(Cia402Modes, SupportsProfileVelocityAndOpenLoopOnly) {
  EXPECT_EQ(kModeNone, 0);
  EXPECT_EQ(kModeProfileVelocity, 3);
  EXPECT_EQ(kModeOpenLoop, -1);
  EXPECT_TRUE(mode_supported(3));
  EXPECT_TRUE(mode_supported(-1));
  for (int mode : {0, 1, 2, 4, 6, 7, 8, 9, 10, -2, 127, -128})
    EXPECT_FALSE(mode_supported(static_cast<std::int8_t>(mode)));
}

// docs/canopen.md "Faults and EMCY codes": one code per swum fault, and back.
TEST(Cia402ErrorCode, EveryFaultCodeHasItsCodeAndBack) {
  using protocol::FaultCode;
  const std::vector<std::pair<FaultCode, std::uint16_t>> table = {
      {FaultCode::none, 0x0000},         {FaultCode::command_timeout, 0x8100},  {FaultCode::numerical, 0x6100},
      {FaultCode::over_current, 0x2320}, {FaultCode::over_temperature, 0x4310},
  };
  for (const auto& [fault, code] : table) {
    EXPECT_EQ(error_code(fault), code) << protocol::to_string(fault);
    EXPECT_EQ(fault_of(code), std::optional<FaultCode>(fault)) << std::hex << code;
  }
  EXPECT_EQ(kErrorCodeGeneric, 0x1000);
  EXPECT_EQ(kErrorCodeHeartbeat, 0x8130);
  // Every value a FaultCode byte can hold: the five above, the generic error for the rest.
  for (int code = 5; code <= 255; ++code) EXPECT_EQ(error_code(static_cast<FaultCode>(code)), kErrorCodeGeneric);
  // Codes of no swum fault: the generic error, the heartbeat error, and a neighbour of each code.
  for (std::uint16_t code : {0x1000, 0x8130, 0x8110, 0x4311, 0x2321, 0x6101, 0x8101, 0xFFFF, 0x0001})
    EXPECT_EQ(fault_of(code), std::nullopt) << std::hex << code;
  // Every 16-bit code: exactly the five of the table name a fault, each its own.
  int faults = 0;
  for (std::uint32_t code = 0; code <= 0xFFFF; ++code) {
    const std::optional<FaultCode> fault = fault_of(static_cast<std::uint16_t>(code));
    if (!fault) continue;
    ++faults;
    EXPECT_EQ(error_code(*fault), code);
  }
  EXPECT_EQ(faults, 5);
}

}  // namespace
}  // namespace swum::canopen
