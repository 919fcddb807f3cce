"""The bench's CAN client without a bus: what it encodes (config/swum.dbc through canmatrix, the
CRC written from docs/protocols.md), the mode it sends for a keep-alive, and set-points that do
not fit their signals."""
import os

import pytest

from swum_bench import can_link
from swum_bench.can_link import CanLink, crc8_sae_j1850

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
DATA = os.path.join(REPO, "config")  # the data directory of the checkout


class Recorder(CanLink):
    """A CanLink whose frames go to a list instead of a socket."""

    def __init__(self):  # noqa: the bus is the list
        self.dbc = can_link.load_dbc(DATA)
        self.frames = {f.name: f for f in self.dbc.frames}
        self.ids = {name: f.arbitration_id.id for name, f in self.frames.items() if name != "Sync"}
        self._alive = {"Command": 0, "AuxCommand": 0}
        self._aux = None
        self._rejects = None
        self._mode = 0
        self.sent = []

    def _send(self, name, raw):
        self.sent.append((name, dict(raw)))


def command(action, amplitude_v=100.0, frequency_hz=40000.0, phase_deg=90.0, load_n=0.0):
    return {"command": action, "frequency_setpoint": frequency_hz, "amplitude_setpoint": amplitude_v,
            "phase_setpoint": phase_deg, "load_force": load_n, "frequency_slew": 1e6, "amplitude_slew": 1e5}


def sample(state, rejects=0):
    return {"state": state, "reject_count": rejects}


def modes(link):
    return [raw["Mode"] for name, raw in link.sent if name == "Command"]


def test_crc_check_value():
    # CRC-8/SAE-J1850's check value over "123456789" is 0x4B; the identifier 0x3231 sent
    # little-endian is "12", so this covers the identifier bytes and their order too.
    assert crc8_sae_j1850(0x3231, b"3456789") == 0x4B


def test_keep_alive_repeats_the_commanded_mode_not_the_delayed_state():
    link = Recorder()
    link.send_command(command(1), sample(0))          # enable
    link.send_command(command(0), sample(0))          # the SYNC's state still says disabled
    link.send_command(command(0), sample(1))
    link.send_command(command(2), sample(1))          # disable
    link.send_command(command(0), sample(1))          # the state still says enabled
    assert modes(link) == [1, 1, 1, 0, 0]


def test_keep_alive_in_fault_and_after_a_reset_is_mode_0():
    link = Recorder()
    link.send_command(command(1), sample(0))
    link.send_command(command(0), sample(2))          # fault: the drive is off
    link.send_command(command(3), sample(2))          # reset fault (Mode 2)
    link.send_command(command(0), sample(0))          # after a reset: disabled
    assert modes(link) == [1, 0, 2, 0]


def test_command_signal_is_the_mode_sent():
    link = Recorder()
    assert link.send_command(command(1), None)["command"] == 1
    assert link.send_command(command(0), sample(1))["command"] == 1
    assert link.send_command(command(2), sample(1))["command"] == 2
    assert link.send_command(command(3), sample(2))["command"] == 3


def test_aux_command_when_changed_or_after_a_reject():
    link = Recorder()
    link.send_command(command(1), sample(0, rejects=0))
    link.send_command(command(0), sample(1, rejects=0))
    link.send_command(command(0, load_n=1.0), sample(1, rejects=0))
    link.send_command(command(0, load_n=1.0), sample(1, rejects=1))  # something was rejected: resend
    link.send_command(command(0, load_n=1.0), sample(1, rejects=1))
    assert [name for name, _ in link.sent].count("AuxCommand") == 3


@pytest.mark.parametrize("fields, pattern", [
    (dict(amplitude_v=-5.0), r"Command.Amplitude: -5.0 does not fit the signal \(12 bits\)"),
    (dict(amplitude_v=2000.0), r"Command.Amplitude: 2000.0 does not fit"),
    (dict(frequency_hz=200000.0), r"Command.Frequency: 200000.0 does not fit the signal \(20 bits\)"),
    (dict(phase_deg=-300.0), r"Command.Phase: -300.0 does not fit"),
    (dict(frequency_hz=float("nan")), r"Command.Frequency: nan is not a finite number"),
    (dict(load_n=40.0), r"AuxCommand.Load: 40.0 does not fit"),
])
def test_set_points_that_do_not_fit_are_refused_not_wrapped(fields, pattern):
    link = Recorder()
    with pytest.raises(ValueError, match=pattern):
        link.send_command(command(1, **fields), None)
    assert link.sent == []


def test_set_points_round_to_the_nearest_count_like_modbus():
    link = Recorder()
    link.send_command(command(1, amplitude_v=100.2), None)  # 400.8 counts of 0.25 V
    assert link.sent[0][1]["Amplitude"] == 401


def test_a_slew_that_rounds_to_unlimited_is_refused():
    link = Recorder()
    cmd = command(1)
    cmd["frequency_slew"] = 40.0  # 0.4 counts of 100 Hz/s: 0 would mean unlimited
    with pytest.raises(ValueError, match=r"AuxCommand.FrequencySlew: 40.0 rounds to 0, which means unlimited"):
        link.send_command(cmd, None)


def test_a_refused_enable_does_not_turn_later_keep_alives_into_enables():
    link = Recorder()
    with pytest.raises(ValueError):
        link.send_command(command(1, amplitude_v=5000.0), None)
    link.send_command(command(0), sample(0))
    assert modes(link) == [0]


@pytest.mark.parametrize("frame_name", [f.name for f in can_link.load_dbc(DATA).frames])
def test_frame_decoder_equals_canmatrix_on_every_frame(frame_name):
    """The bench's own unpacking (frame_decoder) gives what canmatrix's decode gives, value for
    value and in the same order, on the edges of every signal and on random payloads."""
    import random
    frame = next(f for f in can_link.load_dbc(DATA).frames if f.name == frame_name)
    decode = can_link.frame_decoder(frame)
    size = int(frame.size)
    rng = random.Random(frame_name)
    payloads = [bytes(size), bytes([0xFF] * size), bytes([0x80] * size), bytes([0x7F] * size)]
    payloads += [bytes(rng.getrandbits(8) for _ in range(size)) for _ in range(500)]
    for data in payloads:
        expected = {k: float(v.phys_value) for k, v in frame.decode(bytearray(data)).items()}
        got = decode(data)
        assert list(got.items()) == list(expected.items()), data.hex()


def test_frame_decoder_refuses_a_payload_of_the_wrong_length_as_canmatrix_does():
    from canmatrix.canmatrix import DecodingFrameLength
    frame = next(f for f in can_link.load_dbc(DATA).frames if f.name == "Motion")
    decode = can_link.frame_decoder(frame)
    for data in (bytes(7), bytes(9), b""):
        with pytest.raises(DecodingFrameLength):
            frame.decode(bytearray(data))
        with pytest.raises(DecodingFrameLength, match="expected 8"):
            decode(data)


def test_frame_decoder_leaves_big_endian_frames_to_canmatrix():
    """A layout it does not unpack itself (here a Motorola-order signal) still decodes, through
    canmatrix."""
    import copy
    frame = copy.deepcopy(next(f for f in can_link.load_dbc(DATA).frames if f.name == "Motion"))
    for s in frame.signals:
        s.is_little_endian = False
    decode = can_link.frame_decoder(frame)
    data = bytes(range(1, 9))
    assert decode(data) == {k: float(v.phys_value) for k, v in frame.decode(bytearray(data)).items()}
