#!/usr/bin/python3
"""make_garment.py — flat pattern pieces (and a simple body) as OBJ files for garment scenes.

    /usr/bin/python3 tools/make_garment.py skirt [--waist 0.70] [--hip 1.00] [--hem 1.10]
        [--ease -0.07] [--waist-ease -0.03] [--hip-depth 0.17] [--length 0.55]
        [--columns 8] [--rows 20] [-o scenes/meshes/garment_skirt.obj]
        [--dxf scenes/patterns/garment_skirt.dxf]
    /usr/bin/python3 tools/make_garment.py tank [--bust 0.88] [--ease -0.07] [--length 0.275]
        [--strap-length 0.185] [--strap-width 0.05] [--strap-at 0.11] [--columns 16]
        [--rows 10] [--strap-columns 5] [--strap-rows 8] [-o scenes/meshes/garment_tank.obj]
        [--dxf garment_tank.dxf]
    /usr/bin/python3 tools/make_garment.py tshirt [--bust 0.88] [--ease -0.03] [--length 0.30]
        [--strap-length 0.20] [--strap-width 0.10] [--strap-at 0.115] [--columns 16] [--rows 10]
        [--strap-columns 5] [--strap-rows 8] [--sleeve-width 0.36] [--sleeve-length 0.12]
        [--sleeve-columns 12] [--sleeve-rows 8] [-o scenes/meshes/garment_tshirt.obj]
        [--dxf scenes/patterns/garment_tshirt.dxf]
    /usr/bin/python3 tools/make_garment.py tube [--width 0.3] [--height 0.2] [--columns 6]
        [--rows 4] [-o tests/data/tube_pieces.obj]
    /usr/bin/python3 tools/make_garment.py body [--waist 0.70] [--hip 1.00] [--bust 0.90]
        [--height 1.70] [--around 24] [--rows 20] [-o scenes/meshes/body_revolution.obj]
    /usr/bin/python3 tools/make_garment.py cylinder [--radius 0.08] [--height 0.4]
        [--around 16] [--rows 5] [-o tests/data/cylinder.obj]

Pieces (skirt, tank, tshirt, tube) are separate flat panels: each its own vertices (`v` at the flat layout,
z = 0, laid side by side), its own per-corner (u,v) in metres (`vt`, u across, v up) and its
own group (`usemtl NAME`); the scene sews them with `seams` and places them with `arrange`
(docs/garments.md).  Each piece is a grid of quads (the tank's with the neckline cut out); its
corners are printed as a comment at the head of the file (0-based vertex indices, as the
scene's `seams` take them) and on stdout as the scene's `seams:` list.  With --dxf, skirt,
tank and tshirt write the pattern instead as a DXF file as a pattern CAD system exports it (ASTM
D6673; the same bytes for the same command), for `sinew pattern import` (docs/garments.md, "A
skirt from its DXF pattern", "A T-shirt from its DXF pattern").

skirt: four quarter panels (back_left, back_right, front_right, front_left, in that order
anticlockwise seen from above), sewn at the centre back, the right side, the centre front and
the left side.  A quarter panel's width at depth y below the waist is a quarter of the girth
  waist (1 + waist-ease) at the waist, hip (1 + ease) at hip-depth, then straight to hem at
  length,
with a smooth hip curve (a quarter sine) between waist and hip: a negative ease cuts the
pattern smaller than the body (a tight fit), e.g. -0.07 = 7 % smaller at the hips.

tank: a tank top's front and back, the same pattern: a body of width bust (1 + ease) / 2
(ease -0.07: 7 % smaller than the body at the bust) from the armpit line down `length` to the
hem, columns x rows quads, and two straps from the armpit line up `strap-length` to the
shoulder seam, each strap-columns x strap-rows quads: at the armpit line a strap is the body's
outer strap-columns columns, at the shoulder seam it is strap-width wide centred strap-at from
the piece's centre line; its neckline edge is straight, its armhole edge a parabola, steepest
at the armpit.  Sewn at the two shoulders (the straps' tops) and the two sides (armpit to hem),
the front facing -y and the back +y.

tshirt: a T-shirt's front and back (the tank's pattern with the straps as wide shoulders,
strap-width the shoulder seam's length) and two short sleeves: each sleeve-width round at the
foot of its cap and sleeve-length from there to the hem, sleeve-columns x sleeve-rows quads, its
cap a bell v = h cos^2(pi u / sleeve-width) with h solved so that each half of the cap is as
long as one armhole (the strap's outer edge, armpit to shoulder point).  Sewn at the shoulders,
the sides, the armholes (a sleeve's cap half that faces the front to the front's armhole, the
other to the back's) and each sleeve's underarm; the sleeves are wrapped about the arms
(scenes/garment_tshirt.yaml).

tube: two rectangles (front, back) of width x height, sewn along both sides into a tube.

body: a closed body of revolution about the z axis (a stand-in mannequin from the knees to the
neck): girths at the knee, hip, waist, bust and shoulder heights of a figure of the given
height (proportions of a standard dress form), joined by a smooth monotone profile, `around`
vertices per ring, `rows` rings, and a pole at each end.  cylinder: the same with one radius
(a test body)."""
import argparse
import math


