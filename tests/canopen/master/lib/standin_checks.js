// What the harness must do against the stand-in slave (lib/standin.js), whichever bus joins them:
// the selftest runs it on vcan0 in the guest (the stand-in in a process of its own, killed by
// pid), units.test.js on joined in-memory buses (the stand-in's Device stopped). Each check names
// the exact value it expected.
'use strict';

const { abortCode, hex } = require('./master');
const { check } = require('./check');
const { STANDIN } = require('./standin');

const FRAME_MS = 5000;  // any single answer; generous for a TCG guest

async function checkAgainstStandin(master, node, loseStandin) {
  const bus = master.bus;
  // SDO upload, expedited (4 bytes or less) and segmented (the name).
  const deviceType = await master.read(node, 0x1000);
  check(deviceType === STANDIN.deviceType, `0x1000 read ${hex(deviceType, 8)}, expected ${hex(STANDIN.deviceType, 8)}`);
  const identity = [];
  for (let sub = 1; sub <= 4; ++sub) {
    identity.push(await master.read(node, 0x1018, sub));
  }
  const want = [STANDIN.identity.vendorId, STANDIN.identity.productCode, STANDIN.identity.revisionNumber, node];
  check(identity.join() === want.join(), `0x1018 sub1-4 read ${identity.map((v) => hex(v, 8))}, expected ${want.map((v) => hex(v, 8))}`);
  const name = await master.read(node, 0x1008);
  check(name === STANDIN.deviceName, `0x1008 read ${JSON.stringify(name)} (segmented), expected ${JSON.stringify(STANDIN.deviceName)}`);
  // SDO download, segmented and expedited, read back.
  const text = 'written by the master in segments of seven bytes';
  await master.write(node, 0x2060, 0, text);
  const back = await master.read(node, 0x2060);
  check(back === text, `0x2060 read back ${JSON.stringify(back)} after a segmented download of ${JSON.stringify(text)}`);
  await master.write(node, 0x606C, 0, -5000);
  const velocity = await master.read(node, 0x606C);
  check(velocity === -5000, `0x606C read back ${velocity} after an expedited download of -5000`);
  // Aborts arrive as their codes.
  const unknown = await abortCode(master.readRaw(node, 0x2FFF, 0));
  check(unknown === 0x06020000, `upload of 0x2FFF: abort ${unknown === null ? 'none' : hex(unknown, 8)}, expected 0x06020000`);
  const readOnly = await abortCode(master.write(node, 0x1000, 0, 1));
  check(readOnly === 0x06010002, `download to 0x1000: abort ${readOnly === null ? 'none' : hex(readOnly, 8)}, expected 0x06010002`);
  // NMT start: the heartbeat says operational (0x05).
  const operational = bus.waitFor((f) => f.id === 0x700 + node && f.len === 1 && f.data[0] === 0x05, FRAME_MS, `heartbeat 05 of node ${node} after NMT start`);
  master.nmtStart(node);
  await operational;
  // PDO: the master mirrors the stand-in's TPDO1 from its parameters and decodes it at each SYNC.
  const tpdo = await master.mirrorTpdo(node, 1);
  check(tpdo && tpdo.cobId === 0x180 + node && tpdo.transmissionType === 1 &&
        JSON.stringify(tpdo.entries) === JSON.stringify([[0x6041, 0], [0x606C, 0]]),
  `TPDO1 mirrored as ${JSON.stringify(tpdo)}, expected 0x${(0x180 + node).toString(16)} type 1 [0x6041.0, 0x606C.0]`);
  let pdoEvents = 0;
  const countPdo = (pdo) => { pdoEvents += pdo.cobId === 0x180 + node ? 1 : 0; };
  master.device.pdo.on('pdo', countPdo);
  let [frame] = await master.sync([0x180 + node]);
  check(frame.len === 6 && frame.pdo.get('0x6041.0') === STANDIN.statusword && frame.pdo.get('0x606C.0') === -5000,
    `PDO after SYNC 1: ${frame.data.toString('hex')} decoded ${JSON.stringify([...(frame.pdo || [])])}, expected 6 bytes, 0x6041 = ${STANDIN.statusword}, 0x606C = -5000`);
  await master.write(node, 0x606C, 0, 777);
  [frame] = await master.sync([0x180 + node]);
  check(frame.data.equals(Buffer.from([0x50, 0x02, 0x09, 0x03, 0x00, 0x00])) && master.value(node, 0x606C) === 777,
    `PDO after SYNC 2: ${frame.data.toString('hex')}, expected 500209030000 (0x0250, 777), process image ${master.value(node, 0x606C)}`);
  master.device.pdo.removeListener('pdo', countPdo);
  check(pdoEvents >= 1, 'the library emitted no pdo event for a PDO whose values changed');
  // EMCY: the stand-in sends one when told; the master's EMCY consumer reports it.
  const emergency = master.waitEmergency(node, 0x4310, FRAME_MS);
  await master.write(node, STANDIN.emcyTrigger, 0, 0x4310);
  const em = await emergency;
  check(em.node === node && em.code === 0x4310, `EMCY ${JSON.stringify(em)}, expected node ${node} code 0x4310`);
  // Heartbeat loss: consumer time 3 x the producer's; the stand-in is lost after a heartbeat.
  master.consumeHeartbeat(node, 3 * STANDIN.heartbeatMs);
  await bus.waitFor((f) => f.id === 0x700 + node, FRAME_MS, `a heartbeat of node ${node}`);
  const timeout = master.waitHeartbeatTimeout(FRAME_MS);
  const lost = bus.now();
  await loseStandin();
  const timedOut = await timeout;
  const afterMs = bus.now() - lost;
  check(timedOut === node, `heartbeat timeout reported for node ${timedOut}, expected ${node}`);
  check(afterMs <= 1000, `heartbeat timeout ${afterMs.toFixed(0)} ms after the loss, expected within 1000 ms`);
  return `SDO (expedited, segmented, aborts), NMT, PDO (${pdoEvents} pdo events), EMCY, heartbeat loss after ${afterMs.toFixed(0)} ms`;
}

module.exports = { checkAgainstStandin };
