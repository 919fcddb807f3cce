"""Waveform assertions on captured signals, in emulated time (docs/testing-controllers.md).

Common rules:
- Times are emulated seconds from the emulator's start; windows include both ends; a window
  without samples, a negative band / tolerance / duration, a non-finite argument are
  BenchUsageError (a mistake in the test, not a controller failure).
- A value on the edge of a band is inside it (compared with a rounding allowance of 1e-12
  relative to the values' scale), and a sample at a deadline is at it (times within 1 ns:
  0.1 + 0.2 is 0.3 here).
- A NaN in the analysed window fails the assertion at the NaN's time: a controller or a plant
  that produces a non-number has failed, whatever the rest of the signal does.
- A failure raises WaveformAssertionError naming the assertion, the signal, the first violating
  time and the values there; inside pytest it also attaches a PNG of the signal with its band.
Each assertion returns what it measured (a settling time, an overshoot, a rise time...)."""
import math
import reprlib

import numpy as np

from .plot import failure_plot
from .signals import BenchUsageError, Signal


class WaveformAssertionError(AssertionError):
    """A failed waveform assertion: the message names it, the time and the values; `plot` is the
    attached PNG (or None), `time_s` the first violating time (None if there is none)."""

    def __init__(self, message, plot=None, time_s=None):
        super().__init__(message + (f"; plot: {plot}" if plot else ""))
        self.plot = plot
        self.time_s = time_s


def _number(what, name, value, minimum=None, strict=False):
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) \
            or not math.isfinite(value):
        raise BenchUsageError(f"{what}: {name} must be a finite number, not {_describe(value)}")
    value = float(value)
    if minimum is not None and (value < minimum or (strict and value == minimum)):
        relation = ">" if strict else ">="
        raise BenchUsageError(f"{what}: {name} must be {relation} {minimum:.9g}, got {value:.9g}")
    return value


def _describe(value):
    """A one-line description of a value for an error message (no multi-line numpy repr)."""
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape}"
    return reprlib.repr(value).replace("\n", " ")


def _signal(what, signal):
    if not isinstance(signal, Signal):
        raise BenchUsageError(f"{what}: expected a Signal (bench.signal(NAME)), not {type(signal).__name__}")
    return signal


def _slack(*scales):
    return 1e-12 * max([1.0] + [abs(float(s)) for s in scales if math.isfinite(s)])


TIME_SLACK_S = 1e-9  # emulated times are whole ticks (>= 1 us); sums like 0.1 + 0.2 miss by ~1e-17


def _u(unit):
    return f" {unit}" if unit else ""


def _v(value, unit):
    return f"{value:.9g}{(' ' + unit) if unit else ''}"


def _first_nan(w):
    bad = np.flatnonzero(np.isnan(w.values))
    return None if bad.size == 0 else int(bad[0])


def _fail(assertion, w, message, time_s, value, band=None, reference=None, marks=()):
    full = f"{assertion}({w.name}) failed: {message}"
    plot = failure_plot(assertion, w, full, band=band, reference=reference, marks=marks,
                        violation=None if time_s is None else (time_s, value))
    raise WaveformAssertionError(full, plot=plot, time_s=time_s)


def _nan_check(assertion, w, band=None, reference=None, marks=()):
    i = _first_nan(w)
    if i is not None:
        _fail(assertion, w, f"NaN at t = {w.time_s[i]:.6f} s", float(w.time_s[i]), float("nan"),
              band=band, reference=reference, marks=marks)


def assert_settles(signal, target, band, within_s, start_s=None, end_s=None):
    """From start_s (default: the first sample), the signal is within target ± band at every
    sample after start_s + within_s, to end_s (default: the last sample). Returns the settling
    time: the first time from which every later sample of the window is inside, minus start_s."""
    what = "assert_settles"
    signal = _signal(what, signal)
    target = _number(what, "target", target)
    band = _number(what, "band", band, minimum=0)
    within_s = _number(what, "within_s", within_s, minimum=0)
    w = signal.window(start_s, end_s, what)
    start = float(w.time_s[0]) if start_s is None else _number(what, "start_s", start_s)
    deadline = start + within_s
    if w.time_s[-1] < deadline - TIME_SLACK_S:
        raise BenchUsageError(f"{what}: the window ends at {w.time_s[-1]:.9g} s, before the deadline "
                              f"{deadline:.9g} s (start {start:.9g} s + within {within_s:.9g} s): nothing to check")
    lo, hi = target - band, target + band
    marks = [(deadline, "deadline")]
    _nan_check(what, w, band=(lo, hi), marks=marks)
    inside = np.abs(w.values - target) <= band + _slack(target, band, *w.values)
    outside = np.flatnonzero(~inside)
    settled_at = float(w.time_s[0]) if outside.size == 0 else None
    if outside.size and outside[-1] + 1 < len(w):
        settled_at = float(w.time_s[outside[-1] + 1])
    late = np.flatnonzero(~inside & (w.time_s >= deadline - TIME_SLACK_S))
    if late.size:
        i = int(late[0])
        when = ("it never settles (the last sample is outside)" if settled_at is None
                else f"it settles only at {settled_at:.6f} s")
        _fail(what, w, f"not within {target:.9g} ± {band:.9g}{_u(w.unit)} from {deadline:.6f} s "
                       f"(start {start:.9g} s + {within_s:.9g} s): first violation at t = {w.time_s[i]:.6f} s, "
                       f"value {_v(w.values[i], w.unit)} (off by {w.values[i] - target:+.6g}); {when}",
              float(w.time_s[i]), float(w.values[i]), band=(lo, hi), marks=marks)
    return settled_at - start


