// A stand-in CANopen slave for the harness's selftest (selftest.js): an npm canopen Device with a
// small dictionary built with the library's setters, on its own bus (its own can_bridge.py), in
// a process of its own so that the selftest can kill it by pid as two_nodes.test.js kills a
// swum-emu. It proves the bridge and the master (SDO, NMT, heartbeat, PDO, EMCY) end to end
// before, and independently of, swum-emu's CANopen profile.
//
// usage: node lib/standin.js IFACE NODE    (runs until killed or its stdin ends)
'use strict';

const { Device, Eds, DataType, ObjectType, AccessType } = require('./canopen');
const { Bus } = require('./bus');

const STANDIN = {
  deviceType: 0x00020192,
  deviceName: 'swum-hil stand-in slave (npm canopen), the master harness selftest',
  identity: { vendorId: 0, productCode: 0x5357554D, revisionNumber: 0x00010002, serialNumber: 0 },
  statusword: 0x0250,
  velocity: -1234,
  text: 'initial',
  heartbeatMs: 100,
  emcyTrigger: 0x2070,  // a write of a code here makes the stand-in send that EMCY
};

function variable(eds, index, parameterName, dataType, accessType, defaultValue, pdoMapping = false) {
  return eds.addEntry(index, { parameterName, objectType: ObjectType.VAR, dataType, accessType, defaultValue, pdoMapping });
}

// The stand-in's dictionary; the selftest's master loads the same one as the slave's EDS.
function standinEds(node) {
  const eds = new Eds();
  eds.getEntry(0x1000).value = STANDIN.deviceType;  // new Eds() has 0x1000, 0x1001 and 0x1018
  eds.setDeviceName(STANDIN.deviceName);
  eds.setIdentity({ ...STANDIN.identity, serialNumber: node });
  eds.setHeartbeatProducerTime(STANDIN.heartbeatMs);
  eds.setEmcyCobId(0x80 + node);  // bit 31 clear: valid (the library's setEmcyValid(true) would set it)
  eds.setSyncCobId(0x80);
  eds.addSdoServerParameter(0x7F, 0x580 + node, 0x600 + node);
  const statusword = variable(eds, 0x6041, 'Statusword', DataType.UNSIGNED16, AccessType.READ_WRITE, STANDIN.statusword, true);
  const velocity = variable(eds, 0x606C, 'Velocity actual value', DataType.INTEGER32, AccessType.READ_WRITE, STANDIN.velocity, true);
  variable(eds, 0x2060, 'A string for segmented downloads', DataType.VISIBLE_STRING, AccessType.READ_WRITE, STANDIN.text);
  variable(eds, STANDIN.emcyTrigger, 'EMCY trigger', DataType.UNSIGNED16, AccessType.READ_WRITE, 0);
  eds.addTransmitPdo({ cobId: 0x180 + node, transmissionType: 1, dataObjects: [statusword, velocity] });
  return eds;
}

async function main(iface, node) {
  const bus = await Bus.open(iface);
  const device = new Device({ id: node, eds: standinEds(node), enableLss: false });
  bus.attach(device);
  device.eds.getEntry(STANDIN.emcyTrigger).on('update', (entry) => device.emcy.write(entry.value));
  device.start();
  bus.send({ id: 0x700 + node, data: Buffer.from([0]) });  // boot-up (the library sends none)
  process.stdin.resume();
  process.stdin.on('end', () => process.exit(0));
}

if (require.main === module) {
  const [iface, node] = [process.argv[2], Number(process.argv[3])];
  if (!iface || !(node >= 1 && node <= 127)) {
    console.error('usage: node lib/standin.js IFACE NODE');
    process.exit(2);
  }
  main(iface, node).catch((e) => {
    console.error(`standin: ${e.message}`);
    process.exit(1);
  });
}

module.exports = { standinEds, STANDIN };
