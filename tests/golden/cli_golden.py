#!/usr/bin/python3
"""Golden CLI outputs of `swum` and `swum-emu` (tests/golden/README.md).

  cli_golden.py --list                    the case names (CMake registers golden.cli.<name>)
  cli_golden.py CASE                      run CASE, compare with tests/golden/cli/CASE.*
  cli_golden.py --regenerate [CASE ...]   write tests/golden/cli/CASE.* from the current binaries

Regenerate ONLY for a deliberate change of an output (a new column, option or subcommand that
the issue making it documents), in a commit of its own that says which files changed and why;
never to make a restructuring pass.

Environment: SWUM_BINARY, SWUM_EMU, SWUM_SOURCE_DIR (ctest sets them; by hand they default to
build/ci of this checkout). Commands run in SWUM_SOURCE_DIR with relative input paths, so the
outputs that echo an input path do not depend on the checkout's location; the scratch folder
is written as $OUT.

How outputs are compared (one kind per stored file):
  .json     same structure, keys, strings, booleans and integers; other numbers within 1e-9
            relative (simulated numbers may differ in the last bits across compilers)
  .txt      exactly, byte for byte
  .csv      header and row count exactly; text cells exactly; numeric cells within one unit of
            the last digit printed in the stored file (or 1e-9 relative)
  .entries  help text: every stored entry (a heading, or an option / subcommand with its
            description, whitespace collapsed) appears in the output, in the same order; new
            entries may appear between them (later issues add options and subcommands)
Simulated values that later issues change on purpose (the model's speed and amplitudes in
`swum sweep` / `swum synth` files, issue 16's faster step) are not captured: of those files only
the header lines and the input columns are. Timing (lateness, overruns, rates) never is.
"""
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
EXPECTED = os.path.join(HERE, "cli")
SOURCE = os.environ.get("SWUM_SOURCE_DIR", os.path.abspath(os.path.join(HERE, "..", "..")))
SWUM = os.environ.get("SWUM_BINARY", os.path.join(SOURCE, "build", "ci", "host", "swum"))
EMU = os.environ.get("SWUM_EMU", os.path.join(SOURCE, "build", "ci", "firmware_sim", "swum-emu"))
CONFIG = "config/li2019.toml"
LITERAL = "config/li2019_literal.toml"
INPUTS = "tests/golden/inputs"
SUBCOMMANDS = ["modes", "simulate", "sweep", "validate", "stator", "identify", "pick", "log", "synth", "discrepancy",
               "band", "track", "track-report", "calibrate"]


class Run:
    def __init__(self, out_dir):
        self.out = out_dir

    def normal(self, text):
        text = text.replace(self.out, "$OUT")
        return text.replace(SWUM, "swum").replace(EMU, "swum-emu")

    def swum(self, *args, expect=0, timeout=120):
        r = subprocess.run([SWUM, *args], cwd=SOURCE, capture_output=True, text=True, timeout=timeout)
        if expect is not None and r.returncode != expect:
            raise AssertionError(f"swum {' '.join(args)}: exit {r.returncode}, expected {expect}\n{r.stdout}{r.stderr}")
        return r

    def path(self, name):
        return os.path.join(self.out, name)


def read(path):
    with open(path) as f:
        return f.read()


def csv_columns(text, columns, skip_comments=True):
    """The rows of a CSV projected onto `columns` (by name), as CSV text."""
    lines = [l for l in text.splitlines() if not (skip_comments and l.startswith("#"))]
    header = lines[0].split(",")
    index = [header.index(c) for c in columns]
    out = [",".join(columns)]
    for line in lines[1:]:
        cells = line.split(",")
        out.append(",".join(cells[i] for i in index))
    return "\n".join(out) + "\n"


def header_lines(text):
    """Leading comment lines and the column header of a CSV."""
    out = []
    for line in text.splitlines():
        out.append(line)
        if not line.startswith("#"):
            break
    return "\n".join(out) + "\n"


# ------------------------------------------------------------------ cases
# Each returns {file name: content}; the file's extension selects the comparison.

def case_help(run):
    return {"help.entries": run.normal(run.swum("--help").stdout)}


def make_help_case(sub):
    def case(run):
        return {f"help_{sub}.entries": run.normal(run.swum(sub, "--help").stdout)}
    return case


def case_emu_help(run):
    r = subprocess.run([EMU, "--help"], cwd=SOURCE, capture_output=True, text=True, timeout=60)
    if r.returncode != 0:
        raise AssertionError(f"swum-emu --help: exit {r.returncode}\n{r.stderr}")
    return {"emu_help.entries": run.normal(r.stdout)}


