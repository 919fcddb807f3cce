"""Unit tests of swum_bench's waveform assertions (swum_bench/assertions.py) on synthetic Signals.

Covers, for assert_settles, assert_within, assert_overshoot, assert_rise_time, assert_reaches,
assert_follows and assert_fault_within:
- a passing case and the measurement each one returns (settling time, overshoot %, rise time,
  time reached, error, delay);
- a failing case: the WaveformAssertionError message names the assertion and the signal, the
  first violating time and value (exact numbers), and `.time_s` is that time;
- edge cases: a value exactly on a band's edge passes (also with inexact floats), a signal that
  never settles, a NaN inside the analysed window (fails at its time), a NaN outside (ignored);
- bad arguments: BenchUsageError with a clear message (negative or non-finite numbers, bools,
  empty windows, empty steps, low >= high, wrong direction, non-Signals, a short reference, bad
  fault codes);
- the PNG a failure attaches when swum_bench.attachments.begin() is active, and none without it.

No emulator is involved; every signal is built here."""
import math
import re

import numpy as np
import pytest

from swum_bench import (BenchUsageError, Signal, WaveformAssertionError, assert_fault_within, assert_follows,
                        assert_overshoot, assert_reaches, assert_rise_time, assert_settles, assert_within)
from swum_bench import attachments

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
N = 501  # samples at 1 ms: 0.000 .. 0.500 s
T = np.arange(N) / 1000.0  # i / 1000: the closest double to each millisecond


@pytest.fixture(autouse=True)
def _no_attachments():
    """Every test starts and ends without an attachment folder (module-global state)."""
    attachments.end()
    yield
    attachments.end()


def step_signal(spike_at=None, spike=1.25, name="speed", unit="mm/s"):
    """0 before 0.1 s, then 1.0; optionally one sample `spike` at index spike_at."""
    values = np.where(T < 0.1, 0.0, 1.0)
    if spike_at is not None:
        values[spike_at] = spike
    return Signal(name, unit, T, values)


def ramp_signal(top=1.0, name="speed", unit="mm/s"):
    """0 until 0.100 s, a straight line to 1.0 at 0.200 s (exact hundredths per ms), held;
    clipped at `top`."""
    values = np.clip((np.arange(N) - 100) / 100.0, 0.0, top)
    return Signal(name, unit, T, values)


def fault_signal(code=3, from_index=304):
    return Signal("fault_code", "", T, np.where(np.arange(N) >= from_index, code, 0))


def failure(call):
    with pytest.raises(WaveformAssertionError) as info:
        call()
    return info.value


def usage(call, pattern):
    with pytest.raises(BenchUsageError, match=pattern):
        call()


# ---- assert_settles ----------------------------------------------------------------------

def test_settles_returns_settling_time():
    assert assert_settles(step_signal(), 1.0, 0.1, within_s=0.2) == pytest.approx(0.1, abs=1e-12)


def test_settles_time_is_relative_to_start_s():
    assert assert_settles(step_signal(), 1.0, 0.1, within_s=0.1, start_s=0.05) == pytest.approx(0.05, abs=1e-12)


def test_settles_first_order_response():
    values = 1.0 - np.exp(-T / 0.05)  # inside 1 +- 0.02 from 0.05 ln 50 = 0.19560 s: the sample at 0.196 s
    s = Signal("speed", "mm/s", T, values)
    assert assert_settles(s, 1.0, 0.02, within_s=0.25) == pytest.approx(0.196, abs=1e-12)


def test_settles_already_inside_returns_zero():
    s = Signal("speed", "mm/s", T, np.full(N, 1.0))
    assert assert_settles(s, 1.0, 0.0, within_s=0.1) == 0.0


def test_settles_failure_names_first_violation():
    e = failure(lambda: assert_settles(step_signal(spike_at=304), 1.0, 0.1, within_s=0.2))
    msg = str(e)
    assert msg.startswith("assert_settles(speed) failed:")
    assert "t = 0.304000 s" in msg
    assert "value 1.25 mm/s" in msg
    assert "off by +0.25" in msg
    assert "from 0.200000 s" in msg
    assert "it settles only at 0.305000 s" in msg
    assert e.time_s == pytest.approx(0.304)
    assert e.plot is None


def test_settles_late_settling_names_deadline_sample():
    e = failure(lambda: assert_settles(step_signal(), 1.0, 0.1, within_s=0.05))
    assert "first violation at t = 0.050000 s" in str(e)
    assert "value 0 mm/s" in str(e)
    assert "it settles only at 0.100000 s" in str(e)
    assert e.time_s == pytest.approx(0.05)


def test_settles_never_settles():
    values = np.where(T < 0.1, 0.0, 1.0)
    values[-1] = 1.5
    e = failure(lambda: assert_settles(Signal("speed", "mm/s", T, values), 1.0, 0.1, within_s=0.2))
    assert "never settles" in str(e)
    assert "t = 0.500000 s" in str(e)
    assert e.time_s == pytest.approx(0.5)


