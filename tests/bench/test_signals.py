"""Unit tests of swum_bench.signals: Signal construction and its errors (mismatched lengths,
non-1-D arrays, decreasing or non-finite times), len/repr/label, window() (inclusive ends,
defaults, empty windows, bad bounds), at() (sampled, last sample at or before a time) and
write_csv() of a capture's samples (header with units, time first, repr numbers, byte-identical
files for equal captures).
"""
import csv
import math

import numpy as np
import pytest

from swum_bench import BenchUsageError, Signal
from swum_bench.signals import write_csv


def sig(name="speed", unit="mm/s"):
    return Signal(name, unit, [0.0, 0.1, 0.2, 0.3], [1.0, 2.0, 3.0, 4.0])


# ---- construction ----------------------------------------------------------------------------

def test_construction_converts_to_float_arrays():
    s = Signal("speed", "mm/s", [0, 1, 2], [3, 4, 5])
    assert s.name == "speed" and s.unit == "mm/s"
    assert s.time_s.dtype == float and s.values.dtype == float
    assert s.time_s.tolist() == [0.0, 1.0, 2.0]
    assert s.values.tolist() == [3.0, 4.0, 5.0]
    assert len(s) == 3


def test_mismatched_lengths():
    with pytest.raises(BenchUsageError, match=r"signal speed: time_s and values must be 1-D and of the same "
                                              r"length \(got \(2,\) and \(3,\)\)"):
        Signal("speed", "mm/s", [0.0, 0.1], [1.0, 2.0, 3.0])


def test_two_dimensional_values():
    with pytest.raises(BenchUsageError, match=r"1-D"):
        Signal("speed", "mm/s", [0.0, 0.1], [[1.0, 2.0], [3.0, 4.0]])


@pytest.mark.parametrize("times", [[0.0, 0.2, 0.1], [1.0, 0.0], [0.0, math.nan], [0.0, math.inf]])
def test_bad_times(times):
    with pytest.raises(BenchUsageError, match=r"signal speed: times must be finite and non-decreasing"):
        Signal("speed", "mm/s", times, [0.0] * len(times))


def test_equal_times_and_nan_values_are_allowed():
    s = Signal("speed", "mm/s", [0.0, 0.1, 0.1], [1.0, math.nan, 2.0])
    assert len(s) == 3
    assert math.isnan(s.values[1])


def test_empty_signal():
    s = Signal("speed", "mm/s", [], [])
    assert len(s) == 0
    assert repr(s) == "Signal(speed [mm/s], 0 samples, empty)"


def test_repr_and_label():
    assert repr(sig()) == "Signal(speed [mm/s], 4 samples, 0.0000..0.3000 s)"
    assert sig().label() == "speed [mm/s]"
    assert sig(name="state", unit="").label() == "state"


def test_bench_usage_error_is_value_error():
    assert issubclass(BenchUsageError, ValueError)


# ---- window ----------------------------------------------------------------------------------

def test_window_includes_both_ends():
    w = sig().window(0.1, 0.2)
    assert w.time_s.tolist() == [0.1, 0.2]
    assert w.values.tolist() == [2.0, 3.0]
    assert w.name == "speed" and w.unit == "mm/s"


def test_window_defaults_to_whole_signal():
    w = sig().window()
    assert w.time_s.tolist() == sig().time_s.tolist()
    assert sig().window(0.15).time_s.tolist() == [0.2, 0.3]
    assert sig().window(None, 0.15).time_s.tolist() == [0.0, 0.1]


def test_window_wider_than_signal():
    assert len(sig().window(-1.0, 10.0)) == 4


def test_window_single_point():
    w = sig().window(0.2, 0.2)
    assert w.values.tolist() == [3.0]


def test_window_does_not_alias_the_original():
    s = sig()
    w = s.window(0.1, 0.2)
    w.values[0] = 99.0
    assert s.values[1] == 2.0


def test_window_no_samples_between():
    with pytest.raises(BenchUsageError, match=r"check: no samples of speed in \[0.12, 0.18\] s "
                                              r"\(the signal spans 0..0.3 s\)"):
        sig().window(0.12, 0.18, what="check")


def test_window_end_before_start():
    with pytest.raises(BenchUsageError, match=r"window: empty window: end 0.1 s is before start 0.2 s"):
        sig().window(0.2, 0.1)


def test_window_start_after_signal():
    with pytest.raises(BenchUsageError, match=r"no samples of speed from 0.5 s on: the signal ends at 0.3 s \(step the bench further\)"):
        sig().window(0.5)


def test_window_of_empty_signal():
    with pytest.raises(BenchUsageError, match=r"no samples of speed in \[-, -\] s \(the signal spans no samples at all\)"):
        Signal("speed", "mm/s", [], []).window()


