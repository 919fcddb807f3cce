#!/usr/bin/env python3
"""swum-emu --clock external over Modbus TCP, driven by an independent client (pymodbus + the
register map of config/modbus_registers.json): lockstep steps, determinism of a closed loop
under CPU load, record and replay, long steps, the end of a run. Usage: lockstep_integration.py SCENARIO"""
import filecmp
import os
import subprocess
import sys
import tempfile
import time

try:
    import serial_asyncio  # noqa: F401  (pymodbus.client imports it; only Recommended by Debian)
except ImportError:
    import types
    sys.modules["serial_asyncio"] = types.SimpleNamespace(create_serial_connection=None)
from pymodbus.client import ModbusTcpClient  # noqa: E402

from emu_harness import EMU, CONFIG, Emulator, RegisterMap  # noqa: E402

MAP = RegisterMap()
ADVANCE = MAP.holding["advance"]["address"]


class Stepper:
    """A controller in lockstep: one FC16 of registers 0..advance sets and steps, one FC04 reads."""

    def __init__(self, emu, timeout=10):
        self.client = ModbusTcpClient(emu.host, port=emu.port, timeout=timeout)
        assert self.client.connect(), "cannot connect"

    def step(self, command, amplitude_v, ticks, frequency_hz=40000.0, load_n=0.0):
        regs = ([command] + MAP.encode("frequency_setpoint", frequency_hz) + MAP.encode("amplitude_setpoint", amplitude_v)
                + MAP.encode("phase_setpoint", 90.0) + MAP.encode("load_force", load_n)
                + MAP.encode("frequency_slew", 1e6) + MAP.encode("amplitude_slew", 1e5) + [ticks])
        assert len(regs) == ADVANCE + 1
        return self.client.write_registers(0, regs, slave=1)

    def inputs(self):
        rr = self.client.read_input_registers(0, MAP.input_count, slave=1)
        assert not rr.isError(), rr
        return MAP.decode_inputs(rr.registers)

    def close(self):
        self.client.close()


def closed_loop(emu, cycles=300, target_mm_s=250.0):
    """A small PI speed loop (amplitude actuator, 1 ms cycles): the commands depend on the
    telemetry, so any nondeterminism in the emulator changes the command sequence too."""
    s = Stepper(emu)
    amplitude_v, integral, rows = 0.0, 0.0, []
    for k in range(cycles):
        w = s.step(1 if k == 0 else 0, round(amplitude_v, 1), 10, load_n=(0.0 if k < 150 else 1.0))
        assert not w.isError(), f"cycle {k}: {w}"
        t = s.inputs()
        speed = t["speed"] * 1e3  # m/s -> mm/s
        error = target_mm_s - speed
        integral += error * 1e-3
        amplitude_v = min(500.0, max(0.0, 0.4 * error + 60.0 * integral))
        rows.append((t["tick"], t["speed"], t["position"], t["amplitude_output"], t["state"], t["overruns"],
                     t["lateness_max"]))
    s.close()
    return rows


def hog():
    """A CPU hog on the other core (stopped by its pid)."""
    return subprocess.Popen([sys.executable, "-c", "while True: pass"])


def run_recorded(path, load=False):
    h = hog() if load else None
    try:
        with Emulator("--clock", "external", "--record", path) as emu:
            assert "clock=external" in emu.ready, emu.ready
            rows = closed_loop(emu)
            assert emu.stop() == 0, emu.stderr
    finally:
        if h:
            h.kill()
            h.wait()
    return rows


def determinism():
    with tempfile.TemporaryDirectory() as d:
        a, b = os.path.join(d, "a.csv"), os.path.join(d, "b.csv")
        quiet = run_recorded(a)
        loaded = run_recorded(b, load=True)
        assert quiet == loaded, "the closed loop saw different telemetry under load"
        assert filecmp.cmp(a, b, shallow=False), "traces differ byte for byte"
        final = quiet[-1]
        assert final[0] == 3001, final  # 1 start-up tick + 300 cycles x 10 ticks
        assert all(r[5] == 0 and r[6] == 0 for r in quiet), "timing registers are not 0 in lockstep"
        assert final[4] == 1, "not enabled at the end"
        speeds = [r[1] * 1e3 for r in quiet[100:150]]
        assert all(abs(v - 250.0) < 25.0 for v in speeds), f"the PI loop did not hold 250 mm/s: {speeds[:5]}..."
        print(f"determinism: {len(quiet)} cycles, traces identical ({os.path.getsize(a)} bytes), with and "
              f"without a CPU hog")


