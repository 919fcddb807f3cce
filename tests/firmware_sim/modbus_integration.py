#!/usr/bin/python3
"""swum-emu over Modbus TCP on 127.0.0.1 with an independent client (Debian's python3-pymodbus).

usage: modbus_integration.py SCENARIO   (enable_speed frequency_change watchdog rejects malformed clients electrical)
Environment: SWUM_EMU, SWUM_EMU_REFERENCE, SWUM_SOURCE_DIR (set by ctest).
"""
import json
import math
import os
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time

try:
    import serial_asyncio  # noqa: F401  (pymodbus.client imports it; only Recommended by Debian)
except ImportError:
    import types
    sys.modules["serial_asyncio"] = types.SimpleNamespace(create_serial_connection=None)
from pymodbus.client import ModbusTcpClient  # noqa: E402

from emu_harness import SOURCE_DIR, Emulator, RegisterMap, deadline, reference

MAP = RegisterMap()
ILLEGAL_FUNCTION, ILLEGAL_DATA_ADDRESS, ILLEGAL_DATA_VALUE = 1, 2, 3


class Controller:
    """A controller under test, as a Modbus TCP client."""

    def __init__(self, emu):
        self.client = ModbusTcpClient(emu.host, port=emu.port, timeout=5)
        assert self.client.connect(), "cannot connect"
        self.accepted = 0  # writes accepted by the emulator (each one command) on this connection

    def close(self):
        self.client.close()

    def inputs(self):
        rr = self.client.read_input_registers(0, MAP.input_count, slave=1)
        assert not rr.isError(), rr
        return MAP.decode_inputs(rr.registers)

    def holding(self):
        rr = self.client.read_holding_registers(0, MAP.holding_count, slave=1)
        assert not rr.isError(), rr
        return MAP.decode_holding(rr.registers)

    def write(self, **values):
        """Writes named holding registers in one FC16 request when contiguous, else one by one.
        Returns the exception code (0 = accepted)."""
        for name, value in values.items():
            rr = self.client.write_registers(MAP.holding[name]["address"], MAP.encode(name, value), slave=1)
            if rr.isError():
                return rr.exception_code
            self.accepted += 1
        return 0

    def command(self, code):
        return self.write(command=code)

    def run_at(self, amplitude_v, frequency_hz):
        assert self.write(frequency_setpoint=frequency_hz, amplitude_setpoint=amplitude_v) == 0
        assert self.command(1) == 0  # enable

    def wait_applied(self, timeout=60):
        """Input registers once every write this client got accepted has been applied; for a
        client that is the emulator's only writer since it started (applied_commands counts all
        interfaces). A command takes effect at the next tick boundary, so a read right after an
        accepted write may still show an earlier tick (docs/protocols.md): time an effect from
        the snapshot this returns, whose emulated time is at or after the last write's effect."""
        expired = deadline(timeout)
        while True:
            values = self.inputs()
            if values["applied_commands"] >= self.accepted:
                break
            assert not expired(), f"accepted writes not applied: {values['applied_commands']} of {self.accepted}; {values}"
        # Nothing accepted lost, nothing applied that was not accepted, nothing refused.
        assert values["applied_commands"] == self.accepted and values["reject_count"] == 0, (self.accepted, values)
        return values

    def wait_sim_time(self, t_s, keepalive=True, timeout=60):
        expired = deadline(timeout)
        while True:
            values = self.inputs()
            if values["sim_time"] >= t_s:
                return values
            assert not expired(), f"emulated time stuck at {values['sim_time']}"
            if keepalive:
                assert self.command(0) == 0


def steady_reference(amplitude_v, frequency_hz):
    """The model's steady state (run_to_steady_state). Computed before the emulator starts: the
    emulator keeps running (and its watchdog counting) while a scenario waits for it."""
    ref = reference(amplitude_v, frequency_hz)
    assert ref["ok"], ref
    return ref


def check_speed(measured_m_s, ref, what):
    speed_mm_s = measured_m_s * 1e3
    tolerance = 0.03 * abs(ref["speed_mm_s"]) + 2.0
    print(f"{what}: emulator {speed_mm_s:.2f} mm/s, model steady state {ref['speed_mm_s']:.2f} mm/s (tolerance {tolerance:.2f})")
    assert abs(speed_mm_s - ref["speed_mm_s"]) <= tolerance, "speed differs from the model's steady state"
    return ref


