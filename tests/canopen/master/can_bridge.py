#!/usr/bin/python3
"""One SocketCAN bus as text lines, for the npm canopen master (lib/bus.js), which has no CAN I/O.

usage: can_bridge.py IFACE

stdin:  one frame per line to send, in cansend's notation: "ID#HEX" with ID three hex digits
        (standard, 11 bits) or eight (extended, 29 bits) and HEX 0-8 bytes as pairs of hex digits,
        or "ID#R" / "ID#Rn" for a remote frame (n: its DLC, 0-8). End of input ends the bridge (status 0).
stdout: every frame received on IFACE, one "ID#HEX" line each (upper case), flushed at once.
        The bridge's own frames are not echoed (SocketCAN's default: CAN_RAW_RECV_OWN_MSGS off).
stderr: "can_bridge: listening on IFACE" once the socket is bound (frames sent to the bus from
        then on are seen), then nothing unless it fails.

A bad line, or a socket that cannot be opened, bound, read or written, ends the bridge with one
line on stderr naming what and why, status 1 (bad line) or 2 (socket). Python's standard library
only (socket.AF_CAN): nothing to install in the test guest.
"""
import os
import re
import socket
import struct
import sys
import threading

# struct can_frame (linux/can.h): id, length, 3 bytes padding/reserved, 8 data bytes.
CAN_FRAME = struct.Struct("=IB3x8s")
CAN_EFF_FLAG = 0x80000000
CAN_RTR_FLAG = 0x40000000
CAN_ERR_FLAG = 0x20000000
LINE = re.compile(r"([0-9A-Fa-f]{3}|[0-9A-Fa-f]{8})#(R[0-8]?|(?:[0-9A-Fa-f]{2}){0,8})")


def fail(status, message):
    """One line on stderr, then exit at once (from either thread)."""
    sys.stderr.write(f"can_bridge: {message}\n")
    sys.stderr.flush()
    os._exit(status)


def parse_line(text):
    """'ID#HEX' -> struct can_frame bytes; raises ValueError naming the problem."""
    m = LINE.fullmatch(text)
    if not m:
        raise ValueError(f"bad frame line {text!r} (expected ID#HEX: 3 or 8 hex digits, '#', 0-8 hex byte pairs, or R with an optional DLC 0-8)")
    can_id = int(m.group(1), 16)
    if len(m.group(1)) == 3:
        if can_id > 0x7FF:
            raise ValueError(f"bad frame line {text!r}: a standard identifier is at most 7FF")
    else:
        if can_id > 0x1FFFFFFF:
            raise ValueError(f"bad frame line {text!r}: an extended identifier is at most 1FFFFFFF")
        can_id |= CAN_EFF_FLAG
    if m.group(2).startswith("R"):
        return CAN_FRAME.pack(can_id | CAN_RTR_FLAG, int(m.group(2)[1:] or "0"), bytes(8))
    data = bytes.fromhex(m.group(2))
    return CAN_FRAME.pack(can_id, len(data), data.ljust(8, b"\0"))


def format_frame(raw):
    """struct can_frame bytes -> 'ID#HEX'."""
    can_id, length, data = CAN_FRAME.unpack(raw)
    if can_id & CAN_EFF_FLAG:
        ident = f"{can_id & 0x1FFFFFFF:08X}"
    else:
        ident = f"{can_id & 0x7FF:03X}"
    if can_id & CAN_RTR_FLAG:
        return f"{ident}#R"
    return f"{ident}#{data[:min(length, 8)].hex().upper()}"


def receive_forever(sock, out):
    while True:
        try:
            raw = sock.recv(CAN_FRAME.size)
        except OSError as e:
            fail(2, f"receive failed: {e.strerror or e}")
        if len(raw) != CAN_FRAME.size:
            fail(2, f"receive returned {len(raw)} bytes, not a classic CAN frame")
        if CAN_FRAME.unpack(raw)[0] & CAN_ERR_FLAG:
            continue  # error frames are only delivered when asked for; skip them if they come
        try:
            out.write(format_frame(raw).encode() + b"\n")
            out.flush()
        except BrokenPipeError:
            os._exit(0)  # the master is gone: nothing left to do


def main(argv):
    if len(argv) != 2 or not argv[1]:
        fail(1, "usage: can_bridge.py IFACE")
    iface = argv[1]
    try:
        sock = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 20)  # a slow reader loses nothing
        sock.bind((iface,))
    except OSError as e:
        fail(2, f"cannot open {iface}: {e.strerror or e}")
    threading.Thread(target=receive_forever, args=(sock, sys.stdout.buffer), daemon=True).start()
    sys.stderr.write(f"can_bridge: listening on {iface}\n")
    sys.stderr.flush()
    for number, line in enumerate(sys.stdin.buffer, start=1):
        text = line.decode("ascii", errors="replace").strip()
        try:
            frame = parse_line(text)
        except ValueError as e:
            fail(1, f"line {number}: {e}")
        try:
            sock.send(frame)
        except OSError as e:
            fail(2, f"send of {text} failed: {e.strerror or e}")
    os._exit(0)  # end of input; the receive thread dies with the process


if __name__ == "__main__":
    main(sys.argv)