def test_settles_never_settles_constant_offset():
    s = Signal("speed", "mm/s", T, np.full(N, 2.0))
    e = failure(lambda: assert_settles(s, 1.0, 0.1, within_s=0.2))
    assert "never settles" in str(e)
    assert "first violation at t = 0.200000 s" in str(e)


@pytest.mark.parametrize("target, band, edges", [
    (1.0, 0.1, (0.9, 1.1)),
    (0.1, 0.2, (-0.1, 0.3)),
    (0.0, 0.0, (0.0, 0.0)),
    (40000.0, 0.5, (39999.5, 40000.5)),
    (-3.3, 0.7, (-4.0, -2.6)),
])
def test_settles_band_edges_are_inside(target, band, edges):
    values = np.array([edges[i % 2] for i in range(N)])
    s = Signal("speed", "mm/s", T, values)
    assert assert_settles(s, target, band, within_s=0.0) == 0.0


def test_settles_just_beyond_the_edge_fails():
    values = np.full(N, 0.3)
    values[400] = 0.3 + 1e-9
    e = failure(lambda: assert_settles(Signal("speed", "mm/s", T, values), 0.1, 0.2, within_s=0.0))
    assert "t = 0.400000 s" in str(e)


def test_settles_nan_in_window_fails_at_its_time():
    s = step_signal()
    s.values[250] = math.nan
    e = failure(lambda: assert_settles(s, 1.0, 0.1, within_s=0.2))
    assert "assert_settles(speed) failed: NaN at t = 0.250000 s" in str(e)
    assert e.time_s == pytest.approx(0.25)


def test_settles_nan_before_the_deadline_fails_too():
    s = step_signal()
    s.values[50] = math.nan
    e = failure(lambda: assert_settles(s, 1.0, 0.1, within_s=0.2))
    assert "NaN at t = 0.050000 s" in str(e)


def test_settles_nan_outside_window_is_ignored():
    s = step_signal()
    s.values[20] = math.nan  # before start_s
    s.values[490] = math.nan  # after end_s
    assert assert_settles(s, 1.0, 0.1, within_s=0.1, start_s=0.1, end_s=0.45) == pytest.approx(0.0)


def test_settles_sample_at_deadline_is_checked():
    values = np.ones(N)
    values[300] = 2.0
    s = Signal("speed", "mm/s", T, values)
    e = failure(lambda: assert_settles(s, 1.0, 0.1, within_s=0.2, start_s=0.1))
    assert "t = 0.300000 s" in str(e)


def test_settles_window_ending_at_deadline_is_usable():
    s = Signal("speed", "mm/s", T[:301], np.ones(301))
    assert assert_settles(s, 1.0, 0.1, within_s=0.2, start_s=0.1) == pytest.approx(0.0)


@pytest.mark.parametrize("kwargs, pattern", [
    (dict(target=1.0, band=-0.1, within_s=0.2), r"assert_settles: band must be >= 0, got -0.1"),
    (dict(target=1.0, band=0.1, within_s=-0.2), r"assert_settles: within_s must be >= 0, got -0.2"),
    (dict(target=math.nan, band=0.1, within_s=0.2), r"assert_settles: target must be a finite number, not nan"),
    (dict(target=math.inf, band=0.1, within_s=0.2), r"target must be a finite number, not inf"),
    (dict(target=1.0, band=math.inf, within_s=0.2), r"band must be a finite number, not inf"),
    (dict(target=True, band=0.1, within_s=0.2), r"target must be a finite number, not True"),
    (dict(target=1.0, band=False, within_s=0.2), r"band must be a finite number, not False"),
    (dict(target="1", band=0.1, within_s=0.2), r"target must be a finite number, not '1'"),
    (dict(target=1.0, band=0.1, within_s=0.2, start_s=0.6), r"no samples of speed from 0.6 s on: the signal ends at 0.5 s"),
    (dict(target=1.0, band=0.1, within_s=0.0, start_s=0.3, end_s=0.2), r"empty window: end 0.2 s is before start 0.3 s"),
    (dict(target=1.0, band=0.1, within_s=0.0, start_s=0.1005, end_s=0.1008), r"no samples of speed in \[0.1005, 0.1008\] s"),
    (dict(target=1.0, band=0.1, within_s=1.0), r"before the deadline 1 s"),
    (dict(target=1.0, band=0.1, within_s=0.2, start_s=math.nan), r"start_s must be a finite number of seconds"),
])
def test_settles_bad_arguments(kwargs, pattern):
    usage(lambda: assert_settles(step_signal(), **kwargs), pattern)


def test_settles_numpy_numbers_are_accepted():
    assert assert_settles(step_signal(), np.float64(1.0), np.float32(0.1), np.int64(1) * 0.2) == pytest.approx(0.1)


