"""The bench's SDO client (canopen_sdo.py) without a bus: the exact request frames of CiA 301
7.2.4.3 for expedited and segmented transfers, the server's answers as a CiA 301 server writes
them (scripted here byte by byte), and every way a transfer ends in an abort: the server's
(decoded with its CiA 301 name) and the client's own (toggle bit, unknown command specifier,
size, timeout), which it sends before raising."""
import os
import re
import struct

import pytest

from swum_bench.canopen_eds import Eds
from swum_bench.canopen_sdo import ABORT_NAMES, SdoAbort, SdoClient, abort_name

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
NODE = 4
REQUEST, RESPONSE = 0x604, 0x584


class ScriptedBus:
    """Answers each request the client sends with the next scripted answer (a list of frames,
    [] for silence)."""

    def __init__(self, *answers):
        self.answers = list(answers)
        self.sent = []
        self.queue = []

    def send(self, can_id, data):
        self.sent.append((can_id, bytes(data)))
        if data[0] >> 5 != 4 and self.answers:  # a client's abort is not answered
            self.queue.extend(self.answers.pop(0))

    def receive(self, timeout_s):
        return self.queue.pop(0) if self.queue else None


def h(text):
    return bytes.fromhex(text)


def client(bus, timeout_s=0.05):
    return SdoClient(bus, NODE, REQUEST, RESPONSE, timeout_s=timeout_s)


@pytest.fixture(scope="module")
def eds():
    return Eds(os.path.join(REPO, "config", "swum.eds"), NODE)


def test_expedited_upload(eds):
    bus = ScriptedBus([(RESPONSE, h("4b41600037020000"))])  # scs 2, n = 2, e, s: two bytes 0x0237
    assert client(bus).read(eds[0x6041, 0]) == 0x0237
    assert bus.sent == [(REQUEST, h("4041600000000000"))]


def test_expedited_upload_without_size_takes_four_bytes():
    bus = ScriptedBus([(RESPONSE, h("420010000a000000"))])  # e, no s
    assert client(bus).upload(0x1000, 0) == h("0a000000")


@pytest.mark.parametrize("index, value, frame", [
    (0x6040, 0x0F, "2b4060000f000000"),   # 2 bytes: n = 2
    (0x6060, -1, "2f606000ff000000"),     # 1 byte: n = 3
    (0x2001, 40000000, "23012000005a6202"),  # 4 bytes: n = 0
])
def test_expedited_download(eds, index, value, frame):
    bus = ScriptedBus([(RESPONSE, bytes([0x60]) + h(frame)[1:4] + bytes(4))])
    client(bus).write(eds[index, 0], value)
    assert bus.sent == [(REQUEST, h(frame))]


def test_segmented_upload_of_the_device_name(eds):
    name = eds[0x1008, 0].default.encode()
    assert len(name) == 53
    answers = [[(RESPONSE, h("4108100035000000"))]]  # scs 2, s: size 53
    for k, start in enumerate(range(0, 53, 7)):
        chunk = name[start:start + 7]
        last = start + 7 >= 53
        answers.append([(RESPONSE, bytes([(k % 2) << 4 | (7 - len(chunk)) << 1 | last]) + chunk.ljust(7, b"\0"))])
    bus = ScriptedBus(*answers)
    assert client(bus).read(eds[0x1008, 0]) == eds[0x1008, 0].default
    assert bus.sent[0] == (REQUEST, h("4008100000000000"))
    assert [d for _, d in bus.sent[1:]] == [bytes([0x60 | (k % 2) << 4]) + bytes(7) for k in range(8)]


def test_segmented_download():
    data = bytes(range(1, 10))  # 9 bytes: one full segment, one of 2
    bus = ScriptedBus([(RESPONSE, h("6008100000000000"))], [(RESPONSE, h("2000000000000000"))],
                      [(RESPONSE, h("3000000000000000"))])
    client(bus).download(0x1008, 0, data)
    assert [d for _, d in bus.sent] == [h("2108100009000000"), h("00") + data[:7],
                                        bytes([0x10 | 5 << 1 | 1]) + data[7:] + bytes(5)]


