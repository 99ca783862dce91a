#!/usr/bin/python3
"""Write a circular specimen as an OBJ with per-corner UVs (the flat positions, m), for the
Cusick drape test (scenes/cusick_drape.yaml, docs/drape.md).

The vertices lie on concentric rings of spacing h (ring k at radius k h carries round(2 pi k)
vertices, every other ring turned by half a step), so the clamp radius, a whole number of
rings, is a ring of vertices and the edge of the specimen is a circle of polygon; the
triangles are their Delaunay triangulation (scipy.spatial.Delaunay).  Deterministic.

    /usr/bin/python3 tools/make_disc.py --radius 0.15 --spacing 0.01 scenes/meshes/cusick_disc.obj
"""
import argparse
import sys

import numpy as np
from scipy.spatial import Delaunay


def disc_points(radius, spacing):
    """(n, 2) points on rings of spacing `spacing` up to `radius` (a whole number of rings)."""
    rings = int(round(radius / spacing))
    if abs(rings * spacing - radius) > 1e-9 * radius:
        raise ValueError(f"radius {radius} is not a whole number of spacings {spacing}")
    pts = [np.zeros((1, 2))]
    for k in range(1, rings + 1):
        n = int(round(2 * np.pi * k))
        a = (np.arange(n) + 0.5 * (k % 2)) * 2 * np.pi / n
        pts.append(k * spacing * np.column_stack([np.cos(a), np.sin(a)]))
    return np.vstack(pts)


def disc_mesh(radius, spacing):
    """Points (n, 2) and counter-clockwise triangles (m, 3) of the disc."""
    p = disc_points(radius, spacing)
    tri = Delaunay(p).simplices.copy()
    a, b, c = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    tri = tri[cross > 1e-12 * spacing ** 2]          # drop slivers on the convex hull, if any
    flip = cross[cross > 1e-12 * spacing ** 2] < 0
    tri[flip] = tri[flip][:, [0, 2, 1]]
    return p, tri


def write_obj(path, p, tri, radius, spacing):
    with open(path, "w") as f:
        f.write(f"# disc of radius {radius} m, ring spacing {spacing} m, written by "
                f"tools/make_disc.py: {len(p)} vertices, {len(tri)} triangles\n")
        for x, y in p:
            f.write(f"v {x:.9g} {y:.9g} 0\n")
        for x, y in p:
            f.write(f"vt {x:.9g} {y:.9g}\n")
        for t in tri + 1:
            f.write(f"f {t[0]}/{t[0]} {t[1]}/{t[1]} {t[2]}/{t[2]}\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--radius", type=float, default=0.15, help="m (default 0.15)")
    ap.add_argument("--spacing", type=float, default=0.01, help="ring spacing, m (default 0.01)")
    a = ap.parse_args(argv)
    p, tri = disc_mesh(a.radius, a.spacing)
    write_obj(a.out, p, tri, a.radius, a.spacing)
    print(f"{a.out}: {len(p)} vertices, {len(tri)} triangles")


if __name__ == "__main__":
    sys.exit(main())