# ---- assert_within -------------------------------------------------------------------------

def test_within_returns_largest_deviation_from_middle():
    assert assert_within(step_signal(), -0.5, 1.5) == pytest.approx(0.5)
    assert assert_within(step_signal(), -1.0, 1.0) == pytest.approx(1.0)
    assert assert_within(step_signal(), 0.0, 1.0) == pytest.approx(0.5)


def test_within_failure():
    e = failure(lambda: assert_within(step_signal(spike_at=304), 0.0, 1.2, start_s=0.1))
    msg = str(e)
    assert msg.startswith("assert_within(speed) failed:")
    assert "leaves [0, 1.2] mm/s at t = 0.304000 s, value 1.25 mm/s" in msg
    assert "1 of 401 samples outside" in msg
    assert e.time_s == pytest.approx(0.304)


def test_within_first_violation_below():
    s = step_signal(spike_at=420, spike=-0.25)
    e = failure(lambda: assert_within(s, -0.2, 1.0))
    assert "t = 0.420000 s, value -0.25 mm/s" in str(e)


def test_within_edges_are_inside():
    s = Signal("v", "", T, np.where(np.arange(N) % 2, 0.3, -0.1))
    assert assert_within(s, -0.1, 0.3) == pytest.approx(0.2)
    assert assert_within(s, 0.3 - 0.4, 0.1 + 0.2) == pytest.approx(0.2)  # inexact floats: 0.30000000000000004


def test_within_equal_bounds():
    s = Signal("v", "", T, np.full(N, 0.7))
    assert assert_within(s, 0.7, 0.7) == 0.0


def test_within_nan_inside_and_outside_window():
    s = step_signal()
    s.values[10] = math.nan
    e = failure(lambda: assert_within(s, -1.0, 2.0))
    assert "NaN at t = 0.010000 s" in str(e)
    assert e.time_s == pytest.approx(0.01)
    assert assert_within(s, -1.0, 2.0, start_s=0.011) == pytest.approx(0.5)


@pytest.mark.parametrize("args, kwargs, pattern", [
    ((1.0, 0.0), {}, r"assert_within: high 0 is below low 1"),
    ((math.nan, 1.0), {}, r"low must be a finite number, not nan"),
    ((0.0, -math.inf), {}, r"high must be a finite number, not -inf"),
    ((True, 1.0), {}, r"low must be a finite number, not True"),
    ((0.0, None), {}, r"high must be a finite number, not None"),
    ((0.0, 1.0), dict(start_s=0.7), r"no samples of speed from 0.7 s on"),
    ((0.0, 1.0), dict(start_s=0.2, end_s=0.1), r"empty window"),
])
def test_within_bad_arguments(args, kwargs, pattern):
    usage(lambda: assert_within(step_signal(), *args, **kwargs), pattern)


# ---- assert_overshoot ----------------------------------------------------------------------

OVERSHOOT_T = np.arange(6) / 10.0


def overshoot_signal():
    return Signal("speed", "mm/s", OVERSHOOT_T, [0.0, 0.6, 1.08, 1.03, 0.98, 1.0])


def test_overshoot_returns_percent():
    assert assert_overshoot(overshoot_signal(), 1.0, 10) == pytest.approx(8.0)


def test_overshoot_none_is_zero():
    s = Signal("speed", "mm/s", OVERSHOOT_T, [0.0, 0.5, 0.9, 0.95, 1.0, 1.0])
    assert assert_overshoot(s, 1.0, 0) == 0.0


def test_overshoot_downward_step():
    s = Signal("speed", "mm/s", OVERSHOOT_T, [1.0, 0.5, -0.05, 0.0, 0.0, 0.0])
    assert assert_overshoot(s, 0.0, 10) == pytest.approx(5.0)
    e = failure(lambda: assert_overshoot(s, 0.0, 4))
    assert "t = 0.200000 s, value -0.05 mm/s" in str(e)


def test_overshoot_explicit_initial():
    s = Signal("speed", "mm/s", OVERSHOOT_T, [0.5, 0.6, 1.08, 1.03, 0.98, 1.0])
    assert assert_overshoot(s, 1.0, 10, initial=0.0) == pytest.approx(8.0)
    assert assert_overshoot(s, 1.0, 20) == pytest.approx(16.0)  # step 0.5 -> 1


def test_overshoot_failure():
    e = failure(lambda: assert_overshoot(overshoot_signal(), 1.0, 5))
    msg = str(e)
    assert msg.startswith("assert_overshoot(speed) failed:")
    assert "overshoot 8 % > 5 % of the step 0 -> 1 mm/s" in msg
    assert "first beyond at t = 0.200000 s, value 1.08 mm/s" in msg
    assert "peak 1.08 mm/s at t = 0.200000 s" in msg
    assert e.time_s == pytest.approx(0.2)


