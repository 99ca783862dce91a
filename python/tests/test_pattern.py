"""sinew pattern import on DXF files written by tests/data/patterns/make_patterns.py (ezdxf):
areas against the exact areas of the drawn shapes, the grain line as the u direction, units,
graded sizes, a mirrored INSERT, notches as mesh vertices, the entities not used listed, bad
files refused with nothing written, the skeleton accepted by `sinew check`, and random damage
answered by a message, never a traceback."""
import importlib.util
import math
import os
import random
import re
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("ezdxf")
pytest.importorskip("gmsh")
from sinew import pattern  # noqa: E402
from sinew.pattern.__main__ import main  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SINEW = os.environ.get("SINEW_EXE", os.path.join(ROOT, "build", "sinew"))
IN = 0.0254


@pytest.fixture(scope="module")
def fx(tmp_path_factory):
    """(folder of the DXF files, {file: {piece: exact area m²}})."""
    spec = importlib.util.spec_from_file_location(
        "make_patterns", os.path.join(ROOT, "tests", "data", "patterns", "make_patterns.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    out = tmp_path_factory.mktemp("patterns")
    return out, mod.main(str(out))


@pytest.fixture(scope="module")
def skirt(fx):
    pat = pattern.read(str(fx[0] / "aama_skirt.dxf"))
    return pat, {m.group: m for m in pattern.mesh(pat)}


def test_areas_match_the_drawn_shapes(fx, skirt):
    """At the default edge length every piece's mesh area is within 0.05 % of the exact area
    of the drawn shape (docs/patterns.md, "Meshing"); at 5 cm edges within 0.5 %."""
    folder, expected = fx
    pat, meshed = skirt
    assert sorted(meshed) == sorted(expected["aama_skirt.dxf"])
    coarse = {m.group: m for m in pattern.mesh(pat, edge=0.05)}
    for name, area in expected["aama_skirt.dxf"].items():
        assert meshed[name].area == pytest.approx(area, rel=5e-4), name
        assert coarse[name].area == pytest.approx(area, rel=5e-3), name
    sleeve = pattern.mesh(pattern.read(str(folder / "clo_sleeve.dxf")))
    assert [m.group for m in sleeve] == ["Sleeve"]
    assert sleeve[0].area == pytest.approx(expected["clo_sleeve.dxf"]["Sleeve"], rel=5e-4)


def test_sew_line_replaces_the_cut_line(skirt):
    pat, meshed = skirt
    back = meshed["Back"]
    assert back.piece.boundary_from.startswith("sew line")
    # the sew line is 0.5 in inside the 22 in wide cut line
    w = back.xy[:, 0].max() - back.xy[:, 0].min()
    assert w == pytest.approx(21 * IN, rel=1e-6)


def rotation_of(m):
    """The 2x2 map from file-plane offsets to (u,v) offsets, fitted over all vertices."""
    dxy, duv = m.xy - m.xy[0], m.uv - m.uv[0]
    r, *_ = np.linalg.lstsq(dxy, duv, rcond=None)
    return r.T


@pytest.mark.parametrize("piece,angle", [("Front", 90.0), ("Back", 30.0)])
def test_grain_line_is_u(skirt, piece, angle):
    m = skirt[1][piece]
    a = math.radians(angle)
    expect = np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]])
    assert np.allclose(rotation_of(m), expect, atol=1e-9)
    assert m.grain_from_line and m.grain_deg == pytest.approx(angle)


def test_triangles_counter_clockwise_and_edges_near_target(skirt):
    for m in skirt[1].values():
        e1, e2 = m.uv[m.tris[:, 1]] - m.uv[m.tris[:, 0]], m.uv[m.tris[:, 2]] - m.uv[m.tris[:, 0]]
        assert (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).min() > 0
        b = np.array(m.boundary)
        assert pattern.geometry.signed_area(m.uv[b]) > 0  # counter-clockwise in (u,v)
        assert b[0] == m.corners[0] and sorted(set(b)) == sorted(b)
        at = {v: i for i, v in enumerate(b)}
        assert [at[c] for c in m.corners] == sorted(at[c] for c in m.corners)
        assert [at[c] for c in m.notches] == sorted(at[c] for c in m.notches)
        edges = np.hypot(*(m.uv[np.roll(b, -1)] - m.uv[b]).T)
        assert edges.max() <= 1.5 * pattern.DEFAULT_EDGE


