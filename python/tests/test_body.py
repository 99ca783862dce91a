"""sinew.body and the arrangement of `sinew garment` on it: a body generated from measurements
reads its girths under a tape measure (1 %), is closed, outward and does not cross itself, its
arms are as long as asked and its landmarks where they are named; the tops' pieces placed from
the landmarks lie on their side of the body and cross nothing (the scene loader's exact check
and an independent one here); inconsistent measurements and tables are refused, nothing
written."""
import os

import numpy as np
import pytest

from sinew import body as sb
import test_mannequin
from test_mannequin import edge_crosses_triangle, tape_measure

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TEE = os.path.join(ROOT, "scenes", "patterns", "garment_tshirt.dxf")
WOMEN = "height: 1.68, bust: 0.88, waist: 0.70, hip: 0.95, arm: 0.58, sex: women"
MEN = "height: 1.82, chest: 1.02, waist: 0.88, hip: 1.00, arm: 0.63, sex: men"


@pytest.fixture(scope="module", params=[WOMEN, MEN])
def made(request):
    m = sb.parse(request.param)
    verts, tris, marks = sb.body_mesh(m)
    return m, verts, tris, marks


def torso(tris):
    return tris[np.all(tris < 32 * 30 + 2, axis=1)]


def test_girths(made):
    m, verts, tris, _ = made
    for frac, girth in ((sb.BUST, m.bust), (sb.WAIST, m.waist), (sb.HIP, m.hip)):
        assert tape_measure(verts, torso(tris), frac * m.height) == pytest.approx(girth, rel=0.01)


def test_closed_outward_not_crossing(made):
    m, verts, tris, _ = made
    directed = set(map(tuple, np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])))
    assert len(directed) == 3 * len(tris) and all((j, i) in directed for i, j in directed)
    a, b, c = verts[tris[:, 0]], verts[tris[:, 1]], verts[tris[:, 2]]
    assert np.einsum("ij,ij->i", a, np.cross(b, c)).sum() > 0
    test_mannequin.test_does_not_cross_itself((None, verts, tris))
    assert verts[:, 2].max() == pytest.approx(m.height)


def test_landmarks(made):
    m, verts, tris, mk = made
    h, t = m.height, torso(tris)
    ring = verts[:32 * 30]
    # the centre front and back: on the mesh, the section's most forward and backward points
    for level, frac in (("bust", sb.BUST), ("waist", sb.WAIST)):
        sec = ring[np.abs(ring[:, 2] - frac * h) < 1e-12]
        assert len(sec) == 32
        assert mk["front_" + level] == pytest.approx((0, sec[:, 1].min(), frac * h), abs=1e-12)
        assert mk["back_" + level] == pytest.approx((0, sec[:, 1].max(), frac * h), abs=1e-12)
    # the shoulder points: the torso's outermost points at the shoulder's height, left at +x
    for side, s in (("left", 1), ("right", -1)):
        x, y, z = mk[side + "_shoulder"]
        assert z == pytest.approx(sb.SHOULDER * h) and s * x > 0.15 * h / 1.7
        e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
        p, q = verts[e[:, 0]], verts[e[:, 1]]
        cut = (p[:, 2] - z) * (q[:, 2] - z) < 0
        u = (z - p[cut, 2]) / (q[cut, 2] - p[cut, 2])
        xs = p[cut, 0] + u * (q[cut, 0] - p[cut, 0])
        assert s * x == pytest.approx((s * xs).max(), abs=1e-9)
    # neck base above the shoulders, below the head; arms: every vertex at its ring's radius
    # about the stated axis, as long as asked (cap to wrist) plus the hand
    assert sb.SHOULDER * h < mk["neck_base"][2] < 0.9 * h
    n = (len(verts) - (32 * 30 + 2)) // 2
    for side, k, s in (("left", 32 * 30 + 2, 1), ("right", 32 * 30 + 2 + n, -1)):
        top, d = np.array(mk[side + "_arm"]), np.array(mk[side + "_arm_direction"])
        arm = verts[k:k + n] - top
        along = arm @ d
        radial = np.linalg.norm(arm - np.outer(along, d), axis=1)
        for a in np.unique(np.round(along, 6)):
            r = radial[np.abs(along - a) < 1e-6]
            assert np.ptp(r) < 1e-9
        assert s * d[0] > 0 and d[2] < 0 and s * top[0] > 0
        assert mk[side + "_arm_length"] == pytest.approx(m.arm + (0.39 - sb.WRIST) * h)
        wrist = np.unique(np.round(along, 9))[-5]   # ..., the wrist, three hand rings, the tip
        assert wrist == pytest.approx(m.arm, abs=1e-9)