def grid_piece(width_at, height, nx, ny):
    """(u, v) of a piece's (nx + 1) x (ny + 1) vertices, row j = 0 at the top (v = 0) down to
    v = -height; width_at(y) the width at depth y >= 0, centred on u = 0."""
    uv = []
    for j in range(ny + 1):
        y = height * j / ny
        w = width_at(y)
        for i in range(nx + 1):
            uv.append(((i / nx - 0.5) * w, -y))
    return uv


def quads(base, nx, ny):
    """The quads of a piece whose vertex (i, j) is base + j (nx + 1) + i (0-based), corners
    anticlockwise in (u,v)."""
    q = []
    for j in range(ny):
        for i in range(nx):
            a = base + j * (nx + 1) + i
            q.append((a + nx + 1, a + nx + 2, a + 1, a))  # (i,j+1) (i+1,j+1) (i+1,j) (i,j)
    return q


def corners(base, nx, ny):
    """0-based indices of a piece's top-left, top-right, bottom-left, bottom-right corners."""
    return {"top_left": base, "top_right": base + nx, "bottom_left": base + ny * (nx + 1),
            "bottom_right": base + ny * (nx + 1) + nx}


def grid(name, uv, nx, ny):
    """A grid piece (the output of grid_piece) as (name, uv, quads, corners), local indices."""
    return name, uv, quads(0, nx, ny), corners(0, nx, ny)


def pieces_obj(path, title, pieces, seams):
    """Write pieces [(name, uv list, quads, named corners)] (indices local to the piece) laid
    side by side in z = 0 with a 5 cm gap; print the `seams:` list of seams
    [(name, (panel, from corner, to corner), (panel, from corner, to corner))]."""
    pos, uvs, groups, info, x0 = [], [], [], [], 0.0
    for name, uv, qs, cs in pieces:
        base = len(pos)
        umin = min(u for u, _ in uv)
        umax = max(u for u, _ in uv)
        for u, v in uv:
            pos.append((x0 + u - umin, v, 0.0))
            uvs.append((u, v))
        x0 += umax - umin + 0.05
        groups.append((name, [tuple(base + k for k in q) for q in qs]))
        info.append((name, {key: base + k for key, k in cs.items()}))
    with open(path, "w") as f:
        f.write("# %s\n" % title)
        for name, c in info:
            f.write("# piece %s corners (0-based): %s\n" % (
                name, ", ".join("%s %d" % kv for kv in c.items())))
        for p in pos:
            f.write("v %.9g %.9g %.9g\n" % p)
        for t in uvs:
            f.write("vt %.9g %.9g\n" % t)
        for name, qs in groups:
            f.write("usemtl %s\n" % name)
            for q in qs:
                f.write("f " + " ".join("%d/%d" % (k + 1, k + 1) for k in q) + "\n")
    c = dict(info)
    print("seams:")
    for name, (pa, fa, ta), (pb, fb, tb) in seams:
        print("  - {name: %s, a: {panel: %s, from: %d, to: %d}, b: {panel: %s, from: %d, to: %d}}"
              % (name, pa, c[pa][fa], c[pa][ta], pb, c[pb][fb], c[pb][tb]))


def side_seam(name, a, ea, b, eb):
    """A seam from the top to the bottom of edge ea ("left", "right") of piece a and eb of b."""
    return name, (a, "top_" + ea, "bottom_" + ea), (b, "top_" + eb, "bottom_" + eb)


