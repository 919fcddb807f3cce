"""Unit tests of swum_bench.modbus_map against the project's register table
(config/modbus_registers.json): the table is read (counts, reason codes); 32-bit values decode
high word first (uint32 and int32), int16 negatives decode, physical values encode to words and
back, out-of-range values are a ValueError, and encode_holding wants every holding register.
"""
import json
import math
import os

import pytest

from swum_bench.modbus_map import ModbusMap, Register, default_path

TABLE = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", "..", "config", "modbus_registers.json"))


@pytest.fixture(scope="module")
def regmap():
    return ModbusMap(TABLE)


def full_holding(**overrides):
    values = {"command": 1, "frequency_setpoint": 40000.0, "amplitude_setpoint": 150.0, "phase_setpoint": -90.0,
              "load_force": -2.5, "frequency_slew": 1000000.0, "amplitude_slew": 100000.0, "advance": 10}
    values.update(overrides)
    return values


# ---- the table -------------------------------------------------------------------------------

def test_table_is_read(regmap):
    assert regmap.holding_count == 11
    assert regmap.input_count == 51
    assert set(regmap.holding) == {"command", "frequency_setpoint", "amplitude_setpoint", "phase_setpoint",
                                   "load_force", "frequency_slew", "amplitude_slew", "advance"}
    assert regmap.holding["advance"].address == 10
    assert regmap.reasons[0] == "none"
    assert regmap.reasons[17] == "clock_not_external"


def test_register_shapes(regmap):
    f = regmap.holding["frequency_setpoint"]
    assert (f.address, f.words, f.signed, f.scale, f.unit) == (1, 2, False, 0.001, "Hz")
    p = regmap.holding["phase_setpoint"]
    assert (p.words, p.signed) == (1, True)
    s = regmap.inputs["speed"]
    assert (s.words, s.signed) == (2, True)


def test_default_path_points_at_the_table():
    assert os.path.normpath(default_path(os.path.dirname(TABLE))) == TABLE
    assert os.path.normpath(default_path()) == TABLE  # found by itself: the checkout's config/


def test_unknown_type_is_refused():
    with pytest.raises(ValueError, match=r"register x: unknown type 'float32'"):
        Register({"name": "x", "address": 0, "type": "float32", "scale": 1})


# ---- decode ------------------------------------------------------------------------------------

def test_decode_uint32_high_word_first(regmap):
    f = regmap.holding["frequency_setpoint"]
    assert f.decode([0x0002, 0x625A]) == pytest.approx(156.25)  # 0x0002625A = 156250 mHz
    assert f.decode([0x0262, 0x5A00]) == pytest.approx(40000.0)  # 0x02625A00 = 40 000 000 mHz
    assert f.decode([0x625A, 0x0002]) != pytest.approx(156.25)


def test_decode_uint32_is_never_negative(regmap):
    assert regmap.inputs["tick"].decode([0xFFFF, 0xFFFF]) == 4294967295
    assert regmap.inputs["tick"].decode([0x8000, 0x0000]) == 2147483648


def test_decode_int32(regmap):
    speed = regmap.inputs["speed"]
    assert speed.decode([0xFFFF, 0xFFFE]) == pytest.approx(-2e-6)
    assert speed.decode([0x8000, 0x0000]) == pytest.approx(-2147.483648)
    assert speed.decode([0x7FFF, 0xFFFF]) == pytest.approx(2147.483647)
    assert speed.decode([0x0000, 0x0001]) == pytest.approx(1e-6)


def test_decode_int16_negative(regmap):
    phase = regmap.holding["phase_setpoint"]
    assert phase.decode([0xFFFF]) == pytest.approx(-0.01)
    assert phase.decode([0xDCD8]) == pytest.approx(-90.0)
    assert phase.decode([0x8000]) == pytest.approx(-327.68)
    assert phase.decode([0x7FFF]) == pytest.approx(327.67)
    assert regmap.holding["load_force"].decode([0xF63C]) == pytest.approx(-2.5)


def test_decode_uint16(regmap):
    assert regmap.holding["amplitude_setpoint"].decode([0xFFFF]) == pytest.approx(6553.5)
    assert regmap.holding["command"].decode([3]) == 3


def test_decode_inputs_names_every_input(regmap):
    words = [0] * regmap.input_count
    words[8], words[9] = 0xFFFF, 0xFFFF  # speed -1 um/s
    words[21], words[22] = 0x0000, 0x03E8  # sim_time 1.000 s
    values = regmap.decode_inputs(words)
    assert set(values) == set(regmap.inputs)
    assert values["speed"] == pytest.approx(-1e-6)
    assert values["sim_time"] == pytest.approx(1.0)
    assert values["tick"] == 0


def test_decode_holding_partial_read(regmap):
    words = regmap.encode_holding(full_holding())
    part = regmap.decode_holding(words[1:5], first=1)
    assert set(part) == {"frequency_setpoint", "amplitude_setpoint", "phase_setpoint"}
    assert part["frequency_setpoint"] == pytest.approx(40000.0)
    # a read that splits a 32-bit value leaves it out
    assert "frequency_setpoint" not in regmap.decode_holding(words[2:5], first=2)