def test_overshoot_first_beyond_precedes_peak():
    s = Signal("speed", "mm/s", OVERSHOOT_T, [0.0, 1.06, 1.09, 1.03, 0.98, 1.0])
    e = failure(lambda: assert_overshoot(s, 1.0, 5))
    assert "first beyond at t = 0.100000 s, value 1.06 mm/s" in str(e)
    assert "peak 1.09 mm/s at t = 0.200000 s" in str(e)
    assert e.time_s == pytest.approx(0.1)


@pytest.mark.parametrize("initial, target, max_percent, peak", [
    (0.0, 1.0, 10.0, 1.1),
    (0.0, 0.1, 10.0, 0.11),
    (1.0, 0.0, 5.0, -0.05),
    (0.0, 0.3, 20.0, 0.36),
])
def test_overshoot_exactly_at_limit_passes(initial, target, max_percent, peak):
    s = Signal("speed", "mm/s", OVERSHOOT_T, [initial, peak, target, target, target, target])
    assert assert_overshoot(s, target, max_percent) == pytest.approx(max_percent)


def test_overshoot_exactly_at_limit_with_large_values():
    s = Signal("speed", "mm/s", OVERSHOOT_T, [100000.0, 100000.2, 100000.22, 100000.2, 100000.2, 100000.2])
    assert assert_overshoot(s, 100000.2, 10) == pytest.approx(10.0)


def test_overshoot_nan():
    s = overshoot_signal()
    s.values[3] = math.nan
    e = failure(lambda: assert_overshoot(s, 1.0, 10))
    assert "NaN at t = 0.300000 s" in str(e)
    assert e.time_s == pytest.approx(0.3)
    assert assert_overshoot(s, 1.0, 10, end_s=0.25) == pytest.approx(8.0)


@pytest.mark.parametrize("args, kwargs, pattern", [
    ((0.0, 10), {}, r"the step is empty: target 0 equals the initial value 0"),
    ((1.0, 10), dict(initial=1.0), r"the step is empty"),
    ((1.0, -1), {}, r"max_percent must be >= 0, got -1"),
    ((1.0, math.nan), {}, r"max_percent must be a finite number, not nan"),
    ((1.0, True), {}, r"max_percent must be a finite number, not True"),
    ((math.inf, 10), {}, r"target must be a finite number, not inf"),
    ((1.0, 10), dict(initial=math.nan), r"initial must be a finite number, not nan"),
    ((1.0, 10), dict(start_s=0.9), r"no samples of speed from 0.9 s on"),
])
def test_overshoot_bad_arguments(args, kwargs, pattern):
    usage(lambda: assert_overshoot(overshoot_signal(), *args, **kwargs), pattern)


def test_overshoot_nan_first_sample_fails_at_its_time():
    s = overshoot_signal()
    s.values[0] = math.nan
    with pytest.raises(WaveformAssertionError, match=r"assert_overshoot\(speed\) failed: NaN at t = 0\.000000 s"):
        assert_overshoot(s, 1.0, 10)


# ---- assert_rise_time ----------------------------------------------------------------------

def test_rise_time_returns_10_to_90():
    assert assert_rise_time(ramp_signal(), 1.0, 0.1) == pytest.approx(0.08, abs=1e-12)


def test_rise_time_custom_levels():
    assert assert_rise_time(ramp_signal(), 1.0, 0.1, low=0.2, high=0.7) == pytest.approx(0.05, abs=1e-12)
    # 0 % of the step is reached by the first sample (t = 0), 100 % at 0.2 s
    assert assert_rise_time(ramp_signal(), 1.0, 0.25, low=0.0, high=1.0) == pytest.approx(0.2, abs=1e-12)


def test_rise_time_downward_step():
    s = Signal("speed", "mm/s", T, 1.0 - ramp_signal().values)
    assert assert_rise_time(s, 0.0, 0.1) == pytest.approx(0.08, abs=1e-12)


def test_rise_time_exactly_max_passes():
    assert assert_rise_time(ramp_signal(), 1.0, 0.08) == pytest.approx(0.08, abs=1e-12)


def test_rise_time_failure_too_slow():
    e = failure(lambda: assert_rise_time(ramp_signal(), 1.0, 0.05))
    msg = str(e)
    assert msg.startswith("assert_rise_time(speed) failed:")
    assert "rise time 0.080000 s > 0.05 s" in msg
    assert "10 % at 0.110000 s" in msg
    assert "90 % = 0.9 mm/s only at 0.190000 s" in msg
    assert re.search(r"at t = 0\.160000 s the value is 0\.6\d* mm/s", msg)
    assert e.time_s == pytest.approx(0.16, abs=0.0011)


def test_rise_time_failure_names_the_sample_at_the_limit():
    e = failure(lambda: assert_rise_time(ramp_signal(), 1.0, 0.05))
    assert "at t = 0.160000 s the value is 0.6 mm/s" in str(e)
    assert e.time_s == pytest.approx(0.16)


