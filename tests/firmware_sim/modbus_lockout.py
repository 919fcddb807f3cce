#!/usr/bin/python3
"""No client locks the others out of swum-emu's Modbus TCP server (docs/emulator.md, "Modbus: no
client locks the others out"). Raw sockets on 127.0.0.1, frames built here from
docs/protocols.md; the server's counts are read from its exit report.

usage: modbus_lockout.py SCENARIO   (idle_holders trickle idle_timeout reply_stall stalled_server options)
Environment: SWUM_EMU, SWUM_SOURCE_DIR (set by ctest).

No sleep waits for the server: every wait is a select() on a socket with a deadline. The pauses
a client makes between its own bytes or attempts are the stimulus, not a wait for a result.
"""
import os
import re
import select
import signal
import socket
import struct
import subprocess
import sys
import threading
import time

from emu_harness import CONFIG, EMU, Emulator, RegisterMap, deadline

MAP = RegisterMap()
SLOTS = 16            # docs/emulator.md
FRAME_TIMEOUT_S = 0.5  # default --modbus-frame-timeout-ms
EVICT_IDLE_S = 1.0     # default --modbus-evict-idle-ms
READ_STATE = struct.pack(">BHH", 4, MAP.input["state"]["address"], 1)  # FC04, one register


def mbap(transaction, pdu, unit=1):
    return struct.pack(">HHHB", transaction, 0, len(pdu) + 1, unit) + pdu


def connect(emu):
    s = socket.create_connection((emu.host, emu.port), timeout=5)
    s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return s


def closed_by_server(s, timeout):
    """True when the server closed `s` (end of stream or reset) within `timeout` s."""
    ready, _, _ = select.select([s], [], [], timeout)
    if not ready:
        return False
    try:
        return s.recv(512, socket.MSG_PEEK) == b""
    except ConnectionResetError:
        return True


def read_reply(s, timeout):
    """One Modbus TCP reply on `s`, or None when the server closed the connection first."""
    data = b""
    expired = deadline(timeout)
    while len(data) < 7 or len(data) < 6 + struct.unpack(">H", data[4:6])[0]:
        ready, _, _ = select.select([s], [], [], 0.2)
        if ready:
            try:
                chunk = s.recv(512)
            except ConnectionResetError:
                return None
            if not chunk:
                return None
            data += chunk
        assert not expired(), f"no reply within {timeout} s: {data.hex()}"
    return data


def ask(s, transaction=1):
    """Reads the state register on an open connection; the reply PDU, or None if closed."""
    s.sendall(mbap(transaction, READ_STATE))
    reply = read_reply(s, 5)
    if reply is None:
        return None
    assert struct.unpack(">H", reply[:2])[0] == transaction and reply[7] == 4, reply.hex()
    return reply[7:]


def drops(output):
    """The server's own closes by reason, from the exit report."""
    m = re.search(r"modbus tcp closed: (.*)", output)
    assert m, output
    return {k: int(v) for k, v in re.findall(r"([a-z ]+?) (\d+)(?:,\s*|$)", m.group(1))}


def connections(output):
    m = re.search(r"modbus +\d+ requests, \d+ exceptions, (\d+) connections", output)
    assert m, output
    return int(m.group(1))


def scenario_idle_holders():
    """40 connections opened and left idle, then a valid client: those beyond the 16 slots are
    closed at once; the newcomer is served, at the latest once a holder has been idle for the
    eviction time (1 s), evicting the longest-idle holder."""
    # The idle timeout out of the way (60 s): here only eviction and "no slot" close connections.
    with Emulator("--watchdog-ms", "0", "--modbus-idle-timeout-ms", "60000") as emu:
        opened = time.monotonic()  # the first holder's connect: no holder is idle longer
        holders = [connect(emu) for _ in range(40)]
        # Those beyond the slots are closed at once (the server never reads from them).
        expired = deadline(10)
        while sum(closed_by_server(s, 0) for s in holders) < 40 - SLOTS:
            select.select(holders, [], [], 0.1)
            assert not expired(), "connections beyond the slots were not closed"
        t0 = time.monotonic()
        attempts = refused = 0
        while True:
            attempts += 1
            client = connect(emu)
            pdu = ask(client)
            if pdu is not None:
                break
            refused += 1
            client.close()
            assert time.monotonic() - t0 < EVICT_IDLE_S + 1.5, f"not served after {attempts} attempts"
            select.select([], [], [], 0.05)  # the client's retry interval
        served_after = time.monotonic() - t0
        print(f"valid client served after {served_after * 1e3:.0f} ms, {attempts} attempt(s)")
        # Documented: served once a holder has been idle 1 s, plus the retry interval; 0.5 s more
        # for a loaded machine. And never before a holder was idle that long (no early eviction).
        assert served_after < EVICT_IDLE_S + 1.5, served_after
        assert time.monotonic() - opened >= EVICT_IDLE_S - 0.01, time.monotonic() - opened
        assert ask(client, 2) is not None, "the served client was cut off"
        # It took the slot of one idle holder: 15 holders remain, 25 were closed.
        expired = deadline(10)
        while sum(closed_by_server(s, 0) for s in holders) < 40 - (SLOTS - 1):
            select.select(holders, [], [], 0.1)
            assert not expired(), "no holder was evicted"
        closed = sum(closed_by_server(s, 0) for s in holders)
        assert closed == 40 - (SLOTS - 1), closed
        client.close()
        for s in holders:
            s.close()
        assert emu.stop() == 0
    counts, accepted = drops(emu.output), connections(emu.output)
    print(emu.output)
    print(f"closed by the server: {counts}; accepted {accepted}; client attempts {attempts}")
    assert counts["idle"] == 0 and counts["frame timeout"] == 0 and counts["reply timeout"] == 0, counts
    # Every connection was either taken into a slot or closed at once for want of one ...
    assert accepted + counts["no slot"] == 40 + attempts, (accepted, counts, attempts)
    assert counts["no slot"] >= refused, (counts, refused)
    # ... and every one taken beyond the first 16 evicted a holder.
    assert counts["evicted"] == accepted - SLOTS >= 1, (accepted, counts)