def skirt(a):
    wq, hq, mq = (a.waist * (1 + a.waist_ease) / 4, a.hip * (1 + a.ease) / 4, a.hem / 4)

    def width(y):
        if y <= a.hip_depth:  # the hip curve: a quarter sine from waist to hip
            return wq + (hq - wq) * math.sin(0.5 * math.pi * y / a.hip_depth)
        return hq + (mq - hq) * (y - a.hip_depth) / (a.length - a.hip_depth)

    if a.dxf:
        return skirt_dxf(a, width)
    names = ["back_left", "back_right", "front_right", "front_left"]
    pieces = [grid(n, grid_piece(width, a.length, a.columns, a.rows), a.columns, a.rows)
              for n in names]
    seams = [side_seam("centre_back", "back_left", "right", "back_right", "left"),
             side_seam("right_side", "back_right", "right", "front_right", "left"),
             side_seam("centre_front", "front_right", "right", "front_left", "left"),
             side_seam("left_side", "front_left", "right", "back_left", "left")]
    title = ("four-panel skirt: tools/make_garment.py skirt --waist %g --hip %g --hem %g --ease %g "
             "--waist-ease %g --hip-depth %g --length %g --columns %d --rows %d"
             % (a.waist, a.hip, a.hem, a.ease, a.waist_ease, a.hip_depth, a.length, a.columns,
                a.rows))
    pieces_obj(a.output, title, pieces, seams)


def dxf_document():
    """A new DXF document as a pattern CAD system exports one (R2000, millimetres), its
    metadata fixed so that the same command writes the same bytes."""
    import ezdxf  # Debian's python3-ezdxf; only the DXF outputs need it

    ezdxf.options.write_fixed_meta_data_for_testing = True
    doc = ezdxf.new("R2000")
    doc.header["$INSUNITS"] = 4
    return doc


def dxf_save(doc, path, what):
    for var in ("$TDCREATE", "$TDUPDATE"):  # a fixed date: 2026-01-01 (Julian day)
        doc.header[var] = 2461041.5
    doc.saveas(path)
    print("wrote %s: %s, mm" % (path, what))


def skirt_dxf(a, width):
    """The skirt's pattern as a pattern CAD system exports it (ASTM D6673, as CLO writes it: DXF
    R2000, millimetres in $INSUNITS, LWPOLYLINE boundaries): a FRONT and a BACK block, the
    same quarter panel (a skirt symmetric front to back), each placed twice, the second time
    mirrored; the grain line (layer 7) from the hem up to the waist, so that u runs up the
    body; a notch (layer 4) at the hip line on both sides.  The boundary's sides follow
    width(y) at 2 mm steps of depth."""
    mm = 1000.0
    steps = max(2, int(round(a.length * mm / 2)))
    ys = [a.length * k / steps for k in range(steps + 1)]  # depth below the waist, m
    hip = a.length - a.hip_depth  # the hip line's height above the hem, m
    right = [(width(y) / 2 * mm, (a.length - y) * mm) for y in reversed(ys)]  # hem to waist
    left = [(-x, yy) for x, yy in reversed(right)]                             # waist to hem
    doc = dxf_document()
    msp = doc.modelspace()
    for name in ("FRONT", "BACK"):
        b = doc.blocks.new(name)
        b.add_lwpolyline(right + left, close=True, dxfattribs={"layer": "1"})
        b.add_line((0, 0.1 * a.length * mm), (0, 0.9 * a.length * mm), dxfattribs={"layer": "7"})
        for side in (-1, 1):
            b.add_point((side * width(a.hip_depth) / 2 * mm, hip * mm), dxfattribs={"layer": "4"})
        b.add_text("Piece Name: %s" % name.title(), dxfattribs={"layer": "1"})
        b.add_text("Quantity: 2", dxfattribs={"layer": "1"})
    gap = (max(a.hem / 4, a.hip * (1 + a.ease) / 4) + 0.05) * mm
    for k, name in enumerate(("FRONT", "BACK")):
        msp.add_blockref(name, (2 * k * gap, 0))
        msp.add_blockref(name, ((2 * k + 1) * gap, 0), dxfattribs={"xscale": -1})
    msp.add_text("Style Name: four-panel skirt (tools/make_garment.py skirt --dxf)")
    dxf_save(doc, a.dxf, "FRONT and BACK, each placed twice (once mirrored)")


def tube(a):
    pieces = [grid(n, grid_piece(lambda y: a.width, a.height, a.columns, a.rows), a.columns,
                   a.rows) for n in ("front", "back")]
    seams = [side_seam("left", "front", "right", "back", "left"),
             side_seam("right", "back", "right", "front", "left")]
    title = ("two pieces of a tube: tools/make_garment.py tube --width %g --height %g "
             "--columns %d --rows %d" % (a.width, a.height, a.columns, a.rows))
    pieces_obj(a.output, title, pieces, seams)


