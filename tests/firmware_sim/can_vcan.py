#!/usr/bin/python3
"""swum-emu on a SocketCAN bus (vcan0) with independent peers: python3-can (frames encoded and
decoded through config/swum.dbc with python3-canmatrix, CRC computed here) and can-utils'
cansend/candump. Runs natively when the host has vcan0, else inside the test guest
(tools/vm/with-vcan). Never asserts timing (TCG guest).

usage: can_vcan.py SCENARIO   (enable_speed rejects watchdog bus_errors lockstep bus_off)

Every scenario also checks, from the exit report, that each frame the emulator received carried
the kernel's receive timestamp (SO_TIMESTAMPNS): none missing, none implausible.
"""
import decimal
import os
import re
import socket
import struct
import subprocess
import sys
import time

import can
import canmatrix
import canmatrix.formats

from emu_harness import SOURCE_DIR, Emulator, RegisterMap, deadline, reference

# The Python side's one CRC-8/SAE-J1850, written from docs/protocols.md (not the C++ codec's).
sys.path.insert(0, os.path.join(SOURCE_DIR, "bench"))
from swum_bench.can_link import crc8_sae_j1850 as crc8  # noqa: E402

DB = canmatrix.formats.loadp_flat(os.path.join(SOURCE_DIR, "config/swum.dbc"))
REASONS = RegisterMap().reasons
COMMAND = DB.frame_by_name("Command")
NODE = 1  # the DBC describes node 1


def command_frame(mode, alive, frequency_hz, amplitude_v, phase_deg=90.0):
    physical = {"Mode": mode, "Reserved1": 0, "AliveCounter": alive % 16, "Frequency": frequency_hz,
                "Phase": phase_deg, "Amplitude": amplitude_v, "Reserved2": 0, "Crc": 0}
    # canmatrix's Frame.encode takes raw values: convert through the DBC's factors.
    data = bytearray(COMMAND.encode({name: COMMAND.signal_by_name(name).phys2raw(decimal.Decimal(str(value)))
                                     for name, value in physical.items()}))
    data[7] = crc8(COMMAND.arbitration_id.id, data[:7])
    return bytes(data)


class Peer:
    """The controller under test on the bus."""

    def __init__(self):
        telemetry = [f.arbitration_id.id for f in DB.frames if f.name not in ("Command", "AuxCommand")]
        self.bus = can.Bus(interface="socketcan", channel="vcan0",
                           can_filters=[{"can_id": i, "can_mask": 0x7FF, "extended": False} for i in telemetry])
        self.alive = 0
        self.latest = {}

    def send_command(self, mode, frequency_hz, amplitude_v, phase_deg=90.0):
        self.alive = (self.alive + 1) % 16
        data = command_frame(mode, self.alive, frequency_hz, amplitude_v, phase_deg)
        self.bus.send(can.Message(arbitration_id=COMMAND.arbitration_id.id, data=data, is_extended_id=False))

    def poll(self, seconds=0.01):
        """Receives for a while; keeps the latest decoded value of every telemetry message."""
        end = time.monotonic() + seconds
        while True:
            left = end - time.monotonic()
            msg = self.bus.recv(timeout=max(0.0, left))
            if msg is None:
                return self.latest
            frame = DB.frame_by_id(canmatrix.ArbitrationId(msg.arbitration_id))
            if frame is not None and not msg.is_extended_id:
                self.latest[frame.name] = {k: float(v.phys_value) for k, v in frame.decode(bytes(msg.data)).items()}
            if left <= 0:  # a slow decoder (TCG guest) must not be trapped by the backlog
                return self.latest

    def wait_for(self, predicate, what, timeout=60, keep_sending=None):
        expired = deadline(timeout)
        while True:
            if keep_sending:
                keep_sending()
            latest = self.poll(0.01)
            try:
                matched = "Status" in latest and "Motion" in latest and predicate(latest)
            except KeyError:  # a frame the predicate reads has not come yet (a poll can end mid-set)
                matched = False
            if matched:
                return latest
            assert not expired(), f"timeout waiting for {what}; last telemetry {latest}"

    def close(self):
        self.bus.shutdown()


def cansend(data, can_id=0x200 + NODE):
    subprocess.run(["cansend", "vcan0", f"{can_id:03X}#{data.hex().upper()}"], check=True)