def scenario_trickle():
    """A client sending a request one byte every 100 ms is cut off after the frame timeout
    (0.5 s); meanwhile another client is served."""
    with Emulator("--watchdog-ms", "0") as emu:
        other = connect(emu)
        assert ask(other) is not None
        request = mbap(7, READ_STATE)
        result = {}
        started = threading.Event()

        def trickler():
            s = connect(emu)
            t0 = time.monotonic()
            sent = 0
            for byte in request:
                s.sendall(bytes([byte]))
                sent += 1
                started.set()
                if closed_by_server(s, 0.1):  # one byte every 100 ms; stop when cut off
                    result["cut_after_s"] = time.monotonic() - t0
                    break
            else:
                result["reply"] = read_reply(s, 5)
            result["sent"] = sent
            s.close()

        thread = threading.Thread(target=trickler)
        thread.start()
        assert started.wait(10)
        served = 0
        while thread.is_alive():
            assert ask(other, served + 2) is not None, "the other client was cut off"
            served += 1
        thread.join()
        print(f"trickler: {result}; other client served {served} times meanwhile")
        assert "reply" not in result, f"a trickled request was served: {result}"
        assert result["sent"] < len(request), result
        assert result["cut_after_s"] >= FRAME_TIMEOUT_S, result
        assert served > 0
        assert ask(other, 1) is not None
        other.close()
        assert emu.stop() == 0
    counts = drops(emu.output)
    print(emu.output)
    assert counts == {"no slot": 0, "evicted": 0, "idle": 0, "frame timeout": 1, "reply timeout": 0, "bad header": 0, "too long": 0}, counts


def scenario_idle_timeout():
    """--modbus-idle-timeout-ms 300: a connection that says nothing and one that stops asking
    are closed; one that keeps asking (every 100 ms) is not."""
    with Emulator("--watchdog-ms", "0", "--modbus-idle-timeout-ms", "300") as emu:
        silent = connect(emu)
        quiet = connect(emu)
        busy = connect(emu)
        # Taken before the request: the server's idle clock starts when it handles the request,
        # which is after this instant, so its close cannot come earlier than 300 ms from here
        # (after the reply it could: the reply's transit and this process's wake-up count).
        t_quiet = time.monotonic()
        assert ask(quiet) is not None
        asked = 0
        expired = deadline(10.0)
        open_idle = [silent, quiet]
        while open_idle:
            assert ask(busy, asked + 2) is not None, "a client asking every 100 ms was closed"
            asked += 1
            assert not expired(), "idle connections were not closed within 10 s"
            # The busy client's polling interval. Only connections still open are watched: a
            # closed one is readable at once and would turn this into a busy loop.
            select.select(open_idle, [], [], 0.1)
            open_idle = [s for s in open_idle if not closed_by_server(s, 0)]
        quiet_for = time.monotonic() - t_quiet
        print(f"idle connections closed; the quiet one after {quiet_for * 1e3:.0f} ms, busy client asked {asked} times")
        assert quiet_for >= 0.3, quiet_for
        assert ask(busy, 1) is not None
        for s in (silent, quiet, busy):
            s.close()
        assert emu.stop() == 0
    counts = drops(emu.output)
    print(emu.output)
    assert counts["idle"] == 2 and counts["no slot"] == 0 and counts["evicted"] == 0, counts


