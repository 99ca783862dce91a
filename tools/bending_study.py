#!/usr/bin/python3
"""Bending on unstructured meshes: strip cantilevers and Peirce's cantilever on irregular
triangulations, solved statically through the Python package, against the analytic answers.

    PYTHONPATH=python SINEW_LIB=build/libsinew.so /usr/bin/python3 tools/bending_study.py [--quick]
    PYTHONPATH=python SINEW_LIB=build/libsinew.so /usr/bin/python3 tools/bending_study.py --clamp
    /usr/bin/python3 tools/bending_study.py --square OUT.obj N

(--clamp prints the clamp's table of docs/models.md: the strip at 45 degrees with and without
triangles across the pinned column.  --square writes gmsh's Frontal-Delaunay mesh of the unit
square at mesh size 1/(N-1), for bench/bench_step --obj: the cost of the bending models on an
unstructured mesh.)

Meshes (a strip 0.2 m from the clamp, L/5 wide; two straight pinned columns at s = 0 and s = h
clamp it at s = h/2; n cells along, h = 0.2/n):
  delaunay   jittered points (every vertex off the clamp, tip and long edges moved by up to
             +-0.25 h each way, the long edges' only along them), scipy's Delaunay triangulation
             of the free part s >= h beside the pinned band [0, h] as a column of cells;
  delaunay45 a square lattice of spacing h turned by 45 degrees against the strip, jittered the
             same, plus the boundary points every h, Delaunay: the strip at 45 degrees to the
             mesh's dominant directions;
  gmsh       gmsh's Frontal-Delaunay (the pattern importer's mesher) of the strip at mesh size
             h times 0.95, 1.0 and 1.05 (three meshes).
Cases: a tip load and the strip's own weight, each sized for a deflection of 1e-4 of the length
(small deflection: Euler-Bernoulli P L^3 / (3 D w) and rho g L^4 / (8 D)); and Peirce's
cantilever (scenes/peirce_cantilever.yaml's strip, overhang 2c, on a jittered Delaunay mesh), the
chord angle against the heavy elastica's 41.487 degrees.  Every model (dihedral, quadratic,
morley) on every mesh; the table (markdown) gives the mean and the largest error over the seeds.
Prints the table on stdout; docs/models.md ("Unstructured meshes") has it.
"""
import os
import sys
import tempfile

import numpy as np
from scipy.spatial import Delaunay

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import sinew  # noqa: E402

LEN, KB, G = 0.2, 1e-3, 9.81
MODELS = ("dihedral", "quadratic", "morley")


# ----------------------------------------------------------------------------- meshes
def boundary_points(n, nt, h, W, rng, tip):
    """The two clamp columns, the tip column and the long edges (jittered along s)."""
    pts = [(i * h, j * W / nt) for i in (0, 1) for j in range(nt + 1)]
    pts += [(tip, j * W / nt) for j in range(nt + 1)]
    for i in range(2, int(np.ceil(tip / h - 1e-9))):
        for t in (0.0, W):
            pts.append((i * h + 0.25 * h * rng.uniform(-1, 1), t))
    return pts


def delaunay_strip(n, seed, turned, raw_band=False):
    rng = np.random.default_rng(seed)
    h = LEN / n
    nt, W, tip = n // 5, LEN / 5, (n + 1) * h
    pts = boundary_points(n, nt, h, W, rng, tip)
    if turned:  # a lattice at 45 degrees, spacing h, kept 0.3 h inside the free part
        a = h / np.sqrt(2.0)
        for i in range(-int(W / a) - 2, int(tip / a) + 3):
            for j in range(-int(tip / a) - 2, int(tip / a) + 3):
                s, t = (i + j) * a, (j - i) * a
                if 1.3 * h < s < tip - 0.3 * h and 0.3 * h < t < W - 0.3 * h:
                    pts.append((s + 0.25 * h * rng.uniform(-1, 1), t + 0.25 * h * rng.uniform(-1, 1)))
    else:
        for i in range(2, n + 1):
            for j in range(1, nt):
                pts.append((i * h + 0.25 * h * rng.uniform(-1, 1),
                            j * h + 0.25 * h * rng.uniform(-1, 1)))
    p = np.array(pts)
    return p, keep_good(p, Delaunay(p).simplices if raw_band else banded(p, h)), h