def test_empty_download_is_one_empty_last_segment():
    bus = ScriptedBus([(RESPONSE, h("6008100000000000"))], [(RESPONSE, h("2000000000000000"))])
    client(bus).download(0x1008, 0, b"")
    assert [d for _, d in bus.sent] == [h("2108100000000000"), bytes([7 << 1 | 1]) + bytes(7)]


def test_server_abort_is_raised_with_its_name(eds):
    bus = ScriptedBus([(RESPONSE, h("8001200131000906"))])
    with pytest.raises(SdoAbort, match=r"^SDO 0x2001 sub 0: node 4 aborted with 0x06090031 \(value of parameter "
                                       r"written too high\)$") as e:
        client(bus).write(eds[0x2001, 0], 40000000)
    assert (e.value.code, e.value.by_server) == (0x06090031, True)
    assert len(bus.sent) == 1  # a server's abort is not answered


def _client_abort(bus, code):
    assert bus.sent[-1][0] == REQUEST and bus.sent[-1][1][0] == 0x80
    assert struct.unpack_from("<I", bus.sent[-1][1], 4)[0] == code


@pytest.mark.parametrize("answers, code, name", [
    ([[]], 0x05040000, "SDO protocol timed out"),
    ([[(RESPONSE, h("6008100000000000"))]], 0x05040001, "client/server command specifier not valid or unknown"),
    ([[(RESPONSE, h("4b41600100000000"))]], 0x08000000, "general error"),       # another sub-index answered
    ([[(RESPONSE, h("4b416000370200"))]], 0x08000000, "general error"),          # 7 bytes: not an SDO frame
    ([[(RESPONSE, h("410810000a000000"))], [(RESPONSE, h("1000000000000000"))]], 0x05030000,
     "toggle bit not alternated"),
    ([[(RESPONSE, h("410810000a000000"))], [(RESPONSE, h("0161626364656667"))]], 0x06070010,
     "data type does not match, length of service parameter does not match"),  # 7 of 10, then "no more"
    ([[(RESPONSE, h("4108100001000100"))]], 0x05040005, "out of memory"),       # 64 KiB + 1 announced
])
def test_client_aborts_a_transfer_the_server_gets_wrong(answers, code, name):
    bus = ScriptedBus(*answers)
    index = 0x6041 if answers[0] and answers[0][0][1][0] == 0x4B else 0x1008
    expected = f"the bench aborted (to node {NODE}) with 0x{code:08X} ({name})"
    with pytest.raises(SdoAbort, match=re.escape(expected)) as e:
        client(bus).upload(index, 0)
    assert e.value.by_server is False
    _client_abort(bus, code)


def test_segmented_download_toggle_error_is_aborted():
    bus = ScriptedBus([(RESPONSE, h("6008100000000000"))], [(RESPONSE, h("3000000000000000"))])
    with pytest.raises(SdoAbort, match="0x05030000"):
        client(bus).download(0x1008, 0, bytes(9))
    _client_abort(bus, 0x05030000)


def test_frames_of_other_identifiers_are_passed_over(eds):
    bus = ScriptedBus([(0x184, h("3702")), (RESPONSE, h("4b41600037020000"))])
    assert client(bus).read(eds[0x6041, 0]) == 0x0237


def test_every_abort_code_docs_canopen_names_has_its_cia301_name():
    with open(os.path.join(REPO, "docs", "canopen.md")) as f:
        cited = {int(c, 16) for c in re.findall(r"\b0x0[5-8][0-9A-F]{6}\b", f.read())}
    assert cited and cited <= set(ABORT_NAMES), sorted(hex(c) for c in cited - set(ABORT_NAMES))
    assert abort_name(0x12345678) == "not a CiA 301 abort code"
