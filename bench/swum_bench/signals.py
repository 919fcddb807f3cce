"""Captured signals: one value per control cycle, stamped with the emulated time (seconds from
the emulator's start). No wall-clock time is ever stored here."""
import csv
import math

import numpy as np


class BenchUsageError(ValueError):
    """A bench call with bad arguments (a negative band, an empty window, an unknown signal...):
    a mistake in the test, not a failure of the controller under test."""


class Signal:
    """A named, unit-carrying series of (time_s, value) in emulated time, sorted by time."""

    def __init__(self, name, unit, time_s, values):
        t = np.asarray(time_s, dtype=float)
        v = np.asarray(values, dtype=float)
        if t.ndim != 1 or v.ndim != 1 or t.shape != v.shape:
            raise BenchUsageError(f"signal {name}: time_s and values must be 1-D and of the same length "
                                  f"(got {t.shape} and {v.shape})")
        if t.size and (not np.all(np.isfinite(t)) or np.any(np.diff(t) < 0)):
            raise BenchUsageError(f"signal {name}: times must be finite and non-decreasing")
        self.name = name
        self.unit = unit
        self.time_s = t
        self.values = v

    def __len__(self):
        return int(self.time_s.size)

    def __repr__(self):
        span = f"{self.time_s[0]:.4f}..{self.time_s[-1]:.4f} s" if len(self) else "empty"
        return f"Signal({self.name} [{self.unit}], {len(self)} samples, {span})"

    def label(self):
        return f"{self.name} [{self.unit}]" if self.unit else self.name

    def window(self, start_s=None, end_s=None, what="window"):
        """The samples with start_s <= t <= end_s (None = the signal's own end). An empty
        result is a BenchUsageError naming the signal and its span."""
        lo = self.time_s[0] if start_s is None and len(self) else start_s
        hi = self.time_s[-1] if end_s is None and len(self) else end_s
        for name, value in (("start_s", lo), ("end_s", hi)):
            if value is not None and not _finite_number(value):
                raise BenchUsageError(f"{what}: {name} must be a finite number of seconds, not {value!r}")
        if lo is not None and hi is not None and hi < lo:
            if end_s is None:
                raise BenchUsageError(f"{what}: no samples of {self.name} from {lo:g} s on: the signal ends at "
                                      f"{hi:g} s (step the bench further)")
            raise BenchUsageError(f"{what}: empty window: end {hi:g} s is before start {lo:g} s")
        mask = np.ones(self.time_s.shape, dtype=bool)
        if lo is not None:
            mask &= self.time_s >= lo
        if hi is not None:
            mask &= self.time_s <= hi
        if not mask.any():
            span = f"{self.time_s[0]:g}..{self.time_s[-1]:g} s" if len(self) else "no samples at all"
            raise BenchUsageError(f"{what}: no samples of {self.name} in [{_fmt(lo)}, {_fmt(hi)}] s "
                                  f"(the signal spans {span})")
        return Signal(self.name, self.unit, self.time_s[mask], self.values[mask])

    def at(self, time_s):
        """The value of the last sample at or before time_s (signals are sampled, not continuous)."""
        if not _finite_number(time_s):
            raise BenchUsageError(f"{self.name}.at: time_s must be a finite number of seconds, not {time_s!r}")
        i = int(np.searchsorted(self.time_s, time_s, side="right")) - 1
        if i < 0:
            raise BenchUsageError(f"{self.name}: no sample at or before {time_s:g} s")
        return float(self.values[i])


def _finite_number(value):
    return (not isinstance(value, (bool, np.bool_)) and isinstance(value, (int, float, np.integer, np.floating))
            and math.isfinite(value))


def _fmt(value):
    return "-" if value is None else f"{value:g}"


def write_csv(path, samples, units=None):
    """Samples ({name: value} per cycle, the same names in each) as CSV: a header of
    "name [unit]" and repr() numbers, so that equal captures give equal bytes."""
    if not samples:
        raise BenchUsageError("write_csv: nothing captured")
    names = sorted(samples[0], key=lambda n: n != "time_s")  # time first, then as captured
    units = units or {}
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow([f"{n} [{units[n]}]" if units.get(n) else n for n in names])
        for sample in samples:
            w.writerow([repr(float(sample[n])) for n in names])
