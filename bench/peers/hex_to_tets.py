#!/usr/bin/python3
"""Hexahedra split into tetrahedra on the same nodes, for running dipc's scenes in a peer code
that takes tetrahedra only (issue 34): the same nodes, so the same degrees of freedom, and the
same contact surface as dipc's.

Each quad face is cut along its diagonal through its smallest node id, the rule dipc uses for
its own contact surface (so the tetrahedra's boundary triangles are dipc's surface triangles),
and which two hexahedra sharing a face apply alike (so the tetrahedra conform). Each hexahedron
is then cut into tetrahedra with no added point whose faces use those diagonals (Dompierre,
Labbé, Vallet and Camarero 1999, "How to subdivide pyramids, prisms and hexahedra into
tetrahedra", showed that the smallest-id rule always allows one). The cuts of the 64 diagonal
patterns are found here, once, by a search over the unit cube's tetrahedra in integer
arithmetic, not copied from a table: a set of corner tetrahedra whose interiors are disjoint,
whose volumes add up to the cube's and which meet face to face is a cut.

    hex_to_tets.py OUTPUT.h5|.xmf DIR [--frame K]

reads a dipc output (any rank count; the mesh at frame K, default 0, its reference positions
with K = -1) and writes DIR/<body>.msh for each body (Gmsh 2.2 ASCII, 4-node tetrahedra, nodes
numbered from 1 in the order of DIR/<body>.nodes.txt, the dipc input node ids) and DIR/tets.json
(the bodies, their files, node and element counts). Exits 1 with a message naming the element
where a tetrahedron would not have positive volume or the cut does not conform.
"""
import argparse
import itertools
import json
import os
import sys

import numpy as np

# The reference hexahedron's corners in dipc's (and Gmsh's and VTK's) order, and its faces, each
# as a cycle of corners: the diagonals are (f[0], f[2]) and (f[1], f[3]).
CORNERS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _six_volume(t):
    """Six times the signed volume of the tetrahedron of reference corners t."""
    p = [CORNERS[i] for i in t]
    return _dot(_sub(p[1], p[0]), _cross(_sub(p[2], p[0]), _sub(p[3], p[0])))


def _interiors_disjoint(s, t):
    """Whether two corner tetrahedra have disjoint interiors: some axis among their face normals
    and the cross products of their edges separates them (convex polyhedra, exact integers)."""
    axes = []
    for u in (s, t):
        for a, b, c in itertools.combinations(u, 3):
            axes.append(_cross(_sub(CORNERS[b], CORNERS[a]), _sub(CORNERS[c], CORNERS[a])))
    edges_s = [_sub(CORNERS[b], CORNERS[a]) for a, b in itertools.combinations(s, 2)]
    edges_t = [_sub(CORNERS[b], CORNERS[a]) for a, b in itertools.combinations(t, 2)]
    axes += [_cross(e, f) for e in edges_s for f in edges_t]
    for axis in axes:
        if axis == (0, 0, 0):
            continue
        ps = [_dot(axis, CORNERS[i]) for i in s]
        pt = [_dot(axis, CORNERS[i]) for i in t]
        if max(ps) <= min(pt) or max(pt) <= min(ps):
            return True
    return False


def _corner_tetrahedra():
    """Every tetrahedron of 4 cube corners with a volume, positively oriented, and its 6 volume."""
    tets = []
    for t in itertools.combinations(range(8), 4):
        v = _six_volume(t)
        if v < 0:
            t, v = (t[1], t[0], t[2], t[3]), -v
        if v:
            tets.append((t, v))
    return tets


