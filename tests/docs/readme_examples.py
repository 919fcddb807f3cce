#!/usr/bin/python3
"""The README's examples are real. An example is a block README.md marks with an HTML comment
right above it: `<!-- example -->` over a ```sh block, `<!-- example: NAME.py -->` over a
```python block (a controller test, written to NAME.py and run by bench.readme_example).

Run as a script (ctest docs.readme_examples), each sh block runs with bash -euo pipefail in a
scratch folder of its own, where `config/` is the checkout's and `swum` and `swum-emu` are the
build's ($SWUM_BINARY, $SWUM_EMU) on PATH, as after the README's install steps; it must exit 0
within EXAMPLE_SECONDS, and whatever it left running is stopped.
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


def marked_examples(repo=REPO):
    """README.md's marked examples: [(line, sh code)], {NAME.py: python code}; exits on a bad mark."""
    with open(os.path.join(repo, "README.md")) as f:
        text = f.read()
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
    shell, _ = marked_examples()
    failures = [f for f in (run_shell(line, code) for line, code in shell) if f]
    for f in failures:
        print("FAIL:", f)
    if failures:
        sys.exit(1)
    print(f"PASS: {len(shell)} shell examples")


if __name__ == "__main__":
    main()
