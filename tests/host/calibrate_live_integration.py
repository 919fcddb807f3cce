#!/usr/bin/python3
"""From a live sweep to a calibrated config (`swum calibrate`, src/analysis/calibration/calibration.h):
swum-emu runs a motor of the design whose base parameters differ from config/li2019.toml
(preload 24.8 -> 22.5 N, L1 damping 39 -> 44 N s/m, friction coefficient 0.35 -> 0.33, c1111
-0.85e17 -> -1.0e17 Pa), `swum sweep --modbus` measures it across the softening resonance at two
loads, only the speed is kept (a real board measures speed only), and `swum calibrate` fits those
four and e311 (the quadratic voltage-dependent stiffness, flat in speed sweeps as in free-stator
amplitudes, docs/identification.md) starting from config/li2019.toml.

The device's speed telemetry is noisy: the emulator runs with `--inject speed_noise@0:sigma_mm_s=3`
(docs/scenarios.md; Gaussian, seeded by the scenario's default seed 0), which the sweep averages
over each point's dwell (its speed_spread_mm_s column shows it).

Asserted: stator.e311_c_per_v_m is not identifiable (no standard error, held at its prior, a reason);
each perturbed parameter that is identifiable lies within 3 reported standard errors or
PROTOCOL_ALLOWANCE of its truth, whichever is wider; the held-out RMS gap after the fit is
<= 30 % of the prior's; fitted.toml parses and carries the fitted values (e311 at its prior);
the report directory holds report.md and summary.json; and swum-emu running fitted.toml
reproduces the device: the same live sweep on it is within 30 % of the gap between the device
and swum-emu on the prior config (relative RMS, the workflow's floor of 5 % of the largest speed).

Why an allowance at all: the model predicts each point with the sweep's own protocol (PROTOCOL:
settle 50 ms, average 50 ms) and each sweep as one continuous run, but the first point of each
sweep is reached by a voltage ramp on the device and from rest in the model, and the device
samples its speed at the loop's ticks. What is left lands the fits 0.01-0.2 % from the truth
(0.1-2.3 standard errors in the runs seen); PROTOCOL_ALLOWANCE (1 %) is the margin for it.
"""
import csv
import json
import os
import tempfile
import time
import tomllib

from live_device_integration import check, swum  # also puts ../firmware_sim on the path
from sweep_files import relative_rms_gap, speed_only

from emu_harness import CONFIG, Emulator

OUT = tempfile.mkdtemp(prefix="swum-calibrate-live-")
# --speedup 4: a sweep of 114 points takes ~5 s; a generous watchdog, as in
# live_device_integration.py (a shared CI machine can stall the client for a while).
EMU_ARGS = ["--speedup", "4", "--watchdog-ms", "5000"]
NOISE = ["--inject", "speed_noise@0:sigma_mm_s=3"]
GRID = ["--amplitude-v", "150,250,350", "--frequency-hz", "39200:41000:100", "--load", "0,2"]
POINTS_PER_CURVE = 19
CURVES = 3 * 2
# The model predicts each point as the sweep took it: settle 50 ms, average 50 ms (swum sweep's
# device defaults). With the model's shorter default protocol (40 + 10 ms) the predictions lag
# the device where the speed changes fast between points, and the fit used the mover's mass to
# make up the lag (0.14 kg, on its bound, in 8 of 13 runs). With the protocol matched the mass
# is determined (the mover's inertia sets the transient within each 50 ms settle) and lands
# within its standard error of 0.2 kg; it is not among the free parameters here.
PROTOCOL = ["--settle-ms", "50", "--dwell-ms", "50"]
PROTOCOL_ALLOWANCE = 0.01  # relative; see the module docstring
MAX_GAP_FRACTION = 0.30

