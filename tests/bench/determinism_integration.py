#!/usr/bin/python3
"""Two runs of the example suite give identical captured signals (lockstep): runs
bench/examples twice with the bench's plugin (as tools/bench does), in parallel emulator
processes (pytest-xdist, -n 2), the second with one CPU hog per core (busy loops started and
stopped by pid), and compares every test's capture.csv byte for byte. Over CAN
(--swum-transport can) the tests run one at a time.

Both runs are pytest sessions in this one process, so the second does not import pytest, numpy,
matplotlib, python-can and canmatrix again under the hogs (in the TCG guest that took longer
than its tests). Each test still starts its own swum-emu and controller processes, which is
what captures the signals.

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


def bench_environment():
    """What tools/bench sets up: the binaries of the ci build unless told, the package on the
    path (also for pytest-xdist's workers), no bytecode written into the tree."""
    os.environ.setdefault("SWUM_SOURCE_DIR", REPO)
    os.environ.setdefault("SWUM_EMU", os.path.join(REPO, "build", "ci", "firmware_sim", "swum-emu"))
    os.environ.setdefault("SWUM_BINARY", os.path.join(REPO, "build", "ci", "host", "swum"))
    check(os.access(os.environ["SWUM_EMU"], os.X_OK), f"swum-emu not found at {os.environ['SWUM_EMU']}")
    package = os.path.join(REPO, "bench")
    os.environ["PYTHONPATH"] = package + (":" + os.environ["PYTHONPATH"] if os.environ.get("PYTHONPATH") else "")
    os.environ["PYTHONDONTWRITEBYTECODE"] = "1"
    sys.dont_write_bytecode = True
    sys.path.insert(0, package)


def run_suite(folder):
    import pytest
    # In parallel emulator processes over Modbus; one at a time over CAN (a SYNC steps every node).
    parallel = [] if "can" in sys.argv[1:] else ["-n", "2"]
    status = pytest.main([os.path.join(REPO, "bench", "examples"), "-q", "-p", "swum_bench.plugin",
                          "-p", "no:cacheprovider", *parallel, "--swum-artifacts", folder, *sys.argv[1:]])
    sys.stdout.flush()
    check(status == 0, f"the example suite failed (exit {int(status)}); its report is above")
    captures = {}
    for test in sorted(os.listdir(folder)):
        path = os.path.join(folder, test, "capture.csv")
        if os.path.isfile(path):
            captures[test] = path
    return captures


def main():
    bench_environment()
    out = tempfile.mkdtemp(prefix="swum-bench-determinism-")
    quiet = run_suite(os.path.join(out, "quiet"))
    # At least the captures the selection asks for (over CAN in the guest tier: a Python controller
    # and an external one through the CAN gate, tests/bench/CMakeLists.txt), so that an empty
    # selection cannot pass.
    floor = 2 if "can" in sys.argv[1:] else 4
    check(len(quiet) >= floor, f"only {len(quiet)} captures: {sorted(quiet)}")
    # Each hog dies with this process (PR_SET_PDEATHSIG), also when a time limit kills it.
    hog = "import ctypes, signal; ctypes.CDLL(None).prctl(1, signal.SIGKILL)\nwhile True: pass"
    hogs = [subprocess.Popen([sys.executable, "-c", hog]) for _ in range(os.cpu_count() or 2)]
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
