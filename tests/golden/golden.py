#!/usr/bin/env python3
"""Golden per-step records of the shipped scenes, in the spirit of PETSc's output/*.out files.

Each shipped scene (scenes/*.json) runs for the number of steps in SCENES (the long ones
shortened so that the set stays within a CI budget of about two minutes on 2 cores); its
stats.csv is reduced to the compared columns and checked, row by row, against the committed
record tests/golden/<scene>.csv:

  t, substeps   equal (relative 1e-9): the same steps, cut the same way by step recovery
  newton_its    within NEWTON_BAND iterations of the record
  energy, kinetic_energy, elastic_energy, min_distance, min_volume_ratio
                |a - b| <= RTOL * max(|a|, |b|) + RTOL * (the column's largest |value| in the
                record), the second term so that a quantity passing through zero (the
                incremental potential) is compared at its own scale

RTOL and NEWTON_BAND come from the spread measured between 1 and 2 ranks (records are written on
1 rank, CI checks on 2; two runs on the same ranks are bit-for-bit alike): see tests/golden/README.md.

  golden.py check  --dipc BIN --scene NAME [--ranks N] [--mpiexec CMD] [--work DIR]
  golden.py update --dipc BIN [--scene NAME ...] [--mpiexec CMD] [--work DIR]   (tests/golden/update.sh)

Only the standard library: CI's python3 need not have numpy.
"""
import argparse
import csv
import math
import os
import shlex
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))

# scene -> steps compared (None: all of the scene's). Chosen to include each contact scene's
# first contacts: boxes_drop touches at step 20, roller_squeeze at 5, box_on_obj_ramp at 13,
# fast_impact at 2; block_on_plane's first step alone takes ~30 s on 1 rank.
SCENES = {
    "default_beam": None,
    "stretched_block_static": None,
    "twisted_bar": 30,
    "fast_impact": 10,
    "box_on_obj_ramp": None,
    "friction_stack": 30,
    "block_on_plane": 2,
    "roller_squeeze": 12,
    "boxes_drop": 40,
}

EXACT = ["t", "substeps"]
NEWTON = "newton_its"
CLOSE = ["energy", "kinetic_energy", "elastic_energy", "min_distance", "min_volume_ratio"]
NEWTON_BAND = 3
RTOL = 1e-5


def run_scene(args, scene, ranks, work):
    """Runs dipc on `scene`; returns the rows of its stats.csv (dicts of strings)."""
    out = os.path.join(work, f"{scene}_np{ranks}")
    cmd = shlex.split(args.mpiexec) + ["-n", str(ranks), args.dipc, os.path.join(SOURCE, "scenes", scene + ".json"),
                                       "-dipc_quiet", "-dipc_output", out]
    if SCENES[scene] is not None:
        cmd += ["-dipc_steps", str(SCENES[scene])]
    done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode != 0:
        sys.exit(f"{scene}: dipc failed with status {done.returncode}:\n{' '.join(cmd)}\n{done.stdout}")
    with open(os.path.join(out, "stats.csv"), newline="") as f:
        return list(csv.DictReader(f))


def columns_of(rows):
    return ["step"] + [c for c in EXACT + [NEWTON] + CLOSE if c in rows[0]]


def read_record(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def write_record(path, scene, rows):
    cols = columns_of(rows)
    steps = SCENES[scene]
    with open(path, "w", newline="") as f:
        f.write(f"# golden record: scenes/{scene}.json, "
                f"{'-dipc_steps ' + str(steps) if steps else 'all steps'}, 1 rank, default options\n")
        f.write("# regenerate with tests/golden/update.sh (compared by tests/golden/golden.py)\n")
        w = csv.writer(f, lineterminator="\n")
        w.writerow(cols)
        for r in rows:
            w.writerow([r[c] for c in cols])


def compare(scene, record, rows):
    """The differences between the record and a run, as messages (empty: they agree)."""
    problems = []
    if len(rows) != len(record):
        problems.append(f"{len(rows)} steps run, the record has {len(record)}")
    scale = {c: max((abs(float(r[c])) for r in record if math.isfinite(float(r[c]))), default=0.0)
             for c in CLOSE if c in record[0]}
    for want, got in zip(record, rows):
        step = want["step"]
        for c in EXACT:
            if c in want and not math.isclose(float(want[c]), float(got[c]), rel_tol=1e-9):
                problems.append(f"step {step}: {c} {got[c]}, record {want[c]}")
        if abs(int(got[NEWTON]) - int(want[NEWTON])) > NEWTON_BAND:
            problems.append(f"step {step}: {NEWTON} {got[NEWTON]}, record {want[NEWTON]} (band +-{NEWTON_BAND})")
        for c in scale:
            a, b = float(got[c]), float(want[c])
            if not (math.isfinite(a) and math.isfinite(b)):
                if a != b:
                    problems.append(f"step {step}: {c} {got[c]}, record {want[c]}")
                continue
            bound = RTOL * max(abs(a), abs(b)) + RTOL * scale[c]
            if abs(a - b) > bound:
                problems.append(f"step {step}: {c} {got[c]}, record {want[c]} "
                                f"(difference {abs(a - b):.3g} > {bound:.3g})")
    return problems


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("mode", choices=["check", "update"])
    p.add_argument("--dipc", required=True, help="the dipc program")
    p.add_argument("--scene", action="append", help="scene name (default for update: all of SCENES)")
    p.add_argument("--ranks", type=int, default=2, help="ranks of a check run (records are written on 1)")
    p.add_argument("--mpiexec", default="mpiexec", help="the MPI launcher with its flags")
    p.add_argument("--work", default="golden_runs", help="directory for the runs' output")
    p.add_argument("--records", default=HERE, help="directory of the records (default: this script's)")
    args = p.parse_args()
    scenes = args.scene or list(SCENES)
    for scene in scenes:
        if scene not in SCENES:
            sys.exit(f"unknown scene {scene}; known: {' '.join(SCENES)}")
    os.makedirs(args.work, exist_ok=True)
    failed = False
    for scene in scenes:
        path = os.path.join(args.records, scene + ".csv")
        if args.mode == "update":
            write_record(path, scene, run_scene(args, scene, 1, args.work))
            print(f"wrote {path}")
            continue
        problems = compare(scene, read_record(path), run_scene(args, scene, args.ranks, args.work))
        if problems:
            failed = True
            print(f"{scene}: {len(problems)} difference(s) from {path}:")
            for m in problems[:40]:
                print("  " + m)
        else:
            print(f"{scene}: matches {path}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