def _find_cuts():
    """For each pattern of face diagonals (bit k: face k cut along (f[1], f[3])), a list of
    corner tetrahedra that fill the cube using those diagonals, or None where none exists."""
    tets = _corner_tetrahedra()
    n = len(tets)
    disjoint = [[i != j and _interiors_disjoint(tets[i][0], tets[j][0]) for j in range(n)] for i in range(n)]
    cube = 6  # six times the unit cube's volume
    cuts = []
    for pattern in range(64):
        # A tetrahedron may not have the other diagonal of a face as an edge.
        other = set()
        for k, f in enumerate(FACES):
            other.add(frozenset((f[0], f[2]) if pattern >> k & 1 else (f[1], f[3])))
        allowed = [i for i in range(n) if not any(frozenset(e) in other for e in itertools.combinations(tets[i][0], 2))]
        found = []

        def search(start, chosen, volume):
            if volume == cube:
                # Face to face: inside the cube each triangle is two tetrahedra's, so that the
                # cut conforms within the hexahedron too (disjoint tetrahedra can fill the cube
                # while meeting on an inner square cut along both its diagonals).
                faces = {}
                for i in chosen:
                    for f in itertools.combinations(sorted(tets[i][0]), 3):
                        faces[f] = faces.get(f, 0) + 1
                if sum(1 for n in faces.values() if n == 1) != 2 * len(FACES):
                    return False
                found.extend(tets[i][0] for i in chosen)
                return True
            for k in range(start, len(allowed)):
                i = allowed[k]
                if volume + tets[i][1] <= cube and all(disjoint[i][j] for j in chosen):
                    chosen.append(i)
                    if search(k + 1, chosen, volume + tets[i][1]):
                        return True
                    chosen.pop()
            return False

        cuts.append(found if search(0, [], 0) else None)
    return cuts


CUTS = _find_cuts()


def _smallest_first(hexes, f):
    """Face f of each hexahedron as its cycle started at its smallest node id (a, b, c, d: the
    cut is (a, c)), and where in FACES[f]'s cycle that id stood."""
    q = hexes[:, list(FACES[f])]
    at = np.argmin(q, axis=1)
    rows = np.arange(len(q))
    return tuple(q[rows, (at + s) % 4] for s in range(4)), at


def face_pattern(hexes):
    """Each hexahedron's diagonal pattern (the index into CUTS) under the smallest-id rule."""
    pattern = np.zeros(len(hexes), dtype=np.int64)
    for k in range(len(FACES)):
        _, at = _smallest_first(hexes, k)
        pattern |= (at % 2 == 1).astype(np.int64) << k
    return pattern


def split_hexes(hexes):
    """(E, 8) hexahedra -> (T, 4) tetrahedra on the same node ids and (T,) their hexahedron."""
    hexes = np.asarray(hexes, dtype=np.int64)
    pattern = face_pattern(hexes)
    tets, owner = [], []
    for p in np.unique(pattern):
        cut = CUTS[int(p)]
        if cut is None:  # unreachable under the smallest-id rule; a guard against a wrong mesh
            raise ValueError(f"diagonal pattern {int(p)} has no cut without an added point")
        which = np.nonzero(pattern == p)[0]
        for t in cut:
            tets.append(hexes[which][:, list(t)])
            owner.append(which)
    if not tets:
        return np.zeros((0, 4), dtype=np.int64), np.zeros(0, dtype=np.int64)
    tets, owner = np.concatenate(tets), np.concatenate(owner)
    order = np.lexsort((np.arange(len(owner)), owner))  # hexahedron by hexahedron
    return tets[order], owner[order]


def check_split(coordinates, hexes, tets, owner):
    """Raises ValueError naming the element where a tetrahedron's volume is not positive, or
    where the tetrahedra's faces do not conform: each face shared by two tetrahedra or on the
    boundary, and the boundary faces the hexahedra's boundary quads cut by the smallest-id rule."""
    x = np.asarray(coordinates, dtype=float)
    p = x[tets]
    six_volume = np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))
    bad = np.nonzero(~(six_volume > 0))[0]
    if len(bad):
        raise ValueError(f"element {int(owner[bad[0]])}: a tetrahedron of its cut has volume "
                         f"{six_volume[bad[0]] / 6:.3e} (the hexahedron is too distorted to cut into positive tetrahedra)")
    tri = np.sort(np.concatenate([tets[:, [0, 1, 2]], tets[:, [0, 1, 3]], tets[:, [0, 2, 3]], tets[:, [1, 2, 3]]]), axis=1)
    faces, count = np.unique(tri, axis=0, return_counts=True)
    if (count > 2).any():
        raise ValueError(f"the cut does not conform: face {faces[count > 2][0].tolist()} belongs to more than two tetrahedra")
    quads = np.sort(np.concatenate([hexes[:, list(f)] for f in FACES]), axis=1)
    _, quad_inverse, quad_count = np.unique(quads, axis=0, return_inverse=True, return_counts=True)
    on_boundary = (quad_count == 1)[quad_inverse.reshape(-1)].reshape(len(FACES), len(hexes))
    expected = []
    for k in range(len(FACES)):
        (a, b, c, d), _ = _smallest_first(hexes[on_boundary[k]], k)
        expected += [np.stack([a, b, c], 1), np.stack([a, c, d], 1)]  # cut along (a, c)
    expected = np.unique(np.sort(np.concatenate(expected), axis=1), axis=0)
    once = faces[count == 1]
    if len(once) != len(expected) or not np.array_equal(once, expected):
        raise ValueError(f"the cut does not conform: its {len(once)} boundary triangles are not the "
                         f"{len(expected)} of the hexahedra's surface")


