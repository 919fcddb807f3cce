#!/usr/bin/python3
"""From a live sweep to the missing effect (docs/host.md, "From a live sweep to an augmented
config"): swum-emu runs the calibrated motor with one effect hidden in its config, `swum sweep
--modbus` measures it across the softening resonance, only the speed is kept (a real board
measures speed only), and `swum discrepancy` holds the calibrated config against that file.

  discrepancy_live_integration.py preload | guide_friction | thermal

Asserted: the hidden effect is named first and alone, the held-out RMS gap shrinks by >= 70 %,
the augmented config enables that effect alone, the fitted value is within 3 reported standard
errors or PROTOCOL_ALLOWANCE of the truth, whichever is wider, and swum-emu running the
augmented config reproduces the device: the same live sweep on it is within 30 % of the
baseline's held-out gap (relative RMS, the workflow's floor of 5 % of the largest speed).

Why the allowance: the emulator's telemetry has no measurement noise, so the reported standard
error (from the fit's residual) only measures how far the model's measurement protocol is from
the live sweep, and it shrinks with the number of points while that mismatch does not. Above
the softening peak (39800-41000 Hz) the live sweep and the model agree to ~0.1 % and the fits
land within 0.1 % of the truth (preload 0.8007, guide friction 0.03999), still several standard
errors away; across the peak, where the curve has collapsed and the speed depends on the
mover's history (per-point spreads of several mm/s), they are pulled by 0.7-3.5 % (preload
0.8055, guide friction 0.0386, thermal 7.90 K/W), 7-50 standard errors.
"""
import csv
import json
import os
import sys
import tempfile
import tomllib

from live_device_integration import check, swum  # also puts ../firmware_sim on the path
from sweep_files import relative_rms_gap, speed_only

import emu_harness
from emu_harness import CONFIG, Emulator

OUT = tempfile.mkdtemp(prefix="swum-discrepancy-live-")
# --speedup 4: the ~33 s thermal session takes ~8 s; a generous watchdog, as in
# live_device_integration.py (a shared CI machine can stall the client for a while).
EMU_ARGS = ["--speedup", "4", "--watchdog-ms", "5000"]
GRID = ["--amplitude-v", "150,250,350", "--frequency-hz", "39200:41000:150", "--load", "0,2"]
POINTS_PER_CURVE = 13
CURVES = 3 * 2
PROTOCOL_ALLOWANCE = 0.06  # relative; see the module docstring
MIN_GAP_REDUCTION = 0.70

# effect -> (parameter, true value, extra sweep arguments). The thermal time constant is 30 s:
# longer settle and dwell make a session of ~33 s of device time, long enough to heat up.
CASES = {
    "preload": ("preload_factor", 0.8, []),
    "guide_friction": ("extra_coefficient", 0.04, []),
    "thermal": ("thermal_resistance_k_per_w", 8.0, ["--settle-ms", "300", "--dwell-ms", "100"]),
}


def emulator(config, *args):
    """swum-emu on `config` (emu_harness.Emulator starts its module's CONFIG)."""
    saved = emu_harness.CONFIG
    emu_harness.CONFIG = config
    try:
        return Emulator(*args)
    finally:
        emu_harness.CONFIG = saved


def hidden_effect_config(effect, key, value, path):
    with open(CONFIG) as f:
        text = f.read()
    with open(path, "w") as f:
        f.write(text + f"\n[effects.{effect}]\nenabled = true\n{key} = {value}\n")


