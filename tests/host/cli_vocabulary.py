#!/usr/bin/python3
"""One name per idea on the command line (issue 34): walks `swum --help`, every `swum SUB --help`
and `swum-emu --help` of the built binaries and fails on

  (a) a retired spelling still offered (the tables of host/commands/retired_options.cpp and
      firmware_sim/app/emu_options.cpp), a retired spelling whose new spelling nobody offers, or
      a retired spelling the binary does not answer with "OLD was renamed NEW" (a row without a
      new spelling: "OLD was removed") and a non-zero status;
  (b) a synonym pair: two names of one group of SYNONYM_GROUPS offered anywhere (in one command
      or across commands);
  (c) a unit mismatch: one option name whose unit (from the name's suffix, e.g. -hz, -ms, or the
      help's parentheses, e.g. "(Hz)", "(device time, ms)") differs between commands, or between
      its name and its help;
  (d) a duration, frequency or voltage option (by its name) with no unit in its name or help.

  cli_vocabulary.py help        the real binaries (SWUM_BINARY, SWUM_EMU, SWUM_SOURCE_DIR; by
                                hand they default to build/ci of this checkout)
  cli_vocabulary.py self-test   the checks on fixture help texts: a clean one passes and each
                                deliberately broken one fails with the check it breaks
"""
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.environ.get("SWUM_SOURCE_DIR", os.path.normpath(os.path.join(HERE, "..", "..")))
SWUM = os.environ.get("SWUM_BINARY", os.path.join(SOURCE_DIR, "build/ci/host/swum"))
SWUM_EMU = os.environ.get("SWUM_EMU", os.path.join(SOURCE_DIR, "build/ci/firmware_sim/swum-emu"))
RETIRED_TABLES = {"swum": "host/commands/retired_options.cpp", "swum-emu": "firmware_sim/app/emu_options.cpp"}

# Names that mean one idea; at most one of each group may be offered anywhere. A retired spelling
# belongs to the retired tables (check a); these groups also hold names nobody has used yet.
SYNONYM_GROUPS = [
    ("worker threads", {"--jobs", "--threads", "--workers", "--num-threads"}),
    ("a directory of plots", {"--plot-dir", "--plots", "--plot-directory", "--figures"}),
    ("a run length", {"--duration-s", "--duration", "--run-s", "--length-s", "--time-s"}),
    ("the sampling window per point", {"--dwell-ms", "--window-ms", "--sample-ms"}),
    ("the drive frequency", {"--frequency-hz", "--frequency", "--freq", "--freq-hz"}),
    ("the drive phase (B ahead of A)", {"--drive-phase-deg", "--phase", "--phase-b-deg"}),
    ("the motional-phase set-point", {"--motional-phase-deg", "--phase-deg"}),
    ("the lowest drive frequency", {"--min-frequency-hz", "--min-hz", "--frequency-min"}),
    ("the highest drive frequency", {"--max-frequency-hz", "--max-hz", "--frequency-max"}),
    ("the largest load", {"--max-load-n", "--load-max"}),
    ("the frequency slew limit", {"--frequency-slew-hz-per-s", "--frequency-slew"}),
    ("the load force", {"--load", "--load-n", "--force-n"}),
    # The voltage vocabulary: the terminal amplitude of one phase, in V.
    ("the amplitude limit", {"--max-amplitude-v", "--max-vpp", "--amplitude-max"}),
    ("the amplitude slew limit", {"--amplitude-slew-v-per-s", "--vpp-slew", "--ramp-vpp-per-s", "--amplitude-slew"}),
    ("the drive amplitude", {"--amplitude-v", "--vpp", "--amplitude", "--voltage-v"}),
]

