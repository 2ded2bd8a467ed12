#!/usr/bin/python3
"""Independent judge of a dipc run: reads <dir>/<name>.h5 and the scene JSON and checks every
written step, with numpy only (no dipc code), for

  (a) inversions: det of the trilinear map's Jacobian > 0 at the 8 corners and 8 Gauss
      points of every hex;
  (b) intersections: no surface edge crosses a surface triangle (edges and triangles of the
      bodies' boundary quads, each quad split in two) unless they share a vertex; pairs within
      one body are checked where that body has self_contact;
  (c) distances: the smallest distance between surfaces of different bodies (point–triangle
      and edge–edge, up to a cutoff) and from every surface vertex to the scene's contact
      planes stays > 0.

(b) and (c) are contact claims, judged only when the scene enables contact. Prints one JSON
line (steps judged, inverted element-steps, intersecting pairs, smallest distances, smallest
det J and det F) and exits 1 on any violation, 2 on unreadable input.

    judge_output.py OUTPUT.h5 SCENE.json [--ids-from ONE_RANK.h5] [--cutoff LENGTH]

Quads are split as dipc splits them, along the diagonal through the smallest input node id.
dipc's files number nodes by input id on any rank count; files written by dipc before
checkpoints (issue 13) numbered them by partition on more than one rank: for those pass
--ids-from with a 1-rank file of the same scene to recover the input ids (nodes are matched by
reference coordinates). Without it the file's ids are taken, which can split a
non-planar quad along the other diagonal: a difference of the order of the quad's warp.
"""
import argparse
import json
import sys

import h5py
import numpy as np

import judge_geometry as geo


class JudgeInputError(Exception):
    pass


def read_scene(path):
    """Contact settings and per-body self_contact of a scene file (dipc's defaults otherwise)."""
    with open(path) as f:
        scene = json.load(f)
    contact = scene.get('contact', {})
    planes = []
    for plane in contact.get('planes', []):
        n = np.asarray(plane['normal'], float)
        planes.append((np.asarray(plane['point'], float), n / np.linalg.norm(n)))
    return {'contact': bool(contact.get('enabled', False)),
            'dhat': float(contact.get('dhat', 1e-3)),
            'dhat_relative': bool(contact.get('dhat_relative', True)),
            'planes': planes,
            'self_contact': [bool(b.get('self_contact', True)) for b in scene['geometry']]}


def read_steps(h5):
    """Names of the written steps, in order."""
    return sorted(h5['steps'].keys(), key=int)


def input_order(coordinates, reference_coordinates):
    """Input id of each node of `coordinates`, taken from a file whose ids are input ids
    (the same mesh, so the same rest coordinates, in another order)."""
    if coordinates.shape != reference_coordinates.shape:
        raise JudgeInputError('--ids-from: the meshes have different numbers of nodes')
    mine = np.lexsort(coordinates.T[::-1])
    theirs = np.lexsort(reference_coordinates.T[::-1])
    if not np.array_equal(coordinates[mine], reference_coordinates[theirs]):
        raise JudgeInputError('--ids-from: the rest coordinates differ')
    ids = np.empty(len(coordinates), np.int64)
    ids[mine] = theirs
    return ids


class Surface:
    """Boundary triangles, edges and vertices (file node indices) with their bodies."""

    def __init__(self, topology, element_body, split_ids):
        faces = topology[:, geo.HEX_FACES].reshape(-1, 4)
        face_body = np.repeat(element_body, 6)
        _, first, count = np.unique(np.sort(faces, axis=1), axis=0, return_index=True, return_counts=True)
        boundary = first[count == 1]
        quads, quad_body = faces[boundary], face_body[boundary]
        # Split each quad along the diagonal through its corner of smallest input id.
        m = np.argmin(split_ids[quads], axis=1)
        corner = lambda k: quads[np.arange(len(quads)), (m + k) % 4]
        self.triangles = np.vstack([np.stack([corner(0), corner(1), corner(2)], axis=1),
                                    np.stack([corner(0), corner(2), corner(3)], axis=1)])
        self.triangle_body = np.concatenate([quad_body, quad_body])
        sides = np.vstack([self.triangles[:, [0, 1]], self.triangles[:, [1, 2]], self.triangles[:, [2, 0]]])
        side_body = np.tile(self.triangle_body, 3)
        self.edges, first = np.unique(np.sort(sides, axis=1), axis=0, return_index=True)
        self.edge_body = side_body[first]
        self.vertices, first = np.unique(self.triangles.ravel(), return_index=True)
        self.vertex_body = np.repeat(self.triangle_body, 3)[first]


def shares_vertex(edges, triangles):
    return np.any(edges[:, :, None] == triangles[:, None, :], axis=(1, 2))


def intersecting_pairs(x, s, self_contact):
    """Number of (surface edge, surface triangle) pairs that cross."""
    e, t = s.edges, s.triangles
    ex, tx = x[e], x[t]
    i, j = geo.overlapping_boxes(ex.min(axis=1), ex.max(axis=1), tx.min(axis=1), tx.max(axis=1))
    same = s.edge_body[i] == s.triangle_body[j]
    keep = (~same | self_contact[s.edge_body[i]]) & ~shares_vertex(e[i], t[j])
    i, j = i[keep], j[keep]
    hit = geo.segment_crosses_triangle(ex[i, 0], ex[i, 1], tx[j, 0], tx[j, 1], tx[j, 2])
    return int(hit.sum())


