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
