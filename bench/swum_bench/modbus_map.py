"""The Modbus register table, read from config/modbus_registers.json: the bench's own encoding
and decoding of docs/protocols.md, written apart from the C++ codec so that it checks the
emulator's side (32-bit values high word first, each register big-endian; raw * scale)."""
import json
import math
import os

from .installation import data_dir

_TYPES = {"uint16": (1, False), "int16": (1, True), "uint32": (2, False), "int32": (2, True)}


class Register:
    def __init__(self, entry):
        self.name = entry["name"]
        self.address = int(entry["address"])
        self.type = entry["type"]
        if self.type not in _TYPES:
            raise ValueError(f"modbus_registers.json: register {self.name}: unknown type {self.type!r}")
        self.words, self.signed = _TYPES[self.type]
        self.scale = float(entry["scale"])
        self.unit = entry.get("unit", "")

    def decode(self, words):
        """Physical value of the register's words (a list of 16-bit values at self.address...)."""
        if len(words) < self.words:
            raise ValueError(f"{self.name}: {len(words)} word(s) given, the register has {self.words}")
        raw = 0
        for w in words[: self.words]:
            raw = (raw << 16) | (int(w) & 0xFFFF)
        bits = 16 * self.words
        if self.signed and raw >= 1 << (bits - 1):
            raw -= 1 << bits
        return raw * self.scale

    def encode(self, value):
        """The words of a physical value, rounded to the nearest count; out of the type's range is
        an error (the bench never writes a wrapped value)."""
        if not math.isfinite(value):
            raise ValueError(f"{self.name}: {value!r} is not a finite number")
        raw = int(round(value / self.scale))
        bits = 16 * self.words
        lo, hi = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if self.signed else (0, (1 << bits) - 1)
        if not lo <= raw <= hi:
            raise ValueError(f"{self.name}: {value!r} {self.unit} is outside the register's range")
        if raw == 0 and value != 0 and self.name.endswith("_slew"):
            raise ValueError(f"{self.name}: {value!r} {self.unit} rounds to 0, which means unlimited")
        raw &= (1 << bits) - 1
        return [(raw >> (16 * (self.words - 1 - i))) & 0xFFFF for i in range(self.words)]


class ModbusMap:
    def __init__(self, path):
        with open(path) as f:
            table = json.load(f)
        self.holding = {e["name"]: Register(e) for e in table["holding_registers"]}
        self.inputs = {e["name"]: Register(e) for e in table["input_registers"]}
        self.reasons = {int(k): v for k, v in table["reason_codes"].items()}
        self.input_count = max(r.address + r.words for r in self.inputs.values())
        self.holding_count = max(r.address + r.words for r in self.holding.values())

    def decode_inputs(self, words):
        """{name: physical value} of a read of input registers 0..input_count-1."""
        return {name: r.decode(words[r.address: r.address + r.words]) for name, r in self.inputs.items()}

    def decode_holding(self, words, first=0):
        """{name: value} of the holding registers wholly inside words (starting at `first`)."""
        out = {}
        for name, r in self.holding.items():
            i = r.address - first
            if 0 <= i and i + r.words <= len(words):
                out[name] = r.decode(words[i: i + r.words])
        return out

    def encode_holding(self, values):
        """Words for holding registers 0..holding_count-1 from {name: physical value}; every
        register must be given (one FC16 sets them all atomically)."""
        words = [0] * self.holding_count
        missing = set(self.holding) - set(values)
        if missing:
            raise ValueError(f"holding registers not given: {sorted(missing)}")
        unknown = set(values) - set(self.holding)
        if unknown:
            raise ValueError(f"no such holding registers: {sorted(unknown)}")
        for name, value in values.items():
            r = self.holding[name]
            words[r.address: r.address + r.words] = r.encode(value)
        return words


def default_path(data_directory=None):
    """modbus_registers.json of the data directory (installation.data_dir() unless given)."""
    return os.path.join(data_directory or data_dir() or "", "modbus_registers.json")
