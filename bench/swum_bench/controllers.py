"""Controllers the bench can put in the loop.

- A Python controller: any object with `cycle(sample) -> Command`; the bench calls it once per
  control cycle with the telemetry of the previous one and sends what it returns.
- An external process (ExternalController): it talks Modbus TCP to the endpoint the bench gives
  it ("{modbus}" in its command line) and steps the emulator itself in lockstep; the bench's
  gate lets its cycles through one by one (modbus_gate.py).
- ReferenceController: `swum control`, the project's reference speed controller, as an external
  process."""
from dataclasses import dataclass

from .signals import BenchUsageError


@dataclass
class Command:
    """One cycle's command: action keep_alive | enable | disable | reset_fault, and the set-points
    (Modbus holding registers 0-9 / CAN Command + AuxCommand / CANopen RPDOs). velocity_mm_s, over
    CANopen only: the drive's profile velocity mode (3) with this target, the drive closing the
    speed loop itself; None (the default) is the open-loop mode -1 with the set-points."""
    action: str = "keep_alive"
    frequency_hz: float = 40000.0
    amplitude_v: float = 0.0
    phase_deg: float = 90.0
    frequency_slew_hz_s: float = 1e6
    amplitude_slew_v_per_s: float = 1e5
    velocity_mm_s: float = None


ACTIONS = {"keep_alive": 0, "enable": 1, "disable": 2, "reset_fault": 3}


def holding_values(command, load_n, advance_ticks):
    """The holding registers 0..10 of a command ({register name: physical value})."""
    if not isinstance(command, Command):
        raise BenchUsageError(f"a controller's cycle() must return a swum_bench.Command, not {command!r}")
    if command.action not in ACTIONS:
        raise BenchUsageError(f"Command.action must be one of {sorted(ACTIONS)}, not {command.action!r}")
    for field in ("frequency_hz", "amplitude_v", "phase_deg", "frequency_slew_hz_s", "amplitude_slew_v_per_s"):
        value = getattr(command, field)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise BenchUsageError(f"Command.{field} must be a number, not {value!r}")
    velocity = command.velocity_mm_s
    if velocity is not None and (isinstance(velocity, bool) or not isinstance(velocity, (int, float))):
        raise BenchUsageError(f"Command.velocity_mm_s must be a number or None, not {velocity!r}")
    return {"command": ACTIONS[command.action], "frequency_setpoint": command.frequency_hz,
            "amplitude_setpoint": command.amplitude_v, "phase_setpoint": command.phase_deg, "load_force": load_n,
            "frequency_slew": command.frequency_slew_hz_s, "amplitude_slew": command.amplitude_slew_v_per_s,
            "advance": advance_ticks}


class ExternalController:
    """A controller process. argv: its command line, with "{modbus}" (tcp://127.0.0.1:PORT) or
    "{can}" (IFACE:NODE, the controller's bus) where the bench's endpoint goes, and optionally
    "{artifacts}" (the test's artifact folder). It must step the emulator in lockstep (write
    `advance` / send SYNC) and wait for replies without a short timeout: the bench holds a cycle
    while the test is not stepping."""

    def __init__(self, argv, name=None):
        self.argv = [str(a) for a in argv or []]
        if not any("{modbus}" in a or "{can}" in a for a in self.argv):
            raise BenchUsageError("ExternalController: the command line must contain '{modbus}' or '{can}' "
                                  "(where the bench's endpoint goes)")
        self.name = name or self.argv[0].rsplit("/", 1)[-1]

    def check_transport(self, transport):
        if not any("{" + transport + "}" in a for a in self.argv):
            raise BenchUsageError(f"{self.name}: its command line has no '{{{transport}}}', and the bench runs "
                                  f"over {transport}")

    def command_line(self, transport, endpoint, artifacts):
        """argv with the transport's placeholder -> the endpoint, "{artifacts}" -> the folder."""
        return [a.replace("{" + transport + "}", endpoint).replace("{artifacts}", artifacts) for a in self.argv]


class ReferenceController(ExternalController):
    """`swum control`: PI speed control by the drive amplitude at a fixed frequency (docs/host.md),
    over whichever transport the bench runs. Keyword arguments become its options
    (frequency_hz=40000 -> --frequency-hz 40000)."""

    def __init__(self, swum_binary, speed_mm_s, duration_s=1000.0, cycle_ms=1, out="{artifacts}/swum_control.csv",
                 **options):
        argv = [swum_binary, "control", "{device}", "--speed-mm-s", repr(float(speed_mm_s)),
                "--duration-s", repr(float(duration_s)), "--cycle-ms", str(cycle_ms),
                # The gate holds a cycle while the test is not stepping: no response timeout.
                "--connect-timeout-ms", "600000", "--timeout-ms", "600000", "--out", out]
        for key, value in options.items():
            argv += ["--" + key.replace("_", "-"), str(value)]
        self.argv = argv
        self.name = "swum control"

    def check_transport(self, transport):
        pass  # swum control speaks both

    def command_line(self, transport, endpoint, artifacts):
        argv = []
        for a in self.argv:
            argv += [f"--{transport}", endpoint] if a == "{device}" else [a.replace("{artifacts}", artifacts)]
        return argv
