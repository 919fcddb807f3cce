// One CAN bus for the npm canopen library, which has no CAN I/O of its own: can_bridge.py (one
// child process per bus) carries frames as "ID#HEX" lines; this side hands every received frame
// to the attached canopen Devices (Device#receive) and sends what they emit (Device 'message',
// the library's transmit hook since 6.0). Tests wait for frames with a predicate and a deadline:
// readiness is a frame (a boot-up, an SDO response, a PDO after a SYNC), never a sleep.
'use strict';

const { spawn } = require('child_process');
const path = require('path');
const { performance } = require('perf_hooks');

const BRIDGE = path.join(__dirname, '..', 'can_bridge.py');
const PYTHON = '/usr/bin/python3';

// "ID#HEX" / "ID#R" (can_bridge.py's stdout) -> { id, data, len, extended, rtr }.
function parseFrame(line) {
  const m = /^([0-9A-F]{3}|[0-9A-F]{8})#(R|(?:[0-9A-F]{2}){0,8})$/.exec(line);
  if (!m) {
    return null;
  }
  const rtr = m[2] === 'R';
  const data = rtr ? Buffer.alloc(0) : Buffer.from(m[2], 'hex');
  return { id: parseInt(m[1], 16), data, len: data.length, extended: m[1].length === 8, rtr };
}

// { id, data } -> "ID#HEX" (can_bridge.py's stdin): 3 hex digits for a standard identifier.
function formatFrame({ id, data, rtr, len }) {
  if (!Number.isInteger(id) || id < 0 || id > 0x1FFFFFFF) {
    throw new RangeError(`CAN identifier ${id} out of range`);
  }
  if (rtr) {  // a remote frame: no data, a DLC of its own
    const ident = id > 0x7FF ? id.toString(16).padStart(8, '0') : id.toString(16).padStart(3, '0');
    return `${ident.toUpperCase()}#R${len || 0}`;
  }
  const bytes = data || Buffer.alloc(0);
  if (bytes.length > 8) {
    throw new RangeError(`CAN frame 0x${id.toString(16)} with ${bytes.length} bytes (at most 8)`);
  }
  const ident = id > 0x7FF ? id.toString(16).padStart(8, '0') : id.toString(16).padStart(3, '0');
  return `${ident.toUpperCase()}#${Buffer.from(bytes).toString('hex').toUpperCase()}`;
}

// What every bus does with frames, whatever carries them: hands each received frame to the
// attached Devices, then to the listeners, then to the waiters.
class FrameHub {
  constructor(iface) {
    this.iface = iface;
    this.devices = [];
    this.listeners = new Set();
    this.waiters = new Set();
    this.failure = null;  // why the bus is gone, once it is
    this.started = performance.now();
    this.received = 0;
    this.sent = 0;
  }

  // Milliseconds since the bus was opened (monotonic).
  now() {
    return performance.now() - this.started;
  }

  // A canopen Device on this bus: it receives every frame; what it emits is sent.
  attach(device) {
    this.devices.push(device);
    device.on('message', (message) => this.send(message));
  }

  send(frame) {
    if (this.failure) {
      throw this.failure;
    }
    this._transmit(frame);
    this.sent += 1;
  }

  // Calls listener(frame) for every received frame, after the Devices have seen it (so a
  // listener reads what the library decoded from it). Returns the function that removes it.
  onFrame(listener) {
    this.listeners.add(listener);
    return () => this.listeners.delete(listener);
  }

  // Resolves with the first frame received from now on for which predicate(frame) is true;
  // rejects after timeoutMs ("timeout after N ms waiting for WHAT") or when the bus fails.
  // Register it before the action that causes the frame.
  waitFor(predicate, timeoutMs, what) {
    return new Promise((resolve, reject) => {
      if (this.failure) {
        reject(this.failure);
        return;
      }
      const waiter = { predicate, resolve, reject, what };
      waiter.timer = setTimeout(() => {
        this.waiters.delete(waiter);
        reject(new Error(`timeout after ${timeoutMs} ms waiting for ${what}`));
      }, timeoutMs);
      this.waiters.add(waiter);
    });
  }