def top_widths(a):
    """A top's body piece across, m: half its width, the neckline's half width at the armpit
    line, and the strap's inner and outer edges at the shoulder seam (from the centre line)."""
    half = a.bust * (1 + a.ease) / 4
    inner0 = half - a.strap_columns * 2 * half / a.columns
    return half, inner0, a.strap_at - a.strap_width / 2, a.strap_at + a.strap_width / 2


def tank_piece(name, a):
    """One piece of the tank top as (name, uv, quads, corners): a body of columns x rows quads
    from the armpit line (v = -strap_length) down to the hem, and two straps of strap_columns x
    strap_rows quads from the armpit line up to the shoulder seam (v = 0).  A strap's bottom is
    the body's outer strap_columns columns; its neckline edge runs straight up to the shoulder,
    its armhole edge curves in (a parabola, steepest at the armpit) to the strap's outer edge."""
    nx, ns, nyb, nys = a.columns, a.strap_columns, a.rows, a.strap_rows
    half, inner0, inner1, outer1 = top_widths(a)
    slot, uv = {}, []
    for j in range(nys + nyb + 1):
        if j < nys:                           # strap rows: t = 0 at the armpit, 1 at the top
            t = 1 - j / nys
            inner = inner0 + (inner1 - inner0) * t
            outer = outer1 + (half - outer1) * (1 - t) ** 2
            cols = [(i, -(outer + (inner - outer) * i / ns)) for i in range(ns + 1)]
            cols += [(nx - ns + k, inner + (outer - inner) * k / ns) for k in range(ns + 1)]
            v = -a.strap_length * j / nys
        else:
            cols = [(i, -half + 2 * half * i / nx) for i in range(nx + 1)]
            v = -a.strap_length - a.length * (j - nys) / nyb
        for i, u in cols:
            slot[i, j] = len(uv)
            uv.append((u, v))
    qs = []
    for j in range(nys + nyb):
        for i in range(nx):
            if j < nys and ns <= i < nx - ns:
                continue                      # the neckline between the straps
            qs.append((slot[i, j + 1], slot[i + 1, j + 1], slot[i + 1, j], slot[i, j]))
    ny = nys + nyb
    cs = {"shoulder_left_out": slot[0, 0], "shoulder_left_in": slot[ns, 0],
          "shoulder_right_in": slot[nx - ns, 0], "shoulder_right_out": slot[nx, 0],
          "armpit_left": slot[0, nys], "armpit_right": slot[nx, nys],
          "hem_left": slot[0, ny], "hem_right": slot[nx, ny]}
    return name, uv, qs, cs


def top_seams():
    """The seams of a top's front and back: the shoulders and the sides.  The front is wrapped
    facing -y and the back facing +y, u anticlockwise seen from above: the front's left (u < 0)
    and the back's right are on the body's right (-x)."""
    return [("right_shoulder", ("front", "shoulder_left_out", "shoulder_left_in"),
             ("back", "shoulder_right_out", "shoulder_right_in")),
            ("left_shoulder", ("front", "shoulder_right_out", "shoulder_right_in"),
             ("back", "shoulder_left_out", "shoulder_left_in")),
            ("right_side", ("front", "armpit_left", "hem_left"),
             ("back", "armpit_right", "hem_right")),
            ("left_side", ("front", "armpit_right", "hem_right"),
             ("back", "armpit_left", "hem_left"))]


def top_title(what, a):
    """The command that writes a top's pieces, as the OBJ's title."""
    return ("%s --bust %g --ease %g --length %g --strap-length %g --strap-width %g --strap-at %g "
            "--columns %d --rows %d --strap-columns %d --strap-rows %d"
            % (what, a.bust, a.ease, a.length, a.strap_length, a.strap_width, a.strap_at,
               a.columns, a.rows, a.strap_columns, a.strap_rows))


def tank(a):
    if a.dxf:
        return tank_dxf(a)
    pieces = [tank_piece(n, a) for n in ("front", "back")]
    pieces_obj(a.output, top_title("tank top: tools/make_garment.py tank", a), pieces, top_seams())


def polyline_length(pts):
    return sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(pts, pts[1:]))


def armhole_length(a):
    """The length of one armhole edge of a top's body piece (tank_piece's strap outer edge, from
    the armpit up to the shoulder point), m."""
    half, _, _, outer1 = top_widths(a)
    pts = []
    for j in range(a.strap_rows + 1):
        t = 1 - j / a.strap_rows
        pts.append((outer1 + (half - outer1) * (1 - t) ** 2, -a.strap_length * j / a.strap_rows))
    return polyline_length(pts)


