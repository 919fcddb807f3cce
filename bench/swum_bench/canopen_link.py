"""The bench as the CANopen master of swum-emu's CiA 402 drive in lockstep (docs/canopen.md,
"The test bench as a master"), written from CiA 301/402 and config/swum.eds alone.

Start: NMT reset communication, the boot-up awaited; by SDO (pre-operational) the supported
modes checked, controlword 0x06 and the mode written, the TPDOs mapped with the objects of the
bench's signals (transmission type 1: sampled at every SYNC) and the RPDOs with the command
objects (type 1: acting at the next SYNC), by CiA 301's procedure; then NMT start. Each control
cycle is the RPDOs whose content changed, one SYNC, and the synchronous TPDOs sampled at it:
the state before the cycle the SYNC starts (as on the swum CAN link). Slews (0x2004/0x2005, not
mappable) go by SDO when they change. Identifiers, types, limits and defaults are the EDS's."""
import math
import os
import re
import time

from . import cia402
from .installation import data_file
from .canopen_eds import Eds
from .canopen_sdo import SdoClient
from .emulator import BenchError
from .signals import BenchUsageError

NMT_ID = 0x000            # CiA 301 7.2.8.3.1: NMT command, 2 bytes: command, node id
NMT_START, NMT_RESET_COMMUNICATION = 0x01, 0x82
BOOT_UP_BASE = 0x700      # CiA 301 7.2.8.3.2.2: boot-up (and heartbeat) 0x700 + node, data 00
COB_ID_NOT_VALID = 1 << 31  # CiA 301 7.5.2.35: bit 31 of a PDO's COB-ID
SYNCHRONOUS_EVERY_SYNC = 1  # transmission type 1
PDO_BITS = 64
# 0x6502 bits: 2 profile velocity (CiA 402), 16 the manufacturer's mode -1 (docs/canopen.md).
MODE_OPEN_LOOP, MODE_PROFILE_VELOCITY = -1, 3
SUPPORTED_MODE_BIT = {MODE_OPEN_LOOP: 16, MODE_PROFILE_VELOCITY: 2}
# The command objects in the RPDOs: controlword, mode and phase; frequency and amplitude;
# target velocity (profile velocity, mode 3).
RPDO_OBJECTS = [(0x6040, 0x6060, 0x2003), (0x2001, 0x2002), (0x60FF,)]
# Every sample carries the state, so every TPDO plan starts with the statusword and 0x603F.
ALWAYS_MAPPED = (0x6041, 0x603F)


def amplifier_limits(data_dir, emu_args=()):
    """{option: value} of the amplifier's set-point limits (--min-frequency-hz, --max-frequency-hz,
    --max-amplitude-v): config/modbus_registers.json names them with their defaults ("--min-frequency-hz
    (30000)"), and emu_args may set them. swum-emu refuses a set-point beyond them in an RPDO
    without an answer on the bus, so the bench checks them before it sends."""
    import json
    path = data_file(data_dir, "modbus_registers.json")
    try:
        with open(path) as f:
            holding = {r["name"]: r for r in json.load(f)["holding_registers"]}
    except (OSError, ValueError, KeyError) as e:
        raise BenchUsageError(f"the register map {path} cannot be read (--swum-data): {e}") from None
    limits = {}
    for name in ("frequency_setpoint", "amplitude_setpoint"):
        for bound in ("min", "max"):
            m = re.fullmatch(r"(--[a-z-]+) \(([-+0-9.eE]+)\)", str(holding[name].get(bound, "")))
            if m:
                limits[m.group(1)] = float(m.group(2))
    args = [str(a) for a in emu_args]
    for i, arg in enumerate(args):
        option, _, value = arg.partition("=")
        if option in limits:
            text = value if _ else (args[i + 1] if i + 1 < len(args) else "")
            try:
                limits[option] = float(text)
            except ValueError:
                pass  # swum-emu refuses it at start-up with its own message
    return limits


