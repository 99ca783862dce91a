"""The Python package sinew against `sinew run`: the same scene stepped from Python gives the
same positions, tension XY and tendon tension to the last bit, with a rest length changed
between steps too; views, errors, every method, the run folder."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import sinew

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "scenes", "cloth_drawstring.yaml")
SINEW = os.environ.get("SINEW_EXE", os.path.join(ROOT, "build", "sinew"))
REST_LINE = ("    rest_length: {keyframes: [[0, 1.0], [1.5, 0.5]], relative: true, "
             "interpolation: smooth}")


def scene_with_rest(tmp_path, rest):
    """cloth_drawstring.yaml with the drawstring's rest_length line replaced by `rest`."""
    text = open(SCENE).read()
    assert REST_LINE in text
    path = tmp_path / "scene.yaml"
    path.write_text(text.replace(REST_LINE, "    rest_length: " + rest))
    return str(path)


def sinew_run(scene, out, duration):
    """`sinew run` of scene to duration with every step's positions; (times, positions,
    tendons.csv tension per step, tension.csv rows)."""
    subprocess.run([SINEW, "run", scene, "--out", str(out), "--duration", str(duration),
                    "--positions-every", "0.01", "--no-frames", "--quiet"], check=True)
    raw = open(out / "positions.bin", "rb").read()
    nv, dim = np.frombuffer(raw[8:16], dtype=np.int32)
    recs = np.frombuffer(raw[16:], dtype=np.float64).reshape(-1, 1 + nv * dim)
    tendons = np.genfromtxt(out / "tendons.csv", delimiter=",", names=True, dtype=None,
                            encoding=None)
    tension = np.genfromtxt(out / "tension.csv", delimiter=",", names=True)
    return recs[:, 0], recs[:, 1:].reshape(-1, nv, dim), tendons["tension"], tension


def compare_steps(sim, times, xs, tendon_tension, txy, change=None):
    """Step sim through every logged time and compare with sinew run's logs."""
    string = sim.tendons["drawstring"]
    for k in range(len(times)):
        if k:
            if change:
                change(sim, string)
            sim.step()
        assert sim.time == times[k]
        assert np.array_equal(sim.positions, xs[k])
        assert string.tension == tendon_tension[k]
        assert sim.tension_xy.max() == txy["txy_max"][k]
        assert sim.tension_xy.mean() == pytest.approx(txy["txy_mean"][k], rel=1e-13)


def test_stepping_is_sinew_run(tmp_path):
    times, xs, tt, txy = sinew_run(SCENE, tmp_path / "run", 0.3)
    assert len(times) == 31
    compare_steps(sinew.load(SCENE), times, xs, tt, txy)


def test_rest_change_between_steps_is_sinew_run(tmp_path):
    """Rest 1 (relative) to t = 0.1, then 0.8: the scene whose keyframes jump there between
    two steps (backward Euler evaluates the rest length only at the ends of its steps)."""
    jump = scene_with_rest(tmp_path, "{keyframes: [[0, 1.0], [0.1, 1.0], [0.105, 0.8]], "
                                     "relative: true}")
    times, xs, tt, txy = sinew_run(jump, tmp_path / "run", 0.3)
    sim = sinew.load(scene_with_rest(tmp_path, "{keyframes: [[0, 1.0]], relative: true}"))
    l0 = sim.tendons["drawstring"].rest_length

    def change(sim, string):
        if abs(sim.time - 0.1) < 1e-12:
            string.rest_length = 0.8 * l0
    compare_steps(sim, times, xs, tt, txy, change)
    assert sim.tendons["drawstring"].rest_length == 0.8 * l0
    assert sim.tendons["drawstring"].tension > 5.0  # N: the string gathers the hem


def test_views_follow_and_are_read_only():
    sim = sinew.load(SCENE)
    x, txy = sim.positions, sim.tension_xy
    assert x.shape == (sim.nv, 3) and txy.shape == (sim.nfaces,)
    before = x.copy()
    sim.step(3)
    assert not np.array_equal(x, before)          # the same memory, moved on
    assert np.array_equal(x, sim.positions)
    with pytest.raises(ValueError):
        x[0, 0] = 1.0
    assert np.all(sim.masses > 0) and sim.pinned.sum() == 21
    assert sim.faces.shape == (sim.nfaces, 3)
    e = sim.energy
    assert e["total"] == pytest.approx(e["kinetic"] + e["potential"])
    assert e["potential"] == pytest.approx(sum(v for k, v in e.items() if k.startswith("E_")))
    assert sim.counters["nstep"] == 3


def test_set_state_and_pins():
    sim = sinew.load(SCENE)
    sim.step(5)
    x, v, t = sim.positions.copy(), sim.velocities.copy(), sim.time
    sim.step(5)
    after = sim.positions.copy()
    sim.set_state(time=t, positions=x, velocities=v)
    assert sim.time == t and np.array_equal(sim.positions, x)
    sim.step(5)
    assert np.array_equal(sim.positions, after)     # backward Euler: no history
    top = np.flatnonzero(sim.pinned)[0]
    p = sim.positions[top] + [0.0, 0.1, 0.0]
    sim.set_pin(top, p)
    assert np.array_equal(sim.positions[top], p)
    sim.step()
    assert np.array_equal(sim.positions[top], p)