def test_clo_sleeve_in_mm_with_grain_at_30_degrees(fx):
    pat = pattern.read(str(fx[0] / "clo_sleeve.dxf"))
    assert pat.scale == 1e-3 and "INSUNITS" in pat.units
    m = pattern.mesh(pat)[0]
    a = math.radians(30)
    assert np.allclose(rotation_of(m), [[math.cos(a), math.sin(a)],
                                        [-math.sin(a), math.cos(a)]], atol=1e-9)
    assert m.xy[:, 0].max() == pytest.approx(0.4)


def test_units(fx):
    folder, expected = fx
    assert pattern.read(str(folder / "aama_skirt.dxf")).scale == IN   # 'Units: ENGLISH'
    nu = pattern.read(str(folder / "no_units.dxf"))
    assert nu.scale == IN and "default" in nu.units
    mm = pattern.read(str(folder / "no_units.dxf"), units="mm")
    area = pattern.geometry.signed_area(mm.pieces[0].boundary)
    assert area == pytest.approx(expected["no_units.dxf"]["Front"] / IN ** 2 * 1e-6, rel=1e-3)


def test_sizes(fx, skirt, capsys):
    pat, _ = skirt
    assert pat.sizes == ["S", "M"] and pat.base_size == "M"
    small = {m.group: m for m in pattern.mesh(pat, size="S")}
    # size S's pocket says Quantity 2 and is placed once: its mirrored copy is made
    assert sorted(small) == ["Back", "Front", "Pocket", "Pocket_2"]
    assert small["Pocket_2"].piece.mirrored and small["Pocket_2"].piece.copy == 2
    assert small["Pocket"].area == pytest.approx(6.5 * 7 * IN * IN, rel=5e-3)
    with pytest.raises(pattern.PatternError, match="no size 'XL'; expected one of: S, M"):
        pattern.mesh(pat, size="XL")
    assert main(["import", str(fx[0] / "aama_skirt.dxf"), "--list"]) == 0
    assert "sizes: S, M (base M)" in capsys.readouterr().out


def test_mirrored_insert(skirt):
    meshed = skirt[1]
    a, b = meshed["Pocket"], meshed["Pocket_2"]
    assert not a.piece.mirrored and b.piece.mirrored
    # placed at x = 10 in and, mirrored, at x = 30 in: mirror images about x = 20 in
    assert sorted(np.round(40 * IN - a.xy[a.boundary, 0], 9)) == \
        sorted(np.round(b.xy[b.boundary, 0], 9))
    assert a.xy[a.notches[0], 0] == pytest.approx(10 * IN)
    assert b.xy[b.notches[0], 0] == pytest.approx(30 * IN)
    # the mirrored pocket's (u,v) are the mirror image: its slanted side on the other side
    assert a.area == pytest.approx(b.area, rel=1e-9)


def test_notches_and_corners_are_vertices(skirt):
    front = skirt[1]["Front"]
    w, h = 20 * IN, 24 * IN
    notch_xy = sorted(map(tuple, np.round(front.xy[front.notches], 9)))
    assert notch_xy == sorted([(round(w, 9), round(h / 2, 9)), (round(w / 2, 9), 0.0)])
    corners = np.round(front.xy[front.corners], 9)
    assert sorted(map(tuple, corners)) == sorted([(0.0, 0.0), (round(w, 9), 0.0),
                                                  (round(w, 9), round(h, 9)),
                                                  (0.0, round(h, 9))])
    assert set(front.notches) <= set(front.boundary)
    back = skirt[1]["Back"]
    assert len(back.drills) == 1 and len(back.internal) == 1 and len(back.internal[0]) >= 3


def test_skipped_entities_are_listed(fx, capsys):
    assert main(["import", str(fx[0] / "aama_skirt.dxf"), "--list"]) == 0
    out = capsys.readouterr().out
    assert "skipped: 5" in out
    for what in ("CIRCLE on layer '0'", "3DFACE on layer '1'", "TEXT on layer '15'",
                 "POLYLINE on layer '9'", "LINE on layer 'CUT'"):
        assert re.search(re.escape(what) + r" \(handle [0-9A-F]+\)", out), what


