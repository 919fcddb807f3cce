#!/usr/bin/python3
"""`swum control` against a running swum-emu in lockstep (--clock external): the real binaries,
independent processes, Modbus TCP on 127.0.0.1.

  control_integration.py lockstep | errors

lockstep: the controller reaches the target and settles (every sample of the last 0.2 s within
2 % of it), and the --out file is byte-identical across two runs and a third one while CPU hogs
(one busy loop per CPU, started and stopped by pid) compete for the machine: in lockstep the
emulated time is what the controller asks for, never the wall clock.
errors: a wall-time emulator runs the same law (not stepped); a wrong --tick-hz is refused.
"""
import csv
import os
import signal
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../firmware_sim"))
from emu_harness import Emulator  # noqa: E402

SWUM = os.environ["SWUM_BINARY"]
OUT = tempfile.mkdtemp(prefix="swum-control-")
TARGET_MM_S = 300.0
DURATION_S = 0.5
SETTLE_WINDOW_S = 0.2
SETTLE_BAND = 0.02


def check(condition, message):
    if not condition:
        raise AssertionError(message)


def swum(*args, timeout=300):
    r = subprocess.run([SWUM, *args], capture_output=True, text=True, timeout=timeout)
    return r.returncode, r.stdout, r.stderr


def control(emu, out, *extra, duration_s=DURATION_S):
    return swum("control", "--modbus", f"tcp://{emu.host}:{emu.port}", "--speed-mm-s", str(TARGET_MM_S),
                "--duration-s", str(duration_s), "--cycle-ms", "1", "--out", out, *extra)


def lockstep_run(name):
    """One run against a fresh lockstep emulator: the bytes of --out."""
    out = os.path.join(OUT, name + ".csv")
    with Emulator("--clock", "external", "--duration-s", "5") as emu:
        status, stdout, stderr = control(emu, out)
        emu.stop()
    check(status == 0, f"{name}: swum control exited {status}: {stderr}")
    check("lockstep" in stdout and "0 faults" in stdout, f"{name}: summary {stdout!r}")
    with open(out, "rb") as f:
        return f.read()


def rows(data):
    return list(csv.DictReader(data.decode().splitlines()))


def check_settles(data):
    r = rows(data)
    check(len(r) == round(DURATION_S / 0.001), f"{len(r)} rows")
    check(all(row["state"] == "1" and row["fault_code"] == "0" for row in r[1:]), "the drive left 'enabled'")
    end = float(r[-1]["time_s"])
    window = [float(row["speed_mm_s"]) for row in r if float(row["time_s"]) > end - SETTLE_WINDOW_S]
    worst = max(abs(s - TARGET_MM_S) for s in window)
    check(worst <= SETTLE_BAND * TARGET_MM_S, f"not settled: worst error {worst:.3f} mm/s in the last 0.2 s")
    rise = next(float(row["time_s"]) for row in r if float(row["speed_mm_s"]) >= 0.9 * TARGET_MM_S)
    print(f"rise to 90 % at {rise:.3f} s; worst error over the last {SETTLE_WINDOW_S} s {worst:.3f} mm/s")


def scenario_lockstep():
    first = lockstep_run("first")
    check_settles(first)
    second = lockstep_run("second")
    check(first == second, "two lockstep runs gave different files")
    hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(os.cpu_count() or 2)]
    try:
        third = lockstep_run("under_load")
    finally:
        for h in hogs:
            os.kill(h.pid, signal.SIGKILL)
            h.wait()
    check(first == third, "the run under CPU load gave a different file")
    print(f"3 runs byte-identical ({len(first)} bytes)")


def scenario_errors():
    out = os.path.join(OUT, "wall.csv")
    with Emulator("--duration-s", "30") as emu:
        status, stdout, stderr = control(emu, out, duration_s=0.2)
        emu.stop()
    check(status == 0, f"wall-time run exited {status}: {stderr}")
    check("wall time" in stdout and "not reproducible" in stderr, f"wall-time run not reported: {stdout!r} {stderr!r}")
    with Emulator("--clock", "external", "--duration-s", "5") as emu:
        status, _, stderr = control(emu, out, "--tick-hz", "20000")
        emu.stop()
    check(status == 1 and "--tick-hz 20000.000000 does not match the device" in stderr, f"{status} {stderr!r}")
    check(os.path.exists(out + ".partial"), "the rows before the error are kept")


if __name__ == "__main__":
    {"lockstep": scenario_lockstep, "errors": scenario_errors}[sys.argv[1]]()
    print("ok")
