#!/usr/bin/python3
"""A peer's run of a dipc scene (bench/peers/libuipc_run: frame_<k>.bin, the positions of the
tetrahedra's nodes, body by body as in TETS_DIR/tets.json) written as a dipc output, so that
tests/tools/judge_output.py judges it as it judges dipc's, and compared with dipc's run.

    peer_output.py DIPC_OUTPUT.h5 TETS_DIR RUN_DIR OUT.h5

DIPC_OUTPUT.h5 is the dipc run the tetrahedra came from (its mesh is copied: the same nodes).
OUT.h5 gets one step per frame (steps/<k>/displacement). Prints one JSON line: frames, the
smallest tetrahedron volume over the frames relative to its rest volume (the peer's own
elements: the judge's det J test is of hexahedra), and per frame the distance between the two
runs' centres of mass and the largest nodal distance, both relative to the bodies' bounding-box
diagonal, over the frames both runs have. Exits 1 where a frame is missing or malformed.
"""
import argparse
import json
import os
import sys

import h5py
import numpy as np

from hex_to_tets import read_msh  # the reader of the files hex_to_tets.py writes


def convert(dipc_path, tets_dir, run_dir, out_path):
    with open(os.path.join(tets_dir, "tets.json")) as f:
        bodies = json.load(f)["bodies"]
    ids = [np.loadtxt(os.path.join(tets_dir, b["nodes"]), dtype=np.int64, ndmin=1) for b in bodies]
    tets = [read_msh(os.path.join(tets_dir, b["msh"]))[1] + sum(len(i) for i in ids[:k]) for k, b in enumerate(bodies)]
    ids, tets = np.concatenate(ids), np.concatenate(tets)
    with h5py.File(dipc_path, "r") as src:
        X = src["mesh/coordinates"][...]
        body = src["mesh/body"][...]
        dipc_steps = sorted(src["steps"].keys(), key=int)
        dipc_x = {int(k): X + src[f"steps/{k}/displacement"][...] for k in dipc_steps}
        tmp = out_path + ".part"
        with h5py.File(tmp, "w") as out:
            src.copy("mesh", out)
            frames = 0
            while os.path.exists(os.path.join(run_dir, f"frame_{frames}.bin")):
                frames += 1
            if frames == 0:
                raise ValueError(f"{run_dir}: no frame_0.bin")
            rest = None
            min_volume_ratio, com_error, node_error = np.inf, [], []
            lo, hi = X[ids].min(axis=0), X[ids].max(axis=0)
            diagonal = float(np.linalg.norm(hi - lo))
            mass_nodes = np.zeros(len(X), dtype=bool)
            mass_nodes[ids] = True
            for k in range(frames):
                path = os.path.join(run_dir, f"frame_{k}.bin")
                xb = np.fromfile(path, dtype=np.float64)
                if xb.size != 3 * len(ids) or not np.isfinite(xb).all():
                    raise ValueError(f"{path}: {xb.size} values, expected {3 * len(ids)} finite ones")
                xb = xb.reshape(-1, 3)
                p = xb[tets]
                volume = np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))
                if rest is None:
                    rest = volume
                min_volume_ratio = min(min_volume_ratio, float((volume / rest).min()))
                x = X.copy()
                x[ids] = xb
                out.create_dataset(f"steps/{k}/displacement", data=x - X)
                if k in dipc_x:
                    # Unweighted node centres: both runs have the same nodes (the masses differ
                    # between the codes' lumpings, the nodes do not).
                    com_error.append(float(np.linalg.norm(x[mass_nodes].mean(0) - dipc_x[k][mass_nodes].mean(0))) / diagonal)
                    node_error.append(float(np.linalg.norm(x[mass_nodes] - dipc_x[k][mass_nodes], axis=1).max()) / diagonal)
        os.replace(tmp, out_path)
    return {"frames": frames, "min_tet_volume_ratio": min_volume_ratio, "centre_error_rel": com_error,
            "max_node_error_rel": node_error, "bodies": len(bodies), "nodes": int(len(ids)), "tets": int(len(tets)),
            "elements_of_dipc": int(len(body))}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dipc_output")
    parser.add_argument("tets_dir")
    parser.add_argument("run_dir")
    parser.add_argument("out")
    args = parser.parse_args(argv)
    try:
        summary = convert(args.dipc_output, args.tets_dir, args.run_dir, args.out)
    except (OSError, KeyError, ValueError) as e:
        print(f"peer_output: {e}", file=sys.stderr)
        return 1
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