def test_import_writes_obj_and_skeleton_that_sinew_check_loads(fx, tmp_path):
    out = tmp_path / "out"
    r = subprocess.run([SINEW, "pattern", "import", str(fx[0] / "aama_skirt.dxf"),
                        "--out", str(out), "--edge", "0.03"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "4 entities not used" not in r.stderr and "5 entities not used" in r.stderr
    assert sorted(os.listdir(out)) == ["aama_skirt.obj", "aama_skirt.yaml"]
    umask = os.umask(0)
    os.umask(umask)
    for f in os.listdir(out):  # as any file written, not the temporary file's 0600
        assert os.stat(out / f).st_mode & 0o777 == 0o666 & ~umask, f
    obj = (out / "aama_skirt.obj").read_text()
    assert re.findall(r"^g (\S+)$", obj, re.M) == ["Front", "Back", "Pocket", "Pocket_2"]
    chk = subprocess.run([SINEW, "check", str(out / "aama_skirt.yaml")],
                         capture_output=True, text=True)
    assert chk.returncode == 0, chk.stderr
    areas = dict(re.findall(r"panel (\S+)\s+([0-9.e-]+) m\^2", chk.stdout))
    for name, area in fx[1]["aama_skirt.dxf"].items():
        assert float(areas[name]) == pytest.approx(area, rel=5e-3), name
    # the skeleton's corner indices are the vertices at the Front's corners
    scene = (out / "aama_skirt.yaml").read_text()
    corners = [int(i) for i in re.search(r'"Front".*?corners: \[([^\]]*)\]', scene,
                                          re.S).group(1).split(",")]
    v = np.array([[float(x) for x in ln.split()[1:3]]
                  for ln in obj.splitlines() if ln.startswith("v ")])
    box = v[corners]
    assert np.ptp(box[:, 0]) == pytest.approx(20 * IN) and np.ptp(box[:, 1]) == \
        pytest.approx(24 * IN)


def test_python_m_and_explicit_paths(fx, tmp_path):
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "python"))
    r = subprocess.run([sys.executable, "-m", "sinew.pattern", "import",
                        str(fx[0] / "clo_sleeve.dxf"), "--obj", str(tmp_path / "a.obj"),
                        "--scene", str(tmp_path / "b.yaml"), "--quiet"],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0 and r.stdout == "", r.stderr
    assert 'mesh: {obj: "a.obj"}' in (tmp_path / "b.yaml").read_text()


@pytest.mark.parametrize("name,message", [
    ("bad_not_dxf.dxf", "not a DXF file"),
    ("bad_no_pieces.dxf", "no pieces"),
    ("bad_open.dxf", "open boundary"),
    ("bad_self_crossing.dxf", "crosses itself"),
    ("bad_grain_outside.dxf", "grain line .* lies outside the piece"),
    ("bad_tiny.dxf", "too small for edges of 0.02 m"),
    ("missing.dxf", "cannot read"),
])
def test_bad_files_write_nothing(fx, tmp_path, capsys, name, message):
    out = tmp_path / "out"
    assert main(["import", str(fx[0] / name), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert re.search(message, err) and str(fx[0] / name) in err and "Traceback" not in err
    assert not out.exists()


def test_a_failed_write_leaves_nothing(fx, tmp_path, capsys):
    assert main(["import", str(fx[0] / "clo_sleeve.dxf"), "--obj", str(tmp_path / "a.obj"),
                 "--scene", str(tmp_path / "none" / "b.yaml")]) == 1
    assert "folder does not exist" in capsys.readouterr().err
    assert os.listdir(tmp_path) == []


def test_damaged_files_give_messages_not_tracebacks(fx, tmp_path, capsys):
    """Random bytes, and the skirt file with lines deleted, swapped or overwritten: every
    outcome is exit 0 or 1 with a message, never an exception."""
    rng = random.Random(7)
    lines = (fx[0] / "aama_skirt.dxf").read_text().splitlines()
    for k in range(40):
        path = tmp_path / ("damaged_%d.dxf" % k)
        if k < 8:
            path.write_bytes(bytes(rng.randrange(256) for _ in range(rng.randrange(1, 3000))))
        else:
            ln = list(lines)
            for _ in range(rng.randrange(1, 6)):
                i = rng.randrange(len(ln))
                op = rng.randrange(3)
                if op == 0:
                    del ln[i]
                elif op == 1:
                    ln[i] = rng.choice(["-1e300", "nan", "999999999999", "ABC", "", "1.5.6",
                                        "  8", "SECTION", "EOF", "POLYLINE"])
                else:
                    j = rng.randrange(len(ln))
                    ln[i], ln[j] = ln[j], ln[i]
            path.write_text("\n".join(ln) + "\n")
        rc = main(["import", str(path), "--out", str(tmp_path / "o"), "--edge", "0.05",
                   "--quiet"])
        assert rc in (0, 1)
        if rc == 1:
            assert capsys.readouterr().err.startswith("sinew pattern: ")
        capsys.readouterr()


def test_turn_points_on_the_boundary_are_corners(tmp_path, capsys):
    """A layer-2 turn point where the boundary turns by only 7 degrees is a corner; one off the
    boundary, and a layer-3 curve point, are listed as ignored."""
    import ezdxf
    doc = ezdxf.new("R12")
    b = doc.blocks.new("P")
    b.add_polyline2d([(0, 0), (10, 0), (10, 10), (5, 10.3), (0, 10)], close=True,
                     dxfattribs={"layer": "1"})
    b.add_point((5, 10.3), dxfattribs={"layer": "2"})
    b.add_point((5, 5), dxfattribs={"layer": "2"})
    b.add_point((3, 3), dxfattribs={"layer": "3"})
    doc.modelspace().add_blockref("P", (0, 0))
    doc.saveas(str(tmp_path / "tp.dxf"))
    m = pattern.mesh(pattern.read(str(tmp_path / "tp.dxf")))[0]
    assert len(m.corners) == 5
    assert [5 * IN, 10.3 * IN] in np.round(m.xy[m.corners], 12).tolist()
    assert main(["import", str(tmp_path / "tp.dxf"), "--list"]) == 0
    out = capsys.readouterr().out
    assert "POINT on layer '2'" in out and "turn point off the boundary" in out
    assert "POINT on layer '3'" in out and "curve point" in out


def test_out_of_spec_integers_are_repaired_and_listed(fx, tmp_path, capsys):
    """Integers written as reals ("70\\n1.0", as some exporters do) read as the same pattern;
    what ezdxf repaired is counted on import and listed, with its line, by --list."""
    lines = (fx[0] / "aama_skirt.dxf").read_text().split("\n")
    for i in range(1, len(lines)):
        if lines[i - 1].strip() == "70" and lines[i].strip().lstrip("-").isdigit():
            lines[i] = lines[i].strip() + ".0"
    path = tmp_path / "reals.dxf"
    path.write_text("\n".join(lines))
    pat = pattern.read(str(path))
    assert pat.repaired and all("near line" in r for r in pat.repaired)
    areas = {m.group: m.area for m in pattern.mesh(pat, edge=0.05)}
    for name, area in fx[1]["aama_skirt.dxf"].items():
        assert areas[name] == pytest.approx(area, rel=5e-3)
    assert main(["import", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "ezdxf repaired %d things" % len(pat.repaired) in err
    assert "recovered invalid integer" not in err  # listed by --list, not printed


SHIPPED_DXF = {  # garment: (make_garment.py's arguments, each piece's block, seams)
    "skirt": (["skirt", "--hip", "0.96", "--hip-depth", "0.204"],
              {"Front": "FRONT", "Front_2": "FRONT", "Back": "BACK", "Back_2": "BACK"}, 4),
    "tshirt": (["tshirt"], {"Front": "FRONT", "Back": "BACK", "Sleeve": "SLEEVE",
                            "Sleeve_2": "SLEEVE"}, 10)}


@pytest.mark.parametrize("garment", sorted(SHIPPED_DXF))
def test_shipped_dxf_garment_is_its_commands(tmp_path, garment):
    """scenes/patterns/garment_G.dxf is what `make_garment.py G --dxf` writes (the same bytes:
    no dates or GUIDs of the moment), scenes/meshes/garment_G_dxf.obj is what `sinew pattern
    import` makes of it (gmsh is deterministic here), each piece's rest area is its drawn
    polygon's within 0.5 %, the scene that sews them loads (its seams, nothing crossing at the
    start) and its pieces' corners and notches are those the importer lists."""
    import ezdxf
    args, blocks, nseam = SHIPPED_DXF[garment]
    scenes = os.path.join(ROOT, "scenes")
    dxf = os.path.join(scenes, "patterns", "garment_%s.dxf" % garment)
    obj = os.path.join(scenes, "meshes", "garment_%s_dxf.obj" % garment)
    scene = os.path.join(scenes, "garment_%s_dxf.yaml" % garment)
    subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "tools", "make_garment.py")] + args +
                   ["--dxf", str(tmp_path / "p.dxf")], check=True, capture_output=True)
    assert (tmp_path / "p.dxf").read_bytes() == open(dxf, "rb").read()
    (tmp_path / "patterns").mkdir()
    (tmp_path / "meshes").mkdir()
    (tmp_path / "patterns" / os.path.basename(dxf)).write_bytes(open(dxf, "rb").read())
    r = subprocess.run([os.path.abspath(SINEW), "pattern", "import",
                        "patterns/" + os.path.basename(dxf), "--obj",
                        "meshes/" + os.path.basename(obj), "--scene", "skel.yaml", "--quiet"],
                       cwd=tmp_path, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "meshes" / os.path.basename(obj)).read_text() == open(obj).read()
    drawn = {}  # each block's drawn polygon's area, m² (an LWPOLYLINE in mm)
    for block in set(blocks.values()):
        poly = [e for e in ezdxf.readfile(dxf).blocks.get(block) if e.dxftype() == "LWPOLYLINE"]
        p = np.array([pt[:2] for pt in poly[0].get_points()]) / 1000.0
        drawn[block] = 0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], 1)) -
                                 np.dot(p[:, 1], np.roll(p[:, 0], 1)))
    chk = subprocess.run([SINEW, "check", scene], capture_output=True, text=True)
    assert chk.returncode == 0, chk.stderr
    vt, areas, group = [], {}, None
    for line in open(obj):
        t = line.split()
        if t and t[0] == "vt":
            vt.append([float(t[1]), float(t[2])])
        elif t and t[0] == "g":
            group = t[1]
        elif t and t[0] == "f":
            a, b, c = (np.array(vt[int(k.split("/")[1]) - 1]) for k in t[1:4])
            e, f = b - a, c - a
            areas[group] = areas.get(group, 0.0) + 0.5 * (e[0] * f[1] - e[1] * f[0])
    assert sorted(areas) == sorted(blocks)
    for name, area in areas.items():  # (u,v) counter-clockwise: positive
        assert area == pytest.approx(drawn[blocks[name]], rel=5e-3), name
    assert len(re.findall(r"^seam ", chk.stdout, re.M)) == nseam
    assert "crossings   0 face pairs intersect at the start" in chk.stdout
    # the scene's landmarks (which its seams name: {corner: K}) are the skeleton's
    marks = r'^ *"?(\w+)"?: (\{corners: \[[^\]]*\](?:, notches: \[[^\]]*\])?\})$'
    shipped = re.findall(marks, open(scene).read(), re.M)
    assert len(shipped) == len(blocks)
    assert shipped == re.findall(marks, (tmp_path / "skel.yaml").read_text(), re.M)


