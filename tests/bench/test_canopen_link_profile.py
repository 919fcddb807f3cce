"""The bench's CANopen master (canopen_link.py, in Python) against swum-emu's own CANopen profile
(the C++ slave: dictionary, SDO server, PDOs, NMT), with no SocketCAN: canopen_stdio_slave runs
the profile in lockstep on stdin/stdout (tests/firmware_sim/transports/canopen_stdio_slave.cpp).
Two implementations written apart: the start's SDO configuration is accepted as it is, the
server's aborts decode to their CiA 301 names, a segmented upload reads the device name, the
RPDOs of each command reach the drive request only at the SYNC, and the TPDOs the profile
samples decode to the bench's signals. The drive's physics is not here (bench.vcan_canopen.*).
Needs SWUM_CANOPEN_SLAVE (ctest sets it)."""
import os
import subprocess

import pytest

from swum_bench import Command, telemetry
from swum_bench.canopen_link import CanopenLink
from swum_bench.canopen_sdo import SdoAbort

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
DATA = os.path.join(REPO, "config")  # the data directory of the checkout
SLAVE = os.environ.get("SWUM_CANOPEN_SLAVE")
NODE = 7
pytestmark = pytest.mark.skipif(not SLAVE, reason="needs SWUM_CANOPEN_SLAVE (run through ctest)")


class ProfileBus:
    """A frame bus whose other end is canopen_stdio_slave."""

    def __init__(self, ids):
        self.proc = subprocess.Popen([SLAVE, str(NODE)], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, text=True)
        self.queue, self.ids, self.lines = [], set(ids), []
        self._answer()  # the power-up boot-up

    def _answer(self):
        while True:
            line = self.proc.stdout.readline().strip()
            assert line, "canopen_stdio_slave ended"
            if line == ".":
                return
            assert not line.startswith("error"), line
            if "#" in line:
                can_id, data = line.split("#")
                self.queue.append((int(can_id, 16), bytes.fromhex(data)))
            else:
                self.lines.append(line)

    def _line(self, text):
        self.proc.stdin.write(text + "\n")
        self.proc.stdin.flush()
        self._answer()

    def send(self, can_id, data):
        self._line(f"{can_id:03X}#{bytes(data).hex().upper()}")

    def receive(self, timeout_s):
        while self.queue:
            frame = self.queue.pop(0)
            if frame[0] in self.ids:
                return frame
        return None

    def set_ids(self, ids):
        self.ids = set(ids)

    def telemetry(self, **values):
        self._line("telemetry " + " ".join(f"{k}={v}" for k, v in values.items()))

    def request(self):
        self._line("request")
        return {k: int(v) for k, v in (pair.split("=") for pair in self.lines.pop().split()[1:])}

    def close(self):
        self.proc.stdin.close()
        assert self.proc.wait(10) == 0


def open_link(names=telemetry.CANOPEN_DEFAULT_SIGNALS):
    bus = ProfileBus([0x700 + NODE, 0x580 + NODE])
    link = CanopenLink("stdio", NODE, DATA,
                       [dict(telemetry.CANOPEN_TABLE)[n] for n in names], timeout_s=1.0, bus=bus)
    return link, bus


@pytest.fixture
def started():
    link, bus = open_link()
    link.start()
    yield link, bus
    bus.close()


def test_the_profile_takes_the_configuration_as_the_link_writes_it(started):
    link, bus = started
    read = lambda index, sub=0: link.sdo.read(link.eds[index, sub])  # noqa: E731
    assert [read(0x1A00, s) for s in range(4)] == [3, 0x60410010, 0x603F0010, 0x606C0020]
    assert [read(0x1A03, s) for s in range(3)] == [2, 0x20200020, 0x20210020]
    assert [read(0x1800 + n, 2) for n in range(4)] == [1, 1, 1, 1]
    assert [read(0x1800 + n, 1) for n in range(4)] == [0x187, 0x287, 0x387, 0x487]
    assert [read(0x1600, s) for s in range(4)] == [3, 0x60400010, 0x60600008, 0x20030010]
    assert read(0x1403, 1) == 0x80000507 and read(0x1400, 2) == 1
    assert read(0x1008) == link.eds[0x1008, 0].default  # a segmented upload from the C++ server
    request = bus.request()
    assert (request["controlword"], request["mode"]) == (0x06, -1)


@pytest.mark.parametrize("index, value, code, name", [
    (0x6060, 2, 0x06090030, "invalid value for parameter"),            # the drive's modes: 0, 3, -1
    (0x6041, 0, 0x06010002, "attempt to write a read only object"),
    (0x2001, 20000000, 0x06090032, "value of parameter written too low"),  # below the amplifier's limit
])
def test_the_servers_aborts_are_named(started, index, value, code, name):
    link, _ = started
    with pytest.raises(SdoAbort, match=rf"node {NODE} aborted with 0x{code:08X} \({name}\)"):
        link.sdo.write(link.eds[index, 0], value)


def test_an_unknown_object_is_aborted_by_the_server(started):
    link, _ = started
    with pytest.raises(SdoAbort, match=r"0x2099 sub 0: node 7 aborted with 0x06020000 \(object does not exist in "
                                       r"the object dictionary\)"):
        link.sdo.upload(0x2099, 0)