def check_exit_report(output):
    """The exit report's CAN lines: every received frame kernel-timestamped; returns the counters."""
    m = re.search(r"can +rx (\d+) \(accepted (\d+), rejected (\d+), receive errors (\d+)\), tx (\d+) "
                  r"\(dropped (\d+), send errors (\d+)\), error frames (\d+), bus-off (\d+)", output)
    assert m, output
    keys = ("rx", "accepted", "rejected", "rx_errors", "tx", "tx_dropped", "tx_errors", "error_frames", "bus_off")
    report = dict(zip(keys, (int(g) for g in m.groups())))
    m = re.search(r"kernel timestamps (\d+), missing (\d+), implausible (\d+); kernel drops (\d+); "
                  r"kernel rx -> read p50 ([\d.]+) us  p99 ([\d.]+) us  max ([\d.]+) us", output)
    assert m, output
    stamped, missing, implausible, drops = (int(g) for g in m.groups()[:4])
    assert report["rx"] > 0, "the emulator received no frame"
    assert stamped == report["rx"] and missing == 0 and implausible == 0, \
        f"frames without a usable kernel receive timestamp: {stamped} of {report['rx']} stamped, " \
        f"{missing} missing, {implausible} implausible"
    assert float(m.group(7)) > 0.0, "kernel rx -> read latency is zero: timestamps not taken from the kernel?"
    m = re.search(r"commands +(\d+); accept-to-effect p50 ([\d.]+) us", output)
    assert m and int(m.group(1)) > 0 and float(m.group(2)) > 0.0, output
    report["kernel_drops"] = drops
    print(f"kernel timestamps on all {stamped} received frames; CAN counters {report}")
    return report


def speed_close(latest, ref):
    return abs(latest["Motion"]["Speed"] - ref["speed_mm_s"]) <= 0.03 * abs(ref["speed_mm_s"]) + 2.0


def scenario_enable_speed():
    # The model's steady states first, before the emulator runs beside them: each is seconds of
    # the guest's emulated CPU.
    refs = {frequency: reference(400, frequency) for frequency in (40000, 39700)}
    with Emulator("--can", "vcan0", "--node", str(NODE), "--speedup", "0", "--watchdog-ms", "5000",
                  "--telemetry-hz", "50", modbus="none") as emu:
        peer = Peer()
        peer.wait_for(lambda t: t["Status"]["State"] == 0, "disabled at start")
        for frequency, ref in refs.items():
            send = lambda f=frequency: peer.send_command(1, f, 400)  # noqa: E731
            t = peer.wait_for(lambda t: t["Status"]["State"] == 1 and t["Drive"]["AmplitudeOut"] == 400 and
                              abs(t["Output"]["FrequencyOut"] - frequency) < 0.01 and speed_close(t, ref),
                              f"steady speed at {frequency} Hz", keep_sending=send)
            peer.poll(0.3)  # and it stays there
            t = peer.latest
            assert speed_close(t, ref), (t["Motion"], ref)
            print(f"{frequency} Hz: emulator {t['Motion']['Speed']:.2f} mm/s, model {ref['speed_mm_s']:.2f} mm/s, "
                  f"tip {t['Drive']['TipNormal']:.3f}/{ref['tip_normal_um']:.3f} um")
        peer.send_command(0, 40000, 0)
        peer.wait_for(lambda t: t["Status"]["State"] == 0 and t["Drive"]["AmplitudeOut"] == 0, "disabled")
        peer.close()
        assert emu.stop() == 0
        print(emu.output)
        check_exit_report(emu.output)


