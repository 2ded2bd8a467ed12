#!/usr/bin/python3
"""Writes the OBJ shapes of the funnel and OBJ-roller scenes and voxelises the falling solid.

    /usr/bin/python3 scenes/shapes/make_shapes.py [--resolution N] [--voxelize PATH]

writes into scenes/meshes/ (z is up, lengths in metres):
  funnel.obj  an open funnel about the z axis: a cone from radius 0.2 at z = 0.32 down to
              radius 0.06 at z = 0.12, then a straight neck down to z = 0.06 (16 sides)
  floor.obj   a 0.6 m square floor at z = 0 (4 x 4 quads)
  ball.obj    a closed sphere of radius 0.04 (UV sphere, outward-facing triangles)
  roller.obj  a closed cylinder of radius 0.06 along y, from y = -0.12 to 0.12 (24 sides)
  ball.msh    ball.obj voxelised by dipc-voxelize into N cells across (default 6, the size the
              scene file ships with; selections ball.solid and ball.boundary)
The OBJ files do not depend on N. PATH defaults to build/src/tools/dipc-voxelize."""
import argparse
import math
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
MESHES = os.path.join(HERE, "..", "meshes")


def write_obj(name, vertices, faces, comment):
    with open(os.path.join(MESHES, name), "w") as f:
        f.write("# %s (scenes/shapes/make_shapes.py)\n" % comment)
        for v in vertices:
            f.write("v %.9g %.9g %.9g\n" % v)
        for face in faces:
            f.write("f %s\n" % " ".join(str(i + 1) for i in face))


def ring(radius, z, n):
    return [(radius * math.cos(2 * math.pi * k / n), radius * math.sin(2 * math.pi * k / n), z) for k in range(n)]


def funnel(n=16):
    # Rings from the rim down; quads between consecutive rings (fan-split by the reader).
    rings = [(0.2, 0.32), (0.13, 0.22), (0.06, 0.12), (0.06, 0.06)]
    vertices = [v for r, z in rings for v in ring(r, z, n)]
    faces = [[i * n + k, i * n + (k + 1) % n, (i + 1) * n + (k + 1) % n, (i + 1) * n + k]
             for i in range(len(rings) - 1) for k in range(n)]
    write_obj("funnel.obj", vertices, faces, "open funnel, rim r 0.2 at z 0.32, neck r 0.06 from z 0.12 to 0.06")


def floor(n=4, half=0.3):
    vertices = [(-half + 2 * half * i / n, -half + 2 * half * j / n, 0.0) for j in range(n + 1) for i in range(n + 1)]
    faces = [[j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i]
             for j in range(n) for i in range(n)]
    write_obj("floor.obj", vertices, faces, "0.6 m square floor at z = 0")


def ball(radius=0.04, rings=12, sectors=24):
    # Poles plus rings of latitude; triangles counter-clockwise seen from outside.
    vertices = [(0.0, 0.0, radius)]
    for i in range(1, rings):
        theta = math.pi * i / rings
        vertices += [(radius * math.sin(theta) * math.cos(2 * math.pi * k / sectors),
                      radius * math.sin(theta) * math.sin(2 * math.pi * k / sectors), radius * math.cos(theta))
                     for k in range(sectors)]
    vertices.append((0.0, 0.0, -radius))
    south = len(vertices) - 1
    at = lambda i, k: 1 + (i - 1) * sectors + k % sectors
    faces = [[0, at(1, k), at(1, k + 1)] for k in range(sectors)]
    for i in range(1, rings - 1):
        for k in range(sectors):
            faces += [[at(i, k), at(i + 1, k), at(i + 1, k + 1)], [at(i, k), at(i + 1, k + 1), at(i, k + 1)]]
    faces += [[at(rings - 1, k), south, at(rings - 1, k + 1)] for k in range(sectors)]
    write_obj("ball.obj", vertices, faces, "closed sphere of radius 0.04")


def roller(radius=0.06, half_length=0.12, n=24):
    # Side quads and two capping fans, every face counter-clockwise seen from outside.
    front = [(radius * math.cos(2 * math.pi * k / n), -half_length, radius * math.sin(2 * math.pi * k / n)) for k in range(n)]
    back = [(x, half_length, z) for x, _, z in front]
    vertices = front + back + [(0.0, -half_length, 0.0), (0.0, half_length, 0.0)]
    faces = [[k, (k + 1) % n, n + (k + 1) % n, n + k] for k in range(n)]
    faces += [[2 * n, (k + 1) % n, k] for k in range(n)]
    faces += [[2 * n + 1, n + k, n + (k + 1) % n] for k in range(n)]
    write_obj("roller.obj", vertices, faces, "closed cylinder r 0.06 along y, y in [-0.12, 0.12]")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--resolution", type=int, default=6, help="cells across the ball (default 6)")
    parser.add_argument("--voxelize", default=os.path.join(HERE, "..", "..", "build", "src", "tools", "dipc-voxelize"))
    args = parser.parse_args()
    funnel()
    floor()
    ball()
    roller()
    subprocess.run([args.voxelize, os.path.join(MESHES, "ball.obj"), os.path.join(MESHES, "ball.msh"),
                    "--resolution", str(args.resolution)],
                   check=True)


if __name__ == "__main__":
    main()
