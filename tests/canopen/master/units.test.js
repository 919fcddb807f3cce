// The harness's own parts on the host, without CAN (ctest canopen.master.units): lib/crc.js
// against published check values, the frame lines of lib/bus.js, the master against the
// stand-in slave on joined in-memory buses, and config/swum.eds as the master reads it (the data
// types the scenario scripts take from it, as docs/canopen.md lists them).
'use strict';

const fs = require('fs');
const path = require('path');
const { crc } = require('./lib/crc');
const { MemoryBus, parseFrame, formatFrame } = require('./lib/bus');
const { Master } = require('./lib/master');
const { standinEds, STANDIN } = require('./lib/standin');
const { checkAgainstStandin } = require('./lib/standin_checks');
const { Device, Eds, DataType } = require('./lib/canopen');
const { check, run } = require('./lib/check');
const { stateOf } = require('./lib/cia402');

function checkCrc() {
  // "123456789" (the catalogue's check input): CRC-16/XMODEM is SDO block transfer's (CiA 301
  // 7.2.4.3.16: polynomial 0x1021, initial value 0).
  const data = Buffer.from('123456789');
  const cases = [
    ['CRC-16/XMODEM', [16, false, 0x1021, 0, 0, 0, 0, 0], '31c3'],
    ['CRC-16/ARC', [16, true, 0xA001, 0, 0, 0, 0, 0], 'bb3d'],
    ['CRC-16/IBM-3740', [16, false, 0x1021, 0, 0xFFFF, 0, 0, 0], '29b1'],
    ['CRC-32/ISO-HDLC', [32, true, 0xEDB88320, 0, 0xFFFFFFFF, 0, 0xFFFFFFFF, 0], 'cbf43926'],
    ['CRC-32/BZIP2', [32, false, 0x04C11DB7, 0, 0xFFFFFFFF, 0, 0xFFFFFFFF, 0], 'fc891918'],
    ['CRC-8/SMBUS', [8, false, 0x07, 0, 0, 0, 0, 0], 'f4'],
  ];
  for (const [name, args, want] of cases) {
    const got = crc(...args, data).toString('hex');
    check(got === want, `${name} of "123456789" = ${got}, expected ${want}`);
  }
  check(crc(16, false, 0x1021, 0, 0, 0, 0, 0, Buffer.alloc(0)).toString('hex') === '0000', 'CRC-16 of nothing is not 0000');
  let refused = false;
  try {
    crc(64, false, 1, 1, 0, 0, 0, 0, data);
  } catch (e) {
    refused = e instanceof RangeError;
  }
  check(refused, 'a 64-bit CRC was not refused');
}

function checkFrameLines() {
  const cases = [
    ['181#500209030000', { id: 0x181, data: '500209030000', extended: false, rtr: false }],
    ['080#', { id: 0x80, data: '', extended: false, rtr: false }],
    ['1ABCDEF0#0102', { id: 0x1ABCDEF0, data: '0102', extended: true, rtr: false }],
    ['705#R', { id: 0x705, data: '', extended: false, rtr: true }],
  ];
  for (const [line, want] of cases) {
    const f = parseFrame(line);
    check(f && f.id === want.id && f.data.toString('hex') === want.data && f.len === want.data.length / 2 &&
          f.extended === want.extended && f.rtr === want.rtr, `parseFrame(${line}) = ${JSON.stringify(f)}`);
  }
  for (const bad of ['18#00', '181#0', '181#00112233445566778', '181 00', '181#zz', '']) {
    check(parseFrame(bad) === null, `parseFrame accepted ${JSON.stringify(bad)}`);
  }
  check(formatFrame({ id: 0x605, data: Buffer.from([0x40, 0x08, 0x10, 0]) }) === '605#40081000', 'formatFrame standard');
  check(formatFrame({ id: 0x80, data: Buffer.alloc(0) }) === '080#', 'formatFrame of an empty SYNC');
  check(formatFrame({ id: 0x800, data: Buffer.from([1]) }) === '00000800#01', 'formatFrame of an extended identifier');
  for (const bad of [{ id: 0x20000000, data: Buffer.alloc(0) }, { id: 0x181, data: Buffer.alloc(9) }, { id: -1 }]) {
    let refused = false;
    try {
      formatFrame(bad);
    } catch (e) {
      refused = e instanceof RangeError;
    }
    check(refused, `formatFrame accepted ${JSON.stringify(bad)}`);
  }
}

