#!/usr/bin/env python3
"""No spindle formula outside include/chatter/kinematics.hpp (ctest `kinematics`).

A spindle speed turns into seconds in one place: include/chatter/kinematics.hpp
(Ω = 2π N / 60, a revolution 60 / N, a tooth period, tooth passing, cutting
and table speed). This check reads every C++ source under src/ and python/,
drops comments and string literals, and fails on a line that has the number
60 beside a spindle quantity (rpm, rev_per_s, spindle, omega, teeth, tooth),
naming the file and line. Minutes and hours (a time in min times 60)
are not spindle formulas and pass.

    python3 tests/check_kinematics.py [SOURCE_DIR]
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cpp_text import blank  # noqa: E402

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SIXTY = re.compile(r"(?<![\w.])60(\.0*)?(?![\w.])")
SPINDLE = re.compile(r"rpm|rev_per_s|spindle|omega|teeth|tooth", re.I)


def code_lines(text):
    """The text with comments and string/char literals blanked, split in lines."""
    return blank(text).split("\n")


def main():
    bad = []
    for top in ("src", "python"):
        for d, _, files in os.walk(os.path.join(ROOT, top)):
            for f in files:
                if not f.endswith((".cpp", ".hpp", ".h")):
                    continue
                path = os.path.join(d, f)
                for k, line in enumerate(code_lines(open(path, encoding="utf-8").read()), 1):
                    if SIXTY.search(line) and SPINDLE.search(line):
                        bad.append(f"{os.path.relpath(path, ROOT)}:{k}: {line.strip()}")
    for b in bad:
        print("check_kinematics: a spindle formula outside include/chatter/kinematics.hpp:", b)
    if bad:
        return 1
    print("check_kinematics: every spindle formula is in include/chatter/kinematics.hpp")
    return 0


if __name__ == "__main__":
    sys.exit(main())