def banded(p, h):
    """The pinned band s <= h as a column of cells (two triangles between each two consecutive
    vertices of the columns s = 0 and s = h) and the rest, s >= h, by Delaunay on its own: the
    clamp as gmsh's meshes have it.  A Delaunay triangulation of all the points at once joins
    the column s = 0 to a free vertex that falls inside a band cell's circumcircle (closer than
    about 0.2 h to s = h, as the 45-degree lattice's can), across the column s = h."""
    free = np.where(p[:, 0] > h * (1 - 1e-9))[0]
    c0, ch = (np.where(np.abs(p[:, 0] - s) < 1e-9 * h)[0] for s in (0.0, h))
    c0, ch = c0[np.argsort(p[c0, 1])], ch[np.argsort(p[ch, 1])]
    band = [(c0[j], ch[j], ch[j + 1]) for j in range(len(c0) - 1)]
    band += [(c0[j], ch[j + 1], c0[j + 1]) for j in range(len(c0) - 1)]
    return np.vstack([free[Delaunay(p[free]).simplices], np.array(band)])


def straddling(p, tri, h):
    """Triangles with a vertex on s = 0 and one beyond s = h: across the pinned column."""
    s = p[tri, 0]
    return int(np.sum((s.min(axis=1) < 1e-9 * h) & (s.max(axis=1) > h * (1 + 1e-9))))


def keep_good(p, tri):
    """Counter-clockwise triangles of non-zero area (Delaunay of collinear boundary points can
    add slivers of zero area along a straight edge)."""
    a, b, c = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
    cr = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    tri = tri[np.abs(cr) > 1e-6 * np.max(np.abs(cr))]
    cr = cr[np.abs(cr) > 1e-6 * np.max(np.abs(cr))]
    tri[cr < 0] = tri[cr < 0][:, [0, 2, 1]]
    return tri


def gmsh_strip(n, factor):
    """gmsh's Frontal-Delaunay of the free part [h, tip] beside the pinned band [0, h] (one
    column of cells, as in the other meshes: the clamp line is then at h/2), both long edges and
    both clamp lines split every h."""
    import gmsh
    h = LEN / n
    nt, W, tip = n // 5, LEN / 5, (n + 1) * h
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.MeshSizeMax", factor * h)
        gmsh.model.add("strip")
        geo = gmsh.model.geo
        P = [geo.addPoint(x, y, 0, factor * h) for x, y in
             ((0, 0), (h, 0), (tip, 0), (tip, W), (h, W), (0, W))]
        L = [geo.addLine(P[i], P[(i + 1) % 6]) for i in range(6)]
        mid = geo.addLine(P[1], P[4])
        band = geo.addPlaneSurface([geo.addCurveLoop([L[0], mid, L[4], L[5]])])
        geo.addPlaneSurface([geo.addCurveLoop([L[1], L[2], L[3], -mid])])
        geo.synchronize()
        for c in (mid, L[5]):  # the clamp columns: straight, every h across, aligned
            gmsh.model.mesh.setTransfiniteCurve(c, nt + 1)
        gmsh.model.mesh.setTransfiniteCurve(L[0], 2)
        gmsh.model.mesh.setTransfiniteCurve(L[4], 2)
        gmsh.model.mesh.setTransfiniteSurface(band)  # no vertex inside the band: clamp at h/2
        gmsh.model.mesh.generate(2)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        index = {t: k for k, t in enumerate(tags)}
        p = xyz.reshape(-1, 3)[:, :2].copy()
        tris = []
        for etype, _, nodes in zip(*gmsh.model.mesh.getElements(2)):
            if etype == 2:
                tris.append(np.array([index[t] for t in nodes]).reshape(-1, 3))
        tri = np.vstack(tris)
    finally:
        gmsh.finalize()
    used = np.unique(tri)  # drop nodes no triangle uses (geometry points)
    remap = -np.ones(len(p), dtype=int)
    remap[used] = np.arange(len(used))
    return p[used], keep_good(p[used], remap[tri]), h


