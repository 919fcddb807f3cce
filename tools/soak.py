#!/usr/bin/python3
"""Soak of swum-emu's Modbus TCP server (issue 14 item 6; figures in docs/reliability.md, "Soak").

usage: tools/soak [--minutes N] [--emu PATH] [--seed S] [--json FILE]

Starts swum-emu (tests/firmware_sim/emu_harness.py) and runs, for N minutes (default 10), on
127.0.0.1 with raw sockets (so malformed frames are under our control):

  pollers (2)    FC04 all 35 input registers every 50 ms, FC03 holding every 10th time; the
                 counters (applied, rejected, tick) must never go backwards
  setpoints (1)  valid FC16 / FC06 set-point and slew writes every 20 ms
  commands (1)   keep-alive every 20 ms, enable / disable / reset fault about once a second,
                 and every 30 s a blackout (below)
  invalid (1)    a catalogue of invalid PDUs (out-of-range values, split 32-bit accesses, illegal
                 addresses, bad quantities / byte counts, unsupported function codes) every 25 ms:
                 each must get its exception code and, when no other reject interleaved, its
                 reject reason (input register 3)
  framing (1)    a new connection every 0.5-1 s for a framing fault: truncated frames (then
                 silence: closed after the frame timeout; or hang-up), MBAP length or protocol id
                 wrong and an MBAP length announcing surplus bytes (not answered, closed at once),
                 a frame longer than an ADU, and pipelined requests
  churn (2)      connect, 1-5 valid requests, disconnect, every 100-300 ms; refused connections
                 (all slots busy) are retried; the first answer must come within the deadline
  holders (12)   connections opened and left idle; reopened 0.5-3 s after the server closes them
                 (idle timeout, eviction, or no slot); and every minute a burst of 20 more, left
                 idle: those beyond the free slots are closed at once or evict idle holders

Blackout: the writers, the invalid and framing clients and the churners pause; after 0.5 s the
watchdog (100 ms) must have faulted the enabled amplifier; one `enable` is then accepted by the
server and rejected by the amplifier ("fault active"), checked on the reject count and reason;
reset fault and enable follow.

Ledger, once the writers stopped and the queue drained (the tick moved on twice):
  accepted (writes answered without exception, counted by the clients)
    = applied (input registers 6-7) + amplifier-rejected (reject count 4-5 minus every exception
      the clients received: each exception also counts as a reject)
  last sequence (33-34) = applied + amplifier-rejected + queue-full refusals (each refusal
      also draws a number)
and the exit report (SIGTERM) must agree: same applied / rejected counts, exceptions = those the
clients received, requests = those answered, connections + "no slot" = connections opened.

Also violations: a valid request unanswered within DEADLINE_S (5 s, refused reconnects
included), or answered with an exception other than BUSY; an invalid one answered otherwise than
expected; a client closed by the server although it asked within the eviction time (see
Client.closed_by_server); the emulator crashing or exiting non-zero.

Resources: VmRSS, threads and open fds of swum-emu every 10 s (see RSS_TOLERANCE_KB and
check_resources for the rules). Exit status 0 when nothing was violated, 1 otherwise, 2 when
the run could not start.
"""
import argparse
import collections
import json
import os
import random
import re
import select
import signal
import socket
import struct
import sys
import threading
import time

SOURCE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(SOURCE_DIR, "tests/firmware_sim"))
import emu_harness  # noqa: E402
from emu_harness import Emulator, RegisterMap  # noqa: E402

MAP = RegisterMap()
H = {name: e["address"] for name, e in MAP.holding.items()}
I = {name: e["address"] for name, e in MAP.input.items()}
REASON = MAP.reasons
INPUT_COUNT = MAP.input_count  # 35

# The server's rules (docs/emulator.md), passed explicitly so the expectations below cannot drift.
SLOTS = 16
IDLE_TIMEOUT_MS, FRAME_TIMEOUT_MS, EVICT_IDLE_MS, WATCHDOG_MS = 10000, 500, 1000, 100
EMU_ARGS = ["--modbus-idle-timeout-ms", str(IDLE_TIMEOUT_MS), "--modbus-frame-timeout-ms", str(FRAME_TIMEOUT_MS),
            "--modbus-evict-idle-ms", str(EVICT_IDLE_MS), "--watchdog-ms", str(WATCHDOG_MS)]

DEADLINE_S = 5.0          # a valid request must be answered within this (retries included)
SAMPLE_EVERY_S = 10.0
BLACKOUT_FIRST_S, BLACKOUT_EVERY_S, BLACKOUT_QUIET_S = 20.0, 30.0, 0.5
HOLDERS = 12
BURST, BURST_EVERY_S = 20, 60.0  # and, every minute, a burst of connections left idle
# RSS may exceed the highest warm-up sample by at most this much (see check_resources).
RSS_TOLERANCE_KB = 2048

FC_READ_HOLDING, FC_READ_INPUT, FC_WRITE_SINGLE, FC_WRITE_MULTIPLE = 3, 4, 6, 16
ILLEGAL_FUNCTION, ILLEGAL_ADDRESS, ILLEGAL_VALUE, BUSY = 1, 2, 3, 6


# ---------------------------------------------------------------------------------------------
# Frames and a raw client

def mbap(tid, pdu, unit=1, length=None, protocol=0):
    return struct.pack(">HHHB", tid, protocol, len(pdu) + 1 if length is None else length, unit) + pdu


def read_pdu(address, count, function=FC_READ_INPUT):
    return struct.pack(">BHH", function, address, count)


def write_single(address, value):
    return struct.pack(">BHH", FC_WRITE_SINGLE, address, value & 0xFFFF)


def write_multiple(address, values, quantity=None, byte_count=None):
    values = [v & 0xFFFF for v in values]
    q = len(values) if quantity is None else quantity
    bc = 2 * len(values) if byte_count is None else byte_count
    return struct.pack(">BHHB", FC_WRITE_MULTIPLE, address, q, bc) + b"".join(struct.pack(">H", v) for v in values)


def u32(value):
    value &= 0xFFFFFFFF
    return [value >> 16, value & 0xFFFF]


def regs(name, physical):
    return MAP.encode(name, physical)


class Closed(Exception):
    """The server closed the connection (end of stream or reset) before a whole reply."""


class NoReply(Exception):
    """No whole reply within the deadline."""


class Link:
    """One Modbus TCP connection to the emulator."""

    def __init__(self, port):
        self.start = time.monotonic()  # of the current request (at first: of the connect)
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=DEADLINE_S)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.tid = random.randrange(0x10000)
        self.buffer = b""
        self.replies = 0
        self.window = 0.0

    def mark_sent(self, started):
        """From the start of the previous request (or the connect) to the end of sending this one:
        an upper bound of the idle time the server can have counted before this request."""
        self.window = time.monotonic() - self.start
        self.start = started

    def close(self):
        try:
            self.sock.close()
        except OSError:
            pass

    def send(self, data):
        try:
            self.sock.sendall(data)
        except (BrokenPipeError, ConnectionResetError) as e:
            raise Closed(repr(e)) from None

    def reply(self, timeout=DEADLINE_S):
        """One whole ADU (MBAP header included)."""
        end = time.monotonic() + timeout
        while len(self.buffer) < 7 or len(self.buffer) < 6 + struct.unpack(">H", self.buffer[4:6])[0]:
            left = end - time.monotonic()
            if left <= 0:
                # Tell a slow server from a starved client thread (the deadline is checked on the
                # client's clock, before it reads): was a reply already waiting?
                waiting, _, _ = select.select([self.sock], [], [], 0)
                raise NoReply(("a reply was waiting: the client was late; " if waiting else "nothing waiting; ")
                              + f"had {self.buffer.hex() or 'no bytes'}")
            ready, _, _ = select.select([self.sock], [], [], left)
            if not ready:
                continue
            try:
                chunk = self.sock.recv(4096)
            except (ConnectionResetError, socket.timeout) as e:
                raise Closed(repr(e)) from None
            if not chunk:
                raise Closed("end of stream")
            self.buffer += chunk
        n = 6 + struct.unpack(">H", self.buffer[4:6])[0]
        adu, self.buffer = self.buffer[:n], self.buffer[n:]
        return adu

    def ask(self, pdu, **header):
        """Sends one request; its reply PDU (transaction id and protocol id checked)."""
        self.tid = (self.tid + 1) & 0xFFFF
        started = time.monotonic()
        self.send(mbap(self.tid, pdu, **header))
        self.mark_sent(started)
        adu = self.reply()
        self.replies += 1
        tid, protocol, _ = struct.unpack(">HHH", adu[:6])
        if tid != self.tid or protocol != 0 or len(adu) < 9:
            raise ValueError(f"reply {adu.hex()} to transaction {self.tid}")
        return adu[7:]

    def wait_closed(self, timeout):
        """True when the server closes the connection within `timeout` s (data before it ignored)."""
        end = time.monotonic() + timeout
        while True:
            left = end - time.monotonic()
            if left <= 0:
                return False
            ready, _, _ = select.select([self.sock], [], [], left)
            if ready:
                try:
                    if not self.sock.recv(4096):
                        return True
                except ConnectionResetError:
                    return True


