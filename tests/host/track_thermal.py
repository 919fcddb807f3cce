#!/usr/bin/python3
"""`swum track` against swum-emu in lockstep with the thermal motor (config/li2019_thermal.toml),
ten minutes of emulated running at 400 V (docs/host.md "swum track", docs/validation.md
"Tracking the drift"):

  track_thermal.py ten_minutes   the cold pick held fixed loses a share of the best speed; tracking
                                 by phase and by speed each keep >= 90 % of the best speed at the
                                 same margin above the peak at that moment's temperature (the
                                 reference: `swum band` over temperature rises, `swum track-report`)
  track_thermal.py interrupt     SIGINT mid-run: exit 130, the drive off, the log complete

Runs are in emulated time (lockstep): nothing here depends on the wall clock, only on readiness
lines and files.
"""
import csv
import json
import os
import signal
import subprocess
import sys
import tempfile
import types

try:  # pymodbus 3.0 imports its serial client eagerly; TCP needs none of it
    import serial_asyncio  # noqa: F401
except ImportError:
    sys.modules["serial_asyncio"] = types.SimpleNamespace(create_serial_connection=None)

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../firmware_sim"))
from emu_harness import SOURCE_DIR, Emulator  # noqa: E402

SWUM = os.environ["SWUM_BINARY"]
THERMAL = os.path.join(SOURCE_DIR, "config/li2019_thermal.toml")
OUT = os.environ.get("SWUM_TRACK_OUT") or tempfile.mkdtemp(prefix="swum-track-")
V = 400
MARGIN_HZ = 100
DURATION_S = 600


def check(condition, message):
    if not condition:
        raise AssertionError(message)


def emulator():
    # Connection timeouts far above a stall of this loaded machine (the test measures tracking;
    # the connection rules have their own tests, emu.modbus.lockout.*): beside the guest tier
    # the server's 500 ms frame/reply timeout once closed a lockstep step's connection.
    return Emulator("--clock", "external", "--duration-s", "100000", "--modbus-frame-timeout-ms", "10000",
                    "--modbus-idle-timeout-ms", "60000", config=THERMAL)


# Lockstep: time is emulated, so the link's wall-time limits are hang guards only. At swum's
# defaults (500 ms per answer) a step of an emulator starved by the rest of the ci stage failed
# ("no answer within the response timeout") in a cold run.
LINK = ["--connect-timeout-ms", "60000", "--timeout-ms", "60000"]


def track_command(emu, method, out, duration_s=DURATION_S, *extra):
    return [SWUM, "track", "--modbus", f"tcp://{emu.host}:{emu.port}", *LINK, "--amplitude-v", str(V), "--method", method,
            "--margin-hz", str(MARGIN_HZ), "--duration-s", str(duration_s), "--out", out, *extra]


