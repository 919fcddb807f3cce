#!/usr/bin/python3
"""The docs render as written: parses README.md and docs/*.md with a CommonMark parser that knows
GitHub's tables (markdown-it-py, Debian's python3-markdown-it) and fails, naming file and line, on

  - a line starting with `|` (outside code) that the parser does not put inside a table: a row
    cut off from its table by a blank line, or a table without its delimiter row;
  - two tables with only blank lines between them: one table split in two;
  - a relative link or image whose file is not in the checkout, or whose #anchor names no
    heading of that file (anchors as GitHub makes them from headings).

Usage: check_markdown.py ROOT [FILE ...]   (FILEs relative to ROOT; default README.md, docs/*.md)
"""
import glob
import os
import re
import sys
import urllib.parse

try:
    from markdown_it import MarkdownIt
except ImportError:
    sys.exit("check_markdown: error: markdown-it-py is missing (Debian: python3-markdown-it; tools/setup installs it)")

PARSER = MarkdownIt("commonmark").enable("table")
CODE = ("fence", "code_block", "html_block")


def inline_text(token):
    return "".join(c.content for c in (token.children or []) if c.type in ("text", "code_inline"))


def slug(text):
    """GitHub's heading anchor: lower case, punctuation other than - and _ dropped, spaces -> -."""
    return re.sub(r"[^\w\- ]", "", text.strip().lower()).replace(" ", "-")


ANCHORS = {}


def anchors(path):
    if path not in ANCHORS:
        found, seen = set(), {}
        with open(path, encoding="utf-8") as f:
            tokens = PARSER.parse(f.read())
        for i, t in enumerate(tokens):
            if t.type == "heading_open":
                base = slug(inline_text(tokens[i + 1]))
                n = seen.get(base, 0)
                seen[base] = n + 1
                found.add(base if n == 0 else f"{base}-{n}")
            if t.type == "html_block" or t.type == "inline":
                found.update(re.findall(r'<a\s+(?:name|id)="([^"]+)"', t.content))
        ANCHORS[path] = found
    return ANCHORS[path]


def check_file(root, name):
    path = os.path.join(root, name)
    with open(path, encoding="utf-8") as f:
        text = f.read()
    lines = text.splitlines()
    tokens = PARSER.parse(text)
    problems = []
    in_table, in_code = set(), set()
    tables = []
    for t in tokens:
        if t.type == "table_open" and t.map:
            in_table.update(range(*t.map))
            tables.append(t.map)
        elif t.type in CODE and t.map:
            in_code.update(range(*t.map))
    for i, line in enumerate(lines):
        if line.lstrip().startswith("|") and i not in in_table and i not in in_code:
            problems.append(f"{name}:{i + 1}: a table row outside any table (cut off by a blank line, or no "
                            f"delimiter row above it): {line.strip()[:60]}")
    for (_, end), (start, _) in zip(tables, tables[1:]):
        if all(not lines[k].strip() for k in range(end, start)):
            problems.append(f"{name}:{start + 1}: a table split in two by a blank line (the part above ends at line {end})")

    def check_target(target, line_no, what):
        parts = urllib.parse.urlsplit(target)
        if parts.scheme or parts.netloc or target.startswith("//"):
            return
        file_part = urllib.parse.unquote(parts.path)
        where = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
        if not os.path.exists(where):
            problems.append(f"{name}:{line_no}: {what} {target}: no file {os.path.relpath(where, root)}")
            return
        if parts.fragment and where.endswith(".md") and os.path.isfile(where):
            if urllib.parse.unquote(parts.fragment) not in anchors(where):
                problems.append(f"{name}:{line_no}: {what} {target}: {os.path.relpath(where, root)} has no heading "
                                f"with the anchor #{parts.fragment}")

    for t in tokens:
        if t.type != "inline" or not t.map:
            continue
        def line_of(target):
            # The line of the paragraph that holds the target (the token knows the paragraph only).
            for k in range(*t.map):
                if target and target in lines[k]:
                    return k + 1
            return t.map[0] + 1

        for c in t.children or []:
            if c.type == "link_open":
                href = c.attrGet("href") or ""
                check_target(href, line_of(href), "link")
            elif c.type == "image":
                src = c.attrGet("src") or ""
                check_target(src, line_of(src), "image")
    return problems


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    root = os.path.abspath(sys.argv[1])
    names = sys.argv[2:] or ["README.md"] + sorted(os.path.relpath(p, root) for p in glob.glob(os.path.join(root, "docs", "*.md")))
    problems = []
    for name in names:
        problems += check_file(root, name)
    for p in problems:
        print(p)
    if problems:
        print(f"check_markdown: {len(problems)} problems in {len(names)} files")
        sys.exit(1)
    print(f"check_markdown: {len(names)} files render: every table row in a table, every relative link and image present")


if __name__ == "__main__":
    main()
