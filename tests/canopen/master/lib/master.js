// The independent CANopen master of the guest-tier tests: an npm canopen Device (node id 0x7F)
// whose own object dictionary is built with the library's Eds setters, as a CANopen manager is
// configured (CiA 301 7.4.8 and 7.5.2): an SDO client channel per slave (0x1280+: 0x600+N out,
// 0x580+N in), an EMCY consumer entry per slave (0x1028: 0x080+N), heartbeat consumer entries
// (0x1016), the SYNC producer (0x1005 bit 30, no cycle period: one SYNC per sync() call, so a test
// steps a lockstep emulator one cycle at a time) and local RPDOs that mirror the slaves' TPDOs
// (0x1400/0x1600 pointing at local copies of the mapped objects), which the library's Pdo module
// decodes. The slaves' data types come from their EDS (config/swum.eds), loaded with the
// library's Eds: nothing here knows an object's type.
'use strict';

const { Device, Eds, DataType, ObjectType, SdoError } = require('./canopen');

const MASTER_ID = 0x7F;   // the library's Device needs an id (1-127); no swum node uses 127
const SDO_TIMEOUT_MS = 5000;  // the library's default (30 ms) is far below a TCG guest's latency
const LOCAL_OBJECTS_START = 0x2000;  // where mapRemoteNode() puts remote objects, too

// Bits of a mapped object for a PDO mapping entry (CiA 301 7.4.7.2: index << 16 | sub << 8 |
// length in bits), from its data type.
const TYPE_BITS = {
  [DataType.BOOLEAN]: 8, [DataType.INTEGER8]: 8, [DataType.UNSIGNED8]: 8,
  [DataType.INTEGER16]: 16, [DataType.UNSIGNED16]: 16,
  [DataType.INTEGER24]: 24, [DataType.UNSIGNED24]: 24,
  [DataType.INTEGER32]: 32, [DataType.UNSIGNED32]: 32, [DataType.REAL32]: 32,
  [DataType.INTEGER40]: 40, [DataType.UNSIGNED40]: 40,
  [DataType.INTEGER48]: 48, [DataType.UNSIGNED48]: 48,
  [DataType.INTEGER56]: 56, [DataType.UNSIGNED56]: 56,
  [DataType.INTEGER64]: 64, [DataType.UNSIGNED64]: 64, [DataType.REAL64]: 64,
};

// Default COB-IDs of the predefined connection set (CiA 301 7.3.5).
const tpdoCobId = (n, node) => 0x180 + 0x100 * (n - 1) + node;
const rpdoCobId = (n, node) => 0x200 + 0x100 * (n - 1) + node;

const hex = (value, digits = 4) => '0x' + value.toString(16).toUpperCase().padStart(digits, '0');
const objectName = (index, sub) => `${hex(index)}.${sub}`;

// An SDO abort code from a rejected transfer, or null when the transfer succeeded. Errors that
// are not aborts (timeouts of the bus, the library's own errors) are rethrown.
async function abortCode(transfer) {
  try {
    await transfer;
    return null;
  } catch (e) {
    if (e instanceof SdoError) {
      return e.code >>> 0;
    }
    throw e;
  }
}

class Master {
  // bus: a lib/bus.js Bus; slaveEds: the slaves' EDS (a path or an Eds).
  constructor(bus, slaveEds, { id = MASTER_ID, sdoTimeoutMs = SDO_TIMEOUT_MS } = {}) {
    this.bus = bus;
    this.slaveEds = slaveEds instanceof Eds ? slaveEds : Eds.fromFile(slaveEds);
    this.sdoTimeoutMs = sdoTimeoutMs;
    this.device = new Device({ id, eds: new Eds(), enableLss: false });
    const eds = this.device.eds;
    eds.setSyncCobId(0x80);
    eds.setSyncGenerationEnable(true);  // SYNC producer; no 0x1006: SYNCs only from sync()
    this.nodes = new Set();
    this.localObjects = new Map();  // "node:index.sub" -> the master's copy (a DataObject)
    this.rpdos = new Map();         // COB-ID -> { node, entries: [[index, sub]], objects }
    this.emergencies = [];          // { node, code, register, info, at } as the EMCY consumer got them
    this.heartbeatTimeouts = [];    // { node, at } as the heartbeat consumer reported them
    this.syncs = 0;
    this.device.emcy.on('emergency', ({ cobId, em }) => {
      this.emergencies.push({ node: cobId - 0x80, code: em.code, register: em.register, info: em.info, at: bus.now() });
    });
    this.device.nmt.on('timeout', (node) => this.heartbeatTimeouts.push({ node, at: bus.now() }));
    // Runs after the library has decoded the frame (Bus calls Devices first): the values a PDO
    // carried are kept with the frame, so a later frame cannot overwrite what a test reads.
    bus.onFrame((frame) => {
      const rpdo = this.rpdos.get(frame.id);
      if (rpdo && !frame.extended) {
        frame.pdo = new Map(rpdo.entries.map(([index, sub], i) => [objectName(index, sub), rpdo.objects[i].value]));
      }
    });
    bus.attach(this.device);
  }