# ----------------------------------------------------------------------------- runs
def write_obj(path, p, tri):
    with open(path, "w") as f:
        for s, t in p:
            f.write("v %.17g %.17g 0\n" % (s, t))
        for s, t in p:
            f.write("vt %.17g %.17g\n" % (s, t))
        for a, b, c in tri + 1:
            f.write("f %d/%d %d/%d %d/%d\n" % (a, a, b, b, c, c))


def tip_edges(p, tri):
    """(a, b, length) of the boundary edges on the tip s = max."""
    smax = p[:, 0].max()
    out = set()
    for t in tri:
        for k in range(3):
            a, b = t[k], t[(k + 1) % 3]
            if p[a, 0] > smax - 1e-12 and p[b, 0] > smax - 1e-12:
                out.add((min(a, b), max(a, b)))
    return [(a, b, abs(p[a, 1] - p[b, 1])) for a, b in out]


def solve(folder, p, tri, model, h, material, gravity, loads):
    write_obj(os.path.join(folder, "m.obj"), p, tri)
    rest = ", rest: flat" if model == "dihedral" else ""
    lines = ["name: study", "dimension: 3", "mesh: {obj: m.obj}", "material:",
             "  density: %.17g" % material[0],
             "  membrane: {model: bw98, k_u: 10000, k_v: 10000, k_shear: 10000}",
             "  bending: {model: %s, stiffness: %.17g%s}" % (model, material[1], rest),
             "pins: [{select: {box: [[-1, -1, -1], [%.17g, 1, 1]]}}]" % (h * (1 + 1e-9))]
    if gravity:
        lines.append("gravity: [0, 0, %.17g]" % -G)
    if loads:
        lines.append("loads:")
        lines += ["  - {select: {vertices: [%d]}, force: [0, 0, %.17g]}" % (v, fz)
                  for v, fz in loads.items()]
    lines += ["integrator: {method: static, newton: {force_tol: 1e-12}}", "duration: 0"]
    path = os.path.join(folder, "s.yaml")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    with sinew.load(path) as sim:
        sim.step()
        return np.array(sim.positions)


def cantilever(folder, p, tri, h, model, tip):
    """Relative error of the tip deflection (mean over the tip edges)."""
    L, W = p[:, 0].max() - 0.5 * h, p[:, 1].max() - p[:, 1].min()
    delta = 1e-4 * LEN
    edges = tip_edges(p, tri)
    if tip:
        P = delta * 3 * KB * W / L ** 3
        loads = {}
        for a, b, l in edges:
            for v in (a, b):
                loads[v] = loads.get(v, 0.0) - 0.5 * P * l / W
        x = solve(folder, p, tri, model, h, (0.1, KB), False, loads)
    else:
        x = solve(folder, p, tri, model, h, (delta * 8 * KB / (G * L ** 4), KB), True, None)
    z = sum(0.5 * l * (x[a, 2] + x[b, 2]) for a, b, l in edges) / sum(l for _, _, l in edges)
    return -z / delta - 1.0


def peirce(folder, n, seed, model):
    """Peirce's strip (2 cm wide, overhang 0.08 m = 2c, D = 1.25568e-4 N m, 0.2 kg/m^2) on a
    jittered Delaunay mesh of n cells along the overhang: the chord angle, degrees."""
    rng = np.random.default_rng(seed)
    h = 0.08 / (n + 0.5)
    W, nt, tip = 0.02, max(2, int(round(0.02 / h))), (n + 1) * h
    pts = boundary_points(n, nt, h, W, rng, tip)
    hy = W / nt
    for i in range(2, n + 1):
        for j in range(1, nt):
            pts.append((i * h + 0.25 * h * rng.uniform(-1, 1), j * hy + 0.25 * hy * rng.uniform(-1, 1)))
    p = np.array(pts)
    tri = keep_good(p, Delaunay(p).simplices)
    x = solve(folder, p, tri, model, h, (0.2, 1.25568e-4), True, None)
    tipv = p[:, 0] > p[:, 0].max() - 1e-12
    return np.degrees(np.arctan2(-x[tipv, 2].mean(), x[tipv, 0].mean() - 0.5 * h))


def row(label, n, errs):
    cells = []
    for m in MODELS:
        e = 100 * np.array(errs[m])
        cells.append("%+.3f %% / %.3f %%" % (e.mean(), np.abs(e).max()))
    return "| %s | %d | %s |" % (label, n, " | ".join(cells))