def min_body_distance(x, s, cutoff):
    """Smallest point–triangle / edge–edge distance between different bodies; inf beyond cutoff."""
    best = np.inf
    v, t = s.vertices, s.triangles
    tx = x[t]
    i, j = geo.overlapping_boxes(x[v] - cutoff, x[v] + cutoff, tx.min(axis=1), tx.max(axis=1))
    keep = s.vertex_body[i] != s.triangle_body[j]
    i, j = i[keep], j[keep]
    if len(i):
        best = min(best, geo.point_triangle_distance(x[v[i]], tx[j, 0], tx[j, 1], tx[j, 2]).min())
    ex = x[s.edges]
    lo, hi = ex.min(axis=1), ex.max(axis=1)
    i, j = geo.overlapping_boxes(lo - cutoff, hi + cutoff, lo, hi)
    keep = (s.edge_body[i] < s.edge_body[j])  # each pair of different bodies once
    i, j = i[keep], j[keep]
    if len(i):
        best = min(best, geo.segment_segment_distance(ex[i, 0], ex[i, 1], ex[j, 0], ex[j, 1]).min())
    return float(best) if best <= cutoff else np.inf


def judge(h5_path, scene_path, ids_from=None, cutoff=None):
    """Judges every written step; returns the summary dict (see the module docstring)."""
    scene = read_scene(scene_path)
    with h5py.File(h5_path, 'r') as h5:
        X = h5['mesh/coordinates'][...]
        topology = h5['mesh/topology'][...].astype(np.int64)
        body = h5['mesh/body'][...].astype(np.int64)
        split_ids = np.arange(len(X))
        if ids_from:
            with h5py.File(ids_from, 'r') as ref:
                split_ids = input_order(X, ref['mesh/coordinates'][...])
        if body.max() >= len(scene['self_contact']):
            raise JudgeInputError(f'{h5_path} has body {body.max()}, the scene {len(scene["self_contact"])} bodies')
        surface = Surface(topology, body, split_ids)
        self_contact = np.array(scene['self_contact'])
        diagonal = float(np.linalg.norm(X.max(axis=0) - X.min(axis=0)))
        dhat = scene['dhat'] * diagonal if scene['dhat_relative'] else scene['dhat']
        cutoff = cutoff if cutoff else max(2 * dhat, 1e-2 * diagonal)
        rest_dets = geo.hex_jacobian_dets(X[topology])

        summary = {'steps': 0, 'inverted': 0, 'intersections': None, 'min_distance': None,
                   'min_plane_distance': None, 'min_det_J': np.inf, 'min_det_F': np.inf,
                   'dhat': dhat, 'cutoff': cutoff, 'first_violation': None}
        if scene['contact']:
            summary['intersections'] = 0
            summary['min_distance'] = np.inf
            if scene['planes']:
                summary['min_plane_distance'] = np.inf
        for name in read_steps(h5):
            x = X + h5[f'steps/{name}/displacement'][...]
            problems = []
            dets = geo.hex_jacobian_dets(x[topology])
            inverted = int(np.any(dets <= 0, axis=1).sum())
            summary['inverted'] += inverted
            summary['min_det_J'] = min(summary['min_det_J'], float(dets.min()))
            summary['min_det_F'] = min(summary['min_det_F'], float((dets / rest_dets).min()))
            if inverted:
                problems.append(f'{inverted} inverted elements')
            if scene['contact']:
                crossings = intersecting_pairs(x, surface, self_contact)
                summary['intersections'] += crossings
                if crossings:
                    problems.append(f'{crossings} crossing edge-triangle pairs')
                d = min_body_distance(x, surface, cutoff)
                summary['min_distance'] = min(summary['min_distance'], d)
                if not d > 0:
                    problems.append(f'distance between bodies {d:g}')
                for point, normal in scene['planes']:
                    d = float(((x[surface.vertices] - point) @ normal).min())
                    summary['min_plane_distance'] = min(summary['min_plane_distance'], d)
                    if not d > 0:
                        problems.append(f'distance to plane {d:g}')
            if problems and summary['first_violation'] is None:
                summary['first_violation'] = f'step {name}: ' + ', '.join(problems)
            summary['steps'] += 1
    summary['ok'] = summary['first_violation'] is None
    return summary


def to_json(summary):
    """One JSON line; infinite distances (nothing within the cutoff) become null."""
    clean = {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in summary.items()}
    return json.dumps(clean)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('h5')
    parser.add_argument('scene')
    parser.add_argument('--ids-from', help='1-rank output of the same scene (input node ids)')
    parser.add_argument('--cutoff', type=float, help='distance search radius (default max(2 dhat, 1%% of diagonal))')
    args = parser.parse_args(argv)
    try:
        summary = judge(args.h5, args.scene, args.ids_from, args.cutoff)
    except (OSError, KeyError, ValueError, JudgeInputError) as e:
        print(f'judge_output: {e}', file=sys.stderr)
        return 2
    print(to_json(summary))
    return 0 if summary['ok'] else 1


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
