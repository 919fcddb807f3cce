// The CiA 402 power drive system's state machine (IEC 61800-7-201, CiA 402-2 "PDS FSA") as pure
// functions: the transitions 0-16, the quick stop option code's behaviour (0x605A) and the
// statusword with the drive's flags. The wire codes (states, statusword coding, controlword
// commands, modes, error codes) are canopen/cia402.h's, shared with the host's master. No state
// of its own: Cia402Drive (core/cia402_drive.h) keeps the state and acts on the amplifier.
#pragma once

#include <array>
#include <cstdint>

#include "cia402.h"

namespace swum::emu {

// The drive speaks the codec's states and commands.
using canopen::Cia402Command;
using canopen::Cia402State;

// What a quick stop does (0x605A; CiA 402-2 "quick stop option code"): which deceleration, and
// whether the drive then leaves quick stop active for switch on disabled (transition 12) or
// stays there, powered at standstill, until "enable operation" (16) or "disable voltage" (12).
enum class QuickStopRamp : std::uint8_t {
  none,                     // 0: disable the drive function at once (the mover coasts)
  profile_deceleration,     // 1, 5: 0x6084
  quick_stop_deceleration,  // 2, 6: 0x6085
};
struct QuickStopBehaviour {
  QuickStopRamp ramp = QuickStopRamp::quick_stop_deceleration;
  bool stays_in_quick_stop_active = false;
};
// 0, 1, 2, 5 and 6 are supported (0x605A's range in docs/canopen.md); any other value, which the
// profile refuses to store, behaves as the default 2.
[[nodiscard]] QuickStopBehaviour quick_stop_behaviour(std::int16_t option);
[[nodiscard]] bool quick_stop_option_supported(std::int16_t option);

// What decides a step besides the controlword.
struct Cia402Inputs {
  Cia402Command command = Cia402Command::none;
  bool fault_reset_edge = false;     // a rising edge of bit 7 since the last step
  bool fault = false;                // a fault to react to (transition 13)
  bool quick_stop_finished = false;  // quick stop active: the ramp has reached standstill
  std::int16_t quick_stop_option = 2;
  // Quick stop active entered by the device itself (0x6007 = 3): the master's "enable operation"
  // still latched from before does not count as a new command for transition 16.
  bool enable_operation_is_stale = false;
};

inline constexpr std::int8_t kNoTransition = -1;
struct Cia402Step {
  Cia402State state = Cia402State::not_ready_to_switch_on;
  // The transitions taken, in order (CiA 402-2 numbers; kNoTransition where none): at most two,
  // 3 + 4 ("switch on + enable operation") and 11 + 12 (quick stop with option 0).
  std::array<std::int8_t, 2> transitions{kNoTransition, kNoTransition};
  [[nodiscard]] bool changed() const { return transitions[0] != kNoTransition; }
};

// One step from `state`. Transition 0 (power on) is where a drive starts, 1 (self-test passed)
// is taken from not ready to switch on at the first step, 14 (fault reaction done) at the step
// after 13. A fault takes 13 from every state but the two fault states; in fault only the reset
// edge acts (15).
[[nodiscard]] Cia402Step next_state(Cia402State state, const Cia402Inputs& inputs);

// The drive's flags besides its state (CiA 402-2 "statusword" bits 7, 10-13).
struct Cia402StatusFlags {
  bool warning = false;
  bool target_reached = false;
  bool internal_limit = false;
  bool mode_bit12 = false;
  bool mode_bit13 = false;
};
// canopen::state_statusword(state) with the flags' bits.
[[nodiscard]] std::uint16_t statusword(Cia402State state, const Cia402StatusFlags& flags);

}  // namespace swum::emu
