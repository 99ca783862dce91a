"""sinew.body: a body of a pattern's size, from its measurements (docs/garments.md, "A body of
the pattern's size").

    m = body.parse("height: 1.68, bust: 0.88, waist: 0.70, hip: 0.95, arm: 0.58, sex: women")
    verts, tris, marks = body.body_mesh(m)      # closed, outward, arms out at 45 degrees
    body.write_obj("body.obj", verts, tris, marks, m)

The construction is the dress form's of tools/make_mannequin.py (which calls this module):
the body from the knees up, the torso a stack of rings and each arm a closed surface of
revolution of its own.  Coordinates: z up, z = 0 the floor the body would stand on, the body's
axis the z axis, its front facing -y, its left side +x; metres.

Each horizontal cross section is an ellipse of half-width a (along x), half-depth b (along y)
and centre (0, c) (c < 0: forward).  At the bust, waist and hip heights (0.72, 0.62 and 0.50 of
the height, standard proportions of an adult) a and b are set so that the ellipse's perimeter is
the stated girth, by Ramanujan's second approximation (S. Ramanujan, "Modular equations and
approximations to pi", 1914)
    P = pi (a + b) (1 + 3h / (10 + sqrt(4 - 3h))),  h = (a - b)^2 / (a + b)^2,
with a depth-to-width ratio b/a typical of each level.  Between the levels a, b and c are
interpolated by monotone cubics (F. N. Fritsch and R. E. Carlson, "Monotone piecewise cubic
interpolation", 1980): smooth, with no overshoot between levels.  The other levels (knee, thigh,
crotch, underbust, armpit, shoulder, neck) scale with the height and the nearby girths; the head
is an ellipsoid.  Below the crotch the section is pinched front and back, so the thighs read as
two legs side by side.

The surface is a stack of rings of `around` vertices at polar angles shared by every ring
(each ring a star-shaped polygon about the z axis) plus a centre vertex closing the flat base
and a pole vertex on the crown: the surface is a graph r(theta, z) over the cylinder, so it is
closed and cannot cross itself.  The rings sit at equal arc length along the side profile, with
a ring exactly at each measurement height; each ring is scaled so that its polygon's perimeter,
not only the ideal ellipse's, is the girth that the ellipse has, so a tape measure around the
mesh at the bust, waist and hip heights reads the stated girths.  Triangles are wound
counter-clockwise seen from outside.  The output is a function of the arguments only."""
import math
from dataclasses import dataclass

import numpy as np

# proportions of the height (adult, standing; rounded from anthropometric tables)
KNEE, THIGH, CROTCH, HIP, WAIST = 0.285, 0.38, 0.455, 0.50, 0.62
UNDERBUST, BUST, ARMPIT, SHOULDER = 0.685, 0.72, 0.75, 0.815
NECK_BASE, NECK_TOP, HEAD_CENTRE = 0.848, 0.875, 0.93
HEAD_JOIN = 0.895             # below: the neck's levels; above: the head's ellipsoid
# Per sex: depth / width ratios b / a of the measured sections, the underbust's girth as a
# fraction of the way from the waist's to the bust's, the shoulder points' and the neck base's
# half-widths (m at REF_HEIGHT).  Stylised proportions that shape the body between the
# measured levels, not measurements: a women's bust standing out above a narrower underbust, a
# men's chest flatter and wider at the shoulders.
SEX = {"women": {"ratio_hip": 0.75, "ratio_waist": 0.73, "ratio_bust": 0.80, "underbust": 0.28,
                 "shoulder": 0.185, "neck": 0.062},
       "men": {"ratio_hip": 0.78, "ratio_waist": 0.80, "ratio_bust": 0.70, "underbust": 0.70,
               "shoulder": 0.205, "neck": 0.068}}
REF_HEIGHT = 1.70             # m: lengths below are for this height and scale with it
HEAD_A, HEAD_B, HEAD_C = 0.075, 0.095, 0.0  # m: head half-width, half-depth, centre offset


