// Profile velocity to 300 mm/s through a 1.5 N load step, in lockstep (ctest
// canopen.vcan.velocity). The master reads the supported modes (0x6502 bit 2: pv), selects mode 3,
// walks the power state machine (controlword 0x06, 0x07, 0x0F; statusword checked after each),
// commands 300 mm/s (0x60FF = 300000 µm/s) and steps the drive with SYNCs until "target reached"
// (statusword bit 10) with the velocity actual within the velocity window (0x606D, read from the
// drive). The scenario's load_step of 1.5 N at a fixed emulated time then slows the mover (the
// speed falls by more than 1 mm/s), the drive changes its output, and the speed recovers to target
// reached inside the window again. The velocity trace is printed.
'use strict';

const fs = require('fs');
const os = require('os');
const path = require('path');
const { bootLockstepNode, stopNode } = require('./lib/node_under_test');
const { LockstepDrive, STATUS } = require('./lib/drive');
const { MODE, describe } = require('./lib/cia402');
const { hex } = require('./lib/master');
const { check, atEnd, run } = require('./lib/check');

const NODE = 2;
const SYNC_TICKS = 20;          // 2 ms per SYNC at 10 kHz: a common CiA 402 cycle
const TARGET_UM_S = 300000;     // 300 mm/s
const ACCELERATION_UM_S2 = 10000000;  // 10 m/s²: 30 ms from rest to target
const LOAD_AT_S = 0.3;
const LOAD_N = 1.5;
const DIP_UM_S = 1000;          // the load must cost at least 1 mm/s before the drive compensates
const RECOVERY_SYNCS = 250;     // 0.5 s emulated
const HOLD_SYNCS = 150;         // 0.3 s emulated under the load after the recovery
const HOLD_CHECK_MS = 150;      // the last of them all in the window with target reached
const LOAD_DIP_UM_S = 10000;    // the load must show: at least 10 mm/s lost at its lowest (26 seen)
const EXTRA_AMPLITUDE_MV = 10000;  // and carried by at least 10 V more amplitude (22.7 V seen)

function scenarioFile() {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'swum-canopen-'));
  atEnd(() => fs.rmSync(dir, { recursive: true, force: true }));
  const file = path.join(dir, 'load_step.toml');
  fs.writeFileSync(file, `name = "canopen velocity: load step"\n\n[[event]]\nat_s = ${LOAD_AT_S}\ntype = "load_step"\nload_n = ${LOAD_N}\n`);
  return file;
}

// Every 5th sample, and each one around the load (printed at the end, passed or failed).
function printTrace(trace, window, windowTimeMs) {
  const loadMs = LOAD_AT_S * 1000;
  console.log(`velocity trace (emulated ms, statusword, velocity µm/s, amplitude mV, frequency mHz); window ${window} µm/s for ${windowTimeMs} ms; ${LOAD_N} N from ${loadMs} ms`);
  for (const [i, s] of trace.entries()) {
    if (i % 5 === 0 || (s.ms > loadMs - 10 && s.ms < loadMs + 40) || i === trace.length - 1) {
      console.log(`  ${s.ms.toFixed(0).padStart(5)} ${hex(s.statusword)} ${String(s.velocity).padStart(7)} ${String(s.amplitude).padStart(7)} ${s.frequency}`);
    }
  }
}

