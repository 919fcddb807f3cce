"""The bench's CANopen master (canopen_link.py, cia402.py, telemetry.from_canopen) without a bus:
against a stand-in drive written here (the least of a CiA 301 slave: NMT, expedited SDO on a
dictionary of the EDS defaults, synchronous RPDOs and TPDOs as their mapping objects say), the
start (NMT reset communication, boot-up, the configuration by CiA 301's mapping procedure, NMT
start), the RPDO bytes of each command, the controlwords of the bench's commands, the TPDO
values as signals in the bench's units, and what the link refuses before it sends anything.
The real drive is swum-emu's, in the guest tier (bench.vcan_canopen.examples)."""
import math
import os
import struct

import pytest

from swum_bench import BenchUsageError, Command, telemetry
from swum_bench import cia402
from swum_bench.canopen_eds import Eds
from swum_bench.canopen_link import CanopenLink, plan_tpdos
from swum_bench.emulator import BenchError

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
DATA = os.path.join(REPO, "config")  # the data directory of the checkout
NODE = 3


class StandInDrive:
    """A frame bus with a stand-in CiA 301 slave behind it."""

    def __init__(self, eds):
        self.eds = eds
        self.od = {key: e.default for key, e in eds.entries.items() if e.format is not None}
        self.sent = []          # every frame the link sent, in order
        self.queue = []
        self.ids = None
        self.operational = False
        self.latched = {}
        self.sdo_writes = []    # (index, sub, value) in order
        self.answer_syncs = True
        self.tpdo_length_offset = 0

    # the bus side
    def send(self, can_id, data):
        data = bytes(data)
        self.sent.append((can_id, data))
        if can_id == 0x000 and data == bytes([0x82, NODE]):
            self.od.update({k: e.default for k, e in self.eds.entries.items()
                            if e.format is not None and 0x1000 <= k[0] < 0x2000})
            self.queue += [(0x700 + NODE, b"\x7f"), (0x700 + NODE, b"\x00")]  # a heartbeat, then the boot-up
        elif can_id == 0x000 and data == bytes([0x01, NODE]):
            self.operational = True
        elif can_id == 0x600 + NODE:
            self._sdo(data)
        elif can_id == 0x080:
            self._sync()
        elif self.operational:
            for n in range(4):
                cob = self.od[(0x1400 + n, 1)]
                if not cob >> 31 and cob & 0x7FF == can_id:
                    self.latched[n] = data

    def receive(self, timeout_s):
        while self.queue:
            can_id, data = self.queue.pop(0)
            if self.ids is None or can_id in self.ids:
                return can_id, data
        return None

    def set_ids(self, ids):
        self.ids = set(ids)

    def close(self):
        pass

    # the slave side
    def _sdo(self, data):
        index, sub = data[1] | data[2] << 8, data[3]
        entry = self.eds[index, sub]
        if data[0] == 0x40:
            raw = entry.encode(self.od[(index, sub)])
            self.queue.append((0x580 + NODE, bytes([0x43 | (4 - len(raw)) << 2]) + data[1:4] + raw.ljust(4, b"\0")))
            return
        assert data[0] & 0xE3 == 0x23, "the link downloads expedited, size indicated"
        value = entry.decode(data[4:8 - (data[0] >> 2 & 3)])
        self.od[(index, sub)] = value
        self.sdo_writes.append((index, sub, value))
        self.queue.append((0x580 + NODE, bytes([0x60]) + data[1:4] + bytes(4)))

    def _entries(self, mapping):
        return [self.eds[m >> 16, m >> 8 & 0xFF] for m in (self.od[(mapping, s)] for s in
                                                           range(1, self.od[(mapping, 0)] + 1))]

    def _sync(self):
        for n, data in sorted(self.latched.items()):
            offset = 0
            for entry in self._entries(0x1600 + n):
                size = entry.bits // 8
                self.od[(entry.index, entry.sub)] = entry.decode(data[offset:offset + size])
                offset += size
        self.latched = {}
        if not (self.operational and self.answer_syncs):
            return
        for n in range(4):
            cob = self.od[(0x1800 + n, 1)]
            if cob >> 31 or self.od[(0x1800 + n, 2)] != 1:
                continue
            data = b"".join(e.encode(self.od[(e.index, e.sub)]) for e in self._entries(0x1A00 + n))
            self.queue.append((cob & 0x7FF, data[:len(data) + self.tpdo_length_offset]))


