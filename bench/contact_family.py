#!/usr/bin/env python3
"""Contact-rich benchmark family (issue 29): seconds per Newton iteration, and where they go, on
scenes where contact dominates, against the mesh size.

  bench/contact_family.py [--members stack,squeeze,press] [--refine 1,2 | --elements 20000,100000]
                          [--steps 3] [--ranks 1] [--dipc build/src/app/dipc] [--tag cpu]
                          [--out bench/results] [--timeout 600] [--cores-per-rank K]
                          [-- extra dipc options, e.g. -dipc_backend cuda -vec_type cuda -mat_type hypre
                              -use_gpu_aware_mpi 0]

The members (bench/contact_family/*.json, rubber E = 1 MPa, nu = 0.4, dt = 2 ms, adaptive kappa,
d^ = 1e-3 of the bounding-box diagonal; contact is active from the first or second step):
  stack    8 rubber cubes of 0.2 m in two layers of 2 x 2 (2 mm apart, the top layer offset by
           3 cm and 2 cm), falling at 0.5 m/s from 1 mm onto the plane z = 0, friction 0.2
  squeeze  4 rubber slabs (0.25 x 0.25 x 0.06 m, offset from one another by 0.5 to 1.5 cm, 0.4 mm
           apart) between two kinematic steel plates, the lower fixed, the upper moving down at
           0.2 m/s, friction 0.5
  press    a rubber slab (0.4 x 0.4 x 0.1 m) whose top face is driven down and sideways
           (velocity (0.2, 0, -0.5) m/s) onto the OBJ obstacle wavy_floor.obj (egg-crate bumps
           of 4 mm, 10 cm apart), friction 0.3
Sizes: --refine R runs the shipped scene with -dipc_refine R (every box's resolution times R:
elements times R^3); --elements N writes a copy of the scene whose boxes' resolutions are
scaled by (N / base elements)^(1/3), rounded, at least 1 (for sizes between or below the
refine levels; the element count of the row is what dipc reports).

Each run is
  mpirun -n RANKS dipc member.json -dipc_steps STEPS -dipc_no_output [-dipc_refine R] [extra]
(with --keep-output DIR, -dipc_output DIR/<member>_<refine|elements><size> instead of -dipc_no_output)
and from its output:
  newton_its, ksp_its     summed over the step lines (a step cut into sub-steps counts all of them)
  max_contact_pairs       the largest "contacts N" of the step lines (active pairs after the step)
  max_step_newton         the most Newton iterations of one step line (a cut step's sub-steps
                          together): the heaviest step, issue 29's measure of item 4
  *_s phases              dipc's timing table (slowest rank per row): assembly (of which COO
                          insertion), line search, contact (ghost surfaces, broad phase, CCD), new
                          matrix patterns, linear solve (KSP + AMG and the rest of the solve),
                          other; partition and setup
  per_newton_s            (assembly + line search + contact + new patterns + linear solve) / Newton
                          iterations: the solves' time per iteration (each row is its slowest
                          rank, so the sum can exceed the slowest rank's sum a little);
                          per_newton_<phase>_s is each phase's share
  host_rss_max_mib        peak resident memory of the fullest rank at the end (ru_maxrss)
  gpu_setup_mib           device memory the setup took on the fullest rank (run header; GPU runs)
  gpu_peak_mib            the largest memory.used of any GPU sampled by nvidia-smi every 0.5 s
                          during the run, minus its value before (only where nvidia-smi exists;
                          other processes on the GPU would count too)
  wall_s                  mpirun's wall time, startup and setup included
The exit status is 1 when a run failed, printed no timing table, or no contact pair became active in it.
Rows go to <out>/contact_family_<tag>.csv (rows of the same member, elements, ranks and backend
are replaced) and, with matplotlib, a plot <out>/contact_family_<tag>.png: per member, seconds
per Newton iteration against elements, stacked by phase. Each run's whole output goes to
<out>/contact_family_<tag>_<member>_<refine|elements><size>.log.
"""
import argparse
import csv
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

from bench_csv import earlier_rows
from pyplot import pyplot_or_none
from run_dipc import run_dipc

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.join(HERE, "contact_family")
MEMBERS = ["stack", "squeeze", "press"]