def test_landmarks_give_the_mannequins_arrangement():
    """The rule of sinew garment's arrangement points, on the shipped mannequin's measurements
    (its arm 0.30 of the height), gives the points used for it."""
    from sinew import garment
    m = sb.Measurements(1.70, 0.88, 0.70, 0.96, 0.30 * 1.70)
    pts = garment.Points.of(sb.body_mesh(m)[2], 1.70)
    assert pts.top == pytest.approx(garment.TOP, abs=1e-12)
    for s in (1, -1):
        assert pts.arms[s][0] == pytest.approx(garment.MANNEQUIN.arms[s][0], abs=1e-6)
        assert pts.arms[s][1] == pytest.approx(garment.MANNEQUIN.arms[s][1], abs=1e-6)


@pytest.mark.parametrize("text, message", [
    ("height: 1.68, bust: 0.80, waist: 1.10, hip: 0.95, arm: 0.58, sex: women",
     "waist 1.1 m against bust 0.8 m and hip 0.95 m: expected the waist at most 1.15"),
    ("height: 1.68, bust: -0.88, waist: 0.70, hip: 0.95, arm: 0.58, sex: women",
     "bust -0.88: expected a positive length in m"),
    ("height: 1.68, bust: 0.88, waist: 0.70, hip: 0.95, arm: 1.80, sex: women",
     "arm 1.8 m: expected the shoulder point to the wrist between 0.25 and 0.45 times"),
    ("height: 1.68, bust: 0.88, waist: 0.70, hip: 0.95, arm: 0.58, sex: other",
     "sex 'other': expected women or men"),
    ("height: 1.68, bust: 0.88, waist: 0.70, hip: 0.95, sex: women", "missing arm"),
    ("height: 1.68, bust: 0.88, chest: 0.9, waist: 0.70, hip: 0.95, arm: 0.58, sex: men",
     "both bust and chest"),
    ("height: 1.68, bust: 0.88, waist: 0.70, hips: 0.95, arm: 0.58, sex: women",
     "unknown key hips"),
    ("height: 17, bust: 0.88, waist: 0.70, hip: 0.95, arm: 0.58, sex: women",
     "height 17 m: expected 1.0 to 2.5 m"),
])
def test_bad_measurements(text, message):
    with pytest.raises(sb.BodyError) as e:
        sb.parse(text)
    assert message in str(e.value)


def test_tables(tmp_path):
    csv = tmp_path / "t.csv"
    csv.write_text("# an example\nsize,height,bust,waist,hip,arm,sex\n"
                   "S,1.64,0.84,0.66,0.91,0.57,women\nM,1.68,0.88,0.70,0.95,0.58,women\n")
    t = sb.read_table(str(csv))
    assert list(t) == ["S", "M"] and t["M"] == sb.parse(WOMEN)
    yml = tmp_path / "t.yaml"
    yml.write_text("S: {height: 1.64, bust: 0.84, waist: 0.66, hip: 0.91, arm: 0.57, "
                   "sex: women}\n36: {%s}\n" % WOMEN)
    assert sb.read_table(str(yml))["36"] == sb.parse(WOMEN)
    csv.write_text("size,height,bust,waist,hip,arm,sex\nS,1.64,0.84,o.66,0.91,0.57,women\n")
    with pytest.raises(sb.BodyError, match=r"t.csv:2:13: waist 'o.66': expected a length"):
        sb.read_table(str(csv))
    yml.write_text("S: {height: 1.64, bust: 0.84, waist: 0.66, hip: 0.91, arm: 0.57}\n"
                   "M: {height: 1.68, bust: 0.88, waist: 1.70, hip: 0.95, arm: 0.58, "
                   "sex: women}\n")
    with pytest.raises(sb.BodyError, match=r"t.yaml:1:1: size S: missing sex"):
        sb.read_table(str(yml))


