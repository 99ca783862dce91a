"""sinew render RUN_DIR: pictures of a run's tension XY map, headless (matplotlib's Agg backend).

For every frame of the run folder (or those chosen) one PNG: on the left the flat pattern, each
panel in its rest (u,v) layout, labelled with its name, with its grain line and the seams; on
the right the 3D shape with the scene's obstacles (the body) in grey; both coloured by tension
XY (N/m, one colour bar), the tendons drawn over them coloured by their tension (N, a second
colour bar) and labelled with it; the title is the scene's name and the time.  Then an
animation of all of them: a GIF (Pillow) or, where ffmpeg is installed and asked for, an MP4.

    python3 -m sinew.render RUN_DIR [--out DIR] [--every K] [--last] [--range R] [--smooth]
                                    [--scene FILE] [--animation gif|mp4|none] [--dpi N]
                                    [--quiet]

The colour range (--range): `MIN:MAX` in N/m, or `[SCOPE:]pQ`, 0 to the Q-th percentile of
the tension XY of the faces that touch no pinned vertex, over the last frame (SCOPE `last`, the
default), every frame (`run`) or each frame on its own (`frame`).  The default `last:p98` is
the settled garment's range: see docs/garments.md, "Fit-check pictures".

The obstacles and the panels' names and bias come from the run's scene (summary.json's
scene_file, else restart.bin's absolute path, or --scene); the seams from RUN_DIR/seams.json
when it exists."""
import argparse
import json
import os
import re
import shutil
import sys

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import animation, cm, colors, patheffects  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402

from . import frames  # noqa: E402

GAP = 0.05  # gap between panels laid side by side, as a share of the widest panel
DEFAULT_RANGE = "last:p98"
BODY_GREY = 0.78  # the obstacles' colour (lit: times 0.45 .. 1)
SHAPE_HEIGHT = 0.77  # the 3D view's height, a fraction of the figure's
LIGHT = np.array([-0.35, -0.75, 0.55]) / np.linalg.norm([-0.35, -0.75, 0.55])
SEAM_COLOURS = ["#e6194b", "#f58231", "#ffe119", "#3cb44b", "#42d4f4", "#f032e6", "#ffffff",
                "#fabed4"]


# ------------------------------------------------------------------ colour range

def parse_range(text):
    """--range: ("fixed", lo, hi) from "MIN:MAX" (N/m), or (scope, q) from "[SCOPE:]pQ" with
    SCOPE last (default), run or frame and 0 < Q <= 100.  ValueError otherwise."""
    m = re.fullmatch(r"(?:(last|run|frame):)?p(\d+(?:\.\d*)?)", text.strip())
    if m:
        q = float(m.group(2))
        if not 0.0 < q <= 100.0:
            raise ValueError("--range %s: the percentile must be in (0, 100]" % text)
        return (m.group(1) or "last", q)
    parts = text.split(":")
    try:
        if len(parts) != 2:
            raise ValueError
        lo, hi = float(parts[0]), float(parts[1])
    except ValueError:
        raise ValueError("--range %s: expected MIN:MAX (N/m) or [last|run|frame:]pQ "
                         "(a percentile, e.g. p98 or frame:p95)" % text) from None
    if not (np.isfinite(lo) and np.isfinite(hi) and hi > lo):
        raise ValueError("--range %s: expected MIN < MAX, both finite" % text)
    return ("fixed", lo, hi)


def free_faces(cloth):
    """Faces with no pinned vertex (all faces when every face touches a pin)."""
    nf = len(cloth.offsets)
    pinned = cloth.point_data.get("pinned")
    if pinned is None:
        return np.ones(nf, bool)
    free = ~pinned.astype(bool)[cloth.connectivity.reshape(nf, 3)].any(axis=1)
    return free if free.any() else np.ones(nf, bool)


def percentile_top(clothes, q):
    """The q-th percentile of the tension XY of the free faces (free_faces) of clothes, N/m."""
    values = np.concatenate([c.cell_data["tension_xy"][free_faces(c)] for c in clothes])
    return float(np.percentile(values, q))


def tension_norms(run, spec):
    """The colour range of each frame: a list of Normalize, one per frame of run."""
    if spec[0] == "fixed":
        return [colors.Normalize(spec[1], spec[2])] * len(run)
    scope, q = spec
    clothes = [p["cloth"] for _, p in run]
    if scope == "frame":
        tops = [percentile_top([c], q) for c in clothes]
    else:
        tops = [percentile_top(clothes if scope == "run" else clothes[-1:], q)] * len(run)
    return [colors.Normalize(0.0, top if top > 0.0 else 1.0) for top in tops]


def tendon_norm(run):
    """One scale for the tendons' tension (N) over the whole run."""
    tt = [p["tendons"].cell_data["tension"] for _, p in run if "tendons" in p]
    tmax = float(np.concatenate(tt).max()) if tt else 0.0
    return colors.Normalize(0.0, tmax if tmax > 0 else 1.0)


def smooth_faces(cloth, values):
    """Face values averaged over each vertex's faces (weighted by the faces' areas), then over
    each face's three vertices: a display that trades the per-face detail (a zigzag between
    neighbouring triangles) for the local mean."""
    nf = len(cloth.offsets)
    tri = cloth.connectivity.reshape(nf, 3)
    p = cloth.points[tri]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    num, den = np.zeros(len(cloth.points)), np.zeros(len(cloth.points))
    for k in range(3):
        np.add.at(num, tri[:, k], area * values)
        np.add.at(den, tri[:, k], area)
    vertex = num / np.maximum(den, 1e-300)
    return vertex[tri].mean(axis=1)


def range_label(spec, smooth=False):
    if spec[0] == "fixed":
        return "tension XY (N/m), range set by --range"
    what = {"last": "the last frame", "run": "the run", "frame": "this frame"}[spec[0]]
    q = spec[1]
    suffix = "th"
    if q == int(q) and int(q) % 100 not in (11, 12, 13):
        suffix = {1: "st", 2: "nd", 3: "rd"}.get(int(q) % 10, "th")
    return "tension XY (N/m%s), 0 to the %g%s percentile of %s (faces free of pins)" % (
        ", smoothed" if smooth else "", q, suffix, what)