def test_rise_time_never_reaches():
    e = failure(lambda: assert_rise_time(ramp_signal(top=0.8), 1.0, 0.1))
    msg = str(e)
    assert "assert_rise_time(speed) failed: never reaches 90 % of the step 0 -> 1 (0.9 mm/s) by 0.500000 s" in msg
    assert "closest 0.8 mm/s at t = 0.180000 s" in msg
    assert e.time_s == pytest.approx(0.18)


def test_rise_time_level_touched_exactly():
    # 0.1 and 0.9 of a step 0.1 -> 0.3 (inexact floats): 0.12 and 0.28 reached exactly
    s = Signal("v", "", np.arange(5) / 10.0, [0.1, 0.12, 0.2, 0.28, 0.3])
    assert assert_rise_time(s, 0.3, 0.2) == pytest.approx(0.2)


def test_rise_time_level_touched_exactly_large_values():
    s = Signal("speed", "mm/s", np.arange(4) / 10.0, [10000.0, 10000.01, 10000.09, 10000.1])
    assert assert_rise_time(s, 10000.1, 0.1) == pytest.approx(0.1)


def test_rise_time_nan():
    s = ramp_signal()
    s.values[150] = math.nan
    e = failure(lambda: assert_rise_time(s, 1.0, 0.1))
    assert "NaN at t = 0.150000 s" in str(e)
    assert assert_rise_time(s, 1.0, 0.1, start_s=0.151, initial=0.0) == pytest.approx(0.039, abs=1e-12)


@pytest.mark.parametrize("args, kwargs, pattern", [
    ((1.0, 0.1), dict(low=0.9, high=0.1), r"need 0 <= low < high <= 1, got low 0.9, high 0.1"),
    ((1.0, 0.1), dict(low=0.5, high=0.5), r"need 0 <= low < high <= 1"),
    ((1.0, 0.1), dict(low=0.1, high=1.5), r"need 0 <= low < high <= 1"),
    ((1.0, 0.1), dict(low=-0.1), r"low must be >= 0, got -0.1"),
    ((1.0, -0.1), {}, r"max_s must be >= 0, got -0.1"),
    ((1.0, math.inf), {}, r"max_s must be a finite number, not inf"),
    ((0.0, 0.1), {}, r"the step is empty: target 0 equals the initial value 0"),
    ((1.0, 0.1), dict(high=True), r"high must be a finite number, not True"),
])
def test_rise_time_bad_arguments(args, kwargs, pattern):
    usage(lambda: assert_rise_time(ramp_signal(), *args, **kwargs), pattern)


# ---- assert_reaches ------------------------------------------------------------------------

def test_reaches_returns_first_time():
    assert assert_reaches(ramp_signal(), 0.5, before_s=0.3) == pytest.approx(0.15)


def test_reaches_exactly_at_deadline_and_threshold():
    assert assert_reaches(ramp_signal(), 0.5, before_s=0.15) == pytest.approx(0.15)
    assert assert_reaches(ramp_signal(), 0.1 + 0.2, before_s=0.13) == pytest.approx(0.13)  # 0.30000000000000004


def test_reaches_below():
    s = Signal("speed", "mm/s", T, 1.0 - ramp_signal().values)
    assert assert_reaches(s, 0.25, before_s=0.2, direction="below") == pytest.approx(0.175)


def test_reaches_from_start_s():
    s = Signal("speed", "mm/s", T, np.where((T > 0.05) & (T < 0.07), 1.0, 0.0) + ramp_signal().values)
    assert assert_reaches(s, 0.9, before_s=0.3) == pytest.approx(0.051)
    assert assert_reaches(s, 0.9, before_s=0.3, start_s=0.1) == pytest.approx(0.19)


def test_reaches_failure_late():
    e = failure(lambda: assert_reaches(ramp_signal(), 0.5, before_s=0.12))
    msg = str(e)
    assert msg.startswith("assert_reaches(speed) failed:")
    assert "not >= 0.5 mm/s by 0.120000 s" in msg
    assert "at t = 0.120000 s the value is 0.2 mm/s" in msg
    assert "it does so only at 0.150000 s" in msg
    assert e.time_s == pytest.approx(0.12)


def test_reaches_failure_never():
    e = failure(lambda: assert_reaches(ramp_signal(top=0.4), 0.5, before_s=0.3))
    assert "it never does by 0.500000 s" in str(e)
    assert "at t = 0.300000 s the value is 0.4 mm/s" in str(e)
    e = failure(lambda: assert_reaches(ramp_signal(), -0.5, before_s=0.3, direction="below"))
    assert "not <= -0.5 mm/s by 0.300000 s" in str(e)


def test_reaches_signal_ending_before_deadline_is_a_usage_error():
    usage(lambda: assert_reaches(ramp_signal(top=0.4), 0.5, before_s=0.8),
          r"assert_reaches: speed ends at 0.5 s, before before_s 0.8 s, without reaching >= 0.5: step the bench further")
    # reached before the end of the capture: no matter that before_s is later
    assert assert_reaches(ramp_signal(), 0.5, before_s=0.8) == pytest.approx(0.15)


