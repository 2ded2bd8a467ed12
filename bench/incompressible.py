#!/usr/bin/env python3
"""CG and Newton iterations against Poisson's ratio, per preconditioner (issue 11, part 4).

  bench/incompressible.py [--dipc build/src/app/dipc] [--ranks 1,2] [--nu 0,0.3,...]
                          [--pcs default,...] [--scenes drop,squeeze] [--out bench/results]

Two small contact scenes, generated here with Poisson's ratio nu substituted:
  drop     a 0.2 m rubber cube (E = 1 MPa, 10x10x10 = 1000 hexes) landing at 1 m/s on the
           plane z = 0 under gravity (block_on_plane.json at a tenth of its hexes), 10 steps of 2 ms;
  squeeze  a 0.1 m cube (8x8x8 = 512 hexes) on the plane z = 0, its top face pushed down at
           0.5 m/s, 6 steps of 10 ms (15 % compression, frictionless contact with the plane).
Each run uses -snes_max_it 1000 (only dipc's |p|_inf/h criterion ends a Newton solve) and
-dipc_no_output. Newton and CG iterations are the
sums of the per-step lines; wall is the "total" line of the timing table (slowest rank).
Writes <out>/incompressible.csv and <out>/incompressible.png (python3-matplotlib); rows already
in the CSV are kept (rows of the same scene, ranks, element, variant and nu are replaced).
"""
import argparse
import csv
import os
import re
import sys
import tempfile

from run_dipc import run_dipc

# Preconditioner variants: extra PETSc options on top of dipc's defaults.
PCS = {
    "default": [],  # whatever dipc chooses (newton_solver.cpp set_default_options)
    "theta0.5": ["-pc_hypre_boomeramg_strong_threshold", "0.5"],
    "theta0.7": ["-pc_hypre_boomeramg_strong_threshold", "0.7"],
    "theta0.8": ["-pc_hypre_boomeramg_strong_threshold", "0.8"],
    "theta0.9": ["-pc_hypre_boomeramg_strong_threshold", "0.9"],
    "nodal": ["-pc_hypre_boomeramg_nodal_coarsen", "6"],
    "nodal_theta0.8": ["-pc_hypre_boomeramg_nodal_coarsen", "6", "-pc_hypre_boomeramg_strong_threshold", "0.8"],
    "vec_interp": ["-pc_hypre_boomeramg_nodal_coarsen", "6", "-pc_hypre_boomeramg_vec_interp_variant", "3"],
    "gamg": ["-pc_type", "gamg", "-pc_gamg_agg_nsmooths", "1"],
    "minres": ["-ksp_type", "minres"],
    "sweeps2": ["-pc_hypre_boomeramg_grid_sweeps_all", "2"],
    "sweeps3": ["-pc_hypre_boomeramg_grid_sweeps_all", "3"],
    "chebyshev": ["-pc_hypre_boomeramg_relax_type_all", "Chebyshev"],
    "l1jacobi": ["-pc_hypre_boomeramg_relax_type_all", "l1scaled-Jacobi"],
    "pmax0": ["-pc_hypre_boomeramg_P_max", "0"],
    "classical": ["-pc_hypre_boomeramg_interp_type", "classical"],
    "falgout": ["-pc_hypre_boomeramg_coarsen_type", "Falgout"],
    # Linear solves of mean-dilatation scenes (src/nonlinear/mixed_linear_solve.hpp): the mixed
    # u-p system by MINRES, its s block preconditioned by the pressure mass over mu (the default
    # for such scenes) or by AMG on I + Bs diag(A)^-1 Bs^T; or CG + AMG on the full Hessian.
    # The block factorization (diag: MINRES; upper: block upper triangular, FGMRES) and the s
    # block's approximation (mass, selfp, nodal) are named in the variant.
    "mixed": ["-dipc_mixed_solve", "1", "-dipc_mixed_schur_fact", "diag", "-dipc_mixed_schur", "mass"],
    "mixed_selfp": ["-dipc_mixed_solve", "1", "-dipc_mixed_schur_fact", "diag", "-dipc_mixed_schur", "selfp"],
    "mixed_nodal": ["-dipc_mixed_solve", "1", "-dipc_mixed_schur_fact", "diag", "-dipc_mixed_schur", "nodal"],
    "mixed_upper": ["-dipc_mixed_solve", "1", "-dipc_mixed_schur_fact", "upper", "-dipc_mixed_schur", "mass"],
    "mixed_upper_selfp": ["-dipc_mixed_solve", "1", "-dipc_mixed_schur_fact", "upper", "-dipc_mixed_schur", "selfp"],
    "mixed_lsc": ["-dipc_mixed_solve", "1", "-dipc_mixed_schur_fact", "diag", "-dipc_mixed_schur", "lsc"],
    "mixed_upper_lsc": ["-dipc_mixed_solve", "1", "-dipc_mixed_schur_fact", "upper", "-dipc_mixed_schur", "lsc"],
    "mixed_upper_nodal": ["-dipc_mixed_solve", "1", "-dipc_mixed_schur_fact", "upper", "-dipc_mixed_schur", "nodal"],
    "primal": ["-dipc_mixed_solve", "0"],
}
# Variants that need mean-dilatation elements (skipped for the standard element).
NEEDS_MEAN_DILATATION = {"primal"} | {pc for pc in PCS if pc.startswith("mixed")}

