#include "cia402.h"

#include <array>
#include <cstddef>

namespace swum::canopen {

namespace {

// CiA 402-2 Table "state coding": the bits that select each state and their values (bit 5, quick
// stop, only where it tells two states apart), and whether swum's drive sets voltage enabled
// there. In the order of Cia402State, so that a state's row is at its value. The masks make the
// codings disjoint: no statusword codes two states.
struct StateCoding {
  Cia402State state;
  std::uint16_t mask;
  std::uint16_t value;
  bool voltage_enabled;
};
// The fault reaction here is "disable the drive function": the output is already off in fault
// reaction active.
constexpr std::array<StateCoding, 8> kStateCodings{{
    {Cia402State::not_ready_to_switch_on, 0x004F, 0x0000, false},
    {Cia402State::switch_on_disabled, 0x004F, 0x0040, false},
    {Cia402State::ready_to_switch_on, 0x006F, 0x0021, true},
    {Cia402State::switched_on, 0x006F, 0x0023, true},
    {Cia402State::operation_enabled, 0x006F, 0x0027, true},
    {Cia402State::quick_stop_active, 0x006F, 0x0007, true},
    {Cia402State::fault_reaction_active, 0x004F, 0x000F, false},
    {Cia402State::fault, 0x004F, 0x0008, false},
}};
constexpr bool codings_in_state_order() {
  for (std::size_t i = 0; i < kStateCodings.size(); ++i)
    if (static_cast<std::size_t>(kStateCodings[i].state) != i) return false;
  return true;
}
static_assert(codings_in_state_order());
constexpr bool codings_disjoint() {
  for (const StateCoding& a : kStateCodings) {
    if ((a.value & ~a.mask) != 0) return false;
    for (const StateCoding& b : kStateCodings)  // two codings meet where they agree on the bits both select
      if (a.state != b.state && ((a.value ^ b.value) & a.mask & b.mask) == 0) return false;
  }
  return true;
}
static_assert(codings_disjoint());

// docs/canopen.md "Faults and EMCY codes": one code per swum fault.
struct FaultCoding {
  protocol::FaultCode fault;
  std::uint16_t error_code;
};
constexpr std::array<FaultCoding, 5> kFaultCodings{{
    {protocol::FaultCode::none, 0x0000},
    {protocol::FaultCode::over_temperature, 0x4310},  // excess temperature drive
    {protocol::FaultCode::over_current, 0x2320},      // short circuit, device output side
    {protocol::FaultCode::numerical, 0x6100},         // internal software
    {protocol::FaultCode::command_timeout, 0x8100},   // communication
}};

}  // namespace

const char* to_string(Cia402State state) {
  switch (state) {
    case Cia402State::not_ready_to_switch_on: return "not ready to switch on";
    case Cia402State::switch_on_disabled: return "switch on disabled";
    case Cia402State::ready_to_switch_on: return "ready to switch on";
    case Cia402State::switched_on: return "switched on";
    case Cia402State::operation_enabled: return "operation enabled";
    case Cia402State::quick_stop_active: return "quick stop active";
    case Cia402State::fault_reaction_active: return "fault reaction active";
    case Cia402State::fault: return "fault";
    case Cia402State::unknown: return "no CiA 402 state";
  }
  return "?";
}

std::uint16_t state_statusword(Cia402State state) {
  const auto index = static_cast<std::size_t>(state);
  if (index >= kStateCodings.size()) return kStatuswordRemote;
  const StateCoding& c = kStateCodings[index];
  return static_cast<std::uint16_t>(c.value | (c.voltage_enabled ? kStatuswordVoltageEnabled : 0U) | kStatuswordRemote);
}

Cia402State state_of(std::uint16_t statusword) {
  for (const StateCoding& c : kStateCodings)
    if ((statusword & c.mask) == c.value) return c.state;
  return Cia402State::unknown;
}

Cia402Command decode_controlword(std::uint16_t controlword) {
  if ((controlword & kControlwordFaultReset) != 0) return Cia402Command::none;
  if ((controlword & kControlwordEnableVoltageBit) == 0) return Cia402Command::disable_voltage;  // xx0x
  if ((controlword & kControlwordQuickStopBit) == 0) return Cia402Command::quick_stop;           // x01x
  if ((controlword & kControlwordSwitchOnBit) == 0) return Cia402Command::shutdown;              // x110
  return (controlword & kControlwordEnableOperationBit) != 0 ? Cia402Command::enable_operation
                                                             : Cia402Command::switch_on;
}

bool mode_supported(std::int8_t mode) { return mode == kModeProfileVelocity || mode == kModeOpenLoop; }

std::uint16_t error_code(protocol::FaultCode fault) {
  for (const FaultCoding& c : kFaultCodings)
    if (c.fault == fault) return c.error_code;
  return kErrorCodeGeneric;
}

std::optional<protocol::FaultCode> fault_of(std::uint16_t error_code) {
  for (const FaultCoding& c : kFaultCodings)
    if (c.error_code == error_code) return c.fault;
  return std::nullopt;
}

}  // namespace swum::canopen
