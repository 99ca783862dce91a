"""Automatic sewing (sinew.pattern.sew) and `sinew garment`: the proposals for the project's
generated tank and T-shirt patterns (tools/make_garment.py --dxf) are the hand-written seams of
scenes/garment_tshirt_dxf.yaml and scenes/garment_tank.yaml (same pairs, same directions); the
generated T-shirt fits through `sinew garment` closed and with nothing crossing; bad inputs
give a message and write nothing."""
import os
import subprocess
import sys

import pytest
import yaml

pytest.importorskip("ezdxf")
pytest.importorskip("gmsh")
from sinew import garment, pattern  # noqa: E402
from sinew.pattern import sew  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TEE = os.path.join(ROOT, "scenes", "patterns", "garment_tshirt.dxf")
MAKE = os.path.join(ROOT, "tools", "make_garment.py")


def proposal(path, edge=0.02):
    return sew.propose(sew.upright(pattern.mesh(pattern.read(path), edge=edge)))


def as_tuples(seams):
    return [(s.name, (s.a.panel, s.a.start.yaml(), s.a.end.yaml()),
             (s.b.panel, s.b.start.yaml(), s.b.end.yaml())) for s in seams]


def ref(e):
    return "{%s: %d}" % next(iter(e.items()))


def hand_written(scene):
    with open(os.path.join(ROOT, "scenes", scene)) as f:
        doc = yaml.safe_load(f)
    return [(s["name"], (s["a"]["panel"], ref(s["a"]["from"]), ref(s["a"]["to"])),
             (s["b"]["panel"], ref(s["b"]["from"]), ref(s["b"]["to"]))) for s in doc["seams"]]


@pytest.fixture(scope="module")
def tank_dxf(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("tank") / "garment_tank.dxf")
    subprocess.run([sys.executable, MAKE, "tank", "--dxf", path], check=True,
                   stdout=subprocess.DEVNULL)
    return path


def test_tshirt_proposal_is_the_hand_written_seams():
    seams = proposal(TEE)
    assert as_tuples(seams) == hand_written("garment_tshirt_dxf.yaml")
    # the armholes: front armhole against half the cap (make_garment.py solves the cap's height
    # for equal lengths: they agree to the meshing's chords)
    for s in seams:
        assert s.mismatch < 0.005, s


def test_tank_proposal_is_the_hand_written_seams(tank_dxf):
    """The tank's DXF has the T-shirt's body outline (make_garment.py top_outline): its seams are
    the T-shirt's shoulders and sides, named and ordered as scenes/garment_tank.yaml's."""
    seams = as_tuples(proposal(tank_dxf))
    assert seams == hand_written("garment_tshirt_dxf.yaml")[:4]
    tank = yaml.safe_load(open(os.path.join(ROOT, "scenes", "garment_tank.yaml")))
    assert [s[0] for s in seams] == [s["name"] for s in tank["seams"]]


def test_lengths_checked_against_the_ease(tank_dxf):
    """A tank's front with a T-shirt's back: shoulders of 5 cm against 10 cm."""
    fr = [m for m in pattern.mesh(pattern.read(tank_dxf)) if m.group == "Front"]
    bk = [m for m in pattern.mesh(pattern.read(TEE)) if m.group == "Back"]
    with pytest.raises(sew.SewError) as e:
        sew.propose(fr + bk)
    msg = str(e.value)
    assert "right_shoulder: Front corner 8-corner 7 0.05 m against Back corner 3-corner 4 " \
           "0.1 m (100.0 %)" in msg
    assert "right_side" not in msg  # the sides (27.5 and 30 cm, 9.1 %) are within the ease


def test_upright_turns_a_piece_drawn_upside_down():
    ms = pattern.mesh(pattern.read(TEE))
    turned = [m if m.group != "Back" else
              type(m)(**{**m.__dict__, "uv": -m.uv}) for m in ms]
    back = sew.upright(turned)[1]
    assert (back.uv == ms[1].uv).all()
    assert as_tuples(sew.propose(sew.upright(turned))) == as_tuples(sew.propose(ms))