def input_registers(pdu):
    """Registers of an FC04/FC03 reply PDU."""
    n = pdu[1] // 2
    return list(struct.unpack(f">{n}H", pdu[2:2 + 2 * n]))


def u32_at(registers, address):
    return (registers[address] << 16) | registers[address + 1]


# ---------------------------------------------------------------------------------------------
# Shared tallies

class Tally:
    def __init__(self):
        self.lock = threading.Lock()
        self.sent = collections.Counter()       # request kind -> requests sent
        self.answered = collections.Counter()   # request kind -> whole replies received (served)
        self.exceptions = collections.Counter()  # exception code -> replies
        self.expected = collections.Counter()    # (kind, code) -> invalid requests answered as they should
        self.accepted = 0                       # writes answered without exception: commands queued
        self.in_doubt = 0                       # writes sent on a connection that closed before the reply
        self.events = collections.Counter()
        self.slowest = collections.defaultdict(float)  # client group -> slowest answer (s)
        self.by_group = collections.Counter()  # client group -> requests answered
        self.violations = collections.Counter()
        self.examples = {}

    def violation(self, what, detail=""):
        with self.lock:
            self.violations[what] += 1
            self.examples.setdefault(what, detail)

    def event(self, what, n=1):
        with self.lock:
            self.events[what] += n

    def served(self, kind, group, seconds, exception=None, accepted=False):
        with self.lock:
            self.answered[kind] += 1
            if exception is not None:
                self.exceptions[exception] += 1
            if accepted:
                self.accepted += 1
            self.slowest[group] = max(self.slowest[group], seconds)
            self.by_group[group] += 1

    def doubt(self):
        with self.lock:
            self.in_doubt += 1

    def count_sent(self, kind):
        with self.lock:
            self.sent[kind] += 1


class Quiet:
    """The blackout: participants call checkpoint() before each request; hold() returns once
    all of them are paused (or have ended)."""

    def __init__(self, stop):
        self.cv = threading.Condition()
        self.stop = stop
        self.requested = False
        self.paused = 0
        self.participants = 0

    def join(self):
        with self.cv:
            self.participants += 1

    def leave(self):
        with self.cv:
            self.participants -= 1
            self.cv.notify_all()

    def checkpoint(self):
        """Waits while a blackout is on; True when it did."""
        with self.cv:
            if not self.requested:
                return False
            self.paused += 1
            self.cv.notify_all()
            while self.requested and not self.stop.is_set():
                self.cv.wait(0.1)
            self.paused -= 1
            return True

    def hold(self, timeout):
        with self.cv:
            self.requested = True
            end = time.monotonic() + timeout
            while self.paused < self.participants and time.monotonic() < end and not self.stop.is_set():
                self.cv.wait(0.05)
            return self.paused >= self.participants

    def release(self):
        with self.cv:
            self.requested = False
            self.cv.notify_all()


# ---------------------------------------------------------------------------------------------
# Clients

class Client(threading.Thread):
    group = "client"
    pauses = True  # takes part in the blackout

    def __init__(self, soak, name):
        super().__init__(name=name, daemon=True)
        self.soak, self.tally, self.stop = soak, soak.tally, soak.stop
        self.rng = random.Random(f"{soak.seed}-{name}")
        self.link = None

    def run(self):
        if self.pauses:
            self.soak.quiet.join()
        try:
            self.body()
        except Exception as e:  # noqa: BLE001 - a client's own failure is a finding of the run
            self.tally.violation(f"{self.name}: client failed", repr(e))
        finally:
            if self.link:
                self.link.close()
            if self.pauses:
                self.soak.quiet.leave()

    def checkpoint(self):
        return self.pauses and self.soak.quiet.checkpoint()

    def connect(self):
        if self.link:
            self.link.close()
        self.link = Link(self.soak.port)
        self.tally.event("connections opened")
        return self.link

    def closed_by_server(self, link, what):
        """Classifies a close by the server of a connection that was sending `what`. A fresh one
        (no reply yet) was refused for want of a slot: documented, retried. One that asked within
        the eviction time must not have been evicted (nor idle-closed): a violation. One whose
        own pause (a stalled client) reached it may have been: documented."""
        if link.replies == 0:
            self.tally.event(f"{self.group}: refused (no slot), retried")
        elif link.window < EVICT_IDLE_MS / 1000 - 0.05:
            self.tally.violation("client closed by the server although it asked within the eviction time",
                                 f"{self.name} {what}: {link.window * 1e3:.0f} ms since its previous request began")
        else:
            self.tally.event(f"{self.group}: closed by the server after a pause of its own >= 1 s")

    def exchange(self, kind, pdu, write=False):
        """A valid request on the persistent connection, on a new one when the server closed it
        (retried until DEADLINE_S). The reply PDU, or None when only BUSY refused a write."""
        t_first = time.monotonic()
        while True:
            if self.link is None:
                self.connect()
            self.tally.count_sent(kind)
            try:
                reply = self.link.ask(pdu)
            except Closed:
                self.closed_by_server(self.link, kind)
                if write and self.link.replies > 0:
                    self.tally.doubt()  # not read by the server (evicted idle): retried below
                self.link.close()
                self.link = None
                if time.monotonic() - t_first > DEADLINE_S:
                    self.tally.violation("valid request unanswered within the deadline", f"{self.name} {kind}: refused")
                    return None
                self.stop.wait(0.05)  # the client's retry interval
                continue
            except NoReply as e:
                self.tally.violation("valid request unanswered within the deadline", f"{self.name} {kind}: {e}")
                if write:
                    self.tally.doubt()
                self.link.close()
                self.link = None
                return None
            took = time.monotonic() - t_first
            if reply[0] == pdu[0]:
                self.tally.served(kind, self.group, took, accepted=write)
                return reply
            if reply[0] == pdu[0] | 0x80 and len(reply) == 2:
                self.tally.served(kind, self.group, took, exception=reply[1])
                if not (write and reply[1] == BUSY):  # only "queue full" may refuse a valid write
                    self.tally.violation("valid request answered with an exception",
                                         f"{self.name} {kind} {pdu.hex()} -> {reply.hex()}")
                return None
            self.tally.violation("malformed reply", f"{self.name} {kind} {pdu.hex()} -> {reply.hex()}")
            return None

    def write(self, kind, pdu):
        reply = self.exchange(kind, pdu, write=True)
        if reply is not None and reply[:5] != pdu[:5]:
            self.tally.violation("write reply does not echo the request", f"{pdu.hex()} -> {reply.hex()}")
        return reply is not None

    def read_inputs(self, kind="read inputs", address=0, count=INPUT_COUNT):
        reply = self.exchange(kind, read_pdu(address, count))
        if reply is None:
            return None
        if reply[1] != 2 * count or len(reply) != 2 + 2 * count:
            self.tally.violation("malformed reply", f"{self.name} {kind} -> {reply.hex()}")
            return None
        return [0] * address + input_registers(reply)

    def pace(self, period, next_at):
        """Sleeps until next_at (skipping missed slots); the following slot. False when stopping."""
        now = time.monotonic()
        if next_at > now and self.stop.wait(next_at - now):
            return None
        return max(next_at + period, time.monotonic())


