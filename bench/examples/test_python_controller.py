"""A controller written in Python (speed_pi.py) in the loop: the bench calls its cycle() once
per control cycle with the telemetry and sends what it returns. The same tests run over Modbus
TCP (default) and over CAN in the vcan guest tier (--swum-transport can, lockstep by SYNC: one
more cycle of delay, as on a CANopen drive)."""
from speed_pi import SpeedPI

from swum_bench import assert_fault_within, assert_follows, assert_reaches, assert_settles, assert_within


def ramp_300_in_200ms(time_s):
    return 300.0 * min(time_s / 0.2, 1.0)


def test_follows_a_speed_ramp(swum_bench):
    bench = swum_bench(SpeedPI(300, target=ramp_300_in_200ms))
    bench.step(0.4)
    speed = bench.signal("speed_mm_s")
    # After the start-up transient, a PI lags a ramp by a constant error; 20 mm/s covers it.
    assert_follows(speed, ramp_300_in_200ms, band=20, start_s=0.1)
    assert_settles(speed, 300, band=3, within_s=0.1, start_s=0.2)


def test_holds_speed_through_load_step(swum_bench):
    bench = swum_bench(SpeedPI(300))
    step = bench.inject("load_step", at_s=0.3, load_n=2.0)
    bench.step(0.6)
    speed = bench.signal("speed_mm_s")
    assert_within(speed, 300 - 25 * 2.0, 315, start_s=step.at_s)
    assert_settles(speed, 300, band=6, within_s=0.1, start_s=step.at_s)


def test_drive_off_on_over_temperature_then_recovers(swum_bench):
    bench = swum_bench(SpeedPI(300))
    hot = bench.inject("over_temperature", at_s=0.3)
    bench.inject("clear", at_s=0.305, fault="over_temperature")
    bench.step(0.3)
    bench.run_until(lambda s: s["state"] == 2, timeout_s=0.01)
    back = bench.run_until(lambda s: s["state"] == 1, timeout_s=0.05)
    bench.step(0.2)
    # The drive trips at once; the controller commands 0 V within two cycles (one to see the
    # fault, one to send; on CAN one more), resets after its hold-off and takes the speed back.
    assert_fault_within(bench.signal("fault_code"), 4, injected_at_s=hot.at_s, within_s=0.001)
    assert_reaches(bench.signal("command_amplitude_v"), 0, before_s=hot.at_s + 0.003, start_s=hot.at_s, direction="below")
    assert_settles(bench.signal("speed_mm_s"), 300, band=6, within_s=0.1, start_s=back)
