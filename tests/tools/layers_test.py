#!/usr/bin/env python3
"""scripts/check_layers.py: docs/design.md's layer table agrees with the rooms' link lines in
src/**/CMakeLists.txt, and the checker reports a use the CMake files lack, a use the table
misses and an arrow pointing up, each in a copy of design.md doctored to hold one."""
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECKER = os.path.join(ROOT, "scripts", "check_layers.py")
DESIGN = os.path.join(ROOT, "docs", "design.md")


def run(*arguments):
    return subprocess.run([sys.executable, CHECKER, *arguments], cwd=ROOT, capture_output=True, text=True)


def doctored(text, room, change):
    """design.md with `change` applied to the "uses" cell (third column) of `room`'s row."""
    def edit(match):
        cells = match.group(0).split(" | ")
        cells[2] = change(cells[2])
        return " | ".join(cells)
    return re.sub(r"^\| `src/" + re.escape(room) + r"/` \|.*$", edit, text, count=1, flags=re.M)


def main():
    shipped = run()
    print(shipped.stdout, end="")
    if shipped.returncode != 0:
        print("FAIL: docs/design.md's layer table disagrees with the CMake files")
        return 1
    with open(DESIGN, encoding="utf-8") as f:
        text = f.read()
    cases = {
        "a use the CMake files lack": (doctored(text, "mesh", lambda c: c + ", io"), "mesh uses io"),
        "a missing use": (doctored(text, "forms", lambda c: c.replace("assembly, ", "")), "forms does not list assembly"),
        "an arrow pointing up": (doctored(text, "io", lambda c: c + ", app"), "io uses app, which is above it"),
    }
    failed = False
    with tempfile.TemporaryDirectory() as work:
        for kind, (bad, expected) in cases.items():
            path = os.path.join(work, "design.md")
            with open(path, "w", encoding="utf-8") as f:
                f.write(bad)
            result = run("--design", path)
            if result.returncode != 1 or expected not in result.stdout:
                print(f"FAIL: {kind} not reported (exit {result.returncode}, wanted '{expected}'):\n{result.stdout}")
                failed = True
    if failed:
        return 1
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
