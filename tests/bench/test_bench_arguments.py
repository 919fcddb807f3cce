"""Unit tests of swum_bench.Bench's argument checks that need no emulator, of Injection.option()
(the --inject text swum-emu gets) and of controllers.holding_values.

Covers: Bench(...) transport, tick_hz and cycle_s (a whole number of ticks, 1..65535); inject()
with a bad at_s, a value that is not a bare word, NaN, a bool, and the option text it builds;
scenario() with a missing file; use() with an object that is no controller; command() without
an emulator; step() with a negative / non-finite / bool duration and run_until() with a
non-callable condition or a bad timeout (both refused before any emulator would start);
signal() before a capture; holding_values() with a non-Command or an unknown action.
The emulator binary given is a path that does not exist: none of these calls starts it.
"""
import math
import os

import pytest

from swum_bench import Bench, BenchUsageError, Command, ExternalController, Injection, telemetry
from swum_bench.controllers import ACTIONS, holding_values

NO_EMULATOR = "/nonexistent/swum-emu"
SOURCE = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", "..", "config"))  # the data directory


@pytest.fixture
def make_bench(tmp_path):
    made = []

    def make(**kwargs):
        bench = Bench(NO_EMULATOR, SOURCE, str(tmp_path / f"artifacts{len(made)}"), **kwargs)
        made.append(bench)
        return bench

    yield make
    for bench in made:
        bench.close()
        assert bench.emulator is None  # nothing here ever starts swum-emu


@pytest.fixture
def bench(make_bench):
    return make_bench()


# ---- Bench(...) -------------------------------------------------------------------------------

def test_defaults(bench, tmp_path):
    assert bench.transport == "modbus"
    assert bench.cycle_ticks == 10
    assert bench.config == os.path.join(SOURCE, "li2019.toml")
    assert os.path.isdir(tmp_path / "artifacts0")
    assert bench.time_s == 0.0
    assert bench.injections == []


@pytest.mark.parametrize("transport", ["udp", "Modbus", "", None])
def test_bad_transport(tmp_path, transport):
    with pytest.raises(BenchUsageError, match=r"transport must be one of modbus, can, canopen, not "):
        Bench(NO_EMULATOR, SOURCE, str(tmp_path), transport=transport)


def test_can_transport_accepted(make_bench):
    assert make_bench(transport="can").transport == "can"


def test_canopen_transport_and_its_signals(make_bench):
    assert make_bench(transport="canopen").canopen_signals == telemetry.CANOPEN_DEFAULT_SIGNALS
    assert make_bench(transport="canopen", canopen_signals=["temperature_c"]).canopen_signals == ("temperature_c",)


@pytest.mark.parametrize("kwargs, pattern", [
    (dict(transport="canopen", canopen_signals=["load_n", "speed"]),
     r"canopen_signals: 'load_n', 'speed' not in the drive's dictionary \(choose from speed_mm_s, "),
    (dict(transport="can", canopen_signals=["speed_mm_s"]),
     r"canopen_signals: only with transport canopen \(this bench runs over can\)"),
])
def test_canopen_signals_refused(tmp_path, kwargs, pattern):
    with pytest.raises(BenchUsageError, match=pattern):
        Bench(NO_EMULATOR, SOURCE, str(tmp_path), **kwargs)


def test_external_controllers_cannot_run_over_canopen(make_bench):
    bench = make_bench(transport="canopen")
    with pytest.raises(BenchUsageError, match=r"^ctrl: external controllers cannot run over canopen yet: the bench "
                                              r"has no CANopen gate"):
        bench.use(ExternalController(["ctrl", "{can}"]))


@pytest.mark.parametrize("transport", ["modbus", "can"])
def test_velocity_command_only_over_canopen(make_bench, transport):
    bench = make_bench(transport=transport)
    with pytest.raises(BenchUsageError, match=rf"Command.velocity_mm_s: only over canopen .*runs over {transport}$"):
        bench.command("enable", velocity_mm_s=100.0)
    make_bench(transport="canopen").command("enable", velocity_mm_s=100.0)


def test_velocity_must_be_a_number_or_none():
    with pytest.raises(BenchUsageError, match=r"Command.velocity_mm_s must be a number or None, not '1'"):
        holding_values(Command(velocity_mm_s="1"), 0.0, 0)


def test_a_signal_the_transport_does_not_carry(make_bench):
    bench = make_bench(transport="canopen")
    bench.samples = [{"time_s": 0.0, "speed_mm_s": 1.0}]
    with pytest.raises(BenchUsageError, match=r"signal load_n: not captured over canopen \(not in the drive's "
                                              r"dictionary\)"):
        bench.signal("load_n")
    with pytest.raises(BenchUsageError, match=r"signal temperature_c: not captured over canopen \(not mapped "):
        bench.signal("temperature_c")
    assert list(bench.signals()) == ["speed_mm_s"]
    modbus = make_bench()
    modbus.samples = [{"time_s": 0.0, "speed_mm_s": 1.0}]
    with pytest.raises(BenchUsageError, match=r"signal statusword: not captured over modbus \(CANopen only\)"):
        modbus.signal("statusword")


