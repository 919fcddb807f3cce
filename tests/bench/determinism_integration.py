#!/usr/bin/python3
"""Two runs of the example suite give identical captured signals (lockstep): runs
bench/examples twice through tools/bench, in parallel emulator processes (pytest-xdist, -n 2),
the second with one CPU hog per core (busy loops started and stopped by pid), and compares
every test's capture.csv byte for byte. Over CAN (--swum-transport can) the tests run one at a
time.

  determinism_integration.py [pytest args, e.g. --swum-transport can -k python]"""
import filecmp
import os
import subprocess
import sys
import tempfile

REPO = os.environ.get("SWUM_SOURCE_DIR") or os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))


def check(condition, message):
    if not condition:
        print("FAIL:", message)
        sys.exit(1)


def run_suite(folder):
    # In parallel emulator processes over Modbus; one at a time over CAN (a SYNC steps every node).
    parallel = [] if "can" in sys.argv[1:] else ["-n", "2"]
    r = subprocess.run([os.path.join(REPO, "tools", "bench"), os.path.join(REPO, "bench", "examples"), "-q", *parallel,
                        "--swum-artifacts", folder, *sys.argv[1:]], capture_output=True, text=True, timeout=1200)
    print(r.stdout[-1500:])
    check(r.returncode == 0, f"the example suite failed (exit {r.returncode}): {r.stdout[-3000:]} {r.stderr[-2000:]}")
    captures = {}
    for test in sorted(os.listdir(folder)):
        path = os.path.join(folder, test, "capture.csv")
        if os.path.isfile(path):
            captures[test] = path
    return captures


def main():
    out = tempfile.mkdtemp(prefix="swum-bench-determinism-")
    quiet = run_suite(os.path.join(out, "quiet"))
    check(len(quiet) >= 4, f"only {len(quiet)} captures: {sorted(quiet)}")
    hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(os.cpu_count() or 2)]
    try:
        loaded = run_suite(os.path.join(out, "loaded"))
    finally:
        for h in hogs:
            h.kill()
            h.wait()
    check(sorted(quiet) == sorted(loaded), f"different tests captured: {sorted(quiet)} vs {sorted(loaded)}")
    different = [t for t in quiet if not filecmp.cmp(quiet[t], loaded[t], shallow=False)]
    check(not different, f"captured signals differ between the runs: {different}")
    rows = sum(sum(1 for _ in open(p)) - 1 for p in quiet.values())
    print(f"PASS: {len(quiet)} captures, {rows} cycles, identical with {len(hogs)} CPU hogs")


if __name__ == "__main__":
    main()