  // A slave: SDO client channel 0x600+N / 0x580+N, EMCY consumer 0x080+N, and a heartbeat
  // consumer entry when heartbeatConsumerMs is given (0x1016: node << 16 | ms).
  addNode(node, { heartbeatConsumerMs = 0 } = {}) {
    const eds = this.device.eds;
    eds.addSdoClientParameter(node, 0x600 + node, 0x580 + node);
    eds.addEmcyConsumer(0x80 + node);
    if (heartbeatConsumerMs) {
      this.consumeHeartbeat(node, heartbeatConsumerMs);
    }
    this.nodes.add(node);
  }

  // A heartbeat consumer entry for node (may be added while running): the library reports a
  // 'timeout' when no heartbeat came for ms after the last one.
  consumeHeartbeat(node, ms) {
    this.device.eds.addHeartbeatConsumer(node, ms);
  }

  // The master's own NMT state: operational, so its Pdo module decodes RPDOs (the library runs
  // PDOs only in OPERATIONAL). No frame is sent.
  start() {
    this.device.start();
    this.device.nmt.startNode();
  }

  stop() {
    this.device.stop();
  }

  // NMT services (CiA 301 7.2.8.3.1) for node, 0 = all nodes. The library applies a broadcast to
  // the master itself too, so a broadcast other than start would also stop its own PDOs.
  nmtStart(node) { this.device.nmt.startNode(node); }
  nmtStop(node) { this.device.nmt.stopNode(node); }
  nmtPreOperational(node) { this.device.nmt.enterPreOperational(node); }
  nmtResetNode(node) { this.device.nmt.resetNode(node); }
  nmtResetCommunication(node) { this.device.nmt.resetCommunication(node); }

  // The slave object's description in its EDS (throws for an object the EDS lacks).
  slaveObject(index, sub = 0) {
    const entry = this.slaveEds.getEntry(index);
    if (!entry) {
      throw new Error(`${hex(index)} is not in the slave's EDS`);
    }
    if (entry.subNumber === undefined && !entry.compactSubObj) {
      if (sub !== 0) {
        throw new Error(`${hex(index)} is a VAR in the slave's EDS: no sub-index ${sub}`);
      }
      return entry;
    }
    const object = entry[sub];
    if (object) {
      return object;
    }
    if (entry.compactSubObj) {  // CiA 306 4.5.2.2: sub 0 is the count, 1..n of the entry's type
      return sub === 0 ? { dataType: DataType.UNSIGNED8, parameterName: entry.parameterName + ' (count)' }
        : { dataType: entry.dataType, parameterName: `${entry.parameterName} ${sub}`, accessType: entry.accessType };
    }
    throw new Error(`${objectName(index, sub)} is not in the slave's EDS`);
  }

  typeOf(index, sub = 0) {
    return this.slaveObject(index, sub).dataType;
  }

  // SDO upload of a slave object, converted with its EDS data type.
  read(node, index, sub = 0) {
    return this.device.sdo.upload({ deviceId: node, index, subIndex: sub, dataType: this.typeOf(index, sub), timeout: this.sdoTimeoutMs });
  }

  // SDO download of a value, encoded with the object's EDS data type (its size decides
  // expedited or segmented).
  write(node, index, sub, value) {
    return this.device.sdo.download({ deviceId: node, index, subIndex: sub, data: value, dataType: this.typeOf(index, sub), timeout: this.sdoTimeoutMs });
  }