def scenario_rejects():
    with Emulator("--can", "vcan0", "--node", str(NODE), "--speedup", "1", "--watchdog-ms", "0",
                  "--heartbeat-ms", "100", "--telemetry-hz", "50", modbus="none") as emu:
        # candump sees heartbeats and status frames (independent receiver).
        dump = subprocess.run(["candump", "-L", "-n", "3", "vcan0,701:7FF"], capture_output=True, text=True, timeout=30)
        assert dump.returncode == 0 and dump.stdout.count("701#05") == 3, dump.stdout
        peer = Peer()
        cansend(command_frame(1, 1, 40000, 100))  # valid: enable at 100 V
        peer.wait_for(lambda t: t["Status"]["State"] == 1, "enabled via cansend")

        def expect(data, reason, can_id=0x200 + NODE):
            before = peer.poll(0.05)["Status"]
            cansend(data, can_id)
            t = peer.wait_for(lambda t: t["Status"]["RejectCount"] != before["RejectCount"], f"reject {reason}")
            assert t["Status"]["LastReject"] == REASONS[reason], (t["Status"], reason)
            assert t["Status"]["State"] == 1 and t["Status"]["AppliedCount"] == before["AppliedCount"], t["Status"]
            assert t["Drive"]["AmplitudeOut"] == 100, t["Drive"]
            print(f"cansend {data.hex()}: rejected, reason {reason}")

        good = command_frame(1, 3, 40000, 300)
        bad_crc = good[:7] + bytes([good[7] ^ 0x5A])
        expect(bad_crc, "bad_checksum")
        expect(good[:5], "wrong_length")
        expect(command_frame(1, 2, 60000, 300), "frequency_out_of_range")
        # Stale: a repeat of the counter last accepted, sent back to back with the frame it
        # repeats - well inside the 1 s of silence after which an identifier takes any counter
        # again (a restarted controller), which a slow guest could otherwise exceed between two
        # cansend runs.
        before = peer.poll(0.05)["Status"]
        fresh = command_frame(1, 2, 40000, 100)
        for data in (fresh, fresh):
            peer.bus.send(can.Message(arbitration_id=0x200 + NODE, data=data, is_extended_id=False))
        t = peer.wait_for(lambda t: t["Status"]["RejectCount"] != before["RejectCount"], "reject stale_alive_counter")
        assert t["Status"]["LastReject"] == REASONS["stale_alive_counter"], t["Status"]
        assert t["Drive"]["AmplitudeOut"] == 100, t["Drive"]
        print("alive counter 2 repeated at once: rejected, reason stale_alive_counter")
        expect(command_frame(3, 2, 40000, 300), "unknown_command")
        reserved = bytearray(command_frame(1, 2, 40000, 300))
        reserved[0] |= 0x04
        reserved[7] = crc8(0x200 + NODE, reserved[:7])
        expect(bytes(reserved), "reserved_bits")
        # A frame for another node is not even received (kernel filter): no reject counted.
        before = peer.poll(0.05)["Status"]["RejectCount"]
        cansend(bad_crc, 0x200 + NODE + 1)
        assert peer.poll(0.3)["Status"]["RejectCount"] == before
        # Then the valid one is applied.
        cansend(good)
        peer.wait_for(lambda t: t["Drive"]["AmplitudeOut"] == 300, "valid command applied")
        peer.close()
        assert emu.stop() == 0
        print(emu.output)
        report = check_exit_report(emu.output)
        assert report["accepted"] == 3 and report["rejected"] == 6, report


def scenario_watchdog():
    with Emulator("--can", "vcan0", "--node", str(NODE), "--speedup", "1", "--watchdog-ms", "100", "--telemetry-hz", "50",
                  modbus="none") as emu:
        peer = Peer()
        send = lambda: peer.send_command(1, 40000, 400)  # noqa: E731
        peer.wait_for(lambda t: t["Status"]["State"] == 1 and t["Motion"]["Speed"] > 20, "moving", keep_sending=send)
        # Silence. Status and Drive are separate frames: wait until both show the fault.
        t = peer.wait_for(lambda t: t["Status"]["State"] == 2 and t["Drive"]["AmplitudeOut"] == 0, "watchdog fault")
        assert t["Status"]["FaultCode"] == 1 and t["Status"]["DriveOn"] == 0, t["Status"]
        peer.wait_for(lambda t: abs(t["Motion"]["Speed"]) < 1.0, "coasting to rest")
        # Enable refused in fault; reset then enable works.
        peer.send_command(1, 40000, 400)
        t = peer.wait_for(lambda t: t["Status"]["LastReject"] == REASONS["fault_active"], "enable refused")
        assert t["Status"]["State"] == 2
        peer.send_command(2, 40000, 400)
        peer.wait_for(lambda t: t["Status"]["State"] == 0 and t["Status"]["FaultCode"] == 0, "fault reset")
        peer.close()
        assert emu.stop() == 0
        check_exit_report(emu.output)


CAN_ERR_FLAG, CAN_ERR_BUSOFF, CAN_ERR_DLC = 0x20000000, 0x40, 8


def send_error_frame(classes):
    """An error frame as a CAN controller driver reports it (raw socket: python-can sends data only)."""
    s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    try:
        s.bind(("vcan0",))
        s.send(struct.pack("=IB3x8s", CAN_ERR_FLAG | classes, CAN_ERR_DLC, bytes(8)))
    finally:
        s.close()


def ip_link(state):
    subprocess.run(["ip", "link", "set", "vcan0", state], check=True)