DROP = """{
  "materials": [{"name": "rubber", "E": 1e6, "nu": NU, "rho": 1000, "volumetric": "VOL"}],
  "geometry": [{"name": "block",
     "box": {"size": [0.2, 0.2, 0.2], "resolution": [10, 10, 10], "origin": [-0.1, -0.1, 0.002]},
     "material": "rubber", "initial_velocity": [0, 0, -1]}],
  "boundary_conditions": {"gravity": [0, 0, -9.81]},
  "time": {"integrator": "implicit_euler", "dt": 0.002, "steps": 10},
  "solver": {"mass": "lumped"},
  "output": {"directory": "output/incompressible", "name": "drop"},
  "contact": {"enabled": true, "dhat": 1e-3, "dhat_relative": true, "barrier_stiffness": "adaptive",
              "planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}]}
}
"""

SQUEEZE = """{
  "materials": [{"name": "rubber", "E": 1e6, "nu": NU, "rho": 1000, "volumetric": "VOL"}],
  "geometry": [{"name": "block",
     "box": {"size": [0.1, 0.1, 0.1], "resolution": [8, 8, 8], "origin": [-0.05, -0.05, 0.0005]},
     "material": "rubber"}],
  "boundary_conditions": {"gravity": [0, 0, -9.81],
     "dirichlet": [{"selection": "block.zmax", "type": "velocity", "velocity": [0, 0, -0.5]}]},
  "time": {"integrator": "implicit_euler", "dt": 0.01, "steps": 6},
  "solver": {"mass": "lumped"},
  "output": {"directory": "output/incompressible", "name": "squeeze"},
  "contact": {"enabled": true, "dhat": 1e-3, "dhat_relative": true, "barrier_stiffness": "adaptive",
              "planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}]}
}
"""
SCENES = {"drop": DROP, "squeeze": SQUEEZE}
STEP = re.compile(r"^step\s+\d+\s.*newton\s+(\d+)(?:\s+\([^)]*\))?\s+ksp\s+(\d+)")
TOTAL = re.compile(r"^total\s+([0-9.eE+-]+)")