# dipc's timing table rows (src/app/simulation.cpp) and the CSV columns they fill.
TABLE_ROWS = [("partition", "partition_s"), ("setup", "setup_s"), ("assembly (gradient, Hessian)", "assembly_s"),
              ("  of which COO insertion", "coo_insert_s"), ("line search (energy, validity, segments)", "line_search_s"),
              ("contact: ghost surfaces, broad phase, CCD", "contact_s"), ("contact patterns: active sets, new matrices", "patterns_s"),
              ("linear solve (KSP + AMG) and rest", "linear_solve_s"), ("output", "output_s"),
              ("other (step reports, energies, checks)", "other_s"), ("total", "total_s")]
# The phases of a Newton iteration, in the order they are stacked.
SOLVE_PHASES = ["assembly_s", "line_search_s", "contact_s", "patterns_s", "linear_solve_s"]

FIELDS = (["member", "backend", "ranks", "refine", "elements", "dofs", "steps", "newton_its", "ksp_its", "dt_cuts",
           "max_contact_pairs", "per_newton_s", "per_step_s"] +
          ["per_newton_" + p for p in SOLVE_PHASES] +
          [c for _, c in TABLE_ROWS] +
          ["new_patterns", "pattern_remaps", "host_rss_max_mib", "gpu_setup_mib", "gpu_peak_mib", "wall_s", "status",
           "max_step_newton"])


def base_elements(scene):
    return sum(g["box"]["resolution"][0] * g["box"]["resolution"][1] * g["box"]["resolution"][2]
               for g in scene["geometry"] if "box" in g)


def member_scene(member, elements=None):
    """The member's scene as a dict, every box's resolution scaled towards `elements` in all (as
    shipped without it), mesh paths made absolute (they are relative to the scene file)."""
    with open(os.path.join(SCENES, member + ".json")) as f:
        scene = json.load(f)
    if elements:
        s = (elements / base_elements(scene)) ** (1.0 / 3.0)
        for g in scene["geometry"]:
            if "box" in g:
                g["box"]["resolution"] = [max(1, round(r * s)) for r in g["box"]["resolution"]]
    for g in scene["geometry"]:
        if "mesh" in g and not os.path.isabs(g["mesh"]):
            g["mesh"] = os.path.join(SCENES, g["mesh"])
    for o in scene.get("contact", {}).get("obstacles", []):
        if not os.path.isabs(o["mesh"]):
            o["mesh"] = os.path.join(SCENES, o["mesh"])
    return scene


def scaled_scene(member, elements, workdir):
    """A copy of the member's scene scaled towards `elements` hexes (member_scene), written to workdir."""
    scene = member_scene(member, elements)
    path = os.path.join(workdir, "%s_%d.json" % (member, elements))
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path


class GpuSampler:
    """The largest memory.used (MiB) of any GPU, sampled by nvidia-smi every 0.5 s, minus the
    largest before the run; None without nvidia-smi."""

    def __init__(self):
        self.tool = shutil.which("nvidia-smi")
        self.peak = None
        self.stop = threading.Event()

    def read(self):
        try:
            out = subprocess.run([self.tool, "--query-gpu=memory.used", "--format=csv,noheader,nounits"],
                                 capture_output=True, text=True, timeout=10).stdout
            return max(float(v) for v in out.split())
        except (OSError, ValueError, subprocess.SubprocessError):
            return None

    def __enter__(self):
        if self.tool:
            self.before = self.read()
            self.thread = threading.Thread(target=self.loop, daemon=True)
            self.thread.start()
        return self

    def loop(self):
        while not self.stop.wait(0.5):
            v = self.read()
            if v is not None and self.before is not None:
                self.peak = max(self.peak or 0.0, v - self.before)

    def __exit__(self, *exc):
        if self.tool:
            self.stop.set()
            self.thread.join()


