#!/usr/bin/env python3
"""scripts/check_doc_paths.py: the engineers' documents (docs/design.md, docs/README.md) cite only paths, identifiers
and commits that exist, and the checker reports each kind of dangling reference in a document
made to hold one of each (so a checker that stopped looking would fail here)."""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECKER = os.path.join(ROOT, "scripts", "check_doc_paths.py")


def run(*documents):
    return subprocess.run([sys.executable, CHECKER, *documents], cwd=ROOT, capture_output=True, text=True)


def main():
    shipped = run()
    print(shipped.stdout, end="")
    if shipped.returncode != 0:
        print("FAIL: docs/design.md or docs/README.md cite references that do not exist")
        return 1

    bad = {
        "link": "[the plan](../no_such_plan.md)",
        "path": "`src/nonlinear/no_such_form.hpp`",
        "file": "`no_such_header.hpp`",
        "member": "`IncrementalPotential::no_such_member_xyz`",
        "identifier": "`no_such_function_xyz`",
    }
    # Commits are checked only in a git checkout (a source tarball has no history).
    if subprocess.run(["git", "rev-parse", "--git-dir"], cwd=ROOT, capture_output=True).returncode == 0:
        bad["commit"] = "`deadbee1`"
    with tempfile.TemporaryDirectory() as work:
        doc = os.path.join(work, "bad.md")
        with open(doc, "w", encoding="utf-8") as f:
            f.write("# references that exist\n\n`src/forms/form.hpp` `Form::max_step` `add_psd_correction`\n\n")
            for kind, text in bad.items():
                f.write(f"{kind}: {text}\n")
        # The bad document lives outside the tree, so its link is resolved from there.
        result = run(doc)
    print(result.stdout, end="")
    # Lines 1-4 cite things that exist; line 5 onwards one dangling reference each.
    reported = {int(line.split("bad.md:")[1].split(":")[0]) for line in result.stdout.splitlines() if "bad.md:" in line}
    expected = set(range(5, 5 + len(bad)))
    if result.returncode != 1 or reported != expected:
        kinds = list(bad)
        missed = [kinds[n - 5] for n in sorted(expected - reported)]
        print(f"FAIL: exit {result.returncode}; not reported: {missed}; reported in error: lines {sorted(reported - expected)}")
        return 1
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
