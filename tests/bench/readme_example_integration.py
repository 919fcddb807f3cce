#!/usr/bin/python3
"""The controller tests the docs show are real: the ones README.md marks (`<!-- example: NAME.py -->`
over a python block, at most 10 lines each; tests/docs/readme_examples.py finds them) and
docs/testing-controllers.md's python block under "A test" run through tools/bench against
swum-emu; all must pass. (The README's shell examples run in docs.readme_examples.)"""
import os
import re
import subprocess
import sys
import tempfile

REPO = os.environ.get("SWUM_SOURCE_DIR") or os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(REPO, "tests", "docs"))
from readme_examples import marked_examples  # noqa: E402


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
    _, cases = marked_examples(REPO)
    for name, code in cases.items():
        lines = [line for line in code.splitlines() if line.strip()]
        if len(lines) > 10:
            sys.exit(f"FAIL: README.md's controller test {name} has {len(lines)} lines, more than 10")
    cases["test_testing_controllers.py"] = block("docs/testing-controllers.md", "## A test")
    folder = tempfile.mkdtemp(prefix="swum-bench-readme-")
    for name, code in cases.items():
        with open(os.path.join(folder, name), "w") as f:
            f.write(code)
    r = subprocess.run([os.path.join(REPO, "tools", "bench"), folder, "-q"], capture_output=True, text=True,
                       timeout=600)
    print(r.stdout[-3000:], r.stderr[-2000:])
    if r.returncode != 0 or f"{len(cases)} passed" not in r.stdout:
        sys.exit(f"FAIL: the documented tests did not all pass (exit {r.returncode})")
    print(f"PASS: {len(cases)} controller tests")


if __name__ == "__main__":
    main()