def test_reaches_nan_before_and_after_deadline():
    s = ramp_signal()
    s.values[400] = math.nan  # after before_s: not analysed
    assert assert_reaches(s, 0.5, before_s=0.3) == pytest.approx(0.15)
    s.values[120] = math.nan
    e = failure(lambda: assert_reaches(s, 0.5, before_s=0.3))
    assert "NaN at t = 0.120000 s" in str(e)
    assert e.time_s == pytest.approx(0.12)


@pytest.mark.parametrize("args, kwargs, pattern", [
    ((0.5, 0.3), dict(direction="up"), r"direction must be 'above' or 'below', not 'up'"),
    ((0.5, 0.3), dict(direction=None), r"direction must be 'above' or 'below', not None"),
    ((0.5, -0.1), {}, r"before_s must be >= 0, got -0.1"),
    ((math.nan, 0.3), {}, r"threshold must be a finite number, not nan"),
    ((0.5, 0.3), dict(start_s=0.35), r"before_s 0.3 s is before the window's start 0.35 s"),
    ((0.5, 0.3), dict(start_s=0.6), r"no samples of speed from 0.6 s on"),
    ((0.5, True), {}, r"before_s must be a finite number, not True"),
])
def test_reaches_bad_arguments(args, kwargs, pattern):
    usage(lambda: assert_reaches(ramp_signal(), *args, **kwargs), pattern)


# ---- assert_follows ------------------------------------------------------------------------

def test_follows_number_reference():
    assert assert_follows(overshoot_signal(), 1.0, 0.05, start_s=0.3) == pytest.approx(0.03)


def test_follows_function_reference():
    s = Signal("speed", "mm/s", T, 2.0 * T + 0.01 * np.sin(1000 * T))
    assert assert_follows(s, lambda t: 2.0 * t, 0.01) <= 0.01


def test_follows_signal_reference_interpolated():
    ref = Signal("ref", "mm/s", [0.0, 0.5], [0.0, 1.0])
    s = Signal("speed", "mm/s", T, 2.0 * T)
    assert assert_follows(s, ref, 1e-9) == pytest.approx(0.0, abs=1e-12)


def test_follows_band_edge():
    ref = Signal("ref", "mm/s", T, 0.1 * np.ones(N))
    s = Signal("speed", "mm/s", T, np.where(np.arange(N) % 2, 0.3, -0.1))
    assert assert_follows(s, ref, 0.2) == pytest.approx(0.2)


def test_follows_band_edge_with_varying_reference():
    t = np.array([0.0, 0.1])
    ref = Signal("ref", "N", t, [0.0, 1000000.5])
    s = Signal("speed", "N", t, [0.3, 1000000.5 + 0.3])
    assert assert_follows(s, ref, 0.3) == pytest.approx(0.3)


def test_follows_failure():
    e = failure(lambda: assert_follows(overshoot_signal(), lambda t: 2.0 * t, 0.1))
    msg = str(e)
    assert msg.startswith("assert_follows(speed) failed:")
    assert "off the reference <lambda> by more than 0.1 mm/s at t = 0.100000 s" in msg
    assert "value 0.6 mm/s, reference 0.2 (error +0.4)" in msg
    assert "4 of 6 samples outside" in msg
    assert e.time_s == pytest.approx(0.1)


def test_follows_failure_named_reference():
    ref = Signal("ref", "mm/s", [0.0, 0.5], [0.0, 1.0])
    e = failure(lambda: assert_follows(overshoot_signal(), ref, 0.5))
    assert "off the reference ref by more than 0.5 mm/s at t = 0.200000 s: value 1.08 mm/s, reference 0.4" \
           in str(e)
    assert e.time_s == pytest.approx(0.2)


def test_follows_nan():
    s = overshoot_signal()
    s.values[4] = math.nan
    e = failure(lambda: assert_follows(s, 1.0, 0.1, start_s=0.3))
    assert "NaN at t = 0.400000 s" in str(e)
    assert assert_follows(s, 1.0, 0.1, start_s=0.3, end_s=0.35) == pytest.approx(0.03)


@pytest.mark.parametrize("reference, kwargs, pattern", [
    (Signal("ref", "mm/s", [0.0, 0.3], [0.0, 1.0]), {},
     r"the reference ref spans 0..0.3 s, not the whole window 0..0.5 s"),
    (Signal("ref", "mm/s", [0.1, 0.5], [0.0, 1.0]), {}, r"the reference ref spans 0.1..0.5 s"),
    (Signal("ref", "mm/s", [], []), {}, r"the reference ref is empty"),
    (lambda t: math.nan, {}, r"the reference <lambda> is not a finite number at t = 0 s"),
    (math.inf, {}, r"reference must be a finite number, not inf"),
    ("1.0", {}, r"reference must be a finite number, not '1.0'"),
    (1.0, dict(band=-1.0), r"band must be >= 0, got -1"),
    (1.0, dict(band=True), r"band must be a finite number, not True"),
    (1.0, dict(band=0.1, start_s=0.2, end_s=0.1), r"empty window"),
])
def test_follows_bad_arguments(reference, kwargs, pattern):
    kwargs = {"band": 0.1, **kwargs}
    usage(lambda: assert_follows(overshoot_signal(), reference, **kwargs), pattern)


