"""The drive's object dictionary as the bench reads it from config/swum.eds (CiA 306), with
Python's configparser: every object's type, access, PDO mapping, default (with $NODEID resolved)
and limits, and the unit its name carries. The bench's CANopen master takes all of these from
the file, so it holds no copy of a number the EDS holds; what the EDS cannot say (the data
types' sizes, CiA 301 Table 44) is written here once.

Values on the bus are little-endian (CiA 301 7.1.2); encode()/decode() turn a Python number into
an object's bytes and back, refusing what its type or its limits cannot hold."""
import configparser
import math
import re
import struct

from .signals import BenchUsageError

# CiA 301 Table 44: data type index -> (name, struct format or None for a string, signed)
DATA_TYPES = {
    0x0001: ("BOOLEAN", "<B", False),
    0x0002: ("INTEGER8", "<b", True),
    0x0003: ("INTEGER16", "<h", True),
    0x0004: ("INTEGER32", "<i", True),
    0x0005: ("UNSIGNED8", "<B", False),
    0x0006: ("UNSIGNED16", "<H", False),
    0x0007: ("UNSIGNED32", "<I", False),
    0x0008: ("REAL32", "<f", True),
    0x0009: ("VISIBLE_STRING", None, False),
    0x000A: ("OCTET_STRING", None, False),
}
_VAR, _ARRAY, _RECORD = 0x7, 0x8, 0x9  # CiA 306 ObjectType
_UNIT = re.compile(r"\(([^()]+)\)\s*$")  # "Drive frequency actual (mHz)" -> "mHz"


class EdsError(ValueError):
    """The EDS file does not say what the bench needs (a missing key, a bad number)."""


def _number(text, node, where):
    """A CiA 306 number: decimal, 0x hex or 0 octal, optionally "$NODEID+" before it."""
    text = text.strip()
    base = 0
    if text.upper().startswith("$NODEID"):
        rest = text[len("$NODEID"):].strip()
        if rest and not rest.startswith("+"):
            raise EdsError(f"{where}: {text!r}: only $NODEID+value is understood")
        base = node
        text = rest[1:].strip() if rest else "0"
    try:
        value = int(text, 0) if not re.fullmatch(r"0[0-7]+", text) else int(text, 8)
    except ValueError:
        raise EdsError(f"{where}: {text!r} is not a number") from None
    return base + value


class Entry:
    """One sub-index of the dictionary."""

    def __init__(self, index, sub, name, data_type, access, pdo_mapping, default, low, high):
        self.index, self.sub, self.name = index, sub, name
        self.data_type, self.access, self.pdo_mapping = data_type, access, pdo_mapping
        self.default, self.low, self.high = default, low, high
        self.type_name, self.format, self.signed = DATA_TYPES[data_type]
        m = _UNIT.search(name)
        self.unit = m.group(1) if m else ""

    def __repr__(self):
        return f"Entry(0x{self.index:04X} sub {self.sub} {self.name!r} {self.type_name} {self.access})"

    @property
    def where(self):
        return f"0x{self.index:04X} sub {self.sub} ({self.name})"

    @property
    def bits(self):
        """Its length in a PDO mapping (CiA 301 7.5.2.36); None for a string."""
        return None if self.format is None else 8 * struct.calcsize(self.format)

    @property
    def readable(self):
        return self.access in ("ro", "rw", "rww", "rwr", "const")

    @property
    def writable(self):
        return self.access in ("rw", "rww", "rwr", "wo")

    def mapping_entry(self):
        """The 32-bit mapping entry index << 16 | sub << 8 | length in bits (CiA 301 7.5.2.36)."""
        return self.index << 16 | self.sub << 8 | self.bits

    def encode(self, value):
        """The object's bytes for a value: a number for a numeric type (an integer type takes an
        integer, or a float with no fraction), str or bytes for a string. A value that the type
        or the EDS limits do not hold is a ValueError naming the object."""
        if self.format is None:
            data = value.encode("latin-1") if isinstance(value, str) else bytes(value)
            return data
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"{self.where}: {value!r} is not a number")
        if self.format == "<f":
            if not math.isfinite(value):
                raise ValueError(f"{self.where}: {value!r} is not a finite number")
            return struct.pack(self.format, value)
        if isinstance(value, float):
            if not math.isfinite(value) or value != int(value):
                raise ValueError(f"{self.where}: {value!r} is not an integer count")
            value = int(value)
        bits = self.bits
        lo, hi = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if self.signed else (0, (1 << bits) - 1)
        if self.low is not None:
            lo = max(lo, self.low)
        if self.high is not None:
            hi = min(hi, self.high)
        if not lo <= value <= hi:
            raise ValueError(f"{self.where}: {value} is outside {lo}..{hi}")
        return struct.pack(self.format, value)

    def decode(self, data):
        """The value of the object's bytes (exactly its length for a number)."""
        if self.format is None:
            return bytes(data).decode("latin-1") if self.data_type == 0x0009 else bytes(data)
        size = struct.calcsize(self.format)
        if len(data) != size:
            raise ValueError(f"{self.where}: {len(data)} bytes, the type {self.type_name} has {size}")
        return struct.unpack(self.format, bytes(data))[0]


