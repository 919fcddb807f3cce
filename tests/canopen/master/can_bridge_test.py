#!/usr/bin/python3
"""can_bridge.py on the host, without CAN (ctest canopen.master.bridge): its line parser and
formatter byte for byte, and its failures (a socket that cannot be had, bad usage) as one line
and a non-zero status. The guest's selftest covers the rest on vcan0 (frames through, a bad line)."""
import os
import struct
import subprocess
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import can_bridge  # noqa: E402

BRIDGE = os.path.join(HERE, "can_bridge.py")


def frame(can_id, data=b"", length=None):
    return struct.pack("=IB3x8s", can_id, len(data) if length is None else length, data.ljust(8, b"\0"))


class LineTest(unittest.TestCase):
    def test_standard_frames(self):
        self.assertEqual(can_bridge.parse_line("605#4008100000000000"),
                         frame(0x605, bytes.fromhex("4008100000000000")))
        self.assertEqual(can_bridge.parse_line("080#"), frame(0x080))
        self.assertEqual(can_bridge.parse_line("7ff#0a"), frame(0x7FF, b"\x0a"))

    def test_extended_and_remote_frames(self):
        self.assertEqual(can_bridge.parse_line("1ABCDEF0#01"), frame(0x1ABCDEF0 | 0x80000000, b"\x01"))
        self.assertEqual(can_bridge.parse_line("705#R"), frame(0x705 | 0x40000000, length=0))

    def test_bad_lines(self):
        for bad in ["", "605", "605#4", "605#001122334455667788", "800#00", "20000000#00", "60#00", "605#zz",
                    "605 # 00", "605#00 "]:
            with self.assertRaises(ValueError, msg=bad):
                can_bridge.parse_line(bad)

    def test_format(self):
        self.assertEqual(can_bridge.format_frame(frame(0x185, bytes.fromhex("500209030000"))), "185#500209030000")
        self.assertEqual(can_bridge.format_frame(frame(0x080)), "080#")
        self.assertEqual(can_bridge.format_frame(frame(0x1ABCDEF0 | 0x80000000, b"\xff")), "1ABCDEF0#FF")
        self.assertEqual(can_bridge.format_frame(frame(0x705 | 0x40000000, length=0)), "705#R")
        # A length field above 8 (CAN FD's DLC codes on a classic socket) never reads past the data.
        self.assertEqual(can_bridge.format_frame(frame(0x181, bytes(range(8)), length=15)), "181#0001020304050607")

    def test_round_trip(self):
        for line in ["000#0100", "181#", "5FF#0011223344556677", "00000123#AB", "123#R"]:
            self.assertEqual(can_bridge.format_frame(can_bridge.parse_line(line)), line)


class FailureTest(unittest.TestCase):
    def run_bridge(self, *args, stdin=""):
        return subprocess.run(["/usr/bin/python3", BRIDGE, *args], input=stdin, capture_output=True, text=True,
                              timeout=30)

    def test_no_such_interface(self):
        # Without AF_CAN (this host, perhaps) or without the interface: either way no socket.
        r = self.run_bridge("swumnone0")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertRegex(r.stderr, r"^can_bridge: cannot open swumnone0: [^\n]+\n$")
        self.assertEqual(r.stdout, "")

    def test_usage(self):
        r = self.run_bridge()
        self.assertEqual(r.returncode, 1)
        self.assertEqual(r.stderr, "can_bridge: usage: can_bridge.py IFACE\n")


if __name__ == "__main__":
    unittest.main()