def case_modes(run):
    return {"modes.json": run.swum("modes", "--config", CONFIG, "--json").stdout,
            "modes_literal.json": run.swum("modes", "--config", LITERAL, "--json").stdout,
            "modes.txt": run.swum("modes", "--config", CONFIG).stdout,
            "modes_literal.txt": run.swum("modes", "--config", LITERAL).stdout}


def case_stator(run):
    grid = ["--config", CONFIG, "--amplitude-v", "100,400", "--frequency-hz", "38600:39600:200"]
    backbone = run.path("backbone.csv")
    csv_out = run.swum("stator", *grid, "--backbone", backbone)
    return {"stator.json": run.swum("stator", *grid, "--json").stdout,
            "stator.csv": csv_out.stdout,
            "stator_backbone.csv": read(backbone)}


def case_pick(run):
    sweep = f"{INPUTS}/pick_sweep.csv"
    schedule = run.path("schedule.csv")
    j = run.swum("pick", "--sweep", sweep, "--amplitude-v", "100,300,400", "--json", "--schedule", schedule)
    return {"pick.json": j.stdout,
            "pick_schedule.txt": read(schedule),
            "pick.txt": run.swum("pick", "--sweep", sweep, "--amplitude-v", "100,300,400").stdout,
            "pick_load_margin.json": run.swum("pick", "--sweep", sweep, "--amplitude-v", "400,100,300", "--load", "1",
                                              "--margin-hz", "100", "--json").stdout,
            "pick_one.txt": run.swum("pick", "--sweep", sweep, "--amplitude-v", "300").stdout}


def case_pick_undecided(run):
    r = run.swum("pick", "--sweep", f"{INPUTS}/pick_sweep_coarse.csv", "--amplitude-v", "100", expect=1)
    return {"pick_undecided.txt": f"exit {r.returncode}\n--- stdout\n{r.stdout}--- stderr\n{run.normal(r.stderr)}"}


def case_sweep_model(run):
    out = run.path("sweep.csv")
    r = run.swum("sweep", "--config", CONFIG, "--amplitude-v", "200,300", "--frequency-hz", "39800:40000:100", "--load", "0,0.5",
                 "--jobs", "1", "--out", out)
    text = read(out)
    return {"sweep_model.header.txt": header_lines(text),
            "sweep_model.inputs.txt": csv_columns(text, ["amplitude_v", "frequency_hz", "load_n", "status"]),
            "sweep_model.stdout.txt": run.normal(r.stdout)}


def case_synth(run):
    points = f"{INPUTS}/synth_points.csv"
    out1, out2 = run.path("synth1.csv"), run.path("synth2.csv")
    r1 = run.swum("synth", "--config", CONFIG, "--points", points, "--seed", "7", "--repeats", "2", "--jobs", "1",
                  "--out", out1)
    r2 = run.swum("synth", "--config", CONFIG, "--effect", "thermal", "--effect", "preload:preload_factor=1.5",
                  "--linear", "--points", points, "--seed", "7", "--noise", "0", "--speed-floor-mm-s", "0.5",
                  "--frequency-jitter-hz", "2", "--quantities", "speed,tip_normal", "--jobs", "1", "--out", out2)
    t1, t2 = read(out1), read(out2)
    inputs = ["amplitude_v", "frequency_hz", "load_n", "time_s", "sweep"]
    return {"synth.header.txt": header_lines(t1),
            "synth.inputs.txt": csv_columns(t1, inputs),
            "synth.stdout.txt": run.normal(r1.stdout),
            "synth_effects.header.txt": header_lines(t2),
            "synth_effects.inputs.txt": csv_columns(t2, inputs),
            "synth_effects.stdout.txt": run.normal(r2.stdout)}


