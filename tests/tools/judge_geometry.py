"""Geometry predicates of the output judge (judge_output.py), vectorised over arrays of cases.

Written from the textbook definitions, independent of dipc's C++ contact and element code, so
that a bug there cannot hide itself here. Every function takes arrays of shape (n, 3) (or
(n, 8, 3) for hexahedra) and returns one value per row.
"""
from fractions import Fraction

import numpy as np

# Reference corners of the hex8 element in Gmsh order: bottom face (ζ = -1) counter-clockwise,
# then the top face.
HEX_CORNERS = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)

# The 6 faces as cycles of local corners (any cyclic order works: only the quad's diagonals
# and its set of nodes are used).
HEX_FACES = np.array([[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4],
                      [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]])


def _shape_gradients(points):
    """dN_n/dξ_j of the trilinear shape functions at reference points: (p, 8, 3)."""
    c = HEX_CORNERS[None, :, :]              # (1, 8, 3)
    x = points[:, None, :]                   # (p, 1, 3)
    f = 1.0 + x * c                          # (p, 8, 3): the three factors of N_n
    g = np.empty(f.shape)
    g[..., 0] = c[..., 0] * f[..., 1] * f[..., 2]
    g[..., 1] = f[..., 0] * c[..., 1] * f[..., 2]
    g[..., 2] = f[..., 0] * f[..., 1] * c[..., 2]
    return g / 8.0


# The 8 corners and the 8 points of the 2×2×2 Gauss rule: where dipc's mesh checks and line
# search look as well, and where an inverted trilinear element shows first.
_SAMPLE_POINTS = np.vstack([HEX_CORNERS, HEX_CORNERS / np.sqrt(3.0)])
_SAMPLE_GRADIENTS = _shape_gradients(_SAMPLE_POINTS)


def hex_jacobian_dets(x):
    """det of the Jacobian of the trilinear map of each hex at the 16 sample points.

    x: (e, 8, 3) corner positions. Returns (e, 16)."""
    J = np.einsum('eni,pnj->epij', x, _SAMPLE_GRADIENTS)
    return (J[..., 0, 0] * (J[..., 1, 1] * J[..., 2, 2] - J[..., 1, 2] * J[..., 2, 1])
            - J[..., 0, 1] * (J[..., 1, 0] * J[..., 2, 2] - J[..., 1, 2] * J[..., 2, 0])
            + J[..., 0, 2] * (J[..., 1, 0] * J[..., 2, 1] - J[..., 1, 1] * J[..., 2, 0]))


def _orient_exact(a, b, c, d):
    """The orientation sign of one tetrahedron in exact rational arithmetic (the doubles' values)."""
    a, b, c, d = ([Fraction(float(v)) for v in point] for point in (a, b, c, d))
    u, v, w = ([y - x for x, y in zip(a, point)] for point in (b, c, d))
    det = (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
           + u[2] * (v[0] * w[1] - v[1] * w[0]))
    return (det > 0) - (det < 0)


def orient(a, b, c, d):
    """Sign of the orientation of the tetrahedron abcd: +1, -1 or 0, exact for the doubles given.
    The floating-point determinant decides where it lies beyond its round-off bound (a static
    filter in the manner of Shewchuk's predicates); the few tetrahedra within the bound are
    decided in exact rational arithmetic. Taking those as coplanar instead made an edge of a flat
    face, bent by 1e-12 m, cross a triangle of the next quad on that face (the extremes matrix's
    dt_1e-3 case, 2026-12-07): a 0 counts as on the line in segment_crosses_triangle."""
    u, v, w = b - a, c - a, d - a
    det = np.einsum('ij,ij->i', u, np.cross(v, w))
    # Each difference carries up to eps·|coordinate| of error; the products add a few eps more.
    eps = np.finfo(float).eps
    slack = eps * np.max(np.abs(np.stack([a, b, c, d])), axis=(0, 2))
    norm = lambda x: np.linalg.norm(x, axis=1) + slack
    bound = 16 * eps * norm(u) * norm(v) * norm(w)
    sign = np.where(det > bound, 1, np.where(det < -bound, -1, 0))
    for k in np.nonzero(sign == 0)[0]:
        sign[k] = _orient_exact(a[k], b[k], c[k], d[k])
    return sign


def segment_crosses_triangle(p, q, a, b, c):
    """True where segment pq passes through triangle abc: p and q on opposite sides of its plane,
    and the line pq inside or on the triangle's three edges. Touching and coplanar configurations
    are not crossings (between bodies the distance test sees them). The line tests run only where
    the plane test passes (the exact fall-back of orient is slow)."""
    crosses_plane = orient(a, b, c, p) * orient(a, b, c, q) < 0
    hit = np.zeros(len(p), dtype=bool)
    k = np.nonzero(crosses_plane)[0]
    if len(k):
        p, q, a, b, c = p[k], q[k], a[k], b[k], c[k]
        t1 = orient(p, q, a, b)
        t2 = orient(p, q, b, c)
        t3 = orient(p, q, c, a)
        hit[k] = ((t1 >= 0) & (t2 >= 0) & (t3 >= 0)) | ((t1 <= 0) & (t2 <= 0) & (t3 <= 0))
    return hit


