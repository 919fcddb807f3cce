"""The bench against the real swum-emu (Modbus TCP on 127.0.0.1): its edges, each once a defect.
Needs SWUM_EMU and SWUM_BINARY (ctest sets them; tools/bench too)."""
import os
import sys

import pytest

from swum_bench import BenchUsageError, Command, ExternalController

HERE = os.path.dirname(os.path.abspath(__file__))
pytestmark = pytest.mark.skipif(not os.environ.get("SWUM_EMU"), reason="needs SWUM_EMU (run through ctest or tools/bench)")


class Constant:
    def __init__(self, **fields):
        self.command = Command(action="enable", **fields)

    def cycle(self, sample):
        return self.command


def test_start_failure_names_swum_emus_reason_and_keeps_the_log(swum_bench):
    bench = swum_bench()
    bench.inject("load_step", at_s=0.1, load_n=40.0)
    with pytest.raises(BenchUsageError, match=r"swum-emu exited with status 1 before it was ready: .*load_n 40(\.0)? out of "
                                              r"range \[-30, 30\] \(log .*swum-emu.log\)"):
        bench.step(0.01)
    assert os.path.isfile(bench.emulator_log)
    with pytest.raises(BenchUsageError, match="this bench failed to start"):
        bench.step(0.01)


def test_bad_data_directory_is_a_usage_error_before_any_process(swum_bench, tmp_path):
    bench = swum_bench()
    bench.data_dir = str(tmp_path)
    with pytest.raises(BenchUsageError, match=r"^modbus_registers.json not found in the data directory .* \(--swum-data"):
        bench.step(0.01)
    assert bench.emulator is None


def test_no_idle_deadline_on_the_benchs_connections(swum_bench):
    bench = swum_bench()
    bench.step(0.001)
    with open(bench.emulator_log) as f:
        assert "--modbus-idle-timeout-ms 0" in f.readline()


def test_controller_that_dies_before_connecting(swum_bench):
    bench = swum_bench(ExternalController(["/bin/false", "{modbus}"]))
    assert bench.step(0.01) == pytest.approx(0.01)
    assert bench.controller_exit == (0.0, 1)
    assert len(bench.signal("speed_mm_s")) == 11  # t = 0 and ten bare cycles


def test_controller_children_are_stopped_with_it(swum_bench):
    bench = swum_bench(ExternalController(["/bin/sh", "-c", "sleep 300 & echo $! > {artifacts}/child.pid; wait",
                                           "{modbus}"]))
    bench.start()
    pid_file = os.path.join(bench.artifacts, "child.pid")
    bench.emulator._ready.wait(1)
    while not (os.path.exists(pid_file) and open(pid_file).read().strip()):
        pass  # the shell writes it at once; the bench never steps this controller
    child = int(open(pid_file).read())
    bench.close()
    try:  # gone, or a zombie waiting for init to reap it (killed either way)
        with open(f"/proc/{child}/stat") as f:
            assert f.read().split(")")[-1].split()[0] == "Z"
    except FileNotFoundError:
        pass


def test_refused_step_of_an_external_controller_is_recorded_not_fatal(swum_bench):
    bench = swum_bench(ExternalController([sys.executable, os.path.join(HERE, "tiny_controller.py"), "{modbus}", "10",
                                           "50"]))
    bench.step(0.005)
    assert len(bench.refusals) == 1 and "exception 3" in bench.refusals[0][1]
    assert bench.signal("command_frequency_hz").at(0.005) == 40000.0


def test_external_controller_with_its_own_cycle_steps_by_time(swum_bench):
    bench = swum_bench(swum_bench.reference_controller(300, frequency_hz=40000, cycle_ms=2))
    assert bench.step(0.1) == pytest.approx(0.1)
    assert len(bench.signal("speed_mm_s")) == 51  # t = 0 and fifty 2 ms cycles


def test_reference_controller_finishes_its_file_when_closed(swum_bench):
    bench = swum_bench(swum_bench.reference_controller(300, frequency_hz=40000))
    bench.step(0.02)
    bench.close()
    out = os.path.join(bench.artifacts, "swum_control.csv")
    assert os.path.isfile(out), os.listdir(bench.artifacts)
    with open(os.path.join(bench.artifacts, "controller.log")) as f:
        assert "interrupted: drive off" in f.read()  # SIGTERM: its documented stop, file complete


def test_refused_command_of_a_python_controller_fails_the_test_with_its_time(swum_bench):
    bench = swum_bench(Constant(frequency_hz=20000.0, amplitude_v=100.0))
    with pytest.raises(AssertionError, match=r"controller at t = 0\.000000 s: swum-emu refused the command .*"
                                             r"exception 03, reject reason 1 frequency_out_of_range"):
        bench.step(0.01)


def test_nan_command_fails_the_test(swum_bench):
    bench = swum_bench(Constant(amplitude_v=float("nan")))
    with pytest.raises(AssertionError, match=r"controller at t = 0\.000000 s: amplitude_setpoint: nan is not a finite"):
        bench.step(0.01)


def test_non_numeric_command_is_a_usage_error(swum_bench):
    bench = swum_bench()
    with pytest.raises(BenchUsageError, match=r"Command.amplitude_v must be a number, not '100'"):
        bench.command("enable", amplitude_v="100")


def test_fault_already_latched_is_not_caused_by_the_injection(swum_bench):
    from swum_bench import WaveformAssertionError, assert_fault_within
    bench = swum_bench()
    bench.inject("over_temperature", at_s=0.0)
    bench.command("enable", amplitude_v=100)
    bench.step(0.02)
    with pytest.raises(WaveformAssertionError, match="was already present at t = "):
        assert_fault_within(bench.signal("fault_code"), 4, injected_at_s=0.01, within_s=0.005)


def test_controller_whose_every_step_is_refused_fails_instead_of_hanging(swum_bench):
    bench = swum_bench(ExternalController([sys.executable, os.path.join(HERE, "tiny_controller.py"), "{modbus}", "10",
                                           "1000", "1000"]))
    with pytest.raises(AssertionError, match=r"100 steps in a row refused by swum-emu, none run"):
        bench.step(0.01)
    assert bench.time_s == 0.0


def test_start_refusal_by_the_option_parser_names_the_option(swum_bench):
    bench = swum_bench(emu_args=["--bogus"])
    with pytest.raises(BenchUsageError, match=r"before it was ready: .*--bogus"):
        bench.step(0.001)


def test_steps_add_up_from_what_was_asked_with_a_longer_controller_cycle(swum_bench):
    bench = swum_bench(swum_bench.reference_controller(300, frequency_hz=40000, cycle_ms=2))
    assert [bench.step(0.001) for _ in range(4)] == pytest.approx([0.002, 0.002, 0.004, 0.004])


@pytest.mark.parametrize("kind", ["modbus_drop", "telemetry_silence", "can_bus_off"])
def test_events_on_the_benchs_own_link_are_refused(swum_bench, kind):
    with pytest.raises(BenchUsageError, match=rf"inject {kind}: it acts on the link the bench steps"):
        swum_bench().inject(kind, at_s=0.1)