def case_errors(run):
    """Exit status and message of usage errors a restructured main() must keep."""
    calls = [[], ["nosuch"], ["modes", "--config"], ["modes", "--config", "nothere.toml"], ["modes", "--config", CONFIG, "--bogus"],
             ["pick", "--sweep", f"{INPUTS}/pick_sweep.csv", "--amplitude-v", "250"],
             ["sweep", "--config", CONFIG, "--amplitude-v", "100", "--frequency-hz", "40000"],
             ["log", "--out", run.path("x.csv")],
             ["sweep", "--config", CONFIG, "--modbus", "tcp://127.0.0.1:1", "--amplitude-v", "100", "--frequency-hz", "40000",
              "--out", run.path("y.csv")],
             ["sweep", "--modbus", "tcp://127.0.0.1:1", "--amplitude-v", "100", "--frequency-hz", "40000", "--out", run.path("z.csv")],
             ["pick", "--sweep", f"{INPUTS}/missing.csv", "--amplitude-v", "100"],
             # a retired spelling (issue 34): one line naming the new one, before the missing --out
             ["sweep", "--config", CONFIG, "--amplitude-v", "100", "--frequency", "40000"]]
    lines = []
    for args in calls:
        r = run.swum(*args, expect=None)
        lines.append(f"$ swum {' '.join(args)}\nexit {r.returncode}\n--- stdout\n{run.normal(r.stdout)}--- stderr\n"
                     f"{run.normal(r.stderr)}")
    return {"errors.txt": run.normal("\n".join(lines))}


class Emulator:
    def __init__(self, *args):
        self.proc = subprocess.Popen([EMU, "--config", CONFIG, "--modbus", "tcp://127.0.0.1:0", *args], cwd=SOURCE,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.ready = self.proc.stdout.readline()
        m = re.search(r"modbus=tcp://([\d.]+):(\d+)", self.ready)
        if not m:
            self.proc.kill()
            raise AssertionError(f"swum-emu did not start: {self.ready!r} {self.proc.stderr.read()}")
        self.endpoint = f"tcp://127.0.0.1:{m.group(2)}"

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.communicate(timeout=30)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.communicate()


def case_live_modbus(run):
    """`swum log` and `swum sweep --modbus` against swum-emu: file layouts only (the values are
    live and timed); and swum-emu's ready line, which harnesses parse.

    Every wait is on a condition: the ready line, the exit of each command. The link's wall-time
    limits are hang guards only (in no output): under CPU load swum-emu, whose loop wants more
    than a core at --speedup 4, stalls for longer than swum's defaults (1 s to connect, 0.5 s
    per answer), and a run failed on such a stall, not on anything it checks."""
    link = ["--connect-timeout-ms", "60000", "--timeout-ms", "60000"]
    with Emulator("--speedup", "4", "--watchdog-ms", "5000") as emu:
        ready = re.sub(r"modbus=tcp://127\.0\.0\.1:\d+", "modbus=tcp://127.0.0.1:PORT", emu.ready)
        ready = re.sub(r"pid=\d+", "pid=PID", ready)
        log = run.path("log.csv")
        run.swum("log", "--modbus", emu.endpoint, *link, "--duration-s", "0.2", "--out", log)
        sweep = run.path("live_sweep.csv")
        r = run.swum("sweep", "--modbus", emu.endpoint, *link, "--amplitude-v", "100,150", "--frequency-hz", "40000:40200:100",
                     "--settle-ms", "5", "--dwell-ms", "5", "--out", sweep)
        log_text, sweep_text = read(log), read(sweep)
    cells = {len(l.split(",")) for l in log_text.splitlines()}
    return {"emu_ready.txt": ready,
            "log.header.txt": header_lines(log_text) + f"cells per line: {sorted(cells)}\n",
            "sweep_modbus.header.txt": header_lines(sweep_text),
            "sweep_modbus.inputs.txt": csv_columns(sweep_text, ["amplitude_v", "frequency_hz", "load_n", "sweep", "status"]),
            "sweep_modbus.stdout.txt": run.normal(r.stdout)}


CASES = {"help": case_help}
for _sub in SUBCOMMANDS:
    CASES[f"help_{_sub}"] = make_help_case(_sub)
CASES.update({"emu_help": case_emu_help, "modes": case_modes, "stator": case_stator, "pick": case_pick,
              "pick_undecided": case_pick_undecided, "sweep_model": case_sweep_model, "synth": case_synth,
              "errors": case_errors, "live_modbus": case_live_modbus})


# ------------------------------------------------------------------ comparison
def json_diff(expected, actual, where="$"):
    if isinstance(expected, bool) or isinstance(actual, bool):
        return None if expected is actual else f"{where}: {expected!r} vs {actual!r}"
    if isinstance(expected, (int, float)) and isinstance(actual, (int, float)):
        if isinstance(expected, int) and isinstance(actual, int):
            return None if expected == actual else f"{where}: {expected} vs {actual}"
        if expected == actual or abs(expected - actual) <= 1e-9 * max(abs(expected), abs(actual)):
            return None
        return f"{where}: {expected!r} vs {actual!r}"
    if type(expected) is not type(actual):
        return f"{where}: {expected!r} vs {actual!r}"
    if isinstance(expected, dict):
        if list(expected) != list(actual):
            return f"{where}: keys {list(expected)} vs {list(actual)}"
        for k in expected:
            d = json_diff(expected[k], actual[k], f"{where}.{k}")
            if d:
                return d
        return None
    if isinstance(expected, list):
        if len(expected) != len(actual):
            return f"{where}: {len(expected)} elements vs {len(actual)}"
        for i, (e, a) in enumerate(zip(expected, actual)):
            d = json_diff(e, a, f"{where}[{i}]")
            if d:
                return d
        return None
    return None if expected == actual else f"{where}: {expected!r} vs {actual!r}"


NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def last_digit_unit(text):
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.partition(".")[2])
    return 10.0 ** (-decimals + (int(exponent) if exponent else 0))