class Poller(Client):
    group = "pollers"
    pauses = False

    def body(self):
        last = None
        n = 0
        next_at = time.monotonic()
        while not self.stop.is_set():
            r = self.read_inputs()
            if r is not None:
                now = (u32_at(r, I["tick"]), u32_at(r, I["applied_commands"]), u32_at(r, I["reject_count"]),
                       u32_at(r, I["last_sequence"]))
                if r[I["state"]] not in (0, 1, 2):
                    self.tally.violation("state register out of range", str(r[I["state"]]))
                if r[I["state"]] == 2:
                    self.tally.event("poller saw the amplifier in fault")
                if last is not None:
                    for i, what in enumerate(("tick", "applied commands", "reject count")):
                        if now[i] < last[i]:
                            self.tally.violation(f"{what} went backwards", f"{last[i]} -> {now[i]}")
                    if now[3] < last[3]:
                        self.tally.event("last sequence went backwards (seen by a poller)")
                last = now
            n += 1
            if n % 10 == 0:
                reply = self.exchange("read holding", read_pdu(0, 10, FC_READ_HOLDING))
                if reply is not None and (reply[1] != 20 or len(reply) != 22):
                    self.tally.violation("malformed reply", f"read holding -> {reply.hex()}")
            next_at = self.pace(0.05, next_at)
            if next_at is None:
                return


class SetpointWriter(Client):
    group = "writers"

    def body(self):
        rng = self.rng
        next_at = time.monotonic()
        while not self.stop.is_set():
            self.checkpoint()
            k = rng.random()
            if k < 0.4:
                values = (regs("frequency_setpoint", rng.uniform(38500, 41500)) + regs("amplitude_setpoint", rng.uniform(50, 300))
                          + regs("phase_setpoint", rng.choice((-1, 1)) * rng.uniform(60, 90))
                          + regs("load_force", rng.uniform(0, 1)))
                self.write("write set-points (FC16 x5)", write_multiple(H["frequency_setpoint"], values))
            elif k < 0.6:
                self.write("write amplitude (FC06)", write_single(H["amplitude_setpoint"], regs("amplitude_setpoint", rng.uniform(50, 300))[0]))
            elif k < 0.75:
                self.write("write phase (FC06)", write_single(H["phase_setpoint"], regs("phase_setpoint", rng.choice((-1, 1)) * rng.uniform(60, 90))[0]))
            elif k < 0.9:
                self.write("write frequency (FC16 x2)", write_multiple(H["frequency_setpoint"], regs("frequency_setpoint", rng.uniform(38500, 41500))))
            else:
                values = regs("frequency_slew", rng.choice((1e5, 1e6))) + regs("amplitude_slew", rng.choice((1e4, 1e5)))
                self.write("write slew limits (FC16 x4)", write_multiple(H["frequency_slew"], values))
            next_at = self.pace(0.02, next_at)
            if next_at is None:
                return


class CommandWriter(Client):
    """Keep-alives, enable / disable / reset, and the blackouts."""
    group = "writers"
    pauses = False  # it conducts the blackout

    def command(self, code, kind):
        return self.write(kind, write_single(H["command"], code))

    def state(self):
        r = self.read_inputs("read state", 0, 8)
        return None if r is None else (r[I["state"]], r[I["fault_code"]], u32_at(r, I["reject_count"]))

    def wait_state(self, wanted, timeout=2.0):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            s = self.state()
            if s and s[0] == wanted:
                return s
            time.sleep(0.01)
        return self.state()

    def ensure_enabled(self):
        s = self.state()
        if s and s[0] == 2:
            self.command(3, "reset fault")
        self.command(1, "enable")
        return self.wait_state(1)

    def blackout(self):
        """Everyone else who writes pauses; the watchdog must fault the enabled amplifier; one
        enable is then accepted by the server and rejected by the amplifier."""
        quiet = self.soak.quiet
        s = self.ensure_enabled()
        if not s or s[0] != 1:
            self.tally.violation("blackout: amplifier not enabled before", str(s))
            return
        if not quiet.hold(10.0):
            self.tally.violation("blackout: clients did not pause within 10 s")
            quiet.release()
            return
        try:
            if self.stop.wait(BLACKOUT_QUIET_S):
                return
            self.tally.event("blackouts")
            s = self.wait_state(2, 3.0)  # 0.5 s is 5 watchdog periods; a lagging loop gets 3 s more
            if not s or s[0] != 2 or s[1] != 1:  # fault, command timeout
                self.tally.violation("blackout: watchdog did not fault the amplifier", str(s))
                return
            before = s[2]
            if not self.command(1, "enable (in fault)"):
                return
            r = None
            end = time.monotonic() + 2.0
            while time.monotonic() < end:  # the command is taken at the next tick
                r = self.read_inputs("read state", 0, 8)
                if r and u32_at(r, I["reject_count"]) != before:
                    break
            if r is None or u32_at(r, I["reject_count"]) != before + 1 or r[I["last_reject_reason"]] != REASON["fault_active"]:
                self.tally.violation("blackout: enable in fault not rejected once as 'fault active'", str(r))
            else:
                self.tally.event("amplifier rejects verified (enable in fault)")
            self.command(3, "reset fault")
            self.command(1, "enable")
            s = self.wait_state(1)
            if not s or s[0] != 1:
                self.tally.violation("blackout: not enabled again after reset", str(s))
        finally:
            quiet.release()

    def body(self):
        rng = self.rng
        start = time.monotonic()
        self.ensure_enabled()
        next_blackout = start + BLACKOUT_FIRST_S
        next_action = start + 1.0
        next_at = time.monotonic()
        while not self.stop.is_set():
            now = time.monotonic()
            if now >= next_blackout:
                self.blackout()
                next_blackout += BLACKOUT_EVERY_S
                next_at = time.monotonic()
            elif now >= next_action:
                next_action = now + rng.uniform(0.5, 1.5)
                k = rng.random()
                s = self.state()
                if s and s[0] == 2:  # a fault outside a blackout: the clients stalled > watchdog
                    self.tally.event("fault outside a blackout (reset)")
                    self.command(3, "reset fault")
                if k < 0.6:
                    self.command(1, "enable")
                elif k < 0.8:
                    self.command(2, "disable")
                else:  # enable with set-points in one FC16 (command register + frequency)
                    values = [1] + regs("frequency_setpoint", rng.uniform(38500, 41500))
                    self.write("write enable + frequency (FC16 x3)", write_multiple(H["command"], values))
            else:
                self.command(0, "keep-alive")
            next_at = self.pace(0.02, next_at)
            if next_at is None:
                return


