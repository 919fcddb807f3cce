"""Unit tests of the Modbus gate's framing helpers (swum_bench/modbus_gate.py), without an emulator:
written_registers() on FC06 / FC16 requests (well-formed and malformed) and on other function
codes; read_frame() over a socket.socketpair() and over a socket that returns a few bytes per
recv(): a whole frame, frames split across sends, frames back to back, end of stream (before,
inside the header, inside the body) and bad MBAP headers (BenchError)."""
import socket
import struct

import pytest

from swum_bench import BenchError
from swum_bench.modbus_gate import ADVANCE, read_frame, written_registers


def fc16(start, values, count=None, nbytes=None):
    count = len(values) if count is None else count
    nbytes = 2 * len(values) if nbytes is None else nbytes
    return struct.pack(">BHHB", 0x10, start, count, nbytes) + struct.pack(f">{len(values)}H", *values)


def mbap(pdu, transaction=0x1234, protocol=0, unit=1, length=None):
    length = len(pdu) + 1 if length is None else length
    return struct.pack(">HHHB", transaction, protocol, length, unit) + pdu


# ---- written_registers -----------------------------------------------------------------------------

def test_fc06():
    assert written_registers(bytes([0x06, 0x00, 0x0A, 0x00, 0x0A])) == {10: 10}
    assert written_registers(bytes([0x06, 0x12, 0x34, 0xFF, 0xFF])) == {0x1234: 0xFFFF}


@pytest.mark.parametrize("pdu", [bytes([0x06, 0x00, 0x0A, 0x00]), bytes([0x06, 0x00, 0x0A, 0x00, 0x0A, 0x00])])
def test_fc06_wrong_length(pdu):
    assert written_registers(pdu) == {}


def test_fc16():
    words = [1, 0x0262, 0x5A00, 1500, 0xDCD8, 0xF63C, 0x000F, 0x4240, 0x0001, 0x86A0, 10]
    assert written_registers(fc16(0, words)) == dict(enumerate(words))
    assert written_registers(fc16(ADVANCE, [7])) == {ADVANCE: 7}
    assert written_registers(fc16(3, [0xAAAA, 0x5555])) == {3: 0xAAAA, 4: 0x5555}


def test_fc16_zero_registers():
    assert written_registers(fc16(0, [])) == {}


@pytest.mark.parametrize("pdu", [
    fc16(0, [1, 2, 3], nbytes=4),            # byte count disagrees with the quantity
    fc16(0, [1, 2, 3], nbytes=7),
    fc16(0, [1, 2], count=3),                # quantity disagrees with the data
    fc16(0, [1, 2, 3])[:-1],                 # truncated data
    fc16(0, [1, 2, 3]) + b"\x00\x00",        # trailing bytes
    bytes([0x10, 0x00, 0x00, 0x00]),         # truncated header
])
def test_fc16_malformed(pdu):
    assert written_registers(pdu) == {}


@pytest.mark.parametrize("pdu", [
    b"",
    bytes([0x03, 0x00, 0x00, 0x00, 0x0B]),        # read holding registers
    bytes([0x04, 0x00, 0x00, 0x00, 0x2D]),        # read input registers
    bytes([0x01, 0x00, 0x00, 0x00, 0x01]),        # read coils
    bytes([0x05, 0x00, 0x0A, 0xFF, 0x00]),        # write single coil: not a register
    bytes([0x86, 0x02]),                          # exception reply to FC06
    bytes([0x90, 0x03]),                          # exception reply to FC16
    bytes([0x17, 0x00, 0x00, 0x00, 0x01, 0x00, 0x0A, 0x00, 0x01, 0x02, 0x00, 0x07]),  # FC23: not supported
])
def test_other_function_codes(pdu):
    assert written_registers(pdu) == {}


# ---- read_frame over a socket pair -------------------------------------------------------------------

@pytest.fixture
def pair():
    a, b = socket.socketpair()
    b.settimeout(10.0)  # a hang guard only: every test sends all its bytes before reading
    yield a, b
    a.close()
    b.close()


def test_whole_frame(pair):
    a, b = pair
    frame = mbap(fc16(ADVANCE, [10]))
    a.sendall(frame)
    assert read_frame(b) == frame


def test_frame_split_across_sends(pair):
    a, b = pair
    frame = mbap(fc16(0, list(range(11))))
    for piece in (frame[:3], frame[3:7], frame[7:8], frame[8:20], frame[20:]):
        a.sendall(piece)
    assert read_frame(b) == frame


def test_frames_back_to_back(pair):
    a, b = pair
    first = mbap(bytes([0x06, 0x00, 0x0A, 0x00, 0x01]), transaction=1)
    second = mbap(bytes([0x04, 0x00, 0x00, 0x00, 0x2D]), transaction=2)
    a.sendall(first + second)
    a.close()
    assert read_frame(b) == first
    assert read_frame(b) == second
    assert read_frame(b) is None


def test_smallest_and_largest_length(pair):
    a, b = pair
    smallest = mbap(b"\x03")                        # length 2: unit id + function code
    largest = mbap(bytes([0x10]) + bytes(252))      # length 254
    a.sendall(smallest + largest)
    assert read_frame(b) == smallest
    assert read_frame(b) == largest


def test_end_of_stream(pair):
    a, b = pair
    a.close()
    assert read_frame(b) is None


def test_end_of_stream_inside_header(pair):
    a, b = pair
    a.sendall(mbap(fc16(ADVANCE, [10]))[:5])
    a.close()
    assert read_frame(b) is None


def test_end_of_stream_inside_body(pair):
    a, b = pair
    a.sendall(mbap(fc16(ADVANCE, [10]))[:-1])
    a.close()
    assert read_frame(b) is None


def test_bad_protocol_id(pair):
    a, b = pair
    a.sendall(mbap(bytes([0x03, 0x00, 0x00, 0x00, 0x01]), protocol=1))
    with pytest.raises(BenchError, match=r"Modbus gate: bad MBAP header 12340001000601 \(protocol 1, length 6\)"):
        read_frame(b)


@pytest.mark.parametrize("length", [0, 1, 255, 0xFFFF])
def test_bad_length(pair, length):
    a, b = pair
    a.sendall(mbap(b"\x03", length=length))
    with pytest.raises(BenchError, match=rf"bad MBAP header .*\(protocol 0, length {length}\)"):
        read_frame(b)


def test_bench_error_is_not_a_usage_error():
    from swum_bench import BenchUsageError
    assert issubclass(BenchError, RuntimeError)
    assert not issubclass(BenchError, BenchUsageError)


# ---- read_frame over a trickling socket ----------------------------------------------------------------

class Trickle:
    """A socket stand-in whose recv() returns at most `chunk` bytes, then b"" at the end."""

    def __init__(self, data, chunk=1):
        self.data = data
        self.chunk = chunk
        self.calls = 0

    def recv(self, n):
        self.calls += 1
        assert n > 0
        out, self.data = self.data[:min(n, self.chunk)], self.data[min(n, self.chunk):]
        return out


@pytest.mark.parametrize("chunk", [1, 2, 3, 7, 100])
def test_trickling_frame(chunk):
    frame = mbap(fc16(0, list(range(11))))
    sock = Trickle(frame + frame, chunk)
    assert read_frame(sock) == frame
    assert read_frame(sock) == frame
    assert read_frame(sock) is None


def test_read_frame_does_not_read_past_the_frame():
    frame = mbap(bytes([0x06, 0x00, 0x0A, 0x00, 0x01]))
    sock = Trickle(frame + b"NEXT", chunk=1000)
    assert read_frame(sock) == frame
    assert sock.data == b"NEXT"