def gmsh_square(path, n):
    import gmsh
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 1.0 / (n - 1))
        gmsh.model.add("square")
        gmsh.model.occ.addRectangle(0, 0, 0, 1, 1)
        gmsh.model.occ.synchronize()
        gmsh.model.mesh.generate(2)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        index = {t: k for k, t in enumerate(tags)}
        p = xyz.reshape(-1, 3)[:, :2].copy()
        tri = np.vstack([np.array([index[t] for t in nodes]).reshape(-1, 3)
                         for etype, _, nodes in zip(*gmsh.model.mesh.getElements(2)) if etype == 2])
    finally:
        gmsh.finalize()
    write_obj(path, p, keep_good(p, tri))
    print("%s: %d vertices, %d triangles" % (path, len(p), len(tri)))


def clamp_study():
    """The strip at 45 degrees to the lattice, morley, tip load, six meshes per resolution: the
    error with the whole point set triangulated by Delaunay at once (triangles across the pinned
    column) and with the pinned band kept as a column of cells, the same points."""
    seeds = range(1, 7)
    print("| cells along | triangles across the pinned column, per mesh | Delaunay at once | "
          "band as cells |\n| --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as folder:
        for n in (20, 40, 80, 160):
            count, errs = [], {False: [], True: []}
            for seed in seeds:
                for raw in (True, False):
                    p, tri, h = delaunay_strip(n, 100 * n + seed, True, raw_band=raw)
                    if raw:
                        count.append(straddling(p, tri, h))
                    errs[raw].append(100 * cantilever(folder, p, tri, h, "morley", 1))
            cells = ["%+.4f %% / %.4f %%" % (np.mean(errs[r]), np.max(np.abs(errs[r])))
                     for r in (True, False)]
            print("| %d | %s | %s |" % (n, " ".join(map(str, count)), " | ".join(cells)), flush=True)


def main():
    if "--square" in sys.argv:
        k = sys.argv.index("--square")
        return gmsh_square(sys.argv[k + 1], int(sys.argv[k + 2]))
    if "--clamp" in sys.argv:
        return clamp_study()
    quick = "--quick" in sys.argv
    sizes = (10, 20, 40) if quick else (10, 20, 40, 80)
    seeds = (1, 2) if quick else (1, 2, 3)
    kinds = (("delaunay", "jittered Delaunay"), ("delaunay45", "jittered Delaunay, lattice at 45 degrees"),
             ("gmsh", "gmsh Frontal-Delaunay"))
    print("Tip deflection error, mean / largest |error| over %d meshes (negative: too stiff)\n"
          % len(seeds))
    head = "| mesh, case | cells along | " + " | ".join(MODELS) + " |"
    print(head + "\n|" + "---|" * (2 + len(MODELS)))
    with tempfile.TemporaryDirectory() as folder:
        for tip in (1, 0):
            for kind, label in kinds:
                for n in sizes:
                    errs = {m: [] for m in MODELS}
                    for k, seed in enumerate(seeds):
                        if kind == "gmsh":
                            p, tri, h = gmsh_strip(n, (0.95, 1.0, 1.05)[k % 3])
                        else:
                            p, tri, h = delaunay_strip(n, 100 * n + seed, kind == "delaunay45")
                        for m in MODELS:
                            errs[m].append(cantilever(folder, p, tri, h, m, tip))
                    print(row("%s, %s" % (label, "tip load" if tip else "own weight"), n, errs),
                          flush=True)
        print("\nPeirce's cantilever on jittered Delaunay meshes: chord angle, mean / largest "
              "|angle - 41.487| over %d meshes\n" % len(seeds))
        print("| cells over the ledge | " + " | ".join(MODELS) + " |\n|" + "---|" * (1 + len(MODELS)))
        for n in sizes:
            cells = []
            for m in MODELS:
                a = np.array([peirce(folder, n, 7 * n + s, m) for s in seeds])
                cells.append("%.3f° / %.3f°" % (a.mean(), np.abs(a - 41.487).max()))
            print("| %d | %s |" % (n, " | ".join(cells)), flush=True)


if __name__ == "__main__":
    main()