# Units: an option name's suffix (longest first) and the words a help text states them with.
NAME_UNITS = [("hz-per-s", "Hz/s"), ("hz-per-deg", "Hz/deg"), ("v-per-s", "V/s"), ("vpp-per-s", "Vpp/s"), ("mm-s", "mm/s"), ("hz", "Hz"),
              ("ms", "ms"), ("us", "us"), ("s", "s"), ("deg", "deg"), ("n", "N"), ("v", "V"), ("vpp", "Vpp"),
              ("k", "K"), ("c", "degC"), ("um", "um"), ("mm", "mm"), ("bytes", "bytes"), ("cycles", "cycles"),
              ("ticks", "ticks")]
HELP_UNITS = {"Hz": "Hz", "kHz": "kHz", "Hz/s": "Hz/s", "Hz/deg": "Hz/deg", "ms": "ms", "s": "s", "us": "us", "µs": "us", "N": "N",
              "V": "V", "Vpp": "Vpp", "V peak-to-peak": "Vpp", "V/s": "V/s", "Vpp/s": "Vpp/s", "deg": "deg",
              "degrees": "deg", "K": "K", "degC": "degC", "°C": "degC", "mm/s": "mm/s", "um": "um", "µm": "um",
              "mm": "mm", "m": "m", "A": "A", "mA": "mA"}
# Which quantity an option sets, by the words of its name: these must state a unit (check d).
QUANTITY_WORDS = {
    "duration": {"duration", "timeout", "interval", "period", "window", "dwell", "settle", "delay", "watchdog",
                 "heartbeat", "skip", "block", "cycle"},
    "frequency": {"frequency", "rate", "hz"},
    "voltage": {"vpp", "voltage", "volt", "amplitude"},
}


HELP_COLUMN = 30  # where CLI11's help puts an option's description
TYPE = r"[A-Z][A-Z0-9_]*(?=[:= ]|$)"  # CLI11's type name: TEXT, FLOAT, INT, UINT, MS...


class Option:
    def __init__(self, names, spec, help_text):
        self.names = names  # every spelling of one option, e.g. ["--duration-s"]
        self.spec = spec  # CLI11's type, check, default and constraints, e.g. "FLOAT=60"
        self.help = help_text

    @property
    def is_flag(self):
        return not re.match(TYPE, self.spec)

    @property
    def is_choice(self):
        return "{" in self.spec.split(" ")[0]


def parse_help(text):
    """CLI11 help text -> [Option] of its Options section (descriptions joined across lines)."""
    options = []
    section = None
    for line in text.splitlines():
        if re.match(r"^\S.*:$", line):
            section = line[:-1]
            continue
        if section != "Options":
            continue
        m = re.match(r"^  (-\S+)(.*)$", line)
        if m:
            names = m.group(1).split(",")
            # CLI11 pads the name, type and constraints to column 30 and starts the description
            # there, or on the next line when they are longer.
            if len(line) > HELP_COLUMN and line[HELP_COLUMN - 1] == " " and line[HELP_COLUMN] != " ":
                spec, help_text = line[len(m.group(1)) + 2:HELP_COLUMN].strip(), line[HELP_COLUMN:].strip()
            else:
                spec, help_text = m.group(2).strip(), ""
            if not help_text and not re.match(TYPE, spec) and not spec.startswith(("Excludes", "Needs")):
                spec, help_text = "", spec  # a flag: its description only
            options.append(Option(names, spec, help_text))
        elif options and re.match(r"^\s{6,}\S", line):
            options[-1].help = (options[-1].help + " " + line.strip()).strip()
    return options


def long_names(option):
    return [n for n in option.names if n.startswith("--")]


def name_unit(name):
    stem = name.lstrip("-")
    for suffix, unit in NAME_UNITS:
        if stem == suffix or stem.endswith("-" + suffix):
            return unit
    return None


