#!/usr/bin/python3
"""The examples the docs show are real: extracts every block of README.md marked as an example
(an HTML comment `<!-- example -->` right above a ```sh block, `<!-- example: NAME.py -->` above a
```python block, which is a controller test written to NAME.py) and docs/testing-controllers.md's
python block under "A test", and runs them against the build:

  - each sh block with bash -euo pipefail in a scratch folder of its own, where `config/` is the
    checkout's and `swum` and `swum-emu` are the build's on PATH (as after the README's install
    steps); it must exit 0 within EXAMPLE_SECONDS, and whatever it left running is stopped;
  - the controller tests through tools/bench; all must pass, and README's has at most 10 lines.
"""
import os
import re
import signal
import subprocess
import sys
import tempfile
import time

REPO = os.environ.get("SWUM_SOURCE_DIR") or os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
EXAMPLE_SECONDS = 60
MARKED = re.compile(r"^<!-- example(?::\s*(\S+))? -->\n```(\w+)\n(.*?)^```", re.S | re.M)


def read(path):
    with open(os.path.join(REPO, path)) as f:
        return f.read()


def block(path, heading):
    section = read(path).split(heading, 1)
    if len(section) != 2:
        sys.exit(f"FAIL: {path} has no heading {heading!r}")
    m = re.search(r"```python\n(.*?)```", section[1], re.S)
    if not m:
        sys.exit(f"FAIL: {path}: no python block under {heading!r}")
    return m.group(1)


def readme_examples():
    text = read("README.md")
    shell, tests = [], {}
    for m in MARKED.finditer(text):
        name, language, code = m.group(1), m.group(2), m.group(3)
        line = text.count("\n", 0, m.start()) + 1
        if language == "sh" and not name:
            shell.append((line, code))
        elif language == "python" and name and name.endswith(".py"):
            tests[name] = code
        else:
            sys.exit(f"FAIL: README.md:{line}: an example is `<!-- example -->` over ```sh or "
                     f"`<!-- example: NAME.py -->` over ```python, not {name!r} over {language!r}")
    if not shell or not tests:
        sys.exit(f"FAIL: README.md marks {len(shell)} shell examples and {len(tests)} controller tests; "
                 "expected at least one of each")
    return shell, tests


def run_shell(line, code):
    folder = tempfile.mkdtemp(prefix="swum-readme-example-")
    os.symlink(os.path.join(REPO, "config"), os.path.join(folder, "config"))
    env = dict(os.environ)
    binaries = [os.path.dirname(os.environ["SWUM_BINARY"]), os.path.dirname(os.environ["SWUM_EMU"])]
    env["PATH"] = ":".join(binaries + [env.get("PATH", "/usr/bin:/bin")])
    start = time.monotonic()
    p = subprocess.Popen(["/bin/bash", "-euo", "pipefail", "-c", code], cwd=folder, env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        out, _ = p.communicate(timeout=EXAMPLE_SECONDS)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, _ = p.communicate()
        print(out[-3000:])
        return f"README.md:{line}: the example did not finish within {EXAMPLE_SECONDS} s"
    finally:
        try:  # whatever the block started in the background
            os.killpg(p.pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
    seconds = time.monotonic() - start
    print(f"--- README.md:{line} ({seconds:.1f} s, exit {p.returncode}, in {folder})\n{code}{out[-2000:]}")
    if p.returncode != 0:
        return f"README.md:{line}: the example exited {p.returncode}"
    return None


def main():
    for variable in ("SWUM_BINARY", "SWUM_EMU"):
        if not os.access(os.environ.get(variable, ""), os.X_OK):
            sys.exit(f"FAIL: {variable} names no executable (ctest sets it)")
    shell, tests = readme_examples()
    failures = [f for f in (run_shell(line, code) for line, code in shell) if f]

    for name, code in tests.items():
        lines = [line for line in code.splitlines() if line.strip()]
        if len(lines) > 10:
            failures.append(f"README.md: the controller test {name} has {len(lines)} lines, more than 10")
    folder = tempfile.mkdtemp(prefix="swum-bench-readme-")
    cases = dict(tests)
    cases["test_testing_controllers.py"] = block("docs/testing-controllers.md", "## A test")
    for name, code in cases.items():
        with open(os.path.join(folder, name), "w") as f:
            f.write(code)
    r = subprocess.run([os.path.join(REPO, "tools", "bench"), folder, "-q"], capture_output=True, text=True,
                       timeout=600)
    print(r.stdout[-3000:], r.stderr[-2000:])
    if r.returncode != 0 or f"{len(cases)} passed" not in r.stdout:
        failures.append(f"the documented controller tests did not all pass (exit {r.returncode})")
    for f in failures:
        print("FAIL:", f)
    if failures:
        sys.exit(1)
    print(f"PASS: {len(shell)} shell examples and {len(cases)} controller tests")


if __name__ == "__main__":
    main()
