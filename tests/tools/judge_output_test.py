#!/usr/bin/python3
"""Unit tests of the output judge: crafted outputs whose verdict is known (crossing boxes must
be caught, separated ones pass, an inverted hex is caught) and the distance primitives against
hand-computed values. Run: python3 tests/tools/judge_output_test.py (CTest: tools_judge_output)."""
import json
import os
import sys
import tempfile
import unittest

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import judge_geometry as geo  # noqa: E402
import judge_output  # noqa: E402


def box_mesh(origin, size, n, first_node=0):
    """n×n×n hexes filling a box, Gmsh node order; returns (coordinates, topology)."""
    axis = [np.linspace(origin[d], origin[d] + size[d], n + 1) for d in range(3)]
    z, y, x = np.meshgrid(axis[2], axis[1], axis[0], indexing='ij')
    coords = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    node = lambda i, j, k: first_node + (k * (n + 1) + j) * (n + 1) + i
    hexes = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                hexes.append([node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                              node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1),
                              node(i, j + 1, k + 1)])
    return coords, np.array(hexes)


class CraftedRun:
    """Writes an output file in dipc's layout and its scene into a temporary directory."""

    def __init__(self, tmp, bodies, displacements, planes=(), contact=True):
        coords, topo, body = [], [], []
        for b, (origin, size, n) in enumerate(bodies):
            c, t = box_mesh(origin, size, n, sum(len(x) for x in coords))
            coords.append(c)
            topo.append(t)
            body += [b] * len(t)
        self.coords = np.vstack(coords)
        self.h5 = os.path.join(tmp, 'run.h5')
        self.scene = os.path.join(tmp, 'scene.json')
        with h5py.File(self.h5, 'w') as f:
            f['mesh/coordinates'] = self.coords
            f['mesh/topology'] = np.vstack(topo)
            f['mesh/body'] = np.array(body, np.int32)
            for k, u in enumerate(displacements(self.coords)):
                f[f'steps/{k}/displacement'] = u
        scene = {'geometry': [{'name': f'b{b}'} for b in range(len(bodies))],
                 'contact': {'enabled': contact, 'dhat': 1e-3,
                             'planes': [{'point': p, 'normal': n} for p, n in planes]}}
        with open(self.scene, 'w') as f:
            json.dump(scene, f)

    def judge(self):
        return judge_output.judge(self.h5, self.scene)


def move_second_body(offsets):
    """Displacement fields that move body 1 (nodes with x > 1.5 at rest) by each offset."""
    def fields(coords):
        second = coords[:, 0] > 1.5
        for offset in offsets:
            u = np.zeros_like(coords)
            u[second] = offset
            yield u
    return fields


TWO_BOXES = [([0, 0, 0], [1, 1, 1], 2), ([2, 0.1, 0.2], [1, 1, 1], 2)]


