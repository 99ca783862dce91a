"""Meshing pattern pieces with gmsh (Debian's python3-gmsh): the boundary resampled at the
target edge length (corners and notches kept as points), internal cutouts as holes, drill holes
and the points of internal lines embedded as mesh vertices, then gmsh's Frontal-Delaunay
triangulation (Mesh.Algorithm 6) with a largest element size of the edge length.

The (u,v) of a piece are its plane coordinates turned so that u runs along its grain line
(the warp) and shifted so that the smallest u and v are 0, in metres."""
import math
from dataclasses import dataclass, field

import numpy as np

from . import geometry as geo
from .dxf import JOIN_TOL, PatternError, Skipped, grain_frame

CORNER_ANGLE = math.radians(30)  # a boundary turning by more than this is a corner
MIN_EDGES = 8                    # a piece's perimeter must hold this many edges


@dataclass
class Meshed:
    piece: object
    group: str
    xy: np.ndarray        # (n, 2) m: where the piece lies in the file (then laid out)
    uv: np.ndarray        # (n, 2) m: rest layout, u along the grain line
    tris: np.ndarray      # (m, 3) 0-based, counter-clockwise in (u,v)
    boundary: list        # vertex indices around the boundary, counter-clockwise in (u,v)
    corners: list
    notches: list
    drills: list
    internal: list        # a list of vertex indices per internal line
    holes: list           # a boundary loop per internal cutout
    grain_deg: float      # angle of the grain line in the file's plane, degrees
    grain_from_line: bool
    area: float = 0.0     # m², the sum of the triangles' (u,v) areas
    notes: list = field(default_factory=list)


def _marks(piece, p, h):
    """Arc-length positions of the boundary points that must be mesh vertices: corners (turns
    over CORNER_ANGLE, and turn points of layer 2 on the boundary) and notches; marks closer than
    h/4 merged (a corner wins).  Returns the sorted positions, the index (into them) of each
    corner and of each notch."""
    s0, total = geo.arclength(p)
    corners = list(s0[geo.turn_angles(p) > CORNER_ANGLE])
    for q, _ in piece.turn_points:
        d, s = geo.project(p, q)
        if d <= JOIN_TOL:
            corners.append(s)
    notch_s = [geo.project(p, q)[1] for q in piece.notches]
    marks = []  # (position, is_corner)
    for s, is_corner in sorted([(s, True) for s in corners] + [(s, False) for s in notch_s]):
        if marks and (s - marks[-1][0]) < h / 4:
            continue
        marks.append((s, is_corner))
    if len(marks) > 1 and marks[0][0] + total - marks[-1][0] < h / 4:
        marks.pop()
    if not marks:
        marks = [(0.0, True)]
    pos = np.array([s for s, _ in marks])

    def nearest(s):
        d = np.abs(pos - s)
        d = np.minimum(d, total - d)
        return int(np.argmin(d))
    return pos, sorted({nearest(s) for s in corners}), [nearest(s) for s in notch_s]


class _Gmsh:
    """One gmsh model per piece, built from points and straight lines."""

    def __init__(self, gmsh, h):
        self.g, self.h = gmsh, h
        self.lines = []

    def point(self, q):
        return self.g.model.geo.addPoint(float(q[0]), float(q[1]), 0.0, self.h)

    def loop(self, pts):
        tags = [self.point(q) for q in pts]
        n = len(tags)
        lines = [self.g.model.geo.addLine(tags[i], tags[(i + 1) % n]) for i in range(n)]
        self.lines += lines
        return self.g.model.geo.addCurveLoop(lines), tags


def _embedded(piece, outer, holes, h, where, skipped):
    """Drill holes and the points of internal lines (resampled at h) that lie inside the piece,
    at least h/3 from its boundary and from each other."""
    def ok(q, taken):
        if not geo.inside(outer, q) or any(geo.inside(hl, q) for hl in holes):
            return False
        if min([geo.project(outer, q)[0]] + [geo.project(hl, q)[0] for hl in holes]) < h / 3:
            return False
        return all(math.hypot(*(q - t)) >= h / 3 for t in taken)
    taken, drills, lines = [], [], []
    for q in piece.drills:
        if ok(q, taken):
            drills.append(len(taken))
            taken.append(q)
        else:
            skipped.append(Skipped(where, "drill hole at (%.4g, %.4g) m" % tuple(q),
                                   "outside the piece or within %.3g m of its boundary or "
                                   "another drill hole" % (h / 3)))
    for line in piece.internal:
        seg = np.hypot(*np.diff(line, axis=0).T)
        s = np.concatenate(([0.0], np.cumsum(seg)))
        k = max(1, int(round(s[-1] / h)))
        pts = np.column_stack([np.interp(np.linspace(0, s[-1], k + 1), s, line[:, i])
                               for i in (0, 1)])
        idx = []
        for q in pts:
            if ok(q, taken):
                idx.append(len(taken))
                taken.append(q)
        if len(idx) < len(pts):
            skipped.append(Skipped(where, "internal line of %d points from (%.4g, %.4g) m" %
                                   (len(pts), pts[0][0], pts[0][1]),
                                   "%d of its points outside the piece or near its boundary "
                                   "or other points: not mesh vertices" % (len(pts) - len(idx))))
        lines.append(idx)
    return taken, drills, lines