# The device's parameters: (section, key) -> (the line of config/li2019.toml up to its comment,
# the replacement, the true value).
TRUTH = {
    ("contact", "preload_n"): ("preload_n = 24.8 ", "preload_n = 22.5 ", 22.5),
    ("stator", "damping_l1_n_s_m"): ("damping_l1_n_s_m = 39.0 ", "damping_l1_n_s_m = 44.0 ", 44.0),
    ("contact", "friction_coefficient"): ("friction_coefficient = 0.35 ", "friction_coefficient = 0.33 ", 0.33),
    ("stator", "c1111_pa"): ("c1111_pa = -0.85e17 ", "c1111_pa = -1.0e17 ", -1.0e17),
}
UNSEEN = "stator.e311_c_per_v_m"
FREE = [f"{s}.{k}" for s, k in TRUTH] + [UNSEEN]


def device_config(path):
    """config/li2019.toml with the TRUTH lines replaced (each must occur exactly once, at a line start)."""
    with open(CONFIG) as f:
        lines = f.read().split("\n")
    for old, new, _ in TRUTH.values():
        hits = [i for i, line in enumerate(lines) if line.startswith(old)]
        check(len(hits) == 1, f"{CONFIG}: {len(hits)} lines start with {old!r}")
        lines[hits[0]] = new + lines[hits[0]][len(old):]
    with open(path, "w") as f:
        f.write("\n".join(lines))
    with open(path, "rb") as f:
        table = tomllib.load(f)
    for (section, key), (_, _, value) in TRUTH.items():
        check(table[section][key] == value, f"{path}: {section}.{key} = {table[section][key]}")