class JudgeVerdicts(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def test_separated_boxes_pass(self):
        run = CraftedRun(self.tmp.name, TWO_BOXES, move_second_body([[0, 0, 0], [-0.99, 0, 0]]))
        s = run.judge()
        self.assertTrue(s['ok'], s)
        self.assertEqual(s['steps'], 2)
        self.assertEqual(s['intersections'], 0)
        self.assertAlmostEqual(s['min_distance'], 0.01, places=12)
        self.assertAlmostEqual(s['min_det_F'], 1.0, places=12)

    def test_crossing_boxes_are_caught(self):
        run = CraftedRun(self.tmp.name, TWO_BOXES, move_second_body([[0, 0, 0], [-1.4, 0, 0]]))
        s = run.judge()
        self.assertFalse(s['ok'])
        self.assertGreater(s['intersections'], 0)
        self.assertTrue(s['first_violation'].startswith('step 1:'), s['first_violation'])

    def test_grazing_crossing_is_caught(self):
        # Body 1 pushed 1e-9 into body 0: distances of 1e-9 must not hide behind a tolerance.
        run = CraftedRun(self.tmp.name, TWO_BOXES, move_second_body([[-1 - 1e-9, 0, 0]]))
        self.assertGreater(run.judge()['intersections'], 0)

    def test_inverted_hex_is_caught(self):
        def flatten_one_corner(coords):
            u = np.zeros_like(coords)
            u[0] = [0.8, 0.8, 0.8]  # corner 0 of element 0 pushed through the opposite corner
            yield u
        run = CraftedRun(self.tmp.name, TWO_BOXES[:1], flatten_one_corner, contact=False)
        s = run.judge()
        self.assertFalse(s['ok'])
        self.assertEqual(s['inverted'], 1)
        self.assertLess(s['min_det_J'], 0)
        self.assertIsNone(s['intersections'])  # contact off: not a contact claim

    def test_plane_penetration_is_caught(self):
        planes = [([0, 0, -0.5], [0, 0, 2])]
        above = CraftedRun(self.tmp.name, TWO_BOXES, move_second_body([[0, 0, 0]]), planes).judge()
        self.assertAlmostEqual(above['min_plane_distance'], 0.5, places=12)
        below = CraftedRun(self.tmp.name, TWO_BOXES, move_second_body([[0, 0, -0.8]]), planes).judge()
        self.assertFalse(below['ok'])
        self.assertLess(below['min_plane_distance'], 0)

    def test_input_ids_from_another_numbering(self):
        run = CraftedRun(self.tmp.name, TWO_BOXES[:1], lambda c: [np.zeros_like(c)])
        perm = np.random.default_rng(1).permutation(len(run.coords))
        ids = judge_output.input_order(run.coords[perm], run.coords)
        np.testing.assert_array_equal(ids, perm)


class Primitives(unittest.TestCase):
    def rows(self, *points):
        return [np.array([p], float) for p in points]

    def test_point_triangle_regions(self):
        a, b, c = [0, 0, 0], [1, 0, 0], [0, 1, 0]
        for p, d in [([0.2, 0.2, 0.5], 0.5), ([-1, 0, 0], 1.0), ([2, -1, 0], np.sqrt(2)),
                     ([1, 1, 0], np.sqrt(0.5)), ([0.5, -2, 2], np.sqrt(8))]:
            self.assertAlmostEqual(geo.point_triangle_distance(*self.rows(p, a, b, c))[0], d, places=14)

    def test_segment_segment(self):
        cases = [([0, 0, 0], [1, 0, 0], [0.5, -1, 1], [0.5, 1, 1], 1.0),      # skew, interior
                 ([0, 0, 0], [1, 0, 0], [2, 0, 1], [3, 0, 1], np.sqrt(2)),     # collinear-parallel, ends
                 ([0, 0, 0], [1, 0, 0], [0.2, 0.3, 0], [0.7, 0.3, 0], 0.3)]    # parallel, overlapping
        for p0, p1, q0, q1, d in cases:
            self.assertAlmostEqual(geo.segment_segment_distance(*self.rows(p0, p1, q0, q1))[0], d, places=14)

    def test_segment_triangle(self):
        a, b, c = [0, 0, 0], [1, 0, 0], [0, 1, 0]
        through = geo.segment_crosses_triangle(*self.rows([0.2, 0.2, -1], [0.2, 0.2, 1], a, b, c))
        beside = geo.segment_crosses_triangle(*self.rows([0.8, 0.8, -1], [0.8, 0.8, 1], a, b, c))
        short = geo.segment_crosses_triangle(*self.rows([0.2, 0.2, 1e-12], [0.2, 0.2, 1], a, b, c))
        self.assertEqual((through[0], beside[0], short[0]), (True, False, False))
        # Coplanar up to round-off (two triangles of one flat face, seen in a real run): the
        # orientation signs are noise there and must not make a crossing.
        flat = geo.segment_crosses_triangle(*self.rows(
            [0.05, 1.11131396e-17, 0.19975475], [0.1, 0.05, 0.19975475], [0.1, 1.38804028e-17, 0.19975475],
            [0.15, 2.65727675e-17, 0.19975475], [0.15, 0.05, 0.19975475]))
        self.assertFalse(flat[0])
        # A flat face bent by 1e-12 m (the extremes matrix's dt_1e-3 case, step 2): the edge's ends
        # lie on both sides of the next quad's triangle's plane and one line test is within the
        # round-off bound; decided exactly, the line passes beside the triangle.
        h = float.fromhex
        bent = geo.segment_crosses_triangle(*self.rows(*[[h(v) for v in point] for point in [
            ['0x1.eb851eb851ee1p-5', '-0x1.9999999999992p-4', '0x1.fcdbb34490237p-11'],
            ['0x1.99999999999a9p-4', '-0x1.eb851eb851ea6p-5', '0x1.fcdbb344912afp-11'],
            ['0x1.eb851eb851ec8p-5', '-0x1.eb851eb851eb5p-5', '0x1.fcdbb34490c60p-11'],
            ['0x1.eb851eb851eaep-5', '-0x1.47ae147ae148ap-6', '0x1.fcdbb34490e15p-11'],
            ['0x1.9999999999999p-4', '-0x1.47ae147ae147ap-6', '0x1.fcdbb344908f0p-11']]]))
        self.assertFalse(bent[0])

    def test_unit_cube_dets(self):
        x = geo.HEX_CORNERS[None] * [1, 2, 3]
        np.testing.assert_allclose(geo.hex_jacobian_dets(x), 6.0)

    def test_grid_pairs_match_brute_force(self):
        rng = np.random.default_rng(0)
        lo_a, lo_b = rng.random((300, 3)), rng.random((200, 3))
        hi_a, hi_b = lo_a + 0.1 * rng.random((300, 3)), lo_b + 0.3 * rng.random((200, 3)) ** 4
        i, j = geo.overlapping_boxes(lo_a, hi_a, lo_b, hi_b)
        brute = np.all(lo_a[:, None] <= hi_b[None], axis=2) & np.all(lo_b[None] <= hi_a[:, None], axis=2)
        self.assertEqual(set(zip(i, j)), set(zip(*np.nonzero(brute))))


if __name__ == '__main__':
    unittest.main()
