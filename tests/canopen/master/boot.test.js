// swum-emu boots as a CiA 301 slave (ctest canopen.vcan.boot): its boot-up frame (0x700+N, 00),
// the identity 0x1018 sub1-4 (docs/canopen.md: vendor 0, product "SWUM", revision major << 16 |
// minor of the project version, serial = node id), the device name 0x1008 read by a segmented
// upload (the server's initiate response has e = 0, s = 1 and the name's length) and equal to the
// EDS default, the hardware version 0x1009 equal to its EDS default, and device type 0x1000 =
// 0x00020192 (CiA 402 drive, profile 402). Then SIGTERM ends it with status 0.
'use strict';

const fs = require('fs');
const path = require('path');
const { hex } = require('./lib/master');
const { bootLockstepNode, stopNode } = require('./lib/node_under_test');
const { sourceDir } = require('./lib/emulator');
const { check, run } = require('./lib/check');

const NODE = 4;

function projectRevision() {
  const cmake = fs.readFileSync(path.join(sourceDir(), 'CMakeLists.txt'), 'utf8');
  const m = /project\(\s*\S+\s+VERSION\s+(\d+)\.(\d+)/.exec(cmake);
  check(m, 'no project(... VERSION x.y) in CMakeLists.txt');
  return ((Number(m[1]) << 16) | Number(m[2])) >>> 0;
}

run('canopen.vcan.boot', async () => {
  const { bus, master, emu } = await bootLockstepNode(NODE);
  const identity = [];
  for (let sub = 1; sub <= 4; ++sub) {
    identity.push(await master.read(NODE, 0x1018, sub));
  }
  const want = [0, 0x5357554D, projectRevision(), NODE];
  check(identity.join() === want.join(), `0x1018 sub1-4 = ${identity.map((v) => hex(v, 8))}, expected ${want.map((v) => hex(v, 8))}`);
  const highest = await master.read(NODE, 0x1018, 0);
  check(highest === 4, `0x1018 sub0 = ${highest}, expected 4`);

  const responses = [];
  const unlisten = bus.onFrame((f) => { if (f.id === 0x580 + NODE) responses.push(f.data); });
  const name = await master.read(NODE, 0x1008);
  unlisten();
  const edsName = master.slaveObject(0x1008).defaultValue;
  check(name === edsName, `0x1008 = ${JSON.stringify(name)}, the EDS default is ${JSON.stringify(edsName)}`);
  const initiate = responses[0];
  check(name.length > 4 && initiate && (initiate[0] & 0xE3) === 0x41 && initiate.readUInt32LE(4) === name.length,
    `0x1008 not uploaded in segments: initiate response ${initiate ? initiate.toString('hex') : 'none'} for ${name.length} bytes`);
  check(responses.length === 1 + Math.ceil(name.length / 7), `0x1008: ${responses.length} server frames for ${name.length} bytes, expected ${1 + Math.ceil(name.length / 7)}`);

  const hardware = await master.read(NODE, 0x1009);
  const edsHardware = master.slaveObject(0x1009).defaultValue;
  check(hardware === edsHardware, `0x1009 = ${JSON.stringify(hardware)}, the EDS default is ${JSON.stringify(edsHardware)}`);
  const deviceType = await master.read(NODE, 0x1000);
  check(deviceType === 0x00020192, `0x1000 = ${hex(deviceType, 8)}, expected 0x00020192`);
  await stopNode(emu);
  return `boot-up, identity ${want.map((v) => hex(v, 8)).join(' ')}, name "${name}" in ${responses.length} frames, device type 0x00020192`;
});