# ---- assert_fault_within -------------------------------------------------------------------

def test_fault_within_returns_delay():
    assert assert_fault_within(fault_signal(), 3, 0.3, 0.01) == pytest.approx(0.004)
    assert assert_fault_within(fault_signal(), np.int64(3), 0.3, 0.01) == pytest.approx(0.004)


def test_fault_within_exactly_at_deadline():
    assert assert_fault_within(fault_signal(), 3, 0.3, 0.004) == pytest.approx(0.004)


def test_fault_within_exactly_at_inexact_deadline():
    t = np.arange(1001) / 1000.0
    s = Signal("fault_code", "", t, np.where(np.arange(1001) >= 800, 3, 0))
    assert assert_fault_within(s, 3, 0.7, 0.1) == pytest.approx(0.1)


def test_fault_within_failure_late():
    e = failure(lambda: assert_fault_within(fault_signal(), 3, 0.3, 0.002))
    msg = str(e)
    assert msg.startswith("assert_fault_within(fault_code) failed:")
    assert "fault code 3 not within 0.002 s of the injection at 0.3 s" in msg
    assert "at t = 0.302000 s the code is 0 (codes seen: [0])" in msg
    assert "it appears only at 0.304000 s" in msg
    assert e.time_s == pytest.approx(0.302)


def test_fault_within_failure_other_code():
    e = failure(lambda: assert_fault_within(fault_signal(), 4, 0.3, 0.01))
    assert "fault code 4 not within 0.01 s" in str(e)
    assert "at t = 0.310000 s the code is 3 (codes seen: [0, 3])" in str(e)
    assert "it never appears by 0.500000 s" in str(e)
    assert e.time_s == pytest.approx(0.31)


def test_fault_within_code_before_injection_does_not_count():
    s = Signal("fault_code", "", T, np.where((T > 0.1) & (T < 0.2), 3, 0))
    e = failure(lambda: assert_fault_within(s, 3, 0.3, 0.1))
    assert "it never appears by 0.500000 s" in str(e)


def test_fault_within_signal_ending_before_deadline_is_a_usage_error():
    usage(lambda: assert_fault_within(fault_signal(), 4, 0.3, 0.5),
          r"assert_fault_within: fault_code ends at 0.5 s, before the deadline 0.8 s, without code 4: "
          r"step the bench further")
    assert assert_fault_within(fault_signal(), 3, 0.3, 0.5) == pytest.approx(0.004)


def test_fault_within_nan():
    s = fault_signal()
    s.values[302] = math.nan
    e = failure(lambda: assert_fault_within(s, 3, 0.3, 0.01))
    assert "NaN at t = 0.302000 s" in str(e)
    assert e.time_s == pytest.approx(0.302)
    s = fault_signal()
    s.values[100] = math.nan  # before the injection
    s.values[450] = math.nan  # after the deadline
    assert assert_fault_within(s, 3, 0.3, 0.01) == pytest.approx(0.004)


@pytest.mark.parametrize("args, pattern", [
    ((-1, 0.3, 0.01), r"code must be an integer >= 0, not -1"),
    ((3.0, 0.3, 0.01), r"code must be an integer >= 0, not 3.0"),
    ((True, 0.3, 0.01), r"code must be an integer >= 0, not True"),
    (("3", 0.3, 0.01), r"code must be an integer >= 0, not '3'"),
    ((3, -0.3, 0.01), r"injected_at_s must be >= 0, got -0.3"),
    ((3, 0.3, -0.01), r"within_s must be >= 0, got -0.01"),
    ((3, math.nan, 0.01), r"injected_at_s must be a finite number, not nan"),
    ((3, 0.3, math.inf), r"within_s must be a finite number, not inf"),
    ((3, 0.6, 0.01), r"no samples of fault_code from 0.6 s on"),
])
def test_fault_within_bad_arguments(args, pattern):
    usage(lambda: assert_fault_within(fault_signal(), *args), pattern)


# ---- every assertion: a non-Signal, window arguments -----------------------------------------

