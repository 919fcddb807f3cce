// swum-emu as a child of a scenario script, as a CANopen slave (docs/canopen.md): started with
// --can-profile cia402 on the bus's interface, ready when its boot-up (0x700+N, data 00) is on the
// bus, stopped by its pid (SIGTERM, then wait for the exit). SWUM_EMU names the binary,
// SWUM_SOURCE_DIR the checkout (its config/li2019.toml is the motor).
'use strict';

const { spawn } = require('child_process');
const path = require('path');
const { atEnd } = require('./check');

const KEEP_OUTPUT = 64 * 1024;  // the tail of stdout/stderr kept for a failure's reason

function required(name) {
  const value = process.env[name];
  if (!value) {
    throw new Error(`${name} is not set (ctest sets it: tests/canopen/master/CMakeLists.txt)`);
  }
  return value;
}

function sourceDir() {
  return required('SWUM_SOURCE_DIR');
}

class Emulator {
  constructor(node, child) {
    this.node = node;
    this.child = child;
    this.pid = child.pid;
    this.stdout = '';
    this.stderr = '';
    this.exit = new Promise((resolve) => child.on('exit', (code, signal) => resolve({ code, signal })));
    child.stdout.setEncoding('utf8');
    child.stderr.setEncoding('utf8');
    child.stdout.on('data', (s) => { this.stdout = (this.stdout + s).slice(-KEEP_OUTPUT); });
    child.stderr.on('data', (s) => { this.stderr = (this.stderr + s).slice(-KEEP_OUTPUT); });
  }

  // Starts swum-emu as node on bus and resolves once its boot-up frame is seen.
  //   lockstep: --clock external (emulated time advances one --sync-ticks cycle per SYNC)
  //   syncTicks, scenario (a TOML file), recordCan (a file), args (more options)
  static async start(bus, node, { lockstep = true, syncTicks, scenario, recordCan, args = [], bootTimeoutMs = 60000 } = {}) {
    const argv = ['--config', path.join(sourceDir(), 'config', 'li2019.toml'), '--modbus', 'none',
      '--can', bus.iface, '--node', String(node), '--can-profile', 'cia402'];
    if (lockstep) {
      argv.push('--clock', 'external');
    }
    if (syncTicks !== undefined) {
      argv.push('--sync-ticks', String(syncTicks));
    }
    if (scenario) {
      argv.push('--scenario', scenario);
    }
    if (recordCan) {
      argv.push('--record-can', recordCan);
    }
    argv.push(...args);
    // Registered before the process exists: its boot-up cannot come before anyone waits for it.
    const bootUp = bus.waitFor((f) => f.id === 0x700 + node && !f.extended && f.len === 1 && f.data[0] === 0,
      bootTimeoutMs, `the boot-up of node ${node} (${(0x700 + node).toString(16).toUpperCase()}#00)`);
    const child = spawn(required('SWUM_EMU'), argv, { stdio: ['ignore', 'pipe', 'pipe'] });
    const emu = new Emulator(node, child);
    emu.argv = argv;
    atEnd(() => emu.kill());
    const died = emu.exit.then(({ code, signal }) => {
      throw new Error(`swum-emu (node ${node}) exited (${signal || code}) before its boot-up: ${emu.stderr.trim() || emu.stdout.trim()}`);
    });
    await Promise.race([bootUp, died]);
    died.catch(() => {});  // from now on an exit is stop()'s business
    return emu;
  }

  running() {
    return this.child.exitCode === null && this.child.signalCode === null;
  }

  // SIGTERM by pid, then waits for the exit; resolves with { code, signal, stdout, stderr }.
  async stop(timeoutMs = 30000) {
    if (this.running()) {
      process.kill(this.pid, 'SIGTERM');
    }
    const timer = new Promise((resolve) => setTimeout(resolve, timeoutMs, null));
    const result = await Promise.race([this.exit, timer]);
    if (!result) {
      await this.kill();
      throw new Error(`swum-emu (node ${this.node}, pid ${this.pid}) did not exit within ${timeoutMs} ms of SIGTERM`);
    }
    return { ...result, stdout: this.stdout, stderr: this.stderr };
  }

  // SIGKILL by pid (a node that dies), then waits for the exit.
  async kill() {
    if (this.running()) {
      process.kill(this.pid, 'SIGKILL');
    }
    return this.exit;
  }
}

module.exports = { Emulator, sourceDir };