# ---- encode ------------------------------------------------------------------------------------

def test_encode_uint32_high_word_first(regmap):
    assert regmap.holding["frequency_setpoint"].encode(40000.0) == [0x0262, 0x5A00]
    assert regmap.holding["frequency_setpoint"].encode(156.25) == [0x0002, 0x625A]


def test_encode_int16_negative_twos_complement(regmap):
    assert regmap.holding["phase_setpoint"].encode(-90.0) == [0xDCD8]
    assert regmap.holding["phase_setpoint"].encode(-0.01) == [0xFFFF]
    assert regmap.holding["load_force"].encode(-2.5) == [0xF63C]


def test_encode_rounds_to_nearest_count(regmap):
    amp = regmap.holding["amplitude_setpoint"]
    assert amp.encode(12.34) == [123]
    assert amp.encode(12.36) == [124]
    assert amp.decode(amp.encode(0.3)) == pytest.approx(0.3)


@pytest.mark.parametrize("name, value", [
    ("frequency_setpoint", 30000.0), ("frequency_setpoint", 50000.001), ("amplitude_setpoint", 600.0),
    ("phase_setpoint", -180.0), ("phase_setpoint", 180.0), ("load_force", -30.0), ("load_force", 29.999),
    ("frequency_slew", 10000000.0), ("amplitude_slew", 0.0), ("advance", 65535), ("command", 3),
])
def test_encode_decode_round_trip(regmap, name, value):
    r = regmap.holding[name]
    words = r.encode(value)
    assert len(words) == r.words
    assert all(0 <= w <= 0xFFFF for w in words)
    assert r.decode(words) == pytest.approx(value, abs=r.scale / 2)


@pytest.mark.parametrize("name, raw", [("speed", -2147483648), ("speed", 2147483647), ("tick", 4294967295),
                                       ("phase_a", -32768), ("phase_a", 32767)])
def test_extremes_round_trip(regmap, name, raw):
    r = regmap.inputs[name]
    assert r.decode(r.encode(raw * r.scale)) == pytest.approx(raw * r.scale)


@pytest.mark.parametrize("name, value", [
    ("phase_setpoint", 400.0), ("phase_setpoint", -327.69), ("amplitude_setpoint", -0.1),
    ("amplitude_setpoint", 6553.6), ("frequency_setpoint", 4294967.296), ("frequency_setpoint", -1.0),
    ("advance", 65536), ("advance", -1), ("load_force", 32.768),
])
def test_encode_out_of_range(regmap, name, value):
    with pytest.raises(ValueError, match=rf"{name}: .* is outside the register's range"):
        regmap.holding[name].encode(value)


def test_encode_int32_out_of_range(regmap):
    with pytest.raises(ValueError, match=r"speed: .* outside"):
        regmap.inputs["speed"].encode(2147.483648)


@pytest.mark.parametrize("value", [math.inf, -math.inf, math.nan])
def test_encode_non_finite(regmap, value):
    with pytest.raises(ValueError, match=r"amplitude_setpoint"):
        regmap.holding["amplitude_setpoint"].encode(value)


# ---- encode_holding -------------------------------------------------------------------------------

def test_encode_holding_all_registers(regmap):
    words = regmap.encode_holding(full_holding())
    assert len(words) == regmap.holding_count == 11
    assert words[0] == 1
    assert words[1:3] == [0x0262, 0x5A00]
    assert words[3] == 1500
    assert words[4] == 0xDCD8
    assert words[10] == 10
    back = regmap.decode_holding(words)
    for name, value in full_holding().items():
        assert back[name] == pytest.approx(value, abs=regmap.holding[name].scale / 2)


def test_encode_holding_requires_every_register(regmap):
    values = full_holding()
    del values["advance"]
    del values["load_force"]
    with pytest.raises(ValueError, match=r"holding registers not given: \['advance', 'load_force'\]"):
        regmap.encode_holding(values)


def test_encode_holding_empty(regmap):
    with pytest.raises(ValueError, match=r"holding registers not given"):
        regmap.encode_holding({})


def test_encode_holding_out_of_range_value(regmap):
    with pytest.raises(ValueError, match=r"phase_setpoint"):
        regmap.encode_holding(full_holding(phase_setpoint=1000.0))


def test_table_file_is_valid_json():
    with open(TABLE) as f:
        table = json.load(f)
    addresses = [r["address"] for r in table["holding_registers"]]
    assert addresses == sorted(addresses)


def test_a_slew_that_rounds_to_unlimited_is_refused():
    from swum_bench.modbus_map import ModbusMap, default_path
    with pytest.raises(ValueError, match=r"frequency_slew: 0.4 Hz/s rounds to 0, which means unlimited"):
        ModbusMap(default_path()).holding["frequency_slew"].encode(0.4)