def assert_within(signal, low, high, start_s=None, end_s=None):
    """Every sample in [start_s, end_s] is within [low, high]."""
    what = "assert_within"
    signal = _signal(what, signal)
    low = _number(what, "low", low)
    high = _number(what, "high", high)
    if high < low:
        raise BenchUsageError(f"{what}: high {high:.9g} is below low {low:.9g}")
    w = signal.window(start_s, end_s, what)
    _nan_check(what, w, band=(low, high))
    slack = _slack(low, high, *w.values)
    bad = np.flatnonzero((w.values < low - slack) | (w.values > high + slack))
    if bad.size:
        i = int(bad[0])
        _fail(what, w, f"leaves [{low:.9g}, {high:.9g}]{_u(w.unit)} at t = {w.time_s[i]:.6f} s, value "
                       f"{_v(w.values[i], w.unit)} (window {w.time_s[0]:.9g}..{w.time_s[-1]:.9g} s; "
                       f"{bad.size} of {len(w)} samples outside)",
              float(w.time_s[i]), float(w.values[i]), band=(low, high))
    return float(np.max(np.abs(w.values - 0.5 * (low + high))))


def _step(what, w, target, initial):
    if initial is None:
        _nan_check(what, w.window(None, w.time_s[0], what))  # a NaN first sample fails at its time
        initial = float(w.values[0])
    else:
        initial = _number(what, "initial", initial)
    step = target - initial
    if step == 0:
        raise BenchUsageError(f"{what}: the step is empty: target {target:.9g} equals the initial value "
                              f"{initial:.9g}")
    return initial, step


def assert_overshoot(signal, target, max_percent, start_s=None, end_s=None, initial=None):
    """A step from `initial` (default: the first sample of the window) to `target` overshoots by at
    most max_percent of the step. Returns the overshoot in percent (0 if it never passes target)."""
    what = "assert_overshoot"
    signal = _signal(what, signal)
    target = _number(what, "target", target)
    max_percent = _number(what, "max_percent", max_percent, minimum=0)
    w = signal.window(start_s, end_s, what)
    initial, step = _step(what, w, target, initial)
    limit = target + step * max_percent / 100.0
    band = (min(initial, limit), max(initial, limit))
    _nan_check(what, w, band=band)
    over = (w.values - target) / step * 100.0
    peak = int(np.argmax(over))
    worst = max(0.0, float(over[peak]))
    beyond = (w.values - limit) * np.sign(step)  # > 0: past the allowed overshoot
    bad = np.flatnonzero(beyond > _slack(limit, initial, target, *w.values))
    if bad.size:
        i = int(bad[0])
        _fail(what, w, f"overshoot {worst:.4g} % > {max_percent:.9g} % of the step {initial:.9g} -> {target:.9g} "
                       f"{w.unit}: first beyond at t = {w.time_s[i]:.6f} s, value {_v(w.values[i], w.unit)}; "
                       f"peak {_v(w.values[peak], w.unit)} at t = {w.time_s[peak]:.6f} s",
              float(w.time_s[i]), float(w.values[i]), band=band)
    return worst