def write_blocks(path, blocks):
    """An AAMA-style R12 file (inches, no units in it) of blocks, each placed once at the
    origin: {name: [(kind, data, layer)]}, kind 'poly' (closed), 'open', 'line', 'point',
    'text'."""
    import ezdxf
    doc = ezdxf.new("R12")
    for name, ents in blocks.items():
        b = doc.blocks.new(name)
        for kind, data, layer in ents:
            at = {"layer": str(layer)}
            if kind in ("poly", "open"):
                b.add_polyline2d(data, close=kind == "poly", dxfattribs=at)
            elif kind == "line":
                b.add_line(*data, dxfattribs=at)
            elif kind == "point":
                b.add_point(data, dxfattribs=at)
            else:
                b.add_text(data, dxfattribs=at)
        doc.modelspace().add_blockref(name, (0, 0))
    for var in ("$INSUNITS", "$MEASUREMENT"):
        if var in doc.header:
            del doc.header[var]
    doc.saveas(str(path))
    return str(path)


# A half front cut on the fold x = 0 (inches): its outline, area 10*24 - 4*4/2 = 232 in².
HALF = [(0, 0), (10, 0), (10, 20), (6, 24), (0, 24)]
HALF_AREA = 232 * IN * IN


def half_front(tmp_path, fold=((0, 0), (0, 24))):
    return write_blocks(tmp_path / "fold.dxf", {"FRONT": [
        ("poly", HALF, 1), ("line", fold, 6), ("line", ((3, 5), (3, 15)), 7),
        ("point", (10, 10), 4), ("point", (0, 24), 4), ("point", (5, 12), 13),
        ("point", (0, 0), 2), ("point", (0, 24), 2), ("line", ((2, 2), (8, 2)), 8),
        ("text", "Piece Name: Front", 1), ("text", "Quantity: 1", 1)]})


