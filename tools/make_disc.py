#!/usr/bin/python3
"""Write a circular specimen as an OBJ with per-corner UVs (the flat positions, m), for the
Cusick drape test (scenes/cusick_drape.yaml, docs/drape.md).

The vertices lie on concentric rings of spacing h (ring k at radius k h carries round(2 pi k)
vertices, every other ring turned by half a step), so the clamp radius, a whole number of
rings, is a ring of vertices and the edge of the specimen is a circle of polygon; the
triangles are their Delaunay triangulation (scipy.spatial.Delaunay).  Deterministic.

With --refine R0 R1 H (repeatable) the rings are H apart between radii R0 and R1 and
--spacing apart elsewhere, and --ring R puts a ring at R (the clamp's edge); each ring then
carries round(2 pi r / h) vertices, h the smaller of its spacings to its neighbours. The
drape coefficient depends on the mesh within about 2 cm of the clamp's edge and hardly
anywhere else (docs/drape.md, "Where the mesh matters"), so that is where rings must be close.

    /usr/bin/python3 tools/make_disc.py --radius 0.15 --spacing 0.01 scenes/meshes/cusick_disc.obj
    /usr/bin/python3 tools/make_disc.py --ring 0.09 --refine 0.08 0.11 0.0025 \\
        --refine 0.085 0.10 0.00125 out.obj
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


def refined_radii(radius, spacing, bands, rings=()):
    """Ring radii (ascending, ending at `radius`): the disc cut at the ends of the bands
    (r0, r1, h) and at `rings`; each piece in equal steps no longer than the smallest h of the
    bands that cover it, or `spacing` where none does."""
    cuts = sorted({0.0, radius, *rings, *(r for b in bands for r in b[:2] if 0 < r < radius)})
    out = []
    for a, b in zip(cuts[:-1], cuts[1:]):
        h = min([spacing] + [hb for r0, r1, hb in bands if r0 <= a + 1e-12 and b <= r1 + 1e-12])
        n = max(1, int(np.ceil((b - a) / h - 1e-9)))
        out += [a + (i + 1) * (b - a) / n for i in range(n)]
    return np.array(out)


def ring_points(radii):
    """(n, 2) points: the centre, and on each ring round(2 pi r / h) points, h the smaller of
    the ring's spacings to its neighbours, every other ring turned by half a step."""
    pts = [np.zeros((1, 2))]
    edges = np.concatenate([[0.0], radii])
    for k, r in enumerate(radii):
        h = edges[k + 1] - edges[k]
        if k + 1 < len(radii):
            h = min(h, radii[k + 1] - r)
        n = int(round(2 * np.pi * r / h))
        a = (np.arange(n) + 0.5 * (k % 2)) * 2 * np.pi / n
        pts.append(r * np.column_stack([np.cos(a), np.sin(a)]))
    return np.vstack(pts)


def disc_mesh(radius, spacing, bands=(), rings=()):
    """Points (n, 2) and counter-clockwise triangles (m, 3) of the disc: rings `spacing`
    apart, or closer in the bands (r0, r1, h) (refined_radii)."""
    if not bands:
        p = disc_points(radius, spacing)
    else:
        p = ring_points(refined_radii(radius, spacing, bands, rings))
        spacing = min(b[2] for b in bands)
    tri = Delaunay(p).simplices.copy()
    a, b, c = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    tri = tri[cross > 1e-12 * spacing ** 2]          # drop slivers on the convex hull, if any
    flip = cross[cross > 1e-12 * spacing ** 2] < 0
    tri[flip] = tri[flip][:, [0, 2, 1]]
    return p, tri


def write_obj(path, p, tri, radius, spacing, grading=""):
    with open(path, "w") as f:
        f.write(f"# disc of radius {radius} m, ring spacing {spacing} m{grading}, written by "
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
    ap.add_argument("--refine", nargs=3, type=float, action="append", default=[],
                    metavar=("R0", "R1", "H"), help="rings H apart between radii R0 and R1, m "
                    "(repeatable; the closest spacing wins where bands overlap)")
    ap.add_argument("--ring", type=float, action="append", default=[],
                    help="a ring at this radius, m (the clamp's edge; repeatable)")
    a = ap.parse_args(argv)
    if any(not (0 <= r0 < r1 <= a.radius and 0 < h) for r0, r1, h in a.refine):
        ap.error("expected --refine R0 R1 H with 0 <= R0 < R1 <= radius and H > 0")
    if a.ring and not a.refine:
        ap.error("--ring needs --refine (without it the rings are k times --spacing)")
    p, tri = disc_mesh(a.radius, a.spacing, a.refine, a.ring)
    grading = "".join(f", {h} m from {r0} to {r1} m" for r0, r1, h in a.refine)
    write_obj(a.out, p, tri, a.radius, a.spacing, grading)
    print(f"{a.out}: {len(p)} vertices, {len(tri)} triangles")


if __name__ == "__main__":
    sys.exit(main())
