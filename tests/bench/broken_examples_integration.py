#!/usr/bin/python3
"""The deliberately broken controllers (bench/broken_examples) fail, and say why: runs them
through tools/bench with --junitxml and checks that each failure names its assertion, the first
violating time and the values there, that the plot it attached is a PNG of that signal, and
that the JUnit XML carries the message and names the plot and the emulator's log.

  broken_examples_integration.py [pytest args, e.g. --swum-transport can]"""
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

REPO = os.environ.get("SWUM_SOURCE_DIR") or os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
EXPECTED = {
    # test name: (assertion and signal, pieces the message must contain)
    "test_flipped_gain_reaches_target": ("assert_settles(speed_mm_s) failed",
                                         ["not within 300 ± 6 mm/s from 0.100000 s", "first violation at t = 0.100000 s",
                                          "value 0 mm/s (off by -300)", "it never settles"]),
    "test_missing_fault_reaction_drives_off": ("assert_reaches(command_amplitude_v) failed",
                                               ["not <= 0 V by 0.103000 s", "at t = 0.103000 s the value is",
                                                "it never does by 0.150000 s"]),
}


def check(condition, message):
    if not condition:
        print("FAIL:", message)
        sys.exit(1)


def main():
    out = tempfile.mkdtemp(prefix="swum-bench-broken-")
    junit = os.path.join(out, "report.xml")
    r = subprocess.run([os.path.join(REPO, "tools", "bench"), os.path.join(REPO, "bench", "broken_examples"), "-q",
                        "--junitxml", junit, "--swum-artifacts", os.path.join(out, "artifacts"), *sys.argv[1:]],
                       capture_output=True, text=True, timeout=600)
    print(r.stdout[-4000:])
    check(r.returncode == 1, f"pytest exited {r.returncode}, expected 1 (tests failed): {r.stderr[-2000:]}")
    check(f"{len(EXPECTED)} failed" in r.stdout, "not every broken controller failed")
    cases = {c.get("name"): c for c in ET.parse(junit).getroot().iter("testcase")}
    check(set(cases) == set(EXPECTED), f"test cases {sorted(cases)}")
    for name, (head, pieces) in EXPECTED.items():
        failure = cases[name].find("failure")
        check(failure is not None, f"{name}: no <failure> in the JUnit XML")
        message = failure.get("message")
        check(head in message, f"{name}: the message does not name the assertion: {message}")
        for piece in pieces:
            check(piece in message, f"{name}: {piece!r} missing from the message: {message}")
        check(head in r.stdout, f"{name}: the terminal report lacks the message")
        props = {p.get("name"): p.get("value") for p in cases[name].iter("property")}
        plot = props.get("swum_plot")
        check(plot and plot in message, f"{name}: the plot is not named in both the message and the XML: {props}")
        with open(plot, "rb") as f:
            check(f.read(8) == b"\x89PNG\r\n\x1a\n", f"{name}: {plot} is not a PNG")
        signal = head.split("(")[1].split(")")[0]
        check(os.path.basename(plot).endswith(f"_{signal}.png"), f"{name}: plot {plot} is not of {signal}")
        log = props.get("swum_emulator_log")
        check(log and os.path.isfile(log), f"{name}: no emulator log named: {props}")
        with open(log) as f:
            check("swum-emu ready" in f.read(), f"{name}: {log} lacks the ready line")
        check("swum-emu log" in r.stdout, "the failing tests' report lacks the emulator log section")
        print(f"{name}: {message}")
    print("PASS")


if __name__ == "__main__":
    main()
