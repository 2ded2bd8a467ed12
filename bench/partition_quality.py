#!/usr/bin/env python3
"""Partition quality on a mesh that is not a box (issue 14: edge cut and imbalance of the
partitioners side by side on the same meshes; bench/setup.py does the same for cubes).

  bench/partition_quality.py [--dipc build/src/app/dipc] [--voxelize build/src/tools/dipc-voxelize]
                             [--resolution 90] [--ranks 4,8] [--partitioners metis,ptscotch,rcb]
                             [--tag cpu] [--out bench/results] [--timeout 600]

The scene: the ball and the roller of scenes/meshes (closed OBJ surfaces) voxelized into hexes
with boundary snapping (dipc-voxelize --snap: curved, unstructured-looking boundaries), side by
side above the contact plane, so that a partitioner sees two bodies of different shapes. Each
run is `mpirun -n R dipc scene.json -dipc_setup_only -dipc_no_output -dipc_partitioner P`; the
run header gives the edge cut (interior faces between ranks), the imbalance (largest part over
the mean) and the part sizes, the timing table the partition's seconds (slowest rank; on a
shared machine, wall seconds stretch). Rows go to <out>/partition_quality_<tag>.csv.
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
import tempfile

from run_dipc import run_dipc

FIELDS = ["mesh", "elements", "ranks", "partitioner", "edge_cut", "interior_faces", "imbalance", "smallest_part",
          "largest_part", "partition_s", "status"]
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def voxelize(tool, name, resolution, workdir):
    out = os.path.join(workdir, name + ".msh")
    subprocess.run([tool, os.path.join(ROOT, "scenes", "meshes", name + ".obj"), out, "--resolution", str(resolution),
                    "--snap"], check=True, stdout=subprocess.DEVNULL)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dipc", default=os.path.join(ROOT, "build", "src", "app", "dipc"))
    ap.add_argument("--voxelize", default=os.path.join(ROOT, "build", "src", "tools", "dipc-voxelize"))
    ap.add_argument("--resolution", type=int, default=90)
    ap.add_argument("--ranks", default="4,8")
    ap.add_argument("--partitioners", default="metis,ptscotch,rcb")
    ap.add_argument("--tag", default="cpu")
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--timeout", type=int, default=600)
    args, extra = ap.parse_known_args()
    extra = [a for a in extra if a != "--"]
    os.makedirs(args.out, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as workdir:
        ball = voxelize(args.voxelize, "ball", args.resolution, workdir)
        roller = voxelize(args.voxelize, "roller", args.resolution, workdir)
        scene = {"materials": [{"name": "rubber", "E": 1e6, "nu": 0.4, "rho": 1000}],
                 "geometry": [{"name": "ball", "mesh": ball, "translation": [0, 0, 0.05], "material": "rubber"},
                              {"name": "roller", "mesh": roller, "translation": [0.2, 0, 0.07], "material": "rubber"}],
                 "boundary_conditions": {"gravity": [0, 0, -9.81]},
                 "contact": {"enabled": True, "planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}]},
                 "time": {"dt": 0.01, "steps": 1}}
        path = os.path.join(workdir, "ball_roller.json")
        with open(path, "w") as f:
            json.dump(scene, f)
        mesh = "ball+roller r%d" % args.resolution
        for ranks in [int(r) for r in args.ranks.split(",")]:
            for p in args.partitioners.split(","):
                text, status, _ = run_dipc(args.dipc, ranks, [path, "-dipc_setup_only", "-dipc_no_output",
                                                              "-dipc_partitioner", p] + extra, timeout=args.timeout)
                row = {"mesh": mesh, "ranks": ranks, "partitioner": p, "status": status}
                m = re.search(r"elements (\d+) \(", text)
                if m:
                    row["elements"] = int(m.group(1))
                m = re.search(r"edge cut (\d+) of (\d+) interior faces \| imbalance ([0-9.]+) \(parts (\d+)\.\.(\d+)\)", text)
                if m:
                    row.update(edge_cut=int(m.group(1)), interior_faces=int(m.group(2)), imbalance=float(m.group(3)),
                               smallest_part=int(m.group(4)), largest_part=int(m.group(5)))
                m = re.search(r"^partition\s+([0-9.]+)", text, re.M)
                if m:
                    row["partition_s"] = float(m.group(1))
                if status != 0:
                    sys.stderr.write("failed (%s):\n%s\n" % (status, text[-2000:]))
                print(", ".join("%s=%s" % (k, row.get(k, "")) for k in FIELDS), flush=True)
                rows.append(row)
    csv_path = os.path.join(args.out, "partition_quality_%s.csv" % args.tag)
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    print("wrote", csv_path)


if __name__ == "__main__":
    main()