def help_unit(text):
    """The first unit the help states in parentheses: "(Hz)", "(device time, ms)", "(deg, -90..30)"."""
    for group in re.findall(r"\(([^()]*)\)", text):
        for piece in re.split(r"[;,]", group):
            piece = piece.strip()
            words = piece.split()
            # the piece, its first word, or the last of two ("emulated ms"; not a placeholder: "--sync-ticks N")
            for candidate in [piece] + words[:1] + (words[-1:] if len(words) == 2 else []):
                if candidate in HELP_UNITS:
                    return HELP_UNITS[candidate]
    return None


def quantity(name):
    words = set(name.lstrip("-").split("-"))
    for kind, keys in QUANTITY_WORDS.items():
        if words & keys:
            return kind
    return None


def check(programs, retired):
    """programs: {"swum sweep": [Option]}; retired: [(table, old, new)] -> [problem line]."""
    problems = []
    offered = {}  # name -> [program]
    for program, options in programs.items():
        for option in options:
            for name in long_names(option):
                offered.setdefault(name, []).append(program)
    # (a) retired spellings
    for table, old, new in retired:
        if old in offered:
            problems.append(f"(a) {old} is retired ({table}: renamed {new}) but offered by {', '.join(offered[old])}")
        if new and new not in offered:
            problems.append(f"(a) {table}: {old} was renamed {new}, which no command offers")
    # (b) synonym pairs
    for idea, group in SYNONYM_GROUPS:
        names = sorted(n for n in group if n in offered)
        if len(names) > 1:
            where = "; ".join(f"{n} ({', '.join(offered[n])})" for n in names)
            problems.append(f"(b) {idea} under {len(names)} names: {where}")
    # (c) units: between an option's name and its help, and between commands
    units = {}  # name -> {unit: [program]}
    for program, options in programs.items():
        for option in options:
            if option.is_flag or option.is_choice:
                continue
            stated = help_unit(option.help)
            for name in long_names(option):
                from_name = name_unit(name)
                if from_name and stated and from_name != stated:
                    problems.append(f"(c) {program} {name}: the name says {from_name}, the help ({stated})")
                unit = from_name or stated
                if unit:
                    units.setdefault(name, {}).setdefault(unit, []).append(program)
                # (d) a duration, frequency or voltage without a unit
                kind = quantity(name)
                if kind and not unit:
                    problems.append(f"(d) {program} {name}: a {kind} with no unit in its name or help")
    for name, by_unit in sorted(units.items()):
        if len(by_unit) > 1:
            where = "; ".join(f"{u} in {', '.join(p)}" for u, p in sorted(by_unit.items()))
            problems.append(f"(c) {name} in different units: {where}")
    return problems


def read_retired_tables():
    """[(table, old, new)] of both programs' tables, from the sources."""
    rows = []
    for program, path in RETIRED_TABLES.items():
        with open(os.path.join(SOURCE_DIR, path)) as f:
            text = f.read()
        table = re.search(r"(?:kRetired|kRetiredEmuOptions\[\])[ =]*\{(.*?)\n\};", text, re.S)
        found = re.findall(r'\{"(--[a-z0-9-]+)", "((?:--[a-z0-9-]+)?)", "', table.group(1) if table else "")
        if not found:
            raise SystemExit(f"cli_vocabulary: no retired spellings found in {path} (has the table moved?)")
        rows += [(f"{program}: {path}", old, new) for old, new in found]
    return rows


def run(argv):
    return subprocess.run(argv, capture_output=True, text=True, timeout=60, cwd=SOURCE_DIR)


def walk_binaries():
    """{"swum SUB": [Option], "swum-emu": [Option]} from the binaries' --help."""
    top = run([SWUM, "--help"])
    if top.returncode != 0:
        raise SystemExit(f"cli_vocabulary: {SWUM} --help failed: {top.stderr.strip()}")
    subcommands = []
    section = None
    for line in top.stdout.splitlines():
        if re.match(r"^\S.*:$", line):
            section = line[:-1]
        elif section == "Subcommands" and re.match(r"^  \S", line):
            subcommands.append(line.split()[0])
    if len(subcommands) < 10:
        raise SystemExit(f"cli_vocabulary: only {subcommands} found in swum --help")
    programs = {}
    for sub in subcommands:
        out = run([SWUM, sub, "--help"])
        programs[f"swum {sub}"] = parse_help(out.stdout)
    programs["swum-emu"] = parse_help(run([SWUM_EMU, "--help"]).stdout)
    for program, options in programs.items():
        if not any("--help" in o.names for o in options):
            raise SystemExit(f"cli_vocabulary: no options parsed from {program} --help")
    return programs


