#!/usr/bin/python3
"""A minimal external controller for the bench's own tests, written with pymodbus alone: it
connects to the endpoint it is given, then each cycle writes holding registers 0..10 (enable,
set-points, advance) and reads the input table. Its first BAD cycles (default 1) ask for an
out-of-range frequency (the emulator refuses them, exception 03), the rest are valid.

  tiny_controller.py tcp://HOST:PORT CYCLE_TICKS CYCLES [BAD]"""
import sys
import types

try:
    import serial_asyncio  # noqa: F401
except ImportError:
    sys.modules["serial_asyncio"] = types.SimpleNamespace(create_serial_connection=None)
from pymodbus.client import ModbusTcpClient  # noqa: E402


def words(frequency_hz, amplitude_v, ticks):
    mhz = int(frequency_hz * 1000)
    # command, frequency (u32 mHz, high word first), amplitude (0.1 V), phase (0.01 deg),
    # load, frequency slew (u32), amplitude slew (u32), advance
    return [1, mhz >> 16, mhz & 0xFFFF, int(amplitude_v * 10), 9000, 0, 0x000F, 0x4240, 0x0001, 0x86A0, ticks]


def main():
    host, port = sys.argv[1].removeprefix("tcp://").rsplit(":", 1)
    ticks, cycles = int(sys.argv[2]), int(sys.argv[3])
    bad = int(sys.argv[4]) if len(sys.argv) > 4 else 1
    client = ModbusTcpClient(host, port=int(port), timeout=600, retries=0)
    if not client.connect():
        sys.exit(f"tiny_controller: cannot connect to {sys.argv[1]}")
    for cycle in range(cycles):
        reply = client.write_registers(0, words(20000.0 if cycle < bad else 40000.0, 100.0, ticks), slave=1)
        if reply.isError() and cycle >= bad:
            sys.exit(f"tiny_controller: cycle {cycle} refused: {reply}")
        client.read_input_registers(0, 45, slave=1)
    client.close()


if __name__ == "__main__":
    main()