@pytest.mark.parametrize("method", [m for m in sinew.methods() if m != "static"])
def test_every_method_steps_and_changes(method):
    dt = 2e-4 if method == "symplectic-euler" else 0.01
    sim = sinew.load(SCENE, method=method, dt=dt, grid=(9, 9))
    assert sim.method == method
    sim.run(10 * dt)
    sim.tendons["drawstring"].rest_length = 0.7
    sim.run(20 * dt)
    assert sim.time == pytest.approx(20 * dt, abs=1e-12)
    assert np.all(np.isfinite(sim.positions))
    assert sim.tendons["drawstring"].rest_length == 0.7


def test_errors_carry_sinews_message(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(open(SCENE).read().replace("k_shear: 100", "k_shear: -1"))
    with pytest.raises(sinew.SinewError, match=r"bad.yaml:\d+:\d+: "):
        sinew.load(str(bad))
    with pytest.raises(sinew.SinewError, match="unknown method 'euler'"):
        sinew.load(SCENE, method="euler")
    with pytest.raises(sinew.SinewError, match="option dt"):
        sinew.load(SCENE, dt=-1)
    with pytest.raises(sinew.SinewError, match="unknown Newton norm 'l2'"):
        sinew.load(SCENE, newton_norm="l2")
    sim = sinew.load(SCENE)
    with pytest.raises(KeyError, match="drawstring"):
        sim.tendons["hem"]
    with pytest.raises(sinew.SinewError, match="rest length -1"):
        sim.tendons["drawstring"].rest_length = -1
    with pytest.raises(sinew.SinewError, match="not pinned"):
        sim.set_pin(0, [0, 0, 0])
    with pytest.raises(sinew.SinewError, match="no `loads`"):
        sim.set_load(0, [0, 0, 1])
    with pytest.raises(ValueError, match="positions"):
        sim.positions = np.zeros(5)


def test_run_folder(tmp_path):
    out = tmp_path / "run"
    with sinew.load(SCENE, out=out, frames_every=0.05) as sim:
        sim.run(0.1)
    summary = json.load(open(out / "summary.json"))
    assert summary["status"] == "ok"
    assert (out / "energy.csv").exists() and (out / "frames.pvd").exists()
    assert len(open(out / "energy.csv").read().splitlines()) == 1 + 11


INSTALLED_SCRIPT = """
import json, sys, sinew
sim = sinew.load(sys.argv[1])
string = sim.tendons["drawstring"]
sim.step(3)
string.rest_length = 0.8
sim.step(3)
print(json.dumps({"file": sinew.__file__, "x": sim.positions.tolist(),
                  "txy": sim.tension_xy.tolist(), "tension": string.tension}))
"""


@pytest.mark.skipif(not os.environ.get("SINEW_BUILD_DIR"), reason="needs the build folder")
def test_installed_tree(tmp_path):
    """meson install (into a staging folder standing in for the prefix): the installed package
    and library load the drawstring scene, change its rest length between steps and give the
    numbers of the build tree's."""
    subprocess.run(["meson", "install", "-C", os.environ["SINEW_BUILD_DIR"], "--no-rebuild",
                    "--quiet", "--destdir", str(tmp_path)], check=True, capture_output=True)
    inits = list(tmp_path.rglob("sinew/__init__.py"))
    assert len(inits) == 1
    pkg = inits[0].parent
    config = {}
    exec(open(pkg / "_libpath.py").read(), config)
    lib = tmp_path / config["LIBRARY"].lstrip("/")
    assert lib.exists()
    env = dict(os.environ, PYTHONPATH=str(pkg.parent), SINEW_LIB=str(lib))
    r = subprocess.run([sys.executable, "-c", INSTALLED_SCRIPT, SCENE], env=env, check=True,
                       capture_output=True, text=True, cwd=str(tmp_path))
    got = json.loads(r.stdout)
    assert got["file"].startswith(str(tmp_path))
    sim = sinew.load(SCENE)
    sim.step(3)
    sim.tendons["drawstring"].rest_length = 0.8
    sim.step(3)
    assert np.array_equal(np.array(got["x"]), sim.positions)
    assert np.array_equal(np.array(got["txy"]), sim.tension_xy)
    assert got["tension"] == sim.tendons["drawstring"].tension


def test_contact_pressure():
    """On the drape scene the cloth touches the sphere within 0.12 s: the pressure is positive
    on some faces, never negative, and carries the cloth's weight in the right units (the sum
    of pressure x area is of the order of the weight); a scene without obstacles has none."""
    sim = sinew.load(os.path.join(ROOT, "scenes", "drape_sphere.yaml"))
    assert sim.contact_pressure is not None and sim.contact_pressure.shape == (sim.nfaces,)
    while sim.time < 0.12 - 1e-9:
        sim.step()
    p = sim.contact_pressure
    assert (p >= 0).all() and (p > 0).any()
    assert sinew.load(SCENE).contact_pressure is None