def live_sweep(config, extra, path):
    with emulator(config, *EMU_ARGS) as emu:
        status, out, err = swum("sweep", "--modbus", f"tcp://{emu.host}:{emu.port}", *GRID, *extra, "--out", path)
        check(status == 0, f"live sweep failed ({status}): {err}")
        check(emu.stop() == 0, f"swum-emu exit status {emu.proc.returncode}: {emu.stderr}")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    check(len(rows) == POINTS_PER_CURVE * CURVES, f"{len(rows)} rows")
    # Each (load, voltage) curve is one continuous sweep, timed on the device clock.
    ids = [int(r["sweep"]) for r in rows]
    check(ids == [k // POINTS_PER_CURVE for k in range(len(rows))], f"sweep ids {ids}")
    times = [float(r["time_s"]) for r in rows]
    check(all(b > a for a, b in zip(times, times[1:])), "time_s does not increase")
    return rows


def run_case(effect):
    key, truth, extra = CASES[effect]
    config = os.path.join(OUT, f"{effect}.toml")
    hidden_effect_config(effect, key, truth, config)
    rows = live_sweep(config, extra, os.path.join(OUT, f"{effect}_sweep.csv"))
    measured = os.path.join(OUT, f"{effect}_speed.csv")
    speed_only(rows, measured)
    report = os.path.join(OUT, f"{effect}_report")
    status, out, err = swum("discrepancy", "--config", CONFIG, "--measured", measured, "--out", report, "--json")
    check(status == 0, f"discrepancy failed ({status}): {err}")
    result = json.loads(out)

    names = [e["name"] for e in result["effects"]]
    print(f"{effect} ({key} = {truth}), {len(rows)} points over {float(rows[-1]['time_s']):.1f} s of device time")
    print(f"  conclusion: {result['conclusion']}")
    for e in result["effects"]:
        for k, p in e["parameters"].items():
            print(f"  named {e['name']}: {k} = {p['value']:.6g} +- {p['standard_error']:.2g} {p['unit']}")
    before, after = result["rms_before"], result["rms_after"]
    reduction = 1.0 - after / before if before > 0 else 0.0
    print(f"  held-out RMS gap {100 * before:.3g} % -> {100 * after:.3g} % (reduction {100 * reduction:.1f} %),"
          f" {result['wall_s']:.1f} s")

    check(names[:1] == [effect], f"named {names}, expected {effect} first")
    check(names == [effect], f"named {names}, expected {effect} alone")
    p = result["effects"][0]["parameters"][key]
    miss = abs(p["value"] - truth)
    within_se = miss <= 3 * p["standard_error"]
    print(f"  |fit - truth| = {miss:.3g}: {miss / p['standard_error']:.1f} standard errors, "
          f"{100 * miss / truth:.2f} % of the value ({'within' if within_se else 'not within'} 3 SE)")
    check(within_se or miss <= PROTOCOL_ALLOWANCE * truth,
          f"{key} = {p['value']} +- {p['standard_error']}, truth {truth}")
    check(reduction >= MIN_GAP_REDUCTION, f"held-out gap {before} -> {after}: reduction {reduction:.2f} < 0.70")
    augmented = os.path.join(report, "augmented.toml")
    with open(augmented, "rb") as f:
        effects = tomllib.load(f)["effects"]
    enabled = [name for name, table in effects.items() if table["enabled"]]
    check(enabled == [effect] and abs(effects[effect][key] - p["value"]) <= 1e-5 * abs(p["value"]),
          f"augmented.toml enables {enabled} with {key} = {effects[effect].get(key)}")

    # The augmented config on swum-emu reproduces the device.
    replay = live_sweep(augmented, extra, os.path.join(OUT, f"{effect}_augmented_sweep.csv"))
    gap = relative_rms_gap(replay, rows)
    print(f"  swum-emu --config augmented.toml vs the device: RMS gap {100 * gap:.3g} %")
    check(gap <= (1.0 - MIN_GAP_REDUCTION) * before, f"augmented emulator {gap} vs device; baseline gap {before}")


if __name__ == "__main__":
    case = sys.argv[1] if len(sys.argv) > 1 else ""
    if case not in CASES:
        sys.exit(f"usage: {sys.argv[0]} {'|'.join(CASES)}")
    run_case(case)
    print(f"{case}: PASS")