def run(dipc, ranks, scene_path, extra, timeout):
    out, rc, cmd = run_dipc(dipc, ranks, [scene_path, "-dipc_no_output", "-snes_max_it", "1000"] + extra, timeout)
    newton = ksp = steps = 0
    wall = float("nan")
    for line in out.splitlines():
        m = STEP.match(line)
        if m:
            steps += 1
            newton += int(m.group(1))
            ksp += int(m.group(2))
        m = TOTAL.match(line)
        if m:
            wall = float(m.group(1))
    status = "ok" if rc == 0 else f"rc={rc}"
    if rc != 0:
        tail = [l for l in out.splitlines() if l.strip()][-3:]
        print("   ", " | ".join(tail)[:300], file=sys.stderr)
    return steps, newton, ksp, wall, status, " ".join(cmd)


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    keys = sorted({(r["scene"], int(r["ranks"])) for r in rows})
    fig, axes = plt.subplots(1, len(keys), figsize=(4.5 * len(keys), 4), squeeze=False)
    for ax, (scene, ranks) in zip(axes[0], keys):
        for vol, pc in dict.fromkeys((r.get("volumetric", "gauss_points"), r["pc"]) for r in rows):
            pts = sorted((float(r["nu"]), int(r["ksp_its"])) for r in rows
                         if r["scene"] == scene and int(r["ranks"]) == ranks and r["pc"] == pc
                         and r.get("volumetric", "gauss_points") == vol and r["status"] == "ok")
            if pts:
                # nu on a log scale of (0.5 - nu): 0.3, 0.45, 0.49, 0.499, 0.4999 spread evenly
                ax.plot([0.5 - n for n, _ in pts], [k for _, k in pts], marker="o", label=f"{vol}, {pc}",
                        linestyle="-" if vol == "gauss_points" else "--")
        ax.set_xscale("log")
        ax.invert_xaxis()
        ax.set_yscale("log")
        ax.set_xlabel("0.5 - nu")
        ax.set_ylabel("Krylov iterations, CG, MINRES or FGMRES (sum over the steps)")
        ax.set_title(f"{scene}, {ranks} rank{'s' if ranks > 1 else ''}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dipc", default="build/src/app/dipc")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--nu", default="0,0.3,0.45,0.49,0.499,0.4999")
    ap.add_argument("--pcs", default="theta0.5,theta0.8,nodal_theta0.8,default")
    ap.add_argument("--scenes", default="drop,squeeze")
    ap.add_argument("--volumetric", default="gauss_points,mean_dilatation",
                    help="element kinds (scene key materials[].volumetric)")
    ap.add_argument("--out", default="bench/results")
    ap.add_argument("--csv-name", default="incompressible.csv")
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--resolution", type=int, default=0,
                    help="hexes per edge of the cube (0: the scene's, drop 10, squeeze 8); for a mesh study, "
                         "best with its own --csv-name")
    ap.add_argument("--steps", type=int, default=0,
                    help="run only the first N steps (-dipc_steps N; 0: the scene's); for quick screening, "
                         "best with its own --csv-name")
    ap.add_argument("--plot-only", action="store_true", help="redraw the PNG from the CSV")
    a = ap.parse_args()
    csv_path = os.path.join(a.out, a.csv_name)
    fields = ["scene", "ranks", "volumetric", "pc", "nu", "steps", "newton_its", "ksp_its", "wall_s", "status", "options"]
    if a.resolution:
        fields.insert(5, "resolution")
    if not a.plot_only:
        os.makedirs(a.out, exist_ok=True)
        old = []
        if os.path.exists(csv_path):
            with open(csv_path) as f:
                old = [dict(r, volumetric=r.get("volumetric") or "gauss_points") for r in csv.DictReader(f)]
        key = lambda r: (r["scene"], str(r["ranks"]), r["volumetric"], r["pc"], r["nu"], str(r.get("resolution", "")))
        rows = []
        tmp_dir = tempfile.TemporaryDirectory()
        tmp = tmp_dir.name
        with open(os.path.join(tmp, "rows.csv"), "w", newline="") as f:  # this run's rows, as they come
            w = csv.DictWriter(f, fieldnames=fields)
            w.writeheader()
            for scene in a.scenes.split(","):
                for vol in a.volumetric.split(","):
                    for nu in a.nu.split(","):
                        path = os.path.join(tmp, f"{scene}_{vol}_{nu}.json")
                        with open(path, "w") as s:
                            text = SCENES[scene].replace("NU", nu).replace("VOL", vol)
                            if a.resolution:
                                text = re.sub(r'"resolution": \[\d+, \d+, \d+\]',
                                              '"resolution": [%d, %d, %d]' % ((a.resolution,) * 3), text)
                            s.write(text)
                        for ranks in [int(r) for r in a.ranks.split(",")]:
                            for pc in a.pcs.split(","):
                                if pc in NEEDS_MEAN_DILATATION and vol != "mean_dilatation":
                                    continue
                                extra = PCS[pc] + (["-dipc_steps", str(a.steps)] if a.steps else [])
                                steps, newton, ksp, wall, status, cmd = run(a.dipc, ranks, path, extra, a.timeout)
                                r = dict(scene=scene, ranks=ranks, volumetric=vol, pc=pc, nu=nu, steps=steps,
                                         newton_its=newton, ksp_its=ksp, wall_s=wall, status=status,
                                         options=" ".join(extra))
                                if a.resolution:
                                    r["resolution"] = a.resolution
                                print(f"{scene:8s} np{ranks} {vol:15s} {pc:15s} nu={nu:7s} steps {steps:3d} "
                                      f"newton {newton:4d} ksp {ksp:6d} wall {wall:7.2f} {status}", flush=True)
                                w.writerow(r)
                                f.flush()
                                rows.append(r)
        new_keys = {key(r) for r in rows}
        with open(csv_path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=fields)
            w.writeheader()
            w.writerows([r for r in old if key(r) not in new_keys] + rows)
        tmp_dir.cleanup()
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    try:
        plot(rows, os.path.splitext(csv_path)[0] + ".png")
    except ImportError:
        print("python3-matplotlib missing: no PNG", file=sys.stderr)


if __name__ == "__main__":
    main()
