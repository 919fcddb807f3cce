"""Shared helpers of the swum-emu integration tests: start the real binary, wait for its
"ready" line (no sleeps), read the register map from config/modbus_registers.json (so the test
uses the documented map, not the code's constants), stop the process by its pid."""
import json
import os
import re
import signal
import subprocess
import time

SOURCE_DIR = os.environ.get("SWUM_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "../..")))
EMU = os.environ.get("SWUM_EMU", os.path.join(SOURCE_DIR, "build/emu/firmware_sim/swum-emu"))
REFERENCE = os.environ.get("SWUM_EMU_REFERENCE", os.path.join(SOURCE_DIR, "build/emu/tests/firmware_sim/swum_emu_reference"))
CONFIG = os.path.join(SOURCE_DIR, "config/li2019.toml")


class RegisterMap:
    def __init__(self):
        with open(os.path.join(SOURCE_DIR, "config/modbus_registers.json")) as f:
            m = json.load(f)
        self.holding = {r["name"]: r for r in m["holding_registers"]}
        self.input = {r["name"]: r for r in m["input_registers"]}
        self.reasons = {v: int(k) for k, v in m["reason_codes"].items()}
        self.input_count = max(r["address"] + (2 if "32" in r["type"] else 1) for r in m["input_registers"])
        self.holding_count = max(r["address"] + (2 if "32" in r["type"] else 1) for r in m["holding_registers"])

    @staticmethod
    def _decode(entry, regs, base=0):
        a = entry["address"] - base
        t = entry["type"]
        if t == "uint16":
            raw = regs[a]
        elif t == "int16":
            raw = regs[a] - 0x10000 if regs[a] & 0x8000 else regs[a]
        else:
            raw = (regs[a] << 16) | regs[a + 1]
            if t == "int32" and raw & 0x80000000:
                raw -= 1 << 32
        return raw * entry["scale"]

    def decode_inputs(self, regs):
        return {name: self._decode(e, regs) for name, e in self.input.items()}

    def decode_holding(self, regs):
        return {name: self._decode(e, regs) for name, e in self.holding.items()}

    def encode(self, name, physical):
        """Registers for holding register `name` at `physical` (list of 16-bit words)."""
        e = self.holding[name]
        raw = int(round(physical / e["scale"]))
        if e["type"] in ("uint32", "int32"):
            raw &= 0xFFFFFFFF
            return [raw >> 16, raw & 0xFFFF]
        return [raw & 0xFFFF]


class Emulator:
    """swum-emu as a child process. `args` are extra command-line arguments; `config` the
    parameter file (default: CONFIG at the time of the call, which some tests reassign)."""

    def __init__(self, *args, modbus="tcp://127.0.0.1:0", timeout=30.0, config=None):
        cmd = [EMU, "--config", config or CONFIG, "--modbus", modbus, *args]
        self.proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.ready = self.proc.stdout.readline()  # blocks until the ready line (or EOF on failure)
        if "swum-emu ready" not in self.ready:
            err = self.proc.stderr.read()
            self.proc.kill()
            raise RuntimeError(f"swum-emu did not start: {self.ready!r} {err}")
        m = re.search(r"modbus=tcp://([\d.]+):(\d+)", self.ready)
        self.host, self.port = (m.group(1), int(m.group(2))) if m else (None, None)
        self.output = None

    def stop(self, sig=signal.SIGTERM, timeout=30):
        if self.proc.poll() is None:
            os.kill(self.proc.pid, sig)
        out, err = self.proc.communicate(timeout=timeout)
        self.output = self.ready + out
        self.stderr = err
        return self.proc.returncode

    def wait(self, timeout=60):
        out, err = self.proc.communicate(timeout=timeout)
        self.output = self.ready + out
        self.stderr = err
        return self.proc.returncode

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.proc.poll() is None:
            os.kill(self.proc.pid, signal.SIGKILL)
            self.proc.wait()


def reference(amplitude_v, frequency_hz, phase_deg=90.0, load_n=0.0):
    out = subprocess.run([REFERENCE, CONFIG, str(amplitude_v), str(frequency_hz), str(phase_deg), str(load_n)],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def deadline(seconds):
    end = time.monotonic() + seconds
    return lambda: time.monotonic() > end