class Eds:
    """The objects of an EDS file for one node: entries[(index, sub)]."""

    def __init__(self, path, node):
        if isinstance(node, bool) or not isinstance(node, int) or not 1 <= node <= 127:
            raise BenchUsageError(f"CANopen node id must be 1..127 (CiA 301), not {node!r}")
        self.path = path
        self.node = node
        parser = configparser.ConfigParser(interpolation=None, strict=True)
        parser.optionxform = str.lower
        try:
            with open(path, encoding="latin-1") as f:
                parser.read_file(f)
        except configparser.Error as e:
            raise EdsError(f"{path}: {e}") from None
        self.entries = {}
        sections = {s.upper(): s for s in parser.sections()}
        for key, section in sections.items():
            m = re.fullmatch(r"([0-9A-F]{4})(SUB([0-9A-F]+))?", key)
            if not m:
                continue  # FileInfo, DeviceInfo, the object lists...
            index = int(m.group(1), 16)
            values = parser[section]
            kind = _number(values.get("objecttype", "0x7"), node, f"{path} [{section}] ObjectType")
            if m.group(2) is None and kind in (_ARRAY, _RECORD):
                continue  # the container: its sub-indices are sections of their own
            sub = int(m.group(3), 16) if m.group(2) else 0
            self.entries[(index, sub)] = self._entry(path, section, values, index, sub)
        if not self.entries:
            raise EdsError(f"{path}: no objects")

    def _entry(self, path, section, values, index, sub):
        where = f"{path} [{section}]"

        def need(key):
            if key not in values:
                raise EdsError(f"{where}: no {key}")
            return values[key]

        data_type = _number(need("datatype"), self.node, f"{where} DataType")
        if data_type not in DATA_TYPES:
            raise EdsError(f"{where}: data type 0x{data_type:04X} is not one the bench reads")
        numeric = DATA_TYPES[data_type][1] is not None
        default_text = values.get("defaultvalue", "")
        if numeric and DATA_TYPES[data_type][1] != "<f":
            default = _number(default_text, self.node, f"{where} DefaultValue") if default_text.strip() else 0
        elif numeric:
            default = float(default_text or 0)
        else:
            default = default_text
        limits = [_number(values[k], self.node, f"{where} {k}") if values.get(k, "").strip() else None
                  for k in ("lowlimit", "highlimit")]
        return Entry(index, sub, values.get("parametername", ""), data_type, need("accesstype").strip().lower(),
                     _number(values.get("pdomapping", "0"), self.node, f"{where} PDOMapping") == 1, default,
                     *limits)

    def __getitem__(self, key):
        index, sub = key if isinstance(key, tuple) else (key, 0)
        try:
            return self.entries[(index, sub)]
        except KeyError:
            raise KeyError(f"{self.path}: no object 0x{index:04X} sub {sub}") from None

    def __contains__(self, key):
        return (key if isinstance(key, tuple) else (key, 0)) in self.entries

    def default(self, index, sub=0):
        return self[index, sub].default
