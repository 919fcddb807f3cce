// TPDO remapping by SDO and the SDO server's aborts (ctest canopen.vcan.remap). In pre-operational
// the master remaps TPDO1 with CiA 301's procedure (7.5.2.35/36): COB-ID bit 31 set, 0x1A00 sub0 =
// 0, entries 0x60410010 (statusword) and 0x606C0020 (velocity actual), sub0 = 2, transmission type
// 1, COB-ID valid; the other TPDOs are invalidated. After NMT start every SYNC brings the PDO on
// 0x180+N with the new 6-byte layout, decoded by the master's mirrored RPDO. Then each bad
// request gets its abort code (CiA 301 7.2.4.3.17) and 0x2050 (SDO aborts sent) grows by exactly
// their number.
'use strict';

const { abortCode, hex } = require('./lib/master');
const { bootLockstepNode, stopNode } = require('./lib/node_under_test');
const { stateOf, describe } = require('./lib/cia402');
const { check, run } = require('./lib/check');

const NODE = 3;
const SYNCS = 5;

const codeText = (code) => (code === null ? 'no abort' : hex(code, 8));

run('canopen.vcan.remap', async () => {
  const { bus, master, emu } = await bootLockstepNode(NODE);
  const abortsBefore = await master.read(NODE, 0x2050);
  let aborts = 0;
  const expectAbort = async (what, transfer, ...codes) => {
    const code = await abortCode(transfer);
    check(codes.includes(code), `${what}: ${codeText(code)}, expected ${codes.map((c) => hex(c, 8)).join(' or ')}`);
    aborts += 1;
    return code;
  };

  // TPDO1 remapped; a mapping entry of an object that cannot be mapped (0x2050: PDO "no") is
  // refused with the mapping open, as CiA 301 asks (0x06040041).
  const remapped = await master.configureTpdo(NODE, 1, {
    entries: [[0x6041, 0], [0x606C, 0]],
    transmissionType: 1,
    beforeEntries: (map) => expectAbort('mapping 0x2050 into TPDO1', master.writeRaw(NODE, map, 1, [0x20, 0x00, 0x50, 0x20]), 0x06040041),
  });
  const mapping = [];
  for (let sub = 0; sub <= 2; ++sub) {
    mapping.push(await master.read(NODE, 0x1A00, sub));
  }
  check(mapping.join() === [2, 0x60410010, 0x606C0020].join(), `0x1A00 sub0-2 read back ${mapping.map((v) => hex(v, 8))}`);
  check(remapped.cobId === 0x180 + NODE && remapped.transmissionType === 1,
    `TPDO1 after the remap: COB-ID ${hex(remapped.cobId, 3)}, type ${remapped.transmissionType}`);
  for (const n of [2, 3, 4]) {
    await master.configureTpdo(NODE, n, { enabled: false });
  }
  const cobIds = [remapped.cobId];

  master.nmtStart(NODE);
  for (let k = 1; k <= SYNCS; ++k) {
    const [frame] = await master.sync(cobIds);
    const statusword = frame.data.readUInt16LE(0);
    const velocity = frame.data.readInt32LE(2);
    check(frame.len === 6, `SYNC ${k}: PDO ${frame.data.toString('hex')} has ${frame.len} bytes, the new layout has 6`);
    check(frame.pdo.get('0x6041.0') === statusword && frame.pdo.get('0x606C.0') === velocity,
      `SYNC ${k}: the master decoded ${JSON.stringify([...frame.pdo])} from ${frame.data.toString('hex')}`);
    check(stateOf(statusword) === 'switch on disabled' && velocity === 0,
      `SYNC ${k}: statusword ${describe(statusword)}, velocity ${velocity} µm/s: expected switch on disabled at rest`);
  }

  // Bad requests, each with its abort.
  await expectAbort('upload of 0x2FFF (no such object)', master.readRaw(NODE, 0x2FFF, 0), 0x06020000);
  await expectAbort('upload of 0x1018 sub9 (no such sub-index)', master.readRaw(NODE, 0x1018, 9), 0x06090011);
  await expectAbort('4 bytes to 0x6040 (UNSIGNED16)', master.writeRaw(NODE, 0x6040, 0, [0x06, 0, 0, 0]), 0x06070012);
  await expectAbort('1 byte to 0x6040 (UNSIGNED16)', master.writeRaw(NODE, 0x6040, 0, [0x06]), 0x06070013);
  await expectAbort('download to 0x6041 (read-only)', master.write(NODE, 0x6041, 0, 0x0006), 0x06010002);
  await expectAbort('download to 0x1000 (read-only)', master.write(NODE, 0x1000, 0, 0), 0x06010002);
  await expectAbort('0x60FF = 2000000 (range -1000000..1000000)', master.write(NODE, 0x60FF, 0, 2000000), 0x06090031, 0x06090030);
  await expectAbort('0x60FF = -2000000 (range -1000000..1000000)', master.write(NODE, 0x60FF, 0, -2000000), 0x06090032, 0x06090030);
  await expectAbort('0x6060 = 7 (modes 0, 3, -1)', master.write(NODE, 0x6060, 0, 7), 0x06090030, 0x06090031);
  await expectAbort('0x6083 = 0 (range 1..100000000)', master.write(NODE, 0x6083, 0, 0), 0x06090032, 0x06090030);

  // Malformed frames on the bus itself: an NMT command of one byte (counted in 0x2052), an RPDO
  // shorter than its mapping (EMCY 0x8210, counted in 0x2051), remote frames on RPDO1's identifier
  // with a DLC that fits its mapping (not a PDO: the controlword stays). The node answers on.
  await master.write(NODE, 0x6040, 0, 0x0006);
  const malformedBefore = await master.read(NODE, 0x2052);
  const lengthBefore = await master.read(NODE, 0x2051);
  bus.send({ id: 0x000, data: Buffer.from([0x01]) });
  const since = bus.now();
  bus.send({ id: 0x200 + NODE, data: Buffer.from([0x0F]) });
  await master.waitEmergency(NODE, 0x8210, 5000, since);
  bus.send({ id: 0x200 + NODE, rtr: true, len: 2 });
  bus.send({ id: 0x200 + NODE, rtr: true, len: 8 });
  const malformedAfter = await master.read(NODE, 0x2052);
  const lengthAfter = await master.read(NODE, 0x2051);
  check(malformedAfter - malformedBefore === 1, `0x2052 went ${malformedBefore} -> ${malformedAfter} for one NMT frame of one byte`);
  check(lengthAfter - lengthBefore === 1, `0x2051 went ${lengthBefore} -> ${lengthAfter} for one short RPDO`);
  const controlword = await master.read(NODE, 0x6040);
  check(controlword === 0x0006, `0x6040 = ${hex(controlword, 4)} after a short RPDO and two remote frames, expected 0x0006`);

  // Nothing refused was stored, and the PDO still has its layout.
  const target = await master.read(NODE, 0x60FF);
  check(target === 0, `0x60FF = ${target} after refused downloads, expected 0`);
  const [frame] = await master.sync(cobIds);
  check(frame.len === 6, `after the aborts the PDO has ${frame.len} bytes`);
  const abortsAfter = await master.read(NODE, 0x2050);
  check(abortsAfter - abortsBefore === aborts, `0x2050 went ${abortsBefore} -> ${abortsAfter}, the master got ${aborts} aborts`);
  await stopNode(emu);
  return `TPDO1 remapped (6 bytes at each of ${SYNCS + 1} SYNCs), ${aborts} aborts with their codes, 0x2050 ${abortsBefore} -> ${abortsAfter}`;
});