def sleeve_piece(name, a, cap_height):
    """A short sleeve as (name, uv, quads, corners): width sleeve_width at the cap's foot,
    sleeve_length from the cap's foot to the hem, the cap a bell v = h cos^2(pi u / width) over
    the foot line (v = 0 at the foot), columns x rows quads, each column from the cap to the
    hem."""
    nx, ny, w, L = a.sleeve_columns, a.sleeve_rows, a.sleeve_width, a.sleeve_length
    uv = []
    for j in range(ny + 1):
        for i in range(nx + 1):
            u = (i / nx - 0.5) * w
            top = cap_height * math.cos(math.pi * u / w) ** 2
            uv.append((u, top - (top + L) * j / ny))
    cs = corners(0, nx, ny)
    cs = {"cap_left": cs["top_left"], "cap_right": cs["top_right"], "cap_mid": nx // 2,
          "hem_left": cs["bottom_left"], "hem_right": cs["bottom_right"]}
    return name, uv, quads(0, nx, ny), cs


def cap_height_for(a, want):
    """The cap height h whose half cap (foot corner to the top) is `want` m long (bisection)."""
    def half_len(h):
        n = 400
        pts = []
        for k in range(n + 1):
            u = -a.sleeve_width / 2 * (1 - k / n)
            pts.append((u, h * math.cos(math.pi * u / a.sleeve_width) ** 2))
        return polyline_length(pts)
    lo, hi = 0.0, 1.0
    if half_len(lo) > want:
        raise SystemExit("make_garment: the sleeve is wider than its armhole: a half cap of "
                         "%.3g m against %.3g m; expected a narrower --sleeve-width"
                         % (half_len(lo), want))
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if half_len(mid) < want else (lo, mid)
    return 0.5 * (lo + hi)


def dxf_piece(doc, block, outline, grain, turns, notches, quantity):
    """A piece's block: its closed outline (layer 1), grain line (layer 7, first point to
    last), turn points (layer 2: corners however slight the turn) and notches (layer 4), all
    in m, written in mm."""
    mm = 1000.0
    b = doc.blocks.new(block)
    b.add_lwpolyline([(x * mm, y * mm) for x, y in outline], close=True,
                     dxfattribs={"layer": "1"})
    b.add_line(*[(x * mm, y * mm) for x, y in grain], dxfattribs={"layer": "7"})
    for layer, pts in (("2", turns), ("4", notches)):
        for x, y in pts:
            b.add_point((x * mm, y * mm), dxfattribs={"layer": layer})
    b.add_text("Piece Name: %s" % block.title(), dxfattribs={"layer": "1"})
    b.add_text("Quantity: %d" % quantity, dxfattribs={"layer": "1"})


def top_outline(a, steps):
    """A top's body piece (tank_piece's shape) as a counter-clockwise outline with the hem at
    y = 0 and the piece's centre line at x = 0, m: the armholes at `steps` points each; and
    its ten corners (hem, armpits, shoulder points, neck points, the neckline's foot)."""
    half, inner0, inner1, outer1 = top_widths(a)
    top, arm = a.length + a.strap_length, a.length
    hole = [(outer1 + (half - outer1) * (1 - k / steps) ** 2, arm + a.strap_length * k / steps)
            for k in range(steps + 1)]             # armpit up to the shoulder point, x > 0
    right = [(half, 0.0)] + hole + [(inner1, top), (inner0, arm)]
    left = [(-x, y) for x, y in reversed(right)]
    corners = [(half, 0.0), (half, arm), (outer1, top), (inner1, top), (inner0, arm)]
    return [(-half, 0.0)] + right + left[:-1], corners + [(-x, y) for x, y in corners]


def top_dxf(a):
    """A DXF document holding a top's FRONT and BACK blocks (the same piece, top_outline's),
    grain lines from the hem up, the corners as turn points."""
    doc = dxf_document()
    body, body_corners = top_outline(a, 100)
    for name in ("FRONT", "BACK"):
        dxf_piece(doc, name, body, [(0, 0.1 * a.length), (0, 0.9 * a.length)], body_corners,
                  [], 1)
    return doc


def tank_dxf(a):
    """The tank top's pattern as a pattern CAD system exports it (like tshirt_dxf): FRONT and
    BACK, the same piece, each placed once."""
    doc = top_dxf(a)
    msp = doc.modelspace()
    msp.add_blockref("FRONT", (0, 0))
    msp.add_blockref("BACK", (1000.0 * (a.bust * (1 + a.ease) / 2 + 0.05), 0))
    msp.add_text("Style Name: tank top (tools/make_garment.py tank --dxf)")
    dxf_save(doc, a.dxf, "FRONT and BACK")


