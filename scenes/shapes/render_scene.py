#!/usr/bin/python3
"""Draws steps of a dipc run, with the scene's OBJ obstacles, side by side in one PNG.

    /usr/bin/python3 scenes/shapes/render_scene.py SCENE.json RUN.h5 OUT.png --steps 0,20,40
        [--elev 15] [--azim -60] [--dt 0.01]

The bodies are the boundary quads of the hexahedra at each step (RUN.h5: /mesh/coordinates,
/mesh/topology, /steps/<k>/displacement); the obstacles are the OBJ files of the scene's
contact.obstacles, placed by scale and translation and moved by their motion (fixed, velocity,
rotation, path) to the step's time k * dt (dt from the scene unless --dt)."""
import argparse
import json
import math
import os

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

# Hex faces in dipc's local numbering (src/mesh/boundary_faces.hpp), outward.
HEX_FACES = [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1), (4, 5, 6, 7)]


def boundary_quads(topology):
    count = {}
    for hexa in topology:
        for face in HEX_FACES:
            quad = tuple(int(hexa[i]) for i in face)
            key = tuple(sorted(quad))
            count.setdefault(key, [0, quad])[0] += 1
    return np.array([quad for n, quad in count.values() if n == 1])


def read_obj(path):
    vertices, faces = [], []
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            vertices.append([float(p) for p in parts[1:4]])
        elif parts[0] == "f":
            ids = [int(p.split("/")[0]) for p in parts[1:]]
            faces.append([i - 1 if i > 0 else len(vertices) + i for i in ids])
    return np.array(vertices), faces


def rotate(points, axis, center, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    p = points - center
    # Rodrigues' formula.
    return (center + p * math.cos(angle) + np.cross(a, p) * math.sin(angle)
            + np.outer(p @ a, a) * (1 - math.cos(angle)))


def place_obstacle(obstacle, base, t):
    vertices, faces = read_obj(os.path.join(base, obstacle["mesh"]))
    x = obstacle.get("scale", 1.0) * vertices + np.asarray(obstacle.get("translation", [0, 0, 0]), float)
    motion = obstacle.get("motion", {"type": "fixed"})
    kind = motion.get("type", "fixed")
    if kind == "velocity":
        x = x + t * np.asarray(motion["velocity"], float)
    elif kind == "rotation":
        x = rotate(x, motion.get("axis", [0, 0, 1]), np.asarray(motion.get("center", [0, 0, 0]), float),
                   motion["angular_velocity"] * t)
    elif kind == "path":
        keys = motion["keyframes"]
        times = [k["time"] for k in keys]
        d = [np.interp(t, times, [k["translation"][c] for k in keys]) for c in range(3)]
        x = x + np.asarray(d)
    return [x[f] for f in faces]


def shade(polygons, color, light=(0.3, -0.5, 0.8)):
    light = np.asarray(light) / np.linalg.norm(light)
    colors = []
    for p in polygons:
        n = np.cross(p[1] - p[0], p[2] - p[0])
        norm = np.linalg.norm(n)
        c = 0.35 + 0.65 * abs(n @ light) / norm if norm > 0 else 0.6
        colors.append(np.clip(np.asarray(color) * c, 0, 1))
    return colors


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("run")
    parser.add_argument("out")
    parser.add_argument("--steps", default="0")
    parser.add_argument("--elev", type=float, default=15)
    parser.add_argument("--azim", type=float, default=-60)
    parser.add_argument("--dt", type=float)
    args = parser.parse_args()
    scene = json.load(open(args.scene))
    base = os.path.dirname(os.path.abspath(args.scene))
    dt = args.dt if args.dt else scene["time"]["dt"]
    run = h5py.File(args.run, "r")
    X = run["/mesh/coordinates"][:]
    quads = boundary_quads(run["/mesh/topology"][:])
    steps = [int(s) for s in args.steps.split(",")]
    obstacles = scene.get("contact", {}).get("obstacles", [])

    frames = []
    for k in steps:
        x = X + (run["/steps/%d/displacement" % k][:] if k > 0 else 0)
        frames.append((k, [x[q] for q in quads], [place_obstacle(o, base, k * dt) for o in obstacles]))
    everything = np.concatenate([np.concatenate(b) for _, b, _ in frames] +
                                [np.concatenate(p) for _, _, obs in frames for p in obs])
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    center, half = (lo + hi) / 2, (hi - lo).max() / 2

    fig = plt.figure(figsize=(3.2 * len(frames), 3.4), dpi=90)
    for i, (k, body, placed) in enumerate(frames):
        ax = fig.add_subplot(1, len(frames), i + 1, projection="3d")
        for polygons in placed:
            ax.add_collection3d(Poly3DCollection(polygons, facecolors=shade(polygons, (0.75, 0.75, 0.8)),
                                                 edgecolors=(0.3, 0.3, 0.35, 0.4), linewidths=0.3, alpha=0.35))
        ax.add_collection3d(Poly3DCollection(body, facecolors=shade(body, (0.85, 0.35, 0.2)),
                                             edgecolors=(0.2, 0.1, 0.05, 0.6), linewidths=0.3))
        for c, set_lim in enumerate((ax.set_xlim, ax.set_ylim, ax.set_zlim)):
            set_lim(center[c] - half, center[c] + half)
        ax.set_box_aspect((1, 1, 1))
        ax.view_init(elev=args.elev, azim=args.azim)
        ax.set_proj_type("ortho")
        ax.set_axis_off()
        ax.set_title("t = %.2f s" % (k * dt), fontsize=9)
    fig.subplots_adjust(left=0, right=1, bottom=0, top=0.93, wspace=0)
    fig.savefig(args.out)


if __name__ == "__main__":
    main()