def scenario_enable_speed():
    ref = steady_reference(400, 40000)
    with Emulator("--speedup", "4", "--watchdog-ms", "1000") as emu:
        c = Controller(emu)
        v = c.inputs()
        assert v["state"] == 0 and v["amplitude_output"] == 0
        c.run_at(400, 40000)
        v = c.wait_sim_time(c.wait_applied()["sim_time"] + 0.12)
        assert v["state"] == 1, v
        assert v["status"] & 1 and v["status"] & 8, v  # enabled, drive on
        assert abs(v["amplitude_output"] - 400) < 1e-6 and abs(v["frequency_output"] - 40000) < 1e-3
        check_speed(v["speed"], ref, "400 V 40 kHz")
        assert v["tip_normal_amplitude"] > 1.0, v
        assert v["applied_commands"] >= 3
        c.close()
        assert emu.stop() == 0
        print(emu.output)
        assert "loop statistics" in emu.output and "state disabled" in emu.output


def scenario_frequency_change():
    # Up, not down: below the peak the softening resonance is bistable (model_spec §9.1), so
    # the branch a live change lands on depends on when it arrives; above it the speed
    # has one steady value, the one run_to_steady_state finds from rest.
    first, second = steady_reference(400, 40000), steady_reference(400, 40400)
    assert abs(second["speed_mm_s"] - first["speed_mm_s"]) > 5, "pick frequencies with distinct speeds"
    with Emulator("--speedup", "4", "--watchdog-ms", "1000") as emu:
        c = Controller(emu)
        c.run_at(400, 40000)
        v = c.wait_sim_time(c.wait_applied()["sim_time"] + 0.12)
        check_speed(v["speed"], first, "40 kHz")
        assert c.write(frequency_setpoint=40400) == 0
        # 0.15 s of emulated time from a snapshot in which the change has taken effect (not
        # from `v`: the loop may not have reached the tick that applies the write yet).
        v = c.wait_sim_time(c.wait_applied()["sim_time"] + 0.15)
        assert abs(v["frequency_output"] - 40400) < 1e-3, v
        check_speed(v["speed"], second, "40.4 kHz")
        c.close()
        assert emu.stop() == 0


def scenario_watchdog():
    with Emulator("--speedup", "1", "--watchdog-ms", "200") as emu:
        c = Controller(emu)
        c.run_at(400, 40000)
        v = c.wait_sim_time(c.wait_applied()["sim_time"] + 0.08)  # keep-alive every request: stays enabled
        assert v["state"] == 1 and v["speed"] > 0.05, v
        # Silence: read only (reads do not feed the watchdog).
        expired = deadline(10)
        while v["state"] != 2:
            assert not expired(), "no watchdog fault"
            v = c.inputs()
        assert v["fault_code"] == 1 and v["amplitude_output"] == 0 and not v["status"] & 8, v
        print(f"watchdog fault at {v['sim_time']:.3f} s, speed {v['speed']*1e3:.1f} mm/s")
        # Coast to rest under friction.
        v = c.wait_sim_time(v["sim_time"] + 0.1, keepalive=False)
        assert abs(v["speed"]) < 1e-3, v
        assert v["state"] == 2
        # Enable is refused in fault (state unchanged, reason readable); reset -> disabled.
        rejects = v["reject_count"]
        assert c.command(1) == 0  # the write is well-formed; the amplifier refuses it
        expired = deadline(5)
        while v["reject_count"] == rejects:
            assert not expired()
            v = c.inputs()
        assert v["state"] == 2 and v["last_reject_reason"] == MAP.reasons["fault_active"], v
        assert c.command(3) == 0
        expired = deadline(5)
        while v["state"] != 0:
            assert not expired()
            v = c.inputs()
        assert v["fault_code"] == 0
        c.close()
        assert emu.stop() == 0


