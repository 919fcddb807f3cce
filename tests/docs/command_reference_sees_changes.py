#!/usr/bin/python3
"""tools/gen-command-reference --check can see a difference: on a copy of the page it writes, with
one option renamed, the check must exit 1 and show the changed line; on the unchanged copy it
must pass. Usage: command_reference_sees_changes.py GENERATOR --swum PATH --swum-emu PATH"""
import os
import subprocess
import sys
import tempfile


def main():
    generator, binaries = sys.argv[1], sys.argv[2:]
    page = os.path.join(tempfile.mkdtemp(prefix="swum-commands-"), "commands.md")
    subprocess.run(["/usr/bin/python3", generator, "--file", page, *binaries], check=True)
    same = subprocess.run(["/usr/bin/python3", generator, "--check", "--file", page, *binaries],
                          capture_output=True, text=True)
    if same.returncode != 0:
        sys.exit(f"FAIL: the check fails on the page it just wrote:\n{same.stdout}{same.stderr}")
    with open(page) as f:
        text = f.read()
    if "  --config " not in text:
        sys.exit("FAIL: the generated page lists no --config option")
    with open(page, "w") as f:
        f.write(text.replace("  --config ", "  --configuration ", 1))
    changed = subprocess.run(["/usr/bin/python3", generator, "--check", "--file", page, *binaries],
                             capture_output=True, text=True)
    print(changed.stdout, changed.stderr)
    if changed.returncode != 1 or "-  --configuration " not in changed.stdout or "differs" not in changed.stderr:
        sys.exit(f"FAIL: the check did not report the renamed option (exit {changed.returncode})")
    print("PASS")


if __name__ == "__main__":
    main()
