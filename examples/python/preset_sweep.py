"""Cost against error of dipc's solver presets (fast, balanced, accurate) on a small contact scene.

    mpiexec -n 2 /usr/bin/python3 examples/python/preset_sweep.py [--steps 40] [--out output/preset_sweep]

(PYTHONPATH must hold the built module: build/python.) Runs scenes/boxes_drop.json (two rubber
boxes dropped on each other and on the ground; both have landed by step 35) once per preset and
once with the tight reference settings of bench/speed_accuracy.py, all for --steps steps and
without output files. After every step rank 0 gathers the positions, and the error of a preset
is the largest distance of any node from where the reference has it, over all steps:

  err_diag    relative to the diagonal of the bodies' bounding box at rest;
  err_motion  relative to the largest displacement of the reference, as the README's and
              docs/performance.md's preset tables give it ("Speed or accuracy").

The cost is the run's wall time (finish()["seconds"]["total"], setup included) and its Newton
and CG iterations. Rank 0 prints the table and writes presets.csv and presets.png into --out.
Wall times on a busy machine are noisy; the iteration counts are not (runs are deterministic).
"""
import argparse
import csv
import os

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt
import numpy as np
from mpi4py import MPI

import dipc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "scenes", "boxes_drop.json")
# bench/speed_accuracy.py's reference: Newton 10x and CG 100x tighter than `accurate`.
REFERENCE = ["-dipc_velocity_tol_rel", "1e-7", "-ksp_rtol", "1e-10", "-dipc_pc_reuse", "0"]
PRESETS = ("fast", "balanced", "accurate")


def run(options, steps):
    """One run of the scene: its totals and, on rank 0 (None elsewhere), the rest positions and
    the positions after each step, every node in input order."""
    common = ["-dipc_steps", str(steps), "-dipc_no_output", "-dipc_quiet"]
    with dipc.Simulation(SCENE, options=common + options, report=False) as sim:
        rest = sim.gather("reference_positions")  # collective: every rank calls it
        positions = []
        while sim.step() is not None:
            positions.append(sim.gather("positions"))
        return sim.finish(), rest, positions


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=40, help="scene steps per run (default 40)")
    parser.add_argument("--out", default="output/preset_sweep", help="folder for presets.csv and presets.png")
    args = parser.parse_args()
    root = MPI.COMM_WORLD.rank == 0

    ref_totals, rest, ref = run(REFERENCE, args.steps)
    rows = []
    for preset in PRESETS:
        totals, _, positions = run(["-dipc_preset", preset], args.steps)
        if not root:
            continue
        distance = max(np.linalg.norm(x - r, axis=1).max() for x, r in zip(positions, ref, strict=True))
        rows.append({"preset": preset, "seconds": totals["seconds"]["total"], "newton": totals["newton_iterations"],
                     "cg": totals["linear_iterations"], "distance_m": distance})
    if not root:
        return

    # Scales of the error: the scene's size, and how far the reference moved any node.
    diagonal = np.linalg.norm(rest.max(axis=0) - rest.min(axis=0))
    motion = max(np.linalg.norm(r - rest, axis=1).max() for r in ref)
    for row in rows:
        row["err_diag"] = row["distance_m"] / diagonal
        row["err_motion"] = row["distance_m"] / motion

    print(f"\nboxes_drop, {args.steps} steps, {MPI.COMM_WORLD.size} rank(s); reference ({' '.join(REFERENCE)}): "
          f"{ref_totals['seconds']['total']:.2f} s, {ref_totals['newton_iterations']} Newton, "
          f"{ref_totals['linear_iterations']} CG")
    print(f"{'preset':<10} {'wall s':>7} {'Newton':>7} {'CG':>6} {'err_diag':>10} {'err_motion':>10}")
    for r in rows:
        print(f"{r['preset']:<10} {r['seconds']:7.2f} {r['newton']:7d} {r['cg']:6d} "
              f"{r['err_diag']:10.2e} {r['err_motion']:10.2e}")

    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "presets.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, rows[0].keys())
        writer.writeheader()
        writer.writerows(rows)

    fig, ax = plt.subplots(figsize=(5, 4))
    for key, marker in (("err_diag", "o"), ("err_motion", "s")):
        ax.semilogy([r["seconds"] for r in rows], [r[key] for r in rows], marker, label=key)
    for r in rows:
        ax.annotate(r["preset"], (r["seconds"], r["err_motion"]), textcoords="offset points", xytext=(5, 5))
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel("largest node distance from the reference, relative")
    ax.set_title(f"dipc presets, boxes_drop, {args.steps} steps")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "presets.png"), dpi=120)
    print(f"wrote {args.out}/presets.csv and presets.png")


if __name__ == "__main__":
    main()