ALL_CALLS = {
    "assert_settles": lambda s: assert_settles(s, 1.0, 0.1, 0.2),
    "assert_within": lambda s: assert_within(s, 0.0, 1.0),
    "assert_overshoot": lambda s: assert_overshoot(s, 1.0, 10),
    "assert_rise_time": lambda s: assert_rise_time(s, 1.0, 0.1),
    "assert_reaches": lambda s: assert_reaches(s, 0.5, 0.3),
    "assert_follows": lambda s: assert_follows(s, 1.0, 0.1),
    "assert_fault_within": lambda s: assert_fault_within(s, 3, 0.3, 0.01),
}


@pytest.mark.parametrize("name", sorted(ALL_CALLS))
@pytest.mark.parametrize("not_a_signal, type_name", [([0.0, 1.0], "list"), (np.zeros(3), "ndarray"),
                                                     (None, "NoneType"), ("speed", "str")])
def test_non_signal_argument(name, not_a_signal, type_name):
    usage(lambda: ALL_CALLS[name](not_a_signal),
          rf"{name}: expected a Signal \(bench.signal\(NAME\)\), not {type_name}")


@pytest.mark.parametrize("name", sorted(ALL_CALLS))
def test_empty_signal(name):
    usage(lambda: ALL_CALLS[name](Signal("speed", "mm/s", [], [])), r"no samples")


def test_window_accepts_numpy_integer_start():
    assert assert_within(step_signal(), 0.0, 1.0, start_s=np.int64(0)) == pytest.approx(0.5)


def test_window_refuses_bool_start():
    usage(lambda: assert_within(step_signal(), 0.0, 1.0, start_s=False), r"start_s")


# ---- plot attachment -------------------------------------------------------------------------

FAILING = {
    "assert_settles": lambda: assert_settles(step_signal(spike_at=304), 1.0, 0.1, within_s=0.2),
    "assert_within": lambda: assert_within(step_signal(spike_at=304), 0.0, 1.2),
    "assert_overshoot": lambda: assert_overshoot(overshoot_signal(), 1.0, 5),
    "assert_rise_time": lambda: assert_rise_time(ramp_signal(), 1.0, 0.05),
    "assert_rise_time_never": lambda: assert_rise_time(ramp_signal(top=0.8), 1.0, 0.1),
    "assert_reaches": lambda: assert_reaches(ramp_signal(), 0.5, before_s=0.12),
    "assert_follows": lambda: assert_follows(overshoot_signal(), lambda t: 2.0 * t, 0.1),
    "assert_fault_within": lambda: assert_fault_within(fault_signal(), 3, 0.3, 0.002),
}


def check_png(path):
    with open(path, "rb") as f:
        data = f.read()
    assert len(data) > len(PNG_MAGIC)
    assert data.startswith(PNG_MAGIC)


@pytest.mark.parametrize("name", sorted(FAILING))
def test_failure_attaches_png(tmp_path, name):
    folder = tmp_path / "plots"
    attachments.begin(str(folder))
    e = failure(FAILING[name])
    files = attachments.end()
    assert e.plot is not None
    check_png(e.plot)
    assert str(e).endswith(f"; plot: {e.plot}")
    assert files == [e.plot]
    assert e.plot.startswith(str(folder))
    assert e.plot.endswith(".png")
    assert name.replace("_never", "") in e.plot


def test_nan_failure_attaches_png(tmp_path):
    s = step_signal()
    s.values[250] = math.nan
    attachments.begin(str(tmp_path))
    e = failure(lambda: assert_settles(s, 1.0, 0.1, within_s=0.2))
    assert attachments.end() == [e.plot]
    check_png(e.plot)
    assert "NaN at t = 0.250000 s" in str(e)


def test_two_failures_two_files(tmp_path):
    attachments.begin(str(tmp_path))
    first = failure(FAILING["assert_within"])
    second = failure(FAILING["assert_within"])
    files = attachments.end()
    assert first.plot != second.plot
    assert files == [first.plot, second.plot]
    for path in files:
        check_png(path)


def test_no_plot_without_begin(tmp_path):
    e = failure(FAILING["assert_settles"])
    assert e.plot is None
    assert "plot:" not in str(e)
    assert attachments.end() == []


def test_no_plot_after_end(tmp_path):
    attachments.begin(str(tmp_path))
    attachments.end()
    e = failure(FAILING["assert_within"])
    assert e.plot is None
    assert list(tmp_path.iterdir()) == []


def test_passing_assertion_attaches_nothing(tmp_path):
    attachments.begin(str(tmp_path))
    assert_settles(step_signal(), 1.0, 0.1, within_s=0.2)
    assert attachments.end() == []
    assert list(tmp_path.iterdir()) == []


def test_usage_error_attaches_nothing(tmp_path):
    attachments.begin(str(tmp_path))
    usage(lambda: assert_settles(step_signal(), 1.0, -0.1, within_s=0.2), "band")
    assert attachments.end() == []


def test_waveform_assertion_error_is_assertion_error():
    e = failure(FAILING["assert_within"])
    assert isinstance(e, AssertionError)
    assert not isinstance(e, BenchUsageError)
    assert issubclass(BenchUsageError, ValueError)
