// A CiA 402 drive in lockstep as the master runs it: its synchronous TPDOs configured by SDO, one
// SYNC per control cycle (the emulator advances --sync-ticks ticks per SYNC and answers each with
// the TPDOs sampled at it), the controlword written by SDO and the state machine walked with the
// statusword checked after each word (docs/canopen.md; CiA 402 6.3). Emulated time is counted
// in SYNCs: syncTicks / tickHz seconds each.
'use strict';

const { tpdoCobId, hex } = require('./master');
const { STATUS, CONTROL, stateOf, describe } = require('./cia402');
const { check } = require('./check');

const STATE_STEPS = 5;  // a state change shows within a few cycles (one cycle of delay, CiA 402)

class LockstepDrive {
  constructor(master, node, { syncTicks = 10, tickHz = 10000 } = {}) {
    this.master = master;
    this.node = node;
    this.cycleMs = (1000 * syncTicks) / tickHz;
    this.cobIds = [];   // the synchronous TPDOs every SYNC must bring
    this.steps = 0;     // SYNCs sent
    this.last = null;   // the values of the last SYNC's TPDOs
  }

  // Emulated milliseconds since the start: the cycles the SYNCs sent so far have run.
  get emulatedMs() {
    return this.steps * this.cycleMs;
  }

  // When the last SYNC's TPDOs were sampled: at the SYNC, before its cycle runs (docs/protocols.md,
  // "Lockstep over CAN"), so one cycle before emulatedMs.
  get sampledMs() {
    return Math.max(0, this.steps - 1) * this.cycleMs;
  }

  // Configures the node's TPDOs 1-4 (CiA 301 procedure, lib/master.js): { n: { entries,
  // transmissionType } } maps TPDO n, n: null (or absent) disables it, so that only the given
  // synchronous TPDOs are on the bus. Must run in pre-operational (before NMT start).
  async configureTpdos(tpdos) {
    this.cobIds = [];
    for (let n = 1; n <= 4; ++n) {
      const want = tpdos[n];
      if (!want) {
        await this.master.configureTpdo(this.node, n, { enabled: false });
        continue;
      }
      const got = await this.master.configureTpdo(this.node, n, want);
      check(got && JSON.stringify(got.entries) === JSON.stringify(want.entries || got.entries) &&
            (want.transmissionType === undefined || got.transmissionType === want.transmissionType),
      `TPDO${n} of node ${this.node} read back as ${JSON.stringify(got)} after configuring ${JSON.stringify(want)}`);
      if (got.transmissionType >= 1 && got.transmissionType <= 240) {
        this.cobIds.push(got.cobId);
      }
    }
    return this.cobIds;
  }

  // One SYNC: resolves with the values its synchronous TPDOs carried (Map "0xIIII.s" -> value).
  async step() {
    const frames = await this.master.sync(this.cobIds);
    this.steps += 1;
    const values = new Map();
    for (const frame of frames) {
      for (const [key, value] of frame.pdo || []) {
        values.set(key, value);
      }
    }
    this.last = values;
    return values;
  }

  // SYNCs until predicate(values) holds; fails after maxSteps naming what it waited for.
  async stepUntil(predicate, maxSteps, what, onStep = null) {
    for (let i = 0; i < maxSteps; ++i) {
      const values = await this.step();
      if (onStep) {
        onStep(values);
      }
      if (predicate(values)) {
        return values;
      }
    }
    throw new Error(`${what}: not seen within ${maxSteps} SYNCs (${this.emulatedMs} ms emulated); last TPDO values ${this.describeLast()}`);
  }

  describeLast() {
    if (!this.last) {
      return 'none';
    }
    return [...this.last].map(([key, value]) => `${key}=${key === '0x6041.0' ? describe(value) : value}`).join(' ');
  }

  // Writes the controlword, steps until the statusword (from the TPDO that maps 0x6041) shows
  // the state, then reads 0x6041 by SDO as well: both must say it. Returns the statusword.
  async command(controlword, state) {
    await this.master.write(this.node, 0x6040, 0, controlword);
    await this.stepUntil((v) => stateOf(v.get('0x6041.0')) === state, STATE_STEPS,
      `controlword ${hex(controlword)} -> ${state}`);
    const statusword = await this.master.read(this.node, 0x6041);
    check(stateOf(statusword) === state, `controlword ${hex(controlword)}: statusword read by SDO ${describe(statusword)}, the TPDO said ${state}`);
    return statusword;
  }

  // Shutdown, switch on, enable operation (CiA 402 transitions 2, 3, 4).
  async enable() {
    await this.command(CONTROL.SHUTDOWN, 'ready to switch on');
    await this.command(CONTROL.SWITCH_ON, 'switched on');
    return this.command(CONTROL.ENABLE_OPERATION, 'operation enabled');
  }
}

// TPDO3 of the predefined set: statusword and velocity actual, sent at every SYNC.
const STATUS_AND_VELOCITY = { 3: { entries: [[0x6041, 0], [0x606C, 0]], transmissionType: 1 } };

module.exports = { LockstepDrive, STATUS_AND_VELOCITY, STATUS, CONTROL, tpdoCobId };