  // The same without the EDS: for objects it does not describe and for malformed requests.
  readRaw(node, index, sub = 0) {
    return this.device.sdo.upload({ deviceId: node, index, subIndex: sub, timeout: this.sdoTimeoutMs });
  }

  writeRaw(node, index, sub, bytes) {
    return this.device.sdo.download({ deviceId: node, index, subIndex: sub, data: Buffer.from(bytes), timeout: this.sdoTimeoutMs });
  }

  // A PDO mapping entry for a slave object: index << 16 | sub << 8 | bits (bits from its EDS type).
  mappingEntry(index, sub = 0) {
    const bits = TYPE_BITS[this.typeOf(index, sub)];
    if (!bits) {
      throw new Error(`${objectName(index, sub)}: its data type cannot be mapped into a PDO`);
    }
    return ((index << 16) | (sub << 8) | bits) >>> 0;
  }

  // Configures TPDO n (1-4) of node by SDO with CiA 301's procedure (7.5.2.35/36): COB-ID bit 31
  // set (the PDO is invalid), mapping count 0, the entries, the count, transmission type, COB-ID
  // valid; then mirrors it into a local RPDO. entries: [[index, sub], ...] (omitted: the mapping
  // is kept); enabled false leaves the PDO invalid (and unmirrored). beforeEntries(mappingIndex)
  // runs with the mapping open (count 0), e.g. to try an entry that must be refused.
  async configureTpdo(node, n, { entries, transmissionType, cobId = tpdoCobId(n, node), enabled = true, beforeEntries } = {}) {
    const comm = 0x1800 + n - 1;
    const map = 0x1A00 + n - 1;
    await this.write(node, comm, 1, (cobId | 0x80000000) >>> 0);
    if (!enabled) {
      this.dropRpdo(cobId);
      return null;
    }
    if (entries) {
      await this.write(node, map, 0, 0);
      if (beforeEntries) {
        await beforeEntries(map);
      }
      for (let i = 0; i < entries.length; ++i) {
        await this.write(node, map, i + 1, this.mappingEntry(...entries[i]));
      }
      await this.write(node, map, 0, entries.length);
    }
    if (transmissionType !== undefined) {
      await this.write(node, comm, 2, transmissionType);
    }
    await this.write(node, comm, 1, cobId);
    return this.mirrorTpdo(node, n);
  }

  // Reads TPDO n of node (COB-ID and mapping) by SDO and makes the matching local RPDO, whose
  // objects are the master's copies of the slave's (types from the EDS). Returns { cobId,
  // transmissionType, entries } or null when the slave's TPDO is invalid.
  async mirrorTpdo(node, n) {
    const cob = await this.read(node, 0x1800 + n - 1, 1);
    const transmissionType = await this.read(node, 0x1800 + n - 1, 2);
    const count = await this.read(node, 0x1A00 + n - 1, 0);
    const entries = [];
    for (let i = 1; i <= count; ++i) {
      const entry = await this.read(node, 0x1A00 + n - 1, i);
      entries.push([entry >>> 16, (entry >>> 8) & 0xFF]);
      const bits = entry & 0xFF;
      if (TYPE_BITS[this.typeOf(...entries[i - 1])] !== bits) {
        throw new Error(`TPDO${n} of node ${node}: entry ${hex(entry, 8)} has ${bits} bits, the EDS type of ${objectName(...entries[i - 1])} has ${TYPE_BITS[this.typeOf(...entries[i - 1])]}`);
      }
    }
    if (cob & 0x80000000) {
      this.dropRpdo(cob & 0x7FF);
      return null;
    }
    this.receivePdo(node, cob & 0x7FF, entries);
    return { cobId: cob & 0x7FF, transmissionType, entries };
  }

  // A local RPDO (0x1400+/0x1600+ of the master) on cobId carrying node's objects.
  receivePdo(node, cobId, entries) {
    this.dropRpdo(cobId);
    const objects = entries.map(([index, sub]) => this.localObject(node, index, sub));
    this.device.eds.addReceivePdo({ cobId, transmissionType: 254, dataObjects: objects });
    this.rpdos.set(cobId, { node, entries, objects });
  }