def scenario_reply_stall():
    """A client that sends requests and never reads the replies: once the socket buffers are
    full the server's reply cannot be sent; the connection is closed after the frame timeout
    instead of holding its slot (and thread) for ever. Another client is served meanwhile."""
    with Emulator("--watchdog-ms", "0") as emu:
        staller = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        staller.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)  # before connect: a small window
        staller.connect((emu.host, emu.port))
        staller.setblocking(False)
        read_all = struct.pack(">BHH", 4, 0, MAP.input_count)  # the largest reply: fills buffers fastest
        chunk = b"".join(mbap(i & 0xFFFF, read_all) for i in range(1000))
        other = connect(emu)
        expired = deadline(60)
        cut = False
        while not cut:
            _, writable, _ = select.select([], [staller], [], 0.2)
            if writable:
                try:
                    staller.send(chunk)
                except BlockingIOError:
                    pass
                except (BrokenPipeError, ConnectionResetError):
                    cut = True
            else:
                # Nothing can be sent: the server no longer reads. It must close the connection.
                cut = closed_by_server(staller, 0) or cut
                if not cut:
                    try:
                        staller.send(b"\0")
                    except BlockingIOError:
                        pass
                    except (BrokenPipeError, ConnectionResetError):
                        cut = True
            assert ask(other) is not None, "the other client was cut off"
            assert not expired(), "a client that never reads its replies kept its connection"
        staller.close()
        assert ask(other) is not None
        other.close()
        assert emu.stop() == 0
    counts = drops(emu.output)
    print(emu.output)
    assert counts["reply timeout"] == 1 and counts["idle"] == 0, counts


def scenario_stalled_server():
    """Idle time ends at the first byte of the next request, also when the server has not run to
    read it yet (a starved or descheduled process; here SIGSTOP). 16 clients hold every slot and
    each sends a request while the server stands still for longer than the eviction time; then a
    newcomer connects (the kernel completes it in the listen backlog). On SIGCONT the newcomer is
    closed for want of a slot, never an active client with its request waiting. The same with a
    1 s idle timeout and no newcomer: nobody is closed. Found by tools/soak; before the fix an
    active client was evicted in about 7 rounds of 10, so each case runs 3 rounds."""
    for idle_ms, newcomer_too in (("60000", True), ("1000", False)):
        for round_ in range(3):
            with Emulator("--watchdog-ms", "0", "--modbus-idle-timeout-ms", idle_ms) as emu:
                clients = [connect(emu) for _ in range(SLOTS)]
                for i, s in enumerate(clients):
                    assert ask(s, i) is not None
                os.kill(emu.proc.pid, signal.SIGSTOP)
                try:
                    # The stimulus: the server stands still, past the eviction time or the idle
                    # timeout, while the clients ask.
                    select.select([], [], [], (EVICT_IDLE_S if newcomer_too else int(idle_ms) / 1000) + 0.5)
                    for i, s in enumerate(clients):
                        s.sendall(mbap(100 + i, READ_STATE))
                    newcomer = connect(emu) if newcomer_too else None
                finally:
                    os.kill(emu.proc.pid, signal.SIGCONT)
                for i, s in enumerate(clients):
                    reply = read_reply(s, 10)
                    assert reply is not None, f"idle {idle_ms} ms, round {round_}: client {i} closed with its request waiting"
                    assert struct.unpack(">H", reply[:2])[0] == 100 + i, reply.hex()
                if newcomer:
                    assert closed_by_server(newcomer, 10), "the newcomer was neither served nor closed"
                    newcomer.close()
                for s in clients:
                    s.close()
                assert emu.stop() == 0
            counts = drops(emu.output)
            print(f"idle {idle_ms} ms, round {round_}: closed by the server: {counts}")
            assert counts["evicted"] == 0 and counts["idle"] == 0 and counts["reply timeout"] == 0, counts
            assert counts["no slot"] == (1 if newcomer_too else 0), counts


def scenario_options():
    """Bad values: one line on stderr naming the option and the text, exit status 1."""
    for option, value in [("--modbus-idle-timeout-ms", "abc"), ("--modbus-idle-timeout-ms", "-5"),
                          ("--modbus-idle-timeout-ms", "1.5"), ("--modbus-frame-timeout-ms", "0"),
                          ("--modbus-frame-timeout-ms", "500ms"), ("--modbus-evict-idle-ms", "99999999999"),
                          ("--modbus-evict-idle-ms", "")]:
        r = subprocess.run([EMU, "--config", CONFIG, "--modbus", "tcp://127.0.0.1:0", option, value],
                           capture_output=True, text=True, timeout=30)
        lines = r.stderr.splitlines()
        print(f"{option} {value!r}: exit {r.returncode}: {r.stderr.strip()}")
        assert r.returncode == 1 and len(lines) == 1 and r.stdout == "", (r.returncode, r.stdout, r.stderr)
        assert option in lines[0] and f"'{value}'" in lines[0], lines
    # Good values start (and the defaults are as documented).
    with Emulator("--modbus-idle-timeout-ms", "0", "--modbus-frame-timeout-ms", "86400000",
                  "--modbus-evict-idle-ms", "0", "--duration-s", "0.01", "--speedup", "0") as emu:
        assert emu.wait() == 0
    help_text = subprocess.run([EMU, "--help"], capture_output=True, text=True, timeout=30).stdout
    for option, default in [("--modbus-idle-timeout-ms", 10000), ("--modbus-frame-timeout-ms", 500),
                            ("--modbus-evict-idle-ms", 1000)]:
        assert re.search(rf"{option} MS={default}\b", help_text), (option, help_text)


if __name__ == "__main__":
    name = sys.argv[1] if len(sys.argv) > 1 else "idle_holders"
    globals()["scenario_" + name]()
    print(f"PASS {name}")