def tshirt_dxf(a, h):
    """The T-shirt's pattern as a pattern CAD system exports it (ASTM D6673 as CLO writes it,
    like skirt_dxf): FRONT and BACK, the same body piece, and a SLEEVE placed twice, the
    second time mirrored; grain lines from the hem up (u up the body and up the arm); the
    corners as turn points; a notch at the top of the sleeve's cap, where its front half
    meets its back half."""
    doc = top_dxf(a)
    w, L = a.sleeve_width, a.sleeve_length
    cap = [(w * (k / 200 - 0.5), L + h * math.cos(math.pi * (k / 200 - 0.5)) ** 2)
           for k in range(201)]                    # the cap, left to right
    sleeve = [(-w / 2, 0.0), (w / 2, 0.0)] + cap[::-1]
    dxf_piece(doc, "SLEEVE", sleeve, [(0, 0.1 * L), (0, 0.9 * L)],
              [(-w / 2, 0.0), (w / 2, 0.0), (-w / 2, L), (w / 2, L)], [(0.0, L + h)], 2)
    msp = doc.modelspace()
    gap = 1000.0 * (a.bust * (1 + a.ease) / 2 + 0.05)
    msp.add_blockref("FRONT", (0, 0))
    msp.add_blockref("BACK", (gap, 0))
    msp.add_blockref("SLEEVE", (2 * gap, 0))
    msp.add_blockref("SLEEVE", (2 * gap + 1000.0 * (w + 0.05), 0), dxfattribs={"xscale": -1})
    msp.add_text("Style Name: T-shirt (tools/make_garment.py tshirt --dxf)")
    dxf_save(doc, a.dxf, "FRONT, BACK and SLEEVE (placed twice, once mirrored)")


def tshirt(a):
    want = armhole_length(a)
    h = cap_height_for(a, want)
    if a.dxf:
        return tshirt_dxf(a, h)
    pieces = [tank_piece(n, a) for n in ("front", "back")]
    pieces += [sleeve_piece(n, a, h) for n in ("left_sleeve", "right_sleeve")]
    # the armholes: the left sleeve (on the body's left, +x) has its u < 0 half towards the
    # front, the right sleeve its u > 0 half (docs/garments.md, "The T-shirt")
    seams = top_seams() + [
        ("left_armhole_front", ("front", "armpit_right", "shoulder_right_out"),
         ("left_sleeve", "cap_left", "cap_mid")),
        ("left_armhole_back", ("back", "armpit_left", "shoulder_left_out"),
         ("left_sleeve", "cap_right", "cap_mid")),
        ("right_armhole_front", ("front", "armpit_left", "shoulder_left_out"),
         ("right_sleeve", "cap_right", "cap_mid")),
        ("right_armhole_back", ("back", "armpit_right", "shoulder_right_out"),
         ("right_sleeve", "cap_left", "cap_mid")),
        ("left_underarm", ("left_sleeve", "cap_left", "hem_left"),
         ("left_sleeve", "cap_right", "hem_right")),
        ("right_underarm", ("right_sleeve", "cap_left", "hem_left"),
         ("right_sleeve", "cap_right", "hem_right"))]
    title = ("%s --sleeve-width %g --sleeve-length %g --sleeve-columns %d --sleeve-rows %d\n"
             "# armhole %.4g m, sleeve cap height %.4g m"
             % (top_title("T-shirt: tools/make_garment.py tshirt", a), a.sleeve_width,
                a.sleeve_length, a.sleeve_columns, a.sleeve_rows, want, h))
    pieces_obj(a.output, title, pieces, seams)


def smoothstep_profile(zs, rs, z):
    """A monotone smooth interpolation of radii rs at heights zs (increasing): the quintic blend
    between consecutive points (flat at each, so never beyond them)."""
    if z <= zs[0]:
        return rs[0]
    for k in range(len(zs) - 1):
        if z <= zs[k + 1]:
            u = (z - zs[k]) / (zs[k + 1] - zs[k])
            b = u * u * u * (10 - 15 * u + 6 * u * u)
            return rs[k] + b * (rs[k + 1] - rs[k])
    return rs[-1]


