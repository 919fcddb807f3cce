"""The bench's Modbus TCP client (pymodbus): one control cycle is one FC16 of holding registers
0..10 (command, set-points, slews, advance) and one FC04 of every input register, as
docs/protocols.md prescribes for lockstep."""
import sys
import types

try:  # pymodbus 3.0 imports its serial client eagerly; tools/setup installs python3-serial-asyncio
    import serial_asyncio  # noqa: F401
except ImportError:  # a machine without it still runs TCP
    sys.modules["serial_asyncio"] = types.SimpleNamespace(create_serial_connection=None)

from pymodbus.client import ModbusTcpClient  # noqa: E402

from .emulator import BenchError  # noqa: E402



class CommandRefused(BenchError):
    """swum-emu answered a cycle's write with an exception: the command (a set-point out of
    range, an unknown action...) was refused and no tick ran."""


class ModbusLink:
    def __init__(self, host, port, register_map, unit=1, timeout_s=60.0):
        self.map = register_map
        self.unit = unit
        self.where = f"tcp://{host}:{port}"
        # retries=0: a retried advance would step the emulator twice.
        self.client = ModbusTcpClient(host, port=port, timeout=timeout_s, retries=0, retry_on_empty=False)
        if not self.client.connect():
            raise BenchError(f"Modbus {self.where}: cannot connect")

    def close(self):
        self.client.close()

    def read_inputs(self):
        """{register name: physical value} of one FC04 read of the whole input table."""
        what = f"read of input registers 0..{self.map.input_count - 1}"
        try:
            rr = self.client.read_input_registers(0, self.map.input_count, slave=self.unit)
        except Exception as e:  # pymodbus raises its own ConnectionException / ModbusIOException
            raise BenchError(f"Modbus {self.where}: {what}: {e}") from e
        if rr.isError() or len(getattr(rr, "registers", [])) != self.map.input_count:
            code = getattr(rr, "exception_code", None)
            raise BenchError(f"Modbus {self.where}: {what}: " + (f"exception {code:02d}" if code else str(rr)))
        return self.map.decode_inputs(rr.registers)

    def write_cycle(self, holding_values):
        """One FC16 of holding registers 0..10 ({name: physical value}, 'advance' in ticks)."""
        words = self.map.encode_holding(holding_values)
        what = f"write of holding registers 0..{len(words) - 1}"
        try:
            wr = self.client.write_registers(0, words, slave=self.unit)
        except Exception as e:
            raise BenchError(f"Modbus {self.where}: {what}: {e}") from e
        if wr.isError():
            code = getattr(wr, "exception_code", None)
            if code != 3:  # 04 the emulator is stopping, 06 its queue is full: not the command's fault
                raise BenchError(f"Modbus {self.where}: {what}: " + (f"exception {code:02d}" if code else str(wr)))
            reason = int(self.read_inputs()["last_reject_reason"])  # why (input register 3)
            raise CommandRefused(f"swum-emu refused the command ({', '.join(f'{k}={v:g}' for k, v in holding_values.items())}) "
                                 f"with exception {code:02d}, reject reason {reason} {self.map.reasons.get(reason, '?')}")

    def exchange(self, holding_values):
        """Set-points + advance, then the state after the ticks: two round trips."""
        self.write_cycle(holding_values)
        return self.read_inputs()