def mesh_piece(piece, group, h, skipped):
    """Meshed piece at target edge length h (m); raises PatternError when it cannot be."""
    import gmsh
    where = piece.label
    p = piece.boundary
    _, perimeter = geo.arclength(p)
    if perimeter < MIN_EDGES * h:
        raise PatternError("%s: its boundary is %.3g m long, too small for edges of %.3g m "
                           "(at least %d edges around); expected a smaller --edge" %
                           (where, perimeter, h, MIN_EDGES))
    bad = geo.self_intersection(p)
    if bad is not None:
        raise PatternError("%s: its %s crosses itself near (%.4g, %.4g) m; expected a simple "
                           "closed line" % (where, piece.boundary_from, bad[0], bad[1]))
    d, from_line = grain_frame(piece)
    pos, corner_k, notch_k = _marks(piece, p, h)
    outer, mark_idx = geo.resample(p, pos, h)
    if geo.self_intersection(outer) is not None:
        raise PatternError("%s: with edges of %.3g m its boundary crosses itself (a part of "
                           "the piece is narrower than the edges); expected a smaller --edge" %
                           (where, h))
    holes = []
    for hole in piece.holes:
        if not geo.inside(p, hole[0]):
            skipped.append(Skipped(where, "internal cutout at (%.4g, %.4g) m" % tuple(hole[0]),
                                   "outside the piece"))
            continue
        s0, _ = geo.arclength(hole)
        marks = s0[geo.turn_angles(hole) > CORNER_ANGLE]
        res, _ = geo.resample(hole, marks if len(marks) else [0.0], h)
        if len(res) < 3:
            res = geo.resample(hole, [0.0], h / 3)[0]
        holes.append(res)
    emb, drill_k, line_k = _embedded(piece, outer, holes, h, where, skipped)

    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 1)
        gmsh.model.add(group)
        b = _Gmsh(gmsh, h)
        outer_loop, outer_tags = b.loop(outer)
        hole_loops = [b.loop(hl) for hl in holes]
        surf = gmsh.model.geo.addPlaneSurface([outer_loop] + [lp for lp, _ in hole_loops])
        emb_tags = [b.point(q) for q in emb]
        for ln in b.lines:
            gmsh.model.geo.mesh.setTransfiniteCurve(ln, 2)
        gmsh.model.geo.synchronize()
        if emb_tags:
            gmsh.model.mesh.embed(0, emb_tags, 2, surf)
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        etypes, _, enodes = gmsh.model.mesh.getElements(2, surf)

        def node(pt):
            return int(gmsh.model.mesh.getNodes(0, pt)[0][0])
        outer_nodes = [node(t) for t in outer_tags]
        hole_nodes = [[node(t) for t in tg] for _, tg in hole_loops]
        emb_nodes = [node(t) for t in emb_tags]
    except Exception as e:
        raise PatternError("%s: gmsh cannot mesh it: %s" % (where, e)) from None
    finally:
        gmsh.finalize()
    if list(etypes) != [2]:
        raise PatternError("%s: gmsh made no triangles of it" % where)
    index = {int(t): i for i, t in enumerate(tags)}
    xy = coords.reshape(-1, 3)[:, :2].copy()
    tris = np.array([index[int(t)] for t in enodes[0]]).reshape(-1, 3)
    used = np.unique(tris)
    if len(used) != len(xy):  # nodes no triangle uses: drop them and renumber
        remap = -np.ones(len(xy), int)
        remap[used] = np.arange(len(used))
        xy, tris = xy[used], remap[tris]
        index = {t: remap[i] for t, i in index.items()}
    uv = np.column_stack([xy @ d, xy @ np.array([-d[1], d[0]])])
    uv -= uv.min(axis=0)
    e1, e2 = uv[tris[:, 1]] - uv[tris[:, 0]], uv[tris[:, 2]] - uv[tris[:, 0]]
    cross = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    tris[cross < 0] = tris[cross < 0][:, [0, 2, 1]]
    bnd = [index[t] for t in outer_nodes]
    corners = {bnd[mark_idx[k]] for k in corner_k}
    notches = {bnd[mark_idx[k]] for k in notch_k}
    if corners:  # the boundary starts at a corner; corners and notches in boundary order
        first = min(bnd.index(c) for c in corners)
        bnd = bnd[first:] + bnd[:first]
    at = {v: i for i, v in enumerate(bnd)}
    return Meshed(piece=piece, group=group, xy=xy, uv=uv, tris=tris, boundary=bnd,
                  corners=sorted(corners, key=at.get), notches=sorted(notches, key=at.get),
                  drills=[index[emb_nodes[k]] for k in drill_k],
                  internal=[[index[emb_nodes[k]] for k in ln] for ln in line_k],
                  holes=[[index[t] for t in hl] for hl in hole_nodes],
                  grain_deg=math.degrees(math.atan2(d[1], d[0])), grain_from_line=from_line,
                  area=float(np.abs(cross).sum() / 2))


def layout(meshed, gap=0.05):
    """Each piece's positions (n, 3), m: where the file places it, in the plane z = 0; when two
    pieces' boxes overlap there, all are laid side by side along x instead, gap m apart, in the
    order of the file."""
    boxes = [(m.xy.min(0), m.xy.max(0)) for m in meshed]
    overlap = any(np.all(boxes[i][0] < boxes[j][1]) and np.all(boxes[j][0] < boxes[i][1])
                  for i in range(len(boxes)) for j in range(i + 1, len(boxes)))
    out, x = [], 0.0
    for m, (lo, hi) in zip(meshed, boxes):
        xy = m.xy - lo + np.array([x, 0.0]) if overlap else m.xy
        x += hi[0] - lo[0] + gap
        out.append(np.column_stack([xy, np.zeros(len(xy))]))
    return out, overlap
