"""bench/swum_bench/installation.py: where the plugin finds swum-emu, swum and the data directory
when nothing is set (docs/install.md) - the paths an installed plugin takes, which tools/bench
(setting SWUM_DATA_DIR) never does."""
import os

import pytest

from swum_bench import BenchUsageError
from swum_bench import installation

CHECKOUT_DATA = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "config"))


@pytest.fixture
def no_environment(monkeypatch):
    for name in ("SWUM_DATA_DIR", "SWUM_EMU", "SWUM_BINARY"):
        monkeypatch.delenv(name, raising=False)


def prefix_with_data(root):
    """ROOT/bin/swum-emu (an executable) and ROOT/share/swum-hil/li2019.toml, as an installation."""
    os.makedirs(root / "bin")
    emu = root / "bin" / "swum-emu"
    emu.write_text("#!/bin/sh\n")
    emu.chmod(0o755)
    data = root / "share" / "swum-hil"
    os.makedirs(data)
    (data / "li2019.toml").write_text("# a motor\n")
    return str(emu), str(data)


def test_explicit_data_dir_is_returned_as_it_is(no_environment, monkeypatch, tmp_path):
    monkeypatch.setenv("SWUM_DATA_DIR", str(tmp_path))  # even without li2019.toml: the caller's error names it
    assert installation.data_dir("/nonexistent/swum-emu") == str(tmp_path)


def test_an_installed_swum_emu_brings_its_share_folder(no_environment, tmp_path):
    emu, data = prefix_with_data(tmp_path / "prefix")
    assert installation.data_dir(emu) == os.path.normpath(data)


def test_swum_emu_found_on_path_brings_its_share_folder(no_environment, monkeypatch, tmp_path):
    emu, data = prefix_with_data(tmp_path / "prefix")
    monkeypatch.setenv("PATH", os.path.dirname(emu) + os.pathsep + os.environ.get("PATH", ""))
    assert installation.program("SWUM_EMU", "swum-emu") == emu
    assert installation.data_dir("swum-emu") == os.path.normpath(data)


def test_without_an_installation_the_checkout_config_is_the_data(no_environment, tmp_path):
    assert installation.data_dir(str(tmp_path / "bin" / "swum-emu")) == CHECKOUT_DATA
    assert installation.data_dir(None) == CHECKOUT_DATA


def test_a_missing_file_names_itself_and_the_folder(tmp_path):
    with pytest.raises(BenchUsageError, match=r"^swum.dbc not found in the data directory .* \(--swum-data / SWUM_DATA_DIR\)$"):
        installation.data_file(str(tmp_path), "swum.dbc")
    with pytest.raises(BenchUsageError, match=r"^no swum-hil data directory"):
        installation.data_file(None, "swum.dbc")