def invalid_catalogue():
    """(kind, PDU, exception code, reject reason) of invalid requests whose framing is intact."""
    h = H
    c = [
        ("out of range: amplitude 700 V", write_single(h["amplitude_setpoint"], regs("amplitude_setpoint", 700)[0]), ILLEGAL_VALUE, "amplitude_out_of_range"),
        ("out of range: frequency 60 kHz", write_multiple(h["frequency_setpoint"], regs("frequency_setpoint", 60000)), ILLEGAL_VALUE, "frequency_out_of_range"),
        ("out of range: frequency 20 kHz", write_multiple(h["frequency_setpoint"], regs("frequency_setpoint", 20000)), ILLEGAL_VALUE, "frequency_out_of_range"),
        ("out of range: phase 200 deg", write_single(h["phase_setpoint"], regs("phase_setpoint", 200)[0]), ILLEGAL_VALUE, "phase_out_of_range"),
        ("out of range: phase -200 deg", write_single(h["phase_setpoint"], regs("phase_setpoint", -200)[0]), ILLEGAL_VALUE, "phase_out_of_range"),
        ("out of range: load 31 N", write_single(h["load_force"], regs("load_force", 31)[0]), ILLEGAL_VALUE, "load_out_of_range"),
        ("out of range: frequency slew 2e7", write_multiple(h["frequency_slew"], u32(20_000_000)), ILLEGAL_VALUE, "slew_out_of_range"),
        ("out of range: one of five set-points", write_multiple(h["frequency_setpoint"], regs("frequency_setpoint", 40000) + regs("amplitude_setpoint", 650) + [0, 0]), ILLEGAL_VALUE, "amplitude_out_of_range"),
        ("unknown command 7", write_single(h["command"], 7), ILLEGAL_VALUE, "unknown_command"),
        ("unknown command 0xFFFF", write_single(h["command"], 0xFFFF), ILLEGAL_VALUE, "unknown_command"),
        ("split 32-bit: FC06 to a low word", write_single(h["frequency_setpoint"] + 1, 5), ILLEGAL_ADDRESS, "split_value"),
        ("split 32-bit: FC06 to a high word", write_single(h["frequency_setpoint"], 0), ILLEGAL_ADDRESS, "split_value"),
        ("split 32-bit: FC16 low word + amplitude", write_multiple(h["frequency_setpoint"] + 1, [0, 100]), ILLEGAL_ADDRESS, "split_value"),
        ("split 32-bit: FC16 load + high word", write_multiple(h["load_force"], [0, 0]), ILLEGAL_ADDRESS, "split_value"),
        ("split 32-bit: FC04 low word", read_pdu(I["reject_count"] + 1, 1), ILLEGAL_ADDRESS, "split_value"),
        ("split 32-bit: FC03 high word", read_pdu(h["amplitude_slew"], 1, FC_READ_HOLDING), ILLEGAL_ADDRESS, "split_value"),
        ("illegal address: FC06 10", write_single(10, 1), ILLEGAL_ADDRESS, "illegal_address"),
        ("illegal address: FC16 past the end", write_multiple(h["amplitude_slew"] + 1, [0, 0]), ILLEGAL_ADDRESS, "illegal_address"),
        ("illegal address: FC03 8+5", read_pdu(8, 5, FC_READ_HOLDING), ILLEGAL_ADDRESS, "illegal_address"),
        ("illegal address: FC04 35", read_pdu(INPUT_COUNT, 1), ILLEGAL_ADDRESS, "illegal_address"),
        ("illegal address: FC04 0+36", read_pdu(0, INPUT_COUNT + 1), ILLEGAL_ADDRESS, "illegal_address"),
        ("bad quantity: FC03 0", read_pdu(0, 0, FC_READ_HOLDING), ILLEGAL_VALUE, "wrong_length"),
        ("bad quantity: FC04 126", read_pdu(0, 126), ILLEGAL_VALUE, "wrong_length"),
        ("bad byte count: FC16 2 regs, 2 bytes", write_multiple(h["phase_setpoint"], [0], quantity=2, byte_count=2), ILLEGAL_VALUE, "wrong_length"),
        ("bad quantity: FC16 0", write_multiple(h["command"], [], quantity=0, byte_count=0), ILLEGAL_VALUE, "wrong_length"),
        ("bad quantity: FC16 124", write_multiple(0, [0] * 123, quantity=124, byte_count=246), ILLEGAL_VALUE, "wrong_length"),
        # Unsupported function codes, each with the body libmodbus frames for it (a body it does
        # not expect would start the next frame).
        ("bad function 01 (read coils)", struct.pack(">BHH", 1, 0, 1), ILLEGAL_FUNCTION, "illegal_function"),
        ("bad function 02 (read discrete)", struct.pack(">BHH", 2, 0, 1), ILLEGAL_FUNCTION, "illegal_function"),
        ("bad function 05 (write coil)", struct.pack(">BHH", 5, 0, 0xFF00), ILLEGAL_FUNCTION, "illegal_function"),
        ("bad function 00", struct.pack(">BHH", 0, 0, 1), ILLEGAL_FUNCTION, "illegal_function"),
        ("bad function 15 (write coils)", struct.pack(">BHHBB", 15, 0, 8, 1, 0xFF), ILLEGAL_FUNCTION, "illegal_function"),
        ("bad function 22 (mask write)", struct.pack(">BHHH", 22, 3, 0xFFFF, 0), ILLEGAL_FUNCTION, "illegal_function"),
        ("bad function 23 (read/write)", struct.pack(">BHHHHBH", 23, 0, 1, 3, 1, 2, 100), ILLEGAL_FUNCTION, "illegal_function"),
        ("bad function 07 (exception status)", bytes([7]), ILLEGAL_FUNCTION, "illegal_function"),
        ("bad function 17 (report id)", bytes([17]), ILLEGAL_FUNCTION, "illegal_function"),
        ("bad function 43 (device id)", bytes([43]), ILLEGAL_FUNCTION, "illegal_function"),
        ("bad function 0x84 (an exception code)", bytes([0x84]), ILLEGAL_FUNCTION, "illegal_function"),
        ("bad function 100", bytes([100]), ILLEGAL_FUNCTION, "illegal_function"),
    ]
    return c


class InvalidWriter(Client):
    """Invalid PDUs on one persistent connection; the reject reason is checked whenever the reject
    count moved by exactly one across the request (no other reject interleaved)."""
    group = "invalid"

    def status(self):
        r = self.read_inputs("read reject status", I["last_reject_reason"], 3)
        return None if r is None else (r[I["last_reject_reason"]], u32_at(r, I["reject_count"]))

    def body(self):
        catalogue = invalid_catalogue()
        self.soak.catalogue_size = len(catalogue)
        order = list(range(len(catalogue)))
        before = None
        next_at = time.monotonic()
        while not self.stop.is_set():
            self.rng.shuffle(order)
            for i in order:
                if self.checkpoint():
                    before = None  # the blackout's amplifier reject came in between
                if self.stop.is_set():
                    return
                kind, pdu, code, reason = catalogue[i]
                if before is None:
                    before = self.status()
                if self.link is None:
                    self.connect()
                self.tally.count_sent(kind)
                t0 = time.monotonic()
                try:
                    reply = self.link.ask(pdu)
                except Closed:
                    self.closed_by_server(self.link, kind)  # never read by the server: not answered
                    self.link.close()
                    self.link = None
                    before = None
                    continue
                except NoReply as e:
                    self.tally.violation("invalid request: no exception reply", f"{kind}: {e!r}")
                    self.link.close()
                    self.link = None
                    before = None
                    continue
                took = time.monotonic() - t0
                if reply[0] == pdu[0] | 0x80 and len(reply) == 2:
                    self.tally.served(kind, self.group, took, exception=reply[1])
                    if reply[1] != code:
                        self.tally.violation("invalid request: wrong exception", f"{kind}: {reply[1]} (expected {code})")
                elif pdu[0] >= 0x80 and reply[0] == (pdu[0] + 0x80) & 0xFF and len(reply) == 2:
                    # An exception whose function byte wrapped (0x84 + 0x80 -> 0x04): a client
                    # reads it as a malformed FC04 reply. Still an exception for the ledger.
                    self.tally.served(kind, self.group, took, exception=reply[1])
                    self.tally.violation("exception reply with a wrapped function code", f"{kind}: {reply.hex()}")
                else:
                    self.tally.served(kind, self.group, took, accepted=pdu[0] in (FC_WRITE_SINGLE, FC_WRITE_MULTIPLE))
                    self.tally.violation("invalid request answered normally", f"{kind}: {reply.hex()}")
                after = self.status()
                if before and after:
                    if after[1] == before[1] + 1:
                        if after[0] != REASON[reason]:
                            self.tally.violation("invalid request: wrong reject reason", f"{kind}: {after[0]} (expected {REASON[reason]})")
                        else:
                            with self.tally.lock:
                                self.tally.expected[(kind, code)] += 1
                    else:
                        self.tally.event("reject reason not checked (another reject interleaved)")
                before = after
                next_at = self.pace(0.025, next_at)
                if next_at is None:
                    return