# ------------------------------------------------------------------ the run's scene

def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def restart_scene(run_dir):
    """The scene's absolute path that restart.bin's header holds (after its 8-byte magic
    SWRESTnn, NUL-terminated), or None."""
    try:
        with open(os.path.join(run_dir, "restart.bin"), "rb") as f:
            head = f.read(8 + 4096)
    except OSError:
        return None
    if head[:6] != b"SWREST":  # any version: the scene path follows the magic in each
        return None
    return head[8:].split(b"\0", 1)[0].decode("utf-8", "replace") or None


def find_scene(run_dir, summary, scene=None):
    """The scene file of the run: scene if given, else summary.json's scene_file (as the run
    was given it: relative to the working folder of the run), else the absolute path in
    restart.bin; None if none of them is a file."""
    if scene:
        return scene
    for path in ((summary or {}).get("scene_file"), restart_scene(run_dir)):
        if path and os.path.isfile(path):
            return path
    return None


def load_yaml(path):
    try:
        import yaml
    except ImportError:
        print("sinew render: no PyYAML (Debian's python3-yaml): the scene's obstacles and panel "
              "names are not drawn", file=sys.stderr)
        return None
    try:
        with open(path) as f:
            return yaml.safe_load(f)
    except (OSError, yaml.YAMLError) as e:
        print("sinew render: %s: %s: the scene's obstacles and panel names are not drawn"
              % (path, e), file=sys.stderr)
        return None


def read_obj(path):
    """Vertices (n x 3), triangles (fan-triangulated polygons) and each triangle's group name
    (`g` or `usemtl`, "default" before any) of an OBJ file."""
    verts, tris, groups, group = [], [], [], "default"
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            key, _, rest = line.partition(" ")
            if key == "v":
                verts.append([float(x) for x in rest.split()[:3]])
            elif key in ("g", "usemtl"):
                group = rest.strip() or "default"
            elif key == "f":
                idx = [int(c.split("/")[0]) for c in rest.split()]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    tris.append([idx[0], idx[k], idx[k + 1]])
                    groups.append(group)
    return np.array(verts, float).reshape(-1, 3), np.array(tris, int).reshape(-1, 3), groups


def vec3(value):
    a = np.zeros(3)
    v = np.array(value, dtype=float).ravel()
    a[:len(v)] = v
    return a


def smoothstep5(u):
    """The quintic blend 6u^5 - 15u^4 + 10u^3 of keyframed motions (docs/scenes.md)."""
    return u * u * u * (u * (6.0 * u - 15.0) + 10.0)


def displacement(motion, t):
    """An obstacle's translation at time t (m) from its `motion` map (keyframes, smooth or
    linear interpolation, constant outside them)."""
    if not motion or not motion.get("keyframes"):
        return np.zeros(3)
    keys = [(float(k[0]), vec3(k[1:])) for k in motion["keyframes"]]
    if t <= keys[0][0]:
        return keys[0][1]
    for (t0, d0), (t1, d1) in zip(keys, keys[1:]):
        if t <= t1:
            u = (t - t0) / (t1 - t0) if t1 > t0 else 1.0
            if motion.get("interpolation", "smooth") != "linear":
                u = smoothstep5(u)
            return d0 + u * (d1 - d0)
    return keys[-1][1]


class Scene:
    """What the pictures need of the run's scene: its name, obstacles (each a dict with its
    shape and motion; a mesh as vertices and triangles), the cloth's OBJ groups, each panel's
    bias (degrees) and the seams (seams.json)."""

    def __init__(self, run_dir=None, scene=None):
        """The scene of the run folder run_dir (scene: its file, when not the run's); with no
        run_dir, none: no name, obstacles, groups or seams."""
        self.name, self.obstacles, self.groups, self.bias, self.panel_names = "", [], None, {}, None
        self.dimension, self.seams, self.turned = 3, [], set()
        if run_dir is None:
            return
        summary = read_json(os.path.join(run_dir, "summary.json")) or {}
        self.name = summary.get("scene") or os.path.basename(os.path.normpath(run_dir))
        path = find_scene(run_dir, summary, scene)
        doc = load_yaml(path) if path else None
        if isinstance(doc, dict):
            self.read_scene(doc, os.path.dirname(os.path.abspath(path)))
        elif not path:
            print("sinew render: the run's scene file is not found (summary.json's scene_file, "
                  "restart.bin; give it with --scene): no obstacles or panel names drawn",
                  file=sys.stderr)
        seams = read_json(os.path.join(run_dir, "seams.json"))
        self.seams = seams.get("seams", []) if isinstance(seams, dict) else []

    def read_scene(self, doc, folder):
        self.dimension = int(doc.get("dimension", 3))
        material = doc.get("material") or {}
        panels = doc.get("panels") or {}
        self.panel_names = ["material"] + list(panels)
        default_bias = float(material.get("bias", 0.0))
        self.bias = {name: float((p or {}).get("bias", default_bias))
                     for name, p in panels.items()}
        self.bias[None] = default_bias
        # pieces wrapped with their u up the body (`arrange: NAME: {cylinder: {up: u}}`):
        # drawn turned, u up the page, as they are worn
        for name, place in (doc.get("arrange") or {}).items():
            cyl = place.get("cylinder") if isinstance(place, dict) else None
            if isinstance(cyl, dict) and cyl.get("up") == "u":
                self.turned.add(str(name))
        mesh = doc.get("mesh") or {}
        if isinstance(mesh, dict) and mesh.get("obj"):
            try:
                self.groups = read_obj(os.path.join(folder, mesh["obj"]))[2]
            except (OSError, ValueError):
                self.groups = None
        for item in doc.get("obstacles") or []:
            try:
                self.obstacles.append(self.read_obstacle(item, folder))
            except (OSError, ValueError, KeyError, TypeError) as e:
                print("sinew render: obstacle %s not drawn: %s" % (item, e), file=sys.stderr)

    @staticmethod
    def read_obstacle(item, folder):
        ob = {"motion": item.get("motion")}
        if "mesh" in item:
            v, f, _ = read_obj(os.path.join(folder, item["mesh"]))
            v = v * float(item.get("scale", 1.0)) + vec3(item.get("translate", [0, 0, 0]))
            ob.update(kind="mesh", verts=v, tris=f, normals=vertex_normals(v, f))
            return ob
        kind = item["shape"]
        ob["kind"] = kind
        if kind == "plane":
            n = vec3(item["normal"])
            ob.update(point=vec3(item["point"]), normal=n / np.linalg.norm(n))
        elif kind == "sphere":
            ob.update(center=vec3(item["center"]), radius=float(item["radius"]))
        elif kind == "capsule":
            ob.update(ends=[vec3(e) for e in item["ends"]], radius=float(item["radius"]))
        elif kind == "box":
            ob.update(center=vec3(item["center"]), size=vec3(item["size"]))
        else:
            raise ValueError("unknown shape %r" % kind)
        return ob

    def pieces(self, cloth):
        """Each face's piece (an index) and the pieces' names: the OBJ groups when the scene's
        mesh has them for every face, else the `panel` ids named after the scene's panels."""
        nf = len(cloth.offsets)
        if self.groups is not None and len(self.groups) == nf:
            names = sorted(set(self.groups), key=self.groups.index)
            return np.array([names.index(g) for g in self.groups]), names
        panel = cloth.cell_data.get("panel", np.zeros(nf, dtype=np.int32))
        ids = sorted(set(panel.tolist()))
        known = self.panel_names or []
        names = [known[i] if i < len(known) and len(ids) > 1 else None for i in ids]
        return np.searchsorted(ids, panel), names

    def turned_ids(self, names):
        """The ids of the pieces drawn turned (their u up the page)."""
        return {p for p, n in enumerate(names) if n in self.turned}

    def piece_bias(self, name):
        """The piece's bias, degrees: its panel's, else the material's."""
        return self.bias.get(name, self.bias.get(None, 0.0))