def replay():
    with tempfile.TemporaryDirectory() as d:
        trace = os.path.join(d, "t.csv")
        run_recorded(trace)
        ok = subprocess.run([EMU, "--config", CONFIG, "--replay", trace], capture_output=True, text=True)
        assert ok.returncode == 0 and "identical: 3001 ticks" in ok.stdout, ok.stdout + ok.stderr
        # One command changed: the first differing tick is the one after it was applied.
        lines = open(trace).read().split("\n")
        index = [i for i, line in enumerate(lines) if line.startswith("command,")][120]
        fields = lines[index].split(",")
        applied_at = int(fields[1])
        fields[7] = str(float(fields[7]) + 5.0)  # amplitude_v
        lines[index] = ",".join(fields)
        changed = os.path.join(d, "changed.csv")
        open(changed, "w").write("\n".join(lines))
        bad = subprocess.run([EMU, "--config", CONFIG, "--replay", changed], capture_output=True, text=True)
        assert bad.returncode == 3, bad.stdout + bad.stderr
        assert f"DIFFERENT at tick {applied_at + 1} " in bad.stdout and "column output_amplitude_v" in bad.stdout, bad.stdout
        # Other settings than the recording's are refused, naming the setting.
        other = subprocess.run([EMU, "--config", CONFIG, "--replay", trace, "--watchdog-ms", "50"],
                               capture_output=True, text=True)
        assert other.returncode == 1 and "watchdog_ms=100, this run has 50" in other.stderr, other.stderr
        # A file that is not a trace: file:line.
        junk = os.path.join(d, "junk.csv")
        open(junk, "w").write(lines[0] + "\n" + lines[1] + "\ntelemetry,x\n")
        j = subprocess.run([EMU, "--config", CONFIG, "--replay", junk], capture_output=True, text=True)
        assert j.returncode == 1 and f"{junk}:3:" in j.stderr, j.stderr
        print(f"replay: identical; a changed command found at tick {applied_at + 1}; settings and format checked")


def refused_on_wall_time():
    with Emulator() as emu:
        s = Stepper(emu)
        before = s.inputs()
        w = s.step(1, 100.0, 10)
        assert w.isError() and w.exception_code == 3, w
        after = s.inputs()
        assert after["last_reject_reason"] == MAP.reasons["clock_not_external"], after
        assert after["applied_commands"] == before["applied_commands"], "part of a refused request was applied"
        assert after["clock"] == 0
        s.close()
        assert emu.stop() == 0
    print("refused: a step on wall time is exception 03, reason clock_not_external, nothing applied")


def long_step():
    # A step far longer than the frame timeout: no deadline runs while the ticks are run.
    with Emulator("--clock", "external", "--modbus-frame-timeout-ms", "20") as emu:
        s = Stepper(emu, timeout=300)  # 65535 ticks take ~0.5 s in Release, far longer under ASan
        start = time.monotonic()
        w = s.step(1, 300.0, 65535)
        wall = time.monotonic() - start
        assert not w.isError(), w
        t = s.inputs()
        assert t["tick"] == 1 + 65535, t["tick"]
        s.close()
        assert emu.stop() == 0
        assert "reply timeout 0" in emu.output, emu.output
    print(f"long step: 65535 ticks in {wall:.2f} s wall, connection kept")


def end_of_run():
    with Emulator("--clock", "external", "--duration-s", "0.05") as emu:  # 500 ticks
        s = Stepper(emu)
        assert not s.step(1, 100.0, 400).isError()
        w = s.step(0, 100.0, 200)  # 100 of them run, then the emulator stops
        assert w.isError() and w.exception_code == 4, w
        s.close()
        assert emu.wait() == 0
        assert "after 0.050 s emulated" in emu.output, emu.output
    print("end of run: a step beyond --duration-s is answered with exception 04")


def scenario_refused():
    """A scenario with a bad line, an unknown event, an out-of-range time, or an effect the motor
    lacks is refused at start-up with file:line (or the --inject text); nothing starts (no ready
    line, exit 1)."""
    with tempfile.TemporaryDirectory() as d:
        cases = [
            ("bad.toml", "[[event]]\nat_s = 0.1\ntype = \"load_step\"\nload_n = = 2\n", [], "bad.toml:4"),
            ("unknown.toml", "[[event]]\nat_s = 0.1\ntype = \"melt_down\"\n", [], "unknown.toml:3"),
            ("late.toml", "[[event]]\nat_s = 2e6\ntype = \"over_temperature\"\n", [], "late.toml:2"),
            ("early.toml", "[[event]]\nat_s = -0.5\ntype = \"jam\"\n", [], "early.toml:2"),
            ("ambient.toml", "\n[[event]]\nat_s = 1\ntype = \"ambient\"\ntemperature_c = 60\n", [], "ambient.toml:2"),
            (None, None, ["--inject", "melt_down@1"], "--inject 'melt_down@1'"),
        ]
        for name, text, extra, where in cases:
            args = [EMU, "--config", CONFIG, "--modbus", "tcp://127.0.0.1:0", "--clock", "external", *extra]
            if name:
                path = os.path.join(d, name)
                open(path, "w").write(text)
                args += ["--scenario", path]
            r = subprocess.run(args, capture_output=True, text=True, timeout=60)
            assert r.returncode == 1, f"{name or extra}: exit {r.returncode}"
            assert "swum-emu ready" not in r.stdout, f"{name or extra}: started anyway"
            lines = r.stderr.strip().splitlines()
            assert len(lines) == 1 and where in lines[0], f"{name or extra}: {r.stderr!r}"
            print(f"refused: {lines[0]}")


def throughput():
    with Emulator("--clock", "external") as emu:
        s = Stepper(emu)
        cycles = 1000
        start = time.monotonic()
        for k in range(cycles):
            assert not s.step(1 if k == 0 else 0, 300.0, 10).isError()
            s.inputs()
        wall = time.monotonic() - start
        s.close()
        emu.stop()
    print(f"throughput: {cycles} cycles of 1 ms (step + read) in {wall:.3f} s: {cycles * 1e-3 / wall:.1f}x real time")


if __name__ == "__main__":
    {"determinism": determinism, "replay": replay, "refused": refused_on_wall_time, "long_step": long_step,
     "end_of_run": end_of_run, "throughput": throughput, "scenario_refused": scenario_refused}[sys.argv[1]]()