def check_answers(programs, retired):
    """Each retired spelling on the command line of a command offering its new spelling: one line
    naming the new spelling on stderr, a non-zero status."""
    problems = []
    for table, old, new in retired:
        program = "swum-emu" if table.startswith("swum-emu") else next(
            (p for p, opts in programs.items() if p != "swum-emu" and any(new in o.names for o in opts)),
            None if new else "swum sweep")  # a removed option: any command answers it
        if program is None:
            continue  # reported by check (a)
        argv = [SWUM_EMU] if program == "swum-emu" else [SWUM, program.split(" ", 1)[1]]
        result = run(argv + [old, "1"])
        expected = f"{old} was renamed {new}" if new else f"{old} was removed"
        lines = result.stderr.splitlines()
        if result.returncode == 0 or len(lines) != 1 or expected not in lines[0] or not lines[0].startswith(program):
            problems.append(f"(a) `{program} {old} 1` answered status {result.returncode}, stderr {result.stderr!r}; "
                            f"expected one line '{program}: {expected} (...)'")
    return problems


# Fixture help texts for the self-test: CLEAN passes; each of BROKEN fails with its check.
CLEAN = {
    "swum sweep": """Steady speed
Usage: swum sweep [OPTIONS]

Options:
  -h,--help                   Print this help message and exit
  --vpp TEXT REQUIRED         drive voltages, comma list (V peak-to-peak)
  --frequency-hz TEXT REQUIRED
                              START:STOP:STEP or one value (Hz); swept downward on a device
  --load TEXT=0               loads, comma list (N)
  --temperature-rise-k TEXT=0 stator temperature rises over ambient, comma list (K, 0..300)
  --jobs INT                  worker threads, model only (default: all cores)
  --dwell-ms FLOAT=50         device: sampling window per point (device time, ms)
  --resume                    continue the unfinished sweep
""",
    "swum-emu": """swum-emu
Usage: swum-emu [OPTIONS]

Options:
  -h,--help                   Print this help message and exit
  --clock TEXT:{internal,external}=internal
                              internal: run on wall time
  --tick-hz FLOAT:FLOAT in [100 - 100000]=10000
                              loop rate
  --watchdog-ms FLOAT:NONNEGATIVE=100
                              command timeout while enabled (emulated ms; 0 = off)
  --frequency-hz FLOAT=40000  initial frequency setpoint (Hz)
""",
}
CLEAN_RETIRED = [("swum: table", "--frequency", "--frequency-hz"), ("swum: table", "--threads", "--jobs")]
BROKEN = [  # (check, what is broken, program, a line replaced -> its replacement, or a line added)
    ("(a)", "a retired spelling offered", "swum-emu", "  --frequency-hz FLOAT=40000  initial frequency setpoint (Hz)",
     "  --frequency FLOAT=40000     initial frequency setpoint (Hz)"),
    ("(b)", "worker threads under two names", "swum-emu", None,
     "  --workers INT               worker threads"),
    ("(c)", "--load in N in one command, in mA in another", "swum-emu", None,
     "  --load FLOAT=0              load force (mA)"),
    ("(c)", "a name in ms, its help in s", "swum sweep", "  --dwell-ms FLOAT=50         device: sampling window per point (device time, ms)",
     "  --dwell-ms FLOAT=50         device: sampling window per point (s)"),
    ("(d)", "a duration without a unit", "swum-emu", None,
     "  --heartbeat FLOAT=1000      CAN heartbeat period (0 = off)"),
    ("(d)", "a frequency without a unit", "swum sweep", None,
     "  --sample-rate FLOAT=100     how often to sample"),
    ("(d)", "a voltage without a unit", "swum sweep", "  --vpp TEXT REQUIRED         drive voltages, comma list (V peak-to-peak)",
     "  --amplitude TEXT REQUIRED   drive voltages, comma list"),
]


