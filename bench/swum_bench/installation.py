"""Where the bench finds swum-emu, swum and the data directory (docs/install.md): the same rule
as the two programs. The data directory holds the default motor (li2019.toml), the protocol
definitions (swum.dbc, swum.eds, modbus_registers.json) and the scenarios: config/ of a checkout,
PREFIX/share/swum-hil of an installation."""
import os
import shutil

DEFAULT_CONFIG = "li2019.toml"
_HERE = os.path.dirname(os.path.abspath(__file__))


def program(environment_variable, name):
    """$ENVIRONMENT_VARIABLE, else NAME on PATH, else None."""
    return os.environ.get(environment_variable) or shutil.which(name)


def data_dir(emu_binary=None):
    """$SWUM_DATA_DIR; else PREFIX/share/swum-hil beside an installed swum-emu (PREFIX/bin); else
    the checkout's config/ when this package is the checkout's bench/swum_bench. None when none
    holds li2019.toml (an explicit $SWUM_DATA_DIR is returned as it is: the caller's error names it)."""
    explicit = os.environ.get("SWUM_DATA_DIR")
    if explicit:
        return explicit
    candidates = []
    if emu_binary:
        binary = shutil.which(emu_binary) or emu_binary
        candidates.append(os.path.join(os.path.dirname(os.path.realpath(binary)), "..", "share", "swum-hil"))
    candidates.append(os.path.join(_HERE, "..", "..", "config"))
    for candidate in candidates:
        if os.path.isfile(os.path.join(candidate, DEFAULT_CONFIG)):
            return os.path.normpath(candidate)
    return None


def data_file(data_directory, name):
    """NAME in the data directory; a one-line error naming both when it is not there."""
    from .signals import BenchUsageError
    if not data_directory:
        raise BenchUsageError("no swum-hil data directory (li2019.toml, swum.dbc, swum.eds): install the package, "
                              "or give --swum-data DIR or SWUM_DATA_DIR")
    path = os.path.join(data_directory, name)
    if not os.path.isfile(path):
        raise BenchUsageError(f"{name} not found in the data directory {data_directory} (--swum-data / SWUM_DATA_DIR)")
    return path
