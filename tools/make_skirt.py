#!/usr/bin/python3
"""make_skirt.py — the OBJ of a two-panel skirt for scenes/skirt.yaml and
scenes/garment_drawstring.yaml.

    /usr/bin/python3 tools/make_skirt.py [--columns N] [--rows M] [--waist R0] [--hem R1]
                                         [--length H] [--pattern trapezoid|developed]
                                         [-o scenes/meshes/skirt.obj]

A truncated cone (waist radius R0 at z = 0, hem radius R1 at z = -H, m) cut into a front and a
back panel along two side seams (angles 0 and pi).  Each panel is N x M quads of its own flat
(u,v) pattern in metres:
  trapezoid (the default, scenes/meshes/skirt.obj): rows of the cone's half-circumference at
    that height, straight, and columns down the slant.  It is not the cone's development: the
    slanted columns meet the rows at an angle where the cone's meridians meet its circles at a
    right angle, so the sewn skirt starts strained (scenes/skirt.yaml at t = 0: warp or weft
    stretched by up to 25 %, shear angles up to 0.44 rad) and springs at t = 0.
  developed (scenes/meshes/skirt_developed.obj): the half-cone unrolled, an annular sector of
    radii rho0 = R0 L/(R1 - R0) and rho0 + L (L the slant length) and angle pi (R1 - R0)/L,
    the straight grain (u) along the tangent at the panel's centre.  The skirt then starts at
    its rest shape up to the chords of the mesh (a cylinder, R1 = R0, unrolls to a rectangle).
The panels are sewn
the way garments are: the seam vertices are shared positions (one `v` each), and each panel
has its own `vt` there.  Groups: `usemtl front` and `usemtl back` (scene `panels:` keys).
The waist ring is the vertices at z = 0 (pin them with a box selection)."""
import argparse
import math


def pattern_uv(a, s, r0, r1, slant, developed):
    """(u, v) in metres of the point at fraction a in [0, 1] across a panel (its half circle)
    and s in [0, 1] down the slant."""
    if not developed:
        width = math.pi * (r0 + s * (r1 - r0))  # half circumference at this height, m
        return ((a - 0.5) * width, -s * slant)
    if r1 - r0 <= 1e-12 * slant:  # a cylinder: a rectangle
        return ((a - 0.5) * math.pi * r0, -s * slant)
    rho0 = r0 * slant / (r1 - r0)  # apex to waist along the slant, m
    rho = rho0 + s * slant
    phi = (a - 0.5) * math.pi * (r1 - r0) / slant  # the sector's angle from the centre line
    return (rho * math.sin(phi), rho0 - rho * math.cos(phi))


def skirt(n, m, r0, r1, h, developed=False):
    slant = math.hypot(h, r1 - r0)  # m
    # positions: 2n columns around the circle (column 0 at angle 0), m + 1 rows down
    pos = []
    for j in range(m + 1):
        s = j / m
        r, z = r0 + s * (r1 - r0), -s * h
        for i in range(2 * n):
            a = math.pi * i / n
            pos.append((r * math.cos(a), r * math.sin(a), z))

    def vid(i, j):  # 1-based position index; column 2n is column 0 again (the seam)
        return j * 2 * n + (i % (2 * n)) + 1

    uvs, faces = [], {"front": [], "back": []}
    for p, panel in enumerate(("front", "back")):
        base = len(uvs)
        for j in range(m + 1):
            for i in range(n + 1):
                uvs.append(pattern_uv(i / n, j / m, r0, r1, slant, developed))
        for j in range(m):
            for i in range(n):
                c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
                faces[panel].append([(vid(p * n + a, b), base + b * (n + 1) + a + 1) for a, b in c])
    return pos, uvs, faces


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--columns", type=int, default=16, help="quads across each panel")
    ap.add_argument("--rows", type=int, default=12, help="quads from waist to hem")
    ap.add_argument("--waist", type=float, default=0.15, help="waist radius, m")
    ap.add_argument("--hem", type=float, default=0.35, help="hem radius, m")
    ap.add_argument("--length", type=float, default=0.6, help="waist to hem, m")
    ap.add_argument("--pattern", choices=("trapezoid", "developed"), default="trapezoid",
                    help="each panel's (u,v) layout (see the head of this file)")
    ap.add_argument("-o", "--output", default="scenes/meshes/skirt.obj")
    a = ap.parse_args()
    if a.columns < 1 or a.rows < 1 or not (0 < a.waist <= a.hem) or a.length <= 0:
        ap.error("need columns, rows >= 1 and 0 < waist <= hem, length > 0")
    pos, uvs, faces = skirt(a.columns, a.rows, a.waist, a.hem, a.length,
                            a.pattern == "developed")
    with open(a.output, "w") as f:
        f.write("# two-panel skirt: tools/make_skirt.py --columns %d --rows %d --waist %g "
                "--hem %g --length %g%s\n" % (a.columns, a.rows, a.waist, a.hem, a.length,
                                             " --pattern developed" if a.pattern == "developed"
                                             else ""))
        for p in pos:
            f.write("v %.9g %.9g %.9g\n" % p)
        for t in uvs:
            f.write("vt %.9g %.9g\n" % t)
        for panel in ("front", "back"):
            f.write("usemtl %s\n" % panel)
            for q in faces[panel]:
                f.write("f " + " ".join("%d/%d" % c for c in q) + "\n")


if __name__ == "__main__":
    main()
