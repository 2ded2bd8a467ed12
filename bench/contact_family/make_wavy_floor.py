#!/usr/bin/env python3
"""Write wavy_floor.obj, the obstacle of press.json: the open surface
z = a cos(2 pi x / L) cos(2 pi y / L) over [-w, w]^2 as an n x n grid of quads (a = 4 mm,
L = 0.1 m, w = 0.25 m, n = 50: 1 cm quads, crests of height a at every (i, j) L/2 with i + j
even). A body pressed onto it touches the crests first and then the slopes around them, so the
contact set grows with the load, step after step.

  bench/contact_family/make_wavy_floor.py [--n 50] [--out bench/contact_family/wavy_floor.obj]
"""
import argparse
import math
import os


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=50, help="quads along each side")
    ap.add_argument("--amplitude", type=float, default=0.004)
    ap.add_argument("--wavelength", type=float, default=0.1)
    ap.add_argument("--half-width", type=float, default=0.25)
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "wavy_floor.obj"))
    args = ap.parse_args()
    n, a, L, w = args.n, args.amplitude, args.wavelength, args.half_width
    with open(args.out, "w") as f:
        f.write("# wavy floor z = %g cos(2 pi x / %g) cos(2 pi y / %g), %d x %d quads over [-%g, %g]^2 "
                "(bench/contact_family/make_wavy_floor.py)\n" % (a, L, L, n, n, w, w))
        for j in range(n + 1):
            for i in range(n + 1):
                x, y = -w + 2 * w * i / n, -w + 2 * w * j / n
                z = a * math.cos(2 * math.pi * x / L) * math.cos(2 * math.pi * y / L)
                f.write("v %.9g %.9g %.9g\n" % (x, y, z))
        for j in range(n):
            for i in range(n):
                v = 1 + i + (n + 1) * j  # OBJ vertices are 1-based
                # counter-clockwise seen from above: the normal points up, towards the body
                f.write("f %d %d %d %d\n" % (v, v + 1, v + n + 2, v + n + 1))


if __name__ == "__main__":
    main()
