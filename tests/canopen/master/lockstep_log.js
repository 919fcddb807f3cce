// A fixed master sequence against swum-emu in lockstep, recorded by swum-emu itself
// (--record-can FILE: candump's log format on emulated time). determinism.test.js runs it twice,
// once under a CPU hog on every core, and compares the files byte for byte: the same master
// script gives the same bus traffic, whatever the host's timing.
//
// usage: node lockstep_log.js FILE
// The sequence: TPDO3 (statusword, velocity actual) and TPDO4 (amplitude, frequency actual)
// synchronous, TPDO1/2 off; mode 3, profile acceleration; NMT start; controlword 6, 7, 15; 200
// mm/s for 25 SYNCs, 250 mm/s for 25 more, an SDO read of 0x606C every 10 SYNCs; SIGTERM.
'use strict';

const { bootLockstepNode, stopNode } = require('./lib/node_under_test');
const { LockstepDrive } = require('./lib/drive');
const { MODE } = require('./lib/cia402');
const { check, run } = require('./lib/check');

const NODE = 7;
const SYNCS = 50;

run('lockstep_log', async () => {
  const file = process.argv[2];
  check(file, 'usage: node lockstep_log.js FILE');
  const { master, emu } = await bootLockstepNode(NODE, { recordCan: file, syncTicks: 10 });
  const drive = new LockstepDrive(master, NODE, { syncTicks: 10 });
  await drive.configureTpdos({
    3: { entries: [[0x6041, 0], [0x606C, 0]], transmissionType: 1 },
    4: { entries: [[0x2011, 0], [0x2010, 0]], transmissionType: 1 },
  });
  await master.write(NODE, 0x6060, 0, MODE.PROFILE_VELOCITY);
  await master.write(NODE, 0x6083, 0, 5000000);
  master.nmtStart(NODE);
  await drive.enable();
  const enabledAt = drive.steps;
  const velocities = [];
  for (let k = 0; k < SYNCS; ++k) {
    if (k === 0 || k === SYNCS / 2) {
      await master.write(NODE, 0x60FF, 0, k === 0 ? 200000 : 250000);
    }
    const values = await drive.step();
    if (k % 10 === 9) {
      velocities.push(await master.read(NODE, 0x606C));
    }
    check(values.has('0x606C.0'), `SYNC ${drive.steps}: no velocity in the TPDOs`);
  }
  await stopNode(emu);
  return `${drive.steps} SYNCs (enabled after ${enabledAt}), velocity ${velocities.join(' ')} µm/s`;
});
