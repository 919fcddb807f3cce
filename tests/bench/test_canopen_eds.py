"""The bench's reading of config/swum.eds (canopen_eds.py, configparser): the objects, their
types, access, PDO mapping, defaults ($NODEID resolved) and limits as the file says them, the
units in their names, and the bytes a value becomes on the bus (CiA 301: little-endian)."""
import os
import re

import pytest

from swum_bench import BenchUsageError
from swum_bench.canopen_eds import Eds, EdsError

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
EDS = os.path.join(REPO, "config", "swum.eds")


@pytest.fixture(scope="module")
def eds():
    return Eds(EDS, 5)


def test_every_object_the_file_lists_is_read(eds):
    """Each index of [MandatoryObjects], [OptionalObjects] and [ManufacturerObjects] is there,
    and nothing else (as configparser sees the file, counted apart from Eds)."""
    import configparser
    parser = configparser.ConfigParser(interpolation=None)
    parser.read(EDS, encoding="latin-1")
    listed = {int(v, 16) for s in ("MandatoryObjects", "OptionalObjects", "ManufacturerObjects")
              for k, v in parser[s].items() if k != "supportedobjects"}
    assert {index for index, _ in eds.entries} == listed
    subs = [s for s in parser.sections() if re.fullmatch(r"[0-9A-Fa-f]{4}sub[0-9A-Fa-f]+", s)]
    plain = [s for s in parser.sections() if re.fullmatch(r"[0-9A-Fa-f]{4}", s) and parser[s]["ObjectType"] == "0x7"]
    assert len(eds.entries) == len(subs) + len(plain) == 175


def test_node_id_is_resolved_in_defaults(eds):
    assert eds.default(0x1800, 1) == 0x185
    assert eds.default(0x1403, 1) == 0x505
    assert eds.default(0x1200, 1) == 0x605 and eds.default(0x1200, 2) == 0x585
    assert eds.default(0x1014) == 0x85
    assert eds.default(0x1018, 4) == 5  # serial number: the node id


def test_types_access_mapping_and_limits(eds):
    e = eds[0x6060, 0]
    assert (e.type_name, e.access, e.pdo_mapping, e.low, e.high, e.bits) == ("INTEGER8", "rw", True, -1, 3, 8)
    e = eds[0x2004, 0]
    assert (e.type_name, e.pdo_mapping, e.default, e.unit) == ("UNSIGNED32", False, 1000000, "Hz/s")
    e = eds[0x6041, 0]
    assert (e.access, e.readable, e.writable, e.mapping_entry()) == ("ro", True, False, 0x60410010)
    assert eds[0x1008, 0].type_name == "VISIBLE_STRING"
    assert eds[0x1008, 0].default == "swum-emu bimodal standing-wave ultrasonic motor drive"
    assert eds[0x1008, 0].bits is None
    assert eds[0x60FF, 0].low == -1000000 and eds[0x60FF, 0].high == 1000000


@pytest.mark.parametrize("index, unit", [(0x606C, "um/s"), (0x6064, "um"), (0x2010, "mHz"), (0x2011, "mV"),
                                         (0x2012, "0.01 deg"), (0x2020, "mA"), (0x2027, "0.01 degC"),
                                         (0x6040, "")])
def test_units_are_read_from_the_names(eds, index, unit):
    assert eds[index, 0].unit == unit


def test_unknown_object_is_a_key_error_naming_it(eds):
    with pytest.raises(KeyError, match="no object 0x2099 sub 0"):
        eds[0x2099, 0]
    assert (0x1018, 4) in eds and (0x1018, 5) not in eds and 0x6041 in eds


@pytest.mark.parametrize("index, value, data", [
    (0x2001, 40000000, bytes([0x00, 0x5A, 0x62, 0x02])),   # UNSIGNED32, little-endian
    (0x6060, -1, b"\xff"),                                  # INTEGER8
    (0x2003, -9000, bytes([0xD8, 0xDC])),                   # INTEGER16
    (0x60FF, -300000, bytes([0x20, 0x6C, 0xFB, 0xFF])),     # INTEGER32
    (0x6040, 0x0F, bytes([0x0F, 0x00])),                    # UNSIGNED16
    (0x2001, 3.0, bytes([3, 0, 0, 0])),                     # a float with no fraction is a count
])
def test_encode_and_decode(eds, index, value, data):
    entry = eds[index, 0]
    assert entry.encode(value) == data
    assert entry.decode(data) == int(value)


@pytest.mark.parametrize("index, value, pattern", [
    (0x6060, 4, r"0x6060 sub 0 \(Modes of operation\): 4 is outside -1..3"),            # EDS HighLimit
    (0x2003, 18001, r"18001 is outside -18000..18000"),
    (0x60FF, 1000001, r"1000001 is outside -1000000..1000000"),
    (0x2002, -1, r"0x2002 sub 0 .*: -1 is outside 0..4294967295"),                      # the type's range
    (0x6040, 0x10000, r"65536 is outside 0..65535"),
    (0x2001, 1.5, r"1.5 is not an integer count"),
    (0x2001, float("nan"), r"nan is not an integer count"),
    (0x2001, True, r"True is not a number"),
    (0x2001, "1", r"'1' is not a number"),
])
def test_encode_refuses_what_the_object_cannot_hold(eds, index, value, pattern):
    with pytest.raises(ValueError, match=pattern):
        eds[index, 0].encode(value)


def test_decode_wrong_length(eds):
    with pytest.raises(ValueError, match=r"3 bytes, the type UNSIGNED32 has 4"):
        eds[0x2001, 0].decode(b"\0\0\0")


def test_node_id_range():
    for node in (0, 128, True, "1"):
        with pytest.raises(BenchUsageError, match=r"node id must be 1..127"):
            Eds(EDS, node)


def _eds(tmp_path, body):
    path = tmp_path / "x.eds"
    path.write_text("[FileInfo]\nFileName=x.eds\n\n" + body)
    return str(path)


def test_numbers_in_cia306_forms(tmp_path):
    eds = Eds(_eds(tmp_path, "[2000]\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=$NODEID+010\n"
                             "LowLimit=0x10\nHighLimit=100\n"), 3)
    assert (eds.default(0x2000), eds[0x2000, 0].low, eds[0x2000, 0].high) == (3 + 8, 16, 100)  # 010 is octal


@pytest.mark.parametrize("body, pattern", [
    ("[2000]\nObjectType=0x7\nAccessType=rw\n", r"\[2000\]: no datatype"),
    ("[2000]\nObjectType=0x7\nDataType=0x0007\n", r"\[2000\]: no accesstype"),
    ("[2000]\nObjectType=0x7\nDataType=0x0010\nAccessType=rw\n", r"data type 0x0010 is not one the bench reads"),
    ("[2000]\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=twelve\n", r"'twelve' is not a number"),
    ("[2000]\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=$NODEID*2\n", r"only \$NODEID\+value"),
    ("[DeviceInfo]\nVendorName=x\n", r"no objects"),
    ("[2000]\nA=1\n[2000]\nA=2\n", r"x.eds"),  # a section twice: configparser's strict error, one line
])
def test_a_file_that_does_not_say_what_the_bench_needs(tmp_path, body, pattern):
    with pytest.raises(EdsError, match=pattern):
        Eds(_eds(tmp_path, body), 1)
