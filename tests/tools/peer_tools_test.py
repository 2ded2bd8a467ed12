#!/usr/bin/python3
"""bench/peers' chain on a dipc run (issue 34): hex_to_tets.py cuts a 1-rank run of a small stable
neo-Hookean stack into tetrahedra, peer_job.py writes the peer's job (dipc's (λ', μ'), d̂ and
Newton tolerance from the bounding-box diagonal, the ground plane, kinematic bodies) and refuses
what it does not translate, and peer_output.py turns a stand-in peer run (dipc's own positions, in the
tetrahedra's node order) into an output that the judge passes and that differs from dipc's by
nothing; a malformed frame is refused.

    peer_tools_test.py --dipc build/src/app/dipc --work DIR
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
PEERS = os.path.join(HERE, "..", "..", "bench", "peers")
STACK = os.path.join(HERE, "..", "..", "bench", "contact_family", "stack.json")


def run(*args, expect=0):
    r = subprocess.run([sys.executable, *args], capture_output=True, text=True)
    if r.returncode != expect:
        raise AssertionError(f"{' '.join(args)}: exit {r.returncode}, expected {expect}\n{r.stdout}{r.stderr}")
    return r.stdout + r.stderr


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--dipc", required=True)
    p.add_argument("--work", required=True)
    a = p.parse_args()
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    with open(STACK) as f:
        scene = json.load(f)
    scene["materials"][0]["model"] = "stable_neo_hookean"
    for g in scene["geometry"]:
        g["box"]["resolution"] = [3, 3, 3]
    scene["output"]["directory"] = os.path.join(a.work, "out")
    scene_path = os.path.join(a.work, "stack_snh.json")
    with open(scene_path, "w") as f:
        json.dump(scene, f)
    subprocess.run([a.dipc, scene_path, "-dipc_steps", "2", "-dipc_quiet"], check=True)
    h5 = os.path.join(a.work, "out", "stack.h5")
    tets = os.path.join(a.work, "tets")
    run(os.path.join(PEERS, "hex_to_tets.py"), h5, tets)

    # The job.
    run(os.path.join(PEERS, "peer_job.py"), scene_path, tets, "--steps", "2")
    with open(os.path.join(tets, "job.json")) as f:
        job = json.load(f)
    E, nu = 1e6, 0.4
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    body = job["bodies"][0]
    assert math.isclose(body["lambda"], lam + 5 / 6 * mu) and math.isclose(body["mu"], 4 / 3 * mu), body
    assert body["velocity"] == [0, 0, -0.5] and len(job["bodies"]) == 8
    with h5py.File(h5) as f:
        X = f["mesh/coordinates"][...]
    diagonal = float(np.linalg.norm(X.max(0) - X.min(0)))
    assert math.isclose(job["d_hat"], 1e-3 * diagonal) and math.isclose(job["velocity_tol"], 1e-5 * diagonal), job
    assert job["ground"] == {"normal": [0.0, 0.0, 1.0], "height": 0.0} and job["frames"] == 2 and job["dt"] == 0.002
    for path, words in [(STACK, "stable neo-Hookean only"),
                        (os.path.join(HERE, "..", "..", "bench", "contact_family", "squeeze.json"), "not in")]:
        out = run(os.path.join(PEERS, "peer_job.py"), path, tets, "--out", os.path.join(a.work, "refused.json"), expect=1)
        assert words in out, out
    for change, words in [(lambda s: s["contact"].update(obstacles=[{"name": "o", "mesh": "x.obj"}]), "obstacle"),
                          (lambda s: s["geometry"][0].update(kinematic={"type": "rotation"}), "kinematic type")]:
        s = json.loads(json.dumps(scene))
        change(s)
        path = os.path.join(a.work, "changed.json")
        with open(path, "w") as f:
            json.dump(s, f)
        out = run(os.path.join(PEERS, "peer_job.py"), path, tets, "--out", os.path.join(a.work, "refused.json"), expect=1)
        assert words in out, out

    # A kinematic body moving at a velocity goes to the job with its motion (neo-Hookean or not).
    s = json.loads(json.dumps(scene))
    s["geometry"][0]["kinematic"] = {"type": "velocity", "velocity": [0, 0, -0.2]}
    path = os.path.join(a.work, "kinematic.json")
    with open(path, "w") as f:
        json.dump(s, f)
    run(os.path.join(PEERS, "peer_job.py"), path, tets, "--out", os.path.join(a.work, "kinematic_job.json"))
    with open(os.path.join(a.work, "kinematic_job.json")) as f:
        moving = json.load(f)["bodies"]
    assert moving[0]["kinematic"] == {"type": "velocity", "velocity": [0, 0, -0.2]} and "kinematic" not in moving[1]

    # A stand-in peer run: dipc's positions in the tetrahedra's node order.
    with open(os.path.join(tets, "tets.json")) as f:
        bodies = json.load(f)["bodies"]
    ids = np.concatenate([np.loadtxt(os.path.join(tets, b["nodes"]), dtype=np.int64, ndmin=1) for b in bodies])
    run_dir = os.path.join(a.work, "run")
    os.makedirs(run_dir)
    with h5py.File(h5) as f:
        for k in sorted(f["steps"].keys(), key=int):
            (X + f[f"steps/{k}/displacement"][...])[ids].tofile(os.path.join(run_dir, f"frame_{k}.bin"))
    peer = os.path.join(a.work, "peer.h5")
    summary = json.loads(run(os.path.join(PEERS, "peer_output.py"), h5, tets, run_dir, peer))
    assert summary["frames"] == 3 and summary["tets"] == 6 * summary["elements_of_dipc"], summary
    assert max(summary["centre_error_rel"]) == 0 and max(summary["max_node_error_rel"]) == 0, summary
    assert 0.9 < summary["min_tet_volume_ratio"] <= 1.0, summary
    judged = json.loads(run(os.path.join(HERE, "judge_output.py"), peer, scene_path).strip().splitlines()[-1])
    assert judged["ok"] and judged["steps"] == 3 and judged["intersections"] == 0, judged
    np.zeros(5).tofile(os.path.join(run_dir, "frame_1.bin"))
    out = run(os.path.join(PEERS, "peer_output.py"), h5, tets, run_dir, os.path.join(a.work, "bad.h5"), expect=1)
    assert "frame_1.bin: 5 values" in out and not os.path.exists(os.path.join(a.work, "bad.h5")), out
    print("peer tools: ok")


if __name__ == "__main__":
    main()