def _pieces_outside(verts, tris, x, faces):
    """No edge of the pieces crosses a body triangle, no body edge a piece's triangle."""
    def cross(pv, pe, qv, qt):
        lo, hi = qv[qt].min(axis=1), qv[qt].max(axis=1)
        for e in pe:
            p, q = pv[e[0]], pv[e[1]]
            k = np.nonzero(np.all((lo <= np.maximum(p, q)) & (hi >= np.minimum(p, q)),
                                  axis=1))[0]
            if len(k) and edge_crosses_triangle(
                    np.tile(p, (len(k), 1)), np.tile(q, (len(k), 1)),
                    qv[qt[k, 0]], qv[qt[k, 1]], qv[qt[k, 2]]).any():
                return True
        return False

    def edges(t):
        return np.unique(np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]),
                                 axis=1), axis=0)
    return not cross(x, edges(faces), verts, tris) and not cross(verts, edges(tris), x, faces)


@pytest.mark.parametrize("text", [WOMEN, MEN])
def test_arrangement_from_landmarks(tmp_path, text):
    """The T-shirt's pieces placed on each body: the scene loads (its arrangement checked
    exactly against the body and between pieces), the front in front of the body (-y), the back
    behind it, each sleeve round its own arm beyond the arm's radius, nothing crossing."""
    pytest.importorskip("ezdxf")
    pytest.importorskip("gmsh")
    import sinew
    from sinew import garment
    from sinew.pattern.write import obj_text
    m = sb.parse(text)
    verts, tris, mk = sb.body_mesh(m)
    meshed, seams, positions = garment.build(TEE, None, 0.04)
    pts = garment.Points.of(mk, m.height)
    (tmp_path / "body.obj").write_text(sb.obj_text(verts, tris, mk, m))
    assert sb.read_landmarks(str(tmp_path / "body.obj")) == mk
    (tmp_path / "pieces.obj").write_text(obj_text(meshed, positions, ["t"]))
    (tmp_path / "s.yaml").write_text(garment.scene_text(meshed, seams, "t", None, 0.04,
                                                        body="body.obj", pts=pts, measured=m)
                                     + "fit: {enabled: false}\n")   # the arranged start only
    sim = sinew.load(str(tmp_path / "s.yaml"))
    x, faces = np.array(sim.initial_positions), np.array(sim.faces)
    first = np.cumsum([0] + [len(p.xy) for p in meshed])
    left = {s.b.panel for s in seams if s.name == "left_armhole_front"}
    for p, a, b in zip(meshed, first[:-1], first[1:]):
        v = x[a:b]
        if p.group in ("Front", "Back"):   # wrapped round its half, centred on its side
            s = -1 if p.group == "Front" else 1
            assert (s * v[:, 1] > 0).all() and abs(v[:, 0].min() + v[:, 0].max()) < 1e-6
            assert s * v[:, 1].max(initial=-1, where=np.abs(v[:, 0]) < 0.02) \
                > s * mk[("front" if s < 0 else "back") + "_bust"][1]
        else:
            side = "left" if p.group in left else "right"
            top, d = np.array(mk[side + "_arm"]), np.array(mk[side + "_arm_direction"])
            rel = v - top
            r = np.linalg.norm(rel - np.outer(rel @ d, d), axis=1)
            # one radius (to the 6 digits the scene gives the axis in), beyond the upper arm
            assert np.ptp(r) < 2e-5 and r.min() > 0.029 * m.height
            assert (np.sign(v[:, 0]) == (1 if side == "left" else -1)).all()
            assert ((rel @ d) > -2e-5).all()   # from the cap down the arm
    assert _pieces_outside(verts, tris, x, faces)
    assert not _pieces_outside(verts, tris, x + [0, 0.05, 0], faces)  # the front in the chest