def assert_rise_time(signal, target, max_s, start_s=None, end_s=None, initial=None, low=0.1, high=0.9):
    """The step from `initial` (default: the first sample) to `target` goes from low (10 %) to
    high (90 %) of the step within max_s. Returns the rise time."""
    what = "assert_rise_time"
    signal = _signal(what, signal)
    target = _number(what, "target", target)
    max_s = _number(what, "max_s", max_s, minimum=0)
    low = _number(what, "low", low, minimum=0)
    high = _number(what, "high", high)
    if not low < high <= 1:
        raise BenchUsageError(f"{what}: need 0 <= low < high <= 1, got low {low:.9g}, high {high:.9g}")
    w = signal.window(start_s, end_s, what)
    initial, step = _step(what, w, target, initial)
    level_lo, level_hi = initial + low * step, initial + high * step
    _nan_check(what, w, band=(min(level_lo, level_hi), max(level_lo, level_hi)))
    progress = (w.values - initial) / step
    slack = _slack(initial, target, *w.values)
    hits_lo = np.flatnonzero((w.values - level_lo) * np.sign(step) >= -slack)
    hits_hi = np.flatnonzero((w.values - level_hi) * np.sign(step) >= -slack)
    band = (min(level_lo, level_hi), max(level_lo, level_hi))
    if hits_hi.size == 0:
        best = int(np.argmax(progress))
        _fail(what, w, f"never reaches {high * 100:.9g} % of the step {initial:.9g} -> {target:.9g} ({level_hi:.9g} "
                       f"{w.unit}) by {w.time_s[-1]:.6f} s: closest {_v(w.values[best], w.unit)} at "
                       f"t = {w.time_s[best]:.6f} s", float(w.time_s[best]), float(w.values[best]), band=band)
    t_lo = float(w.time_s[hits_lo[0]])
    t_hi = float(w.time_s[hits_hi[0]])
    rise = t_hi - t_lo
    if rise > max_s + TIME_SLACK_S:
        late = t_lo + max_s
        i = max(int(np.searchsorted(w.time_s, late + TIME_SLACK_S, side="right")) - 1, 0)
        _fail(what, w, f"rise time {rise:.6f} s > {max_s:.9g} s ({low * 100:.9g} % at {t_lo:.6f} s, "
                       f"{high * 100:.9g} % = {level_hi:.9g}{_u(w.unit)} only at {t_hi:.6f} s); at t = "
                       f"{w.time_s[i]:.6f} s the value is {_v(w.values[i], w.unit)}",
              float(w.time_s[i]), float(w.values[i]), band=band,
              marks=[(t_lo, f"{low * 100:.9g} %"), (late, "limit")])
    return rise


def assert_reaches(signal, threshold, before_s, start_s=None, direction="above"):
    """The signal reaches the threshold (>= for direction "above", <= for "below") at a sample
    no later than before_s (absolute emulated time). Returns that sample's time."""
    what = "assert_reaches"
    signal = _signal(what, signal)
    threshold = _number(what, "threshold", threshold)
    before_s = _number(what, "before_s", before_s, minimum=0)
    if direction not in ("above", "below"):
        raise BenchUsageError(f"{what}: direction must be 'above' or 'below', not {direction!r}")
    w = signal.window(start_s, None, what)
    if before_s < w.time_s[0] - TIME_SLACK_S:
        raise BenchUsageError(f"{what}: before_s {before_s:.9g} s is before the window's start {w.time_s[0]:.9g} s")
    relation = ">=" if direction == "above" else "<="
    marks = [(before_s, "deadline")]
    upto = w.window(None, before_s + TIME_SLACK_S, what)
    _nan_check(what, upto, marks=marks)
    slack = _slack(threshold, *w.values)
    reached = w.values >= threshold - slack if direction == "above" else w.values <= threshold + slack
    hits = np.flatnonzero(reached)
    if hits.size and w.time_s[hits[0]] <= before_s + TIME_SLACK_S:
        return float(w.time_s[hits[0]])
    if w.time_s[-1] < before_s - TIME_SLACK_S:
        raise BenchUsageError(f"{what}: {w.name} ends at {w.time_s[-1]:.9g} s, before before_s {before_s:.9g} s, "
                              f"without reaching {relation} {threshold:.9g}: step the bench further")
    band = (threshold, np.nanmax(w.values)) if direction == "above" else (np.nanmin(w.values), threshold)
    i = int(np.searchsorted(w.time_s, before_s + TIME_SLACK_S, side="right")) - 1
    when = (f"it does so only at {w.time_s[hits[0]]:.6f} s" if hits.size
            else f"it never does by {w.time_s[-1]:.6f} s")
    _fail(what, w, f"not {relation} {threshold:.9g}{_u(w.unit)} by {before_s:.6f} s: at t = {w.time_s[i]:.6f} s "
                   f"the value is {_v(w.values[i], w.unit)}; {when}",
          float(w.time_s[i]), float(w.values[i]), band=band, marks=marks)


