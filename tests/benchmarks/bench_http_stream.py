#!/usr/bin/env python3
"""Does the HTTP API disturb the real-time loop? (docs/performance.md, "The control API".)
Runs swum-emu on wall time (10 kHz, the drive on at 400 V / 40 kHz over Modbus, --rt as
tools/rt-bench does unless --no-rt) in pairs, without and with K clients streaming the telemetry
at R Hz from /api/v1/stream, alternating the order, and prints each run's lateness p99 and overrun
share from its exit report, side by side. Printed, never asserted: the machine is shared.
Usage: bench_http_stream.py [--seconds 10] [--pairs 3] [--clients 4] [--rate-hz 50] [--no-rt]"""
import argparse
import http.client
import os
import re
import signal
import statistics
import subprocess
import sys
import threading
import types

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "firmware_sim"))
try:
    import serial_asyncio  # noqa: F401  (pymodbus.client imports it; only Recommended by Debian)
except ImportError:
    sys.modules["serial_asyncio"] = types.SimpleNamespace(create_serial_connection=None)
from pymodbus.client import ModbusTcpClient  # noqa: E402

from emu_harness import RegisterMap  # noqa: E402

SOURCE_DIR = os.environ.get("SWUM_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "../..")))
EMU = os.environ.get("SWUM_EMU", os.path.join(SOURCE_DIR, "build/ci/firmware_sim/swum-emu"))
CONFIG = os.path.join(SOURCE_DIR, "config/li2019.toml")


def stream(port, rate_hz, stop, counts, index, failures):
    """One client reading the event stream until `stop` is set; a refusal goes to `failures`
    (an exception in a thread would end only the thread, and the run would count fewer clients)."""
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=5)
    connection.request("GET", f"/api/v1/stream?rate_hz={rate_hz}")
    response = connection.getresponse()
    if response.status != 200:
        failures.append(f"stream {index} refused: {response.status} {response.read()!r}")
        return
    while not stop.is_set():
        line = response.readline()
        if not line:
            break
        if line.startswith(b"event: telemetry"):
            counts[index] += 1
    connection.close()


def enable(ready):
    """The drive on at 400 V / 40 kHz (what tools/rt-bench measures), through Modbus TCP."""
    port = int(re.search(r"modbus=tcp://127\.0\.0\.1:(\d+)", ready).group(1))
    m = RegisterMap()
    registers = [1] + m.encode("frequency_setpoint", 40000.0) + m.encode("amplitude_setpoint", 400.0)
    client = ModbusTcpClient("127.0.0.1", port=port, timeout=5)
    if not client.connect() or client.write_registers(0, registers, slave=1).isError():
        raise SystemExit("cannot enable the drive over Modbus")
    client.close()


def run(seconds, clients, rate_hz, rt):
    """One swum-emu run of `seconds`; returns (lateness p99 us, overrun %, events received)."""
    proc = subprocess.Popen([EMU, "--config", CONFIG, "--modbus", "tcp://127.0.0.1:0", "--http", "127.0.0.1:0",
                             "--duration-s", str(seconds), "--watchdog-ms", "0"] + (["--rt"] if rt else []),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    ready = proc.stdout.readline()
    match = re.search(r"http=http://127\.0\.0\.1:(\d+)", ready)
    if not match:
        proc.kill()
        raise SystemExit(f"swum-emu did not start: {ready!r} {proc.stderr.read()}")
    enable(ready)
    stop, counts, threads, failures = threading.Event(), [0] * clients, [], []
    for k in range(clients):
        threads.append(threading.Thread(target=stream, args=(int(match.group(1)), rate_hz, stop, counts, k, failures),
                                        daemon=True))
        threads[-1].start()
    try:
        out, err = proc.communicate(timeout=seconds * 5 + 30)
    except subprocess.TimeoutExpired:
        os.kill(proc.pid, signal.SIGKILL)
        raise
    stop.set()
    for t in threads:
        t.join(timeout=10)
    p99 = re.search(r"lateness\s+p50 [\d.]+ us\s+p99 ([\d.]+) us", out)
    overruns = re.search(r"overruns\s+\d+ \(([\d.]+) % of ticks\)", out)
    if proc.returncode != 0 or not p99 or not overruns:
        raise SystemExit(f"swum-emu failed ({proc.returncode}): {out}{err}")
    # Every client streamed the whole run (the first events wait for the drive to be enabled).
    expected = clients * rate_hz * seconds
    if failures or sum(counts) < 0.9 * expected:
        raise SystemExit(f"the streams did not run: {sum(counts)} events of {expected:.0f} expected; {failures}")
    return float(p99.group(1)), float(overruns.group(1)), sum(counts)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--pairs", type=int, default=3)
    parser.add_argument("--clients", type=int, default=4)
    parser.add_argument("--rate-hz", type=float, default=50.0)
    parser.add_argument("--no-rt", action="store_true", help="the loop at the default scheduler (no --rt)")
    a = parser.parse_args()
    print(f"swum-emu 10 kHz on wall time, {'' if a.no_rt else '--rt, '}drive 400 V / 40 kHz, {a.seconds:g} s per "
          f"run; 'with' = {a.clients} clients x {a.rate_hz:g} Hz; load {os.getloadavg()[0]:.2f}")
    print(f"{'pair':>4}  {'without: p99 us':>16} {'overruns %':>10}   {'with: p99 us':>13} {'overruns %':>10} "
          f"{'events':>7}")
    without, with_api = [], []
    for pair in range(a.pairs):
        order = [0, a.clients] if pair % 2 == 0 else [a.clients, 0]  # alternate: drift hits both alike
        results = {k: run(a.seconds, k, a.rate_hz, not a.no_rt) for k in order}
        (p0, o0, _), (p1, o1, events) = results[0], results[a.clients]
        without.append((p0, o0))
        with_api.append((p1, o1))
        print(f"{pair + 1:>4}  {p0:>16.1f} {o0:>10.4f}   {p1:>13.1f} {o1:>10.4f} {events:>7}")
        sys.stdout.flush()
    # The noise is the spread of the runs without the API: the runs with it are compared with it.
    for name, column, unit in (("lateness p99", 0, "us"), ("overruns", 1, "%")):
        w0 = sorted(r[column] for r in without)
        w1 = sorted(r[column] for r in with_api)
        print(f"{name}: without median {statistics.median(w0):.4g} {unit} (range {w0[0]:.4g}-{w0[-1]:.4g}), "
              f"with median {statistics.median(w1):.4g} {unit} (range {w1[0]:.4g}-{w1[-1]:.4g})")


if __name__ == "__main__":
    main()