@pytest.fixture(scope="module")
def eds():
    return Eds(os.path.join(REPO, "config", "swum.eds"), NODE)


def objects(names):
    return [dict(telemetry.CANOPEN_TABLE)[n] for n in names]


def make_link(eds, names=telemetry.CANOPEN_DEFAULT_SIGNALS, emu_args=()):
    drive = StandInDrive(eds)
    link = CanopenLink("vcan0", NODE, DATA, objects(names), emu_args=emu_args, timeout_s=0.05, bus=drive)
    return link, drive


@pytest.fixture
def started(eds):
    link, drive = make_link(eds)
    link.start()
    drive.sent.clear()
    drive.sdo_writes.clear()
    return link, drive


def test_start_resets_configures_by_the_mapping_procedure_and_starts(eds):
    link, drive = make_link(eds)
    link.start()
    assert drive.sent[0] == (0x000, bytes([0x82, NODE]))   # NMT reset communication first
    assert drive.sent[-1] == (0x000, bytes([0x01, NODE]))  # NMT start last
    assert drive.sent[1] == (0x603, bytes.fromhex("4002650000000000"))  # 0x6502 read: modes checked
    w = drive.sdo_writes
    assert w[:2] == [(0x6040, 0, 0x06), (0x6060, 0, -1)]   # shutdown, open loop
    # TPDO1: not valid, count 0, entries, count, type 1, valid (CiA 301 7.5.2.36)
    assert w[2:10] == [(0x1800, 1, 0x80000183), (0x1A00, 0, 0), (0x1A00, 1, 0x60410010), (0x1A00, 2, 0x603F0010),
                       (0x1A00, 3, 0x606C0020), (0x1A00, 0, 3), (0x1800, 2, 1), (0x1800, 1, 0x183)]
    assert [x for x in w if x[:2] == (0x1A03, 0)] == [(0x1A03, 0, 0), (0x1A03, 0, 2)]
    # RPDO1: controlword, mode, phase; RPDO2: frequency, amplitude; RPDO3: target velocity; RPDO4 off
    assert [x[2] for x in w if x[0] == 0x1600 and x[1] in (1, 2, 3)] == [0x60400010, 0x60600008, 0x20030010]
    assert [x[2] for x in w if x[0] == 0x1601 and x[1] in (1, 2)] == [0x20010020, 0x20020020]
    assert [x[2] for x in w if x[0] == 0x1602 and x[1] == 1] == [0x60FF0020]
    assert [x for x in w if x[0] == 0x1403] == [(0x1403, 1, 0x80000503)]
    assert all(drive.od[(c, 2)] == 1 for c in (0x1400, 0x1401, 0x1402, 0x1800, 0x1801, 0x1802, 0x1803))
    assert drive.ids == {0x583, 0x183, 0x283, 0x383, 0x483}  # the heartbeats filtered out from now on


def test_an_unused_tpdo_is_made_not_valid(eds):
    link, drive = make_link(eds, names=("speed_mm_s",))
    link.start()
    assert [n for n, _ in link.tpdos] == [1]
    assert [x for x in drive.sdo_writes if x[0] in (0x1801, 0x1802, 0x1803)] == [
        (0x1801, 1, 0x80000283), (0x1802, 1, 0x80000383), (0x1803, 1, 0x80000483)]


def test_no_boot_up_is_a_bench_error(eds):
    link, drive = make_link(eds)
    drive.send = lambda can_id, data: None  # nothing answers
    with pytest.raises(BenchError, match=r"CANopen vcan0 node 3: no boot-up \(0x703#00\) after NMT reset "
                                         r"communication within 0.05 s"):
        link.start()


def test_a_drive_without_the_open_loop_mode_is_refused(eds):
    link, drive = make_link(eds)
    drive.od[(0x6502, 0)] = 0x00000004  # profile velocity only
    with pytest.raises(BenchError, match=r"0x6502 = 0x00000004: mode -1 not supported"):
        link.start()


def sample(statusword):
    return {"statusword": statusword}


