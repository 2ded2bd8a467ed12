#!/usr/bin/env python3
"""Volumetric locking: tip deflection of a cantilever under its own weight against nu, mesh and
element (issue 11, part 4).

  bench/locking.py [--dipc build/src/app/dipc] [--nu 0.3,0.49,0.499,0.4999]
                   [--meshes 10x1x1,20x2x2,40x4x4] [--out bench/results]

A steel-like beam (L = 1 m, square section h = 0.1 m, E = 1e8 Pa, rho = 1000 kg/m^3) clamped at
x = 0 (Dirichlet "beam.xmin"), loaded by gravity -z, one static load step. Its deflection is
compared with Euler-Bernoulli, delta = q L^4 / (8 E I) with q = rho g h^2 and I = h^4/12
(0.0147 m; shear adds about 1 % at L/h = 10, large-deflection effects are below that): the
ratio delta / delta_EB is ~1 for an element that does not lock, whatever nu, and falls
towards 0 as nu -> 0.5 for one that does. Each mesh runs with both element kinds (scene key
materials[].volumetric). The tip deflection is the mean z displacement of the nodes at x = L,
read from the run's HDF5 output (h5py). Writes <out>/locking.csv and <out>/locking.png.
"""
import argparse
import csv
import os
import sys
import tempfile

import h5py
import numpy as np

from run_dipc import run_dipc

SCENE = """{
  "materials": [{"name": "m", "E": 1e8, "nu": NU, "rho": 1000, "volumetric": "VOL"}],
  "geometry": [{"name": "beam", "box": {"size": [1, 0.1, 0.1], "resolution": [NX, NY, NZ], "origin": [0, 0, 0]},
                "material": "m"}],
  "boundary_conditions": {"gravity": [0, 0, -9.81], "dirichlet": [{"selection": "beam.xmin", "type": "fixed"}]},
  "time": {"integrator": "static", "dt": 1, "steps": 1},
  "output": {"directory": "OUT", "name": "beam"}
}
"""
DELTA_EB = 12 * 1000 * 9.81 * 1.0**4 / (8 * 1e8 * 0.1**2)


def tip_deflection(h5_path):
    with h5py.File(h5_path, "r") as f:
        X = f["/mesh/coordinates"][...]
        last = max(f["/steps"].keys(), key=int)
        u = f[f"/steps/{last}/displacement"][...]
    tip = np.isclose(X[:, 0], X[:, 0].max())
    return -float(u[tip, 2].mean())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dipc", default="build/src/app/dipc")
    ap.add_argument("--nu", default="0.3,0.49,0.499,0.4999")
    ap.add_argument("--meshes", default="10x1x1,20x2x2,40x4x4")
    ap.add_argument("--out", default="bench/results")
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for mesh in a.meshes.split(","):
            nx, ny, nz = mesh.split("x")
            for vol in ("gauss_points", "mean_dilatation"):
                for nu in a.nu.split(","):
                    out = os.path.join(tmp, f"{mesh}_{vol}_{nu}")
                    scene = os.path.join(tmp, f"{mesh}_{vol}_{nu}.json")
                    with open(scene, "w") as s:
                        s.write(SCENE.replace("NU", nu).replace("VOL", vol).replace("NX", nx).replace("NY", ny)
                                .replace("NZ", nz).replace("OUT", out))
                    text, status, _ = run_dipc(a.dipc, 1, [scene, "-dipc_quiet"])
                    if status != 0:
                        print(text[-4000:], file=sys.stderr)
                        sys.exit(f"dipc failed on {scene} (exit {status})")
                    d = tip_deflection(os.path.join(out, "beam.h5"))
                    rows.append(dict(mesh=mesh, volumetric=vol, nu=nu, tip_deflection=d, ratio_to_euler_bernoulli=d / DELTA_EB))
                    print(f"{mesh:9s} {vol:16s} nu={nu:7s} tip {d:.5e} m  delta/delta_EB {d / DELTA_EB:.3f}", flush=True)
    os.makedirs(a.out, exist_ok=True)
    path = os.path.join(a.out, "locking.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("python3-matplotlib missing: no PNG", file=sys.stderr)
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    for mesh in a.meshes.split(","):
        for vol, style in (("gauss_points", "-"), ("mean_dilatation", "--")):
            pts = [(0.5 - float(r["nu"]), r["ratio_to_euler_bernoulli"]) for r in rows
                   if r["mesh"] == mesh and r["volumetric"] == vol]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], style, marker="o", label=f"{mesh} {vol}")
    ax.set_xscale("log")
    ax.invert_xaxis()
    ax.set_xlabel("0.5 - nu")
    ax.set_ylabel("tip deflection / Euler-Bernoulli")
    ax.set_title("cantilever under gravity, L/h = 10")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "locking.png"), dpi=110)


if __name__ == "__main__":
    main()
