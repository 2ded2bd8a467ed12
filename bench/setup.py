#!/usr/bin/env python3
"""Setup benchmark (issue 14, part 4): time to the first Newton iteration and peak memory per rank,
per phase, against the mesh size, for each rank count and partitioner.

  bench/setup.py [--dipc build/src/app/dipc] [--elements 100000,1000000,4000000,16000000]
                 [--ranks 1,2] [--partitioners metis,ptscotch,rcb] [--source generated,hdf5]
                 [--tag cpu] [--out bench/results] [--timeout 600] [--cores-per-rank K]
                 [-- extra dipc options]

The scene: one cube of n^3 hexes (n = round(elements^(1/3))), rubber (E = 1 MPa), resting 1 cm
above the contact plane z = 0 under gravity, contact on, so the setup builds the contact surface
too. source "generated" gives it as a box (every rank generates its rows); "hdf5" writes the same
mesh as a dipc HDF5 mesh file first (numpy + h5py, outside the timing) and names it as the
body's mesh (every rank reads its rows). Each run is
  mpirun -n R dipc scene.json -dipc_setup_only -dipc_no_output -dipc_partitioner P [extra]
which builds everything up to the first Newton iteration and stops. From its report:
  partition_s, setup_s        the timing table's rows (slowest rank); first_iteration_s = their sum
  slices_s .. surface_s       the partition's phases (run header, slowest rank per phase)
  edge_cut, interior_faces, imbalance   the partition's quality (run header)
  setup_threads               rank 0's threads for the partition's and the setup's host loops
                              (run header; --cores-per-rank K binds each rank to K cores for them)
  rss_*_mib                   peak resident memory (ru_maxrss) after partition / after setup,
                              largest and smallest rank; mib_per_melement_rank = largest rank's
                              peak over its share of the elements in millions
  cpu_s                       user + system CPU seconds of all ranks (getrusage of the children):
                              on a shared machine wall times stretch, CPU time much less.
Rows go to <out>/setup_<tag>.csv (rows of the same elements, ranks, partitioner and source are
replaced) and a plot to <out>/setup_<tag>.png (python3-matplotlib).
"""
import argparse
import csv
import os
import re
import resource
import sys
import tempfile
import time

from bench_csv import earlier_rows
from pyplot import pyplot_or_none
from run_dipc import run_dipc

FIELDS = ["elements", "ranks", "partitioner", "source", "setup_threads", "first_iteration_s", "partition_s", "setup_s", "slices_s",
          "faces_s", "partitioner_s", "quality_s", "elements_s", "nodes_s", "surface_s", "edge_cut", "interior_faces",
          "imbalance", "rss_partition_max_mib", "rss_setup_max_mib", "rss_setup_min_mib", "mib_per_melement_rank",
          "cpu_s", "wall_s", "status"]


def scene_text(n, mesh_file=None):
    body = ('{"name": "block", "mesh": "%s", "material": "rubber"}' % mesh_file if mesh_file else
            '{"name": "block", "box": {"size": [1, 1, 1], "resolution": [%d, %d, %d], "origin": [0, 0, 0.01]}, '
            '"material": "rubber"}' % (n, n, n))
    return ('{"materials": [{"name": "rubber", "E": 1e6, "nu": 0.4, "rho": 1000}], "geometry": [%s], '
            '"boundary_conditions": {"gravity": [0, 0, -9.81]}, '
            '"contact": {"enabled": true, "planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}]}, '
            '"time": {"dt": 0.01, "steps": 1}}' % body)


def write_box_h5(path, n):
    """The generated box's rows (box_generator.hpp numbering) as a dipc HDF5 mesh file."""
    import h5py
    import numpy as np
    t = np.arange(n + 1, dtype=np.float64) / n  # size * i / n with size 1, as generate_box computes it
    z, y, x = np.meshgrid(0.01 + t, t, t, indexing="ij")
    coords = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    p = n + 1
    k, j, i = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    base = (i + p * (j + p * k)).ravel().astype(np.int64)
    offsets = [0, 1, 1 + p, p, p * p, 1 + p * p, 1 + p + p * p, p + p * p]
    topo = np.stack([base + o for o in offsets], axis=1)
    with h5py.File(path, "w") as f:
        f["/mesh/coordinates"] = coords
        f["/mesh/topology"] = topo


def parse(text):
    row = {}
    for name, key in [("partition", "partition_s"), ("setup", "setup_s")]:
        m = re.search(r"^%s\s+([0-9.]+)\s*$" % name, text, re.M)
        if m:
            row[key] = float(m.group(1))
    m = re.search(r"partition phases \(s\): slices ([0-9.]+) faces ([0-9.]+) partitioner ([0-9.]+) quality ([0-9.]+) "
                  r"elements ([0-9.]+) nodes ([0-9.]+) surface ([0-9.]+)", text)
    if m:
        for k, v in zip(["slices_s", "faces_s", "partitioner_s", "quality_s", "elements_s", "nodes_s", "surface_s"],
                        m.groups()):
            row[k] = float(v)
    m = re.search(r"edge cut (\d+) of (\d+) interior faces \| imbalance ([0-9.]+)", text)
    if m:
        row["edge_cut"], row["interior_faces"], row["imbalance"] = int(m.group(1)), int(m.group(2)), float(m.group(3))
    m = re.search(r"after partition ([0-9.]+)/([0-9.]+), after setup ([0-9.]+)/([0-9.]+)", text)
    if m:
        row["rss_partition_max_mib"] = float(m.group(1))
        row["rss_setup_max_mib"], row["rss_setup_min_mib"] = float(m.group(3)), float(m.group(4))
    m = re.search(r"setup threads (\d+)", text)
    if m:
        row["setup_threads"] = int(m.group(1))
    m = re.search(r"elements (\d+) \(", text)
    if m:
        row["elements"] = int(m.group(1))
    return row