def body(a):
    H = a.height
    r = lambda girth: girth / (2 * math.pi)
    # heights as fractions of the figure's height (a standard dress form) and radii, m
    zs = [0.27 * H, 0.40 * H, 0.52 * H, 0.62 * H, 0.72 * H, 0.82 * H, 0.86 * H]
    rs = [0.6 * r(a.hip), 0.85 * r(a.hip), r(a.hip), r(a.waist), r(a.bust), 0.85 * r(a.bust),
          0.4 * r(a.bust)]
    title = ("body of revolution: tools/make_garment.py body --height %g --bust %g --waist %g "
             "--hip %g --around %d --rows %d\n# waist at z = %.4g m (radius %.4g), hip at z = "
             "%.4g m (radius %.4g)" % (H, a.bust, a.waist, a.hip, a.around, a.rows, zs[3], rs[3],
                                       zs[2], rs[2]))
    revolution(a.output, title, zs, rs, a.around, a.rows, 0.02)


def cylinder(a):
    title = ("closed cylinder: tools/make_garment.py cylinder --radius %g --height %g --around %d "
             "--rows %d" % (a.radius, a.height, a.around, a.rows))
    revolution(a.output, title, [-0.5 * a.height, 0.5 * a.height], [a.radius, a.radius],
               a.around, a.rows, 0.0)


def revolution(path, title, zs, rs, around, rows, cap):
    """A closed surface of revolution about z through the radii rs at heights zs, `around`
    vertices per ring, `rows` rings, and a pole `cap` m beyond each end."""
    z0, z1 = zs[0] - cap, zs[-1] + cap  # the poles
    pos = [(0.0, 0.0, z0)]
    for j in range(rows):
        z = zs[0] + (zs[-1] - zs[0]) * j / (rows - 1)
        rad = smoothstep_profile(zs, rs, z)
        for i in range(around):
            t = 2 * math.pi * i / around
            pos.append((rad * math.cos(t), rad * math.sin(t), z))
    pos.append((0.0, 0.0, z1))
    top = len(pos) - 1
    ring = lambda j, i: 1 + j * around + i % around
    faces = []
    for i in range(around):  # outward normals
        faces.append((0, ring(0, i + 1), ring(0, i)))
        faces.append((top, ring(rows - 1, i), ring(rows - 1, i + 1)))
        for j in range(rows - 1):
            faces.append((ring(j, i), ring(j, i + 1), ring(j + 1, i + 1)))
            faces.append((ring(j, i), ring(j + 1, i + 1), ring(j + 1, i)))
    with open(path, "w") as f:
        f.write("# %s\n" % title)
        for p in pos:
            f.write("v %.9g %.9g %.9g\n" % p)
        for t in faces:
            f.write("f %d %d %d\n" % tuple(k + 1 for k in t))


def top_options(k, ease, length, strap_length, strap_width, strap_at, output):
    """The options of a top's body pieces (tank and tshirt), with their defaults."""
    k.add_argument("--bust", type=float, default=0.88, help="body bust girth, m")
    k.add_argument("--ease", type=float, default=ease, help="relative ease at the bust")
    k.add_argument("--length", type=float, default=length, help="armpit line to hem, m")
    k.add_argument("--strap-length", type=float, default=strap_length,
                   help="armpit line to shoulder seam, m")
    k.add_argument("--strap-width", type=float, default=strap_width,
                   help="the strap (shoulder) at the shoulder seam, m")
    k.add_argument("--strap-at", type=float, default=strap_at,
                   help="its centre from the piece's centre line at the shoulder seam, m")
    k.add_argument("--columns", type=int, default=16, help="across the body")
    k.add_argument("--rows", type=int, default=10, help="armpit line to hem")
    k.add_argument("--strap-columns", type=int, default=5, help="across a strap")
    k.add_argument("--strap-rows", type=int, default=8, help="armpit line to shoulder seam")
    k.add_argument("-o", "--output", default=output)