def csv_diff(expected, actual):
    e_lines, a_lines = expected.splitlines(), actual.splitlines()
    if len(e_lines) != len(a_lines):
        return f"{len(e_lines)} lines vs {len(a_lines)}"
    for n, (e, a) in enumerate(zip(e_lines, a_lines), 1):
        if e == a:
            continue
        if n == 1 or e.startswith("#"):
            return f"line {n}: {e!r} vs {a!r}"
        ec, ac = e.split(","), a.split(",")
        if len(ec) != len(ac):
            return f"line {n}: {len(ec)} cells vs {len(ac)}"
        for c, (x, y) in enumerate(zip(ec, ac), 1):
            if x == y:
                continue
            if NUMBER.match(x) and NUMBER.match(y):
                fx, fy = float(x), float(y)
                if abs(fx - fy) <= max(1.0001 * last_digit_unit(x), 1e-9 * max(abs(fx), abs(fy))):
                    continue
            return f"line {n} cell {c}: {x!r} vs {y!r}"
    return None


def help_entries(text):
    entries = []
    for line in text.splitlines():
        if not line.strip():
            continue
        indent = len(line) - len(line.lstrip(" "))
        if indent >= 10 and entries:
            entries[-1] += " " + line.strip()
        else:
            entries.append(line.strip())
    return [" ".join(e.split()) for e in entries]


def entries_diff(expected, actual):
    want, have = help_entries(expected), help_entries(actual)
    i = 0
    for entry in want:
        while i < len(have) and have[i] != entry:
            i += 1
        if i == len(have):
            return f"entry missing, changed or out of order: {entry!r}"
        i += 1
    return None


def compare(name, expected, actual):
    if name.endswith(".json"):
        try:
            e, a = json.loads(expected), json.loads(actual)
        except json.JSONDecodeError as error:
            return f"not JSON: {error}"
        return json_diff(e, a)
    if name.endswith(".csv"):
        return csv_diff(expected, actual)
    if name.endswith(".entries"):
        return entries_diff(expected, actual)
    if expected == actual:
        return None
    for n, (e, a) in enumerate(zip(expected.splitlines(), actual.splitlines()), 1):
        if e != a:
            return f"line {n}: {e!r} vs {a!r}"
    return f"{len(expected.splitlines())} lines vs {len(actual.splitlines())} (or a final newline differs)"


def produce(case):
    out = tempfile.mkdtemp(prefix=f"swum-golden-{case}-")
    try:
        return CASES[case](Run(out))
    finally:
        shutil.rmtree(out, ignore_errors=True)


def main(argv):
    if argv[1:] == ["--list"]:
        print("\n".join(CASES))
        return 0
    if argv[1:2] == ["--regenerate"]:
        os.makedirs(EXPECTED, exist_ok=True)
        for case in argv[2:] or list(CASES):
            for name, content in produce(case).items():
                with open(os.path.join(EXPECTED, name), "w") as f:
                    f.write(content)
                print(f"wrote tests/golden/cli/{name}")
        return 0
    if len(argv) != 2 or argv[1] not in CASES:
        print(__doc__, file=sys.stderr)
        return 2
    failures = 0
    for name, actual in produce(argv[1]).items():
        path = os.path.join(EXPECTED, name)
        if not os.path.exists(path):
            print(f"FAIL {name}: no stored output tests/golden/cli/{name}")
            failures += 1
            continue
        problem = compare(name, read(path), actual)
        if problem:
            failures += 1
            print(f"FAIL {name}: {problem}\n--- actual output:\n{actual}")
        else:
            print(f"ok   {name}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