class FramingClient(Client):
    """Framing faults, one new connection each."""
    group = "framing"

    def case_truncated_silent(self, link):
        frame = mbap(1, read_pdu(0, INPUT_COUNT))
        cut = self.rng.randrange(1, len(frame))
        link.send(frame[:cut])
        t0 = time.monotonic()
        if link.wait_closed(DEADLINE_S):
            took = time.monotonic() - t0
            if took < FRAME_TIMEOUT_MS / 1000 - 0.05:
                self.tally.violation("truncated frame closed before the frame timeout", f"{took:.3f} s")
            self.soak.expected_frame_timeouts += 1
            return "closed after the frame timeout"
        self.tally.violation("truncated frame: connection not closed within the deadline")
        return None

    def case_truncated_hangup(self, link):
        frame = mbap(1, write_multiple(H["frequency_setpoint"], regs("frequency_setpoint", 40000)))
        link.send(frame[:self.rng.randrange(1, len(frame))])
        return "client hung up"

    def answered(self, link, kind, pdu, exception=None, **header):
        """The reply PDU to `pdu` (None when closed or unanswered): a normal reply, or with
        `exception` that exception under the function code."""
        self.tally.count_sent(kind)
        t0 = time.monotonic()
        try:
            reply = link.ask(pdu, **header)
        except Closed:
            self.closed_by_server(link, kind)
            return None
        except NoReply as e:
            self.tally.violation(f"{kind}: no reply", repr(e))
            return None
        self.tally.served(kind, self.group, time.monotonic() - t0, exception=exception)
        expected = pdu[:1] if exception is None else bytes([pdu[0] | 0x80, exception])
        if reply[:len(expected)] != expected:
            self.tally.violation(f"{kind}: unexpected reply", reply.hex())
            return None
        return reply

    def refused_header(self, link, kind, frame):
        """A frame whose MBAP header contradicts it: no reply, the connection closed at once and
        counted as "bad header" (docs/emulator.md)."""
        self.tally.count_sent(kind)
        try:
            link.send(frame)
        except Closed:
            self.soak.expected_bad_headers += 1
            return "closed at once, not answered"
        try:
            adu = link.reply()
        except Closed:
            self.soak.expected_bad_headers += 1
            return "closed at once, not answered"
        except NoReply as e:
            self.tally.violation(f"{kind}: connection not closed within the deadline", repr(e))
            return None
        self.tally.violation(f"{kind}: answered", adu.hex())
        return None

    def case_mbap_length(self, link):
        # A length field shorter than the frame, or beyond an ADU: closed at once. One longer than
        # the frame (200) announces bytes that never come: closed at the frame timeout.
        pdu = read_pdu(0, INPUT_COUNT)
        length = self.rng.choice((0, 1, 2, 3, 200, 0xFFFF))
        if length != 200:
            return self.refused_header(link, "MBAP length wrong (PDU whole)", mbap(1, pdu, length=length))
        self.tally.count_sent("MBAP length announcing bytes never sent")
        link.send(mbap(1, pdu, length=length))
        t0 = time.monotonic()
        if link.wait_closed(DEADLINE_S):
            if time.monotonic() - t0 < FRAME_TIMEOUT_MS / 1000 - 0.05:
                self.tally.violation("MBAP length + missing bytes: closed before the frame timeout")
            self.soak.expected_frame_timeouts += 1
            return "closed after the frame timeout"
        self.tally.violation("MBAP length + missing bytes: connection not closed within the deadline")
        return None

    def case_protocol_id(self, link):
        return self.refused_header(link, "MBAP protocol id not 0", mbap(1, read_pdu(0, 4), protocol=0x1234))

    def answered_then_usable(self, link, kind, pdu, exception):
        """A request the MBAP length frames whole but libmodbus frames shorter: the server reads the
        rest, answers `exception` under the function code, and the connection stays in step."""
        if self.answered(link, kind, pdu, exception=exception) is None:
            return None
        if self.answered(link, f"{kind}: next request", read_pdu(I["state"], 1)) is None:
            return None
        return f"exception {exception:02x}, connection kept in step"

    def case_mbap_surplus(self, link):
        # FC04 and 2 more bytes, counted by the MBAP length: a supported function code with a
        # body longer than its own: exception 03 (wrong length).
        return self.answered_then_usable(link, "MBAP length + surplus bytes", read_pdu(0, 4) + b"\x00\x00", 3)

    def case_device_identification(self, link):
        # FC43/14 Read Device Identification with its body (libmodbus frames FC43 without one;
        # HMIs probe it on connect): exception 01.
        return self.answered_then_usable(link, "FC43 read device id (with its body)", b"\x2b\x0e\x01\x00", 1)

    def case_too_long(self, link):
        # FC16 announcing 250 data bytes: 263 bytes, more than an ADU (260): closed at once.
        try:
            link.send(mbap(1, struct.pack(">BHHB", 16, 0, 125, 250) + bytes(250), length=257))
        except Closed:
            self.soak.expected_too_long += 1
            return "closed"  # already while sending
        if link.wait_closed(DEADLINE_S):
            self.soak.expected_too_long += 1
            return "closed"
        self.tally.violation("too long frame: connection not closed within the deadline")
        return None

    def case_pipelined(self, link):
        n = self.rng.randrange(2, 6)
        tids = list(range(100, 100 + n))
        self.tally.event("pipelined requests", n)
        t0 = time.monotonic()
        link.send(b"".join(mbap(t, read_pdu(0, INPUT_COUNT)) for t in tids))
        link.mark_sent(t0)
        for t in tids:
            self.tally.count_sent("pipelined read")
            t0 = time.monotonic()
            try:
                adu = link.reply()
            except Closed:
                self.closed_by_server(link, "pipelined read")
                return None
            except NoReply as e:
                self.tally.violation("pipelined requests: reply missing", repr(e))
                return None
            self.tally.served("pipelined read", self.group, time.monotonic() - t0)
            if struct.unpack(">H", adu[:2])[0] != t or adu[7] != FC_READ_INPUT:
                self.tally.violation("pipelined requests: reply out of order", adu[:9].hex())
        return "answered in order"

    def body(self):
        cases = [self.case_truncated_silent, self.case_truncated_hangup, self.case_mbap_length,
                 self.case_protocol_id, self.case_mbap_surplus, self.case_device_identification,
                 self.case_too_long, self.case_pipelined]
        while not self.stop.is_set():
            self.checkpoint()
            case = self.rng.choice(cases)
            name = case.__name__[5:].replace("_", " ")
            t_first = time.monotonic()
            while True:  # a free slot first: a refused connection is retried
                link = Link(self.soak.port)
                self.tally.event("connections opened")
                # Ask once: when all slots are taken the server closes at once (no slot).
                self.tally.count_sent("framing: slot probe read")
                try:
                    link.ask(read_pdu(I["state"], 1))
                    self.tally.served("framing: slot probe read", self.group, 0.0)
                    break
                except NoReply as e:
                    self.tally.violation("valid request unanswered within the deadline", f"framing probe: {e}")
                    break
                except Closed:
                    self.closed_by_server(link, "framing: slot probe read")
                    link.close()
                    if time.monotonic() - t_first > DEADLINE_S:
                        self.tally.violation("framing client: no slot within the deadline")
                        break
                    self.stop.wait(0.05)
            try:
                outcome = case(link)
            finally:
                link.close()
            if outcome:
                self.soak.framing[(name, outcome)] += 1
            if self.stop.wait(self.rng.uniform(0.5, 1.0)):
                return


