#!/usr/bin/python3
"""swum-emu as a Modbus RTU slave on a pseudo-terminal: this script is the master and builds the
RTU frames itself (unit id, PDU, CRC-16/MODBUS), independently of libmodbus. Checks reads, a
write, exceptions, that frames for another unit and frames with a bad CRC get no answer, and
that the emulator keeps serving afterwards."""
import os
import select
import struct
import sys
import termios
import tty

from emu_harness import Emulator, RegisterMap

MAP = RegisterMap()


def crc16(data):
    crc = 0xFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return struct.pack("<H", crc)


class Master:
    def __init__(self, fd):
        self.fd = fd

    def transact(self, unit, pdu, expect_reply=True, raw=None):
        frame = raw if raw is not None else bytes([unit]) + pdu + crc16(bytes([unit]) + pdu)
        os.write(self.fd, frame)
        reply = b""
        # First byte: generous (loaded machine); then the frame ends at a silence.
        first_wait = 10.0 if expect_reply else 0.3
        while True:
            ready, _, _ = select.select([self.fd], [], [], first_wait if not reply else 0.1)
            if not ready:
                break
            reply += os.read(self.fd, 512)
        if not expect_reply:
            assert reply == b"", reply.hex()
            return None
        assert len(reply) >= 5 and crc16(reply[:-2]) == reply[-2:], reply.hex()
        assert reply[0] == unit
        return reply[1:-2]


def main():
    master, slave = os.openpty()
    tty.setraw(master)
    path = os.ttyname(slave)
    with Emulator("--watchdog-ms", "0", "--modbus-unit", "7", modbus=f"rtu:{path}:115200") as emu:
        m = Master(master)
        # Read all input registers.
        pdu = m.transact(7, struct.pack(">BHH", 4, 0, MAP.input_count))
        assert pdu[0] == 4 and pdu[1] == 2 * MAP.input_count, pdu.hex()
        regs = list(struct.unpack(f">{MAP.input_count}H", pdu[2:]))
        assert MAP.decode_inputs(regs)["state"] == 0
        # Write 400 V, read it back (applied at the next tick).
        addr = MAP.holding["amplitude_setpoint"]["address"]
        assert m.transact(7, struct.pack(">BHH", 6, addr, 4000)) == struct.pack(">BHH", 6, addr, 4000)
        for _ in range(100):
            pdu = m.transact(7, struct.pack(">BHH", 3, addr, 1))
            if struct.unpack(">H", pdu[2:4])[0] == 4000:
                break
        else:
            raise AssertionError("write not applied")
        # Unsupported functions: exception 01 under the function code with its top bit set, also
        # for codes that have it already (128-255; libmodbus alone would wrap 0x84 to 0x04).
        for function in (0x2B, 0x80, 0x84, 0xFF):
            assert m.transact(7, bytes([function])) == bytes([function | 0x80, 1]), hex(function)
        # Exceptions: illegal address, illegal value.
        assert m.transact(7, struct.pack(">BHH", 4, 200, 1)) == bytes([0x84, 2])
        assert m.transact(7, struct.pack(">BHH", 6, addr, 7000)) == bytes([0x86, 3])
        # Another unit, a bad CRC: no answer at all.
        m.transact(8, struct.pack(">BHH", 4, 0, 1), expect_reply=False)
        m.transact(7, None, expect_reply=False, raw=bytes([7, 4, 0, 0, 0, 1, 0x12, 0x34]))
        # Still serving. After a bad frame the emulator discards bytes until the line has been
        # silent for a few ms (docs/emulator.md), so a request that arrives in that window is
        # dropped like on a real bus: retry as a real master would, with a fresh timeout each time.
        pdu = None
        for _ in range(3):
            try:
                pdu = m.transact(7, struct.pack(">BHH", 4, MAP.input["last_reject_reason"]["address"], 1))
                break
            except AssertionError:
                continue
        assert pdu is not None, "no answer after 3 attempts"

        assert struct.unpack(">H", pdu[2:4])[0] == MAP.reasons["amplitude_out_of_range"], pdu.hex()
        assert emu.stop() == 0
    os.close(master)
    os.close(slave)
    print("PASS rtu")


if __name__ == "__main__":
    sys.exit(main())