def rows_of(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def ten_minutes():
    methods = ["phase", "speed", "fixed"]
    emus = [emulator() for _ in methods]
    try:
        procs = {m: subprocess.Popen(track_command(e, m, os.path.join(OUT, f"track_{m}.csv"), DURATION_S, "--plot-dir",
                                                   os.path.join(OUT, f"plots_{m}")),
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                 for m, e in zip(methods, emus)}
        # The reference while the runs go: the model's best speed at peak + margin per temperature rise.
        band_csv = os.path.join(OUT, "band.csv")
        band = subprocess.run([SWUM, "band", "--config", THERMAL, "--amplitude-v", str(V), "--margin-hz", str(MARGIN_HZ),
                               "--temperature-rise-k", "0,10,20,30,40,50,60,70,80,90,100", "--out", band_csv,
                               "--jobs", "1"], capture_output=True, text=True, timeout=600)
        check(band.returncode == 0, f"swum band: {band.stderr}")
        results = {}
        for m, p in procs.items():
            out, err = p.communicate(timeout=1200)
            check(p.returncode == 0, f"swum track --method {m}: exit {p.returncode}: {err}")
            results[m] = (out, err)
    finally:
        for e in emus:
            e.stop()
    for m in methods:
        rows = rows_of(os.path.join(OUT, f"track_{m}.csv"))
        check(len(rows) == DURATION_S * 50, f"{m}: {len(rows)} rows")
        check(float(rows[-1]["time_s"]) >= DURATION_S - 0.02 - 1e-6, f"{m}: ends at {rows[-1]['time_s']} s")
        check(all(r["state"] == "1" for r in rows), f"{m}: the drive was not on throughout")
        check(all(r["motional_phase_a_deg"] != "" for r in rows), f"{m}: electrical port missing")
    report = subprocess.run([SWUM, "track-report", "--band", os.path.join(OUT, "band.csv"), "--amplitude-v", str(V),
                             "--skip-s", "30", "--block-s", "30", "--plot-dir", OUT, "--json",
                             *[a for m in methods for a in ("--run", f"{m}={os.path.join(OUT, f'track_{m}.csv')}")]],
                            capture_output=True, text=True, timeout=120)
    check(report.returncode == 0, f"swum track-report: {report.stderr}")
    summary = {r["run"]: r for r in json.loads(report.stdout)}
    for m in methods:
        s = summary[m]
        print(f"{m:6s}: min share {s['min_share']:.3f}, final share {s['final_share']:.3f}, final "
              f"{s['final_frequency_hz']:.0f} Hz ({s['final_margin_hz']:+.0f} Hz from the peak), rise "
              f"{s['final_rise_k']:.1f} K (max {s['max_rise_k']:.1f} K)")
    # The drift is real: the motor heats by tens of kelvin and the trackers move down with it.
    check(summary["phase"]["max_rise_k"] > 40.0, "the stator did not heat")
    cold = float(rows_of(os.path.join(OUT, "track_fixed.csv"))[-1]["frequency_hz"])
    for m in ("phase", "speed"):
        check(cold - summary[m]["final_frequency_hz"] > 300.0,
              f"{m}: ended {cold - summary[m]['final_frequency_hz']:.0f} Hz below the cold pick: no drift followed")
        check(summary[m]["min_share"] >= 0.90, f"{m}: a block at {summary[m]['min_share']:.3f} of the best speed")
        # The comparison is at the same margin only if the tracker holds it (not closer to the fold).
        check(50.0 <= summary[m]["final_margin_hz"] <= 150.0,
              f"{m}: ends {summary[m]['final_margin_hz']:.0f} Hz above the band's peak, asked {MARGIN_HZ}")
    check(summary["fixed"]["final_share"] < 0.90,
          f"the cold pick held fixed keeps {summary['fixed']['final_share']:.3f}: the comparison shows nothing")
    for name in ("tracking_share.png", "tracking_frequency.png", "tracking_speed.png", "tracking_temperature.png"):
        with open(os.path.join(OUT, name), "rb") as f:
            check(f.read(8) == b"\x89PNG\r\n\x1a\n", f"{name} is not a PNG")
    print(f"outputs in {OUT}")


def interrupt():
    out = os.path.join(OUT, "interrupted.csv")
    with emulator() as emu:
        p = subprocess.Popen(track_command(emu, "phase", out, 600), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
        # Readiness: the tracker's "phase set-point" line on stderr (the lock after ~3 s of emulated time).
        seen = []
        for line in p.stderr:
            seen.append(line)
            if "phase set-point" in line:
                break
        check(p.poll() is None, f"swum track ended early: {''.join(seen)}")
        p.send_signal(signal.SIGINT)
        _, rest = p.communicate(timeout=60)
        err = "".join(seen) + rest
        check(p.returncode == 130, f"exit {p.returncode} after SIGINT: {err}")
        check("interrupted" in err and "drive off" in err, f"no one-line message: {err!r}")
        check(os.path.exists(out) and not os.path.exists(out + ".partial"), "the log was not completed")
        logged = rows_of(out)
        check(len(logged) >= 100 and len(logged) < 600 * 50, f"{len(logged)} rows")
        check([int(r["cycle"]) for r in logged] == list(range(len(logged))), "rows missing or out of order")
        from pymodbus.client import ModbusTcpClient
        c = ModbusTcpClient(emu.host, port=emu.port, timeout=5)
        check(c.connect(), "pymodbus connect")
        state, amplitude = c.read_input_registers(1, 1, slave=1).registers[0], \
            c.read_input_registers(16, 1, slave=1).registers[0]
        c.close()
        check(state == 0 and amplitude == 0, f"drive not off after SIGINT: state {state}, amplitude {amplitude}")
        emu.stop()
    print(f"SIGINT after {len(logged)} cycles: exit 130, drive off, {len(logged)} rows in order")


if __name__ == "__main__":
    {"ten_minutes": ten_minutes, "interrupt": interrupt}[sys.argv[1]]()
