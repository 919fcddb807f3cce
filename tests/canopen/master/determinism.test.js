// In lockstep the same master script gives the same bus traffic (ctest canopen.vcan.determinism):
// lockstep_log.js runs twice, the second time with a busy loop on every core (started and
// stopped by pid), and the two --record-can files (candump's log format, emulated timestamps)
// must be identical byte for byte. Each must also be a complete log: well-formed lines, every
// SYNC and every synchronous TPDO of the run in it.
'use strict';

const { spawn } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');
const { check, atEnd, run } = require('./lib/check');

const NODE = 7;  // lockstep_log.js's
const LINE = /^\(\d+\.\d{6}\) vcan0 ([0-9A-F]{3}|[0-9A-F]{8})#([0-9A-F]{2})*$/;

function runScript(file) {
  return new Promise((resolve) => {
    const child = spawn(process.execPath, [path.join(__dirname, 'lockstep_log.js'), file], { stdio: ['ignore', 'pipe', 'inherit'] });
    let out = '';
    child.stdout.on('data', (s) => { out += s; });
    child.on('exit', (code) => resolve({ code, out: out.trim() }));
  });
}

function startHogs() {
  // Each hog dies with its parent (PR_SET_PDEATHSIG), also when a time limit kills the test.
  const hog = 'import ctypes, signal; ctypes.CDLL(None).prctl(1, signal.SIGKILL)\nwhile True: pass';
  const hogs = os.cpus().map(() => spawn('/usr/bin/python3', ['-c', hog], { stdio: 'ignore' }));
  const stop = async () => {
    await Promise.all(hogs.map((h) => new Promise((resolve) => {
      if (h.exitCode !== null || h.signalCode !== null) {
        resolve();
        return;
      }
      h.on('exit', resolve);
      process.kill(h.pid, 'SIGKILL');
    })));
  };
  atEnd(stop);
  return { count: hogs.length, stop };
}

run('canopen.vcan.determinism', async () => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'swum-canopen-'));
  atEnd(() => fs.rmSync(dir, { recursive: true, force: true }));
  const files = [path.join(dir, 'quiet.log'), path.join(dir, 'loaded.log')];
  const quiet = await runScript(files[0]);
  check(quiet.code === 0, `the quiet run failed: ${quiet.out}`);
  const hogs = startHogs();
  const loaded = await runScript(files[1]);
  await hogs.stop();
  check(loaded.code === 0, `the run under ${hogs.count} busy loops failed: ${loaded.out}`);

  const [a, b] = files.map((f) => fs.readFileSync(f, 'utf8'));
  const lines = a.split('\n').filter((l) => l);
  const bad = lines.find((l) => !LINE.test(l));
  check(!bad, `not a candump log line: ${JSON.stringify(bad)}`);
  const syncs = lines.filter((l) => / 080#$/.test(l)).length;
  const tpdo3 = lines.filter((l) => l.includes(` ${(0x380 + NODE).toString(16).toUpperCase()}#`)).length;
  check(syncs > 50 && tpdo3 === syncs, `the log has ${syncs} SYNCs and ${tpdo3} TPDO3 frames (expected more than 50, one TPDO3 per SYNC)`);
  if (a !== b) {
    const other = b.split('\n');
    const at = a.split('\n').findIndex((l, i) => l !== other[i]);
    check(false, `the logs differ under ${hogs.count} busy loops: line ${at + 1} quiet ${JSON.stringify(a.split('\n')[at])}, loaded ${JSON.stringify(other[at])}`);
  }
  return `${lines.length} identical lines (${syncs} SYNCs) with and without ${hogs.count} busy loops; ${quiet.out.replace(/^PASS lockstep_log: /, '')}`;
});
