"""The plugin's artifact folders: one per test, never shared by two ids that read alike."""
import types

from swum_bench.plugin import _test_folder


def folder(root, nodeid):
    config = types.SimpleNamespace(getoption=lambda name: root)
    return _test_folder(config, types.SimpleNamespace(nodeid=nodeid), None)


def test_ids_that_read_alike_get_their_own_folders(tmp_path):
    a = folder(str(tmp_path), "t.py::test[drive off]")
    b = folder(str(tmp_path), "t.py::test[drive_off]")
    assert a != b and a.startswith(str(tmp_path))


def test_long_ids_stay_unique(tmp_path):
    prefix = "t.py::test[" + "x" * 300
    assert folder(str(tmp_path), prefix + "a]") != folder(str(tmp_path), prefix + "b]")


def test_the_same_test_gets_the_same_folder(tmp_path):
    assert folder(str(tmp_path), "t.py::test_a") == folder(str(tmp_path), "t.py::test_a")


def factory(tmp_path, transport):
    from swum_bench.plugin import BenchFactory
    options = {"--swum-transport": transport, "--swum-emu": "/nonexistent/swum-emu", "--swum-data": None,
               "--swum-can-interface": "vcan0", "--swum-controller-can-interface": "vcan1"}
    return BenchFactory(types.SimpleNamespace(getoption=options.get), str(tmp_path))


def test_transport_from_the_environment_is_checked(tmp_path):
    import pytest
    from swum_bench import BenchUsageError
    with pytest.raises(BenchUsageError, match=r"^--swum-transport \(or SWUM_BENCH_TRANSPORT\) 'CANopen': not one of "
                                              r"modbus, can, canopen$"):
        factory(tmp_path, "CANopen")()
    assert factory(tmp_path, "canopen")().transport == "canopen"


def test_canopen_benches_are_not_run_in_parallel(tmp_path, monkeypatch):
    import pytest
    from swum_bench import BenchUsageError
    monkeypatch.setenv("PYTEST_XDIST_WORKER_COUNT", "2")
    with pytest.raises(BenchUsageError, match=r"CAN benches cannot run in parallel on one bus"):
        factory(tmp_path, "canopen")()