  _deliver(frame) {
    frame.at = this.now();
    this.received += 1;
    try {
      for (const device of this.devices) {
        device.receive({ id: frame.id, data: frame.data, len: frame.len });
      }
    } catch (e) {
      // The library threw on a frame it was given: a finding, not something to step over.
      this._fail(new Error(`the canopen library threw on ${formatFrame(frame)}: ${e.message}`));
      return;
    }
    for (const listener of this.listeners) {
      listener(frame);
    }
    for (const waiter of this.waiters) {
      let matched;
      try {
        matched = waiter.predicate(frame);
      } catch (e) {
        matched = false;
      }
      if (matched) {
        clearTimeout(waiter.timer);
        this.waiters.delete(waiter);
        waiter.resolve(frame);
      }
    }
  }

  _fail(error) {
    if (this.failure) {
      return;
    }
    this.failure = error;
    for (const waiter of this.waiters) {
      clearTimeout(waiter.timer);
      waiter.reject(error);
    }
    this.waiters.clear();
  }
}

// A SocketCAN interface through can_bridge.py (one child process per bus).
class Bus extends FrameHub {
  constructor(iface, child) {
    super(iface);
    this.child = child;
  }

  // Starts the bridge on IFACE and resolves once its socket is bound (its "listening" line), so
  // that a node started afterwards cannot send its boot-up before anyone listens.
  static open(iface = 'vcan0', { readyTimeoutMs = 30000 } = {}) {
    const child = spawn(PYTHON, [BRIDGE, iface], { stdio: ['pipe', 'pipe', 'pipe'] });
    const bus = new Bus(iface, child);
    let stderr = '';
    let pending = '';
    child.stdout.setEncoding('ascii');
    child.stdout.on('data', (chunk) => {
      pending += chunk;
      let end;
      while ((end = pending.indexOf('\n')) >= 0) {
        const line = pending.slice(0, end);
        pending = pending.slice(end + 1);
        const frame = parseFrame(line);
        if (frame) {
          bus._deliver(frame);
        } else {
          bus._fail(new Error(`can_bridge on ${iface}: unreadable line ${JSON.stringify(line)}`));
        }
      }
    });
    child.stdin.on('error', () => {});  // a dead bridge is reported by its exit, below
    return new Promise((resolve, reject) => {
      const timer = setTimeout(() => {
        reject(new Error(`can_bridge on ${iface}: not listening after ${readyTimeoutMs} ms`));
        child.kill('SIGKILL');
      }, readyTimeoutMs);
      child.stderr.setEncoding('utf8');
      child.stderr.on('data', (chunk) => {
        stderr += chunk;
        if (stderr.includes(`can_bridge: listening on ${iface}`)) {
          clearTimeout(timer);
          resolve(bus);
        }
      });
      child.on('exit', (code, signal) => {
        clearTimeout(timer);
        const why = stderr.split('\n').filter((l) => l && !l.includes('listening on')).join('; ');
        bus._fail(bus.closing ? new Error(`bus ${iface} closed`)
          : new Error(`can_bridge on ${iface} exited (${signal || code})${why ? ': ' + why : ''}`));
        reject(bus.failure);
      });
    });
  }

  _transmit(frame) {
    this.child.stdin.write(formatFrame(frame) + '\n');
  }

  // Ends the bridge (end of its input) and resolves when it has exited.
  close() {
    if (this.child.exitCode !== null || this.child.signalCode !== null) {
      return Promise.resolve();
    }
    return new Promise((resolve) => {
      this.closing = true;
      this.child.on('exit', () => resolve());
      this.child.stdin.end();
    });
  }
}

// Buses joined in this process, for host tests without CAN: what one sends, the others receive
// (asynchronously, as from a socket), never the sender itself (as SocketCAN's default).
class MemoryBus extends FrameHub {
  constructor(iface = 'memory') {
    super(iface);
    this.peers = [];
  }

  connect(other) {
    this.peers.push(other);
    other.peers.push(this);
  }

  _transmit(frame) {
    const line = formatFrame(frame);  // the same checks as a real bus, and a copy of the bytes
    for (const peer of this.peers) {
      setImmediate(() => peer._deliver(parseFrame(line)));
    }
  }

  close() {
    return Promise.resolve();
  }
}

module.exports = { Bus, MemoryBus, parseFrame, formatFrame };
