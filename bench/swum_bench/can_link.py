"""The bench's CAN client (python-can on SocketCAN, frames from config/swum.dbc through
canmatrix): one control cycle is a Command frame (plus AuxCommand when the load or a slew
changes) and a CANopen SYNC; the eight telemetry frames that answer the SYNC were sampled at
it (docs/protocols.md, "Lockstep over CAN"). The CRC and the alive counter are written here
from the protocol text, apart from the C++ codec."""
import decimal
import math
import os
import time

from .installation import data_file
from .emulator import BenchError

SYNC_ID = 0x080
# Mode bits of the Command frame; a keep-alive repeats the mode that holds the drive as it is.
# CAN Command frame Mode -> the action code of the Modbus command register, so the `command`
# signal means the same on both transports (Mode 1 is enable and keep-alive alike).
MODE_ACTION = {0: 2, 1: 1, 2: 3}
TELEMETRY = ("Status", "Motion", "Drive", "LoopStats", "Clock", "ElectricalA", "ElectricalB", "Output")


def crc8_sae_j1850(can_id, data7):
    """CRC-8/SAE-J1850 (poly 0x1D, init 0xFF, xorout 0xFF) over the identifier as two bytes,
    little-endian, then payload bytes 0-6."""
    crc = 0xFF
    for byte in bytes([can_id & 0xFF, (can_id >> 8) & 0xFF]) + bytes(data7):
        crc ^= byte
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1D) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc ^ 0xFF


def load_dbc(data_dir):
    import canmatrix.formats  # Debian's python3-canmatrix; imported here so Modbus-only runs need none
    return canmatrix.formats.loadp_flat(data_file(data_dir, "swum.dbc"))


def frame_decoder(frame):
    """data -> {signal name: physical value as float} for a canmatrix frame, equal to
    {k: float(v.phys_value) for k, v in frame.decode(data).items()}: the bit layout and the
    scaling (Signal.raw2phys) are canmatrix's; only the unpacking is done here, on an integer
    instead of canmatrix's bit strings, which took most of the bench's CAN gate's time per cycle in
    the TCG guest (docs/testing.md). Frames it does not cover (big-endian, float or multiplexed
    signals) decode through canmatrix. A payload of the wrong length is canmatrix's error."""
    signals = list(frame.signals)
    if frame.is_multiplexed or frame.is_pdu_container or any(
            not s.is_little_endian or s.is_float or s.is_multiplexer or s.mux_val is not None for s in signals):
        return lambda data: {k: float(v.phys_value) for k, v in frame.decode(bytearray(data)).items()}
    from canmatrix.canmatrix import DecodingFrameLength
    size = int(frame.size)
    layout = [(s.name, int(s.start_bit), (1 << int(s.size)) - 1, 1 << int(s.size), bool(s.is_signed), s.raw2phys)
              for s in signals]

    def decode(data):
        if len(data) != size:
            raise DecodingFrameLength(f"Received message 0x{frame.arbitration_id.id:08X} with length {len(data)}, "
                                      f"expected {size}")
        word = int.from_bytes(data, "little")
        values = {}
        for name, start, mask, span, signed, raw2phys in layout:
            raw = (word >> start) & mask
            if signed and raw > mask >> 1:
                raw -= span
            values[name] = float(raw2phys(raw))
        return values
    return decode


