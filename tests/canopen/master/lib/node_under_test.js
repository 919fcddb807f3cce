// The start of every swum-emu scenario: the bus (vcan0), the master with the slave's EDS
// (SWUM_SOURCE_DIR/config/swum.eds) and an SDO channel, EMCY and optional heartbeat consumer per
// node, and swum-emu started as each node and seen booting. Everything is stopped at the end of
// the script (lib/check.js), whatever happened.
'use strict';

const path = require('path');
const { Bus } = require('./bus');
const { Master } = require('./master');
const { Emulator, sourceDir } = require('./emulator');
const { check, atEnd } = require('./check');

const IFACE = 'vcan0';

function swumEds() {
  return path.join(sourceDir(), 'config', 'swum.eds');
}

// A bus and a started master for the given nodes (none started yet).
async function openMaster(nodes, { heartbeatConsumerMs = 0 } = {}) {
  const bus = await Bus.open(IFACE);
  atEnd(() => bus.close());
  const master = new Master(bus, swumEds());
  for (const node of nodes) {
    master.addNode(node, { heartbeatConsumerMs });
  }
  master.start();
  atEnd(() => master.stop());
  return { bus, master };
}

// One node in lockstep (options: lib/emulator.js), its master and bus.
async function bootLockstepNode(node, options = {}) {
  const { bus, master } = await openMaster([node]);
  const emu = await Emulator.start(bus, node, { lockstep: true, ...options });
  return { bus, master, emu };
}

// SIGTERM, the exit, and a clean status: a node that crashes or hangs on the way out fails.
async function stopNode(emu) {
  const result = await emu.stop();
  check(result.code === 0, `swum-emu (node ${emu.node}) exited with ${result.signal || result.code} on SIGTERM: ${result.stderr.trim().split('\n').slice(-3).join(' | ')}`);
  return result;
}

module.exports = { IFACE, swumEds, openMaster, bootLockstepNode, stopNode };