def test_a_cycle_sends_the_rpdos_then_the_sync_and_reads_the_tpdos(started):
    link, drive = started
    sent = link.send_command(Command(action="enable", frequency_hz=40000.0, amplitude_v=200.0, phase_deg=90.0),
                             sample(0x0240))
    assert drive.sent == [(0x203, bytes.fromhex("0f00ff2823")),        # 0x0F, mode -1, 90.00 deg
                          (0x303, bytes.fromhex("005a6202400d0300")),  # 40 000 000 mHz, 200 000 mV
                          (0x403, bytes(4))]                           # no velocity target
    assert sent["command"] == 1 and sent["amplitude_setpoint"] == 200.0 and math.isnan(sent["velocity_setpoint"])
    drive.od.update({(0x6041, 0): 0x0637, (0x603F, 0): 0, (0x606C, 0): 300123, (0x6064, 0): -2500,
                     (0x2010, 0): 39992500, (0x2011, 0): 197800, (0x2012, 0): -9000, (0x2024, 0): 1500,
                     (0x2020, 0): 812, (0x2021, 0): 799})
    values = link.sync()
    assert drive.sent[-1] == (0x080, b"")
    s = telemetry.from_canopen(values, telemetry.canopen_scales(link.eds, telemetry.CANOPEN_DEFAULT_SIGNALS), 0.002)
    assert s == {"speed_mm_s": 300.123, "position_um": -2500.0, "frequency_hz": 39992.5, "amplitude_v": 197.8,
                 "phase_deg": -90.0, "current_a_ma": 812.0, "current_b_ma": 799.0, "motional_phase_a_deg": 15.0,
                 "state": 1.0, "fault_code": 0.0, "drive_on": 1.0, "statusword": 0x0637, "error_code": 0.0,
                 "time_s": 0.002}


def test_only_changed_rpdos_are_sent_again(started):
    link, drive = started
    link.send_command(Command(action="enable", amplitude_v=100.0), sample(0x0240))
    drive.sent.clear()
    link.send_command(Command(action="keep_alive", amplitude_v=100.0), sample(0x0231))
    assert drive.sent == []  # the drive holds them
    link.send_command(Command(action="keep_alive", amplitude_v=100.5), sample(0x0237))
    assert drive.sent == [(0x303, bytes.fromhex("005a620294880100"))]  # 100 500 mV


def test_slews_go_by_sdo_when_they_change(started):
    link, drive = started
    link.send_command(Command(action="enable", frequency_slew_hz_s=5e5, amplitude_slew_v_per_s=2e4), sample(0x0240))
    assert drive.sdo_writes == [(0x2004, 0, 500000), (0x2005, 0, 20000)]
    assert [c for c, _ in drive.sent] == [0x603, 0x603, 0x203, 0x303, 0x403]  # before the RPDOs
    drive.sdo_writes.clear()
    link.send_command(Command(action="keep_alive", frequency_slew_hz_s=5e5, amplitude_slew_v_per_s=2e4), sample(0x0231))
    assert drive.sdo_writes == []


def test_velocity_command_selects_profile_velocity(started):
    link, drive = started
    sent = link.send_command(Command(action="enable", velocity_mm_s=-300.0), sample(0x0240))
    assert drive.sent[0] == (0x203, bytes.fromhex("0f00032823"))      # mode 3
    assert drive.sent[2] == (0x403, struct.pack("<i", -300000))        # um/s
    assert sent["velocity_setpoint"] == -300.0


@pytest.mark.parametrize("fields, pattern", [
    (dict(amplitude_v=600.5), r"600.5 V is above the amplifier's --max-amplitude-v 600"),
    (dict(frequency_hz=29999.0), r"29999.0 Hz is below the amplifier's --min-frequency-hz 30000"),
    (dict(frequency_hz=50001.0), r"50001.0 Hz is above the amplifier's --max-frequency-hz 50000"),
    (dict(amplitude_v=-1.0), r"0x2002 sub 0 .*: -1000 is outside 0..4294967295"),
    (dict(phase_deg=181.0), r"0x2003 sub 0 .*: 18100 is outside -18000..18000"),
    (dict(amplitude_v=float("nan")), r"0x2002 .*: amplitude_v nan is not a finite number"),
    (dict(velocity_mm_s=1000.5), r"0x60FF sub 0 .*: 1000500 is outside -1000000..1000000"),
    (dict(frequency_slew_hz_s=0.4), r"0x2004 sub 0 .*: 0.4 rounds to 0, which means unlimited"),
])
def test_what_the_drive_would_refuse_silently_is_refused_before_sending(started, fields, pattern):
    link, drive = started
    with pytest.raises(ValueError, match=pattern):
        link.send_command(Command(action="enable", **fields), sample(0x0240))
    assert drive.sent == [] and link.sequencer.last == cia402.SHUTDOWN and not link.sequencer.enabled


