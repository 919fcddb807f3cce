#!/usr/bin/python3
"""The controller tests the docs show are real: extracts the python block of README.md's "A
controller test in ten lines" (at most 10 lines) and of docs/testing-controllers.md's "A test",
and runs each through tools/bench against swum-emu; both must pass."""
import os
import re
import subprocess
import sys
import tempfile

REPO = os.environ.get("SWUM_SOURCE_DIR") or os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))


def block(path, heading):
    with open(os.path.join(REPO, path)) as f:
        text = f.read()
    section = text.split(heading, 1)
    if len(section) != 2:
        sys.exit(f"FAIL: {path} has no heading {heading!r}")
    m = re.search(r"```python\n(.*?)```", section[1], re.S)
    if not m:
        sys.exit(f"FAIL: {path}: no python block under {heading!r}")
    return m.group(1)


def main():
    folder = tempfile.mkdtemp(prefix="swum-bench-readme-")
    cases = {"test_readme.py": block("README.md", "## A controller test in ten lines"),
             "test_testing_controllers.py": block("docs/testing-controllers.md", "## A test")}
    lines = [line for line in cases["test_readme.py"].splitlines() if line.strip()]
    if len(lines) > 10:
        sys.exit(f"FAIL: README's controller test has {len(lines)} lines, more than 10")
    for name, code in cases.items():
        with open(os.path.join(folder, name), "w") as f:
            f.write(code)
    r = subprocess.run([os.path.join(REPO, "tools", "bench"), folder, "-q"], capture_output=True, text=True,
                       timeout=600)
    print(r.stdout[-3000:], r.stderr[-2000:])
    if r.returncode != 0 or "2 passed" not in r.stdout:
        sys.exit(f"FAIL: the documented tests did not pass (exit {r.returncode})")
    print("PASS")


if __name__ == "__main__":
    main()