@pytest.fixture(scope="module")
def tank_dxf(tmp_path_factory):
    import subprocess
    import sys
    path = str(tmp_path_factory.mktemp("tank") / "garment_tank.dxf")
    subprocess.run([sys.executable, os.path.join(ROOT, "tools", "make_garment.py"), "tank",
                    "--dxf", path], check=True, stdout=subprocess.DEVNULL)
    return path


def test_tank_fits_a_body_of_its_size(tmp_path, tank_dxf):
    """The generated tank (cut 7 % under a 0.88 m bust) through sinew garment --body on a
    women's body of bust 0.88 m at 4 cm edges: fitted, seams closed, nothing crossing."""
    pytest.importorskip("ezdxf")
    pytest.importorskip("gmsh")
    import yaml
    from sinew import garment
    out = tmp_path / "tank"
    assert garment.main([tank_dxf, "--out", str(out), "--edge", "0.04", "--quiet",
                         "--body", WOMEN]) == 0
    s = yaml.safe_load(open(out / "run" / "summary.json"))
    assert s["status"] == "ok" and s["seam_gap_max"] < 1e-3
    assert s["self_intersections"] == 0 and s["obstacle_intersections"] == 0
    scene = yaml.safe_load(open(out / "scene.yaml"))
    assert scene["obstacles"] == [{"mesh": "body.obj"}]
    assert sb.read_landmarks(str(out / "body.obj"))["front_bust"][2] == pytest.approx(
        sb.BUST * 1.68)


@pytest.mark.parametrize("args, message", [
    (["--body", "height: 1.68, bust: 0.80, waist: 1.10, hip: 0.95, arm: 0.58, sex: women"],
     "--body: waist 1.1 m against bust 0.8 m"),
    (["--body", "height: 1.68, bust"], "--body: missing waist, hip, arm, sex"),
    (["--body", "height: [1.68"], "--body 'height: [1.68': not a mapping"),
    (["--body-table", os.path.join(ROOT, "scenes", "patterns", "body_sizes_example.csv")],
     "is not graded (no sizes to look up); give its body with --body"),
    (["--body-table", "/nonexistent.csv"], "--body-table /nonexistent.csv: No such file"),
    (["--arrange", "/nonexistent.yaml"], "--arrange /nonexistent.yaml: No such file"),
])
def test_bad_bodies_write_nothing(tmp_path, capsys, args, message):
    pytest.importorskip("ezdxf")
    pytest.importorskip("gmsh")
    from sinew import garment
    out = tmp_path / "x"
    assert garment.main([TEE, "--out", str(out), "--quiet"] + args) == 1
    assert message in capsys.readouterr().err
    assert os.listdir(tmp_path) == []


def test_arrange_overrides(tmp_path):
    pytest.importorskip("ezdxf")
    pytest.importorskip("gmsh")
    from sinew import garment
    meshed, seams, _ = garment.build(TEE, None, 0.04)
    lines = garment.arrangement(meshed, seams, given={"Back": '{"rigid": {"translate": [0, 1, 1]}}'})
    assert lines[1] == '  "Back": {"rigid": {"translate": [0, 1, 1]}}    # given'
    assert lines[0] == garment.arrangement(meshed, seams)[0]
    with pytest.raises(garment.GarmentError, match="--arrange: no piece Nope; expected one of: "
                       "Front, Back, Sleeve, Sleeve_2"):
        garment.arrangement(meshed, seams, given={"Nope": "{}"})