run('canopen.vcan.velocity', async () => {
  const { master, emu } = await bootLockstepNode(NODE, { syncTicks: SYNC_TICKS, scenario: scenarioFile() });
  const drive = new LockstepDrive(master, NODE, { syncTicks: SYNC_TICKS });
  await drive.configureTpdos({
    3: { entries: [[0x6041, 0], [0x606C, 0]], transmissionType: 1 },
    4: { entries: [[0x2011, 0], [0x2010, 0]], transmissionType: 1 },
  });
  const modes = await master.read(NODE, 0x6502);
  check(modes & (1 << 2), `0x6502 = ${hex(modes, 8)}: profile velocity (bit 2) not supported`);
  await master.write(NODE, 0x6083, 0, ACCELERATION_UM_S2);
  await master.write(NODE, 0x6084, 0, ACCELERATION_UM_S2);
  await master.write(NODE, 0x6060, 0, MODE.PROFILE_VELOCITY);
  const window = await master.read(NODE, 0x606D);
  const windowTimeMs = await master.read(NODE, 0x606E);
  master.nmtStart(NODE);
  await drive.step();
  await drive.step();
  const display = await master.read(NODE, 0x6061);
  check(display === MODE.PROFILE_VELOCITY, `0x6061 = ${display} two SYNCs after 0x6060 = 3`);
  await drive.enable();
  await master.write(NODE, 0x60FF, 0, TARGET_UM_S);

  const trace = [];
  atEnd(() => printTrace(trace, window, windowTimeMs));
  const record = (v) => trace.push({ ms: drive.sampledMs, statusword: v.get('0x6041.0'), velocity: v.get('0x606C.0'),
    amplitude: v.get('0x2011.0'), frequency: v.get('0x2010.0') });
  const reached = (v) => (v.get('0x6041.0') & STATUS.TARGET_REACHED) && Math.abs(v.get('0x606C.0') - TARGET_UM_S) <= window;
  const loadMs = LOAD_AT_S * 1000;
  const stepsToLoad = Math.round((loadMs - drive.sampledMs) / drive.cycleMs) - 1;
  await drive.stepUntil(reached, stepsToLoad, `target reached (300 mm/s within ${window} µm/s) before the load at ${loadMs} ms`, record);
  const firstReachedMs = drive.sampledMs;
  while (drive.sampledMs + drive.cycleMs < loadMs) {
    record(await drive.step());
  }
  const before = trace.slice(-5);  // the last samples before the load acts
  check(before.every((s) => s.statusword & STATUS.TARGET_REACHED), `target reached lost before the load: ${before.map((s) => describe(s.statusword))}`);
  const beforeVelocity = before.reduce((sum, s) => sum + s.velocity, 0) / before.length;

  // The load: the speed dips, then the drive brings it back to the target.
  let dip = null;
  await drive.stepUntil((v) => {
    if (dip === null && v.get('0x606C.0') < beforeVelocity - DIP_UM_S) {
      dip = drive.sampledMs;
    }
    return dip !== null && reached(v);
  }, RECOVERY_SYNCS, `the speed dipping by ${DIP_UM_S} µm/s after the ${LOAD_N} N load and target reached again`, record);
  // Held: the drive carries the load for HOLD_SYNCS more cycles, the last HOLD_CHECK_MS of
  // them all inside the window with target reached, on a higher amplitude than before the load.
  for (let k = 0; k < HOLD_SYNCS; ++k) record(await drive.step());
  const after = trace.slice(-1)[0];
  const lowest = trace.filter((s) => s.ms >= loadMs).reduce((low, s) => (s.velocity < low.velocity ? s : low));
  const drivenBefore = before[before.length - 1];
  check(lowest.velocity < beforeVelocity - LOAD_DIP_UM_S,
    `the ${LOAD_N} N load cost only ${((beforeVelocity - lowest.velocity) / 1000).toFixed(1)} mm/s: did it act?`);
  const held = trace.filter((s) => s.ms > after.ms - HOLD_CHECK_MS);
  const off = held.find((s) => Math.abs(s.velocity - TARGET_UM_S) > window || !(s.statusword & STATUS.TARGET_REACHED));
  check(!off, `not held under ${LOAD_N} N: at ${off && off.ms} ms ${off && off.velocity} µm/s, ${off && describe(off.statusword)}`);
  check(after.amplitude > drivenBefore.amplitude + EXTRA_AMPLITUDE_MV,
    `the speed held under ${LOAD_N} N without more amplitude (${drivenBefore.amplitude} -> ${after.amplitude} mV)`);
  await stopNode(emu);
  return `target reached at ${firstReachedMs} ms, ${(beforeVelocity / 1000).toFixed(1)} mm/s before the load, lowest ${(lowest.velocity / 1000).toFixed(1)} mm/s at ${lowest.ms} ms, target reached again at ${dip === null ? '-' : trace.find((s) => s.ms > lowest.ms && (s.statusword & STATUS.TARGET_REACHED)).ms} ms, held to ${after.ms} ms (amplitude ${drivenBefore.amplitude} -> ${after.amplitude} mV)`;
});
