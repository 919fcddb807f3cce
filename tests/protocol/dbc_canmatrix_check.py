#!/usr/bin/python3
"""Independent cross-check of config/swum.dbc against the C++ encoder: python3-canmatrix decodes
the frames printed by swum_emu_can_vectors and must find the values the code put in; the CRC of
the command frames is recomputed here from the protocol description (CRC-8/SAE-J1850 over the
identifier, little-endian, and bytes 0..6).

usage: dbc_canmatrix_check.py SWUM_EMU_CAN_VECTORS config/swum.dbc
"""
import json
import os
import subprocess
import sys

import canmatrix.formats

# The Python side's one CRC-8/SAE-J1850, written from docs/protocols.md (not the C++ codec's).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench"))
from swum_bench.can_link import crc8_sae_j1850 as crc8  # noqa: E402


def main():
    vectors, dbc_path = sys.argv[1], sys.argv[2]
    db = canmatrix.formats.loadp_flat(dbc_path)
    lines = subprocess.run([vectors], check=True, capture_output=True, text=True).stdout.splitlines()
    failures = 0
    seen = set()
    for line in lines:
        vector = json.loads(line)
        frame = db.frame_by_id(canmatrix.ArbitrationId(vector["id"]))
        if frame is None or frame.name != vector["message"]:
            print(f"FAIL: id {vector['id']:#x}: DBC has {frame and frame.name}, code says {vector['message']}")
            failures += 1
            continue
        seen.add(frame.name)
        data = bytes.fromhex(vector["data"])
        if len(data) != frame.size:
            print(f"FAIL: {frame.name}: code sends {len(data)} bytes, DBC says {frame.size}")
            failures += 1
        decoded = frame.decode(data)
        for name, expected in vector["values"].items():
            value = float(decoded[name].phys_value)
            signal = frame.signal_by_name(name)
            tolerance = float(signal.factor) / 2 + 1e-9
            if abs(value - expected) > tolerance:
                print(f"FAIL: {frame.name}.{name}: canmatrix decodes {value}, code encoded {expected}")
                failures += 1
        if frame.name in ("Command", "AuxCommand") and crc8(vector["id"], data[:7]) != data[7]:
            print(f"FAIL: {frame.name}: CRC {data[7]:#04x} != {crc8(vector['id'], data[:7]):#04x}")
            failures += 1
    missing = {f.name for f in db.frames} - seen
    if missing:
        print(f"FAIL: DBC messages the code never produced: {sorted(missing)}")
        failures += 1
    print(f"{len(lines)} frames checked against {dbc_path}: {failures} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