@pytest.mark.parametrize("bounds, name", [((math.nan, None), "start_s"), ((None, math.inf), "end_s"),
                                          (("0.1", None), "start_s"), ((None, [0.2]), "end_s")])
def test_window_bad_bounds(bounds, name):
    with pytest.raises(BenchUsageError, match=rf"window: {name} must be a finite number of seconds"):
        sig().window(*bounds)


# ---- at ----------------------------------------------------------------------------------------

def test_at_exact_sample_times():
    s = sig()
    assert [s.at(t) for t in s.time_s] == [1.0, 2.0, 3.0, 4.0]


def test_at_between_samples_takes_the_previous():
    s = sig()
    assert s.at(0.15) == 2.0
    assert s.at(0.0999) == 1.0
    assert s.at(100.0) == 4.0


def test_at_returns_float():
    assert type(sig().at(0.1)) is float


def test_at_before_first_sample():
    with pytest.raises(BenchUsageError, match=r"speed: no sample at or before -0.1 s"):
        sig().at(-0.1)


def test_at_on_empty_signal():
    with pytest.raises(BenchUsageError, match=r"no sample at or before"):
        Signal("speed", "mm/s", [], []).at(1.0)


def test_at_with_repeated_time_takes_the_last():
    s = Signal("speed", "mm/s", [0.0, 0.1, 0.1, 0.2], [1.0, 2.0, 3.0, 4.0])
    assert s.at(0.1) == 3.0


def test_at_nan_is_an_error():
    with pytest.raises(BenchUsageError):
        sig().at(math.nan)


# ---- write_csv ---------------------------------------------------------------------------------

UNITS = {"time_s": "s", "speed_mm_s": "mm/s", "state": "", "amplitude_v": "V"}


def capture():
    """Five cycles' samples ({name: value} each), time first, as the bench records them."""
    speeds = [0.0, 0.1, 1 / 3, -2.5e-7, 1e20]
    states = [0, 1, 1, 2, 2]
    amplitudes_v = [0.0, math.nan, 100.0, 100.0, 100.0]
    return [{"time_s": i / 1000.0, "speed_mm_s": speeds[i], "state": states[i], "amplitude_v": amplitudes_v[i]} for i in range(5)]


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def test_write_csv_content(tmp_path):
    path = tmp_path / "capture.csv"
    write_csv(str(path), capture(), UNITS)
    rows = read_rows(path)
    assert rows[0] == ["time_s [s]", "speed_mm_s [mm/s]", "state", "amplitude_v [V]"]
    assert len(rows) == 6
    assert rows[1] == ["0.0", "0.0", "0.0", "0.0"]
    assert rows[2] == ["0.001", "0.1", "1.0", "nan"]
    assert rows[3][1] == repr(1 / 3)
    assert rows[4][1] == "-2.5e-07"
    assert rows[5][1] == "1e+20"
    assert float(rows[3][1]) == 1 / 3  # repr numbers read back exactly


def test_write_csv_without_units(tmp_path):
    path = tmp_path / "capture.csv"
    write_csv(str(path), capture())
    assert read_rows(path)[0] == ["time_s", "speed_mm_s", "state", "amplitude_v"]


def test_write_csv_time_column_first(tmp_path):
    samples = [{"speed_mm_s": 1.0, "time_s": 0.0, "state": 1}, {"speed_mm_s": 2.0, "time_s": 0.001, "state": 1}]
    path = tmp_path / "capture.csv"
    write_csv(str(path), samples)
    rows = read_rows(path)
    assert rows[0] == ["time_s", "speed_mm_s", "state"]
    assert rows[2] == ["0.001", "2.0", "1.0"]


def test_write_csv_byte_identical_for_equal_captures(tmp_path):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    write_csv(str(a), capture(), UNITS)
    write_csv(str(b), capture(), dict(UNITS))
    assert a.read_bytes() == b.read_bytes()
    assert b"\r\n" in a.read_bytes()  # the csv module's own line ending, whatever the platform


def test_write_csv_numpy_values_same_bytes(tmp_path):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    write_csv(str(a), capture(), UNITS)
    write_csv(str(b), [{k: np.float64(v) for k, v in s.items()} for s in capture()], UNITS)
    assert a.read_bytes() == b.read_bytes()


def test_write_csv_differs_when_a_value_differs(tmp_path):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    write_csv(str(a), capture(), UNITS)
    other = capture()
    other[2]["state"] = 2
    write_csv(str(b), other, UNITS)
    assert a.read_bytes() != b.read_bytes()


def test_write_csv_nothing_captured(tmp_path):
    with pytest.raises(BenchUsageError, match=r"write_csv: nothing captured"):
        write_csv(str(tmp_path / "x.csv"), [])
