#!/usr/bin/env python3
"""The library's shape, checked from its sources (docs/architecture.md, "Structure checks").

  test_structure.py file_lines   no file of libwave/src over MAX_LINES lines: a file
                                 that grows past it holds more than one job, and is cut
                                 at its seams (one file per job)
  test_structure.py stage_order  (see stage_order below)

Each prints what it found wrong and exits 1, or exits 0.
"""
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
SRC = ROOT / "libwave" / "src"
MAX_LINES = 900
SOURCE_SUFFIXES = {".cpp", ".h", ".inc", ".in"}


def sources():
    return sorted(p for p in SRC.rglob("*") if p.is_file() and p.suffix in SOURCE_SUFFIXES)


def file_lines():
    problems = []
    for path in sources():
        with open(path, encoding="utf-8") as f:
            lines = sum(1 for _ in f)
        if lines > MAX_LINES:
            problems.append(f"{path.relative_to(ROOT)}: {lines} lines, more than {MAX_LINES}: cut it at its seams")
    return problems


CHECKS = {"file_lines": file_lines}


def main(argv):
    if len(argv) != 2 or argv[1] not in CHECKS:
        print(f"usage: {argv[0]} {'|'.join(CHECKS)}", file=sys.stderr)
        return 2
    problems = CHECKS[argv[1]]()
    for p in problems:
        print(p)
    if problems:
        return 1
    print(f"{argv[1]}: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