@pytest.mark.parametrize("cycle_s, tick_hz, ticks", [(0.001, 10000, 10), (0.0001, 10000, 1), (0.002, 20000, 40),
                                                     (6.5535, 10000, 65535), (1, 1000, 1000)])
def test_cycle_whole_ticks(make_bench, cycle_s, tick_hz, ticks):
    assert make_bench(cycle_s=cycle_s, tick_hz=tick_hz).cycle_ticks == ticks


@pytest.mark.parametrize("cycle_s, tick_hz", [(0.00015, 10000), (0.00005, 10000), (0.0, 10000), (-0.001, 10000),
                                              (6.5536, 10000), (math.nan, 10000), (math.inf, 10000),
                                              ("0.001", 10000), (None, 10000), (0.0015, 1000)])
def test_cycle_not_whole_ticks(tmp_path, cycle_s, tick_hz):
    with pytest.raises(BenchUsageError, match=rf"cycle_s .* must be a whole number of ticks \(1..65535\) at {tick_hz} Hz"):
        Bench(NO_EMULATOR, SOURCE, str(tmp_path), cycle_s=cycle_s, tick_hz=tick_hz)


@pytest.mark.parametrize("tick_hz", [0, -10000, 10000.0, "10000", None])
def test_bad_tick_hz(tmp_path, tick_hz):
    with pytest.raises(BenchUsageError, match=r"tick_hz must be a positive integer"):
        Bench(NO_EMULATOR, SOURCE, str(tmp_path), tick_hz=tick_hz)


@pytest.mark.parametrize("kwargs", [dict(cycle_s=True, tick_hz=1000), dict(cycle_s=1, tick_hz=True)])
def test_bool_cycle_or_tick_rate(tmp_path, kwargs):
    with pytest.raises(BenchUsageError):
        Bench(NO_EMULATOR, SOURCE, str(tmp_path), **kwargs)


def test_bad_arguments_create_no_folder(tmp_path):
    with pytest.raises(BenchUsageError):
        Bench(NO_EMULATOR, SOURCE, str(tmp_path / "never"), transport="udp")
    assert not os.path.exists(tmp_path / "never")


# ---- inject / Injection -----------------------------------------------------------------------

def test_injection_option_formatting(bench):
    assert bench.inject("load_step", 0.3, load_n=2.0).option() == "load_step@0.3:load_n=2.0"
    assert bench.inject("phase_open", 1).option() == "phase_open@1"
    assert bench.inject("over_temperature", 0.25, phase="a", celsius=90).option() == \
        "over_temperature@0.25:phase=a,celsius=90"
    assert bench.inject("load_step", 0.1 + 0.2, load_n=-1e-7).option() == \
        "load_step@0.30000000000000004:load_n=-1e-07"


def test_inject_returns_and_records_the_event(bench):
    event = bench.inject("load_step", 0.3, load_n=2.0)
    assert isinstance(event, Injection)
    assert event.at_s == 0.3 and event.kind == "load_step" and event.keys == {"load_n": 2.0}
    assert bench.injections == [event]
    assert repr(event) == "Injection(load_step@0.3:load_n=2.0)"


def test_injection_direct():
    assert Injection("load_step", 0.5, {}).option() == "load_step@0.5"
    assert Injection("x", 0, {"a": "word", "b": 3}).option() == "x@0:a=word,b=3"


@pytest.mark.parametrize("at_s", [-0.1, -1, math.nan, math.inf, True, False, "0.3", None])
def test_inject_bad_at_s(bench, at_s):
    with pytest.raises(BenchUsageError, match=r"inject load_step: at_s must be a finite number of seconds >= 0, not "):
        bench.inject("load_step", at_s)
    assert bench.injections == []


@pytest.mark.parametrize("value", ["a,b", "a:b", "a@b", "a=b", "a b", "a\tb", "a\nb", ""])
def test_inject_value_not_a_bare_word(bench, value):
    with pytest.raises(BenchUsageError, match=r"inject: value .* must be a bare word \(no ',', ':', '@', '=', space\)"):
        bench.inject("load_step", 0.3, phase=value)
    assert bench.injections == []


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_inject_non_finite_value(bench, value):
    with pytest.raises(BenchUsageError, match=r"inject: .* is not a finite number"):
        bench.inject("load_step", 0.3, load_n=value)


def test_inject_bool_value(bench):
    with pytest.raises(BenchUsageError, match=r"inject: True is not a number or a word"):
        bench.inject("load_step", 0.3, enabled=True)


@pytest.mark.parametrize("kind", ["", None, 3])
def test_inject_bad_kind(bench, kind):
    with pytest.raises(BenchUsageError, match=r"inject: the event type must be a name"):
        bench.inject(kind, 0.3)


@pytest.mark.parametrize("kind", ["load_step@1", "load step", "load_step:x", "a,b"])
def test_inject_kind_not_a_bare_word(bench, kind):
    with pytest.raises(BenchUsageError):
        bench.inject(kind, 0.3)