def check_top(ap, a):
    """Refuse a top's body options that make no piece."""
    half = a.bust * (1 + a.ease) / 4
    if (a.columns < 1 or a.rows < 1 or a.strap_rows < 1 or a.strap_columns < 1
            or 2 * a.strap_columns >= a.columns or a.length <= 0 or a.strap_length <= 0):
        ap.error("need columns > 2 strap-columns >= 2, rows, strap-rows >= 1 and positive "
                 "lengths")
    if not 0 < a.strap_at - a.strap_width / 2 < a.strap_at + a.strap_width / 2 < half:
        ap.error("the straps must lie between the neckline and the piece's side edge")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="what", required=True)
    s = sub.add_parser("skirt", help="four quarter panels of a skirt")
    s.add_argument("--waist", type=float, default=0.70, help="body waist girth, m")
    s.add_argument("--hip", type=float, default=1.00, help="body hip girth, m")
    s.add_argument("--hem", type=float, default=1.10, help="hem girth of the pattern, m")
    s.add_argument("--ease", type=float, default=-0.07, help="relative ease at the hips")
    s.add_argument("--waist-ease", type=float, default=-0.03, help="relative ease at the waist")
    s.add_argument("--hip-depth", type=float, default=0.17, help="waist to hip line, m")
    s.add_argument("--length", type=float, default=0.55, help="waist to hem, m")
    s.add_argument("--columns", type=int, default=8)
    s.add_argument("--rows", type=int, default=20)
    s.add_argument("-o", "--output", default="scenes/meshes/garment_skirt.obj")
    s.add_argument("--dxf", help="write the pattern as a DXF file (ASTM D6673) instead of an OBJ")
    t = sub.add_parser("tube", help="two rectangles sewn into a tube")
    t.add_argument("--width", type=float, default=0.3, help="m")
    t.add_argument("--height", type=float, default=0.2, help="m")
    t.add_argument("--columns", type=int, default=6)
    t.add_argument("--rows", type=int, default=4)
    t.add_argument("-o", "--output", default="tests/data/tube_pieces.obj")
    k = sub.add_parser("tank", help="front and back of a tank top")
    top_options(k, ease=-0.07, length=0.275, strap_length=0.185, strap_width=0.05,
                strap_at=0.11, output="scenes/meshes/garment_tank.obj")
    k.add_argument("--dxf", help="write the pattern as a DXF file (ASTM D6673) instead of an OBJ")
    k = sub.add_parser("tshirt", help="front, back and two short sleeves of a T-shirt")
    top_options(k, ease=-0.03, length=0.30, strap_length=0.20, strap_width=0.10, strap_at=0.115,
                output="scenes/meshes/garment_tshirt.obj")
    k.add_argument("--sleeve-width", type=float, default=0.36, help="at the cap's foot, m")
    k.add_argument("--sleeve-length", type=float, default=0.12, help="cap's foot to hem, m")
    k.add_argument("--sleeve-columns", type=int, default=12, help="round the sleeve (even)")
    k.add_argument("--sleeve-rows", type=int, default=8, help="cap to hem")
    k.add_argument("--dxf", help="write the pattern as a DXF file (ASTM D6673) instead of an OBJ")
    b = sub.add_parser("body", help="a closed body of revolution")
    b.add_argument("--height", type=float, default=1.70, help="m")
    b.add_argument("--bust", type=float, default=0.90, help="girth, m")
    b.add_argument("--waist", type=float, default=0.70, help="girth, m")
    b.add_argument("--hip", type=float, default=1.00, help="girth, m")
    b.add_argument("--around", type=int, default=24)
    b.add_argument("--rows", type=int, default=20)
    b.add_argument("-o", "--output", default="scenes/meshes/body_revolution.obj")
    c = sub.add_parser("cylinder", help="a closed cylinder about the z axis, centred at z = 0")
    c.add_argument("--radius", type=float, default=0.08, help="m")
    c.add_argument("--height", type=float, default=0.4, help="m")
    c.add_argument("--around", type=int, default=16)
    c.add_argument("--rows", type=int, default=5)
    c.add_argument("-o", "--output", default="tests/data/cylinder.obj")
    a = ap.parse_args()
    if a.what == "cylinder":
        if a.around < 3 or a.rows < 2 or a.radius <= 0 or a.height <= 0:
            ap.error("need around >= 3, rows >= 2 and a positive radius and height")
        cylinder(a)
    elif a.what == "skirt":
        if a.columns < 1 or a.rows < 1 or not 0 < a.hip_depth < a.length:
            ap.error("need columns, rows >= 1 and 0 < hip-depth < length")
        skirt(a)
    elif a.what == "tank":
        check_top(ap, a)
        tank(a)
    elif a.what == "tshirt":
        check_top(ap, a)
        if (a.sleeve_columns < 2 or a.sleeve_columns % 2 or a.sleeve_rows < 1
                or a.sleeve_width <= 0 or a.sleeve_length <= 0):
            ap.error("need an even sleeve-columns >= 2, sleeve-rows >= 1 and a positive "
                     "sleeve width and length")
        tshirt(a)
    elif a.what == "tube":
        if a.columns < 1 or a.rows < 1 or a.width <= 0 or a.height <= 0:
            ap.error("need columns, rows >= 1 and a positive width and height")
        tube(a)
    else:
        if a.around < 3 or a.rows < 2:
            ap.error("need around >= 3 and rows >= 2")
        body(a)


if __name__ == "__main__":
    main()