class CanLink:
    def __init__(self, interface, node, data_dir, timeout_s=30.0):
        import can  # python3-can
        self.where = f"{interface} node {node}"
        self.node = node
        self.timeout_s = timeout_s
        self.dbc = load_dbc(data_dir)
        # The DBC describes node 1: identifiers are base + node.
        self.frames = {f.name: f for f in self.dbc.frames}
        self.decoders = {name: frame_decoder(f) for name, f in self.frames.items()}
        self.ids = {name: f.arbitration_id.id - 1 + node for name, f in self.frames.items()
                    if name not in ("Sync",)}
        self.by_id = {self.ids[name]: name for name in TELEMETRY}
        try:
            self.bus = can.interface.Bus(channel=interface, interface="socketcan", receive_own_messages=False)
        except (OSError, can.CanError) as e:
            raise BenchError(f"CAN {interface}: cannot open: {e}") from e
        self.bus.set_filters([{"can_id": i, "can_mask": 0x7FF} for i in self.by_id])
        self._can = can
        self._alive = {"Command": 0, "AuxCommand": 0}
        self._aux = None
        self._rejects = None
        self._mode = 0  # the mode the bench last commanded (not the delayed telemetry's state)

    def close(self):
        self.bus.shutdown()

    def _send(self, name, raw):
        frame = self.frames[name]
        can_id = self.ids[name]
        if name in self._alive:
            self._alive[name] = (self._alive[name] + 1) % 16
            raw["AliveCounter"] = self._alive[name]
            raw["Crc"] = 0
            data = frame.encode(raw)
            data[7] = crc8_sae_j1850(can_id, data[:7])
        else:
            data = frame.encode(raw) if raw else bytearray()
        msg = self._can.Message(arbitration_id=can_id, data=bytes(data), is_extended_id=False)
        try:
            self.bus.send(msg, timeout=self.timeout_s)
        except self._can.CanError as e:
            raise BenchError(f"CAN {self.where}: send of {name}: {e}") from e

    def _raw(self, frame_name, signal_name, value):
        """The raw count of a physical value; one that the signal's bits cannot hold (or NaN) is
        a ValueError naming the signal (canmatrix would wrap it silently)."""
        signal = self.frames[frame_name].signal_by_name(signal_name)
        if not math.isfinite(value):
            raise ValueError(f"{frame_name}.{signal_name}: {value!r} is not a finite number")
        # Rounded to the nearest count as the Modbus encoding does (canmatrix's phys2raw
        # truncates); Decimal from repr() keeps the float's shortest exact text.
        scaled = (decimal.Decimal(repr(float(value))) - decimal.Decimal(signal.offset)) / decimal.Decimal(signal.factor)
        raw = int(scaled.to_integral_value(rounding=decimal.ROUND_HALF_EVEN))
        if raw == 0 and value != 0 and signal_name.endswith("Slew"):
            raise ValueError(f"{frame_name}.{signal_name}: {value!r} rounds to 0, which means unlimited")
        bits = int(signal.size)
        lo, hi = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signal.is_signed else (0, (1 << bits) - 1)
        if not lo <= raw <= hi:
            raise ValueError(f"{frame_name}.{signal_name}: {value!r} does not fit the signal ({bits} bits)")
        return raw

    def send_command(self, command, last_sample):
        """One Command frame (every set-point), and an AuxCommand when load or slews changed or
        a command was rejected since the last cycle (it may have been the AuxCommand). Returns
        the command registers as sent, `command` as the Modbus code of the Mode sent."""
        action = command["command"]
        if action == 0:  # keep-alive: repeat the mode that holds the drive as it is
            mode = 0 if last_sample is not None and last_sample["state"] == 2 else self._mode
        else:
            mode = {1: 1, 2: 0, 3: 2}[action]
        raws = {"Frequency": self._raw("Command", "Frequency", command["frequency_setpoint"]),
                "Phase": self._raw("Command", "Phase", command["phase_setpoint"]),
                "Amplitude": self._raw("Command", "Amplitude", command["amplitude_setpoint"])}
        aux = {"Load": self._raw("AuxCommand", "Load", command["load_force"]),
               "FrequencySlew": self._raw("AuxCommand", "FrequencySlew", command["frequency_slew"]),
               "AmplitudeSlew": self._raw("AuxCommand", "AmplitudeSlew", command["amplitude_slew"])}
        self._send("Command", {"Mode": mode, "Reserved1": 0, "Reserved2": 0, **raws})
        self._mode = 1 if mode == 1 else 0  # after a reset the drive is disabled
        rejects = None if last_sample is None else last_sample["reject_count"]
        if aux != self._aux or rejects != self._rejects:
            self._send("AuxCommand", {"Reserved1": 0, **aux})
            self._aux = aux
        self._rejects = rejects
        return {"command": MODE_ACTION[mode], "frequency_setpoint": command["frequency_setpoint"],
                "amplitude_setpoint": command["amplitude_setpoint"], "phase_setpoint": command["phase_setpoint"]}

    @staticmethod
    def command_registers(holding):
        """The command registers of the bench's first SYNC (nothing sent yet: Mode 0)."""
        return {**holding, "command": MODE_ACTION[0]}

    def sync(self):
        """One SYNC, and the telemetry set that answers it: {frame signal name: physical value}."""
        msg = self._can.Message(arbitration_id=SYNC_ID, data=b"", is_extended_id=False)
        try:
            self.bus.send(msg, timeout=self.timeout_s)
        except self._can.CanError as e:
            raise BenchError(f"CAN {self.where}: send of SYNC: {e}") from e
        return self.receive_set()

    def receive_set(self):
        """Telemetry frames up to Output, which ends a set (docs/protocols.md)."""
        values = {}
        deadline = time.monotonic() + self.timeout_s  # a hang guard, not a measurement
        while True:
            left = deadline - time.monotonic()
            msg = self.bus.recv(timeout=max(left, 0)) if left > 0 else None
            if msg is None:
                raise BenchError(f"CAN {self.where}: no complete telemetry set within {self.timeout_s:g} s "
                                 f"(got {sorted(values)})")
            name = self.by_id.get(msg.arbitration_id)
            if name is None:
                continue
            values.update(self.decoders[name](msg.data))
            if name == "Output":
                return values