class Churner(Client):
    group = "churn"

    def body(self):
        rng = self.rng
        while not self.stop.is_set():
            self.checkpoint()
            t_first = time.monotonic()
            attempts = 0
            while not self.stop.is_set():
                attempts += 1
                self.connect()
                self.tally.count_sent("churn: first read")
                try:
                    reply = self.link.ask(read_pdu(0, INPUT_COUNT))
                except Closed:
                    self.closed_by_server(self.link, "churn: first read")
                    if time.monotonic() - t_first > DEADLINE_S:
                        self.tally.violation("valid request unanswered within the deadline", f"{self.name}: {attempts} attempts")
                        break
                    self.stop.wait(0.05)
                    continue
                except NoReply as e:
                    self.tally.violation("valid request unanswered within the deadline", f"{self.name}: {e}")
                    break
                took = time.monotonic() - t_first
                self.tally.served("churn: first read", self.group, took)
                if reply[0] != FC_READ_INPUT:
                    self.tally.violation("malformed reply", reply.hex())
                for _ in range(rng.randrange(0, 5)):
                    k = rng.random()
                    if k < 0.5:
                        self.read_inputs("churn: read inputs")
                    elif k < 0.75:
                        self.exchange("churn: read holding", read_pdu(0, 10, FC_READ_HOLDING))
                    else:
                        self.write("churn: keep-alive", write_single(H["command"], 0))
                break
            if self.link:
                self.link.close()
                self.link = None
            if self.stop.wait(rng.uniform(0.1, 0.3)):
                return


class Holders(Client):
    """HOLDERS connections opened and left idle, each reopened 0.5-3 s after the server closed it;
    and every BURST_EVERY_S a burst of BURST more, left idle and not reopened: the server must
    close those beyond the free slots at once (no slot) or evict idle holders for them."""
    group = "holders"
    pauses = False

    def body(self):
        rng = self.rng
        open_ = {}  # socket -> opened at
        bursts = set()
        reopen = [time.monotonic() + i * 0.1 for i in range(HOLDERS)]
        next_burst = time.monotonic() + BURST_EVERY_S / 2
        while not self.stop.is_set():
            now = time.monotonic()
            due = [t for t in reopen if t <= now]
            if now >= next_burst:
                next_burst += BURST_EVERY_S
                self.tally.event("holders: bursts")
                due += [None] * BURST
            for t in due:
                if t is not None:
                    reopen.remove(t)
                try:
                    s = socket.create_connection(("127.0.0.1", self.soak.port), timeout=DEADLINE_S)
                except OSError as e:
                    self.tally.violation("holder: cannot connect", repr(e))
                    reopen.append(now + 1.0)
                    continue
                open_[s] = now
                if t is None:
                    bursts.add(s)
                self.tally.event("connections opened")
                self.tally.event("holders: opened")
            ready, _, _ = select.select(list(open_), [], [], 0.1) if open_ else ([], [], [])
            if not open_:
                self.stop.wait(0.1)
            for s in ready:
                try:
                    data = s.recv(64)
                except ConnectionResetError:
                    data = b""
                if data:
                    self.tally.violation("holder: data from the server", data.hex())
                lived = time.monotonic() - open_.pop(s)
                s.close()
                if lived < 0.5:
                    self.tally.event("holders: closed at once (no slot)")
                elif lived < IDLE_TIMEOUT_MS / 1000 - 0.2:
                    self.tally.event("holders: closed after 0.5 s .. idle timeout (evicted)")
                else:
                    self.tally.event("holders: closed after the idle timeout")
                if s in bursts:
                    bursts.discard(s)
                else:
                    reopen.append(time.monotonic() + rng.uniform(0.5, 3.0))
        for s in open_:
            s.close()


# ---------------------------------------------------------------------------------------------
# Resources of the emulator process

def sample(pid):
    """VmRSS (kB), threads, open fds, of which sockets."""
    rss = threads = None
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                rss = int(line.split()[1])
            elif line.startswith("Threads:"):
                threads = int(line.split()[1])
    fds = sockets = 0
    for fd in os.listdir(f"/proc/{pid}/fd"):
        try:
            target = os.readlink(f"/proc/{pid}/fd/{fd}")
        except FileNotFoundError:
            continue
        fds += 1
        sockets += target.startswith("socket:")
    return {"rss_kb": rss, "threads": threads, "fds": fds, "sockets": sockets}


def category(kind):
    """The row of the summary table a request kind is counted in."""
    for prefix, name in (("out of range", "invalid: value out of range (03)"), ("unknown command", "invalid: value out of range (03)"),
                         ("split", "invalid: split 32-bit value (02)"), ("illegal address", "invalid: illegal address (02)"),
                         ("bad quantity", "invalid: quantity / byte count (03)"), ("bad byte count", "invalid: quantity / byte count (03)"),
                         ("bad function", "invalid: function code (01)"),
                         ("MBAP length + surplus", "framing: a body beyond what libmodbus frames (answered)"),
                         ("FC43", "framing: a body beyond what libmodbus frames (answered)"),
                         ("MBAP", "framing: MBAP header wrong (closed, not answered)"),
                         ("write", "valid writes"), ("churn: keep-alive", "valid writes"), ("keep-alive", "valid writes"),
                         ("enable", "valid writes"), ("disable", "valid writes"), ("reset", "valid writes")):
        if kind.startswith(prefix):
            return name
    return "valid reads"


def parse_exit_report(text):
    def num(pattern, group=1, cast=int):
        m = re.search(pattern, text)
        return cast(m.group(group)) if m else None
    report = {
        "stopped_by": num(r"swum-emu stopped: (\w+)", cast=str),
        "wall_s": num(r"emulated in ([\d.]+) s wall", cast=float),
        "emulated_s": num(r"after ([\d.]+) s emulated", cast=float),
        "applied": num(r"commands applied (\d+)"),
        "rejected": num(r"commands applied \d+, rejected (\d+)"),
        "queue_full": num(r"\(queue full (\d+)\)"),
        "requests": num(r"modbus +(\d+) requests"),
        "exceptions": num(r"modbus +\d+ requests, (\d+) exceptions"),
        "connections": num(r"exceptions, (\d+) connections"),
        "ticks": num(r"loop statistics: (\d+) ticks"),
        "taken": num(r"commands +(\d+); accept-to-effect"),
        "overruns": num(r"overruns +(\d+)"),
        "resyncs": num(r"resyncs +(\d+)"),
        "lateness": num(r"lateness +(p50 .*)", cast=str),
    }
    m = re.search(r"modbus tcp closed: (.*)", text)
    report["closed"] = {k: int(v) for k, v in re.findall(r"([a-z ]+?) (\d+)(?:,\s*|$)", m.group(1))} if m else {}
    return report


# ---------------------------------------------------------------------------------------------