def live_sweep(config, path, *emu_extra):
    with Emulator(*EMU_ARGS, *emu_extra, config=config) as emu:
        status, out, err = swum("sweep", "--modbus", f"tcp://{emu.host}:{emu.port}", *GRID, "--out", path)
        check(status == 0, f"live sweep failed ({status}): {err}")
        check(emu.stop() == 0, f"swum-emu exit status {emu.proc.returncode}: {emu.stderr}")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    check(len(rows) == POINTS_PER_CURVE * CURVES, f"{len(rows)} rows")
    check(all(r["status"] == "ok" for r in rows), "failed rows in the live sweep")
    # Each (load, voltage) curve is one continuous sweep, timed on the device clock.
    ids = [int(r["sweep"]) for r in rows]
    check(ids == [k // POINTS_PER_CURVE for k in range(len(rows))], f"sweep ids {ids}")
    times = [float(r["time_s"]) for r in rows]
    check(all(b > a for a, b in zip(times, times[1:])), "time_s does not increase")
    return rows


def main():
    start = time.monotonic()
    truth_config = os.path.join(OUT, "device.toml")
    device_config(truth_config)
    rows = live_sweep(truth_config, os.path.join(OUT, "device_sweep.csv"), *NOISE)
    spreads = [float(r["speed_spread_mm_s"]) for r in rows]
    print(f"device: {len(rows)} points over {float(rows[-1]['time_s']):.1f} s of device time, speed noise "
          f"(spread per point) median {sorted(spreads)[len(spreads) // 2]:.2f} mm/s")
    check(sorted(spreads)[len(spreads) // 2] > 1.0, "the injected speed noise does not show in the sweep")
    measured = os.path.join(OUT, "speed.csv")
    speed_only(rows, measured)

    fitted_path = os.path.join(OUT, "fitted.toml")
    report = os.path.join(OUT, "report")
    status, out, err = swum("calibrate", "--config", CONFIG, "--measured", measured, "--free", ",".join(FREE),
                            *PROTOCOL, "--out", fitted_path, "--report", report, "--json")
    check(status == 0, f"calibrate failed ({status}): {err}")
    result = json.loads(out)
    params = {p["name"]: p for p in result["parameters"]}
    check(sorted(params) == sorted(FREE), f"parameters {sorted(params)}")
    m = result["measurements"]
    print(f"  conclusion: {result['conclusion']}")
    print(f"  {m['operating_points']} operating points, {m['held_out_points']} held out; noise estimate "
          f"{100 * m['noise']:.3g} % ({m['noise_source']}); {result['rounds']} rounds, {result['starts']} starts, "
          f"{result['model_evaluations']} model evaluations, {result['wall_s']:.1f} s")

    # e311: the sweep cannot determine it. Checked last, so that every figure is printed.
    unseen = params[UNSEEN]
    print(f"  {UNSEEN} = {unseen['value']:.6g} +- {unseen['standard_error']} {unseen['unit']} (prior {unseen['prior']}, truth "
          f"{unseen['prior']}): identifiable {unseen['identifiable']}{', AT A BOUND' if unseen['at_bound'] else ''}"
          f"{': ' + unseen['reason'] if unseen['reason'] else ''}")
    unseen_held = (not unseen["identifiable"] and unseen["standard_error"] is None and unseen["value"] == unseen["prior"]
                 and unseen["reason"] != "")

    # The perturbed parameters.
    identified = 0
    for (section, key), (_, _, truth) in TRUTH.items():
        p = params[f"{section}.{key}"]
        if not p["identifiable"]:
            print(f"  {p['name']}: not identifiable ({p['reason']}); truth {truth:.6g}")
            check(p["standard_error"] is None and p["value"] == p["prior"], f"{p['name']}: {p}")
            continue
        identified += 1
        se = p["standard_error"]
        miss = abs(p["value"] - truth)
        within_se = miss <= 3 * se
        print(f"  {p['name']} = {p['value']:.6g} +- {se:.2g} {p['unit']} (prior {p['prior']:.6g}, truth {truth:.6g}): "
              f"|fit - truth| {miss / se:.1f} SE, {100 * miss / abs(truth):.2f} % of the truth"
              f" ({'within' if within_se else 'not within'} 3 SE){'  AT A BOUND' if p['at_bound'] else ''}")
        check(within_se or miss <= PROTOCOL_ALLOWANCE * abs(truth),
              f"{p['name']} = {p['value']} +- {se}, truth {truth}")
    check(identified == len(TRUTH), f"{identified} of the {len(TRUTH)} perturbed parameters identified")

    before, after = m["held_out_rms_prior"], m["held_out_rms"]
    print(f"  held-out RMS gap {100 * before:.3g} % -> {100 * after:.3g} % ({100 * after / before:.1f} % of before); "
          f"training {100 * m['train_rms_prior']:.3g} % -> {100 * m['train_rms']:.3g} %")
    check(after <= MAX_GAP_FRACTION * before, f"held-out gap {before} -> {after}: more than 30 % left")

    # fitted.toml: the prior config with the fitted values (e311 at its prior).
    with open(fitted_path, "rb") as f:
        fitted = tomllib.load(f)
    for name, p in params.items():
        section, key = name.split(".")
        value = fitted[section][key]
        check(abs(value - p["value"]) <= 1e-5 * abs(p["value"]), f"fitted.toml: {name} = {value}, fit {p['value']}")
    for name in ("report.md", "summary.json"):
        check(os.path.isfile(os.path.join(report, name)), f"{name} missing from {report}")

    # fitted.toml on swum-emu reproduces the device; the prior config does not.
    prior_rows = live_sweep(CONFIG, os.path.join(OUT, "prior_sweep.csv"))
    replay = live_sweep(fitted_path, os.path.join(OUT, "fitted_sweep.csv"))
    prior_gap, fitted_gap = relative_rms_gap(prior_rows, rows), relative_rms_gap(replay, rows)
    print(f"  swum-emu vs the device, RMS gap: prior config {100 * prior_gap:.3g} %, fitted.toml "
          f"{100 * fitted_gap:.3g} % ({100 * fitted_gap / prior_gap:.1f} % of the prior's)")
    check(fitted_gap <= MAX_GAP_FRACTION * prior_gap, f"fitted emulator gap {fitted_gap} vs prior {prior_gap}")
    print(f"  wall time {time.monotonic() - start:.1f} s; files in {OUT}")
    check(unseen_held, f"{UNSEEN} should be held at its prior as not identifiable: {unseen}")


if __name__ == "__main__":
    main()
    print("calibrate: PASS")