def scenario_bus_errors():
    """Bus-off error frame and the interface going down and up (ENETDOWN on both sockets): the
    emulator reports them, keeps running and applies the next valid command."""
    with Emulator("--can", "vcan0", "--node", str(NODE), "--speedup", "1", "--watchdog-ms", "0",
                  "--telemetry-hz", "100", modbus="none") as emu:
        peer = Peer()
        send = lambda: peer.send_command(1, 40000, 100)  # noqa: E731
        peer.wait_for(lambda t: t["Status"]["State"] == 1 and t["Drive"]["AmplitudeOut"] == 100, "enabled",
                      keep_sending=send)
        send_error_frame(CAN_ERR_BUSOFF)
        peer.poll(0.3)
        peer.close()
        alive = peer.alive  # the emulator remembers the last accepted counter
        ip_link("down")  # telemetry sends fail (ENETDOWN), the receive socket gets ENETDOWN
        time.sleep(0.5)
        ip_link("up")
        assert emu.proc.poll() is None, "swum-emu died with the interface down: " + emu.proc.stderr.read()
        peer = Peer()
        peer.alive = alive
        peer.send_command(1, 40000, 300)
        peer.wait_for(lambda t: t["Drive"]["AmplitudeOut"] == 300, "valid command applied after bus errors")
        peer.close()
        assert emu.stop() == 0, emu.stderr
        print(emu.output)
        print(emu.stderr)
        report = check_exit_report(emu.output)
        assert report["bus_off"] == 1 and report["error_frames"] == 1, report
        assert report["tx_errors"] > 0 and report["rx_errors"] > 0, report  # ENETDOWN, counted, not fatal
        assert "bus-off" in emu.stderr and "Network is down" in emu.stderr, emu.stderr


TELEMETRY = ("Status", "Motion", "Drive", "LoopStats", "Clock", "ElectricalA", "ElectricalB", "Output")


def sync_frame(counter):
    return can.Message(arbitration_id=DB.frame_by_name("Sync").arbitration_id.id, data=bytes([counter]),
                       is_extended_id=False)


def telemetry_after_sync(peer, timeout=60):
    """The telemetry frames one SYNC answers with: {name: (raw bytes, decoded)}."""
    got, expired = {}, deadline(timeout)
    while len(got) < len(TELEMETRY):
        msg = peer.bus.recv(timeout=1.0)
        assert not expired(), f"no complete telemetry after a SYNC: {sorted(got)}"
        if msg is None:
            continue
        frame = DB.frame_by_id(canmatrix.ArbitrationId(msg.arbitration_id))
        if frame is not None and frame.name in TELEMETRY:
            assert frame.name not in got, f"{frame.name} twice for one SYNC (wall-time telemetry in lockstep?)"
            got[frame.name] = (bytes(msg.data), {k: float(v.phys_value) for k, v in frame.decode(bytes(msg.data)).items()})
    return got


def lockstep_run(cycles, enable_at, extra=(), hog=False, can_log=None):
    """Lockstep over CAN: the controller sends its command, then a SYNC, then reads the telemetry
    the SYNC answers with. Returns the raw telemetry bytes of every cycle."""
    h = subprocess.Popen([sys.executable, "-c", "while True: pass"]) if hog else None
    if can_log:
        extra = (*extra, "--record-can", can_log)
    try:
        with Emulator("--can", "vcan0", "--node", str(NODE), "--clock", "external", "--sync-ticks", "10",
                      *extra, modbus="none") as emu:
            assert "clock=external" in emu.ready, emu.ready
            peer = Peer()
            log = []
            for k in range(cycles):
                if k >= enable_at:
                    peer.send_command(1, 40000.0, 300.0)  # every cycle: feeds the watchdog
                peer.bus.send(sync_frame(k % 240 + 1))
                log.append(telemetry_after_sync(peer))
            peer.close()
            assert emu.stop() == 0, emu.stderr
            output = emu.output
    finally:
        if h:
            h.kill()
            h.wait()
    m = re.search(r"lockstep SYNCs (\d+)", output)
    assert m and int(m.group(1)) == cycles, f"SYNCs counted: {m and m.group(1)} of {cycles}\n{output}"
    return log, output