def plan_tpdos(eds, indices):
    """[(TPDO number 1-4, [Entry...])]: the objects (the statusword and 0x603F first) packed in
    their order into the first TPDO with room (64 bits each, CiA 301). More than four TPDOs hold
    is a BenchUsageError naming the bits."""
    entries = []
    for index in [*ALWAYS_MAPPED, *[i for i in indices if i not in ALWAYS_MAPPED]]:
        entry = eds[index, 0]
        if not entry.pdo_mapping or not entry.readable or entry.bits is None:
            raise BenchUsageError(f"{entry.where} cannot be mapped into a TPDO (EDS: PDOMapping=0)")
        entries.append(entry)
    count = sum(1 for i in range(1, 5) if (0x1800 + i - 1, 1) in eds)
    pdos = [[] for _ in range(count)]
    for entry in entries:
        room = next((p for p in pdos if sum(e.bits for e in p) + entry.bits <= PDO_BITS), None)
        if room is None:
            total = sum(e.bits for e in entries)
            raise BenchUsageError(f"the signals need {total} bits of TPDO, {count} TPDOs of {PDO_BITS} bits hold "
                                  f"{count * PDO_BITS} (and whole objects only): choose fewer (canopen_signals=)")
        room.append(entry)
    return [(n + 1, p) for n, p in enumerate(pdos) if p]


class RawCanBus:
    """Frames on Python's own SocketCAN socket (as the CAN gate relays them), receiving only the
    given identifiers."""

    def __init__(self, interface, ids, timeout_s=30.0):
        from .can_gate import open_raw  # socket.AF_CAN: Linux only, imported when used
        self.interface = interface
        self.timeout_s = timeout_s  # a full transmit queue is waited for this long (a hang guard)
        try:
            self.sock = open_raw(interface, ids)
        except OSError as e:
            raise BenchError(f"CAN {interface}: cannot open: {e.strerror or e}") from e

    def set_ids(self, ids):
        import socket
        import struct
        mask = 0x7FF | 0x80000000 | 0x40000000  # standard data frames only
        self.sock.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER,
                             b"".join(struct.pack("=II", i, mask) for i in ids))

    def send(self, can_id, data):
        """Sends a frame; a full transmit queue is waited for up to the hang guard."""
        from .can_gate import CAN_FRAME
        frame = CAN_FRAME.pack(can_id, len(data), bytes(data).ljust(8, b"\0"))
        deadline = time.monotonic() + self.timeout_s
        while True:
            try:
                self.sock.send(frame)
                return
            except TimeoutError:
                if time.monotonic() > deadline:
                    raise BenchError(f"CAN {self.interface}: the bus took no frame for {self.timeout_s:g} s") from None
            except OSError as e:
                raise BenchError(f"CAN {self.interface}: send of 0x{can_id:03X}: {e.strerror or e}") from e

    def receive(self, timeout_s):
        """(can_id, data) or None once timeout_s has passed without one."""
        from .can_gate import receive_raw
        deadline = time.monotonic() + timeout_s
        while True:
            got = receive_raw(self.sock)
            if got is not None:
                return got[0], got[1]
            if time.monotonic() >= deadline:
                return None

    def close(self):
        self.sock.close()


