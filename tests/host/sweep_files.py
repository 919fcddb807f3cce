"""Sweep files of the live integration tests (discrepancy_live_integration.py,
calibrate_live_integration.py): the speed-only copy a real board would give, and the gap
between two sweeps of the same points as the workflows measure it."""
import csv

from live_device_integration import check

SPEED_ONLY = ["amplitude_v", "frequency_hz", "load_n", "time_s", "sweep", "speed_mm_s", "status"]


def speed_only(rows, path):
    """`rows` (a swum sweep file's dicts) with the speed alone, written to `path`."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(SPEED_ONLY)
        for r in rows:
            w.writerow([r[k] for k in SPEED_ONLY])


def relative_rms_gap(rows, device_rows):
    """RMS of (speed - device speed) / max(|device speed|, 5 % of the largest), as the workflow."""
    check([(r["amplitude_v"], r["frequency_hz"], r["load_n"]) for r in rows]
          == [(r["amplitude_v"], r["frequency_hz"], r["load_n"]) for r in device_rows], "the sweeps' points differ")
    device = [float(r["speed_mm_s"]) for r in device_rows]
    floor = 0.05 * max(abs(v) for v in device)
    gaps = [(float(r["speed_mm_s"]) - v) / max(abs(v), floor) for r, v in zip(rows, device)]
    return (sum(g * g for g in gaps) / len(gaps)) ** 0.5