def test_scenario_missing_file(bench, tmp_path):
    with pytest.raises(BenchUsageError, match=r"scenario: no such file .*missing.toml"):
        bench.scenario(str(tmp_path / "missing.toml"))


def test_scenario_existing_file(bench, tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("")
    bench.scenario(str(path))
    assert bench.scenarios == [str(path)]


# ---- use / command ----------------------------------------------------------------------------

@pytest.mark.parametrize("controller", [object(), 42, "swum control"])
def test_use_refuses_a_non_controller(bench, controller):
    with pytest.raises(BenchUsageError, match=r"use: .* has no cycle\(sample\) method and is not an ExternalController"):
        bench.use(controller)


def test_use_accepts_an_object_with_cycle(bench):
    class Hold:
        def cycle(self, sample):
            return Command()

    controller = Hold()
    bench.use(controller)
    assert bench.controller is controller
    with pytest.raises(BenchUsageError, match=r"command: a controller is in the loop"):
        bench.command("enable")


def test_external_controller_needs_an_endpoint_placeholder():
    with pytest.raises(BenchUsageError, match=r"ExternalController: the command line must contain '\{modbus\}'"):
        ExternalController(["my-controller", "--port", "1502"])


def test_command_without_controller(bench):
    bench.command("enable", amplitude_v=100.0, frequency_hz=40500.0)
    assert bench._command.action == "enable"
    assert bench._command.amplitude_v == 100.0
    bench.command(amplitude_v=50.0)  # keeps the other set-points
    assert bench._command.frequency_hz == 40500.0


def test_command_unknown_action(bench):
    with pytest.raises(BenchUsageError, match=r"Command.action must be one of"):
        bench.command("jump")


def test_command_unknown_setpoint_is_a_usage_error(bench):
    with pytest.raises(BenchUsageError, match=r"^command: "):
        bench.command("enable", volts=3.0)


# ---- step / run_until / signal ------------------------------------------------------------------

@pytest.mark.parametrize("seconds", [-0.001, -1, math.nan, math.inf, True, "0.1", None])
def test_step_bad_seconds(bench, seconds):
    with pytest.raises(BenchUsageError, match=r"step: seconds must be a finite number >= 0, not "):
        bench.step(seconds)
    assert bench.emulator is None


@pytest.mark.parametrize("condition", [42, None, "speed_mm_s > 10", True])
def test_run_until_non_callable(bench, condition):
    with pytest.raises(BenchUsageError, match=r"run_until: condition must be a function of the sample, not "):
        bench.run_until(condition, 1.0)
    assert bench.emulator is None


@pytest.mark.parametrize("timeout_s", [0, -1.0, math.nan, math.inf, True, "1"])
def test_run_until_bad_timeout(bench, timeout_s):
    with pytest.raises(BenchUsageError, match=r"run_until: timeout_s must be a finite number > 0, not "):
        bench.run_until(lambda sample: True, timeout_s)
    assert bench.emulator is None


def test_missing_emulator_binary_is_a_usage_error(bench):
    with pytest.raises(BenchUsageError, match=r"swum-emu binary '/nonexistent/swum-emu' is not an executable file"):
        bench.step(0.001)
    assert bench.emulator is None


def test_signal_before_capture(bench):
    with pytest.raises(BenchUsageError, match=r"signal speed_mm_s: nothing captured yet"):
        bench.signal("speed_mm_s")
    with pytest.raises(BenchUsageError, match=r"signal: unknown signal 'nope' \(known: .*speed_mm_s"):
        bench.signal("nope")


def test_closed_bench_does_not_start(bench):
    bench.close()
    with pytest.raises(BenchUsageError, match=r"start: this bench is closed"):
        bench.step(0.001)


# ---- controllers.holding_values ------------------------------------------------------------------

def test_holding_values_of_a_command():
    values = holding_values(Command(action="enable", amplitude_v=120.0), load_n=-1.5, advance_ticks=10)
    assert values == {"command": 1, "frequency_setpoint": 40000.0, "amplitude_setpoint": 120.0,
                      "phase_setpoint": 90.0, "load_force": -1.5, "frequency_slew": 1e6,
                      "amplitude_slew": 1e5, "advance": 10}


@pytest.mark.parametrize("action, code", sorted(ACTIONS.items()))
def test_holding_values_actions(action, code):
    assert holding_values(Command(action=action), 0.0, 0)["command"] == code


@pytest.mark.parametrize("not_a_command", [None, {"action": "enable"}, "enable", 1])
def test_holding_values_rejects_a_non_command(not_a_command):
    with pytest.raises(BenchUsageError, match=r"a controller's cycle\(\) must return a swum_bench.Command, not "):
        holding_values(not_a_command, 0.0, 0)


@pytest.mark.parametrize("action", ["jump", "Enable", "", None])
def test_holding_values_rejects_an_unknown_action(action):
    with pytest.raises(BenchUsageError, match=r"Command.action must be one of \['disable', 'enable', 'keep_alive', "
                                              r"'reset_fault'\], not "):
        holding_values(Command(action=action), 0.0, 0)