def _reference_values(what, reference, w):
    if isinstance(reference, Signal):
        if len(reference) == 0:
            raise BenchUsageError(f"{what}: the reference {reference.name} is empty")
        if w.time_s[0] < reference.time_s[0] or w.time_s[-1] > reference.time_s[-1]:
            raise BenchUsageError(f"{what}: the reference {reference.name} spans {reference.time_s[0]:.9g}.."
                                  f"{reference.time_s[-1]:.9g} s, not the whole window {w.time_s[0]:.9g}.."
                                  f"{w.time_s[-1]:.9g} s")
        return np.interp(w.time_s, reference.time_s, reference.values), reference.name
    if callable(reference):
        name = getattr(reference, "__name__", "reference")
        try:
            values = np.asarray([float(reference(float(t))) for t in w.time_s])
        except (TypeError, ValueError) as e:
            raise BenchUsageError(f"{what}: the reference {name}(t) must return a number: {e}") from e
        return values, name
    value = _number(what, "reference", reference)
    return np.full(w.time_s.shape, value), f"{value:.9g}"


def assert_follows(signal, reference, band, start_s=None, end_s=None):
    """|signal - reference| <= band at every sample in [start_s, end_s]. reference: a Signal
    (linearly interpolated at the samples' times), a function of time (s) or a number."""
    what = "assert_follows"
    signal = _signal(what, signal)
    band = _number(what, "band", band, minimum=0)
    w = signal.window(start_s, end_s, what)
    ref, ref_name = _reference_values(what, reference, w)
    _nan_check(what, w, band=(ref - band, ref + band), reference=ref)
    nan_ref = np.flatnonzero(~np.isfinite(ref))
    if nan_ref.size:
        raise BenchUsageError(f"{what}: the reference {ref_name} is not a finite number at "
                              f"t = {w.time_s[nan_ref[0]]:.9g} s")
    error = w.values - ref
    slack = 1e-12 * np.maximum(np.maximum(np.abs(ref), np.abs(w.values)), max(1.0, band))
    bad = np.flatnonzero(np.abs(error) > band + slack)
    if bad.size:
        i = int(bad[0])
        _fail(what, w, f"off the reference {ref_name} by more than {band:.9g}{_u(w.unit)} at t = "
                       f"{w.time_s[i]:.6f} s: value {_v(w.values[i], w.unit)}, reference {ref[i]:.9g} "
                       f"(error {error[i]:+.6g}); {bad.size} of {len(w)} samples outside",
              float(w.time_s[i]), float(w.values[i]), band=(ref - band, ref + band), reference=ref)
    return float(np.max(np.abs(error)))


def assert_fault_within(fault_code, code, injected_at_s, within_s):
    """The fault code signal shows `code` at a sample no later than within_s after injected_at_s.
    Returns the delay."""
    what = "assert_fault_within"
    fault_code = _signal(what, fault_code)
    if isinstance(code, bool) or not isinstance(code, (int, np.integer)) or code < 0:
        raise BenchUsageError(f"{what}: code must be an integer >= 0, not {code!r}")
    injected_at_s = _number(what, "injected_at_s", injected_at_s, minimum=0)
    within_s = _number(what, "within_s", within_s, minimum=0)
    w = fault_code.window(injected_at_s, None, what)
    deadline = injected_at_s + within_s
    marks = [(injected_at_s, "injection"), (deadline, "deadline")]
    before = np.flatnonzero(fault_code.time_s < injected_at_s - TIME_SLACK_S)
    if before.size and fault_code.values[before[-1]] == code:
        t = float(fault_code.time_s[before[-1]])
        _fail(what, fault_code, f"fault code {code} was already present at t = {t:.6f} s, before the injection at "
                                f"{injected_at_s:.9g} s: the injection did not cause it", t, float(code),
              band=(code, code), marks=marks)
    upto = w.window(None, deadline + TIME_SLACK_S, what) if w.time_s[0] <= deadline + TIME_SLACK_S else None
    if upto is not None:
        _nan_check(what, upto, marks=marks)
    hits = np.flatnonzero(w.values == code)
    if hits.size and w.time_s[hits[0]] <= deadline + TIME_SLACK_S:
        return float(w.time_s[hits[0]]) - injected_at_s
    if w.time_s[-1] < deadline - TIME_SLACK_S:
        raise BenchUsageError(f"{what}: {w.name} ends at {w.time_s[-1]:.9g} s, before the deadline {deadline:.9g} s, "
                              f"without code {code}: step the bench further")
    i = max(0, int(np.searchsorted(w.time_s, deadline + TIME_SLACK_S, side="right")) - 1)
    seen = sorted({int(v) for v in w.values[: i + 1] if np.isfinite(v)})
    when = f"it appears only at {w.time_s[hits[0]]:.6f} s" if hits.size else f"it never appears by {w.time_s[-1]:.6f} s"
    _fail(what, w, f"fault code {code} not within {within_s:.9g} s of the injection at {injected_at_s:.9g} s: at "
                   f"t = {w.time_s[i]:.6f} s the code is {w.values[i]:.9g} (codes seen: {seen}); {when}",
          float(w.time_s[i]), float(w.values[i]), band=(code, code), marks=marks)