def test_commands_reach_the_drive_request_at_the_sync(started):
    link, bus = started
    bus.telemetry(statusword=0x0240)
    first = link.sync()
    assert first[0x6041] == 0x0240
    command = Command(action="enable", frequency_hz=39500.0, amplitude_v=200.0, phase_deg=-90.0)
    link.send_command(command, {"statusword": 0x0240})
    assert bus.request()["controlword"] == 0x06  # synchronous RPDOs act at the next SYNC
    link.sync()
    r = bus.request()
    assert (r["controlword"], r["mode"], r["frequency_mhz"], r["amplitude_mv"], r["phase_cdeg"]) == (
        0x0F, -1, 39500000, 200000, -9000)
    link.send_command(Command(action="keep_alive", velocity_mm_s=300.0), {"statusword": 0x0237})
    link.sync()
    r = bus.request()
    assert (r["controlword"], r["mode"], r["target_velocity_um_s"]) == (0x0F, 3, 300000)
    link.send_command(Command(action="reset_fault"), {"statusword": 0x0208})
    link.sync()
    assert (bus.request()["controlword"], bus.request()["fault_reset_edges"]) == (0x80, 1)


def test_slews_act_at_once_by_sdo(started):
    link, bus = started
    command = Command(action="enable", frequency_slew_hz_s=5e5, amplitude_slew_v_per_s=2e4)
    link.send_command(command, {"statusword": 0x0240})
    r = bus.request()
    assert (r["frequency_slew_hz_per_s"], r["amplitude_slew_v_per_s"]) == (500000, 20000)


def test_the_profiles_tpdos_decode_to_the_benchs_signals(started):
    link, bus = started
    bus.telemetry(statusword=0x0637, error_code=0x4310, speed_um_s=-300123, position_um=12345,
                  frequency_mhz=39992500, amplitude_mv=197800)
    s = telemetry.from_canopen(link.sync(), telemetry.canopen_scales(link.eds, telemetry.CANOPEN_DEFAULT_SIGNALS),
                               0.0)
    assert (s["speed_mm_s"], s["position_um"], s["frequency_hz"], s["amplitude_v"]) == (-300.123, 12345.0,
                                                                                          39992.5, 197.8)
    assert (s["state"], s["fault_code"], s["statusword"], s["error_code"]) == (1.0, 4.0, 0x0637, 0x4310)


def test_the_amplitude_limit_agrees_with_the_profile():
    link, bus = open_link()
    link.start()
    link.sync()
    link.send_command(Command(action="enable", amplitude_v=600.0), {"statusword": 0x0240})  # the limit itself
    link.sync()
    assert bus.request()["amplitude_mv"] == 600000  # 0x2002 is the terminal amplitude, as the command
    with pytest.raises(ValueError, match=r"600.25 V is above the amplifier's --max-amplitude-v 600"):
        link.send_command(Command(action="keep_alive", amplitude_v=600.25), {"statusword": 0x0237})
    # What the bench refuses the profile refuses too: one count above, by SDO.
    with pytest.raises(SdoAbort, match=r"0x06090031 \(value of parameter written too high\)"):
        link.sdo.write(link.eds[0x2002, 0], 600001)
    bus.close()


class NoEmulator:
    """Stands for swum-emu's process: the profile on stdio is the node."""

    def __init__(self, binary, args, log_path):
        self.args = args
        self.log_path = log_path

    def running(self):
        return True

    def stop(self):
        return 0


def test_a_bench_over_canopen_captures_each_sync(tmp_path, monkeypatch):
    """The Bench's own CANopen path (start, the cycles of a Python controller, the samples'
    time, the command signals, the capture) on the profile; swum-emu's options as it would get them."""
    from swum_bench import Bench, bench as bench_module, canopen_link
    buses = []

    def profile_bus(interface, ids, timeout_s):
        buses.append(ProfileBus(ids))
        buses[-1].telemetry(statusword=0x0231)  # ready to switch on, where no drive moves it on from
        return buses[-1]

    monkeypatch.setattr(bench_module, "Emulator", NoEmulator)
    monkeypatch.setattr(canopen_link, "RawCanBus", profile_bus)

    class EnableAt100V:
        def cycle(self, sample):
            return Command(action="enable" if sample["state"] != 1 else "keep_alive", amplitude_v=100.0)

    bench = Bench(SLAVE, DATA, str(tmp_path), transport="canopen", node=NODE)
    bench.use(EnableAt100V())
    bench.step(0.003)
    assert bench.emulator.args[-6:] == ["--node", str(NODE), "--sync-ticks", "10", "--can-profile", "cia402"]
    assert [s["time_s"] for s in bench.samples] == [0.0, 0.001, 0.002, 0.003]
    assert [s["command"] for s in bench.samples] == [2.0, 1.0, 1.0, 1.0]  # 0x06 configured, then 0x0F
    assert [s["command_amplitude_v"] for s in bench.samples] == [0.0, 100.0, 100.0, 100.0]
    assert bench.samples[0]["statusword"] == 0x0231 and bench.samples[0]["state"] == 0.0
    assert buses[0].request()["amplitude_mv"] == 100000
    with open(bench.save_capture()) as f:
        header = f.readline()
    assert header.startswith("time_s,speed_mm_s [mm/s],") and "load_n" not in header
    bench.close()
