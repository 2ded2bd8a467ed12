#!/usr/bin/python3
"""Writes the hex blocks of the PolyFEM-format scene tests as Gmsh MSH 2.2 ASCII files:
block.msh (0.2 x 0.1 x 0.1 m, 4 x 2 x 2 hexes, min corner at the origin) and block_placed.msh,
the same block under the transformation the PolyFEM scenes give it (scale 0.5, rotation 90
degrees about z, translation), so that dipc's own scenes can run the same mesh unrotated.
Run from this directory: /usr/bin/python3 write_blocks.py"""
import math


def block(nx=4, ny=2, nz=2, size=(0.2, 0.1, 0.1)):
    nodes = [(size[0] * i / nx, size[1] * j / ny, size[2] * k / nz)
             for k in range(nz + 1) for j in range(ny + 1) for i in range(nx + 1)]
    nid = lambda i, j, k: (k * (ny + 1) + j) * (nx + 1) + i + 1
    hexes = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                hexes.append([nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k),
                              nid(i, j, k + 1), nid(i + 1, j, k + 1), nid(i + 1, j + 1, k + 1), nid(i, j + 1, k + 1)])
    return nodes, hexes


def write(path, nodes, hexes):
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(nodes))
        for n, (x, y, z) in enumerate(nodes, 1):
            f.write("%d %.17g %.17g %.17g\n" % (n, x, y, z))
        f.write("$EndNodes\n$Elements\n%d\n" % len(hexes))
        for e, h in enumerate(hexes, 1):
            f.write("%d 5 2 1 1 %s\n" % (e, " ".join(map(str, h))))
        f.write("$EndElements\n")


nodes, hexes = block()
write("block.msh", nodes, hexes)
# x = R_z(90 deg) (0.5 X) + t, as PolyFEM's transformation {scale 0.5, rotation [0, 0, 90],
# translation t} places it (scale, then rotation about the origin, then translation).
t = (0.05, 0.002, -0.025)
c, s = math.cos(math.pi / 2), math.sin(math.pi / 2)
placed = [(c * 0.5 * x - s * 0.5 * y + t[0], s * 0.5 * x + c * 0.5 * y + t[1], 0.5 * z + t[2]) for x, y, z in nodes]
write("block_placed.msh", placed, hexes)

# A 1 x 1 m floor at z = 0 (two triangles), and the same floor as PolyFEM's transformation
# {scale 0.5, rotation [90, 0, 0]} (90 degrees about x) turns it: onto the plane y = 0.
corners = [(-0.5, -0.5, 0), (0.5, -0.5, 0), (0.5, 0.5, 0), (-0.5, 0.5, 0)]
for name, points in [("floor.obj", corners), ("floor_y.obj", [(0.5 * x, 0.0, 0.5 * y) for x, y, z in corners])]:
    with open(name, "w") as f:
        f.write("# written by write_blocks.py\n")
        for p in points:
            f.write("v %.17g %.17g %.17g\n" % p)
        f.write("f 1 2 3\nf 1 3 4\n")

# PolyFEM's example obstacle plane.obj is a 10 x 10 m square in the plane y = 0, which its
# scenes scale with "dimensions": [s, 0, s]. This one lies at y = 0.25 instead: the size 0 of
# its flat axis must send it to y = 0 (factor 0, PolyFEM's rule), not keep it at 0.25.
with open("plane_raised.obj", "w") as f:
    f.write("# written by write_blocks.py\n")
    for p in [(-5, 0.25, 5), (5, 0.25, 5), (-5, 0.25, -5), (5, 0.25, -5)]:
        f.write("v %.17g %.17g %.17g\n" % p)
    f.write("f 2 3 1\nf 2 4 3\n")