def xy_set(points, nd=9):
    return sorted(tuple(np.round(np.asarray(q) / IN, nd)) for q in points)


def test_a_piece_cut_on_the_fold_is_unfolded(tmp_path):
    """The half front and its mirror image about its mirror line are one piece of twice its
    area, its notches, drill hole, grain and internal lines mirrored; the fold is inside it
    (its two ends the only boundary vertices on it) and its two ends, turn points, are
    corners once each."""
    pat = pattern.read(half_front(tmp_path))
    p = pat.pieces[0]
    assert pattern.geometry.signed_area(p.boundary) == pytest.approx(2 * HALF_AREA, rel=1e-12)
    assert xy_set(p.boundary) == xy_set([(x * IN, y * IN) for x, y in HALF] +
                                        [(-x * IN, y * IN) for x, y in HALF if x != 0])
    assert xy_set(p.notches) == xy_set([(10 * IN, 10 * IN), (-10 * IN, 10 * IN),
                                        (0, 24 * IN)])
    assert xy_set(p.drills) == xy_set([(5 * IN, 12 * IN), (-5 * IN, 12 * IN)])
    assert [xy_set(g) for g in p.grains] == [xy_set([(3 * IN, 5 * IN), (3 * IN, 15 * IN)]),
                                             xy_set([(-3 * IN, 5 * IN), (-3 * IN, 15 * IN)])]
    assert xy_set(p.grain) == xy_set(p.grains[0])
    assert sorted(xy_set(ln) for ln in p.internal) == sorted(
        [xy_set([(2 * IN, 2 * IN), (8 * IN, 2 * IN)]),
         xy_set([(-2 * IN, 2 * IN), (-8 * IN, 2 * IN)])])
    assert xy_set(q for q, _ in p.turn_points) == xy_set([(0, 0), (0, 24 * IN)])
    assert xy_set(p.fold) == xy_set([(0, 0), (0, 24 * IN)])
    m = pattern.mesh(pat)[0]
    assert m.area == pytest.approx(2 * HALF_AREA, rel=1e-9)  # straight edges: exact
    on_fold = [v for v in m.boundary if abs(m.xy[v, 0]) < 1e-9]
    assert xy_set(m.xy[on_fold]) == xy_set([(0, 0), (0, 24 * IN)])
    # corners: the 3 of the half and their mirror images, and the fold's two ends
    assert xy_set(m.xy[m.corners]) == xy_set(
        [(s * x * IN, y * IN) for x, y in [(10, 0), (10, 20), (6, 24)] for s in (1, -1)] +
        [(0, 0), (0, 24 * IN)])
    assert len(m.notches) == 3 and len(m.drills) == 2 and len(m.internal) == 2


