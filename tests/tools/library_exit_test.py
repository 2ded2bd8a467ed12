#!/usr/bin/env python3
"""A library that ends the process mid-run (issue 29, item 5): hypre answers a failed cuSPARSE
or CUDA call by printing one line and calling exit. dipc must then add its own error (rank,
step, elements, the output that is complete, what to change), end with a non-zero status even
when the library asked for 0, and leave the output of the completed steps readable.

  library_exit_test.py --dipc build/src/app/dipc --shim libexiting_amg_setup.so \\
      --mpiexec "mpiexec --oversubscribe --allow-run-as-root" --work /tmp/library_exit

The shim (exiting_amg_setup.c, preloaded) stands in for HYPRE_BoomerAMGSetup and exits at
its Nth call. Runs, 2 ranks, scenes/boxes_drop.json:
1. exit(0) at the 6th AMG setup: a non-zero status, "dipc: error: rank R: a library ended the
   process ... during step S" from both ranks after the library's line, and the output's frames
   (as the message counts them) all read back and judged by judge_output.py;
2. exit(1) at the first AMG setup (the first Newton iteration of step 1): the same message;
3. the shim loaded but never exiting: status 0 and no such message (normal ends are not reported).
Exit status 0 when all holds; the failures are printed and the status is 1.
"""
import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENE = os.path.join(ROOT, "scenes", "boxes_drop.json")
MESSAGE = re.compile(r"dipc: error: rank (\d+): a library ended the process .* during (step \d+|setup); "
                     r"the rank has (\d+) elements\. (?:The output in (\S+) stays readable: (\d+) complete time "
                     r"frame\(s\)|No output had been written)")


def run(args, name, exit_at, status, steps):
    out = os.path.join(args.work, name)
    env = ["env", "LD_PRELOAD=" + args.shim]
    if exit_at:
        env += ["DIPC_TEST_EXIT_AT_SETUP=%d" % exit_at, "DIPC_TEST_EXIT_STATUS=%d" % status]
    cmd = shlex.split(args.mpiexec) + ["-n", "2"] + env + [args.dipc, SCENE, "-dipc_steps", str(steps),
                                                         "-dipc_output", out]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    return p.returncode, p.stdout, out


def frames_in_xmf(path):
    """Time frames the .xmf lists (its temporal collection's grids)."""
    root = ET.parse(path).getroot()
    return sum(1 for g in root.iter("Grid") if g.find("Time") is not None)


def check_exit(args, name, exit_at, status, failures):
    code, text, out = run(args, name, exit_at, status, 10)
    where = "%s (exit(%d) at AMG setup %d)" % (name, status, exit_at)
    if code == 0:
        failures.append("%s: mpirun exited 0" % where)
    if "CUSPARSE ERROR" not in text:
        failures.append("%s: the library's own line is missing" % where)
    found = MESSAGE.findall(text)
    ranks = sorted({int(m[0]) for m in found})
    if ranks != [0, 1]:
        failures.append("%s: dipc's message from ranks %s, expected both; output:\n%s" % (where, ranks, text[-2500:]))
        return
    rank, phase, elements, xmf, frames = found[0]
    print("%s: exit %d, rank %s stopped during %s with %s elements, %s frame(s) in %s" %
          (where, code, rank, phase, elements, frames or 0, xmf or "no output"))
    if not xmf:
        failures.append("%s: the message names no output, but step 0 is written before step 1" % where)
        return
    listed = frames_in_xmf(xmf)
    if listed != int(frames):
        failures.append("%s: the .xmf lists %d frames, the message %s" % (where, listed, frames))
    judge = subprocess.run([sys.executable, os.path.join(HERE, "judge_output.py"), xmf[:-4] + ".h5", SCENE],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if judge.returncode != 0:
        failures.append("%s: the output does not read back clean (judge exit %d): %s" %
                        (where, judge.returncode, judge.stdout[-1500:]))
    else:
        print("  judge: %s" % judge.stdout.strip().splitlines()[-1][:200])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dipc", required=True)
    ap.add_argument("--shim", required=True)
    ap.add_argument("--mpiexec", default="mpiexec")
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    failures = []
    check_exit(args, "exit0_mid_run", 6, 0, failures)
    check_exit(args, "exit1_first_setup", 1, 1, failures)
    code, text, _ = run(args, "no_exit", 0, 0, 3)
    if code != 0 or "a library ended the process" in text:
        failures.append("no_exit: exit %d, report present: %s\n%s" % (code, "a library ended" in text, text[-2000:]))
    else:
        print("no_exit: exit 0, no report")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
