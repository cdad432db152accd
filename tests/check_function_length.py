#!/usr/bin/env python3
"""No function in src/ or include/ longer than 100 lines (ctest `function_length`).

A function is a brace block opened where only namespaces, classes, structs or
`extern "C"` blocks enclose it, whose head (the text since the previous `;`,
`{` or `}`) has a parameter list and is not an initialiser (`= {`). Its length
counts its lines from the head's `{` to its `}`, lambdas and comments inside
included. Comments and string and character literals are blanked first, so
braces in them do not count. On failure the check names each function with
its file, first line and length.

    python3 tests/check_function_length.py [SOURCE_DIR] [--limit N]
"""
import argparse
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cpp_text import blank  # noqa: E402

PARSER = argparse.ArgumentParser(description="No function over --limit lines in src/ and include/.")
PARSER.add_argument("root", nargs="?", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PARSER.add_argument("--limit", type=int, default=100)
OPTIONS = PARSER.parse_args()
ROOT, LIMIT = OPTIONS.root, OPTIONS.limit
SCOPE = re.compile(r"\b(namespace|class|struct|union|enum)\b|extern\s*\"")
CONTROL = re.compile(r"^\s*(else|if|for|while|switch|do|try|catch)\b")


def long_functions(path):
    text = blank(open(path, encoding="utf-8").read())
    found, stack, head_start = [], [], 0
    line = 1
    for i, c in enumerate(text):
        if c == "\n":
            line += 1
        elif c in ";{}":
            if c == "{":
                head = "\n".join(l for l in text[head_start:i].split("\n") if not l.lstrip().startswith("#"))
                if SCOPE.search(head) and "(" not in head:
                    kind = "scope"
                elif stack and stack[-1][0] != "scope":
                    kind = "inner"
                elif ")" in head and not CONTROL.search(head) and not re.search(r"=\s*$", head):
                    kind = "function"
                else:
                    kind = "inner"
                stack.append((kind, line, " ".join(head.split())[-80:]))
            elif c == "}" and stack:
                kind, first, head = stack.pop()
                if kind == "function" and line - first + 1 > LIMIT:
                    found.append((path, first, line - first + 1, head))
            head_start = i + 1
    return found


def main():
    if not os.path.isdir(os.path.join(ROOT, "src")):
        print(f"{ROOT}: no src/ here (give the source directory)")
        return 2
    bad = []
    for top in ("src", "include"):
        for folder, _, files in os.walk(os.path.join(ROOT, top)):
            for f in sorted(files):
                if f.endswith((".cpp", ".hpp", ".h")):
                    bad += long_functions(os.path.join(folder, f))
    for path, first, n, head in sorted(bad):
        print(f"{os.path.relpath(path, ROOT)}:{first}: a function of {n} lines (limit {LIMIT}): {head}")
    if bad:
        print(f"{len(bad)} function(s) over {LIMIT} lines: split them (docs/architecture.md, Conventions)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