def ramanujan(a, b):
    """Ramanujan's second approximation to the perimeter of the ellipse of half-axes a, b."""
    h = ((a - b) / (a + b)) ** 2
    return math.pi * (a + b) * (1.0 + 3.0 * h / (10.0 + math.sqrt(4.0 - 3.0 * h)))


def axes_for_girth(girth, ratio):
    """Half-axes (a, b = ratio a) of the ellipse whose Ramanujan perimeter is girth."""
    return girth / ramanujan(1.0, ratio), ratio * girth / ramanujan(1.0, ratio)


def pchip(x, y):
    """Fritsch-Carlson monotone cubic through (x, y) (x increasing): a function of an array."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    h, delta = np.diff(x), np.diff(y) / np.diff(x)
    d = np.zeros_like(y)
    for k in range(1, len(x) - 1):
        if delta[k - 1] * delta[k] > 0.0:  # weighted harmonic mean keeps it monotone
            w1, w2 = 2.0 * h[k] + h[k - 1], h[k] + 2.0 * h[k - 1]
            d[k] = (w1 + w2) / (w1 / delta[k - 1] + w2 / delta[k])
    d[0], d[-1] = delta[0], delta[-1]

    def f(t):
        t = np.clip(np.asarray(t, float), x[0], x[-1])
        k = np.clip(np.searchsorted(x, t, side="right") - 1, 0, len(x) - 2)
        s = (t - x[k]) / h[k]
        h00, h10 = (1 + 2 * s) * (1 - s) ** 2, s * (1 - s) ** 2
        h01, h11 = s * s * (3 - 2 * s), s * s * (s - 1)
        return h00 * y[k] + h10 * h[k] * d[k] + h01 * y[k + 1] + h11 * h[k] * d[k + 1]
    return f


class Body:
    """The section (a, b, c) of the form at any height z: ellipse half-width a, half-depth b,
    centre (0, c), m; and the pinch depth (fraction of the radius) front and back."""

    def __init__(self, height, bust, waist, hip, sex="women"):
        self.height = height
        s = height / REF_HEIGHT
        p = SEX[sex]
        ha, hb = axes_for_girth(hip, p["ratio_hip"])
        wa, wb = axes_for_girth(waist, p["ratio_waist"])
        ba, bb = axes_for_girth(bust, p["ratio_bust"])
        ua, ub = axes_for_girth(waist + p["underbust"] * (bust - waist), p["ratio_bust"])
        self.head = (HEAD_A * s, HEAD_B * s, HEAD_C * s, HEAD_CENTRE * height,
                     (1.0 - HEAD_CENTRE) * height)
        ja, jb, jc = self.head_section(HEAD_JOIN * height)
        # (z / height, a, b, c): the levels, bottom to top
        levels = [
            (KNEE, 0.82 * ha, 0.46 * hb, 0.0),        # two knees side by side
            (THIGH, 0.88 * ha, 0.62 * hb, 0.0),
            (CROTCH, 0.97 * ha, 0.92 * hb, 0.0),
            (HIP, ha, hb, 0.0),
            (WAIST, wa, wb, -0.005 * s),
            (UNDERBUST, ua, ub, -0.01 * s),
            (BUST, ba, bb, -0.015 * s),
            (ARMPIT, 0.98 * ba, 0.86 * bb, -0.005 * s),
            (SHOULDER, p["shoulder"] * s, 0.075 * s, 0.005 * s),
            (0.835, 0.125 * s, 0.065 * s, 0.005 * s),  # the shoulders' slope to the neck
            (NECK_BASE, p["neck"] * s, 0.058 * s, 0.0),
            (NECK_TOP, 0.053 * s, 0.056 * s, -0.008 * s),
            (HEAD_JOIN, ja, jb, jc),
        ]
        z = [lv[0] * height for lv in levels]
        self.a, self.b, self.c = (pchip(z, [lv[i] for lv in levels]) for i in (1, 2, 3))
        self.bottom = KNEE * height

    def head_section(self, z):
        """The head's ellipsoid cut at height z: (a, b, c)."""
        a, b, c, zc, half = self.head
        t = np.sqrt(np.clip(1.0 - ((np.asarray(z, float) - zc) / half) ** 2, 0.0, None))
        return a * t, b * t, c + 0.0 * t

    def section(self, z):
        z = np.asarray(z, float)
        head = z >= HEAD_JOIN * self.height
        ha, hb, hc = self.head_section(z)
        a = np.where(head, ha, self.a(z))
        b = np.where(head, hb, self.b(z))
        c = np.where(head, hc, self.c(z))
        # the pinch between the legs: 0 at the crotch, growing smoothly to the knee
        t = np.clip((CROTCH * self.height - z) / ((CROTCH - KNEE) * self.height), 0.0, 1.0)
        return a, b, c, 0.35 * t * t * (3 - 2 * t)


