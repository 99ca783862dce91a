#!/usr/bin/python3
"""make_patterns.py — DXF pattern files for the tests of `sinew pattern import`, written with
ezdxf per the ASTM D6673 layer table, with the exact area of every piece they draw.

    /usr/bin/python3 tests/data/patterns/make_patterns.py OUT_DIR

writes into OUT_DIR:
  aama_skirt.dxf  AAMA style: DXF R12 with no units in its header (as Gerber's exports),
                  inches from the style text
                  'Units: ENGLISH', POLYLINE boundaries.  FRONT: a waist drawn by a bulge,
                  a grain line along y, a point notch and a slit notch.  BACK: a boundary of
                  LINE and ARC entities, a sew line (layer 14) inside it, a grain line at 30
                  degrees, a drill hole, an internal line.  POCKET graded in sizes S and M
                  ('Sample Size: M'), size M placed twice, once mirrored.  Entities the
                  importer does not use: a stripe reference POLYLINE (layer 9), a 3DFACE
                  on layer 1, a LINE on a layer named CUT, an annotation TEXT (layer 15), a
                  CIRCLE outside any block.
  clo_sleeve.dxf  CLO style: DXF R2000, $INSUNITS = 4 (mm), no grading, one LWPOLYLINE with
                  a bulge and a duplicated closing point, a grain line at 30 degrees.
  no_units.dxf    the FRONT piece alone, no units anywhere (AAMA's default: inches).
  bad_*.dxf       not_dxf (text), no_pieces, open boundary, self-crossing boundary, grain line
                  outside its piece, a piece too small for the default edge length.
EXPECTED maps each file to {piece name: exact area, m²} (of the size M for the graded one)."""
import math
import os
import sys

import ezdxf

IN = 0.0254
W, H, B = 20.0, 24.0, 0.15   # FRONT: width, side height (in), waist bulge


def save_aama(doc, path):
    """An R12 file whose header states no units (as Gerber's exports: units from the
    style text only)."""
    for var in ("$INSUNITS", "$MEASUREMENT"):
        if var in doc.header:
            del doc.header[var]
    doc.saveas(path)


def bulge_segment(chord, bulge):
    """Area of the circular segment a bulge adds to a chord (same length unit squared)."""
    theta = 4 * math.atan(abs(bulge))
    r = chord / (2 * math.sin(theta / 2))
    return r * r / 2 * (theta - math.sin(theta))


def front_block(doc, name="FRONT"):
    b = doc.blocks.new(name)
    # counter-clockwise: hem, right side, waist (bulging up), left side
    b.add_polyline2d([(0, 0, 0, 0, 0), (W, 0, 0, 0, 0), (W, H, 0, 0, B), (0, H, 0, 0, 0)],
                     format="xyseb", close=True, dxfattribs={"layer": "1"})
    b.add_line((W / 2, 2), (W / 2, H - 2), dxfattribs={"layer": "7"})
    b.add_point((W, H / 2), dxfattribs={"layer": "4"})                   # side notch
    b.add_line((W / 2, 0), (W / 2, 0.25), dxfattribs={"layer": "4"})     # slit notch at hem
    b.add_text("Piece Name: Front", dxfattribs={"layer": "1"})
    b.add_text("Quantity: 1", dxfattribs={"layer": "1"})
    return (W * H + bulge_segment(W, B)) * IN * IN


def back_block(doc):
    """A 22 x 26 in back, its waist an ARC (sagging into the piece by 1 in) between LINEs;
    a sew line 0.5 in inside the straight sides (the area is the sew line's)."""
    b = doc.blocks.new("BACK")
    w, h, sag = 22.0, 26.0, 1.0
    r = (sag * sag + (w / 2) ** 2) / (2 * sag)
    cy = h - sag + r
    half = math.degrees(math.asin((w / 2) / r))
    for p, q in (((0, 0), (w, 0)), ((w, 0), (w, h)), ((0, h), (0, 0))):
        b.add_line(p, q, dxfattribs={"layer": "1"})
    b.add_arc((w / 2, cy), r, 270 - half, 270 + half, dxfattribs={"layer": "1"})
    # the sew line: 0.5 in inside the hem and sides, the same waist arc
    a = 0.5
    ang = math.degrees(math.asin((w / 2 - a) / r))
    y_end = cy - r * math.cos(math.radians(ang))
    b.add_polyline2d([(a, a), (w - a, a), (w - a, y_end)], dxfattribs={"layer": "14"})
    b.add_arc((w / 2, cy), r, 270 - ang, 270 + ang, dxfattribs={"layer": "14"})
    b.add_line((a, y_end), (a, a), dxfattribs={"layer": "14"})
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    b.add_line((w / 2 - 4 * c, h / 2 - 4 * s), (w / 2 + 4 * c, h / 2 + 4 * s),
               dxfattribs={"layer": "7"})
    b.add_point((w / 2, 6), dxfattribs={"layer": "13"})
    b.add_line((4, 8), (4, 16), dxfattribs={"layer": "8"})
    b.add_point((w, h / 2), dxfattribs={"layer": "4"})
    b.add_text("Piece Name: Back", dxfattribs={"layer": "1"})
    b.add_text("Quantity: 1", dxfattribs={"layer": "1"})
    b.add_text("cut with care", dxfattribs={"layer": "15"})
    b.add_polyline2d([(1, 1), (5, 3), (9, 1)], dxfattribs={"layer": "9"})
    b.add_line((1, 1), (2, 2), dxfattribs={"layer": "CUT"})
    # area inside the sew line: rectangle to the chord at y_end minus the arc's segment
    chord = w - 2 * a
    seg = r * r / 2 * (2 * math.radians(ang) - math.sin(2 * math.radians(ang)))
    return (chord * (y_end - a) - seg) * IN * IN


