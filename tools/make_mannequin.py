#!/usr/bin/python3
"""make_mannequin.py — the OBJ of a dress form (a tailor's mannequin) from a few body
measurements, for mesh obstacles that garments are fitted on:

    /usr/bin/python3 tools/make_mannequin.py [--height 1.70] [--bust 0.88] [--waist 0.70]
        [--hip 0.96] [--around 32] [--rings 30] [--arms none|down|out]
        [-o scenes/meshes/mannequin.obj]

All lengths in metres.  The form is the body from the knees up: the two thighs together as one
piece (as on a dress form with legs to the knee), hips, waist, bust, shoulders, neck and head;
with --arms, two arms as separate closed surfaces (surfaces of revolution about a straight
axis, from a rounded shoulder cap to the fingertips), hung just under the shoulder points at
6 degrees from the vertical (down) or 45 degrees (out), turned further out and moved outward
until they clear the torso by 5 mm: the mesh is then three closed surfaces that do not touch.
Coordinates: z up, z = 0 the floor the body would stand on (the form's flat base is at knee
height, 0.285 of the height), the body's axis is the z axis, its front faces -y, its left side
+x.

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

The surface is a stack of rings of `--around` vertices at polar angles shared by every ring
(each ring a star-shaped polygon about the z axis) plus a centre vertex closing the flat base
and a pole vertex on the crown: the surface is a graph r(theta, z) over the cylinder, so it is
closed and cannot cross itself.  The rings sit at equal arc length along the side profile, with
a ring exactly at each measurement height; each ring is scaled so that its polygon's perimeter,
not only the ideal ellipse's, is the girth that the ellipse has, so a tape measure around the
mesh at the bust, waist and hip heights reads the stated girths.  Triangles are wound
counter-clockwise seen from outside.  The output is a function of the arguments only: the same
command, the same file."""
import argparse
import math
import sys

import numpy as np

# proportions of the height (adult, standing; rounded from anthropometric tables)
KNEE, THIGH, CROTCH, HIP, WAIST = 0.285, 0.38, 0.455, 0.50, 0.62
UNDERBUST, BUST, ARMPIT, SHOULDER = 0.685, 0.72, 0.75, 0.815
NECK_BASE, NECK_TOP, HEAD_CENTRE = 0.848, 0.875, 0.93
HEAD_JOIN = 0.895             # below: the neck's levels; above: the head's ellipsoid
# depth / width ratios b / a of the measured sections
RATIO_HIP, RATIO_WAIST, RATIO_BUST = 0.75, 0.73, 0.80
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

    def __init__(self, height, bust, waist, hip):
        self.height = height
        s = height / REF_HEIGHT
        ha, hb = axes_for_girth(hip, RATIO_HIP)
        wa, wb = axes_for_girth(waist, RATIO_WAIST)
        ba, bb = axes_for_girth(bust, RATIO_BUST)
        ua, ub = axes_for_girth(waist + 0.28 * (bust - waist), RATIO_BUST)   # underbust
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
            (SHOULDER, 0.185 * s, 0.075 * s, 0.005 * s),
            (0.835, 0.125 * s, 0.065 * s, 0.005 * s),  # the shoulders' slope to the neck
            (NECK_BASE, 0.062 * s, 0.058 * s, 0.0),
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
        sys.exit("make_mannequin: too few rings to place one at each measurement height")
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


def arm(body, side, pose, around):
    """One arm (side +1: left, +x; -1: right): its cap's top at shoulder height, tucked under
    the shoulder as close to the side of the chest as it goes, at the pose's angle from the
    vertical, turned further out while it would come closer than ARM_GAP to the torso."""
    h = body.height
    s = np.array([p[0] for p in ARM]) * h
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
    sys.exit("make_mannequin: no arm angle clears the torso")


def mannequin(height, bust, waist, hip, around, rings, arms="none"):
    """Vertices (n x 3, m) and triangles (counter-clockwise seen from outside) of the form:
    the torso's rings (the first around * rings + 2 vertices), then each arm's."""
    body = Body(height, bust, waist, hip)
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
            v, t = arm(body, side, arms, max(8, around // 2))
            tris = np.concatenate([tris, t + len(verts)])
            verts = np.concatenate([verts, v])
    return verts, tris, zr


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--height", type=float, default=1.70, help="standing height, m")
    ap.add_argument("--bust", type=float, default=0.88, help="bust girth, m")
    ap.add_argument("--waist", type=float, default=0.70, help="waist girth, m")
    ap.add_argument("--hip", type=float, default=0.96, help="hip girth, m")
    ap.add_argument("--around", type=int, default=32, help="vertices around each ring (>= 8)")
    ap.add_argument("--rings", type=int, default=30, help="rings from base to crown (>= 12)")
    ap.add_argument("--arms", choices=("none", "down", "out"), default="none",
                    help="no arms (a dress form), arms hanging down, or out at 45 degrees")
    ap.add_argument("-o", "--output", default="scenes/meshes/mannequin.obj")
    args = ap.parse_args(argv)
    if not (1.0 <= args.height <= 2.5):
        ap.error("--height %g: expected 1.0 to 2.5 m" % args.height)
    for name in ("bust", "waist", "hip"):
        g = getattr(args, name)
        if not (0.25 * args.height <= g <= 1.0 * args.height):
            ap.error("--%s %g: expected between 0.25 and 1.0 times the height" % (name, g))
    if args.around < 8 or args.rings < 12:
        ap.error("--around must be >= 8 and --rings >= 12")
    verts, tris, zr = mannequin(args.height, args.bust, args.waist, args.hip,
                                args.around, args.rings, args.arms)
    cmd = "tools/make_mannequin.py --height %g --bust %g --waist %g --hip %g --around %d " \
          "--rings %d --arms %s" % (args.height, args.bust, args.waist, args.hip, args.around,
                                    args.rings, args.arms)
    with open(args.output, "w") as f:
        f.write("# dress form: /usr/bin/python3 %s\n" % cmd)
        f.write("# %d vertices, %d triangles; z up, z = 0 the floor, front -y, metres; girths at "
                "z = %.4g (hip), %.4g (waist), %.4g (bust)\n"
                % (len(verts), len(tris), HIP * args.height, WAIST * args.height,
                   BUST * args.height))
        if args.arms != "none":  # each arm's first vertex is its cap's top, its last the fingertips
            torso = len(zr) * args.around + 2
            n = (len(verts) - torso) // 2
            for name, k in (("left", torso), ("right", torso + n)):
                top, tip = verts[k], verts[k + n - 1]
                d = (tip - top) / np.linalg.norm(tip - top)
                f.write("# %s arm: axis from the cap's top (%.6f, %.6f, %.6f) towards the "
                        "fingertips (%.6f, %.6f, %.6f), %.4g m long\n"
                        % ((name,) + tuple(top) + tuple(d) + (np.linalg.norm(tip - top),)))
        for v in verts:
            f.write("v %.9g %.9g %.9g\n" % tuple(v))
        for t in tris:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


if __name__ == "__main__":
    main()
