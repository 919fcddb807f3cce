"""The gate between an external controller process and swum-emu in lockstep over CAN.

The controller is on its own bus (vcan1 in the guest tier), swum-emu on another (vcan0); the
bench bridges them. The controller's Command and AuxCommand frames cross at once, in their
order; its SYNC waits until the bench lets one cycle through, then crosses, and the telemetry
set that answers it (up to Output) comes back to the controller's bus once the bench has
recorded it. So the bench owns emulated time over CAN as over Modbus (modbus_gate.py), and the
telemetry it records is exactly what the controller received."""
import queue
import threading
import time

from .can_link import MODE_ACTION, SYNC_ID, TELEMETRY, load_dbc
from .emulator import BenchError


class CanGate:
    def __init__(self, controller_interface, emulator_interface, node, source_dir, on_cycle, timeout_s=120.0):
        """on_cycle(telemetry_values, command_values) runs on the gate's thread after each set."""
        import can
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
        dbc = load_dbc(source_dir)
        self._frames = {f.name: f for f in dbc.frames}
        ids = {name: f.arbitration_id.id - 1 + node for name, f in self._frames.items() if name != "Sync"}
        self._command_ids = {ids["Command"]: "Command", ids["AuxCommand"]: "AuxCommand"}
        self._telemetry_ids = {ids[name]: name for name in TELEMETRY}
        try:
            self._ctrl = can.interface.Bus(channel=controller_interface, interface="socketcan")
            self._emu = can.interface.Bus(channel=emulator_interface, interface="socketcan")
        except (OSError, can.CanError) as e:
            raise BenchError(f"CAN gate {controller_interface} <-> {emulator_interface}: cannot open: {e}") from e
        self._ctrl.set_filters([{"can_id": i, "can_mask": 0x7FF} for i in [SYNC_ID, *self._command_ids]])
        self._emu.set_filters([{"can_id": i, "can_mask": 0x7FF} for i in self._telemetry_ids])
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
        self._ctrl.shutdown()
        self._emu.shutdown()

    def _decode(self, name, data):
        return {k: float(v.phys_value) for k, v in self._frames[name].decode(bytearray(data)).items()}

    def _run(self):
        try:
            while not self._stop.is_set():
                msg = self._ctrl.recv(timeout=0.2)
                if msg is None:
                    self._idle += 1
                    continue
                if msg.arbitration_id != SYNC_ID:
                    self._emu.send(msg)
                    name = self._command_ids[msg.arbitration_id]
                    if name == "Command" and len(msg.data) == 8:
                        self.command = self._decode(name, msg.data)
                    continue
                if not self._valid_sync(msg):  # refused by the emulator, never answered: not a cycle
                    self._emu.send(msg)
                    continue
                while not (self._opened.is_set() or self._permits.acquire(timeout=0.2)):
                    if self._stop.is_set():
                        return
                self._emu.send(msg)
                self._answer(record=not self._opened.is_set())
        except BenchError as e:
            self.events.put(("error", str(e)))
        except Exception as e:  # python-can raises CanError / OSError; the bench must hear of it
            if not self._stop.is_set():
                self.events.put(("error", f"CAN gate: {type(e).__name__}: {e}"))

    @staticmethod
    def _valid_sync(msg):
        """DLC 0, or 1 with a counter 1..240 (docs/protocols.md); anything else is refused."""
        return len(msg.data) == 0 or (len(msg.data) == 1 and 1 <= msg.data[0] <= 240)

    def _answer(self, record=True):
        values = {}
        deadline = time.monotonic() + self.timeout_s  # a hang guard, not a measurement
        while True:
            left = deadline - time.monotonic()
            msg = self._emu.recv(timeout=min(left, 0.2)) if left > 0 and not self._stop.is_set() else None
            if msg is None and left > 0 and not self._stop.is_set():
                continue
            if msg is None:
                raise BenchError(f"CAN gate: no telemetry set answered the SYNC within {self.timeout_s:g} s "
                                 f"(got {sorted(values)})")
            name = self._telemetry_ids.get(msg.arbitration_id)
            if name is not None:
                values.update(self._decode(name, msg.data))
            if name == "Output" and not record:
                self._ctrl.send(msg)
                return
            if name == "Output":
                command = {"command": MODE_ACTION.get(int(self.command.get("Mode", 0)), -1),  # -1: Mode 3
                           "frequency_setpoint": self.command.get("Frequency", 0.0),
                           "amplitude_setpoint": self.command.get("Amplitude", 0.0),
                           "phase_setpoint": self.command.get("Phase", 0.0)}
                self.on_cycle(values, command)
                self._ctrl.send(msg)
                self.events.put(("cycle", None))
                return
            self._ctrl.send(msg)
