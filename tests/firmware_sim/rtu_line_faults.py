#!/usr/bin/python3
"""swum-emu's Modbus RTU server is not wedged by what a bad line carries (docs/emulator.md,
"Modbus: no client locks the others out"): garbage, frames for other units, a frame cut short,
a frame too long for RTU, a master trickling one byte every 100 ms (each byte ends in silence: a
partial frame) and one trickling faster than the inter-character gap (cut at the frame deadline).
After each the emulator answers a valid request; the exit report counts each discard.

The emulator is the slave on a pseudo-terminal, this script the master (frames built here, CRC
from rtu_integration.py). Waits for the emulator are select() calls with deadlines; the pauses
between a master's own bytes are the stimulus.
"""
import os
import random
import re
import select
import struct
import sys
import time
import tty

from emu_harness import Emulator, RegisterMap, deadline
from rtu_integration import crc16

MAP = RegisterMap()
UNIT = 7
FRAME_TIMEOUT_MS = 50  # --modbus-frame-timeout-ms: a request's deadline is this + a 256-byte frame's time
GAP_S = 0.020          # a silence this long inside a frame ends it (115200 baud)


def frame(unit, pdu):
    return bytes([unit]) + pdu + crc16(bytes([unit]) + pdu)


def read_answer(fd, timeout):
    """Bytes the emulator sends within `timeout` s (then until a 0.1 s silence)."""
    reply = b""
    while True:
        ready, _, _ = select.select([fd], [], [], timeout if not reply else 0.1)
        if not ready:
            return reply
        reply += os.read(fd, 512)


def served(fd, what, attempts=5):
    """A valid read is answered, retrying like a master whose request fell into the emulator's
    resynchronisation after the fault (each attempt waits 1 s)."""
    request = frame(UNIT, struct.pack(">BHH", 4, MAP.input["state"]["address"], 1))
    for attempt in range(1, attempts + 1):
        os.write(fd, request)
        reply = read_answer(fd, 1.0)
        if reply:
            assert len(reply) == 7 and reply[:3] == bytes([UNIT, 4, 2]) and crc16(reply[:-2]) == reply[-2:], reply.hex()
            print(f"after {what}: answered (attempt {attempt})")
            return
    raise AssertionError(f"no answer after {what} in {attempts} attempts")


def silent(fd, seconds):
    """The emulator answers nothing for `seconds` (a master's pause, also a check)."""
    assert read_answer(fd, seconds) == b"", "answered a frame it should have discarded"


def trickle(fd, data, interval_s):
    """Writes `data` one byte every `interval_s` s; nothing may come back."""
    for b in data:
        os.write(fd, bytes([b]))
        ready, _, _ = select.select([fd], [], [], interval_s)
        assert not ready, "answered a trickled frame"


def main():
    master, slave = os.openpty()
    tty.setraw(master)
    path = os.ttyname(slave)
    rng = random.Random(14)
    read_state = frame(UNIT, struct.pack(">BHH", 4, MAP.input["state"]["address"], 1))
    with Emulator("--watchdog-ms", "0", "--modbus-unit", str(UNIT), "--modbus-frame-timeout-ms", str(FRAME_TIMEOUT_MS),
                  modbus=f"rtu:{path}:115200") as emu:
        served(master, "start")
        # Garbage: 600 random bytes in one burst.
        os.write(master, bytes(rng.randrange(256) for _ in range(600)))
        served(master, "garbage")
        # Well-formed frames for other units (and a reply-like frame of another unit): ignored.
        for unit in (8, 247, 1):
            os.write(master, frame(unit, struct.pack(">BHH", 3, 0, 10)))
            silent(master, 0.2)
        served(master, "frames for other units")
        # A frame cut short: its first 5 bytes, then the master's silence.
        os.write(master, read_state[:5])
        silent(master, 0.3)
        served(master, "a partial frame")
        # A frame too long for RTU: FC16 announcing 250 data bytes (259 in all).
        os.write(master, bytes([UNIT, 16, 0, 3, 0, 125, 250]) + bytes(20))
        silent(master, 0.3)
        served(master, "a frame too long")
        # One byte every 100 ms: every byte ends in silence, none of it is a request.
        trickle(master, read_state, 0.1)
        served(master, "a 100 ms trickle")
        # Faster than the gap (a byte every 2 ms) for 1.5 s: a frame that never ends within its
        # deadline (50 ms + 22 ms); a write of 100 registers whose data bytes are 0xFF.
        long_write = frame(UNIT, struct.pack(">BHHB", 16, 0, 100, 200) + b"\xff" * 200)
        t0 = time.monotonic()
        while time.monotonic() - t0 < 1.5:
            trickle(master, long_write[:20], 0.002)
        served(master, "a 2 ms trickle")
        # Nothing the faults carried was applied.
        values = None
        request = frame(UNIT, struct.pack(">BHH", 4, 0, MAP.input_count))
        expired = deadline(10)
        while values is None:
            os.write(master, request)
            reply = read_answer(master, 1.0)
            if reply:
                values = MAP.decode_inputs(list(struct.unpack(f">{MAP.input_count}H", reply[3:-2])))
            assert not expired(), "no answer"
        assert values["applied_commands"] == 0 and values["state"] == 0, values
        assert emu.stop() == 0
    os.close(master)
    os.close(slave)
    print(emu.output)
    m = re.search(r"modbus rtu discarded: (.*)", emu.output)
    assert m, emu.output
    counts = {k: int(v) for k, v in re.findall(r"([a-z ]+?) (\d+)(?:,\s*|$)", m.group(1))}
    print(counts)
    assert counts["other unit"] >= 3, counts
    for reason in ("bad crc", "bad length", "partial frame", "frame timeout"):
        assert counts[reason] >= 1, (reason, counts)
    assert counts["partial frame"] >= len(read_state), counts  # the 100 ms trickle: one per byte
    print("PASS rtu line faults")


if __name__ == "__main__":
    sys.exit(main())