def test_a_mirror_line_off_the_boundary_is_refused(tmp_path, capsys):
    """A mirror line 5 in inside the piece (127 mm from the boundary at its middle), and one on
    the boundary's line but with the piece on both sides of it: refused, nothing written."""
    path = half_front(tmp_path, fold=((5, 0), (5, 24)))
    out = tmp_path / "out"
    assert main(["import", path, "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert path in err and "piece 'Front'" in err and "mirror line (layer 6" in err
    assert "does not lie on the boundary (up to 127 mm from it) (its cut line (layer 1))" \
        in err and "Traceback" not in err
    assert not out.exists()
    path = write_blocks(tmp_path / "both_sides.dxf", {"P": [
        ("poly", [(0, 0), (10, 0), (10, 10), (-3, 10), (-3, 5), (0, 5)], 1),
        ("line", ((0, 0), (0, 5)), 6)]})
    assert main(["import", path, "--out", str(out)]) == 1
    assert "the piece is on both sides of it (up to 76.2 and 254 mm)" in \
        capsys.readouterr().err
    assert not out.exists()


def wardrobe(tmp_path):
    """A front, a long sleeve (Quantity 2, placed once), a short sleeve (Quantity 0), a
    three-quarter sleeve (an alternate of the long one) and an upper and a lower collar."""
    sleeve = [(0, 0), (12, 0), (10, 8), (2, 6)]
    return write_blocks(tmp_path / "set.dxf", {
        "FR": [("poly", [(0, 0), (20, 0), (20, 24), (0, 24)], 1),
               ("text", "Piece Name: Front", 1), ("text", "Quantity: 1", 1)],
        "SL": [("poly", sleeve, 1), ("point", (11, 4), 4), ("line", ((4, 2), (8, 2)), 7),
               ("text", "Piece Name: Sleeve", 1), ("text", "Category: SLEEVE LONG", 1),
               ("text", "Quantity: 2", 1)],
        "SS": [("poly", [(0, 0), (12, 0), (11, 4), (1, 4)], 1),
               ("text", "Piece Name: Short Sleeve", 1), ("text", "Category: SLEEVE SHORT", 1),
               ("text", "Quantity: 0", 1)],
        "S3": [("poly", [(0, 0), (12, 0), (10, 6), (2, 6)], 1),
               ("text", "Piece Name: Sleeve 34", 1), ("text", "Category: SLEEVE 3/4", 1),
               ("text", "Quantity: 2", 1)],
        "C1": [("poly", [(0, 0), (16, 0), (16, 3), (0, 3)], 1),
               ("text", "Piece Name: Collar1", 1), ("text", "Category: UPPER COLLAR", 1)],
        "C2": [("poly", [(0, 0), (16, 0), (16, 2.5), (0, 2.5)], 1),
               ("text", "Piece Name: Collar2", 1), ("text", "Category: LOWER COLLAR", 1)]})


def test_quantity_two_makes_a_mirrored_second_piece(tmp_path):
    pat = pattern.read(wardrobe(tmp_path))
    a, b = [p for p in pat.pieces if p.name == "Sleeve"]
    assert (a.copy, a.mirrored, b.copy, b.mirrored) == (1, False, 2, True)
    assert a.category == b.category == "SLEEVE"
    sa = pattern.geometry.signed_area
    assert sa(a.boundary) == pytest.approx(sa(b.boundary), rel=1e-12) and sa(b.boundary) > 0
    # the copy is the mirror image x -> c - x (c = 2 * 12 in + 5 cm, beside the first):
    # mapped back, its boundary is the first's in reverse order (the mirror image turned the
    # other way, then reversed to counter-clockwise)
    c = 24 * IN + 0.05
    back = np.column_stack([c - b.boundary[:, 0], b.boundary[:, 1]])
    assert sa(back) < 0   # the mirror image runs clockwise: the copy was reversed
    rev = back[::-1]
    k = int(np.argmin(np.hypot(*(rev - a.boundary[0]).T)))
    assert np.allclose(np.roll(rev, -k, axis=0), a.boundary, atol=1e-12)
    assert np.allclose(b.notches, [(c - 11 * IN, 4 * IN)], atol=1e-12)
    assert np.allclose(b.grain, [(c - 4 * IN, 2 * IN), (c - 8 * IN, 2 * IN)], atol=1e-12)
    meshed = {m.group: m for m in pattern.mesh(pat, edge=0.05)}
    assert sorted(meshed) == ["Collar1", "Collar2", "Front", "Sleeve", "Sleeve_2"]
    assert meshed["Sleeve"].area == pytest.approx(meshed["Sleeve_2"].area, rel=1e-9)
    assert meshed["Sleeve"].area == pytest.approx(sa(a.boundary), rel=1e-9)


def test_quantity_zero_and_alternates_are_listed_and_chosen_by_pieces(tmp_path, capsys):
    path = wardrobe(tmp_path)
    pat = pattern.read(path)
    chosen, _ = pattern.select(pat)
    why = {p.group: p.excluded for p in pat.pieces}
    assert why["Short_Sleeve"] == "Quantity 0"
    assert why["Sleeve_34"] == "alternate of 'Sleeve' (category SLEEVE)"
    assert why["Sleeve_34_2"] == why["Sleeve_34"] and why["Collar2"] is None
    assert [p.group for p in chosen] == ["Front", "Sleeve", "Sleeve_2", "Collar1", "Collar2"]
    assert main(["import", path, "--list"]) == 0
    out = capsys.readouterr().out
    assert "Short Sleeve: block 'SS', size -, quantity 0, category SLEEVE, copy 1, " \
           "not imported: Quantity 0" in out
    assert "pieces: 8; size -: 5 imported" in out
    by_name = [m.group for m in pattern.mesh(pat, edge=0.05, pieces="short_sleeve")]
    assert by_name == ["Short_Sleeve"]
    by_category = [m.group for m in pattern.mesh(pat, edge=0.05, pieces="Sleeve, front")]
    assert by_category == ["Front", "Sleeve", "Sleeve_2", "Short_Sleeve", "Sleeve_34",
                           "Sleeve_34_2"]
    out_dir = tmp_path / "out"
    assert main(["import", path, "--pieces", "Front,nomatch", "--out", str(out_dir)]) == 1
    err = capsys.readouterr().err
    assert "--pieces Front,nomatch: no piece" in err and "'nomatch'" in err
    assert "Short_Sleeve" in err and "SLEEVE" in err and path in err
    assert not out_dir.exists()
    assert main(["import", path, "--list", "--pieces", "nomatch"]) == 1  # listed, then refused
    assert "pieces: 8; size -: 0 imported" in capsys.readouterr().out


def test_a_cutting_annotation_counts_pieces(tmp_path):
    """`Annotation: 2XFABRIC` (cut two in the fabric) on a piece of `Quantity: 1` makes a
    left and a right, as Gerber's polo sleeves are marked; "1XRIB" leaves one; "10X2" (no
    material: not a count) and no annotation leave the Quantity; `Quantity: 3` wins over
    "2XFABRIC"; a Quantity 0 piece asked for by name makes its annotation's count."""
    sq = [(0, 0), (4, 0), (4, 4), (0, 4)]
    blocks = {}
    for name, q, note in [("SL", 1, "2XFABRIC"), ("CO", 1, "1XRIB"), ("BI", 1, "10X2"),
                          ("PL", 1, None), ("PO", 3, "2XFABRIC"), ("CU", 0, "2XRIB")]:
        ents = [("poly", sq, 1), ("text", "Piece Name: %s" % name, 1),
                ("text", "Quantity: %d" % q, 1)]
        if note:
            ents.append(("text", "Annotation: %s" % note, 1))
        blocks[name] = ents
    path = write_blocks(tmp_path / "notes.dxf", blocks)
    pat = pattern.read(path)
    count = {}
    for p in pat.pieces:
        count[p.name] = count.get(p.name, 0) + 1
    assert count == {"SL": 2, "CO": 1, "BI": 1, "PL": 1, "PO": 3, "CU": 2}
    a, b = [p for p in pat.pieces if p.name == "SL"]
    assert (a.mirrored, b.mirrored) == (False, True)
    chosen, _ = pattern.select(pat)
    assert [p.group for p in chosen] == ["SL", "SL_2", "CO", "BI", "PL", "PO", "PO_2", "PO_3"]
    chosen, _ = pattern.select(pat, None, "CU")
    assert [p.group for p in chosen] == ["CU", "CU_2"]


def test_an_open_sew_line_falls_back_to_the_cut_line(tmp_path, capsys):
    path = write_blocks(tmp_path / "open_sew.dxf", {"P": [
        ("poly", [(0, 0), (10, 0), (10, 10), (0, 10)], 1),
        ("open", [(1, 1), (9, 1), (9, 9), (1, 9)], 14), ("text", "Piece Name: Yoke", 1)]})
    out = tmp_path / "out"
    assert main(["import", path, "--out", str(out), "--edge", "0.05"]) == 0
    err = capsys.readouterr().err
    assert re.search(r"warning: piece 'Yoke' \(block 'P'.*its sew line \(layer 14\) is open"
                     r".*the cut line \(layer 1\) is used instead", err)
    p = pattern.read(path).pieces[0]
    assert p.boundary_from == "cut line (layer 1)"
    assert pattern.geometry.signed_area(p.boundary) == pytest.approx(100 * IN * IN, rel=1e-12)
    assert sorted(os.listdir(out)) == ["open_sew.obj", "open_sew.yaml"]


@pytest.mark.parametrize("text,name,category", [
    ("FRONT G", "X", "FRONT"), ("GMX1006S16BK", "GMX1006S18BK", "BACK"),
    ("SLEEVE WITH CUFF", "", "SLEEVE"), ("SLEEVE CUFF", "", "CUFF"),
    ("CREWNECKRIBG", "", "COLLAR"), ("PLACKET U_INTERLIN", "", "INTERLINING"),
    ("HOOD FACING 2P", "", "FACING"), ("P1", "ORILEG WB WB", "WAISTBAND"),
    ("LENGTH OPTIONS", "ORILEG WB LL", ""), ("", "Pocket", "POCKET"), ("", "11", "")])
def test_categories(text, name, category):
    assert pattern.category_of(text, name) == category


def test_a_sew_line_open_along_its_fold_is_closed_there(tmp_path, capsys):
    """A half piece whose sew line stops at the fold (nothing is sewn there): closed along the
    mirror line and unfolded, the sew line's whole, 18 x 8 in; no warning.  Its notch on the
    cut line is moved onto the sew line, and mirrored."""
    path = write_blocks(tmp_path / "fold_sew.dxf", {"P": [
        ("poly", [(0, 0), (10, 0), (10, 10), (0, 10)], 1), ("line", ((0, 0), (0, 10)), 6),
        ("open", [(0, 1), (9, 1), (9, 9), (0, 9)], 14), ("point", (10, 5), 4),
        ("text", "Piece Name: Yoke", 1)]})
    p = pattern.read(path).pieces[0]
    assert p.boundary_from == "sew line (layer 14), closed along its mirror line"
    assert pattern.geometry.signed_area(p.boundary) == pytest.approx(144 * IN * IN, rel=1e-12)
    assert xy_set(p.notches) == xy_set([(9 * IN, 5 * IN), (-9 * IN, 5 * IN)])
    assert p.warnings == []
    assert main(["import", path, "--out", str(tmp_path / "o"), "--edge", "0.05"]) == 0
    assert "warning" not in capsys.readouterr().err