def expect_rejected(c, exception, reason, write=None, read=None):
    before_in, before_hold = c.inputs(), c.holding()
    if write is not None:
        address, values = write
        rr = c.client.write_registers(address, values, slave=1) if len(values) > 1 or address != MAP.holding["command"]["address"] \
            else c.client.write_register(address, values[0], slave=1)
    else:
        address, count, function = read
        rr = (c.client.read_input_registers if function == 4 else c.client.read_holding_registers)(address, count, slave=1)
    assert rr.isError(), rr
    assert rr.exception_code == exception, (rr.exception_code, exception)
    after = c.inputs()
    assert after["last_reject_reason"] == MAP.reasons[reason], (after["last_reject_reason"], reason)
    assert after["reject_count"] == before_in["reject_count"] + 1
    assert after["state"] == before_in["state"] and after["applied_commands"] == before_in["applied_commands"]
    assert c.holding() == before_hold
    print(f"rejected as expected: exception {exception}, reason {reason}")


def scenario_rejects():
    with Emulator("--speedup", "1", "--watchdog-ms", "0") as emu:
        c = Controller(emu)
        h = MAP.holding
        expect_rejected(c, ILLEGAL_DATA_VALUE, "amplitude_out_of_range", write=(h["amplitude_setpoint"]["address"], MAP.encode("amplitude_setpoint", 700)))
        expect_rejected(c, ILLEGAL_DATA_VALUE, "frequency_out_of_range", write=(h["frequency_setpoint"]["address"], MAP.encode("frequency_setpoint", 60000)))
        expect_rejected(c, ILLEGAL_DATA_VALUE, "phase_out_of_range", write=(h["phase_setpoint"]["address"], MAP.encode("phase_setpoint", 200)))
        expect_rejected(c, ILLEGAL_DATA_VALUE, "unknown_command", write=(h["command"]["address"], [7]))
        expect_rejected(c, ILLEGAL_DATA_ADDRESS, "split_value", write=(h["frequency_setpoint"]["address"] + 1, [5]))
        expect_rejected(c, ILLEGAL_DATA_ADDRESS, "illegal_address", write=(40, [1, 2]))
        expect_rejected(c, ILLEGAL_DATA_ADDRESS, "illegal_address", read=(MAP.input_count, 1, 4))
        expect_rejected(c, ILLEGAL_DATA_ADDRESS, "illegal_address", read=(5, 10, 3))
        rr = c.client.read_coils(0, 1, slave=1)
        assert rr.isError() and rr.exception_code == ILLEGAL_FUNCTION, rr
        assert c.inputs()["last_reject_reason"] == MAP.reasons["illegal_function"]
        # A valid write after all that is applied.
        assert c.write(amplitude_setpoint=123.4) == 0
        expired = deadline(5)
        while abs(c.holding()["amplitude_setpoint"] - 123.4) > 1e-6:
            assert not expired()
        c.close()
        assert emu.stop() == 0


def mbap(transaction, pdu, length=None, unit=1):
    return struct.pack(">HHHB", transaction, 0, len(pdu) + 1 if length is None else length, unit) + pdu