def pocket_block(doc, size, grow):
    """An asymmetric pocket (a trapezoid, the right side slanted), graded by `grow` in."""
    b = doc.blocks.new("POCKET_" + size)
    w, h = 6 + grow, 7 + grow
    b.add_polyline2d([(0, 0), (w, 0), (w + 1, h), (0, h)], close=True,
                     dxfattribs={"layer": "1"})
    b.add_line((1, 1), (1, h - 1), dxfattribs={"layer": "7"})
    b.add_point((0, h / 2), dxfattribs={"layer": "4"})
    b.add_text("Piece Name: Pocket", dxfattribs={"layer": "1"})
    b.add_text("Size: %s" % size, dxfattribs={"layer": "1"})
    b.add_text("Quantity: 2", dxfattribs={"layer": "1"})
    return (w + 0.5) * h * IN * IN


def aama_skirt(path):
    doc = ezdxf.new("R12")
    msp = doc.modelspace()
    front = front_block(doc)
    back = back_block(doc)
    # an entity of a type no pattern layer holds
    doc.blocks.get("FRONT").add_3dface([(1, 1), (2, 1), (2, 2)], dxfattribs={"layer": "1"})
    pockets = {s: pocket_block(doc, s, g) for s, g in (("S", 0.0), ("M", 0.5))}
    msp.add_text("Style Name: A-line skirt")
    msp.add_text("Sample Size: M")
    msp.add_text("Units: ENGLISH")
    msp.add_blockref("FRONT", (0, 0))
    msp.add_blockref("BACK", (25, 0))
    msp.add_blockref("POCKET_S", (0, 40))
    msp.add_blockref("POCKET_M", (10, 40))
    msp.add_blockref("POCKET_M", (30, 40), dxfattribs={"xscale": -1})
    msp.add_circle((100, 100), 1)
    save_aama(doc, path)
    return {"Front": front, "Back": back, "Pocket": pockets["M"], "Pocket_2": pockets["M"]}


def clo_sleeve(path):
    doc = ezdxf.new("R2000")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    b = doc.blocks.new("Sleeve")
    w, h, bulge = 400.0, 300.0, 0.3
    b.add_lwpolyline([(0, 0, 0), (w, 0, 0), (w, h, bulge), (0, h, 0), (0, 0, 0)],
                     format="xyb", dxfattribs={"layer": "1"})   # closed by a repeated point
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    b.add_line((200 - 80 * c, 150 - 80 * s), (200 + 80 * c, 150 + 80 * s),
               dxfattribs={"layer": "7"})
    b.add_point((0, 150), dxfattribs={"layer": "4"})
    b.add_text("Piece Name: Sleeve", dxfattribs={"layer": "1"})
    msp.add_blockref("Sleeve", (0, 0))
    doc.saveas(path)
    return {"Sleeve": (w * h + bulge_segment(w, bulge)) * 1e-6}


def no_units(path):
    doc = ezdxf.new("R12")
    area = front_block(doc)
    doc.modelspace().add_blockref("FRONT", (0, 0))
    save_aama(doc, path)
    return {"Front": area}


def one_piece(path, points, grain=((1, 1), (1, 3)), close=True):
    doc = ezdxf.new("R12")
    b = doc.blocks.new("P")
    b.add_polyline2d(points, close=close, dxfattribs={"layer": "1"})
    b.add_line(grain[0], grain[1], dxfattribs={"layer": "7"})
    b.add_text("Piece Name: P", dxfattribs={"layer": "1"})
    doc.modelspace().add_blockref("P", (0, 0))
    doc.modelspace().add_text("Units: ENGLISH")
    save_aama(doc, path)


def bad_files(out):
    with open(os.path.join(out, "bad_not_dxf.dxf"), "w") as f:
        f.write("this is a text file\nwith two lines\n")
    doc = ezdxf.new("R12")
    doc.modelspace().add_line((0, 0), (1, 1), dxfattribs={"layer": "1"})
    doc.saveas(os.path.join(out, "bad_no_pieces.dxf"))
    one_piece(os.path.join(out, "bad_open.dxf"), [(0, 0), (10, 0), (10, 10), (0, 10)],
              close=False)
    one_piece(os.path.join(out, "bad_self_crossing.dxf"), [(0, 0), (10, 10), (10, 0), (0, 6)],
              grain=((6, 3), (8, 3)))
    one_piece(os.path.join(out, "bad_grain_outside.dxf"), [(0, 0), (10, 0), (10, 10), (0, 10)],
              grain=((12, 1), (12, 5)))
    one_piece(os.path.join(out, "bad_tiny.dxf"), [(0, 0), (0.5, 0), (0.5, 0.5), (0, 0.5)],
              grain=((0.25, 0.1), (0.25, 0.4)))


def main(out):
    os.makedirs(out, exist_ok=True)
    expected = {"aama_skirt.dxf": aama_skirt(os.path.join(out, "aama_skirt.dxf")),
                "clo_sleeve.dxf": clo_sleeve(os.path.join(out, "clo_sleeve.dxf")),
                "no_units.dxf": no_units(os.path.join(out, "no_units.dxf"))}
    bad_files(out)
    return expected


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: make_patterns.py OUT_DIR")
    for name, areas in main(sys.argv[1]).items():
        print(name, ", ".join("%s %.6g m²" % kv for kv in areas.items()))