def test_amplifier_limits_given_to_swum_emu_are_the_ones_checked(eds):
    link, _ = make_link(eds, emu_args=["--max-amplitude-v", "300", "--min-frequency-hz=35000"])
    assert link.limits == {"--min-frequency-hz": 35000.0, "--max-frequency-hz": 50000.0, "--max-amplitude-v": 300.0}


def test_a_missing_tpdo_is_a_bench_error_naming_it(started):
    link, drive = started
    drive.answer_syncs = False
    with pytest.raises(BenchError, match=r"no TPDO \[1, 2, 3, 4\] answered the SYNC within 0.05 s"):
        link.sync()


def test_a_tpdo_of_the_wrong_length_is_a_bench_error(started):
    link, drive = started
    drive.tpdo_length_offset = -1
    with pytest.raises(BenchError, match=r"TPDO1 \(0x183\) of 7 bytes, its mapping has 8"):
        link.sync()


def test_more_signals_than_four_tpdos_hold(eds):
    names = [n for n, _ in telemetry.CANOPEN_TABLE]
    with pytest.raises(BenchUsageError, match=r"the signals need 336 bits of TPDO, 4 TPDOs of 64 bits hold 256"):
        plan_tpdos(eds, objects(names))


def test_units_of_every_canopen_signal_match_the_other_transports(eds):
    scales = telemetry.canopen_scales(eds, [n for n, _ in telemetry.CANOPEN_TABLE])
    assert scales["speed_mm_s"] == (0x606C, 1e-3) and scales["temperature_c"] == (0x2027, 0.01)
    assert set(scales) | set(telemetry.CANOPEN_MISSING) | {"state", "fault_code", "drive_on"} == {
        row[0] for row in telemetry.TABLE} | {"drive_on"}


# ---- cia402: the controlwords of the bench's commands ------------------------------------------

SWITCH_ON_DISABLED, READY, ENABLED, FAULT = 0x0240, 0x0231, 0x0237, 0x0208


def words(steps):
    seq = cia402.Sequencer()
    return [seq.controlword(action, status) for action, status in steps]


def test_enable_from_ready_to_switch_on_is_one_word():
    assert words([("enable", READY), ("keep_alive", ENABLED)]) == [0x0F, 0x0F]


def test_enable_at_the_start_follows_the_configured_shutdown():
    # The configuration wrote 0x06: the first cycle acts on it, so 0x0F may follow at once.
    assert words([("enable", SWITCH_ON_DISABLED)]) == [0x0F]


def test_fault_reset_then_enable_walks_through_shutdown():
    assert words([("enable", READY), ("keep_alive", FAULT), ("reset_fault", FAULT), ("enable", SWITCH_ON_DISABLED),
                  ("enable", READY), ("keep_alive", ENABLED)]) == [0x0F, 0x06, 0x80, 0x06, 0x0F, 0x0F]


def test_keep_alive_repeats_what_was_asked_not_the_delayed_state():
    assert words([("enable", READY), ("keep_alive", READY), ("disable", ENABLED), ("keep_alive", ENABLED)]) == [
        0x0F, 0x0F, 0x06, 0x06]


def test_a_drive_that_fell_to_switch_on_disabled_is_walked_back():
    assert words([("enable", READY), ("keep_alive", SWITCH_ON_DISABLED), ("keep_alive", SWITCH_ON_DISABLED)]) == [
        0x0F, 0x06, 0x0F]


@pytest.mark.parametrize("statusword, state, bench_state", [
    (0x0200, "not ready to switch on", 0), (0x0240, "switch on disabled", 0), (0x0231, "ready to switch on", 0),
    (0x0233, "switched on", 0), (0x0637, "operation enabled", 1), (0x0217, "quick stop active", 1),
    (0x020F, "fault reaction active", 2), (0x0208, "fault", 2), (0x0228, "fault", 2),
])
def test_statusword_states(statusword, state, bench_state):
    assert cia402.state_of(statusword) == state and cia402.bench_state(statusword) == bench_state


@pytest.mark.parametrize("error_code, fault", [(0, 0), (0x8100, 1), (0x6100, 2), (0x2320, 3), (0x4310, 4),
                                               (0x8130, -1)])
def test_error_codes_as_swum_fault_codes(error_code, fault):
    assert cia402.fault_code(error_code) == fault