def scenario_malformed():
    with Emulator("--speedup", "1", "--watchdog-ms", "0") as emu:
        c = Controller(emu)
        before = c.inputs()
        # FC16 whose byte count disagrees with the quantity: ILLEGAL DATA VALUE, nothing applied.
        with socket.create_connection((emu.host, emu.port), timeout=5) as s:
            s.sendall(mbap(1, struct.pack(">BHHB", 16, 3, 2, 2) + b"\x00\x10"))
            reply = s.recv(260)
            assert reply[7] == 0x90 and reply[8] == ILLEGAL_DATA_VALUE, reply.hex()
        v = c.inputs()
        assert v["last_reject_reason"] == MAP.reasons["wrong_length"], v
        # Unsupported function codes: exception 01 under the code with its top bit set, also for
        # codes that have it already (128-255, those of exception replies): libmodbus alone
        # answers function + 0x80 in one byte, so 0x84 came back as "04 01", a malformed FC04
        # reply (found by tools/soak). Each body is what libmodbus frames for the code.
        with socket.create_connection((emu.host, emu.port), timeout=5) as s:
            for tid, pdu in enumerate([b"\x2b", b"\x80", b"\x84", b"\xff", b"\x01\x00\x00\x00\x01"], 10):
                s.sendall(mbap(tid, pdu))
                reply = s.recv(260)
                assert reply == mbap(tid, bytes([pdu[0] | 0x80, ILLEGAL_FUNCTION]), unit=1), (pdu.hex(), reply.hex())
        # Truncated frame, then hang up.
        with socket.create_connection((emu.host, emu.port), timeout=5) as s:
            s.sendall(mbap(2, struct.pack(">BHH", 3, 0, 10))[:9])
        # Garbage and a bogus protocol id.
        with socket.create_connection((emu.host, emu.port), timeout=5) as s:
            s.sendall(bytes(range(256)) * 2)
            s.settimeout(2)
            try:
                s.recv(260)
            except (socket.timeout, ConnectionResetError):
                pass
        # MBAP headers that contradict the frame: a valid FC04 read under protocol id 1, one
        # whose length field counts fewer bytes than the read has, one announcing more than an
        # ADU holds. None is answered; each connection is closed at once and counted as "bad
        # header" (docs/protocols.md).
        read = struct.pack(">BHH", 4, 0, 1)
        for tid, frame in [(3, struct.pack(">HHHB", 3, 1, len(read) + 1, 1) + read),
                           (5, mbap(5, read, length=3)),
                           (6, mbap(6, read, length=0xFFFF))]:
            with socket.create_connection((emu.host, emu.port), timeout=5) as s:
                s.sendall(frame)
                s.settimeout(5)
                try:
                    reply = s.recv(260)
                except ConnectionResetError:
                    reply = b""
                assert reply == b"", (frame.hex(), reply.hex())
        # The MBAP length frames the request, libmodbus frames by function code: bytes the
        # length counts beyond that are read as part of the request. FC43/14 (Read Device
        # Identification, which HMIs probe on connect) with its body: exception 01; FC04 with 2
        # bytes more than its own: exception 03, reason wrong_length. The connection stays in
        # step: a read after each is answered.
        with socket.create_connection((emu.host, emu.port), timeout=5) as s:
            for tid, pdu, code in [(20, b"\x2b\x0e\x01\x00", ILLEGAL_FUNCTION),
                                   (21, b"\x08\x00\x00\x12\x34", ILLEGAL_FUNCTION),
                                   (22, read + b"\xde\xad", ILLEGAL_DATA_VALUE)]:
                s.sendall(mbap(tid, pdu))
                reply = s.recv(260)
                assert reply == mbap(tid, bytes([pdu[0] | 0x80, code])), (pdu.hex(), reply.hex())
                s.sendall(mbap(tid + 100, read))
                reply = s.recv(260)
                assert reply[:2] == struct.pack(">H", tid + 100) and reply[7] == 4, reply.hex()
        assert c.inputs()["last_reject_reason"] == MAP.reasons["wrong_length"]
        # A length field announcing bytes that never come: closed at the frame timeout.
        with socket.create_connection((emu.host, emu.port), timeout=5) as s:
            s.sendall(mbap(7, read, length=200))
            s.settimeout(5)
            t0 = time.monotonic()
            try:
                reply = s.recv(260)
            except ConnectionResetError:
                reply = b""
            assert reply == b"" and time.monotonic() - t0 >= 0.45, reply.hex()
        after = c.inputs()  # the first client is still served
        assert after["state"] == before["state"] and after["applied_commands"] == before["applied_commands"], after
        assert emu.proc.poll() is None, "swum-emu died"
        c.close()
        assert emu.stop() == 0
        # The three above and the garbage (its bytes 2-3, 0x0203, are no Modbus protocol id).
        assert "bad header 4" in emu.output, emu.output