class CanopenLink:
    def __init__(self, interface, node, data_dir, signal_objects, emu_args=(), timeout_s=30.0,
                 bus=None):
        """signal_objects: the object indices the bench's signals need in the TPDOs (telemetry.py).
        bus: a frame bus (send/receive/set_ids/close), by default a SocketCAN socket on interface."""
        self.where = f"{interface} node {node}"
        self.node = node
        self.timeout_s = timeout_s
        self.eds = Eds(data_file(data_dir, "swum.eds"), node)
        self.limits = amplifier_limits(data_dir, emu_args)
        self.tpdos = plan_tpdos(self.eds, signal_objects)
        self.tpdo_ids = {self._cob_id(0x1800 + n - 1): (n, entries) for n, entries in self.tpdos}
        self.sync_id = self.eds.default(0x1005) & 0x7FF
        request_id, response_id = (self.eds.default(0x1200, s) & 0x7FF for s in (1, 2))
        self.bus = bus if bus is not None else RawCanBus(interface, [BOOT_UP_BASE + node, response_id], timeout_s)
        self.sdo = SdoClient(self.bus, node, request_id, response_id, timeout_s=timeout_s)
        self.sequencer = cia402.Sequencer()
        self._rpdo_sent = {}  # RPDO COB-ID -> the payload last sent
        self._slews = {0x2004: self.eds.default(0x2004), 0x2005: self.eds.default(0x2005)}
        self._mode = MODE_OPEN_LOOP

    def _cob_id(self, index):
        return self.eds.default(index, 1) & 0x7FF

    def close(self):
        self.bus.close()

    # ---- start ------------------------------------------------------------------------------
    def start(self):
        """NMT reset communication and the boot-up, configuration by SDO, NMT start."""
        self.bus.send(NMT_ID, bytes([NMT_RESET_COMMUNICATION, self.node]))
        self._wait_boot_up()
        modes = self.sdo.read(self.eds[0x6502, 0])
        for mode, bit in SUPPORTED_MODE_BIT.items():
            if not modes >> bit & 1:
                raise BenchError(f"CANopen {self.where}: 0x6502 = 0x{modes:08X}: mode {mode} not supported")
        self.sdo.write(self.eds[0x6040, 0], self.sequencer.last)
        self.sdo.write(self.eds[0x6060, 0], self._mode)
        for n, entries in self.tpdos:
            self._map(0x1800 + n - 1, 0x1A00 + n - 1, entries)
        mapped = {n for n, _ in self.tpdos}
        for n in range(1, 5):
            if n not in mapped and (0x1800 + n - 1, 1) in self.eds:
                self._invalidate(0x1800 + n - 1)
        for n in range(1, 5):
            if (0x1400 + n - 1, 1) not in self.eds:
                continue
            if n <= len(RPDO_OBJECTS):
                self._map(0x1400 + n - 1, 0x1600 + n - 1, [self.eds[i, 0] for i in RPDO_OBJECTS[n - 1]])
            else:
                self._invalidate(0x1400 + n - 1)
        self.bus.set_ids([self.sdo.response_id, *self.tpdo_ids])  # the heartbeats stay out
        self.bus.send(NMT_ID, bytes([NMT_START, self.node]))

    def _frames(self, missing):
        """The frames received until the caller stops; none within the hang guard (not a
        measurement) is a BenchError saying what was missing (missing(): text)."""
        deadline = time.monotonic() + self.timeout_s
        while True:
            left = deadline - time.monotonic()
            got = self.bus.receive(left) if left > 0 else None
            if got is None:
                raise BenchError(f"CANopen {self.where}: {missing()} within {self.timeout_s:g} s")
            yield got

    def _wait_boot_up(self):
        boot_up = BOOT_UP_BASE + self.node
        for can_id, data in self._frames(lambda: f"no boot-up (0x{boot_up:03X}#00) after NMT reset communication"):
            if can_id == boot_up and bytes(data) == b"\0":  # a heartbeat carries the state, not 00
                return

    def _invalidate(self, communication):
        self.sdo.write(self.eds[communication, 1], self._cob_id(communication) | COB_ID_NOT_VALID)

    def _map(self, communication, mapping, entries):
        """CiA 301 7.5.2.36's procedure: the PDO made not valid, its mapping count 0, the entries,
        the count, the transmission type, the PDO valid again."""
        self._invalidate(communication)
        self.sdo.write(self.eds[mapping, 0], 0)
        for sub, entry in enumerate(entries, start=1):
            self.sdo.write(self.eds[mapping, sub], entry.mapping_entry())
        self.sdo.write(self.eds[mapping, 0], len(entries))
        self.sdo.write(self.eds[communication, 2], SYNCHRONOUS_EVERY_SYNC)
        self.sdo.write(self.eds[communication, 1], self._cob_id(communication))

    # ---- the cycle --------------------------------------------------------------------------
    def _count(self, index, value, units_per_unit, what):
        """The bus count of a set-point (rounded to the nearest, as the other links do)."""
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"{self.eds[index, 0].where}: {what} {value!r} is not a finite number")
        return int(round(value * units_per_unit))

    def _check_limit(self, option, value, unit, above):
        limit = self.limits.get(option)
        if limit is not None and (value > limit if above else value < limit):
            raise ValueError(f"{value!r} {unit} is {'above' if above else 'below'} the amplifier's {option} "
                             f"{limit:g} (swum-emu would refuse the RPDO's write without an answer)")

    def send_command(self, command, last_sample):
        """One cycle's command (a controllers.Command): slews by SDO if they changed, then the
        RPDOs whose content changed. Returns the command registers as sent (`command` the action
        code of the controlword)."""
        velocity = getattr(command, "velocity_mm_s", None)
        mode = MODE_OPEN_LOOP if velocity is None else MODE_PROFILE_VELOCITY
        # Units from the objects' names in the EDS: mHz, mV (terminal amplitude), 0.01 deg, um/s.
        frequency = self._count(0x2001, command.frequency_hz, 1e3, "frequency_hz")
        self._check_limit("--min-frequency-hz", command.frequency_hz, "Hz", above=False)
        self._check_limit("--max-frequency-hz", command.frequency_hz, "Hz", above=True)
        amplitude = self._count(0x2002, command.amplitude_v, 1e3, "amplitude_v")
        self._check_limit("--max-amplitude-v", command.amplitude_v, "V", above=True)
        phase = self._count(0x2003, command.phase_deg, 100.0, "phase_deg")
        target = self._count(0x60FF, 0.0 if velocity is None else velocity, 1e3, "velocity_mm_s")
        slews = {0x2004: self._count(0x2004, command.frequency_slew_hz_s, 1.0, "frequency_slew_hz_s"),
                 0x2005: self._count(0x2005, command.amplitude_slew_v_per_s, 1.0, "amplitude_slew_v_per_s")}
        for (index, raw), asked in zip(slews.items(), (command.frequency_slew_hz_s, command.amplitude_slew_v_per_s)):
            if raw == 0 and asked != 0:
                raise ValueError(f"{self.eds[index, 0].where}: {asked!r} rounds to 0, which means unlimited")
        last_statusword = None if last_sample is None else int(last_sample["statusword"])
        values = {0x2001: frequency, 0x2002: amplitude, 0x2003: phase, 0x60FF: target, 0x6060: mode}
        payloads = {}
        for n, objects in enumerate(RPDO_OBJECTS, start=1):  # encoded first: a bad value sends nothing
            payloads[n] = [(index, self.eds[index, 0].encode(values[index])) for index in objects if index != 0x6040]
        for index, raw in slews.items():
            self.eds[index, 0].encode(raw)
        word = self.sequencer.controlword(command.action, last_statusword)
        payloads[1].insert(0, (0x6040, self.eds[0x6040, 0].encode(word)))
        for index, raw in slews.items():
            if raw != self._slews[index]:
                self.sdo.write(self.eds[index, 0], raw)
                self._slews[index] = raw
        for n, fields in payloads.items():
            cob_id = self._cob_id(0x1400 + n - 1)
            data = b"".join(b for _, b in fields)
            if self._rpdo_sent.get(cob_id) != data:
                self.bus.send(cob_id, data)
                self._rpdo_sent[cob_id] = data
        self._mode = mode
        return {"command": cia402.ACTION_OF_CONTROLWORD[word], "frequency_setpoint": command.frequency_hz,
                "amplitude_setpoint": command.amplitude_v, "phase_setpoint": command.phase_deg,
                "velocity_setpoint": math.nan if velocity is None else velocity}

    def command_registers(self, command):
        """The command registers of the bench's first SYNC: nothing sent yet, the controlword
        the configuration wrote."""
        return {"command": cia402.ACTION_OF_CONTROLWORD[self.sequencer.last],
                "frequency_setpoint": command.frequency_hz, "amplitude_setpoint": command.amplitude_v,
                "phase_setpoint": command.phase_deg, "velocity_setpoint": math.nan}

    def sync(self):
        """One SYNC, and the synchronous TPDOs that answer it: {object index: value}."""
        self.bus.send(self.sync_id, b"")
        values, missing = {}, dict(self.tpdo_ids)
        frames = self._frames(lambda: f"no TPDO {sorted(n for n, _ in missing.values())} answered the SYNC")
        while missing:
            can_id, data = next(frames)
            if can_id not in missing:
                continue
            n, entries = missing.pop(can_id)
            size = sum(e.bits for e in entries) // 8
            if len(data) != size:
                raise BenchError(f"CANopen {self.where}: TPDO{n} (0x{can_id:03X}) of {len(data)} bytes, its mapping "
                                 f"has {size}")
            offset = 0
            for entry in entries:
                values[entry.index] = entry.decode(data[offset:offset + entry.bits // 8])
                offset += entry.bits // 8
        return values
