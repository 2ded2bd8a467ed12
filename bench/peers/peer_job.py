#!/usr/bin/python3
"""A dipc scene as a job for bench/peers/libuipc_run (issue 34): the same bodies (the tetrahedra
hex_to_tets.py wrote on dipc's nodes), material, time step, gravity, ground plane, d̂, friction
and Newton tolerance.

    peer_job.py SCENE.json TETS_DIR [--steps N] [--velocity-tol-rel R] [--out JOB.json]

- Material: libuipc's solids are stable neo-Hookean only (Smith, de Goes & Kim 2018, in the
  form λ'/2 (J − α)² + μ'/2 (I_C − 3) − μ'/2 ln(I_C + 1)); the job gives it dipc's (λ', μ') =
  (λ + 5/6 μ, 4/3 μ) of the material's E and ν (src/physics/stable_neo_hookean.hpp), so both
  codes minimise the same energy density up to a constant. A body of another model is refused:
  run the comparison on a copy of the scene whose materials say "model": "stable_neo_hookean".
- d̂ and the Newton tolerance are lengths and speeds of dipc's: d̂ times the bodies' bounding-box
  diagonal where the scene's d̂ is relative (dipc's default), and |Δx|_inf / dt below R times
  the diagonal (R = 1e-5, dipc's balanced preset, unless given), which libuipc's velocity_tol
  tests in the same way.
- Contact: the scene's one contact plane becomes libuipc's ground (a half-space); obstacle meshes,
  more planes and prescribed nodes are refused (not yet translated).
- Kinematic bodies: "fixed" (every node fixed in libuipc too) and "velocity" (X + v t; libuipc
  holds it by its soft position constraint, a penalty, where dipc prescribes it exactly); their
  material's model does not matter. Other motions are refused.
- Friction: μ and ε_v as given; libuipc lags friction per Newton solve as dipc's one lagged
  update per step does.
"""
import argparse
import json
import math
import os
import sys

from hex_to_tets import read_msh  # the reader of the files hex_to_tets.py writes


class JobError(Exception):
    pass


def make_job(scene_path, tets_dir, steps=None, velocity_tol_rel=1e-5):
    with open(scene_path) as f:
        scene = json.load(f)
    with open(os.path.join(tets_dir, "tets.json")) as f:
        tets = json.load(f)
    materials = {m["name"]: m for m in scene.get("materials", [])}
    geometry = {g["name"]: g for g in scene.get("geometry", [])}
    contact = scene.get("contact", {})
    if not contact.get("enabled", False):
        raise JobError(f"{scene_path}: contact is off; the peer comparison is about contact")
    if contact.get("obstacles"):
        raise JobError(f"{scene_path}: contact.obstacles: obstacle meshes are not translated for the peer yet")
    planes = contact.get("planes", [])
    if len(planes) > 1:
        raise JobError(f"{scene_path}: contact.planes: {len(planes)} planes; the peer takes one ground plane")
    if scene.get("boundary_conditions", {}).get("dirichlet"):
        raise JobError(f"{scene_path}: boundary_conditions.dirichlet: prescribed nodes are not translated for the peer yet")

    bodies, lo, hi = [], [math.inf] * 3, [-math.inf] * 3
    for b in tets["bodies"]:
        g = geometry.get(b["name"])
        if g is None:
            raise JobError(f"{tets_dir}/tets.json: body {b['name']!r} is not in {scene_path}")
        kinematic = g.get("kinematic")
        if kinematic and kinematic.get("type") not in ("fixed", "velocity"):
            raise JobError(f"{scene_path}: geometry {b['name']!r}: kinematic type {kinematic.get('type')!r} is not "
                           "translated for the peer (fixed and velocity are)")
        name = g.get("material") or (next(iter(materials)) if len(materials) == 1 else None)
        if name not in materials:
            raise JobError(f"{scene_path}: geometry {b['name']!r}: material {name!r} not found")
        m = materials[name]
        if m.get("model", "neo_hookean") != "stable_neo_hookean" and not kinematic:
            raise JobError(f"{scene_path}: material {name!r}: model {m.get('model', 'neo_hookean')!r}; libuipc's "
                           "solids are stable neo-Hookean only: compare on a copy with \"model\": \"stable_neo_hookean\"")
        E, nu = float(m["E"]), float(m["nu"])
        lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
        nodes, _ = read_msh(os.path.join(tets_dir, b["msh"]))
        lo = [min(a, c) for a, c in zip(lo, nodes.min(axis=0).tolist())]
        hi = [max(a, c) for a, c in zip(hi, nodes.max(axis=0).tolist())]
        bodies.append({"name": b["name"], "msh": os.path.relpath(os.path.join(tets_dir, b["msh"])),
                       "lambda": lam + 5.0 / 6.0 * mu, "mu": 4.0 / 3.0 * mu, "rho": float(m.get("rho", 1000.0)),
                       "velocity": g.get("initial_velocity", [0.0, 0.0, 0.0]), "num_nodes": b["num_nodes"]})
        if kinematic:
            bodies[-1]["kinematic"] = kinematic
    diagonal = math.dist(lo, hi)
    dhat = float(contact.get("dhat", 1e-3))
    if contact.get("dhat_relative", True):
        dhat *= diagonal
    time = scene.get("time", {})
    if time.get("integrator", "implicit_euler") != "implicit_euler":
        raise JobError(f"{scene_path}: time.integrator {time['integrator']!r}: the peer runs implicit Euler (bdf1)")
    dt = float(time["dt"])
    job = {
        "scene": os.path.abspath(scene_path),
        "dt": dt,
        "frames": int(steps if steps is not None else time.get("steps", 1)),
        "gravity": scene.get("boundary_conditions", {}).get("gravity", [0.0, 0.0, 0.0]),
        "d_hat": dhat,
        "friction": float(contact.get("friction", contact.get("friction_coefficient", 0.0))),
        "eps_velocity": float(contact.get("epsv", 1e-3)),
        "velocity_tol": velocity_tol_rel * diagonal,
        "bounding_box_diagonal": diagonal,
        "bodies": bodies,
    }
    if planes:
        n = [float(v) for v in planes[0]["normal"]]
        length = math.sqrt(sum(v * v for v in n))
        n = [v / length for v in n]
        job["ground"] = {"normal": n, "height": sum(p * v for p, v in zip(planes[0]["point"], n))}
    return job


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene")
    parser.add_argument("tets_dir")
    parser.add_argument("--steps", type=int)
    parser.add_argument("--velocity-tol-rel", type=float, default=1e-5)
    parser.add_argument("--out", default=None, help="default: TETS_DIR/job.json")
    args = parser.parse_args(argv)
    try:
        job = make_job(args.scene, args.tets_dir, args.steps, args.velocity_tol_rel)
    except (OSError, KeyError, ValueError, JobError) as e:
        print(f"peer_job: {e}", file=sys.stderr)
        return 1
    out = args.out or os.path.join(args.tets_dir, "job.json")
    # The bodies' files relative to the job's folder, where libuipc_run looks for them.
    for b in job["bodies"]:
        b["msh"] = os.path.relpath(os.path.abspath(b["msh"]), os.path.dirname(os.path.abspath(out)))
    with open(out, "w") as f:
        json.dump(job, f, indent=1)
    print(f"{out}: {len(job['bodies'])} bodies, {sum(b['num_nodes'] for b in job['bodies'])} nodes, "
          f"dt {job['dt']}, {job['frames']} frames, d_hat {job['d_hat']:.4g}, velocity_tol {job['velocity_tol']:.4g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