def ring_angles(around):
    """Polar angles shared by every ring: equal steps of the parameter of a 4:3 ellipse, so
    that the vertices are closer together where the sections curve more (the sides)."""
    t = 2.0 * np.pi * np.arange(around) / around
    return np.arctan2(0.75 * np.sin(t), np.cos(t))


def ring(a, b, c, pinch, theta):
    """Radius along each polar angle theta of the ellipse (a, b, centre (0, c)), pinched."""
    cs, sn = np.cos(theta), np.sin(theta)
    # |r (cos, sin) - (0, c)| on the ellipse: A r^2 - 2 B r + C = 0
    qa = (cs / a) ** 2 + (sn / b) ** 2
    qb = sn * c / b ** 2
    qc = (c / b) ** 2 - 1.0
    r = (qb + np.sqrt(qb * qb - qa * qc)) / qa
    w = 0.35  # rad: the pinch's width about the front (-y) and the back (+y)
    dip = np.exp(-((theta - np.pi / 2) / w) ** 2) + np.exp(-((theta + np.pi / 2) / w) ** 2)
    return r * (1.0 - pinch * dip)


def polygon_perimeter(r, theta):
    p = np.stack([r * np.cos(theta), r * np.sin(theta)], axis=-1)
    return float(np.sum(np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)))


def ring_heights(body, rings, marks):
    """rings heights from the base to below the crown, at equal arc length along the side
    profile (a(z), b(z), z), each of the heights in marks replacing its nearest ring."""
    z = np.linspace(body.bottom, body.height, 4001)
    a, b, _, _ = body.section(z)
    ds = np.sqrt(np.diff(z) ** 2 + np.diff(a) ** 2 + np.diff(b) ** 2)
    s = np.concatenate([[0.0], np.cumsum(ds)])
    # rings + 1 steps from the base to the crown (the pole vertex, not a ring)
    zr = np.interp(np.linspace(0.0, s[-1], rings + 1)[:-1], s, z)
    for m in marks:
        k = int(np.argmin(np.abs(zr[1:] - m))) + 1  # never the base ring
        zr[k] = m
    if np.any(np.diff(zr) <= 0.0):
        raise BodyError("too few rings to place one at each measurement height")
    return zr


