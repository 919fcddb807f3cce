// Two drives and the master on one bus, on the wall clock (ctest canopen.vcan.two_nodes): swum-emu
// as nodes 2 and 3 on vcan0 (no --clock external: the heartbeat is a wall-clock service). The
// master sets each producer heartbeat time 0x1017 to 200 ms by SDO, consumes both heartbeats
// (0x1016, 1500 ms: the TCG guest stalls a node for some 300 ms beside the host's tests), and one NMT broadcast start (node 0) makes both operational (each heartbeat
// says 05). Node 3 killed by pid (SIGKILL): the master's heartbeat consumer reports a timeout for
// node 3, and only node 3, within 3 s, while node 2 keeps sending its heartbeat.
'use strict';

const { openMaster, stopNode } = require('./lib/node_under_test');
const { Emulator } = require('./lib/emulator');
const { check, run } = require('./lib/check');

const NODES = [2, 3];
const KILLED = 3;
const KEPT = 2;
const PRODUCER_MS = 200;
const CONSUMER_MS = 1500;  // the TCG guest, beside the host's tests, stalls a node for some 300 ms
const DETECT_MS = 3000;
const FRAME_MS = 10000;

const heartbeat = (node, state) => (f) => f.id === 0x700 + node && !f.extended && f.len === 1 && (state === undefined || f.data[0] === state);

run('canopen.vcan.two_nodes', async () => {
  const { bus, master } = await openMaster(NODES);
  const emus = {};
  for (const node of NODES) {
    // 1 kHz: the model is not what this test is about, and two 10 kHz loops on the wall clock
    // would starve a TCG guest (docs/vcan.md) and with it the heartbeat threads.
    emus[node] = await Emulator.start(bus, node, { lockstep: false, args: ['--tick-hz', '1000'] });
  }
  for (const node of NODES) {
    await master.write(node, 0x1017, 0, PRODUCER_MS);
    const back = await master.read(node, 0x1017);
    check(back === PRODUCER_MS, `node ${node}: 0x1017 read back ${back}, expected ${PRODUCER_MS}`);
  }
  // Consumers from here on: the first heartbeat of each arms its timer.
  for (const node of NODES) {
    master.consumeHeartbeat(node, CONSUMER_MS);
  }
  const operational = NODES.map((node) => bus.waitFor(heartbeat(node, 0x05), FRAME_MS, `heartbeat 05 of node ${node} after the broadcast start`));
  master.nmtStart(0);
  await Promise.all(operational);
  // Both are heard at the producer's rate before the kill: ten heartbeats of each.
  for (const node of NODES) {
    for (let i = 0; i < 10; ++i) {
      await bus.waitFor(heartbeat(node, 0x05), FRAME_MS, `heartbeat ${i + 1} of node ${node}`);
    }
  }
  check(master.heartbeatTimeouts.length === 0, `heartbeat timeouts before any node died: ${JSON.stringify(master.heartbeatTimeouts)}`);

  const timeout = master.waitHeartbeatTimeout(FRAME_MS);
  await bus.waitFor(heartbeat(KILLED), FRAME_MS, `a heartbeat of node ${KILLED}`);
  const killedAt = bus.now();
  const how = await emus[KILLED].kill();
  check(how.signal === 'SIGKILL', `node ${KILLED} ended by ${how.signal || how.code}, not SIGKILL`);
  const node = await timeout;
  const afterMs = bus.now() - killedAt;
  check(node === KILLED, `the master reported a heartbeat timeout for node ${node}, expected node ${KILLED}`);
  check(afterMs <= DETECT_MS, `the timeout came ${afterMs.toFixed(0)} ms after the kill, expected within ${DETECT_MS} ms`);
  // The other keeps sending, operational, and is never reported.
  const keptAt = bus.now();
  for (let i = 0; i < 5; ++i) {
    await bus.waitFor(heartbeat(KEPT, 0x05), FRAME_MS, `heartbeat ${i + 1} of node ${KEPT} after node ${KILLED} died`);
  }
  const sent = await master.read(KEPT, 0x1017);
  check(sent === PRODUCER_MS, `node ${KEPT} answers SDO after the kill: 0x1017 = ${sent}`);
  const reported = master.heartbeatTimeouts.map((t) => t.node);
  check(reported.length === 1 && reported[0] === KILLED, `heartbeat timeouts reported for nodes ${reported}, expected only ${KILLED}`);
  await stopNode(emus[KEPT]);
  return `broadcast start reached nodes ${NODES}; node ${KILLED} killed, timeout reported after ${afterMs.toFixed(0)} ms; node ${KEPT} kept sending for ${(bus.now() - keptAt).toFixed(0)} ms`;
});
