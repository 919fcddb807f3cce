// The harness on a real CAN bus, without swum-emu (ctest canopen.vcan.selftest; in the guest:
// tools/vm/with-vcan /usr/bin/node tests/canopen/master/selftest.js): can_bridge.py's frames
// through vcan0 between two bridges (standard, extended, remote, empty), its failure on a bad
// line, then the master against a stand-in slave (an npm canopen Device in a process of its own,
// lib/standin.js): boot-up, SDO upload and download (expedited, segmented, aborts), NMT, PDO
// after SYNC, EMCY, and the heartbeat timeout when the stand-in is killed by pid.
'use strict';

const { spawn } = require('child_process');
const path = require('path');
const { Bus } = require('./lib/bus');
const { Master } = require('./lib/master');
const { standinEds } = require('./lib/standin');
const { checkAgainstStandin } = require('./lib/standin_checks');
const { check, atEnd, run } = require('./lib/check');

const IFACE = 'vcan0';
const NODE = 5;
const FRAME_MS = 5000;

async function checkBridges() {
  const a = await Bus.open(IFACE);
  atEnd(() => a.close());
  const b = await Bus.open(IFACE);
  atEnd(() => b.close());
  const frames = [
    { id: 0x123, data: Buffer.from('deadbeef', 'hex') },
    { id: 0x080, data: Buffer.alloc(0) },
    { id: 0x7FF, data: Buffer.from('0011223344556677', 'hex') },
    { id: 0x1ABCDEF0, data: Buffer.from([0xA5]) },
  ];
  for (const sent of frames) {
    const got = b.waitFor(() => true, FRAME_MS, `0x${sent.id.toString(16)} from the other bridge`);
    a.send(sent);
    const f = await got;
    check(f.id === sent.id && f.data.equals(sent.data) && f.extended === sent.id > 0x7FF,
      `sent 0x${sent.id.toString(16)}#${sent.data.toString('hex')}, received 0x${f.id.toString(16)}#${f.data.toString('hex')}`);
  }
  // A bridge does not hear its own frames: the next frame a hears is b's, not its own.
  const echo = a.waitFor(() => true, FRAME_MS, 'a frame from the other bridge');
  a.send({ id: 0x100, data: Buffer.from([1]) });
  b.send({ id: 0x101, data: Buffer.from([2]) });
  const heard = await echo;
  check(heard.id === 0x101, `bridge a heard 0x${heard.id.toString(16)} first: its own frame came back`);
  await b.close();
  await a.close();
  // A bad line ends the bridge: one line on stderr, status 1.
  const bad = spawn('/usr/bin/python3', [path.join(__dirname, 'can_bridge.py'), IFACE], { stdio: ['pipe', 'pipe', 'pipe'] });
  let stderr = '';
  bad.stderr.on('data', (s) => { stderr += s; });
  bad.stdin.end('123#DEADBEEF\n12G#00\n');
  const code = await new Promise((resolve) => bad.on('exit', resolve));
  check(code === 1 && /^can_bridge: listening on vcan0\ncan_bridge: line 2: bad frame line '12G#00'[^\n]*\n$/.test(stderr),
    `bridge given a bad line: status ${code}, stderr ${JSON.stringify(stderr)}`);
}

// The stand-in slave in its own process, killed by pid to lose its heartbeat.
async function checkStandin() {
  const bus = await Bus.open(IFACE);
  atEnd(() => bus.close());
  const master = new Master(bus, standinEds(NODE));
  master.addNode(NODE);
  master.start();
  atEnd(() => master.stop());
  const bootUp = bus.waitFor((f) => f.id === 0x700 + NODE && f.len === 1 && f.data[0] === 0, 30000, `the stand-in's boot-up (0x${(0x700 + NODE).toString(16)}#00)`);
  const standin = spawn(process.execPath, [path.join(__dirname, 'lib', 'standin.js'), IFACE, String(NODE)], { stdio: ['pipe', 'inherit', 'inherit'] });
  const exited = new Promise((resolve) => standin.on('exit', (code, signal) => resolve(signal || code)));
  atEnd(async () => {
    if (standin.exitCode === null && standin.signalCode === null) {
      process.kill(standin.pid, 'SIGKILL');
    }
    await exited;
  });
  await bootUp;
  return checkAgainstStandin(master, NODE, async () => {
    process.kill(standin.pid, 'SIGKILL');
    const how = await exited;
    check(how === 'SIGKILL', `the stand-in ended by ${how}, not by SIGKILL`);
  });
}

run('canopen.vcan.selftest', async () => {
  await checkBridges();
  const summary = await checkStandin();
  return `bridges on ${IFACE} (standard, extended, empty, no echo, bad line); ${summary}`;
});