def run_one(args, n, ranks, partitioner, source, workdir):
    mesh_file = None
    if source == "hdf5":
        mesh_file = os.path.join(workdir, "box_%d.h5" % n)
        if not os.path.exists(mesh_file):
            write_box_h5(mesh_file, n)
    scene = os.path.join(workdir, "setup_%d_%s.json" % (n, source))
    with open(scene, "w") as f:
        f.write(scene_text(n, mesh_file))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.time()
    text, status, cmd = run_dipc(args.dipc, ranks, [scene, "-dipc_setup_only", "-dipc_no_output",
                                                    "-dipc_partitioner", partitioner] + args.extra,
                                 timeout=args.timeout, cores_per_rank=args.cores_per_rank)
    wall = time.time() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    row = {"elements": n ** 3, "ranks": ranks, "partitioner": partitioner, "source": source, "status": status,
           "wall_s": round(wall, 3),
           "cpu_s": round((after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), 3)}
    row.update(parse(text))
    if "partition_s" in row and "setup_s" in row:
        row["first_iteration_s"] = round(row["partition_s"] + row["setup_s"], 3)
    if "rss_setup_max_mib" in row:
        share = row["elements"] / ranks / 1e6
        row["mib_per_melement_rank"] = round(max(row["rss_setup_max_mib"], row.get("rss_partition_max_mib", 0)) / share, 1)
    if status != 0:
        sys.stderr.write("failed (%s): %s\n%s\n" % (status, " ".join(cmd), text[-2000:]))
    return row


def plot(rows, path):
    plt = pyplot_or_none()
    if plt is None:
        return
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8))
    # Rows read back from the CSV hold strings, rows of this run numbers: group by (int, str, str).
    def group(r):
        return (int(r["ranks"]), r["partitioner"], r["source"])
    groups = sorted({group(r) for r in rows})
    for g in groups:
        sel = sorted([r for r in rows if group(r) == g and r.get("first_iteration_s")],
                     key=lambda r: int(r["elements"]))
        if not sel:
            continue
        x = [int(r["elements"]) for r in sel]
        label = "%s ranks, %s, %s" % g
        axes[0].plot(x, [float(r["first_iteration_s"]) for r in sel], "o-", label=label)
        axes[1].plot(x, [float(r["mib_per_melement_rank"]) for r in sel], "o-", label=label)
        if int(g[0]) > 1:
            axes[2].plot(x, [int(r["edge_cut"]) / max(1, int(r["interior_faces"])) for r in sel], "o-", label=label)
    axes[0].set_title("partition + setup: time to the first Newton iteration")
    axes[0].set_ylabel("seconds (slowest rank)")
    axes[1].set_title("peak host memory of the fullest rank")
    axes[1].set_ylabel("MiB per million elements of the rank")
    axes[1].axhline(2048, color="k", ls=":", label="target 2 GB / M elements")
    axes[2].set_title("partition quality")
    axes[2].set_ylabel("edge cut / interior faces")
    for a in axes:
        a.set_xscale("log")
        a.set_xlabel("elements")
        a.grid(True, which="both", alpha=0.3)
    axes[0].set_yscale("log")
    axes[0].legend(fontsize=7)
    axes[2].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dipc", default="build/src/app/dipc")
    ap.add_argument("--elements", default="100000")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--partitioners", default="metis,ptscotch,rcb")
    ap.add_argument("--source", default="generated")
    ap.add_argument("--tag", default="cpu")
    ap.add_argument("--out", default="bench/results")
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--cores-per-rank", type=int, default=None,
                    help="bind each rank to this many cores (mpirun --map-by slot:PE=K) for the setup threads")
    ap.add_argument("extra", nargs="*", help="after --: more dipc options")
    args = ap.parse_args()
    csv_path, rows = earlier_rows(args.out, "setup_%s.csv" % args.tag)
    with tempfile.TemporaryDirectory() as workdir:
        for e in [int(v) for v in args.elements.split(",")]:
            n = max(1, round(e ** (1.0 / 3.0)))
            for source in args.source.split(","):
                for ranks in [int(v) for v in args.ranks.split(",")]:
                    for partitioner in args.partitioners.split(","):
                        if ranks == 1 and partitioner != args.partitioners.split(",")[0]:
                            continue  # one rank needs no partitioner: one row is enough
                        row = run_one(args, n, ranks, partitioner, source, workdir)
                        print(", ".join("%s=%s" % (k, row.get(k, "")) for k in FIELDS), flush=True)
                        key = (str(row["elements"]), str(ranks), partitioner, source)
                        rows = [r for r in rows if (str(r["elements"]), str(r["ranks"]), r["partitioner"], r["source"]) != key]
                        rows.append({k: row.get(k, "") for k in FIELDS})
                        with open(csv_path, "w", newline="") as f:
                            w = csv.DictWriter(f, fieldnames=FIELDS)
                            w.writeheader()
                            w.writerows(sorted(rows, key=lambda r: (r["source"], int(r["ranks"]), r["partitioner"], int(r["elements"]))))
    plot(rows, os.path.join(args.out, "setup_%s.png" % args.tag))
    print("wrote", csv_path)


if __name__ == "__main__":
    main()