# ------------------------------------------------------------------ obstacle surfaces

def vertex_normals(verts, tris):
    """Unit outward normals at the vertices (area-weighted face normals; outward: turned so
    that the enclosed signed volume is positive)."""
    a, b, c = verts[tris[:, 0]], verts[tris[:, 1]], verts[tris[:, 2]]
    fn = np.cross(b - a, c - a)
    if np.einsum("ij,ij->", a, np.cross(b, c)) < 0:
        fn = -fn
    n = np.zeros_like(verts)
    for k in range(3):
        np.add.at(n, tris[:, k], fn)
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]


def sphere_tris(center, radius, n=24):
    """A UV sphere: (n*n*2, 3, 3) triangles."""
    th = np.linspace(0, np.pi, n + 1)
    ph = np.linspace(0, 2 * np.pi, 2 * n + 1)
    p = np.stack([np.sin(th)[:, None] * np.cos(ph), np.sin(th)[:, None] * np.sin(ph),
                  np.cos(th)[:, None] * np.ones_like(ph)], axis=-1) * radius + center
    return grid_tris(p)


def grid_tris(p):
    """Two triangles per cell of a (rows, cols, 3) grid of points."""
    a, b, c, d = p[:-1, :-1], p[:-1, 1:], p[1:, 1:], p[1:, :-1]
    return np.concatenate([np.stack([a, b, c], -2).reshape(-1, 3, 3),
                           np.stack([a, c, d], -2).reshape(-1, 3, 3)])


