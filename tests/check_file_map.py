#!/usr/bin/env python3
"""docs/architecture.md's file map against the tree (ctest `file_map`).

Every source file under include/, src/ and python/ (.hpp, .h, .cpp) must be
named in the map's code block ("Where things live"), by its path under
include/ or by its file name; every file name the map gives must exist. Brace
forms expand: sdm_{grid,map}.cpp is sdm_grid.cpp and sdm_map.cpp, and
live_plot.{hpp,cpp} is both. Exit 1 naming each file missing either way.

    python3 tests/check_file_map.py [SOURCE_DIR]
"""
import itertools
import os
import re
import sys

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXTS = (".hpp", ".h", ".cpp")


def expand(token):
    """All names a brace form stands for."""
    parts = re.split(r"(\{[^{}]*\})", token)
    choices = [p[1:-1].split(",") if p.startswith("{") else [p] for p in parts]
    return ["".join(c) for c in itertools.product(*choices)]


def map_block():
    text = open(os.path.join(ROOT, "docs", "architecture.md"), encoding="utf-8").read()
    m = re.search(r"# Where things live\s*```(.*?)```", text, re.S)
    if not m:
        sys.exit("check_file_map: docs/architecture.md has no file map (a code block under '# Where things live')")
    return m.group(1)


def named(block):
    """File names and include paths the map gives."""
    # A brace form broken over lines (config_{process,structure,\n   positions}.cpp) is one token.
    block = re.sub(r"\{[^{}]*\}", lambda m: re.sub(r"\s+", "", m.group(0)), block)
    names = set()
    for token in re.findall(r"[A-Za-z0-9_./{},+-]+", block):
        token = token.strip(".,;:()")
        for name in expand(token):
            name = name.strip(".,;:()")
            if name.endswith(EXTS):
                names.add(name)
    return names


def sources():
    out = []
    for top in ("include", "src", "python"):
        for d, _, files in os.walk(os.path.join(ROOT, top)):
            for f in files:
                if f.endswith(EXTS):
                    out.append(os.path.relpath(os.path.join(d, f), ROOT))
    return sorted(out)


def main():
    names = named(map_block())
    files = sources()
    basenames = {os.path.basename(f) for f in files}
    include_paths = {os.path.relpath(f, os.path.join("include", "chatter")) for f in files if f.startswith("include")}
    unnamed = []
    for f in files:
        base = os.path.basename(f)
        if f.startswith("include"):
            rel = os.path.relpath(f, os.path.join("include", "chatter"))
            if rel not in names and base not in names:
                unnamed.append(f)
        elif base not in names:
            unnamed.append(f)
    absent = sorted(n for n in names if os.path.basename(n) not in basenames and n not in include_paths)
    for f in unnamed:
        print(f"check_file_map: {f}: not in docs/architecture.md's file map")
    for n in absent:
        print(f"check_file_map: docs/architecture.md names {n}, which is not in include/, src/ or python/")
    if unnamed or absent:
        return 1
    print(f"check_file_map: {len(files)} source files, every one in the map and every named file present")
    return 0


if __name__ == "__main__":
    sys.exit(main())