def parse(text):
    row = {}
    m = re.search(r"backend (\S+)", text)
    if m:
        row["backend"] = m.group(1)
    m = re.search(r"\| elements (\d+) \(.*\| dofs (\d+)", text)
    if m:
        row["elements"], row["dofs"] = int(m.group(1)), int(m.group(2))
    newton = ksp = pairs = cuts = heaviest = 0
    for line in text.splitlines():
        m = re.match(r"step\s+\d+\s+t \S+\s+newton\s+(\d+) \(.*?\)\s+ksp\s+(\d+)", line)
        if not m:
            continue
        newton += int(m.group(1))
        heaviest = max(heaviest, int(m.group(1)))
        ksp += int(m.group(2))
        c = re.search(r"\| contacts (\d+)", line)
        if c:
            pairs = max(pairs, int(c.group(1)))
        c = re.search(r"after (\d+) cut\(s\)", line)
        if c:
            cuts += int(c.group(1))
    row.update(newton_its=newton, ksp_its=ksp, max_contact_pairs=pairs, dt_cuts=cuts, max_step_newton=heaviest)
    for name, column in TABLE_ROWS:
        m = re.search(r"^%s\s+([0-9.]+)\s*$" % re.escape(name), text, re.M)
        row[column] = float(m.group(1)) if m else 0.0  # a row dipc leaves out is a phase the run did not have
    row["new_patterns"] = int(first_number(r"\((\d+) new matrix pattern\(s\) after setup", text) or 0)
    row["pattern_remaps"] = int(first_number(r"(\d+) active-set change\(s\) within the matrix", text) or 0)
    # Reported only by some runs (host memory at the end; device memory of a GPU run's setup).
    for column, pattern in (("host_rss_max_mib", r"at end ([0-9.]+)/([0-9.]+)"),
                            ("gpu_setup_mib", r"setup used ([0-9.]+) MiB on the fullest rank")):
        value = first_number(pattern, text)
        if value is not None:
            row[column] = value
    return row


def first_number(pattern, text):
    """The first group of pattern's first match in text as a float, or None without a match."""
    m = re.search(pattern, text)
    return float(m.group(1)) if m else None


def run_one(args, member, size_kind, size, workdir):
    if size_kind == "refine":
        scene, options, refine = os.path.join(SCENES, member + ".json"), ["-dipc_refine", size], size
    else:
        scene, options, refine = scaled_scene(member, size, workdir), [], ""
    # Output costs time and disk: none, unless --keep-output asks for it (its time is the
    # timing table's "output" row, outside the per-Newton figures).
    output = (["-dipc_output", os.path.join(args.keep_output, "%s_%s%s" % (member, size_kind, size))]
              if args.keep_output else ["-dipc_no_output"])
    cmd = [scene, "-dipc_steps", args.steps] + output + options + args.extra
    start = time.time()
    with GpuSampler() as gpu:
        text, status, full = run_dipc(args.dipc, args.ranks, cmd, timeout=args.timeout,
                                      cores_per_rank=args.cores_per_rank)
    # The whole output beside the CSV: the step lines' Newton counts and the timing table.
    log = os.path.join(args.out, "contact_family_%s_%s_%s%s.log" % (args.tag, member, size_kind, size))
    with open(log, "w") as f:
        f.write(text)
    row = {"member": member, "ranks": args.ranks, "refine": refine, "steps": args.steps, "status": status,
           "wall_s": round(time.time() - start, 2)}
    if gpu.peak is not None:
        row["gpu_peak_mib"] = round(gpu.peak, 1)
    row.update(parse(text))
    if status == 0 and "dipc: error" in text:
        row["status"] = "error"
    elif status == 0 and not re.search(r"^total\s+[0-9.]+\s*$", text, re.M):
        row["status"] = "no_timing_table"
    if row["newton_its"]:
        solve = sum(row[p] for p in SOLVE_PHASES)
        row["per_newton_s"] = round(solve / row["newton_its"], 5)
        row["per_step_s"] = round(solve / args.steps, 5)
        for p in SOLVE_PHASES:
            row["per_newton_" + p] = round(row[p] / row["newton_its"], 5)
    if status != 0 or row["status"] != 0:
        sys.stderr.write("failed (%s): %s\n%s\n" % (row["status"], " ".join(map(str, full)), text[-3000:]))
    return row


def print_row(row, header=False):
    cols = [("member", "%-8s"), ("backend", "%-5s"), ("ranks", "%5s"), ("elements", "%9s"), ("newton_its", "%6s"),
            ("max_step_newton", "%7s"),
            ("ksp_its", "%6s"), ("max_contact_pairs", "%9s"), ("per_newton_s", "%9s")] + \
           [("per_newton_" + p, "%9s") for p in SOLVE_PHASES] + [("host_rss_max_mib", "%8s"), ("wall_s", "%7s"),
                                                                ("status", "%6s")]
    short = {"max_step_newton": "heaviest", "max_contact_pairs": "pairs", "per_newton_s": "s/newton", "newton_its": "newton", "ksp_its": "ksp",
             "host_rss_max_mib": "rss_MiB", "per_newton_assembly_s": "assembly", "per_newton_line_search_s": "lsearch",
             "per_newton_contact_s": "contact", "per_newton_patterns_s": "patterns",
             "per_newton_linear_solve_s": "linsolve"}
    if header:
        print(" ".join(f % short.get(k, k)[:9] for k, f in cols))
    print(" ".join(f % row.get(k, "") for k, f in cols), flush=True)