class Soak:
    def __init__(self, args):
        self.args = args
        self.seed = args.seed
        self.tally = Tally()
        self.stop = threading.Event()
        self.quiet = Quiet(self.stop)
        self.framing = collections.Counter()
        self.expected_frame_timeouts = 0
        self.expected_bad_headers = 0
        self.expected_too_long = 0
        self.catalogue_size = 0
        self.samples = []
        self.port = None

    def take_sample(self, t0, label=""):
        s = sample(self.pid)
        s["t_s"] = round(time.monotonic() - t0, 1)
        s["label"] = label
        self.samples.append(s)
        return s

    def final_registers(self):
        """Input registers once the queue drained: read until the tick moved on twice (every
        command accepted before the first read is taken at the next tick boundary)."""
        end = time.monotonic() + 30
        while time.monotonic() < end:
            link = Link(self.port)
            self.tally.event("connections opened")
            try:
                first = None
                while time.monotonic() < end:
                    self.tally.count_sent("final read (queue drained)")
                    r = input_registers(link.ask(read_pdu(0, INPUT_COUNT)))
                    self.tally.served("final read (queue drained)", "final", 0.0)
                    first = first or r
                    if u32_at(r, I["tick"]) >= u32_at(first, I["tick"]) + 2:
                        return r
                    time.sleep(0.01)
            except Closed:
                time.sleep(0.1)  # refused: a slot is freed as the holders' connections are closed
            finally:
                link.close()
        return None

    def run(self):
        a = self.args
        duration = a.minutes * 60.0
        warmup = min(60.0, duration / 4)
        load_start = os.getloadavg()
        emu_harness.EMU = a.emu
        print(f"soak: {a.minutes:g} min of mixed Modbus TCP traffic against {a.emu}")
        print(f"machine: {os.cpu_count()} CPUs, load {load_start[0]:.2f} {load_start[1]:.2f} {load_start[2]:.2f}; seed {a.seed}")
        print(f"emulator options: --config config/li2019.toml --modbus tcp://127.0.0.1:0 {' '.join(EMU_ARGS)}", flush=True)
        try:
            emu = Emulator(*EMU_ARGS)
        except (RuntimeError, OSError) as e:
            print(f"soak: {e}", file=sys.stderr)
            return 2
        self.emu, self.pid, self.port = emu, emu.proc.pid, emu.port
        print(f"swum-emu pid {self.pid}, listening on 127.0.0.1:{self.port}", flush=True)
        stderr_lines = []
        drain = threading.Thread(target=lambda: stderr_lines.extend(emu.proc.stderr), daemon=True)
        drain.start()  # the emulator's own log must never fill the pipe and block it
        t0 = time.monotonic()
        baseline = self.take_sample(t0, "start (no client)")
        clients = [Poller(self, "poller-1"), Poller(self, "poller-2"), SetpointWriter(self, "setpoints"),
                   CommandWriter(self, "commands"), InvalidWriter(self, "invalid"), FramingClient(self, "framing"),
                   Churner(self, "churn-1"), Churner(self, "churn-2")]
        for c in clients:
            c.start()
        time.sleep(1.0)  # the persistent clients hold their slots before the idle holders arrive
        holders = Holders(self, "holders")
        holders.start()
        clients.append(holders)
        crashed = False
        next_sample = t0 + SAMPLE_EVERY_S
        while time.monotonic() < t0 + duration:
            if emu.proc.poll() is not None:
                crashed = True
                break
            time.sleep(max(0.0, min(0.5, next_sample - time.monotonic())))
            if time.monotonic() >= next_sample:
                s = self.take_sample(t0)
                print(f"  t={s['t_s']:6.0f} s  RSS {s['rss_kb']} kB  threads {s['threads']}  fds {s['fds']} "
                      f"(sockets {s['sockets']})  requests answered {sum(self.tally.answered.values())}", flush=True)
                next_sample += SAMPLE_EVERY_S
        t_traffic = time.monotonic() - t0
        self.stop.set()
        self.quiet.release()
        for c in clients:
            c.join(30)
            if c.is_alive():
                self.tally.violation("client did not stop within 30 s", c.name)
        final = None
        if not crashed and emu.proc.poll() is None:
            final = self.final_registers()
            if final is None:
                self.tally.violation("final registers could not be read")
            # Every client has gone: the fds and threads must come back to the baseline.
            end = time.monotonic() + 15
            while time.monotonic() < end:
                s = sample(self.pid)
                if s["fds"] == baseline["fds"] and s["threads"] == baseline["threads"]:
                    break
                time.sleep(0.1)
            self.take_sample(t0, "end (clients gone)")
            os.kill(self.pid, signal.SIGTERM)
        else:
            crashed = True
        try:
            emu.proc.wait(30)
        except Exception:  # noqa: BLE001
            emu.proc.kill()
            self.tally.violation("emulator did not exit within 30 s of SIGTERM")
        output = emu.ready + emu.proc.stdout.read()
        drain.join(5)
        rc = emu.proc.returncode
        if crashed:
            self.tally.violation("emulator crashed", f"exit status {rc}")
        elif rc != 0:
            self.tally.violation("emulator exit status not 0", str(rc))
        report = parse_exit_report(output)
        load_end = os.getloadavg()
        return self.conclude(output, report, final, stderr_lines, t_traffic, warmup, load_start, load_end)

    # -----------------------------------------------------------------------------------------
    def check_resources(self, warmup):
        """Rules, after the warm-up (connection threads, malloc arenas and libmodbus contexts have
        all been created by then; from there on the process allocates nothing per request or per
        connection that it does not free):
         - RSS never exceeds the highest warm-up sample by more than RSS_TOLERANCE_KB (2 MiB):
           a leak of 16 bytes a request or 1 kB a connection over the 10-minute run exceeds it;
           the tolerance covers glibc's reuse of cached thread stacks and arena pages;
         - open fds: non-socket fds never change from the start; sockets never exceed the
           listener + 2 x 16 connections (holders + as many being closed); threads never exceed
           the start + 32;
         - once the clients have gone, fds and threads are exactly those at the start."""
        base = self.samples[0]
        during = [s for s in self.samples[1:] if not s["label"]]
        warm = [s for s in during if s["t_s"] <= warmup] or during[:1]
        after = [s for s in during if s["t_s"] > warmup]
        checks = []
        if warm and after:
            ceiling = max(s["rss_kb"] for s in warm) + RSS_TOLERANCE_KB
            peak = max(s["rss_kb"] for s in after)
            checks.append((f"RSS after warm-up <= warm-up max + {RSS_TOLERANCE_KB} kB", peak <= ceiling, f"{peak} <= {ceiling} kB"))
        for s in during:
            if s["fds"] - s["sockets"] != base["fds"] - base["sockets"]:
                self.tally.violation("non-socket fds changed", str(s))
            if s["sockets"] > 1 + 2 * SLOTS:
                self.tally.violation("more sockets than the listener + 2 x 16", str(s))
            if s["threads"] > base["threads"] + 2 * SLOTS:
                self.tally.violation("more threads than the start + 32", str(s))
        end = self.samples[-1]
        if end["label"]:
            checks.append(("fds at the end = at the start", end["fds"] == base["fds"], f"{base['fds']} -> {end['fds']}"))
            checks.append(("threads at the end = at the start", end["threads"] == base["threads"], f"{base['threads']} -> {end['threads']}"))
        for what, ok, detail in checks:
            if not ok:
                self.tally.violation(what, detail)
        return checks

    def conclude(self, output, report, final, stderr_lines, t_traffic, warmup, load_start, load_end):
        t = self.tally
        exc_total = sum(t.exceptions.values())
        answered = sum(t.answered.values())
        rows = []  # (measure, value, check)

        def check(what, ok, detail):
            rows.append((what, detail, "ok" if ok else "VIOLATED"))
            if not ok:
                t.violation(what, detail)

        if final is not None and report.get("applied") is not None:
            applied, rejects, last_seq = u32_at(final, I["applied_commands"]), u32_at(final, I["reject_count"]), u32_at(final, I["last_sequence"])
            amp_rejected = rejects - exc_total
            qf = report["queue_full"]
            busy = t.exceptions.get(BUSY, 0)
            lost = t.accepted - (applied + amp_rejected)
            if t.in_doubt == 0:
                check("accepted = applied + amplifier-rejected (registers)", lost == 0,
                      f"{t.accepted} = {applied} + {amp_rejected} (lost {lost})")
            else:
                check("accepted <= applied + amplifier-rejected <= accepted + in doubt", -t.in_doubt <= lost <= 0,
                      f"{t.accepted} <= {applied} + {amp_rejected} <= {t.accepted} + {t.in_doubt}")
            # Every sequence number drawn went to a command the loop took or to a queue-full refusal.
            check("last sequence = applied + amplifier-rejected + queue-full refusals", last_seq == applied + amp_rejected + qf,
                  f"{last_seq} = {applied} + {amp_rejected} + {qf}")
            check("exit report: applied = registers", report["applied"] == applied, f"{report['applied']} = {applied}")
            check("exit report: rejected = registers", report["rejected"] == rejects, f"{report['rejected']} = {rejects}")
            check("exit report: amplifier-rejected = rejected - exceptions",
                  report["rejected"] - report["exceptions"] == amp_rejected,
                  f"{report['rejected']} - {report['exceptions']} = {amp_rejected}")
            check("exit report: exceptions = exception replies received", report["exceptions"] == exc_total,
                  f"{report['exceptions']} = {exc_total}")
            check("exit report: queue full = BUSY replies", qf == busy, f"{qf} = {busy}")
            # The loop's accept-to-effect count: one per command taken, at most 64 a tick (fewer
            # than taken only when more than 64 piled up during a stall of the loop).
            check("exit report: commands taken by the loop <= accepted (= when no tick took > 64)",
                  report["taken"] is not None and report["taken"] <= t.accepted, f"{report['taken']} <= {t.accepted}")
            # Every whole frame is served and answered; a truncated or over-long one is not served.
            check("exit report: requests = requests answered", report["requests"] == answered,
                  f"{report['requests']} = {answered}")
            # Every connection the clients opened was accepted: into a slot or closed at once.
            opened = t.events["connections opened"]
            check("exit report: connections + no slot = connections opened",
                  report["connections"] + report["closed"].get("no slot", 0) == opened,
                  f"{report['connections']} + {report['closed'].get('no slot', 0)} = {opened}")
            check("exit report: frame timeouts = those provoked", report["closed"].get("frame timeout") == self.expected_frame_timeouts,
                  f"{report['closed'].get('frame timeout')} = {self.expected_frame_timeouts}")
            check("exit report: bad headers = those sent", report["closed"].get("bad header") == self.expected_bad_headers,
                  f"{report['closed'].get('bad header')} = {self.expected_bad_headers}")
            check("exit report: too long = those sent", report["closed"].get("too long") == self.expected_too_long,
                  f"{report['closed'].get('too long')} = {self.expected_too_long}")
            check("exit report: reply timeouts = 0", report["closed"].get("reply timeout") == 0, str(report["closed"].get("reply timeout")))
            verified = t.events["amplifier rejects verified (enable in fault)"]
            check("amplifier-rejected >= rejects verified in blackouts", amp_rejected >= verified, f"{amp_rejected} >= {verified}")
        resources = self.check_resources(warmup)
        for what, ok, detail in resources:
            rows.append((what, detail, "ok" if ok else "VIOLATED"))

        # ---- summary
        out = []
        out.append("")
        out.append(f"=== swum-emu soak: {t_traffic:.0f} s of traffic, seed {self.seed}, "
                   f"load {load_start[0]:.2f} -> {load_end[0]:.2f} (1-min avg), {os.cpu_count()} CPUs ===")
        out.append("")
        out.append("requests by category                                 sent   answered  as expected")
        cat_sent, cat_answered, cat_expected = collections.Counter(), collections.Counter(), collections.Counter()
        for kind in set(t.sent) | set(t.answered):
            cat_sent[category(kind)] += t.sent[kind]
            cat_answered[category(kind)] += t.answered[kind]
        for (kind, _code), n in t.expected.items():
            cat_expected[category(kind)] += n
        for c in sorted(cat_sent):
            out.append(f"  {c:<48} {cat_sent[c]:>8} {cat_answered[c]:>9}  {cat_expected[c] or '':>9}")
        out.append("  (framing faults that get no answer are counted under 'framing cases' below)")
        out.append("")
        out.append("requests answered per second by client group: " + ", ".join(
            f"{g} {n / t_traffic:.1f}" for g, n in sorted(t.by_group.items()) if g != "final"))
        out.append("")
        out.append("requests by kind                                     sent   answered  as expected")
        kinds = sorted(set(t.sent) | set(t.answered))
        exc_by_kind = collections.Counter()
        for (kind, _code), n in t.expected.items():
            exc_by_kind[kind] += n
        for kind in kinds:
            out.append(f"  {kind:<48} {t.sent[kind]:>8} {t.answered[kind]:>9}  {exc_by_kind[kind] or '':>9}")
        out.append(f"  {'total':<48} {sum(t.sent.values()):>8} {answered:>9}")
        out.append("")
        out.append("exception replies by code: " + ", ".join(f"{c:02d}: {n}" for c, n in sorted(t.exceptions.items())))
        out.append(f"invalid requests answered with the expected code and reason: {sum(t.expected.values())} "
                   f"({self.catalogue_size} kinds)")
        out.append("framing cases: " + "; ".join(f"{k[0]} -> {k[1]}: {n}" for k, n in sorted(self.framing.items())))
        out.append("slowest answer by client group: " + ", ".join(f"{g} {s * 1e3:.0f} ms" for g, s in sorted(t.slowest.items())))
        out.append("events: " + "; ".join(f"{k}: {n}" for k, n in sorted(t.events.items())))
        out.append(f"writes accepted (answered without exception): {t.accepted}; in doubt: {t.in_doubt}")
        if final is not None:
            out.append(f"final registers: applied {u32_at(final, I['applied_commands'])}, rejected {u32_at(final, I['reject_count'])}, "
                       f"last sequence {u32_at(final, I['last_sequence'])}, state {final[I['state']]}")
        out.append("")
        out.append("exit report of swum-emu:")
        out.extend("  | " + line for line in output.splitlines())
        if stderr_lines:
            out.append(f"swum-emu stderr ({len(stderr_lines)} lines):")
            out.extend("  | " + line.rstrip() for line in stderr_lines[:40])
        out.append("")
        out.append("resources of swum-emu (every 10 s):  t [s]   RSS [kB]  threads  fds (sockets)")
        for s in self.samples:
            out.append(f"  {s['t_s']:>36.0f} {s['rss_kb']:>10} {s['threads']:>8} {s['fds']:>5} ({s['sockets']}) {s['label']}")
        out.append("")
        out.append("checks:")
        for what, detail, verdict in rows:
            out.append(f"  {verdict:<9} {what}: {detail}")
        out.append("")
        if t.violations:
            out.append(f"VIOLATIONS ({sum(t.violations.values())}):")
            for what, n in t.violations.most_common():
                out.append(f"  {n:>6} x {what}: {t.examples[what]}")
            out.append("soak: FAIL")
        else:
            out.append("soak: PASS (no command lost or applied twice, every valid request answered, every invalid one "
                       "refused as it should, resources flat)")
        print("\n".join(out), flush=True)
        if self.args.json:
            with open(self.args.json, "w") as f:
                json.dump({"seed": self.seed, "traffic_s": t_traffic, "load": [load_start, load_end],
                           "sent": t.sent, "answered": t.answered, "exceptions": t.exceptions,
                           "accepted": t.accepted, "in_doubt": t.in_doubt, "events": t.events,
                           "framing": {f"{k[0]} -> {k[1]}": n for k, n in self.framing.items()},
                           "final_registers": final, "exit_report": report, "samples": self.samples,
                           "slowest_s": t.slowest, "checks": rows, "by_group": t.by_group,
                           "violations": {k: [n, t.examples[k]] for k, n in t.violations.items()}}, f, indent=1)
        return 1 if t.violations else 0


def main():
    p = argparse.ArgumentParser(prog="tools/soak", description=__doc__.split("\n")[0])
    p.add_argument("--minutes", type=float, default=10.0, help="traffic duration (default 10)")
    p.add_argument("--emu", default=os.path.join(SOURCE_DIR, "build/release/firmware_sim/swum-emu"),
                   help="swum-emu binary (default: the release build)")
    p.add_argument("--seed", type=int, default=1, help="seed of the clients' random choices")
    p.add_argument("--json", help="also write the figures to this file")
    a = p.parse_args()
    if a.minutes <= 0:
        p.error("--minutes must be positive")
    if not os.access(a.emu, os.X_OK):
        print(f"soak: no {a.emu} (cmake --preset release && cmake --build --preset release --target swum-emu)", file=sys.stderr)
        return 2
    return Soak(a).run()


if __name__ == "__main__":
    sys.exit(main())