  dropRpdo(cobId) {
    if (this.rpdos.has(cobId)) {
      // The library's removeReceivePdo announces the removal as 'removeTpdo', so its Pdo module
      // keeps decoding the old layout until addReceivePdo replaces it (receivePdo does).
      this.device.eds.removeReceivePdo(cobId);
      this.rpdos.delete(cobId);
    }
  }

  // The master's copy of a slave object (a VAR of the same type in 0x2000+), made once.
  localObject(node, index, sub) {
    const key = `${node}:${objectName(index, sub)}`;
    let object = this.localObjects.get(key);
    if (!object) {
      const remote = this.slaveObject(index, sub);
      let local = LOCAL_OBJECTS_START;
      while (this.device.eds.getEntry(local) !== undefined) {
        ++local;
      }
      object = this.device.eds.addEntry(local, {
        parameterName: `node ${node} ${objectName(index, sub)} ${remote.parameterName}`,
        objectType: ObjectType.VAR,
        dataType: remote.dataType,
        accessType: 'rw',
      });
      this.localObjects.set(key, object);
    }
    return object;
  }

  // The latest value of a slave object the master received in a PDO (its process image).
  value(node, index, sub = 0) {
    const object = this.localObjects.get(`${node}:${objectName(index, sub)}`);
    if (!object) {
      throw new Error(`node ${node} ${objectName(index, sub)} is in no RPDO of the master`);
    }
    return object.value;
  }

  // One SYNC from the library's SYNC producer (lockstep: one control cycle of the drive).
  // Resolves with the frames on the expected COB-IDs that answer it (each with .pdo, the
  // decoded values, when it is an RPDO of the master).
  async sync(expectedCobIds = [], timeoutMs = 20000) {
    const number = this.syncs + 1;
    const frames = expectedCobIds.map((cob) => this.bus.waitFor((f) => f.id === cob && !f.extended, timeoutMs, `${hex(cob, 3)} after SYNC ${number}`));
    this.device.sync.write();
    this.syncs = number;
    return Promise.all(frames);
  }

  // Resolves with the first emergency from node (with code, when given) that the EMCY consumer
  // reports from now on (or already reported, when since is given: a bus.now() time).
  waitEmergency(node, code, timeoutMs, since = null) {
    const match = (e) => e.node === node && (code === undefined || e.code === code);
    if (since !== null) {
      const seen = this.emergencies.find((e) => e.at >= since && match(e));
      if (seen) {
        return Promise.resolve(seen);
      }
    }
    return new Promise((resolve, reject) => {
      const listener = ({ cobId, em }) => {
        const e = { node: cobId - 0x80, code: em.code };
        if (match(e)) {
          clearTimeout(timer);
          this.device.emcy.removeListener('emergency', listener);
          resolve(this.emergencies[this.emergencies.length - 1]);
        }
      };
      const timer = setTimeout(() => {
        this.device.emcy.removeListener('emergency', listener);
        const what = code === undefined ? 'an EMCY' : `EMCY ${hex(code)}`;
        reject(new Error(`no ${what} from node ${node} within ${timeoutMs} ms (EMCYs seen: ${this.describeEmergencies()})`));
      }, timeoutMs);
      this.device.emcy.on('emergency', listener);
    });
  }

  // Resolves with the node of the next heartbeat timeout the consumer reports.
  waitHeartbeatTimeout(timeoutMs) {
    return new Promise((resolve, reject) => {
      const listener = (node) => {
        clearTimeout(timer);
        resolve(node);
      };
      const timer = setTimeout(() => {
        this.device.nmt.removeListener('timeout', listener);
        reject(new Error(`no heartbeat timeout reported within ${timeoutMs} ms`));
      }, timeoutMs);
      this.device.nmt.once('timeout', listener);
    });
  }

  describeEmergencies() {
    return this.emergencies.map((e) => `node ${e.node} ${hex(e.code)} reg ${hex(e.register, 2)}`).join(', ') || 'none';
  }
}

module.exports = { Master, abortCode, tpdoCobId, rpdoCobId, hex, objectName, MASTER_ID };
