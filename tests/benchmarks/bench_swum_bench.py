"""Wall time per 1 ms control cycle of the test bench's three paths (docs/performance.md, "The
controller test bench"): printed, never asserted. Run: tools/bench tests/benchmarks/bench_swum_bench.py -q -s"""
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench", "examples"))
from speed_pi import SpeedPI  # noqa: E402

EMULATED_S = 1.0


def run(bench, label):
    bench.step(0.01)  # the emulator's start-up stays out of the measurement
    start = time.perf_counter()
    bench.step(EMULATED_S)
    wall = time.perf_counter() - start
    cycles = round(EMULATED_S / bench.cycle_s)
    print(f"\n{label}: {wall / cycles * 1e3:.3f} ms per 1 ms cycle, {EMULATED_S / wall:.2f}x real time")


def test_python_controller(swum_bench):
    run(swum_bench(SpeedPI(300)), "Python controller (FC16 + FC04 per cycle)")


def test_reference_controller_through_the_gate(swum_bench):
    run(swum_bench(swum_bench.reference_controller(300, frequency_hz=40000)), "swum control through the gate")


def test_no_controller(swum_bench):
    bench = swum_bench()
    bench.command("enable", amplitude_v=200, frequency_hz=40000)
    run(bench, "no controller (the bench's own commands)")