def _dot(u, v):
    return np.einsum('ij,ij->i', u, v)


def point_segment_distance(p, a, b):
    ab = b - a
    length2 = _dot(ab, ab)
    with np.errstate(invalid='ignore', divide='ignore'):
        t = np.where(length2 > 0, _dot(p - a, ab) / length2, 0.0)
    t = np.clip(t, 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)


def point_triangle_distance(p, a, b, c):
    """Euclidean distance from p to the closed triangle abc: the plane distance where p
    projects inside the triangle, else the nearest of its three edges."""
    n = np.cross(b - a, c - a)
    n2 = _dot(n, n)
    inside = ((_dot(np.cross(b - a, p - a), n) >= 0) & (_dot(np.cross(c - b, p - b), n) >= 0)
              & (_dot(np.cross(a - c, p - c), n) >= 0) & (n2 > 0))
    with np.errstate(invalid='ignore', divide='ignore'):
        plane = np.where(inside, np.abs(_dot(p - a, n)) / np.sqrt(np.where(n2 > 0, n2, 1.0)), np.inf)
    edges = np.minimum(np.minimum(point_segment_distance(p, a, b), point_segment_distance(p, b, c)),
                       point_segment_distance(p, c, a))
    return np.minimum(plane, edges)


def segment_segment_distance(p0, p1, q0, q1):
    """Distance between segments p0p1 and q0q1. The squared distance is a convex quadratic on
    [0,1]²: its minimum is the unconstrained one where that lies inside, else on the border,
    i.e. one of the four point–segment distances (which also covers parallel segments)."""
    u = p1 - p0
    v = q1 - q0
    w = p0 - q0
    a, b, c, d, e = _dot(u, u), _dot(u, v), _dot(v, v), _dot(u, w), _dot(v, w)
    denom = a * c - b * b
    with np.errstate(invalid='ignore', divide='ignore'):
        s = (b * e - c * d) / denom
        t = (a * e - b * d) / denom
    interior = (denom > 1e-14 * a * c) & (s >= 0) & (s <= 1) & (t >= 0) & (t <= 1)
    s = np.where(interior, s, 0.0)
    t = np.where(interior, t, 0.0)
    inner = np.where(interior, np.linalg.norm(w + s[:, None] * u - t[:, None] * v, axis=1), np.inf)
    border = np.minimum.reduce([point_segment_distance(p0, q0, q1), point_segment_distance(p1, q0, q1),
                                point_segment_distance(q0, p0, p1), point_segment_distance(q1, p0, p1)])
    return np.minimum(inner, border)


def _grid_cells(lo, hi, origin, cell, dims):
    """(box index, cell key) for every grid cell that each box [lo, hi] touches."""
    i0 = np.floor((lo - origin) / cell).astype(np.int64)
    span = np.floor((hi - origin) / cell).astype(np.int64) - i0 + 1
    counts = span.prod(axis=1)
    box = np.repeat(np.arange(len(lo)), counts)
    k = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    s = span[box]
    ix = i0[box, 0] + k % s[:, 0]
    k //= s[:, 0]
    iy = i0[box, 1] + k % s[:, 1]
    iz = i0[box, 2] + k // s[:, 1]
    return box, (ix * dims[1] + iy) * dims[2] + iz


def overlapping_boxes(lo_a, hi_a, lo_b, hi_b):
    """Index pairs (i, j) whose boxes A_i and B_j overlap, through a uniform grid.

    The cell is the median box size (at least a quarter of the largest box, so that no box
    spans more than a few cells per axis). Returns two int arrays."""
    empty = (np.zeros(0, np.int64), np.zeros(0, np.int64))
    if len(lo_a) == 0 or len(lo_b) == 0:
        return empty
    extent = np.concatenate([hi_a - lo_a, hi_b - lo_b]).max(axis=1)
    origin = np.minimum(lo_a.min(axis=0), lo_b.min(axis=0))
    top = np.maximum(hi_a.max(axis=0), hi_b.max(axis=0))
    cell = max(np.median(extent), extent.max() / 4, (top - origin).max() / 1e6, 1e-300)
    dims = np.floor((top - origin) / cell).astype(np.int64) + 1
    box_a, key_a = _grid_cells(lo_a, hi_a, origin, cell, dims)
    box_b, key_b = _grid_cells(lo_b, hi_b, origin, cell, dims)
    order = np.argsort(key_b, kind='stable')
    key_b, box_b = key_b[order], box_b[order]
    first = np.searchsorted(key_b, key_a, 'left')
    count = np.searchsorted(key_b, key_a, 'right') - first
    i = np.repeat(box_a, count)
    offsets = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    j = box_b[np.repeat(first, count) + offsets]
    code = np.unique(i * len(lo_b) + j)
    i, j = code // len(lo_b), code % len(lo_b)
    keep = np.all(lo_a[i] <= hi_b[j], axis=1) & np.all(lo_b[j] <= hi_a[i], axis=1)
    return i[keep], j[keep]