def test_given_seams_replace_proposed_ones():
    seams = proposal(TEE)
    text = sew.seams_yaml(seams, [("left_side", '{"name": "left_side", "a": 1}'),
                                  ("extra", '{"name": "extra"}')])
    doc = yaml.safe_load(text)["seams"]
    assert [s["name"] for s in doc] == [s.name for s in seams] + ["extra"]
    assert doc[3] == {"name": "left_side", "a": 1}


def test_garment_fits_the_tshirt(tmp_path, capsys):
    """sinew garment on the generated T-shirt at 4 cm edges (about 5 s): fitted, the seams
    closed to under 1 mm, nothing crossing the body or itself."""
    out = tmp_path / "tee"
    assert garment.main([TEE, "--out", str(out), "--edge", "0.04", "--quiet"]) == 0
    s = yaml.safe_load(open(out / "run" / "summary.json"))
    assert s["status"] == "ok"
    assert s["seam_gap_max"] < 1e-3
    assert s["self_intersections"] == 0 and s["obstacle_intersections"] == 0
    text = capsys.readouterr().out
    assert "status ok" in text and "Sleeve_2" in text
    scene = yaml.safe_load(open(out / "scene.yaml"))
    assert len(scene["seams"]) == 10
    # the --sizes outputs of two results: a table row per size and piece, one picture
    tension, last, sc = garment.tension_per_piece(str(out / "run"), str(out / "scene.yaml"))
    res = {"summary": s, "cpu_s": 1.0, "tension": tension, "last": last, "scene": sc}
    rows = garment.sizes_table([dict(res, size="S"), dict(res, size="M")]).splitlines()
    assert len(rows) == 2 + 2 * 4 and rows[2].startswith("| S | Front | ")
    garment.sizes_picture([dict(res, size="S"), dict(res, size="M")], str(tmp_path / "s.png"))
    assert open(tmp_path / "s.png", "rb").read(8) == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("args, message", [
    (["--size", "XL"], "no size 'XL'; expected one of: (the file is not graded)"),
    (["--pieces", "Front,Nope"], "no piece is named 'Nope'"),
    (["--pieces", "Front,Back,Sleeve_2"], "two SLEEVE pieces or none; found 1 (Sleeve_2)"),
    (["--seams", "/nonexistent.yaml"], "--seams /nonexistent.yaml: No such file"),
    (["--fabric", "{mass: -150}", "--edge", "0.08"], "failed before its first step (exit 1)"),
])
def test_bad_inputs_write_nothing(tmp_path, capsys, args, message):
    out = tmp_path / "x"
    assert garment.main([TEE, "--out", str(out), "--quiet"] + args) == 1
    assert message in capsys.readouterr().err
    assert not out.exists() and os.listdir(tmp_path) == []


def test_unsewable_pieces_write_nothing(tmp_path, capsys):
    """The four-panel skirt: two FRONT and two BACK pieces, no top to sew."""
    skirt = os.path.join(ROOT, "scenes", "patterns", "garment_skirt.dxf")
    assert garment.main([skirt, "--out", str(tmp_path / "x"), "--quiet"]) == 1
    assert "one FRONT and one BACK piece; found 2 FRONT, 2 BACK" in capsys.readouterr().err
    assert os.listdir(tmp_path) == []


def test_sinew_garment_runs_the_module():
    """`sinew garment` (sim/cli/render.c) runs python -m sinew.garment."""
    exe = os.environ.get("SINEW_EXE", os.path.join(ROOT, "build", "sinew"))
    r = subprocess.run([exe, "garment", "--help"], capture_output=True, text=True)
    assert r.returncode == 0 and "usage: sinew garment" in r.stdout and "--sizes" in r.stdout