def self_test():
    failures = []
    clean = {p: parse_help(t) for p, t in CLEAN.items()}
    parsed = {p: [(o.names, o.spec, o.help) for o in opts] for p, opts in clean.items()}
    expected_sweep = [(["-h", "--help"], "", "Print this help message and exit"),
                      (["--vpp"], "TEXT REQUIRED", "drive voltages, comma list (V peak-to-peak)"),
                      (["--frequency-hz"], "TEXT REQUIRED",
                       "START:STOP:STEP or one value (Hz); swept downward on a device"),
                      (["--load"], "TEXT=0", "loads, comma list (N)"),
                      (["--temperature-rise-k"], "TEXT=0",
                       "stator temperature rises over ambient, comma list (K, 0..300)"),
                      (["--jobs"], "INT", "worker threads, model only (default: all cores)"),
                      (["--dwell-ms"], "FLOAT=50", "device: sampling window per point (device time, ms)"),
                      (["--resume"], "", "continue the unfinished sweep")]
    if parsed["swum sweep"] != expected_sweep:
        failures.append(f"parse_help: {parsed['swum sweep']}")
    for text, unit in [("(Hz)", "Hz"), ("x (device time, ms)", "ms"), ("(deg, -90..30)", "deg"),
                       ("(V peak-to-peak)", "Vpp"), ("(emulated ms; 0 = off)", "ms"), ("(0: all cores)", None),
                       ("lockstep (--canopen --sync-ticks): rate", None), ("(K, 0..300; needs x)", "K")]:
        if help_unit(text) != unit:
            failures.append(f"help_unit({text!r}) = {help_unit(text)!r}, expected {unit!r}")
    for name, unit in [("--frequency-slew-hz-per-s", "Hz/s"), ("--speed-mm-s", "mm/s"), ("--skip-s", "s"),
                       ("--phase-gain-hz-per-deg", "Hz/deg"), ("--max-load-n", "N"), ("--amplitude-v", "V"), ("--load", None), ("--modbus", None)]:
        if name_unit(name) != unit:
            failures.append(f"name_unit({name!r}) = {name_unit(name)!r}, expected {unit!r}")
    problems = check(clean, CLEAN_RETIRED)
    if problems:
        failures.append(f"the clean fixture fails: {problems}")
    for tag, what, program, old_line, new_line in BROKEN:
        texts = dict(CLEAN)
        if old_line is None:
            texts[program] = texts[program] + new_line + "\n"
        else:
            assert old_line in texts[program], old_line
            texts[program] = texts[program].replace(old_line, new_line)
        problems = check({p: parse_help(t) for p, t in texts.items()}, CLEAN_RETIRED)
        if not any(p.startswith(tag) for p in problems):
            failures.append(f"{what}: no {tag} problem reported (got {problems})")
        else:
            print(f"ok: {what}: {next(p for p in problems if p.startswith(tag))}")
    for f in failures:
        print(f"FAIL: {f}")
    return 1 if failures else 0


def main():
    if len(sys.argv) != 2 or sys.argv[1] not in ("help", "self-test"):
        print(__doc__, file=sys.stderr)
        return 2
    if sys.argv[1] == "self-test":
        return self_test()
    programs = walk_binaries()
    retired = read_retired_tables()
    problems = check(programs, retired) + check_answers(programs, retired)
    for p in problems:
        print(p)
    print(f"{len(programs)} commands, {sum(len(o) for o in programs.values())} options, "
          f"{len(retired)} retired spellings: {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