def scenario_lockstep():
    """CANopen synchronous semantics in lockstep: SYNC k answers with the state sampled at it (tick
    1 + 10 k: nothing runs between SYNCs), the command received before SYNC k acts from then on and
    shows in the telemetry of SYNC k+1, not k (one cycle of delay); the same frames give the same
    bytes with a CPU hog running; a SYNC to a wall-time emulator is refused (reason 17)."""
    cycles, enable_at = 40, 5
    logs = [f"/tmp/swum-can-{os.getpid()}-{n}.log" for n in ("quiet", "loaded")]
    quiet, _ = lockstep_run(cycles, enable_at, can_log=logs[0])
    for k, frames in enumerate(quiet):
        tick = frames["Clock"][1]["Tick"]
        assert tick == 1 + 10 * k, f"SYNC {k}: tick {tick}, expected {1 + 10 * k}"
        assert frames["LoopStats"][1]["LatenessMax"] == 0, "timing fields must be 0 in lockstep"
    states = [frames["Status"][1]["State"] for frames in quiet]
    assert states[enable_at] == 0 and states[enable_at + 1] == 1, \
        f"one cycle of delay expected: state at SYNC {enable_at} = {states[enable_at]}, next = {states[enable_at + 1]}"
    assert quiet[-1]["Motion"][1]["Speed"] > 0.1, "the motor did not move"
    # Output ends every set (a controller takes the set as complete there): the electrical frames come before it.
    assert all(list(frames)[-1] == "Output" for frames in quiet), [list(frames) for frames in quiet[:2]]
    a, b, status = quiet[-1]["ElectricalA"][1], quiet[-1]["ElectricalB"][1], quiet[-1]["Status"][1]
    assert a["CurrentA"] > 0 and b["CurrentB"] > 0 and a["PowerA"] + b["PowerB"] > 0, (a, b)
    assert abs(status["StatorTemperature"] - 20.0) < 5.0, status
    assert quiet[0]["ElectricalA"][1]["CurrentA"] == 0, "a current before the drive was enabled"
    loaded, _ = lockstep_run(cycles, enable_at, hog=True, can_log=logs[1])
    raw = lambda log: [[frames[n][0] for n in TELEMETRY] for frames in log]  # noqa: E731
    assert raw(quiet) == raw(loaded), "telemetry bytes differ with a CPU hog running"
    # --record-can: candump's log format on emulated time, the same file under load, and
    # can-utils' canplayer reads it.
    text = [open(p).read() for p in logs]
    assert text[0] == text[1], "the CAN logs differ with a CPU hog running"
    lines = text[0].splitlines()
    assert all(re.fullmatch(r"\(\d+\.\d{6}\) vcan0 [0-9A-F]{3}#([0-9A-F]{2})*", line) for line in lines), lines[:3]
    assert sum(1 for line in lines if " 080#" in line) == cycles, "every SYNC logged"
    assert sum(1 for line in lines if " 181#" in line) == cycles, "every Status frame logged"
    player = subprocess.run(["canplayer", "-t", "-I", logs[0], "vcan0=vcan0"], capture_output=True, text=True)
    assert player.returncode == 0, player.stderr
    for p in logs:
        os.remove(p)
    with Emulator("--can", "vcan0", "--node", str(NODE), modbus="none") as emu:
        peer = Peer()
        peer.bus.send(sync_frame(1))
        peer.wait_for(lambda t: t["Status"]["LastReject"] == REASONS["clock_not_external"], "SYNC refused on wall time")
        peer.close()
        emu.stop()
    print(f"lockstep over CAN: {cycles} SYNCs, ticks 1 + 10 k, one cycle of delay, identical bytes under load")


def scenario_bus_off():
    """A scenario's bus-off in lockstep: from 5 ms for 5 ms the node sends no telemetry and
    discards the commands it receives (SYNCs still step the run); then it answers again."""
    cycles = 16
    h = None
    with Emulator("--can", "vcan0", "--node", str(NODE), "--clock", "external", "--sync-ticks", "10",
                  "--heartbeat-ms", "0", "--inject", "can_bus_off@0.005:duration_s=0.005", modbus="none") as emu:
        peer = Peer()
        answered = []
        for k in range(cycles):
            peer.send_command(1, 40000.0, 300.0)
            peer.bus.send(sync_frame(k + 1))
            frames = []
            end = time.monotonic() + (5.0 if not 5 <= k < 10 else 1.0)
            while time.monotonic() < end and len(frames) < len(TELEMETRY):
                msg = peer.bus.recv(timeout=0.2)
                if msg is not None:
                    frames.append(msg)
            answered.append(len(frames) == len(TELEMETRY))
        peer.close()
        assert emu.stop() == 0
        output = emu.output
    del h
    silent = [k for k, ok in enumerate(answered) if not ok]
    assert silent == list(range(5, 10)), f"cycles without telemetry: {silent} (expected 5..9)"
    m = re.search(r"frames discarded (\d+)", output)
    assert m and int(m.group(1)) == 5, f"commands discarded during bus-off: {m and m.group(1)}\n{output}"
    print("bus-off: telemetry silent for cycles 5..9, 5 commands discarded, then back")


if __name__ == "__main__":
    scenario = sys.argv[1] if len(sys.argv) > 1 else "enable_speed"
    globals()["scenario_" + scenario]()
    print(f"PASS can {scenario}")
