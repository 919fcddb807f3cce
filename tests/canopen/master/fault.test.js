// An injected over-temperature as a CiA 402 fault, in lockstep (ctest canopen.vcan.fault). The
// drive runs in profile velocity (operation enabled, 100 mm/s) when the scenario's
// over_temperature event trips it at a fixed emulated time; the master's EMCY consumer gets EMCY
// 0x4310 (docs/canopen.md, "Faults and EMCY codes") from 0x080+N with a non-zero error register,
// the statusword shows the fault (bit 3, state fault), 0x603F = 0x4310, 0x1001 is non-zero and
// the newest entry of 0x1003 has code 0x4310. After the scenario clears the condition, a rising
// edge of controlword bit 7 returns the drive to switch on disabled, with the error reset EMCY
// (code 0000) and 0x1001 = 0 that CiA 301 7.2.7.1 asks for when the error is gone.
'use strict';

const fs = require('fs');
const os = require('os');
const path = require('path');
const { bootLockstepNode, stopNode } = require('./lib/node_under_test');
const { LockstepDrive, STATUS_AND_VELOCITY, STATUS, CONTROL } = require('./lib/drive');
const { MODE, stateOf, describe } = require('./lib/cia402');
const { hex } = require('./lib/master');
const { check, atEnd, run } = require('./lib/check');

const NODE = 6;
const FAULT_AT_MS = 50;
const CLEAR_AT_MS = 70;
const OVER_TEMPERATURE = 0x4310;
const LATE_CYCLES = 5;  // the EMCY comes within a few cycles of the event
const REACTION_CYCLES = 100;  // the fault reaction (a stop at 0x6085 from 100 mm/s: 10 ms) ends in fault

function scenarioFile() {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'swum-canopen-'));
  atEnd(() => fs.rmSync(dir, { recursive: true, force: true }));
  const file = path.join(dir, 'over_temperature.toml');
  fs.writeFileSync(file, [
    'name = "canopen fault: over-temperature"', '',
    '[[event]]', `at_s = ${FAULT_AT_MS / 1000}`, 'type = "over_temperature"', '',
    '[[event]]', `at_s = ${CLEAR_AT_MS / 1000}`, 'type = "clear"', 'fault = "over_temperature"', ''].join('\n'));
  return file;
}

run('canopen.vcan.fault', async () => {
  const { bus, master, emu } = await bootLockstepNode(NODE, { scenario: scenarioFile() });
  const drive = new LockstepDrive(master, NODE);
  await drive.configureTpdos(STATUS_AND_VELOCITY);
  const emcyCobId = await master.read(NODE, 0x1014);
  check(emcyCobId === 0x80 + NODE, `0x1014 = ${hex(emcyCobId, 8)}, expected ${hex(0x80 + NODE, 8)}`);
  await master.write(NODE, 0x6060, 0, MODE.PROFILE_VELOCITY);
  master.nmtStart(NODE);
  await drive.enable();
  await master.write(NODE, 0x60FF, 0, 100000);

  const started = bus.now();
  const emergency = () => master.emergencies.find((e) => e.node === NODE && e.code === OVER_TEMPERATURE && e.at >= started);
  await drive.stepUntil(() => emergency(), FAULT_AT_MS / drive.cycleMs + LATE_CYCLES,
    `EMCY ${hex(OVER_TEMPERATURE)} from node ${NODE} (EMCYs: ${master.describeEmergencies()})`);
  const em = emergency();
  const emcyMs = drive.emulatedMs;
  check(emcyMs >= FAULT_AT_MS, `EMCY ${hex(OVER_TEMPERATURE)} after ${drive.emulatedMs} ms, before the event at ${FAULT_AT_MS} ms`);
  check(em.register & 0x01, `EMCY error register ${hex(em.register, 2)}: the generic error bit (CiA 301 7.5.2.2) is not set`);
  const faulted = await drive.stepUntil((v) => stateOf(v.get('0x6041.0')) === 'fault', REACTION_CYCLES, 'statusword: fault');
  check(faulted.get('0x6041.0') & STATUS.FAULT, `statusword ${describe(faulted.get('0x6041.0'))} without bit 3`);
  const errorCode = await master.read(NODE, 0x603F);
  check(errorCode === OVER_TEMPERATURE, `0x603F = ${hex(errorCode)}, expected ${hex(OVER_TEMPERATURE)}`);
  const errorRegister = await master.read(NODE, 0x1001);
  check(errorRegister !== 0 && errorRegister === em.register, `0x1001 = ${hex(errorRegister, 2)}, the EMCY said ${hex(em.register, 2)}`);
  const errors = await master.read(NODE, 0x1003, 0);
  const newest = await master.read(NODE, 0x1003, 1);
  check(errors >= 1 && (newest & 0xFFFF) === OVER_TEMPERATURE, `0x1003: ${errors} errors, newest ${hex(newest, 8)}; expected code ${hex(OVER_TEMPERATURE)}`);

  // The condition ends with the scenario's clear; then the fault reset.
  while (drive.emulatedMs <= CLEAR_AT_MS) {
    await drive.step();
  }
  const reset = master.waitEmergency(NODE, 0x0000, 20000);
  await drive.command(CONTROL.FAULT_RESET, 'switch on disabled');
  const cleared = await reset;
  const registerAfter = await master.read(NODE, 0x1001);
  check(registerAfter === 0, `0x1001 = ${hex(registerAfter, 2)} after the fault reset, expected 0 (error reset EMCY register ${hex(cleared.register, 2)})`);
  await stopNode(emu);
  return `EMCY ${hex(OVER_TEMPERATURE)} (register ${hex(em.register, 2)}) by ${emcyMs} ms for the event at ${FAULT_AT_MS} ms, fault bit, 0x603F, 0x1001, 0x1003 sub1 ${hex(newest, 8)}; fault reset -> switch on disabled, error reset EMCY`;
});