def capsule_tris(e0, e1, radius, n=24):
    """A capsule: a cylinder about e0-e1 with a hemisphere on each end."""
    axis = e1 - e0
    length = np.linalg.norm(axis)
    w = axis / length if length > 0 else np.array([0.0, 0.0, 1.0])
    u = np.cross(w, [1.0, 0, 0] if abs(w[0]) < 0.9 else [0, 1.0, 0])
    u /= np.linalg.norm(u)
    v = np.cross(w, u)
    # profile: the hemisphere at e0 (polar angle pi .. pi/2), the cylinder, the one at e1
    th = np.concatenate([np.linspace(np.pi, np.pi / 2, n // 2 + 1),
                         np.linspace(np.pi / 2, 0, n // 2 + 1)])
    along = np.where(np.arange(len(th)) <= n // 2, 0.0, length) + radius * np.cos(th)
    rad = radius * np.sin(th)
    ph = np.linspace(0, 2 * np.pi, 2 * n + 1)
    p = (e0 + along[:, None, None] * w
         + rad[:, None, None] * (np.cos(ph)[None, :, None] * u + np.sin(ph)[None, :, None] * v))
    return grid_tris(p)


def box_tris(center, size):
    h = size / 2
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * h + center
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return np.array([corners[[q[0], q[1], q[2]]] for q in quads]
                    + [corners[[q[0], q[2], q[3]]] for q in quads])


def plane_tris(point, normal, lo, hi):
    """The plane's square patch under the view box [lo, hi] (none if it misses the box)."""
    mid, half = (lo + hi) / 2, float(np.max(hi - lo)) / 2
    dist = float(np.dot(mid - point, normal))
    if abs(dist) > half * np.sqrt(3):
        return np.zeros((0, 3, 3))
    c = mid - dist * normal
    t1 = np.cross(normal, [1.0, 0, 0] if abs(normal[0]) < 0.9 else [0, 1.0, 0])
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(normal, t1)
    s = np.linspace(-half, half, 9)
    p = c + s[:, None, None] * t1 + s[None, :, None] * t2
    return grid_tris(p)


def obstacle_tris(ob, t, lo, hi, inset=0.0):
    """An obstacle's surface at time t as triangles (k, 3, 3), m, drawn `inset` m inside the
    true surface: a cloth lying on it (a few mm off) then sorts in front of it by depth."""
    d = displacement(ob.get("motion"), t)
    kind = ob["kind"]
    if kind == "mesh":
        return (ob["verts"] - inset * ob["normals"])[ob["tris"]] + d
    if kind == "sphere":
        return sphere_tris(ob["center"] + d, max(ob["radius"] - inset, 0.5 * ob["radius"]))
    if kind == "capsule":
        return capsule_tris(ob["ends"][0] + d, ob["ends"][1] + d,
                            max(ob["radius"] - inset, 0.5 * ob["radius"]))
    if kind == "box":
        return box_tris(ob["center"] + d, np.maximum(ob["size"] - 2 * inset, 0.5 * ob["size"]))
    return plane_tris(ob["point"] + d - inset * ob["normal"], ob["normal"], lo, hi)


def bounded_obstacle_box(ob):
    """The obstacle's bounding box at its stated place (None for a plane)."""
    kind = ob["kind"]
    if kind == "mesh":
        return ob["verts"].min(0), ob["verts"].max(0)
    if kind == "sphere":
        return ob["center"] - ob["radius"], ob["center"] + ob["radius"]
    if kind == "capsule":
        e = np.array(ob["ends"])
        return e.min(0) - ob["radius"], e.max(0) + ob["radius"]
    if kind == "box":
        return ob["center"] - ob["size"] / 2, ob["center"] + ob["size"] / 2
    return None


def view_box(cloth, obstacles, t):
    """The 3D view's box: the cloth's box joined with each bounded obstacle's (moved to t)
    when that keeps it within 3 times the cloth's size (a body stays whole; a far or huge
    obstacle is cut to the cloth's surroundings)."""
    lo, hi = cloth.points.min(0), cloth.points.max(0)
    size = float((hi - lo).max())
    for ob in obstacles:
        box = bounded_obstacle_box(ob)
        if box is None:
            continue
        d = displacement(ob.get("motion"), t)
        nlo, nhi = np.minimum(lo, box[0] + d), np.maximum(hi, box[1] + d)
        if float((nhi - nlo).max()) <= 3.0 * size:
            lo, hi = nlo, nhi
    pad = 0.03 * max(float((hi - lo).max()), 1e-9)
    return lo - pad, hi + pad


def shaded_grey(tris):
    """A grey per triangle lit by LIGHT from the front (Lambert, both sides)."""
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]
    lit = 0.45 + 0.55 * np.abs(n @ LIGHT)
    g = BODY_GREY * lit
    return np.stack([g, g, g, np.ones_like(g)], axis=1)


# ------------------------------------------------------------------ the flat pattern

def face_uv(cloth):
    """(nf, 3, 2) rest (u,v) of each face's corners, m: uv_corners at seams, else the points'."""
    nf = len(cloth.offsets)
    if "uv_corners" in cloth.cell_data:
        return cloth.cell_data["uv_corners"].reshape(nf, 3, 2)
    if "uv" not in cloth.point_data:
        return cloth.points[:, :2][cloth.connectivity.reshape(nf, 3)]
    return cloth.point_data["uv"][cloth.connectivity.reshape(nf, 3)]


def row_layout(boxes, ids, rows):
    """Pieces in order in `rows` rows of about equal count, left to right, rows top to bottom:
    each piece's shift and the layout's (width, height)."""
    widest = max(hi[0] - lo[0] for lo, hi in boxes.values())
    gap = GAP * widest
    shift, y, width = {}, 0.0, 0.0
    per_row = -(-len(ids) // rows)
    for r in range(0, len(ids), per_row):
        row = ids[r:r + per_row]
        tallest = max(boxes[p][1][1] - boxes[p][0][1] for p in row)
        x = 0.0
        for p in row:
            lo, hi = boxes[p]
            shift[p] = np.array([x - lo[0], y - tallest - lo[1]])
            x += hi[0] - lo[0] + gap
        width = max(width, x - gap)
        y -= tallest + gap
    return shift, (width, -y - gap)


def turn(uv):
    """(u, v) -> (-v, u): a piece drawn with its u up the page, as `up: u` wraps it."""
    return np.stack([-uv[..., 1], uv[..., 0]], axis=-1)


def pattern_layout(cloth, piece=None, aspect=None, turned=()):
    """Each face's corners in the flat view, m: each piece (piece: a per-face id, default the
    `panel` array) in its (u,v) layout, turned (u up) when its id is in `turned`; pieces whose
    boxes overlap are laid side by side (in the number of rows that best fills a view of
    width / height `aspect`, one row when it is None); and the shift of each piece (piece id
    -> (du, dv), after the turn)."""
    uv = face_uv(cloth).copy()
    if piece is None:
        piece = cloth.cell_data.get("panel", np.zeros(len(uv), dtype=np.int32))
    for p in turned:
        uv[piece == p] = turn(uv[piece == p])
    ids = sorted(set(np.asarray(piece).tolist()))
    boxes = {p: (uv[piece == p].reshape(-1, 2).min(0), uv[piece == p].reshape(-1, 2).max(0))
             for p in ids}
    overlap = any(np.all(boxes[a][0] < boxes[b][1]) and np.all(boxes[b][0] < boxes[a][1])
                  for i, a in enumerate(ids) for b in ids[i + 1:])
    shift = {p: np.zeros(2) for p in ids}
    if overlap:
        best = None
        for rows in range(1, (len(ids) if aspect else 1) + 1):
            s, (w, h) = row_layout(boxes, ids, rows)
            fill = min(aspect / w, 1.0 / h) if aspect else 0.0  # the scale that fits the view
            if best is None or fill > best[0] * 1.0001:
                best = (fill, s)
        shift = best[1]
        if aspect is None:  # one row, its pieces' bottoms at v = 0
            shift = {p: np.array([s[0], -boxes[p][0][1]]) for p, s in shift.items()}
    for p in ids:
        uv[piece == p] += shift[p]
    return uv, piece, shift


def tendon_pattern(cloth, tend, panel, shift, turned=()):
    """Each tendon's waypoints in the flat view: the (u,v) of the vertex in its first face
    (turned with its piece)."""
    nf = len(cloth.offsets)
    tri = cloth.connectivity.reshape(nf, 3)
    first = np.full(len(cloth.points), -1)
    for f in range(nf - 1, -1, -1):
        first[tri[f]] = f
    uv = cloth.point_data.get("uv", cloth.points[:, :2])
    lines = []
    for cell in tend.cells():
        verts = tend.point_data["vertex"][cell]
        lines.append(np.array([(turn(uv[v]) if panel[first[v]] in turned else uv[v])
                               + shift[panel[first[v]]] if first[v] >= 0 else uv[v]
                               for v in verts]))
    return lines


def corner_lookup(cloth, uv, piece):
    """{(piece, vertex): (u, v) in the flat view} for every face corner."""
    tri = cloth.connectivity.reshape(len(cloth.offsets), 3)
    out = {}
    for f in range(len(tri)):
        for i in range(3):
            out.setdefault((int(piece[f]), int(tri[f, i])), uv[f, i])
    return out


def seam_sides(seam):
    """A seam's two sides as [(panel name, [vertex, ...])], from either form of seams.json:
    {"panels": [a, b], "curves": [[v, ...], [v, ...]]} (what sinew writes) or
    {"a": {"panel": a, "vertices": [...]}, "b": {...}}."""
    if "curves" in seam:
        return list(zip(seam.get("panels") or [], seam.get("curves") or []))
    return [((seam.get(k) or {}).get("panel"), (seam.get(k) or {}).get("vertices") or [])
            for k in ("a", "b")]


def seam_lines(seams, names, lookup):
    """Each seam side's polyline in the flat view: [(seam name, colour, points, piece, side
    0 or 1)], the sides whose panel or vertices the frame does not have left out."""
    out = []
    for k, seam in enumerate(seams):
        colour = SEAM_COLOURS[k % len(SEAM_COLOURS)]
        for side, (panel, verts) in enumerate(seam_sides(seam)):
            if panel not in names:
                continue
            p = names.index(panel)
            pts = [lookup.get((p, int(v))) for v in verts]
            if len(pts) >= 2 and all(q is not None for q in pts):
                out.append((str(seam.get("name", "seam %d" % (k + 1))), colour, np.array(pts),
                            p, side))
    return out


def label_outside(ax, text, pts, centre, colour, at=0.5):
    """text beside polyline pts (at that fraction of its points), along it, on the side away
    from centre (the piece's centroid): a tag in the seam's colour just outside the piece."""
    m = min(int(at * len(pts)), len(pts) - 1)
    tangent = pts[min(m + 1, len(pts) - 1)] - pts[max(m - 1, 0)]
    tangent = tangent / max(np.linalg.norm(tangent), 1e-300)
    normal = np.array([-tangent[1], tangent[0]])
    if np.dot(normal, pts[m] - centre) < 0:
        normal = -normal
    angle = np.degrees(np.arctan2(tangent[1], tangent[0]))
    angle = (angle + 90.0) % 180.0 - 90.0  # never upside down
    ax.annotate(text, pts[m], xytext=tuple(7.0 * normal), textcoords="offset points",
                ha="center", va="center", rotation=angle, rotation_mode="anchor", fontsize=7,
                color="black", bbox={"boxstyle": "round,pad=0.15", "fc": colour, "alpha": 0.85,
                                     "lw": 0})


def outlines(cloth, uv, piece):
    """Each piece's boundary in the flat view: the segments of the edges that only one face of
    that piece has."""
    tri = cloth.connectivity.reshape(len(cloth.offsets), 3)
    count, where = {}, {}
    for f in range(len(tri)):
        for i in range(3):
            j = (i + 1) % 3
            key = (int(piece[f]), min(tri[f, i], tri[f, j]), max(tri[f, i], tri[f, j]))
            count[key] = count.get(key, 0) + 1
            where[key] = (uv[f, i], uv[f, j])
    return [where[k] for k, n in count.items() if n == 1]


def grain_line(uv_piece, bias_deg):
    """The grain line of a piece: a segment through its centroid along the warp (the u axis
    turned by the bias), half as long as the piece is across in that direction."""
    pts = uv_piece.reshape(-1, 2)
    centre = pts.mean(0)
    a = np.radians(bias_deg)
    d = np.array([np.cos(a), np.sin(a)])
    s = (pts - centre) @ d
    half = 0.25 * (s.max() - s.min())
    return centre - half * d, centre + half * d


def draw_flat(ax, cloth, tend, txy_norm, t_norm, scene=None):
    scene = scene or Scene()
    piece, names = scene.pieces(cloth)
    box = ax.get_position()
    fig_w, fig_h = ax.figure.get_size_inches()
    turned = scene.turned_ids(names)
    uv, piece, shift = pattern_layout(cloth, piece, box.width * fig_w / (box.height * fig_h),
                                      turned)
    ax.add_collection(PolyCollection(uv, array=cloth.cell_data["tension_xy"], cmap="viridis",
                                     norm=txy_norm, edgecolors="face", linewidths=0.2))
    ax.add_collection(LineCollection(outlines(cloth, uv, piece), colors="black",
                                     linewidths=0.8))
    for p in sorted(set(piece.tolist())):
        name = names[p] if p < len(names) else None
        a, b = grain_line(uv[piece == p], scene.piece_bias(name) + (90.0 if p in turned else 0.0))
        # white with a dark rim: seen on the fabric's colours and where it crosses a cutout
        ax.annotate("", b, a, arrowprops={
            "arrowstyle": "<|-|>", "color": "white", "lw": 1.2, "shrinkA": 0, "shrinkB": 0,
            "mutation_scale": 9,
            "path_effects": [patheffects.withStroke(linewidth=2.4, foreground="0.25")]})
        if name:  # beside the arrow's middle, below it or to its right, off both heads
            d = (b - a) / max(float(np.hypot(*(b - a))), 1e-300)
            n = np.array([d[1], -d[0]]) if abs(d[0]) >= abs(d[1]) else np.array([-d[1], d[0]])
            n = n if n[0] > 0.5 or n[1] < -0.5 else -n
            ax.annotate(name, (a + b) / 2, xytext=tuple(8 * n), textcoords="offset points",
                        ha="left" if n[0] > 0.5 else "center",
                        va="top" if n[1] < -0.5 else "center", fontsize=10, color="black",
                        bbox={"boxstyle": "round,pad=0.2", "fc": "white", "alpha": 0.8,
                              "lw": 0})
    lookup = corner_lookup(cloth, uv, piece)
    for name, colour, pts, p, side in seam_lines(scene.seams, names, lookup):
        ax.plot(pts[:, 0], pts[:, 1], color=colour, lw=2.2, solid_capstyle="round")
        # the two sides' tags a third and two thirds along: apart where two pieces are close
        label_outside(ax, name, pts, uv[piece == p].reshape(-1, 2).mean(0), colour,
                      (1 + side) / 3)
    if tend is not None:
        lines = tendon_pattern(cloth, tend, piece, shift, turned)
        tension = tend.cell_data["tension"]
        ax.add_collection(LineCollection(lines, array=tension, cmap="autumn_r", norm=t_norm,
                                         linewidths=2.5))
        for line, tn in zip(lines, tension):
            ax.annotate("%.3g N" % tn, line[len(line) // 2], xytext=(0, 6),
                        textcoords="offset points", ha="center", fontsize=9, color="black",
                        bbox={"boxstyle": "round", "fc": "white", "alpha": 0.7, "lw": 0})
    pts = uv.reshape(-1, 2)
    lo, hi = pts.min(0), pts.max(0)
    pad = 0.02 * float((hi - lo).max())
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal", adjustable="datalim")
    ax.tick_params(labelsize=8)
    every = bool(turned) and turned == set(piece.tolist())
    some = bool(turned) and not every
    ax.set_xlabel("−v (m)" if every else "u (m)" + (", turned pieces: −v" if some else ""),
                  fontsize=9)
    ax.set_ylabel("u (m)" if every else "v (m)" + (", turned pieces: u" if some else ""),
                  fontsize=9)
    ax.set_title("flat pattern: grain lines (arrows)%s" % (", seams" if scene.seams else ""),
                 fontsize=10)


# ------------------------------------------------------------------ the 3D shape

def draw_shape(ax, cloth, tend, txy_norm, t_norm, scene=None, t=0.0):
    scene = scene or Scene()
    nf = len(cloth.offsets)
    tris = cloth.points[cloth.connectivity.reshape(nf, 3)]
    rgba = cm.viridis(txy_norm(cloth.cell_data["tension_xy"]))
    obstacles = scene.obstacles if scene.dimension == 3 else []
    lo, hi = view_box(cloth, obstacles, t)
    inset = 0.01 * float((hi - lo).max())
    body = [obstacle_tris(ob, t, lo, hi, inset) for ob in obstacles]
    body = np.concatenate(body) if body else np.zeros((0, 3, 3))
    inside = np.all((body.max(1) >= lo) & (body.min(1) <= hi), axis=1)
    body = body[inside]
    # one collection, so that matplotlib sorts the cloth's and the body's faces by depth together
    faces = np.concatenate([tris, body])
    fc = np.concatenate([rgba, shaded_grey(body)])
    ec = np.concatenate([rgba, np.zeros((len(body), 4))])
    # the faces sorted among themselves; tendons and labels drawn over them
    ax.computed_zorder = False
    ax.add_collection3d(Poly3DCollection(faces, facecolors=fc, edgecolors=ec, linewidths=0.1,
                                         zorder=1))
    if tend is not None:
        lines = [tend.points[c] for c in tend.cells()]
        tension = tend.cell_data["tension"]
        ax.add_collection3d(Line3DCollection(lines, colors=cm.autumn_r(t_norm(tension)),
                                             linewidths=2.5, zorder=2))
        for line, tn in zip(lines, tension):
            ax.text(*line[len(line) // 2], " %.3g N" % tn, fontsize=9, zorder=3,
                    bbox={"boxstyle": "round", "fc": "white", "alpha": 0.7, "lw": 0})
    for setter, a, b in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), lo, hi):
        setter(a, b)
    extent = hi - lo
    # matplotlib draws a 3D view in the largest square of its axes: a view taller than wide
    # (a standing body) is zoomed to its height, and its title raised to the axes' top
    box = ax.get_position(original=True)
    fig_w, fig_h = ax.figure.get_size_inches()
    tall = box.height * fig_h / (box.width * fig_w)
    ax.set_box_aspect(tuple(np.maximum(extent, 0.05 * float(extent.max()))),
                      zoom=float(np.clip(0.9 * tall, 1.0, 1.3)))
    for axis, e in zip((ax.xaxis, ax.yaxis, ax.zaxis), extent):
        axis.set_major_locator(matplotlib.ticker.MaxNLocator(max(2, int(6 * e / extent.max()))))
    ax.tick_params(labelsize=7)
    ax.set_xlabel("x (m)", fontsize=8)
    ax.set_ylabel("y (m)", fontsize=8)
    ax.set_zlabel("z (m)", fontsize=8, labelpad=8)
    ax.set_title("3D shape%s" % (" on the body (grey)" if len(body) else ""), fontsize=10,
                 y=max(1.0, (tall + 1.0) / 2.0))


FLAT_HEIGHT = 0.7   # the flat view's height, a fraction of the figure's
VIEWS_WIDTH = 0.9   # the two views' widths together, a fraction of the figure's


def shape_width(fig, cloth, scene, t):
    """The width the 3D view needs, a fraction of the figure's: what the projection of its box
    (matplotlib's default view, 30 degrees up, azimuth -60 degrees) needs at the view's height,
    between 0.3 (a standing body) and 0.48 (a wide drape)."""
    obstacles = scene.obstacles if scene and scene.dimension == 3 else []
    lo, hi = view_box(cloth, obstacles, t)
    ex, ey, ez = hi - lo
    el, az = np.radians(30.0), np.radians(-60.0)
    wide = ex * abs(np.sin(az)) + ey * abs(np.cos(az))
    tall = ez * np.cos(el) + (ex * abs(np.cos(az)) + ey * abs(np.sin(az))) * np.sin(el)
    fig_w, fig_h = fig.get_size_inches()
    # 1.35: matplotlib draws the box inside a margin of its axes; 0.06 for the tick labels
    need = wide / max(tall, 1e-12) * SHAPE_HEIGHT * fig_h / fig_w * 1.35 + 0.06
    return float(np.clip(need, 0.3, 0.48))


def view_widths(fig, cloth, scene, t):
    """The widths of the flat and the 3D views, fractions of the figure's: the 3D view takes
    what it needs (shape_width); the flat pattern, laid out for the rest, keeps the width its
    layout fills at the view's height, at least 0.42; the 3D view takes what is left."""
    flat_most = VIEWS_WIDTH - shape_width(fig, cloth, scene, t)
    fig_w, fig_h = fig.get_size_inches()
    scene = scene or Scene()
    piece, names = scene.pieces(cloth)
    uv = pattern_layout(cloth, piece, flat_most * fig_w / (FLAT_HEIGHT * fig_h),
                        scene.turned_ids(names))[0]
    w, h = np.ptp(uv.reshape(-1, 2), axis=0) * 1.04  # draw_flat's 2 % pad each side
    need = w / max(h, 1e-12) * FLAT_HEIGHT * fig_h / fig_w
    flat = float(np.clip(need, 0.42, max(flat_most, 0.42)))
    return flat, VIEWS_WIDTH - flat


def draw(fig, t, parts, txy_norm, t_norm, name, scene=None, label=None):
    """One frame on fig (cleared first)."""
    fig.clf()
    cloth, tend = parts["cloth"], parts.get("tendons")
    flat_w, w3 = view_widths(fig, cloth, scene, t)
    flat = fig.add_axes([0.06, 0.2, flat_w, FLAT_HEIGHT])
    shape = fig.add_axes([0.98 - w3, 0.13, w3, SHAPE_HEIGHT], projection="3d")
    draw_flat(flat, cloth, tend, txy_norm, t_norm, scene)
    draw_shape(shape, cloth, tend, txy_norm, t_norm, scene, t)
    over = float(cloth.cell_data["tension_xy"].max()) > txy_norm.vmax
    fig.colorbar(cm.ScalarMappable(norm=txy_norm, cmap="viridis"), orientation="horizontal",
                 cax=fig.add_axes([0.08, 0.08, flat_w - 0.04, 0.03]),
                 extend="max" if over else "neither", label=label or "tension XY (N/m)")
    fig.axes[-1].xaxis.label.set_size(8)
    if tend is not None:
        fig.colorbar(cm.ScalarMappable(norm=t_norm, cmap="autumn_r"), orientation="horizontal",
                     cax=fig.add_axes([1.04 - w3, 0.08, w3 - 0.1, 0.03]),
                     label="tendon tension (N)")
    fig.suptitle("%s   t = %.3f s" % (name, t), fontsize=13)


def writer_for(kind, out):
    """The animation writer and file: GIF through Pillow, MP4 through ffmpeg; None for none."""
    if kind == "none":
        return None, None
    if kind == "mp4":
        if not shutil.which("ffmpeg"):
            raise SystemExit("sinew render: --animation mp4 needs ffmpeg on the PATH")
        return animation.FFMpegWriter(fps=10), os.path.join(out, "tension.mp4")
    return animation.PillowWriter(fps=10), os.path.join(out, "tension.gif")


def render(run_dir, out=None, every=1, last=False, kind="gif", dpi=100, quiet=False,
           value_range=DEFAULT_RANGE, scene=None, smooth=False):
    """Render the frames of run_dir into out (default RUN_DIR/render); the files written."""
    spec = parse_range(value_range) if isinstance(value_range, str) else value_range
    out = out or os.path.join(run_dir, "render")
    os.makedirs(out, exist_ok=True)
    run = list(frames.read_run(run_dir))
    for _, parts in run if smooth else []:
        c = parts["cloth"]
        c.cell_data["tension_xy"] = smooth_faces(c, c.cell_data["tension_xy"])
    if not run:
        raise SystemExit("sinew render: %s/frames.pvd lists no frames" % run_dir)
    chosen = [len(run) - 1] if last else list(range(0, len(run), every))
    if chosen[-1] != len(run) - 1:
        chosen.append(len(run) - 1)
    norms, t_norm = tension_norms(run, spec), tendon_norm(run)
    sc = Scene(run_dir, scene)
    fig = plt.figure(figsize=(11, 6))
    writer, movie = writer_for("none" if len(chosen) < 2 else kind, out)
    written = []
    if writer:
        writer.setup(fig, movie, dpi=dpi)
    for i in chosen:
        t, parts = run[i]
        draw(fig, t, parts, norms[i], t_norm, sc.name, sc, range_label(spec, smooth))
        png = os.path.join(out, "tension_%06d.png" % i)
        fig.savefig(png, dpi=dpi)
        written.append(png)
        if writer:
            writer.grab_frame()
        if not quiet:
            print("sinew render: %s (t = %g s)" % (png, t), file=sys.stderr)
    if writer:
        writer.finish()
        written.append(movie)
        if not quiet:
            print("sinew render: %s (%d frames)" % (movie, len(chosen)), file=sys.stderr)
    plt.close(fig)
    return written


def shared_norm(clothes, spec):
    """One colour range for several runs' last frames: --range's MIN:MAX, or 0 to the
    percentile of all their free faces pooled."""
    if spec[0] == "fixed":
        return colors.Normalize(spec[1], spec[2])
    top = percentile_top(clothes, spec[1])
    return colors.Normalize(0.0, top if top > 0.0 else 1.0)


def compare(run_dirs, png, titles=None, value_range=DEFAULT_RANGE, dpi=100, smooth=False,
            quiet=False):
    """The last frame of each run side by side at one tension XY colour scale: its 3D shape on
    the body above, its flat pattern below (the scale: --range over all the runs' last frames,
    the percentile of their free faces pooled).  Returns png."""
    spec = parse_range(value_range) if isinstance(value_range, str) else value_range
    titles = list(titles) if titles else [os.path.basename(os.path.normpath(d)) for d in run_dirs]
    if len(titles) != len(run_dirs):
        raise SystemExit("sinew render: --titles gives %d titles for %d runs"
                         % (len(titles), len(run_dirs)))
    lasts = []
    for d in run_dirs:
        run = list(frames.read_run(d))
        if not run:
            raise SystemExit("sinew render: %s/frames.pvd lists no frames" % d)
        t, parts = run[-1]
        c = parts["cloth"]
        if smooth:
            c.cell_data["tension_xy"] = smooth_faces(c, c.cell_data["tension_xy"])
        lasts.append((t, parts, Scene(d)))
    norm = shared_norm([p["cloth"] for _, p, _ in lasts], spec)
    n = len(lasts)
    fig = plt.figure(figsize=(4.2 * n + 0.4, 8.2))
    w = 0.96 / n
    for k, ((t, parts, sc), title) in enumerate(zip(lasts, titles)):
        shape = fig.add_axes([0.02 + k * w, 0.44, w * 0.96, 0.48], projection="3d")
        draw_shape(shape, parts["cloth"], None, norm, None, sc, t)
        shape.set_title("")
        flat = fig.add_axes([0.05 + k * w, 0.12, w * 0.86, 0.26])
        draw_flat(flat, parts["cloth"], None, norm, None, sc)
        flat.set_title("")
        fig.text(0.02 + (k + 0.5) * w, 0.93, "%s\nt = %.2f s" % (title, t), ha="center",
                 va="bottom", fontsize=11)
    over = max(float(p["cloth"].cell_data["tension_xy"].max()) for _, p, _ in lasts) > norm.vmax
    label = range_label(spec, smooth).replace("the last frame", "the runs' last frames")
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap="viridis"), orientation="horizontal",
                 cax=fig.add_axes([0.2, 0.05, 0.6, 0.018]), extend="max" if over else "neither",
                 label=label + ", one scale for all")
    fig.axes[-1].xaxis.label.set_size(9)
    os.makedirs(os.path.dirname(os.path.abspath(png)), exist_ok=True)
    fig.savefig(png, dpi=dpi)
    plt.close(fig)
    if not quiet:
        print("sinew render: %s (%d runs)" % (png, n), file=sys.stderr)
    return png


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="sinew render",
        description="Draw the tension XY map of every frame of a sinew run folder on the flat "
                    "pattern (panels named, grain lines, seams from seams.json) and on the 3D "
                    "shape with the scene's obstacles in grey, tendons with their tension, as "
                    "PNG files, and an animation of the run (headless: matplotlib's Agg "
                    "backend).")
    ap.add_argument("run_dir", metavar="RUN_DIR", nargs="+",
                    help="a run folder (with frames.pvd); several with --compare")
    ap.add_argument("--compare", metavar="FILE.png",
                    help="the last frame of each RUN_DIR side by side at one tension XY scale "
                         "(3D shape above, flat pattern below), into FILE.png")
    ap.add_argument("--titles", metavar="A,B,..",
                    help="--compare: a title per run (default: the folders' names)")
    ap.add_argument("--out", metavar="DIR", help="where the pictures go (default RUN_DIR/render)")
    ap.add_argument("--every", metavar="K", type=int, default=1,
                    help="every K-th frame (and the last; default 1: all)")
    ap.add_argument("--last", action="store_true", help="the last frame only, no animation")
    ap.add_argument("--range", metavar="R", default=DEFAULT_RANGE, dest="value_range",
                    help="the tension XY colour range: MIN:MAX (N/m), or [SCOPE:]pQ, 0 to the "
                         "Q-th percentile of the faces free of pins in the last frame (SCOPE "
                         "last), the whole run (run) or each frame (frame); default "
                         + DEFAULT_RANGE)
    ap.add_argument("--smooth", action="store_true",
                    help="draw tension XY averaged over each vertex's faces (the local mean, "
                         "without the zigzag between neighbouring triangles)")
    ap.add_argument("--scene", metavar="FILE",
                    help="the run's scene file, for its obstacles and panel names (default: "
                         "summary.json's scene_file)")
    ap.add_argument("--animation", choices=("gif", "mp4", "none"), default="gif",
                    help="gif (Pillow, default), mp4 (needs ffmpeg) or none")
    ap.add_argument("--dpi", type=int, default=100, help="dots per inch (default 100: 1100x600)")
    ap.add_argument("--quiet", action="store_true", help="no line per file written")
    a = ap.parse_args(argv)
    if a.every < 1:
        ap.error("--every expects an integer >= 1")
    try:
        spec = parse_range(a.value_range)
    except ValueError as e:
        ap.error(str(e))
    for d in a.run_dir:
        if not os.path.isfile(os.path.join(d, "frames.pvd")):
            ap.error("%s has no frames.pvd (a run with --no-frames?)" % d)
    if a.compare:
        if a.scene or a.out:
            ap.error("--compare takes each run's own scene and writes FILE.png: no --scene, --out")
        titles = a.titles.split(",") if a.titles else None
        if titles and len(titles) != len(a.run_dir):
            ap.error("--titles gives %d titles for %d runs" % (len(titles), len(a.run_dir)))
        compare(a.run_dir, a.compare, titles, spec, a.dpi, a.smooth, a.quiet)
        return 0
    if len(a.run_dir) > 1:
        ap.error("several RUN_DIRs need --compare FILE.png")
    if a.titles:
        ap.error("--titles goes with --compare")
    if a.scene and not os.path.isfile(a.scene):
        ap.error("--scene %s: no such file" % a.scene)
    render(a.run_dir[0], a.out, a.every, a.last, a.animation, a.dpi, a.quiet, spec, a.scene,
           a.smooth)
    return 0


if __name__ == "__main__":
    sys.exit(main())
