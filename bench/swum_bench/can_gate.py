"""The gate between an external controller process and swum-emu in lockstep over CAN.

The controller is on its own bus (vcan1 in the guest tier), swum-emu on another (vcan0); the
bench bridges them. The controller's Command and AuxCommand frames cross at once, in their
order; its SYNC waits until the bench lets one cycle through, then crosses, and the telemetry
set that answers it (up to Output) comes back to the controller's bus once the bench has
recorded it. So the bench owns emulated time over CAN as over Modbus (modbus_gate.py), and the
telemetry it records is exactly what the controller received.

The gate relays frames as they are, so it reads and writes them on Python's own SocketCAN
sockets (socket.AF_CAN) rather than through python-can, whose Message objects, debug logging
and select per call cost more than the relay itself: about 20 frames cross per cycle, and in
the TCG guest the gate's Python was most of a cycle's time (docs/testing.md)."""
import queue
import socket
import struct
import threading
import time

from .can_link import MODE_ACTION, SYNC_ID, TELEMETRY, frame_decoder, load_dbc
from .emulator import BenchError

CAN_FRAME = struct.Struct("=IB3x8s")  # struct can_frame (linux/can.h): can_id, len, padding, data
_CAN_EFF_FLAG, _CAN_RTR_FLAG = 0x80000000, 0x40000000
_POLL_S = 0.2  # how often a blocked receive looks at the stop flag


def open_raw(interface, ids):
    """A raw CAN socket on `interface` that receives only standard data frames with these ids."""
    sock = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    try:
        mask = 0x7FF | _CAN_EFF_FLAG | _CAN_RTR_FLAG
        sock.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER,
                        b"".join(struct.pack("=II", i, mask) for i in ids))
        sock.bind((interface,))
        sock.settimeout(_POLL_S)
    except OSError:
        sock.close()
        raise
    return sock


def receive_raw(sock):
    """(can_id, data, the frame's bytes), or None after _POLL_S without a frame."""
    try:
        frame = sock.recv(CAN_FRAME.size)
    except TimeoutError:
        return None
    if len(frame) != CAN_FRAME.size:
        raise BenchError(f"CAN gate: a frame of {len(frame)} bytes, not a classic CAN frame")
    can_id, length, data = CAN_FRAME.unpack(frame)
    return can_id, data[:length], frame


class CanGate:
    def __init__(self, controller_interface, emulator_interface, node, data_dir, on_cycle, timeout_s=120.0):
        """on_cycle(telemetry_values, command_values) runs on the gate's thread after each set."""
        self.endpoint = f"{controller_interface}:{node}"
        self.on_cycle = on_cycle
        self.timeout_s = timeout_s
        self.events = queue.Queue()
        self.command = {}
        self._permits = threading.Semaphore(0)
        self._stop = threading.Event()
        self._opened = threading.Event()  # closing: SYNCs pass unheld and unrecorded
        self._idle = 0           # receive timeouts without a frame from the controller's bus
        self._exit_mark = None
        dbc = load_dbc(data_dir)
        frames = {f.name: f for f in dbc.frames}
        self._decoders = {name: frame_decoder(f) for name, f in frames.items()}
        ids = {name: f.arbitration_id.id - 1 + node for name, f in frames.items() if name != "Sync"}
        self._command_ids = {ids["Command"]: "Command", ids["AuxCommand"]: "AuxCommand"}
        self._telemetry_ids = {ids[name]: name for name in TELEMETRY}
        self._ctrl = self._emu = None
        try:
            self._ctrl = open_raw(controller_interface, [SYNC_ID, *self._command_ids])
            self._emu = open_raw(emulator_interface, list(self._telemetry_ids))
        except OSError as e:
            if self._ctrl is not None:
                self._ctrl.close()
            raise BenchError(f"CAN gate {controller_interface} <-> {emulator_interface}: cannot open: "
                             f"{e.strerror or e}") from e
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def quiet_after_exit(self):
        """After the controller exited: True once a whole receive timeout has passed without a
        frame from it (what it sent before exiting has crossed by then)."""
        if self._exit_mark is None:
            self._exit_mark = self._idle
        return self._idle >= self._exit_mark + 2

    def release(self):
        self._permits.release()

    def open(self):
        """From now on SYNCs pass without waiting and without being recorded (closing)."""
        self._opened.set()

    def close(self):
        self._stop.set()
        self._thread.join(5)
        self._ctrl.close()
        self._emu.close()

    def _send(self, sock, frame, where):
        """Sends the frame's bytes; a full queue is waited for up to the hang guard."""
        deadline = time.monotonic() + self.timeout_s
        while True:
            try:
                sock.send(frame)
                return
            except TimeoutError:
                if self._stop.is_set():
                    return  # closing: the frame no longer matters
                if time.monotonic() > deadline:
                    raise BenchError(f"CAN gate: the {where} bus took no frame for {self.timeout_s:g} s")

    def _run(self):
        try:
            while not self._stop.is_set():
                received = receive_raw(self._ctrl)
                if received is None:
                    self._idle += 1
                    continue
                can_id, data, frame = received
                if can_id != SYNC_ID:
                    self._send(self._emu, frame, "emulator's")
                    name = self._command_ids[can_id]
                    if name == "Command" and len(data) == 8:
                        self.command = self._decoders[name](data)
                    continue
                if not self._valid_sync(data):  # refused by the emulator, never answered: not a cycle
                    self._send(self._emu, frame, "emulator's")
                    continue
                while not (self._opened.is_set() or self._permits.acquire(timeout=_POLL_S)):
                    if self._stop.is_set():
                        return
                self._send(self._emu, frame, "emulator's")
                self._answer(record=not self._opened.is_set())
        except BenchError as e:
            if not self._stop.is_set():
                self.events.put(("error", str(e)))
        except Exception as e:  # OSError from a socket, above all; the bench must hear of it
            if not self._stop.is_set():
                self.events.put(("error", f"CAN gate: {type(e).__name__}: {e}"))

    @staticmethod
    def _valid_sync(data):
        """DLC 0, or 1 with a counter 1..240 (docs/protocols.md); anything else is refused."""
        return len(data) == 0 or (len(data) == 1 and 1 <= data[0] <= 240)

    def _answer(self, record=True):
        values = {}
        deadline = time.monotonic() + self.timeout_s  # a hang guard, not a measurement
        while True:
            left = deadline - time.monotonic()
            received = receive_raw(self._emu) if left > 0 and not self._stop.is_set() else None
            if received is None and left > 0 and not self._stop.is_set():
                continue
            if received is None:
                raise BenchError(f"CAN gate: no telemetry set answered the SYNC within {self.timeout_s:g} s "
                                 f"(got {sorted(values)})")
            can_id, data, frame = received
            name = self._telemetry_ids.get(can_id)
            if name is not None:
                values.update(self._decoders[name](data))
            if name == "Output" and not record:
                self._send(self._ctrl, frame, "controller's")
                return
            if name == "Output":
                command = {"command": MODE_ACTION.get(int(self.command.get("Mode", 0)), -1),  # -1: Mode 3
                           "frequency_setpoint": self.command.get("Frequency", 0.0),
                           "amplitude_setpoint": self.command.get("Amplitude", 0.0),
                           "phase_setpoint": self.command.get("Phase", 0.0)}
                self.on_cycle(values, command)
                self._send(self._ctrl, frame, "controller's")
                self.events.put(("cycle", None))
                return
            self._send(self._ctrl, frame, "controller's")
