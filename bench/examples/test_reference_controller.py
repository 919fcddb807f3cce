"""The reference controller (`swum control`, docs/host.md) under test: the bench starts swum-emu
in lockstep, runs `swum control` as a separate process through its gate, injects faults at
exact emulated times and checks the captured waveforms. Run: tools/bench bench/examples."""
import pytest

from swum_bench import (assert_fault_within, assert_overshoot, assert_reaches, assert_rise_time, assert_settles,
                        assert_within)

FREQUENCY_HZ = 40000  # the operating point the controller holds (docs/host.md's tuning)
MAX_AMPLITUDE_V = 500         # swum control's default --max-amplitude-v
# swum control's default gains were tuned over Modbus (the speed read after a cycle acts in the
# next one). Over CAN a drive answers a SYNC with the state sampled at it (CANopen): one more
# cycle of delay, and the same gains overshoot by 5-9 % (found by this suite's CAN variant).
MAX_OVERSHOOT_PERCENT = {"modbus": 2, "can": 12}


@pytest.mark.parametrize("target_mm_s", [100, 200, 300, 400, 500])
def test_reaches_target(swum_bench, target_mm_s):
    bench = swum_bench(swum_bench.reference_controller(target_mm_s, frequency_hz=FREQUENCY_HZ))
    bench.step(0.2)
    speed = bench.signal("speed_mm_s")
    assert_rise_time(speed, target=target_mm_s, max_s=0.04)
    assert_overshoot(speed, target=target_mm_s, max_percent=MAX_OVERSHOOT_PERCENT[bench.transport])
    assert_settles(speed, target=target_mm_s, band=0.02 * target_mm_s, within_s=0.1)


@pytest.mark.parametrize("target_mm_s", [200, 300, 400])
@pytest.mark.parametrize("load_n", [1.0, 2.0, 3.0])
def test_holds_speed_through_load_step(swum_bench, target_mm_s, load_n):
    bench = swum_bench(swum_bench.reference_controller(target_mm_s, frequency_hz=FREQUENCY_HZ))
    step = bench.inject("load_step", at_s=0.3, load_n=load_n)
    bench.step(0.6)
    speed = bench.signal("speed_mm_s")
    assert_settles(speed, target_mm_s, band=0.02 * target_mm_s, within_s=0.1, end_s=step.at_s)
    # The loop's stiffness: at most 25 mm/s of dip per newton of load, and the integral takes
    # it back out without overshooting by more than 5 %.
    assert_within(speed, target_mm_s - 25 * load_n, 1.05 * target_mm_s, start_s=step.at_s)
    assert_settles(speed, target_mm_s, band=0.02 * target_mm_s, within_s=0.1, start_s=step.at_s)


def test_open_phase_pushes_then_recovers(swum_bench):
    bench = swum_bench(swum_bench.reference_controller(300, frequency_hz=FREQUENCY_HZ))
    open_b = bench.inject("phase_open", at_s=0.2, phase="B", duration_s=0.1)
    bench.step(0.5)
    # No fault code for an open phase: the controller sees the speed collapse and pushes the
    # amplitude to its limit, without a fault.
    assert_reaches(bench.signal("command_amplitude_v"), MAX_AMPLITUDE_V, before_s=open_b.at_s + 0.06, start_s=open_b.at_s)
    assert_within(bench.signal("fault_code"), 0, 0)
    back = open_b.at_s + 0.1
    assert_settles(bench.signal("speed_mm_s"), 300, band=6, within_s=0.1, start_s=back)


def test_over_temperature_stops_with_drive_off(swum_bench):
    bench = swum_bench(swum_bench.reference_controller(300, frequency_hz=FREQUENCY_HZ))
    hot = bench.inject("over_temperature", at_s=0.2)
    bench.step(0.4)
    assert_fault_within(bench.signal("fault_code"), 4, injected_at_s=hot.at_s, within_s=0.001)
    # Not recoverable by default: the controller commands 0 V the cycle after it sees the
    # fault, and stops (exit 1); the amplifier stays off while time runs on.
    assert_reaches(bench.signal("command_amplitude_v"), 0, before_s=hot.at_s + 0.002, start_s=hot.at_s, direction="below")
    assert bench.controller_exit is not None and bench.controller_exit[1] == 1, bench.controller_exit
    assert_within(bench.signal("amplitude_v"), 0, 0, start_s=hot.at_s)
    assert_within(bench.signal("drive_on"), 0, 0, start_s=hot.at_s)


def test_recovers_after_fault_reset(swum_bench):
    # --recover 1,4: an over-temperature that has cleared is reset and the drive re-enabled after
    # the hold-off (10 cycles).
    bench = swum_bench(swum_bench.reference_controller(300, frequency_hz=FREQUENCY_HZ, recover="1,4"))
    hot = bench.inject("over_temperature", at_s=0.2)
    bench.inject("clear", at_s=0.205, fault="over_temperature")
    bench.step(0.2)
    bench.run_until(lambda s: s["state"] == 2, timeout_s=0.01)
    enabled_again = bench.run_until(lambda s: s["state"] == 1, timeout_s=0.05)
    bench.step(0.2)
    speed = bench.signal("speed_mm_s")
    assert_fault_within(bench.signal("fault_code"), 4, injected_at_s=hot.at_s, within_s=0.001)
    assert_within(bench.signal("fault_code"), 0, 0, start_s=enabled_again)
    assert_settles(speed, 300, band=6, within_s=0.1, start_s=enabled_again)