def scenario_clients():
    """8 clients at once, each polling and writing; every accepted write is applied."""
    with Emulator("--speedup", "1", "--watchdog-ms", "0") as emu:
        first = Controller(emu)
        base = first.inputs()["applied_commands"]
        accepted = [0] * 8
        errors = []

        def worker(i):
            try:
                c = Controller(emu)
                for k in range(150):
                    c.inputs()
                    if c.write(amplitude_setpoint=(i * 150 + k) % 500) == 0:
                        accepted[i] += 1
                c.close()
            except Exception as e:  # noqa: BLE001 - reported below
                errors.append(repr(e))

        threads = [threading.Thread(target=worker, args=(i,)) for i in range(8)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert not errors, errors
        expected = base + sum(accepted)
        expired = deadline(5)
        while first.inputs()["applied_commands"] != expected:
            assert not expired(), (first.inputs()["applied_commands"], expected)
        print(f"8 clients: {sum(accepted)} writes accepted, all applied")
        first.close()
        assert emu.stop() == 0
        assert "8 connections" in emu.output or "9 connections" in emu.output, emu.output


def scenario_electrical():
    """The electrical port (input registers 36..44, docs/protocols.md "Electrical port") and the
    amplifier's output (45..50, docs/amplifier.md), read on their own and decoded from the JSON
    map: drive on at 300 V near the resonance, an ideal source (no [amplifier] network)."""
    with Emulator("--speedup", "4", "--watchdog-ms", "1000") as emu:
        c = Controller(emu)
        first = MAP.input["current_a"]["address"]
        count = MAP.input_count - first
        assert count == 15, f"electrical registers {first}..{MAP.input_count - 1}"

        def electrical():
            rr = c.client.read_input_registers(first, count, slave=1)
            assert not rr.isError(), rr
            # decode_inputs wants the table from 0: pad the registers below the first one.
            return MAP.decode_inputs([0] * first + list(rr.registers))

        off = electrical()
        assert off["current_a"] == 0 and off["current_b"] == 0 and off["power_a"] == 0, off
        assert abs(off["stator_temperature"] - 20.0) < 1.0, off
        c.run_at(300, 40400)
        v = c.wait_sim_time(c.wait_applied()["sim_time"] + 0.1)
        assert v["state"] == 1, v
        e = electrical()
        print("300 V 40.4 kHz: " + ", ".join(f"{k} {e[k]:.4g}" for k in (
            "current_a", "current_b", "phase_a", "phase_b", "motional_phase_a", "motional_phase_b", "power_a", "power_b",
            "stator_temperature")))
        assert e["current_a"] > 0.0 and e["current_b"] > 0.0, e
        assert e["power_a"] + e["power_b"] > 0.0, e  # the motor takes power
        for name in ("phase_a", "phase_b", "motional_phase_a", "motional_phase_b"):
            assert -180.0 < e[name] <= 180.0, (name, e[name])
        assert abs(e["stator_temperature"] - 20.0) < 5.0, e
        # Without a network the amplifier delivers the phase current at the commanded voltage: its
        # registers (amplifier_*) are the port's fit (current_*, phase_*), the terminal amplitude the
        # command.
        print("amplifier: " + ", ".join(f"{k} {e[k]:.4g}" for k in (
            "amplifier_current_a", "amplifier_current_b", "amplifier_phase_a", "amplifier_phase_b",
            "terminal_amplitude_a", "terminal_amplitude_b")))
        for phase in ("a", "b"):
            assert abs(e["terminal_amplitude_" + phase] - 300.0) < 0.2, e
            assert abs(e["amplifier_current_" + phase] - e["current_" + phase]) < 0.1 * e["current_" + phase], e
            assert abs(e["amplifier_phase_" + phase] - e["phase_" + phase]) < 5.0, e
        # The whole table in one read gives the same registers (the host tool reads it that way).
        whole = c.inputs()
        assert whole["current_a"] > 0.0 and abs(whole["stator_temperature"] - e["stator_temperature"]) < 1.0, whole
        c.close()
        assert emu.stop() == 0


def scenario_matched_network():
    """The amplifier's output network in swum-emu (docs/amplifier.md, docs/sizing.md): the parallel
    inductor `swum size` buys for the default motor at 400 V (its design row: the highest voltage,
    unloaded, cold), set as [amplifier], brings phase A's amplifier current within 5 deg of its
    voltage at the design row's frequency, read over Modbus (input registers 45-50); without it the
    current leads by far more (C0's current)."""
    motor_path = os.path.join(SOURCE_DIR, "config/li2019.toml")
    size = subprocess.run([os.environ["SWUM_BINARY"], "size", "--config", motor_path, "--amplitude-v", "400", "--json"],
                          capture_output=True, text=True, timeout=120)
    assert size.returncode == 0, size.stderr
    design = json.loads(size.stdout)["network"]
    amplitude_v, frequency_hz = design["amplitude_v"], design["phase_a"]["frequency_hz"]
    inductance_uh = design["phase_a"]["parallel_inductance_uh"]
    sized_current_a = design["phase_a"]["parallel_amplifier_current_a"]
    source_v = [amplitude_v]  # what swum-emu is commanded: with a network, the amplifier's output

    def settled(config):
        with Emulator("--speedup", "4", "--watchdog-ms", "1000", config=config) as emu:
            c = Controller(emu)
            c.run_at(source_v[0], frequency_hz)
            v = c.wait_sim_time(c.wait_applied()["sim_time"] + 0.5)
            assert v["state"] == 1, v
            c.close()
            assert emu.stop() == 0
            return v

    ideal = settled(None)
    with open(motor_path) as f:
        motor = f.read()
    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as f:
        f.write(motor + f"\n[amplifier]\nparallel_inductance_uh = {inductance_uh:.6f}\n")
        matched_config = f.name
    try:
        matched = settled(matched_config)
    finally:
        os.unlink(matched_config)
    print(f"swum size: {amplitude_v:g} V at {frequency_hz:g} Hz, L_p {inductance_uh:.1f} uH, amplifier current "
          f"{sized_current_a:.4f} A; swum-emu ideal: amplifier_phase_a {ideal['amplifier_phase_a']:.2f} deg; matched: "
          f"amplifier_phase_a {matched['amplifier_phase_a']:.2f} deg, amplifier_current_a "
          f"{matched['amplifier_current_a']:.4f} A, terminal_amplitude_a {matched['terminal_amplitude_a']:.1f} V")
    assert ideal["amplifier_phase_a"] > 45.0, ideal
    assert abs(matched["amplifier_phase_a"]) < 5.0, matched
    assert abs(matched["amplifier_current_a"] - sized_current_a) < 0.05 * sized_current_a, matched
    assert abs(matched["terminal_amplitude_a"] - amplitude_v) < 0.4, matched  # no series impedance
    # The series inductor swum size sized in the loop, behind its source resistance, with the
    # amplifier at the voltage it names: phase A's terminal amplitude as the design says.
    series = json.loads(size.stdout)["series_in_loop"]
    assert series["converged"], series
    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as f:
        f.write(motor + f"\n[amplifier]\nseries_inductance_uh = {series['series_inductance_uh']:.6f}\n"
                f"source_resistance_ohm = {series['source_resistance_ohm']:.6f}\n")
        series_config = f.name
    try:
        source_v[0] = series["source_voltage_v"]
        stepped_up = settled(series_config)
    finally:
        os.unlink(series_config)
    print(f"series: {series['series_inductance_uh']:.1f} uH from {series['source_voltage_v']:.2f} V: swum-emu phase A "
          f"{stepped_up['terminal_amplitude_a']:.1f} V (design {series['terminal_a_v']:.1f} V, target "
          f"{design['amplitude_v']:g} V), phase B "
          f"{stepped_up['terminal_amplitude_b']:.1f} V")
    # The design holds phase A within 2 % in the simulator (its own criterion: converged), and
    # swum-emu realises the design: its terminal amplitude within 0.5 % of the simulator's. (The
    # design's fixed point sits ~1.9 % low - docs/sizing.md - so comparing swum-emu with the
    # target alone would test the 0.1 V register resolution and the settling, not the emulator.)
    assert abs(series["terminal_a_v"] - design["amplitude_v"]) <= 0.02 * design["amplitude_v"], series
    assert abs(stepped_up["terminal_amplitude_a"] - series["terminal_a_v"]) < 0.005 * design["amplitude_v"], stepped_up


if __name__ == "__main__":
    scenario = sys.argv[1] if len(sys.argv) > 1 else "enable_speed"
    globals()["scenario_" + scenario]()
    print(f"PASS {scenario}")
