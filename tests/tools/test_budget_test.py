#!/usr/bin/python3
"""tools/test-budget on a real ctest run: a tiny CMake project with a quick test, a deliberately
slow one and a slow one labelled `long`. The slow one fails the budget by name; the long one
does not; bad input gives a one-line error and status 2.

Usage: test_budget_test.py SOURCE_DIR
"""
import os
import subprocess
import sys
import tempfile
import unittest

SOURCE_DIR = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
BUDGET = os.path.join(SOURCE_DIR, "tools", "test-budget")

PROJECT = """cmake_minimum_required(VERSION 3.25)
project(budget_probe NONE)
enable_testing()
add_test(NAME quick COMMAND true)
add_test(NAME deliberately_slow COMMAND sleep 1.5)
add_test(NAME slow_but_long COMMAND sleep 1.5)
set_tests_properties(slow_but_long PROPERTIES LABELS "long")
add_test(NAME slow_and_labelled_otherwise COMMAND sleep 1.5)
set_tests_properties(slow_and_labelled_otherwise PROPERTIES LABELS "host;longer")
"""


def run(*args):
    return subprocess.run([BUDGET, *args], capture_output=True, text=True, timeout=120)


class TestBudget(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        src = os.path.join(cls.tmp.name, "src")
        cls.build = os.path.join(cls.tmp.name, "build")
        os.makedirs(src)
        with open(os.path.join(src, "CMakeLists.txt"), "w") as f:
            f.write(PROJECT)
        subprocess.run(["cmake", "-S", src, "-B", cls.build, "-G", "Ninja"], check=True, capture_output=True)
        cls.junit = os.path.join(cls.tmp.name, "junit.xml")
        subprocess.run(["ctest", "-j4", "--output-junit", cls.junit], cwd=cls.build, check=True, capture_output=True)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_a_slow_test_fails_the_budget_by_name(self):
        r = run("--junit", self.junit, "--build", self.build, "--limit", "1", "--stage", "probe")
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertIn("test 'deliberately_slow' took", r.stderr)
        self.assertIn("over the 1 s limit", r.stderr)
        # A label that merely contains "long" is not the long label.
        self.assertIn("test 'slow_and_labelled_otherwise' took", r.stderr)
        self.assertNotIn("slow_but_long", r.stderr)
        self.assertNotIn("'quick'", r.stderr)

    def test_the_report_lists_the_slowest_first(self):
        r = run("--junit", self.junit, "--build", self.build, "--limit", "60", "--top", "4")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("4 tests", r.stdout)
        rows = [line.split() for line in r.stdout.splitlines()[2:]]
        self.assertEqual(len(rows), 4)
        seconds = [float(row[0]) for row in rows]
        self.assertEqual(seconds, sorted(seconds, reverse=True))
        self.assertEqual(rows[-1][-1], "quick")
        self.assertGreaterEqual(seconds[0], 1.4)

    def test_within_the_limit_passes(self):
        r = run("--junit", self.junit, "--build", self.build, "--limit", "30")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stderr, "")

    def test_another_long_label_exempts_its_tests(self):
        r = run("--junit", self.junit, "--build", self.build, "--limit", "1", "--long-label", "longer")
        self.assertEqual(r.returncode, 1)
        self.assertIn("'slow_but_long'", r.stderr)
        self.assertNotIn("slow_and_labelled_otherwise", r.stderr)

    def assert_one_line_error(self, r, *words):
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        lines = r.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, r.stderr)
        for w in words:
            self.assertIn(w, lines[0])

    def test_bad_input_is_a_one_line_error(self):
        missing = os.path.join(self.tmp.name, "nope.xml")
        self.assert_one_line_error(run("--junit", missing, "--build", self.build, "--limit", "5"), "nope.xml")
        garbage = os.path.join(self.tmp.name, "garbage.xml")
        with open(garbage, "w") as f:
            f.write("<testsuite><testcase name='x' time='soon'/></testsuite>")
        self.assert_one_line_error(run("--junit", garbage, "--build", self.build, "--limit", "5"), "'x'", "soon")
        with open(garbage, "w") as f:
            f.write("not xml")
        self.assert_one_line_error(run("--junit", garbage, "--build", self.build, "--limit", "5"), "not XML")
        self.assert_one_line_error(run("--junit", self.junit, "--build", self.tmp.name, "--limit", "5"))
        nowhere = os.path.join(self.tmp.name, "no-build")
        self.assert_one_line_error(run("--junit", self.junit, "--build", nowhere, "--limit", "5"),
                                   "no-build", "does not exist")
        for limit in ("abc", "0", "nan"):
            self.assert_one_line_error(run("--junit", self.junit, "--build", self.build, "--limit", limit),
                                       "--limit", limit)
        self.assert_one_line_error(run("--junit", self.junit, "--build", self.build, "--limit", "5", "--top", "-1"),
                                   "--top")
        self.assert_one_line_error(run("--junit", self.junit), "--build", "--limit")

    def test_a_long_gtest_that_no_longer_exists_is_an_error(self):
        """A swum_long_gtest line for a renamed test would be skipped by ctest without a word."""
        path = os.path.join(self.build, "swum_long_gtests.cmake")
        try:
            with open(path, "w") as f:
                f.write("set_tests_properties([==[slow_but_long]==] PROPERTIES LABELS [==[long]==] COST 2)\n")
            r = run("--junit", self.junit, "--build", self.build, "--limit", "60")
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(path, "a") as f:
                f.write("set_tests_properties([==[Renamed.Test]==] PROPERTIES LABELS [==[x;long]==] COST 2)\n")
            self.assert_one_line_error(run("--junit", self.junit, "--build", self.build, "--limit", "60"),
                                       "Renamed.Test", "not a test")
            with open(path, "w") as f:
                f.write("set_tests_properties([==[quick]==] PROPERTIES LABELS [==[x;long]==] COST 2)\n")
            self.assert_one_line_error(run("--junit", self.junit, "--build", self.build, "--limit", "60"),
                                       "'quick'", "lacks the label 'long'")
        finally:
            os.remove(path)


if __name__ == "__main__":
    unittest.main(verbosity=2)
