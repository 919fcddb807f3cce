"""The test bench: swum-emu in lockstep, a controller in the loop, and every control cycle's
telemetry captured as named signals in emulated time (docs/testing-controllers.md).

The emulator starts on the first step (or start()): faults and load events are given before,
with inject() / scenario(), and reach swum-emu as --inject / --scenario, so they happen at an
exact emulated time whatever the machine's load."""
import math
import os
import queue
import re
import signal
import subprocess
import time

from . import telemetry
from .installation import DEFAULT_CONFIG, data_file
from .controllers import Command, ExternalController, holding_values
from .emulator import BenchError, Emulator
from .modbus_gate import ModbusGate
from .modbus_link import CommandRefused, ModbusLink
from .modbus_map import ModbusMap
from .signals import BenchUsageError, Signal, write_csv

# A hang guard only (wall time): how long the bench waits for one cycle of an external
# controller, or for the emulator's answer, before calling the bench broken. Never a measure.
HANG_GUARD_S = 120.0
# Scenario events that act on the bench's own link (docs/scenarios.md): a dropped request or a
# silent bus stalls a lockstep bench instead of testing the controller.
LINK_EVENTS = ("modbus_drop", "telemetry_silence", "can_bus_off")
TRANSPORTS = ("modbus", "can", "canopen")
# An external controller whose steps swum-emu refuses this many times in a row makes no
# progress: the bench stops waiting for it.
MAX_REFUSALS_IN_A_ROW = 100


class Injection:
    def __init__(self, kind, at_s, keys):
        self.kind = kind
        self.at_s = at_s
        self.keys = keys

    def option(self):
        text = f"{self.kind}@{_bare(self.at_s)}"
        if self.keys:
            text += ":" + ",".join(f"{k}={_bare(v)}" for k, v in self.keys.items())
        return text

    def __repr__(self):
        return f"Injection({self.option()})"


def _bare(value):
    if isinstance(value, bool):
        raise BenchUsageError(f"inject: {value!r} is not a number or a word")
    if isinstance(value, (int, float)):
        if not math.isfinite(value):
            raise BenchUsageError(f"inject: {value!r} is not a finite number")
        return repr(value)
    text = str(value)
    if not text or any(c in text for c in ",:@= \t\n"):
        raise BenchUsageError(f"inject: value {text!r} must be a bare word (no ',', ':', '@', '=', space)")
    return text


