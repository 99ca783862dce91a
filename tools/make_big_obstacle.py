#!/usr/bin/python3
"""make_big_obstacle.py — the OBJ of a large mesh obstacle for benchmarks of the broad phase
(tools/bench_big_obstacle.sh):

    /usr/bin/python3 tools/make_big_obstacle.py --triangles N [--size S] [--wave A]
                                                -o big.obj

A square plane of side S (m, default 4) centred on the origin at z = 0, split into an n x n
grid of squares (n = ceil(sqrt(N / 2))), each square into two triangles: 2 n^2 >= N triangles
and (n + 1)^2 vertices, wound counter-clockwise seen from +z.  With --wave A the plane is the
surface z = A sin(2 pi x / S) sin(2 pi y / S) (m), so no two faces are coplanar across the
whole plane.  The output is a function of the arguments only: the same command, the same
file."""
import argparse
import math

import numpy as np


def grid(n, size, wave):
    """Vertices ((n + 1)^2 x 3) and faces (2 n^2 x 3, 0-based) of the plane."""
    s = np.linspace(-0.5 * size, 0.5 * size, n + 1)
    x, y = np.meshgrid(s, s, indexing="xy")
    z = wave * np.sin(2 * math.pi * x / size) * np.sin(2 * math.pi * y / size)
    verts = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
    a = (j * (n + 1) + i).ravel()
    b, c, d = a + 1, a + n + 2, a + n + 1
    faces = np.empty((2 * n * n, 3), dtype=np.int64)
    faces[0::2] = np.column_stack([a, b, c])
    faces[1::2] = np.column_stack([a, c, d])
    return verts, faces


def write_obj(path, verts, faces):
    with open(path, "w") as f:
        f.write("# plane of %d triangles (tools/make_big_obstacle.py)\n" % len(faces))
        np.savetxt(f, verts, fmt="v %.9g %.9g %.9g")
        np.savetxt(f, faces + 1, fmt="f %d %d %d")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--triangles", type=int, required=True, help="at least this many triangles")
    ap.add_argument("--size", type=float, default=4.0, help="side of the square, m")
    ap.add_argument("--wave", type=float, default=0.0, help="amplitude of the wave, m")
    ap.add_argument("-o", "--output", required=True)
    a = ap.parse_args()
    if a.triangles < 2 or not a.size > 0:
        ap.error("--triangles must be at least 2 and --size positive")
    n = max(1, math.ceil(math.sqrt(a.triangles / 2.0)))
    write_obj(a.output, *grid(n, a.size, a.wave))


if __name__ == "__main__":
    main()
