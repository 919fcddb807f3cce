#!/usr/bin/python3
"""The README stays short: the words of its prose before the first heading that starts the
links (default "## Documentation") are at most LIMIT (default 1000). Code blocks, images and
HTML comments do not count: the examples are checked by running them (bench.readme_example).
Usage: readme_length.py README.md [LIMIT] [HEADING]"""
import re
import sys


def main():
    path = sys.argv[1]
    limit = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    heading = sys.argv[3] if len(sys.argv) > 3 else "## Documentation"
    with open(path, encoding="utf-8") as f:
        text = f.read()
    if f"\n{heading}\n" not in text:
        sys.exit(f"FAIL: {path} has no heading {heading!r} before its links")
    prose = text.split(f"\n{heading}\n", 1)[0]
    prose = re.sub(r"^```.*?^```", "", prose, flags=re.S | re.M)
    prose = re.sub(r"<!--.*?-->", "", prose, flags=re.S)
    prose = re.sub(r"!\[[^\]]*\]\([^)]*\)", "", prose)
    prose = re.sub(r"\]\([^)]*\)", "]", prose)  # a link's target is not a word the reader reads
    words = len(prose.split())
    print(f"{path}: {words} words of prose before {heading!r} (at most {limit})")
    if words > limit:
        sys.exit(f"FAIL: {path} has {words} words before its links, more than {limit}: move detail into docs/")


if __name__ == "__main__":
    main()
