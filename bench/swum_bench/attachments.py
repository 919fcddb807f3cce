"""Where a failing assertion leaves its plot. The pytest plugin points this at the test's own
artifact folder before each test and collects what was attached after it; outside pytest
(a script) nothing is set and the failure carries its message only."""
import os
import re

_state = {"directory": None, "files": []}


def begin(directory):
    """Plots of the next assertions go to `directory` (created on first use)."""
    _state["directory"] = directory
    _state["files"] = []


def end():
    """Stops attaching; returns the files attached since begin()."""
    files = _state["files"]
    _state["directory"] = None
    _state["files"] = []
    return files


def directory():
    return _state["directory"]


def new_path(stem, suffix=".png"):
    """A fresh file name in the current folder (None when no folder is set)."""
    folder = _state["directory"]
    if folder is None:
        return None
    os.makedirs(folder, exist_ok=True)
    base = re.sub(r"[^A-Za-z0-9_.-]+", "_", stem)[:80] or "plot"
    path = os.path.join(folder, base + suffix)
    n = 2
    while os.path.exists(path):
        path = os.path.join(folder, f"{base}_{n}{suffix}")
        n += 1
    return path


def attach(path):
    _state["files"].append(path)