def write_msh(path, coordinates, tets):
    """Gmsh 2.2 ASCII: the nodes 1..N in the given order, 4-node tetrahedra (type 4)."""
    tmp = path + ".part"
    with open(tmp, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(coordinates))
        for k, (x, y, z) in enumerate(coordinates):
            f.write("%d %.17g %.17g %.17g\n" % (k + 1, x, y, z))
        f.write("$EndNodes\n$Elements\n%d\n" % len(tets))
        for k, t in enumerate(tets):
            f.write("%d 4 2 1 1 %d %d %d %d\n" % (k + 1, t[0] + 1, t[1] + 1, t[2] + 1, t[3] + 1))
        f.write("$EndElements\n")
    os.replace(tmp, path)


def read_msh(path):
    """(nodes (N, 3), tetrahedra (T, 4) 0-based) of a file write_msh wrote."""
    with open(path) as f:
        lines = f.read().split("\n")
    start = lines.index("$Nodes")
    n = int(lines[start + 1])
    nodes = np.array([[float(v) for v in line.split()[1:4]] for line in lines[start + 2:start + 2 + n]]).reshape(-1, 3)
    start = lines.index("$Elements")
    m = int(lines[start + 1])
    tets = np.array([[int(v) for v in line.split()[5:9]] for line in lines[start + 2:start + 2 + m]],
                    dtype=np.int64).reshape(-1, 4) - 1
    return nodes, tets


def export(output_path, out_dir, frame=0):
    # dipc's reader (python/dipc/output.py), loaded on its own: no compiled module needed.
    import importlib.util
    source = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python", "dipc", "output.py")
    spec = importlib.util.spec_from_file_location("dipc_output", source)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    read_output = module.read_output
    run = read_output(output_path)
    hexes = np.asarray(run.hexes, dtype=np.int64)
    x = np.asarray(run.coordinates, dtype=float)
    if frame >= 0:
        x = x + np.asarray(run.field("displacement", frames=[frame]))[0]
    tets, owner = split_hexes(hexes)
    check_split(x, hexes, tets, owner)
    body = np.asarray(run.body)
    names = run.body_names or [f"body{b}" for b in range(int(body.max()) + 1)]
    os.makedirs(out_dir, exist_ok=True)
    summary = {"source": os.path.abspath(output_path), "frame": frame, "bodies": []}
    for b, name in enumerate(names):
        mine = tets[body[owner] == b]
        nodes = np.unique(mine)
        local = np.searchsorted(nodes, mine)
        safe = "".join(c if c.isalnum() or c in "-_" else "_" for c in name)
        write_msh(os.path.join(out_dir, safe + ".msh"), x[nodes], local)
        np.savetxt(os.path.join(out_dir, safe + ".nodes.txt"), nodes, fmt="%d")
        summary["bodies"].append({"name": name, "msh": safe + ".msh", "nodes": safe + ".nodes.txt",
                                  "num_nodes": int(len(nodes)), "num_tets": int(len(mine)),
                                  "num_hexes": int((body == b).sum())})
    with open(os.path.join(out_dir, "tets.json"), "w") as f:
        json.dump(summary, f, indent=1)
    return summary


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output", help="a dipc output (.h5 or .xmf)")
    parser.add_argument("out_dir")
    parser.add_argument("--frame", type=int, default=0, help="the frame whose positions the tetrahedra take "
                        "(-1: the reference positions)")
    args = parser.parse_args(argv)
    try:
        summary = export(args.output, args.out_dir, args.frame)
    except (OSError, ValueError, KeyError) as e:
        print(f"hex_to_tets: {args.output}: {e}", file=sys.stderr)
        return 1
    for b in summary["bodies"]:
        print(f"{b['name']}: {b['num_hexes']} hexahedra -> {b['num_tets']} tetrahedra, {b['num_nodes']} nodes, {b['msh']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
