"""The pytest plugin (`-p swum_bench.plugin`, or `pytest_plugins = ["swum_bench.plugin"]` in a
conftest.py): the `swum_bench` fixture, command-line options, and the artifacts of a failing
test (the plot of the failed assertion and the emulator's log) in its report and in the JUnit
XML (`--junitxml`) as properties swum_plot / swum_emulator_log / swum_capture."""
import hashlib
import os
import re
import shutil

import pytest

from . import attachments, installation
from .bench import TRANSPORTS, Bench
from .controllers import ReferenceController
from .signals import BenchUsageError

_HERE = os.path.dirname(os.path.abspath(__file__))


def pytest_addoption(parser):
    group = parser.getgroup("swum_bench", "swum-hil controller test bench")
    group.addoption("--swum-emu", default=installation.program("SWUM_EMU", "swum-emu"),
                    help="swum-emu binary (default: $SWUM_EMU, else swum-emu on PATH)")
    group.addoption("--swum", default=installation.program("SWUM_BINARY", "swum"),
                    help="swum binary, for the reference controller (default: $SWUM_BINARY, else swum on PATH)")
    group.addoption("--swum-data", default=None,
                    help="the data directory: the default motor li2019.toml, swum.dbc, swum.eds, "
                    "modbus_registers.json (default: $SWUM_DATA_DIR, else share/swum-hil beside the installed "
                    "swum-emu, else the checkout's config/)")
    group.addoption("--swum-transport", default=os.environ.get("SWUM_BENCH_TRANSPORT", "modbus"),
                    choices=TRANSPORTS, help="the bench's link to swum-emu (default $SWUM_BENCH_TRANSPORT or modbus; "
                    "can: the swum frame set on vcan0, lockstep by SYNC; canopen: swum-emu as a CiA 402 drive, the "
                    "bench its CANopen master, lockstep by SYNC)")
    group.addoption("--swum-can-interface", default="vcan0",
                    help="swum-emu's CAN interface for --swum-transport can or canopen")
    group.addoption("--swum-controller-can-interface", default="vcan1",
                    help="the CAN bus an external controller talks on; the bench bridges it to swum-emu's")
    group.addoption("--swum-artifacts", default=None,
                    help="folder for each test's capture.csv, logs and plots (default: under pytest's tmp_path)")


def _test_folder(config, item, tmp_path_factory):
    """The test's own folder: its readable id, made unique by a hash of the whole node id (two
    ids that read alike, "drive off" and "drive_off", never share one)."""
    root = config.getoption("--swum-artifacts")
    digest = hashlib.sha1(item.nodeid.encode()).hexdigest()[:8]
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", item.nodeid)[-100:] + "-" + digest
    if root is None:
        return str(tmp_path_factory.mktemp(name[-50:], numbered=True))
    folder = os.path.join(root, name)
    shutil.rmtree(folder, ignore_errors=True)  # this test's own, from an earlier run
    return folder


def _log_tail(path, lines=40):
    try:
        with open(path) as f:
            return "".join(f.readlines()[-lines:])
    except OSError:
        return ""


class BenchFactory:
    """What the `swum_bench` fixture gives: call it to get a Bench (one emulator each)."""

    def __init__(self, config, folder):
        self._config = config
        self.folder = folder
        self.benches = []

    @property
    def swum_binary(self):
        binary = self._config.getoption("--swum")
        if not binary:
            raise BenchUsageError("the reference controller needs the swum binary: --swum or SWUM_BINARY")
        return binary

    def reference_controller(self, speed_mm_s, **options):
        """`swum control` at speed_mm_s (options as in docs/host.md, e.g. frequency_hz=40000)."""
        return ReferenceController(self.swum_binary, speed_mm_s, **options)

    def __call__(self, controller=None, **options):
        transport = options.pop("transport", self._config.getoption("--swum-transport"))
        if transport not in TRANSPORTS:
            raise BenchUsageError(f"--swum-transport (or SWUM_BENCH_TRANSPORT) {transport!r}: not one of "
                                  f"{', '.join(TRANSPORTS)}")
        if transport in ("can", "canopen") and int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")) > 1:
            raise BenchUsageError("CAN benches cannot run in parallel on one bus: a CANopen SYNC steps every "
                                  "node on it (run without -n, or give each worker its own bus)")
        index = len(self.benches)
        folder = self.folder if index == 0 else os.path.join(self.folder, f"bench{index + 1}")
        emu = self._config.getoption("--swum-emu")
        if not emu:
            raise BenchUsageError("swum-emu not found: install the package, put it on PATH, or give --swum-emu "
                                  "or SWUM_EMU")
        data = self._config.getoption("--swum-data") or installation.data_dir(emu)
        bench = Bench(emu, data, folder,
                      transport=transport,
                      can_interface=self._config.getoption("--swum-can-interface"),
                      controller_can_interface=self._config.getoption("--swum-controller-can-interface"), **options)
        if controller is not None:
            bench.use(controller)
        self.benches.append(bench)
        return bench


@pytest.fixture
def swum_bench(request, tmp_path_factory):
    """Factory of benches: `bench = swum_bench(controller)`; every bench it made is closed (its
    processes stopped by pid) and its capture saved when the test ends."""
    folder = _test_folder(request.config, request.node, tmp_path_factory)
    os.makedirs(folder, exist_ok=True)
    factory = BenchFactory(request.config, folder)
    request.node._swum_factory = factory
    yield factory
    errors = []
    for bench in factory.benches:  # every bench is closed, whatever fails first
        try:
            if bench.samples:
                path = bench.save_capture()
                request.node.user_properties.append(("swum_capture", path))
        except Exception as e:
            errors.append(e)
        try:
            bench.close()
        except Exception as e:
            errors.append(e)
    if errors:
        raise errors[0]


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_call(item):
    factory = getattr(item, "_swum_factory", None)
    attachments.begin(factory.folder if factory else None)
    try:
        yield
    finally:
        item._swum_plots = attachments.end()


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    if call.when == "call":
        factory = getattr(item, "_swum_factory", None)
        failed = call.excinfo is not None
        if failed:
            for path in getattr(item, "_swum_plots", []):
                item.user_properties.append(("swum_plot", path))
            for bench in factory.benches if factory else []:
                if bench.emulator_log is not None and os.path.exists(bench.emulator_log):
                    item.user_properties.append(("swum_emulator_log", bench.emulator_log))
    outcome = yield
    report = outcome.get_result()
    if call.when == "call" and call.excinfo is not None:
        factory = getattr(item, "_swum_factory", None)
        for bench in factory.benches if factory else []:
            if bench.emulator_log is not None and os.path.exists(bench.emulator_log):
                report.sections.append((f"swum-emu log ({bench.emulator_log})", _log_tail(bench.emulator_log)))