def plot(rows, path):
    plt = pyplot_or_none()
    if plt is None:
        return
    members = [m for m in MEMBERS if any(r["member"] == m for r in rows)]
    fig, axes = plt.subplots(1, len(members), figsize=(5.5 * len(members), 4.6), squeeze=False)
    colours = ["tab:blue", "tab:orange", "tab:red", "tab:purple", "tab:green"]
    for ax, member in zip(axes[0], members):
        # One stack per (backend, ranks, elements); rows read back from the CSV hold strings.
        sel = sorted([r for r in rows if r["member"] == member and r.get("per_newton_s") not in ("", None)],
                     key=lambda r: (r["backend"], int(r["ranks"]), int(r["elements"])))
        labels = ["%s\n%s r%s" % (_short(int(r["elements"])), r["backend"], r["ranks"]) for r in sel]
        bottom = [0.0] * len(sel)
        for p, c in zip(SOLVE_PHASES, colours):
            h = [float(r["per_newton_" + p]) for r in sel]
            ax.bar(range(len(sel)), h, bottom=bottom, color=c, label=p[:-2].replace("_", " "))
            bottom = [b + v for b, v in zip(bottom, h)]
        ax.set_xticks(range(len(sel)))
        ax.set_xticklabels(labels, fontsize=8)
        ax.set_title("%s: seconds per Newton iteration" % member)
        ax.set_xlabel("elements, backend, ranks")
        ax.set_ylabel("s (slowest rank per phase)")
        ax.grid(True, axis="y", alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print("wrote", path)


def _short(n):
    return "%.3gM" % (n / 1e6) if n >= 1e6 else "%.3gK" % (n / 1e3)


def main():
    # SIGTERM (a timeout around the driver) as an exception, so that run_dipc ends the running dipc too.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--members", default=",".join(MEMBERS))
    sizes = ap.add_mutually_exclusive_group()
    sizes.add_argument("--refine", help="-dipc_refine levels, e.g. 1,2,3,4")
    sizes.add_argument("--elements", help="approximate element counts, e.g. 2000,100000")
    ap.add_argument("--steps", type=int, default=3)
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--dipc", default="build/src/app/dipc")
    ap.add_argument("--tag", default="cpu")
    ap.add_argument("--out", default="bench/results")
    ap.add_argument("--timeout", type=float, default=1800, help="seconds per run")
    ap.add_argument("--cores-per-rank", type=int, default=None,
                    help="bind each rank to this many cores (mpirun --map-by slot:PE=K)")
    ap.add_argument("--keep-output", metavar="DIR",
                    help="write each run's output (XDMF/HDF5) into DIR/<member>_<refine|elements><size>")
    ap.add_argument("extra", nargs="*", help="after --: more dipc options")
    args = ap.parse_args()
    members = args.members.split(",")
    for m in members:
        if m not in MEMBERS:
            ap.error("unknown member %s (members: %s)" % (m, ", ".join(MEMBERS)))
    size_kind, size_list = ("elements", args.elements) if args.elements else ("refine", args.refine or "1")
    csv_path, rows = earlier_rows(args.out, "contact_family_%s.csv" % args.tag)
    first, failures = True, 0
    with tempfile.TemporaryDirectory() as workdir:
        for member in members:
            for size in [int(v) for v in size_list.split(",")]:
                row = run_one(args, member, size_kind, size, workdir)
                print_row(row, header=first)
                first = False
                failures += row["status"] != 0
                if row["status"] == 0 and not row["max_contact_pairs"]:
                    # A member's purpose is contact: a run in which none became active measured something else.
                    print("%s: no contact pair became active in %d steps" % (member, args.steps), file=sys.stderr)
                    failures += 1
                key = lambda r: (r["member"], str(r.get("elements", "")), str(r["ranks"]), r.get("backend", ""))
                rows = [r for r in rows if key(r) != key(row)]
                rows.append({k: row.get(k, "") for k in FIELDS})
                with open(csv_path, "w", newline="") as f:
                    w = csv.DictWriter(f, fieldnames=FIELDS)
                    w.writeheader()
                    w.writerows(sorted(rows, key=lambda r: (r["member"], r["backend"], int(r["ranks"]),
                                                            int(r["elements"] or 0))))
    print("wrote", csv_path)
    plot(rows, os.path.join(args.out, "contact_family_%s.png" % args.tag))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
