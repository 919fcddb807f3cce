"""Controllers with a defect, and the tests that catch them: what a failing controller test
reads like (the assertion, the first violating time and the values, a plot attached). These
tests FAIL on purpose; tests/bench/broken_examples_integration.py runs them and checks the
messages. Run: tools/bench bench/broken_examples --junitxml report.xml"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
from speed_pi import SpeedPI  # noqa: E402

from swum_bench import assert_reaches, assert_settles  # noqa: E402


class NoFaultReaction(SpeedPI):
    """Forgets the fault: keeps commanding the PI's amplitude as if nothing had happened."""

    def react_to_fault(self, sample):
        return super().cycle({**sample, "state": 1})


def test_flipped_gain_reaches_target(swum_bench):
    bench = swum_bench(SpeedPI(300, kp=-0.5, ki=-50.0))  # sign error: more error, less drive
    bench.step(0.2)
    assert_settles(bench.signal("speed_mm_s"), 300, band=6, within_s=0.1)


def test_missing_fault_reaction_drives_off(swum_bench):
    bench = swum_bench(NoFaultReaction(300))
    hot = bench.inject("over_temperature", at_s=0.1)
    bench.step(0.15)
    assert_reaches(bench.signal("command_amplitude_v"), 0, before_s=hot.at_s + 0.003, start_s=hot.at_s, direction="below")