def tube(axis_points, radii, around):
    """A closed surface of revolution: rings of `around` vertices about the polyline
    axis_points (k x 3, straight) with radii (k, the first and last 0: the two poles);
    triangles counter-clockwise seen from outside."""
    d = axis_points[-1] - axis_points[0]
    d /= np.linalg.norm(d)
    e1 = np.cross(d, [0.0, 0.0, 1.0]) if abs(d[2]) < 0.99 else np.array([1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(d, e1)
    phi = 2.0 * np.pi * np.arange(around) / around
    k = len(radii)
    verts = [axis_points[0]]
    for i in range(1, k - 1):
        verts += list(axis_points[i] + radii[i] * (np.cos(phi)[:, None] * e1
                                                   + np.sin(phi)[:, None] * e2))
    verts.append(axis_points[-1])
    tris, last = [], 1 + (k - 3) * around
    for j in range(around):
        jn = (j + 1) % around
        tris.append((0, 1 + jn, 1 + j))
        tris.append((last + j, last + jn, len(verts) - 1))
        for i in range(k - 3):
            p, q = 1 + i * around + j, 1 + i * around + jn
            tris += [(p, q, q + around), (p, q + around, p + around)]
    return np.array(verts), np.array(tris)


# the arm from the shoulder (s = 0, the top of its cap) to the fingertips: (s, radius) as
# fractions of the height; upper arm, elbow, forearm, wrist, hand
ARM = [(0.0, 0.0), (0.012, 0.020), (0.03, 0.029), (0.08, 0.028), (0.17, 0.022), (0.21, 0.024),
       (0.30, 0.016), (0.33, 0.018), (0.37, 0.014), (0.385, 0.008), (0.39, 0.0)]
WRIST = 0.30     # the wrist (the forearm's narrowest ring) at this fraction of the height
ARM_ANGLE = {"down": 6.0, "out": 45.0}  # degrees from the vertical, at least
ARM_GAP = 0.005  # m: the smallest clearance between an arm and the torso


def inside_torso(body, points, clearance):
    """Which points lie within `clearance` (m) outside the torso's surface, or inside it:
    the radius from the z axis against the section's radius along that polar angle."""
    a, b, c, pinch = body.section(points[:, 2])
    theta = np.arctan2(points[:, 1], points[:, 0])
    r = np.array([ring(ai, bi, ci, pi, np.array([t]))[0]
                  for ai, bi, ci, pi, t in zip(a, b, c, pinch, theta)])
    inside = np.hypot(points[:, 0], points[:, 1]) < r + clearance
    return inside & (points[:, 2] >= body.bottom) & (points[:, 2] <= body.height)


def arm(body, side, pose, around, length=None):
    """One arm (side +1: left, +x; -1: right): its cap's top at shoulder height, tucked under
    the shoulder as close to the side of the chest as it goes, at the pose's angle from the
    vertical, turned further out while it would come closer than ARM_GAP to the torso."""
    h = body.height
    s = np.array([p[0] for p in ARM]) * h
    if length is not None:  # the cap's top to the wrist stretched to length, the hand kept
        s = np.where(s <= WRIST * h, s * (length / (WRIST * h)), s - WRIST * h + length)
    r = np.array([p[1] for p in ARM]) * h
    upper = r[2]  # m: the upper arm's radius
    inner = float(body.a(ARMPIT * h)) + upper + ARM_GAP    # axis beside the chest
    outer = float(body.a(SHOULDER * h)) + upper + ARM_GAP  # axis beyond the shoulder point
    for angle in np.arange(ARM_ANGLE[pose], 90.0, 1.0):
        a = np.radians(angle)
        d = np.array([side * np.sin(a), 0.0, -np.cos(a)])
        for x in np.arange(inner, outer + 1e-3, 2e-3):
            start = np.array([side * x, 0.0, SHOULDER * h - 0.3 * upper])
            verts, tris = tube(start[None, :] + s[:, None] * d, r, around)
            if not inside_torso(body, verts, ARM_GAP).any():
                return verts, tris
    raise BodyError("no arm angle clears the torso: arms of radius %.3g m beside a chest of "
                    "half-width %.3g m" % (upper, float(body.a(ARMPIT * h))))


def mannequin(height, bust, waist, hip, around, rings, arms="none", sex="women",
              arm_length=None):
    """Vertices (n x 3, m) and triangles (counter-clockwise seen from outside) of the form:
    the torso's rings (the first around * rings + 2 vertices), then each arm's."""
    body = Body(height, bust, waist, hip, sex)
    theta = ring_angles(around)
    zr = ring_heights(body, rings, [HIP * height, WAIST * height, BUST * height])
    verts = []
    for z in zr:
        a, b, c, pinch = (float(v) for v in body.section(z))
        r = ring(a, b, c, pinch, theta)
        # the polygon has the ellipse's perimeter (a pinched ring keeps the same scale rule)
        r *= ramanujan(a, b) / polygon_perimeter(ring(a, b, c, 0.0, theta), theta)
        verts += [(ri * math.cos(t), ri * math.sin(t), z) for ri, t in zip(r, theta)]
    base, crown = len(verts), len(verts) + 1
    verts += [(0.0, 0.0, zr[0]), (0.0, body.head[2], height)]
    tris = []
    for i in range(len(zr) - 1):
        for j in range(around):
            p, q = i * around + j, i * around + (j + 1) % around
            tris += [(p, q, q + around), (p, q + around, p + around)]
    top = (len(zr) - 1) * around
    for j in range(around):
        tris.append((base, (j + 1) % around, j))
        tris.append((top + j, top + (j + 1) % around, crown))
    verts, tris = np.array(verts), np.array(tris)
    if arms != "none":
        for side in (1, -1):
            v, t = arm(body, side, arms, max(8, around // 2), arm_length)
            tris = np.concatenate([tris, t + len(verts)])
            verts = np.concatenate([verts, v])
    return verts, tris, zr



class BodyError(ValueError):
    """Measurements that do not make a body, with a message naming what and where."""


KEYS = ("height", "bust", "waist", "hip", "arm", "sex")


@dataclass
class Measurements:
    """A body's measurements, m: standing height; bust (women's) or chest (men's) girth at its
    fullest, under the arms; natural waist girth; hip girth at the seat's fullest; arm length
    from the shoulder point over the elbow to the wrist; sex 'women' or 'men'."""
    height: float
    bust: float
    waist: float
    hip: float
    arm: float
    sex: str = "women"

    def text(self):
        return "height: %g, bust: %g, waist: %g, hip: %g, arm: %g, sex: %s" % (
            self.height, self.bust, self.waist, self.hip, self.arm, self.sex)


def check(m, where="body"):
    """BodyError (prefixed by where) unless the measurements make a body: numbers in range and
    proportions an adult can have.  Returns m."""
    for k in ("height", "bust", "waist", "hip", "arm"):
        v = getattr(m, k)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                or v <= 0:
            raise BodyError("%s: %s %r: expected a positive length in m" % (where, k, v))
    if m.sex not in SEX:
        raise BodyError("%s: sex %r: expected women or men" % (where, m.sex))
    if not 1.0 <= m.height <= 2.5:
        raise BodyError("%s: height %g m: expected 1.0 to 2.5 m" % (where, m.height))
    for k in ("bust", "waist", "hip"):
        g = getattr(m, k)
        if not 0.25 * m.height <= g <= 1.0 * m.height:
            raise BodyError("%s: %s %g m: expected between 0.25 and 1.0 times the height "
                            "(%g to %g m)" % (where, k, g, 0.25 * m.height, m.height))
    if m.waist > 1.15 * min(m.bust, m.hip):
        raise BodyError("%s: waist %g m against bust %g m and hip %g m: expected the waist at "
                        "most 1.15 times the smaller" % (where, m.waist, m.bust, m.hip))
    if m.bust > 1.6 * m.waist or m.hip > 1.8 * m.waist:
        raise BodyError("%s: bust %g m, waist %g m, hip %g m: expected the bust at most 1.6 and "
                        "the hip at most 1.8 times the waist" % (where, m.bust, m.waist, m.hip))
    if not 0.25 * m.height <= m.arm <= 0.45 * m.height:
        raise BodyError("%s: arm %g m: expected the shoulder point to the wrist between 0.25 "
                        "and 0.45 times the height (%g to %g m)"
                        % (where, m.arm, 0.25 * m.height, 0.45 * m.height))
    return m


def from_mapping(d, where="body"):
    """Measurements from a mapping of KEYS (chest is the bust's other name): BodyError naming
    a missing or unknown key."""
    if not isinstance(d, dict):
        raise BodyError("%s: expected a mapping of %s" % (where, ", ".join(KEYS)))
    d = dict(d)
    if "chest" in d:
        if "bust" in d:
            raise BodyError("%s: both bust and chest: give one" % where)
        d["bust"] = d.pop("chest")
    unknown = sorted(set(map(str, d)) - set(KEYS) - {"size"})
    if unknown:
        raise BodyError("%s: unknown key %s; expected %s" % (where, ", ".join(unknown),
                                                             ", ".join(KEYS)))
    missing = [k for k in KEYS if k not in d]
    if missing:
        raise BodyError("%s: missing %s (of %s)" % (where, ", ".join(missing), ", ".join(KEYS)))
    return check(Measurements(*(d[k] for k in KEYS[:5]), str(d["sex"])), where)


def parse(text, where="--body"):
    """Measurements from 'height: 1.68, bust: 0.88, ...' (a YAML flow mapping, braces
    optional)."""
    import yaml
    t = text.strip()
    try:
        d = yaml.safe_load(t if t.startswith("{") else "{" + t + "}")
    except yaml.YAMLError as e:
        raise BodyError("%s %r: not a mapping 'height: M, bust: M, ...': %s"
                        % (where, text, str(e).splitlines()[0])) from None
    return from_mapping(d, where)


def read_table(path):
    """{size: Measurements} from a size table: CSV (a header row naming size and KEYS, then one
    row a size; commas, no quoting) or YAML (a mapping from size to a mapping of KEYS).
    BodyError naming the file, line and column of what is wrong."""
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise BodyError("--body-table %s: %s" % (path, e.strerror)) from None
    if path.lower().endswith(".csv"):
        return _csv_table(path, text)
    if path.lower().endswith((".yaml", ".yml")):
        return _yaml_table(path, text)
    raise BodyError("--body-table %s: expected a .csv or .yaml file" % path)


def _csv_table(path, text):
    rows = [(n + 1, line) for n, line in enumerate(text.splitlines())
            if line.strip() and not line.lstrip().startswith("#")]
    if not rows:
        raise BodyError("%s: empty; expected a header row: size,%s" % (path, ",".join(KEYS)))
    ln, head = rows[0]
    names = [c.strip() for c in head.split(",")]
    want = ["size"] + list(KEYS)
    if sorted(names) != sorted(want):
        raise BodyError("%s:%d:1: header %s; expected the columns %s (any order)"
                        % (path, ln, ",".join(names), ",".join(want)))
    out = {}
    for ln, line in rows[1:]:
        cells, col, d = line.split(","), 1, {}
        if len(cells) != len(names):
            raise BodyError("%s:%d:1: %d fields; expected %d (%s)"
                            % (path, ln, len(cells), len(names), ",".join(names)))
        for name, cell in zip(names, cells):
            v = cell.strip()
            if name not in ("size", "sex"):
                try:
                    v = float(v)
                except ValueError:
                    raise BodyError("%s:%d:%d: %s %r: expected a length in m"
                                    % (path, ln, col, name, v)) from None
            d[name] = v
            col += len(cell) + 1
        _add(out, d["size"], d, "%s:%d:1: size %s" % (path, ln, d["size"]))
    return out


def _yaml_table(path, text):
    import yaml
    try:
        root = yaml.compose(text)
    except yaml.YAMLError as e:
        raise BodyError("%s: not YAML: %s" % (path, e)) from None
    if not isinstance(root, yaml.MappingNode):
        raise BodyError("%s:1:1: expected a mapping from each size to its measurements" % path)
    out = {}
    for k, v in root.value:
        mark = k.start_mark
        where = "%s:%d:%d: size %s" % (path, mark.line + 1, mark.column + 1, k.value)
        _add(out, k.value, yaml.safe_load(yaml.serialize(v)), where)
    return out


def _add(out, size, d, where):
    if size in out:
        raise BodyError("%s: given twice" % where)
    out[size] = from_mapping(d, where)


def _on_mesh(verts, zr, around, k, z):
    """The point of the torso's mesh at height z on its k-th polar angle (an edge between two
    rings: the mesh's own surface)."""
    i = int(np.clip(np.searchsorted(zr, z) - 1, 0, len(zr) - 2))
    p, q = verts[i * around + k], verts[(i + 1) * around + k]
    t = (z - p[2]) / (q[2] - p[2])
    return p + t * (q - p)


def body_mesh(m, around=32, rings=30):
    """(verts, tris, landmarks) of a body with its arms out (45 degrees, or further to clear
    the torso) for Measurements m (checked).  landmarks: {name: (x, y, z)} of points on the
    torso's mesh (front_bust, back_bust, front_waist, back_waist: the centre front and back at
    those heights; left_shoulder, right_shoulder: the shoulder points, the torso's outermost
    points at the shoulder's height) and of the axes (neck_base: the centre of the neck's base
    section; left_arm, right_arm: the top of each arm's cap, on its axis), and
    left_arm_direction, right_arm_direction (unit, towards the fingertips), left_arm_length,
    right_arm_length (the cap's top to the fingertips, m)."""
    check(m)
    if around % 4:
        raise BodyError("around %d: expected a multiple of 4 (vertices at the centre front, "
                        "back and sides)" % around)
    h = m.height
    verts, tris, zr = mannequin(h, m.bust, m.waist, m.hip, around, rings, "out", m.sex, m.arm)
    theta = ring_angles(around)
    k_of = {name: int(np.argmin(np.abs(np.angle(np.exp(1j * (theta - t))))))
            for name, t in (("left", 0.0), ("back", np.pi / 2), ("right", np.pi),
                            ("front", -np.pi / 2))}
    marks = {}
    for level, frac in (("bust", BUST), ("waist", WAIST)):
        for side in ("front", "back"):
            marks["%s_%s" % (side, level)] = _on_mesh(verts, zr, around, k_of[side], frac * h)
    for side in ("left", "right"):
        marks[side + "_shoulder"] = _on_mesh(verts, zr, around, k_of[side], SHOULDER * h)
    body = Body(h, m.bust, m.waist, m.hip, m.sex)
    marks["neck_base"] = np.array([0.0, float(body.c(NECK_BASE * h)), NECK_BASE * h])
    torso = len(zr) * around + 2
    n = (len(verts) - torso) // 2
    for side, k in (("left", torso), ("right", torso + n)):
        top, tip = verts[k], verts[k + n - 1]
        marks[side + "_arm"] = top
        marks[side + "_arm_direction"] = (tip - top) / np.linalg.norm(tip - top)
        marks[side + "_arm_length"] = float(np.linalg.norm(tip - top))
    return verts, tris, {k: (tuple(float(x) for x in v) if not isinstance(v, float) else v)
                         for k, v in marks.items()}


def obj_text(verts, tris, marks, m):
    """The body's OBJ: a header with its measurements and landmarks (read_landmarks reads
    them back), then its vertices and triangles."""
    out = ["# body: sinew.body, %s" % m.text(),
           "# %d vertices, %d triangles; z up, z = 0 the floor, front -y, metres; girths at "
           "z = %.4g (hip), %.4g (waist), %.4g (bust)"
           % (len(verts), len(tris), HIP * m.height, WAIST * m.height, BUST * m.height)]
    for k, v in marks.items():
        out.append("# landmark %s %s" % (k, " ".join("%.17g" % x for x in np.atleast_1d(v))))
    out += ["v %.9g %.9g %.9g" % tuple(v) for v in verts]
    out += ["f %d %d %d" % (t[0] + 1, t[1] + 1, t[2] + 1) for t in tris]
    return "\n".join(out) + "\n"


def read_landmarks(path):
    """{name: tuple or float} from the '# landmark' lines of an OBJ obj_text wrote."""
    marks = {}
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            s = line.split()
            if len(s) > 3 and s[1] == "landmark":
                v = tuple(float(x) for x in s[3:])
                marks[s[2]] = v[0] if len(v) == 1 else v
    return marks
