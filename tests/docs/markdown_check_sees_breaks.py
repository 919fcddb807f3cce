#!/usr/bin/python3
"""check_markdown.py can see what it looks for: on a small fixture written here (in a scratch
folder, so that the checkout itself holds no broken link) with one of each break, it must exit 1
and name each break with its file and line, and it must not flag a table row inside a code block
or a link to a heading that exists. Usage: markdown_check_sees_breaks.py CHECK_MARKDOWN"""
import os
import re
import subprocess
import sys
import tempfile

README = """# A fixture with every break check_markdown.py looks for

| a | b |
|---|---|
| 1 | 2 |

| 3 | 4 |

A [link to no file](missing.md), ![an image that is not there](none.svg), a
[heading that is not there](page.md#nowhere) and one [that is](page.md#a-heading-with-code).
"""
PAGE = """# Page

## A heading with `code`

| x | y |
|---|---|
| 1 | 2 |

| x | y |
|---|---|
| 3 | 4 |

```text
| in a code block: not a table, not a problem |
```
"""
EXPECTED = [
    r"^README.md:7: a table row outside any table .*: \| 3 \| 4 \|$",
    r"^README.md:9: link missing.md: no file missing.md$",
    r"^README.md:9: image none.svg: no file none.svg$",
    r"^README.md:10: link page.md#nowhere: page.md has no heading with the anchor #nowhere$",
    r"^page.md:9: a table split in two by a blank line \(the part above ends at line 7\)$",
    r"^check_markdown: 5 problems in 2 files$",
]


def main():
    folder = tempfile.mkdtemp(prefix="swum-markdown-fixture-")
    for name, text in (("README.md", README), ("page.md", PAGE)):
        with open(os.path.join(folder, name), "w") as f:
            f.write(text)
    r = subprocess.run(["/usr/bin/python3", sys.argv[1], folder, "README.md", "page.md"], capture_output=True, text=True)
    print(r.stdout, r.stderr)
    lines = r.stdout.splitlines()
    missing = [e for e in EXPECTED if not any(re.match(e, line) for line in lines)]
    if r.returncode != 1 or missing or len(lines) != len(EXPECTED):
        sys.exit(f"FAIL: exit {r.returncode}; expected lines not printed: {missing}; {len(lines)} lines printed, "
                 f"{len(EXPECTED)} expected")
    print("PASS")


if __name__ == "__main__":
    main()