class Bench:
    def __init__(self, emu_binary, data_dir, artifacts, transport="modbus", config=None, cycle_s=0.001,
                 tick_hz=10000, watchdog_ms=100, emu_args=(), can_interface="vcan0", controller_can_interface="vcan1",
                 node=1, canopen_signals=None):
        if transport not in TRANSPORTS:
            raise BenchUsageError(f"transport must be one of {', '.join(TRANSPORTS)}, not {transport!r}")
        if canopen_signals is not None and transport != "canopen":
            raise BenchUsageError(f"canopen_signals: only with transport canopen (this bench runs over {transport})")
        canopen_signals = tuple(telemetry.CANOPEN_DEFAULT_SIGNALS if canopen_signals is None else canopen_signals)
        unknown = [n for n in canopen_signals if n not in dict(telemetry.CANOPEN_TABLE)]
        if unknown:
            raise BenchUsageError(f"canopen_signals: {', '.join(map(repr, unknown))} not in the drive's dictionary "
                                  f"(choose from {', '.join(n for n, _ in telemetry.CANOPEN_TABLE)})")
        if isinstance(tick_hz, bool) or not isinstance(tick_hz, int) or tick_hz <= 0:
            raise BenchUsageError(f"tick_hz must be a positive integer, not {tick_hz!r}")
        ticks = (cycle_s * tick_hz if not isinstance(cycle_s, bool) and isinstance(cycle_s, (int, float))
                 and math.isfinite(cycle_s) else float("nan"))
        if not (ticks >= 1 and abs(ticks - round(ticks)) < 1e-9 and round(ticks) <= 65535):
            raise BenchUsageError(f"cycle_s {cycle_s!r} must be a whole number of ticks (1..65535) at {tick_hz} Hz")
        self.emu_binary = emu_binary
        self.data_dir = data_dir
        self.artifacts = artifacts
        self.transport = transport
        self.config = config or data_file(data_dir, DEFAULT_CONFIG)
        self.cycle_s = cycle_s
        self.cycle_ticks = int(round(ticks))
        self.tick_hz = tick_hz
        self.watchdog_ms = watchdog_ms
        self.emu_args = list(emu_args)
        self.can_interface = can_interface
        self.controller_can_interface = controller_can_interface
        self.node = node
        self.canopen_signals = canopen_signals
        self._syncs = 0  # SYNCs sent over CANopen: its samples' time
        self.load_n = 0.0
        self.injections = []
        self.scenarios = []
        self.controller = None
        self.emulator = None
        self.samples = []
        self._link = None
        self._gate = None
        self._process = None
        self._process_log = None
        self._last = None
        self._closed = False
        # (emulated time, exit status) once an external controller has stopped, else None
        self.controller_exit = None
        # (emulated time, what) of each step of an external controller that swum-emu refused
        self.refusals = []
        self.emulator_log = None
        self._start_error = None
        self._requested_s = 0.0  # emulated time the steps so far asked for
        os.makedirs(artifacts, exist_ok=True)

    # ---- set-up (before the emulator starts) ------------------------------------------------
    def _not_started(self, what):
        if self.emulator is not None:
            raise BenchUsageError(f"{what}: the emulator is running already (t = {self.time_s:g} s); "
                                  "swum-emu takes faults and scenarios at start-up: call it before the first step")

    def inject(self, kind, at_s, **keys):
        """A scenario event at emulated time at_s (docs/scenarios.md: load_step, phase_open,
        over_temperature, ...). Returns it; its at_s is what assert_fault_within wants."""
        self._not_started("inject")
        if not isinstance(kind, str) or not re.fullmatch(r"[a-z][a-z_]*", kind):
            raise BenchUsageError(f"inject: the event type must be a name such as load_step, not {kind!r}")
        for key in keys:
            if not re.fullmatch(r"[a-z][a-z_]*", key):
                raise BenchUsageError(f"inject {kind}: key {key!r} is not a key name")
        if isinstance(at_s, bool) or not isinstance(at_s, (int, float)) or not math.isfinite(at_s) or at_s < 0:
            raise BenchUsageError(f"inject {kind}: at_s must be a finite number of seconds >= 0, not {at_s!r}")
        if kind in LINK_EVENTS:
            raise BenchUsageError(f"inject {kind}: it acts on the link the bench steps the emulator through, so "
                                  "in lockstep it would stall the bench, not test the controller (use it on a "
                                  "wall-clock swum-emu; docs/testing-controllers.md, Limits)")
        event = Injection(kind, at_s, keys)
        event.option()  # checks the values now, not at start-up
        self.injections.append(event)
        return event

    def scenario(self, path):
        """A scenario file (TOML, docs/scenarios.md) given to swum-emu at start-up."""
        self._not_started("scenario")
        if not os.path.isfile(path):
            raise BenchUsageError(f"scenario: no such file {path}")
        self.scenarios.append(path)

    def use(self, controller):
        """The controller in the loop: a Python object with cycle(sample) -> Command, an
        ExternalController (a process), or None (the test sends commands with command())."""
        self._not_started("use")
        if controller is not None and not isinstance(controller, ExternalController) \
                and not callable(getattr(controller, "cycle", None)):
            raise BenchUsageError(f"use: {controller!r} has no cycle(sample) method and is not an ExternalController")
        if isinstance(controller, ExternalController):
            if self.transport == "canopen":
                raise BenchUsageError(f"{controller.name}: external controllers cannot run over canopen yet: the "
                                      "bench has no CANopen gate (docs/testing-controllers.md, Limits)")
            controller.check_transport(self.transport)
        self.controller = controller
        self._command = Command()

    def command(self, action="keep_alive", **setpoints):
        """Without a controller: what the bench sends from the next cycle on (the action once,
        then keep-alives); setpoints are Command's fields (amplitude_v=, frequency_hz=...)."""
        if self.controller is not None:
            raise BenchUsageError("command: a controller is in the loop; it sends the commands")
        base = getattr(self, "_command", Command())
        try:
            command = Command(**{**base.__dict__, **setpoints, "action": action})
        except TypeError as e:
            raise BenchUsageError(f"command: {e}") from e
        holding_values(command, self.load_n, 0)  # checks the action and the values now
        self._check_velocity(command)
        self._command = command

    def _check_velocity(self, command):
        if command.velocity_mm_s is not None and self.transport != "canopen":
            raise BenchUsageError(f"Command.velocity_mm_s: only over canopen (the drive's profile velocity mode); "
                                  f"this bench runs over {self.transport}")

    # ---- running --------------------------------------------------------------------------
    def start(self):
        """Starts swum-emu (and an external controller); the first step does it by itself."""
        if self._start_error is not None:
            raise BenchUsageError(f"this bench failed to start ({self._start_error}); make a new one")
        if self.emulator is not None:
            return
        if self._closed:
            raise BenchUsageError("start: this bench is closed")
        if not hasattr(self, "_command"):
            self._command = Command()
        map_path = data_file(self.data_dir, "modbus_registers.json")
        try:
            self.map = ModbusMap(map_path)
        except (OSError, ValueError, KeyError) as e:
            raise BenchUsageError(f"the register map {map_path} cannot be read (--swum-data): {e}") from e
        args = ["--config", self.config, "--clock", "external", "--tick-hz", str(self.tick_hz),
                "--watchdog-ms", str(self.watchdog_ms)]
        if self.transport == "modbus":
            # No idle deadline: wall time between two steps (a debugger, a slow plot, a loaded
            # machine) must not close the bench's connection; time here is emulated.
            args += ["--modbus", "tcp://127.0.0.1:0", "--modbus-idle-timeout-ms", "0"]
        else:
            args += ["--modbus", "none", "--can", self.can_interface, "--node", str(self.node),
                     "--sync-ticks", str(self.cycle_ticks)]
            if self.transport == "canopen":
                args += ["--can-profile", "cia402"]
        for path in self.scenarios:
            args += ["--scenario", path]
        for event in self.injections:
            args += ["--inject", event.option()]
        args += self.emu_args
        self.emulator_log = os.path.join(self.artifacts, "swum-emu.log")
        try:
            self.emulator = Emulator(self.emu_binary, args, self.emulator_log)
            self._connect()
        except BaseException as e:
            self._start_error = str(e).splitlines()[0] if str(e) else type(e).__name__
            self.close()
            raise

    def _connect(self):
        external = isinstance(self.controller, ExternalController)
        if self.transport == "modbus":
            host, port = self.emulator.modbus_endpoint()
            self._link = ModbusLink(host, port, self.map, timeout_s=HANG_GUARD_S)
            holding = self._read_holding()
            self._capture(self._link.read_inputs(), holding)
            if external:
                self._gate = ModbusGate((host, port), self._external_cycle)
                self._gate.holding = dict(enumerate(self.map.encode_holding(holding)))
        elif self.transport == "canopen":
            self._open_canopen_link()
            self._capture_canopen(self._link.sync(), self._link.command_registers(Command()))
        elif external:
            # The controller's own first SYNC gives the first sample (the state at t = 0).
            from .can_gate import CanGate
            self._gate = CanGate(self.controller_can_interface, self.can_interface, self.node, self.data_dir,
                                 self._external_can_cycle, timeout_s=HANG_GUARD_S)
        else:
            self._open_can_link()
            self._capture_can(self._link.sync(), self._link.command_registers(holding_values(Command(), 0.0, 0)))
        if external:
            self._start_process()

    def _open_can_link(self):
        from .can_link import CanLink
        self._link = CanLink(self.can_interface, self.node, self.data_dir, timeout_s=HANG_GUARD_S)

    def _open_canopen_link(self):
        from .canopen_link import CanopenLink
        self._link = CanopenLink(self.can_interface, self.node, self.data_dir,
                                 [dict(telemetry.CANOPEN_TABLE)[n] for n in self.canopen_signals],
                                 emu_args=self.emu_args, timeout_s=HANG_GUARD_S)
        self._canopen_scales = telemetry.canopen_scales(self._link.eds, self.canopen_signals)
        self._link.start()

    def _read_holding(self):
        rr = self._link.client.read_holding_registers(0, self.map.holding_count, slave=1)
        if rr.isError():
            raise BenchError(f"Modbus: read of holding registers 0..{self.map.holding_count - 1}: {rr}")
        return self.map.decode_holding(rr.registers)

    def _start_process(self):
        argv = self.controller.command_line(self.transport, self._gate.endpoint, self.artifacts)
        log_path = os.path.join(self.artifacts, "controller.log")
        self._process_log = open(log_path, "w")
        self._process_log.write("$ " + " ".join(argv) + "\n")
        self._process_log.flush()
        try:
            # Its own session: close() stops the controller and whatever it started (by group).
            self._process = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=self._process_log,
                                             stderr=subprocess.STDOUT, start_new_session=True)
        except OSError as e:
            raise BenchUsageError(f"cannot start the controller {argv[0]}: {e.strerror}") from e

    def _external_cycle(self, words):
        holding = self.map.decode_holding([words.get(i, 0) for i in range(self.map.holding_count)])
        self._capture(self._link.read_inputs(), holding)
        self._gate.events.put(("cycle", None))

    def _external_can_cycle(self, values, command):
        self._capture_can(values, command)

    def _capture(self, inputs, holding):
        sample, sim_time = telemetry.from_modbus(inputs, self.tick_hz)
        self._append(sample, sim_time, holding)

    def _capture_can(self, values, holding):
        sample, sim_time = telemetry.from_can(values, self.tick_hz)
        self._append(sample, sim_time, holding)

    def _capture_canopen(self, values, sent):
        # No object holds the emulated time: in lockstep each SYNC is one cycle, and the TPDOs of
        # the n-th (from 0) were sampled at n cycles (before the cycle it starts).
        sample = telemetry.from_canopen(values, self._canopen_scales, self._syncs * self.cycle_ticks / self.tick_hz)
        self._syncs += 1
        self._append(sample, sample["time_s"], sent)

    def _append(self, sample, sim_time, holding):
        if abs(sample["time_s"] - sim_time) > 0.0015:
            raise BenchError(f"the emulator's tick rate is not {self.tick_hz} Hz: tick {sample['tick']:g} "
                             f"at device time {sim_time:g} s")
        telemetry.add_command(sample, holding)
        self.samples.append(sample)
        self._last = sample

    def _one_cycle(self):
        if isinstance(self.controller, ExternalController):
            return self._external_step()
        if self.controller is None:
            command = self._command
            self._command = Command(**{**command.__dict__, "action": "keep_alive"})
        else:
            command = self.controller.cycle(dict(self._last))
        holding = holding_values(command, self.load_n, self.cycle_ticks)
        self._check_velocity(command)
        try:
            if self.transport == "canopen":
                sent = self._link.send_command(command, self._last)
                self._capture_canopen(self._link.sync(), sent)
            elif self.transport == "modbus":
                self.map.encode_holding(holding)  # NaN, or beyond what a register holds
                self._capture(self._link.exchange(holding), holding)
            else:
                before = self._last["reject_count"]
                sent = self._link.send_command(holding, self._last)
                self._capture_can(self._link.sync(), sent)
                if self._last["reject_count"] != before:  # CAN has no reply to refuse with
                    self.refusals.append((self.time_s, f"reject reason {self._last['last_reject']:g} "
                                                       f"{self.map.reasons.get(int(self._last['last_reject']), '?')}"))
        except (ValueError, CommandRefused) as e:  # the controller's fault, at a time
            raise AssertionError(f"controller at t = {self.time_s:.6f} s: {e}") from e

    def _check_emulator(self):
        if self.emulator is not None and not self.emulator.running():
            raise BenchError(f"swum-emu exited with status {self.emulator.process.returncode} at "
                             f"t = {self.time_s:g} s (log {self.emulator.log_path})")

    def _external_step(self):
        if self.controller_exit is not None:
            return self._bare_step()
        self._gate.release()
        deadline = time.monotonic() + HANG_GUARD_S  # a hang guard over every event, not a measure
        refused = 0
        while True:
            try:
                kind, detail = self._gate.events.get(timeout=0.2)
            except queue.Empty:
                self._check_emulator()
                status = self._process.poll()
                if status is not None and self._gate.quiet_after_exit():
                    # Gone: what it sent before exiting has crossed the gate by now.
                    return self._controller_gone(status)
                kind, detail = "waiting", None
            if kind == "cycle":
                return None
            if time.monotonic() > deadline:
                kind, detail = "error", f"no cycle from the controller in {HANG_GUARD_S:g} s of wall time"
            if kind in ("waiting", "closed"):
                continue  # closed: exiting (seen above once the gate is quiet) or reconnecting
            if kind == "refused":  # the emulator refused the controller's step: no cycle ran
                self.refusals.append((self.time_s, detail))
                refused += 1
                if refused >= MAX_REFUSALS_IN_A_ROW:
                    raise AssertionError(f"controller {self.controller.name} at t = {self.time_s:.6f} s: "
                                         f"{refused} steps in a row refused by swum-emu, none run; the last: {detail}")
                self._gate.release()
                continue
            status = self._process.poll()
            exited = f"; it exited with status {status}" if status is not None else ""
            raise BenchError(f"controller {self.controller.name} at t = {self.time_s:g} s: {detail}{exited} "
                             f"(log {self._process_log.name})")

    def _controller_gone(self, status):
        """The controller stopped (its run ended, or it gave up on a fault): time still belongs
        to the bench, which steps on with bare cycles (no command, no watchdog feed), as a motor
        runs on when its controller dies."""
        self.controller_exit = (self.time_s, status)
        self._gate.close()  # nothing may step the emulator beside the bench's bare cycles now
        self._gate = None
        if self.transport == "can":
            self._open_can_link()
        return self._bare_step()

    def _bare_step(self):
        """One cycle with no command: FC06 of `advance` alone, or a SYNC alone on CAN."""
        if self.transport == "can":
            self._capture_can(self._link.sync(), self._last_command_registers())
            return
        try:
            wr = self._link.client.write_register(self.map.holding["advance"].address, self.cycle_ticks, slave=1)
        except Exception as e:
            raise BenchError(f"Modbus: write of advance: {e}") from e
        if wr.isError():
            raise BenchError(f"Modbus: write of advance refused: {wr}")
        self._capture(self._link.read_inputs(), self._last_command_registers())

    def _last_command_registers(self):
        last = self._last
        if last is None:  # the controller left before its first cycle
            return {"command": 0, "frequency_setpoint": 0.0, "amplitude_setpoint": 0.0, "phase_setpoint": 0.0}
        return {"command": last["command"], "frequency_setpoint": last["command_frequency_hz"],
                "amplitude_setpoint": last["command_amplitude_v"], "phase_setpoint": last["command_phase_deg"]}

    def _first_sample(self):
        self.start()
        if self._last is None:  # an external controller over CAN: its first SYNC is the first sample
            self._one_cycle()

    @property
    def time_s(self):
        """Emulated time of the last captured sample (0 before the start)."""
        return self._last["time_s"] if self._last else 0.0

    @property
    def last(self):
        """The last captured sample ({signal name: value})."""
        self._first_sample()
        return dict(self._last)

    def step(self, seconds):
        """Runs control cycles until `seconds` of emulated time have passed: afterwards the last
        sample is at (start + seconds). An external controller's own cycle decides how many
        cycles that takes."""
        if isinstance(seconds, bool) or not isinstance(seconds, (int, float)) or not math.isfinite(seconds) \
                or seconds < 0:
            raise BenchUsageError(f"step: seconds must be a finite number >= 0, not {seconds!r}")
        cycles = int(round(seconds / self.cycle_s))
        if abs(cycles * self.cycle_s - seconds) > 1e-9:
            raise BenchUsageError(f"step: {seconds:g} s is not a whole number of {self.cycle_s:g} s cycles")
        self._first_sample()
        # Targets add up from what was asked, not from where a long external cycle overshot.
        self._requested_s = max(self._requested_s, 0.0) + seconds
        while self.time_s < self._requested_s - 1e-9:
            self._one_cycle()
        return self.time_s

    def run_until(self, condition, timeout_s):
        """Runs cycles until condition(sample) is true for a captured sample; returns its time.
        Not true within timeout_s of emulated time: AssertionError naming the condition."""
        if not callable(condition):
            raise BenchUsageError(f"run_until: condition must be a function of the sample, not {condition!r}")
        if isinstance(timeout_s, bool) or not isinstance(timeout_s, (int, float)) or not math.isfinite(timeout_s) \
                or timeout_s <= 0:
            raise BenchUsageError(f"run_until: timeout_s must be a finite number > 0, not {timeout_s!r}")
        self._first_sample()
        start = self.time_s
        if condition(dict(self._last)):
            return self.time_s
        while self.time_s < start + timeout_s - 1e-9:
            self._one_cycle()
            self._requested_s = self.time_s
            if condition(dict(self._last)):
                return self.time_s
        name = getattr(condition, "__name__", "condition")
        raise AssertionError(f"run_until({name}): not true within {timeout_s:g} s of emulated time "
                             f"(from {start:.6f} s to {self.time_s:.6f} s); last sample: "
                             + ", ".join(f"{k}={self._last[k]:g}" for k in ("speed_mm_s", "state", "fault_code")
                                         if k in self._last))

    def signal(self, name):
        """The captured signal `name` (telemetry.NAMES) as a Signal in emulated time."""
        if name not in telemetry.UNITS:
            raise BenchUsageError(f"signal: unknown signal {name!r} (known: {', '.join(telemetry.NAMES[1:])})")
        if not self.samples:
            raise BenchUsageError(f"signal {name}: nothing captured yet (step the bench first)")
        if name not in self.samples[0]:
            why = ("not in the drive's dictionary" if name in telemetry.CANOPEN_MISSING
                   else "not mapped (Bench canopen_signals=)" if self.transport == "canopen" else "CANopen only")
            raise BenchUsageError(f"signal {name}: not captured over {self.transport} ({why})")
        return Signal(name, telemetry.UNITS[name], [s["time_s"] for s in self.samples],
                      [s[name] for s in self.samples])

    def signals(self):
        """Every signal the transport captured."""
        return {name: self.signal(name) for name in telemetry.NAMES[1:] if self.samples and name in self.samples[0]}

    def save_capture(self, path=None):
        """Every captured sample as CSV (default: capture.csv in the artifact folder), one column
        per signal with its unit, numbers in repr() so equal captures give equal bytes."""
        path = path or os.path.join(self.artifacts, "capture.csv")
        write_csv(path, self.samples, telemetry.UNITS)
        return path

    def close(self):
        """Stops the controller and the emulator (by their pids) and closes the links; every
        step runs even if an earlier one fails, and the first error is raised at the end."""
        if self._closed:
            return
        self._closed = True
        errors = []

        def attempt(action):
            try:
                action()
            except Exception as e:  # keep closing the rest
                errors.append(e)

        if self._gate is not None:  # the controller's last cycles (its drive-off) pass unheld
            attempt(self._gate.open)
        if self._process is not None:
            attempt(self._stop_process)
        if self._gate is not None:
            attempt(self._gate.close)
        if self._link is not None:
            attempt(self._link.close)
        if self.emulator is not None:
            attempt(self.emulator.stop)
        if self._process_log is not None:
            attempt(self._process_log.close)
        if errors:
            raise errors[0]

    def _stop_process(self):
        """SIGTERM to the controller's process group, SIGKILL after 10 s."""
        if self._process.poll() is None:
            try:
                os.killpg(self._process.pid, signal.SIGTERM)
                self._process.wait(10)
            except subprocess.TimeoutExpired:
                os.killpg(self._process.pid, signal.SIGKILL)
                self._process.wait()
        try:  # what it started and left behind
            os.killpg(self._process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
