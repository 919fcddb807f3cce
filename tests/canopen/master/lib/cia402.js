// CiA 402's power state machine as a master sees it (IEC 61800-7-201, 6.3.1.2 statusword and
// 6.3.1.3 controlword): the state a statusword shows and the controlwords that move between
// states. Pure; the scenario scripts send the words (SDO) and read the states back.
'use strict';

// Statusword bits 0-3, 5 and 6 select the state (bit 5 "quick stop" only where it matters).
const STATES = [
  { name: 'not ready to switch on', mask: 0x4F, value: 0x00 },
  { name: 'switch on disabled', mask: 0x4F, value: 0x40 },
  { name: 'ready to switch on', mask: 0x6F, value: 0x21 },
  { name: 'switched on', mask: 0x6F, value: 0x23 },
  { name: 'operation enabled', mask: 0x6F, value: 0x27 },
  { name: 'quick stop active', mask: 0x6F, value: 0x07 },
  { name: 'fault reaction active', mask: 0x4F, value: 0x0F },
  { name: 'fault', mask: 0x4F, value: 0x08 },
];

const STATUS = {
  FAULT: 1 << 3,
  WARNING: 1 << 7,
  REMOTE: 1 << 9,
  TARGET_REACHED: 1 << 10,
};

const CONTROL = {
  SHUTDOWN: 0x06,          // -> ready to switch on
  SWITCH_ON: 0x07,         // -> switched on
  ENABLE_OPERATION: 0x0F,  // -> operation enabled
  DISABLE_VOLTAGE: 0x00,   // -> switch on disabled
  QUICK_STOP: 0x02,        // -> quick stop active (from operation enabled)
  FAULT_RESET: 0x80,       // rising edge of bit 7: fault -> switch on disabled
};

const MODE = { PROFILE_VELOCITY: 3, OPEN_LOOP: -1 };

function stateOf(statusword) {
  const state = STATES.find((s) => (statusword & s.mask) === s.value);
  return state ? state.name : 'no CiA 402 state';
}

function describe(statusword) {
  return `0x${statusword.toString(16).toUpperCase().padStart(4, '0')} (${stateOf(statusword)})`;
}

module.exports = { STATUS, CONTROL, MODE, stateOf, describe };
