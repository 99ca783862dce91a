#!/usr/bin/python3
"""make_icosphere.py — the OBJ of a low-poly sphere (an icosphere) for mesh obstacles
(scenes/drape_mesh.yaml):

    /usr/bin/python3 tools/make_icosphere.py [--subdivisions N] [--radius R]
                                             [-o scenes/meshes/icosphere2.obj]

The regular icosahedron (12 vertices, 20 triangles) with each triangle split N times into four
at its edges' midpoints, every vertex pushed out to the sphere of radius R (m) about the origin:
10 4^N + 2 vertices and 20 4^N triangles, wound counter-clockwise seen from outside.  The output
is a function of the arguments only (no randomness): the same command, the same file."""
import argparse
import math


def icosahedron():
    """The 12 vertices (on the unit sphere) and 20 faces of the regular icosahedron."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    raw = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
           (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [unit(v) for v in raw]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    return verts, faces


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def subdivide(verts, faces):
    """Each triangle into four; the midpoints shared between neighbours, on the unit sphere."""
    mid = {}

    def midpoint(a, b):
        key = (min(a, b), max(a, b))
        if key not in mid:
            verts.append(unit(tuple((p + q) / 2.0 for p, q in zip(verts[a], verts[b]))))
            mid[key] = len(verts) - 1
        return mid[key]

    out = []
    for a, b, c in faces:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return verts, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--subdivisions", type=int, default=2)
    ap.add_argument("--radius", type=float, default=1.0)
    ap.add_argument("-o", "--output", default="scenes/meshes/icosphere2.obj")
    a = ap.parse_args()
    verts, faces = icosahedron()
    for _ in range(a.subdivisions):
        verts, faces = subdivide(verts, faces)
    with open(a.output, "w") as f:
        f.write("# icosphere: %d subdivisions, radius %g m (tools/make_icosphere.py)\n"
                % (a.subdivisions, a.radius))
        for v in verts:
            f.write("v %.9f %.9f %.9f\n" % tuple(a.radius * c for c in v))
        for t in faces:
            f.write("f %d %d %d\n" % tuple(i + 1 for i in t))


if __name__ == "__main__":
    main()
