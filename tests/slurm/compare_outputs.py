#!/usr/bin/env python3
"""Compares the output of an interrupted and resumed dipc run with an uninterrupted one.

    compare_outputs.py REFERENCE_DIR RUN_DIR [--name dipc] [--steps N] [--tol 1e-12]

Both directories hold <name>.h5, <name>.xmf and stats.csv. The run passes when
- its HDF5 file has exactly the reference's written steps (none lost, none doubled), each
  with the same time, and displacement and velocity equal to the reference's within
  tol * (largest reference value of the field over all steps) -- restarts on the same rank
  count reproduce the uninterrupted run to 1e-12 (issue 13);
- the XDMF lists every one of those steps once, in order, with the same times;
- stats.csv has one row per scene step 1..N, the same steps as the reference's.
Prints one line per check and exits 1 on the first difference.
"""
import argparse
import csv
import re
import sys

import h5py
import numpy as np


def fail(message):
    print(f"compare_outputs: FAIL: {message}")
    sys.exit(1)


def written_steps(h5):
    return sorted(int(k) for k in h5["steps"].keys())


def xdmf_times(path):
    with open(path) as f:
        return [float(t) for t in re.findall(r'<Time Value="([^"]+)"', f.read())]


def stats_steps(path):
    with open(path) as f:
        return [int(row["step"]) for row in csv.DictReader(f)]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("reference")
    parser.add_argument("run")
    parser.add_argument("--name", default="dipc")
    parser.add_argument("--steps", type=int, help="scene steps the runs must have reached")
    parser.add_argument("--tol", type=float, default=1e-12)
    args = parser.parse_args()

    with h5py.File(f"{args.reference}/{args.name}.h5", "r") as ref, h5py.File(f"{args.run}/{args.name}.h5", "r") as run:
        ref_steps, run_steps = written_steps(ref), written_steps(run)
        if args.steps is not None and (not ref_steps or ref_steps[-1] != args.steps):
            fail(f"the reference's last written step is {ref_steps[-1:]} instead of {args.steps}")
        if run_steps != ref_steps:
            lost = sorted(set(ref_steps) - set(run_steps))
            extra = sorted(set(run_steps) - set(ref_steps))
            fail(f"written steps differ: lost {lost}, not in the reference {extra}")
        print(f"compare_outputs: HDF5 steps {ref_steps[0]}..{ref_steps[-1]} ({len(ref_steps)}) all present")
        for field in ("displacement", "velocity"):
            scale = max(np.abs(ref[f"steps/{k}/{field}"][...]).max() for k in ref_steps)
            worst, worst_step = 0.0, None
            for k in ref_steps:
                a, b = ref[f"steps/{k}/{field}"][...], run[f"steps/{k}/{field}"][...]
                if a.shape != b.shape:
                    fail(f"step {k} {field}: shape {b.shape} instead of {a.shape}")
                d = float(np.abs(a - b).max())
                if d > worst:
                    worst, worst_step = d, k
            relative = worst / scale if scale > 0 else worst
            where = f" (step {worst_step})" if worst_step is not None else ""
            print(f"compare_outputs: {field}: largest difference {worst:.3e}{where}, "
                  f"{relative:.3e} of the largest value {scale:.3e}")
            if relative > args.tol:
                fail(f"{field} differs by {relative:.3e} > {args.tol:g} (relative) at step {worst_step}")
        last = ref_steps[-1]
        for k in ref_steps:
            t_ref, t_run = ref[f"steps/{k}"].attrs["time"], run[f"steps/{k}"].attrs["time"]
            if t_ref != t_run:
                fail(f"step {k}: time {t_run!r} instead of {t_ref!r}")
        print(f"compare_outputs: times equal; last step {last} at t = {ref[f'steps/{last}'].attrs['time']!r}")

    ref_times, run_times = xdmf_times(f"{args.reference}/{args.name}.xmf"), xdmf_times(f"{args.run}/{args.name}.xmf")
    if run_times != ref_times:
        fail(f"the XDMF lists {len(run_times)} steps {run_times} instead of {len(ref_times)} {ref_times}")
    print(f"compare_outputs: XDMF lists the same {len(run_times)} steps")

    ref_rows, run_rows = stats_steps(f"{args.reference}/stats.csv"), stats_steps(f"{args.run}/stats.csv")
    if run_rows != ref_rows or (args.steps is not None and run_rows != list(range(1, args.steps + 1))):
        fail(f"stats.csv rows are steps {run_rows} instead of {ref_rows}")
    print(f"compare_outputs: stats.csv has one row per step 1..{run_rows[-1]}")
    print("compare_outputs: PASS")


if __name__ == "__main__":
    main()
