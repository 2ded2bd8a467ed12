#!/usr/bin/env python3
"""dipc's output opened by ParaView itself (issue 13 part 8): a 2-rank run of a scene with a
deformable box, a kinematic pusher and a ground plane, read with both of ParaView's XDMF readers
through pvbatch. Each reader must list every written step and show the blocks box, pusher and
plane0 in that order, the box's and the pusher's hexahedra with their cell fields (volume_ratio,
rank, body, kinematic: the pusher's block holds only body 1) and node fields (displacement,
velocity, contact_force, friction_force).

Exits 77 (CTest: skipped) when pvbatch is not installed (Debian: python3-paraview).
Usage: paraview_open_test.py --dipc build/src/app/dipc --mpiexec "mpiexec --oversubscribe" --work DIR
"""
import argparse
import json
import os
import shlex
import shutil
import subprocess
import sys

SCENE = """{
  "materials": [{"name": "rubber", "E": 1e5, "nu": 0.3, "rho": 1000}],
  "geometry": [
    {"name": "box", "box": {"size": [0.1, 0.1, 0.1], "resolution": [2, 2, 2], "origin": [0, 0, 0.0005]}},
    {"name": "pusher", "box": {"size": [0.05, 0.05, 0.05], "resolution": [1, 1, 1], "origin": [0.102, 0.025, 0.02]},
     "kinematic": {"type": "velocity", "velocity": [-0.2, 0, 0]}}],
  "boundary_conditions": {"gravity": [0, 0, -9.81]},
  "time": {"integrator": "implicit_euler", "dt": 0.01, "steps": 3},
  "contact": {"enabled": true, "dhat": 1e-3, "dhat_relative": false, "friction": 0.2, "epsv": 1e-3,
              "planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}]}
}
"""
CELL_FIELDS = ["body", "kinematic", "rank", "volume_ratio"]
NODE_FIELDS = ["contact_force", "displacement", "friction_force", "velocity"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dipc", required=True)
    parser.add_argument("--mpiexec", required=True)
    parser.add_argument("--work", required=True)
    args = parser.parse_args()
    pvbatch = shutil.which("pvbatch")
    if pvbatch is None:
        print("SKIP: pvbatch not found (Debian package python3-paraview)")
        return 77
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    scene, out = os.path.join(args.work, "scene.json"), os.path.join(args.work, "out")
    with open(scene, "w") as f:
        f.write(SCENE)
    command = shlex.split(args.mpiexec) + ["-n", "2", args.dipc, scene, "-dipc_quiet", "-dipc_output", out]
    subprocess.run(command, check=True, timeout=600)
    reader_script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "paraview_read.py")
    result = subprocess.run([pvbatch, "--force-offscreen-rendering", reader_script, os.path.join(out, "dipc.xmf")],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
    reads = [json.loads(line[5:]) for line in result.stdout.splitlines() if line.startswith("READ ")]
    if result.returncode != 0 or len(reads) != 2:
        sys.exit("FAIL: pvbatch exited %d:\n%s" % (result.returncode, result.stdout[-3000:]))
    for read in reads:
        what = "ParaView's %s reader" % read["reader"]
        print("%s: %d steps, blocks %s" % (what, read["times"], [(b["cells"], b["body"]) for b in read["blocks"]]))
        assert read["times"] == 4, "%s lists %d steps, dipc wrote 4" % (what, read["times"])
        box, pusher, plane = read["blocks"]
        for name, block, cells, body in (("box", box, 8, [0, 0]), ("pusher", pusher, 1, [1, 1])):
            assert block["cells"] == cells, "%s: block %s has %d cells" % (what, name, block["cells"])
            assert block["cell_arrays"] == CELL_FIELDS, "%s: %s cell fields %s" % (what, name, block["cell_arrays"])
            assert block["point_arrays"] == NODE_FIELDS, "%s: %s node fields %s" % (what, name, block["point_arrays"])
            assert block["body"] == body, "%s: block %s holds bodies %s" % (what, name, block["body"])
        assert plane["cells"] == 1 and plane["point_arrays"] == ["displacement"], "%s: plane block %s" % (what, plane)
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