function checkStates() {
  const cases = [[0x0250, 'switch on disabled'], [0x0231, 'ready to switch on'], [0x0233, 'switched on'],
    [0x0637, 'operation enabled'], [0x0217, 'quick stop active'], [0x021F, 'fault reaction active'],
    [0x0218, 'fault'], [0x0200, 'not ready to switch on']];
  for (const [sw, want] of cases) {
    check(stateOf(sw) === want, `stateOf(0x${sw.toString(16)}) = ${stateOf(sw)}, expected ${want}`);
  }
}

async function checkMasterOnMemoryBuses() {
  const node = 5;
  const masterBus = new MemoryBus('master');
  const slaveBus = new MemoryBus('slave');
  masterBus.connect(slaveBus);
  const master = new Master(masterBus, standinEds(node));
  master.addNode(node);
  master.start();
  check(master.mappingEntry(0x606C) === 0x606C0020 && master.mappingEntry(0x6041) === 0x60410010,
    'mapping entries of 0x606C / 0x6041 are not 0x606C0020 / 0x60410010');
  const slave = new Device({ id: node, eds: standinEds(node), enableLss: false });
  slaveBus.attach(slave);
  slave.eds.getEntry(STANDIN.emcyTrigger).on('update', (entry) => slave.emcy.write(entry.value));
  const bootUp = masterBus.waitFor((f) => f.id === 0x700 + node && f.data.equals(Buffer.from([0])), 1000, 'boot-up');
  slave.start();
  slaveBus.send({ id: 0x700 + node, data: Buffer.from([0]) });
  await bootUp;
  const summary = await checkAgainstStandin(master, node, async () => slave.stop());
  master.stop();
  return summary;
}

// config/swum.eds as the master loads it: the types the scenario scripts download and upload with.
function checkSwumEds() {
  const file = path.join(__dirname, '..', '..', '..', 'config', 'swum.eds');
  if (!fs.existsSync(file)) {
    return 'config/swum.eds not there yet: skipped';
  }
  const master = new Master(new MemoryBus(), Eds.fromFile(file));
  const T = DataType;
  const expected = [
    [0x1000, 0, T.UNSIGNED32], [0x1001, 0, T.UNSIGNED8], [0x1003, 1, T.UNSIGNED32], [0x1008, 0, T.VISIBLE_STRING],
    [0x1017, 0, T.UNSIGNED16], [0x1018, 1, T.UNSIGNED32], [0x1018, 4, T.UNSIGNED32], [0x1800, 1, T.UNSIGNED32],
    [0x1800, 2, T.UNSIGNED8], [0x1A00, 0, T.UNSIGNED8], [0x1A00, 1, T.UNSIGNED32], [0x1A02, 2, T.UNSIGNED32],
    [0x603F, 0, T.UNSIGNED16], [0x6040, 0, T.UNSIGNED16], [0x6041, 0, T.UNSIGNED16], [0x6060, 0, T.INTEGER8],
    [0x6061, 0, T.INTEGER8], [0x606C, 0, T.INTEGER32], [0x606D, 0, T.UNSIGNED16], [0x60FF, 0, T.INTEGER32],
    [0x6502, 0, T.UNSIGNED32], [0x2050, 0, T.UNSIGNED32],
  ];
  for (const [index, sub, type] of expected) {
    const got = master.typeOf(index, sub);
    check(got === type, `config/swum.eds: 0x${index.toString(16)}.${sub} has data type ${got}, docs/canopen.md says ${type}`);
  }
  const name = master.slaveObject(0x1008).defaultValue;
  check(name === 'swum-emu bimodal standing-wave ultrasonic motor drive', `config/swum.eds: 0x1008 default ${JSON.stringify(name)}`);
  return `config/swum.eds: ${expected.length} objects typed as docs/canopen.md says`;
}

run('canopen.master.units', async () => {
  checkCrc();
  checkFrameLines();
  checkStates();
  const standin = await checkMasterOnMemoryBuses();
  const eds = checkSwumEds();
  return `crc, frame lines, states; ${standin}; ${eds}`;
});
