"""The state API of the Python package: reset, dt, state copies, arrays over all tendons, and a
clear exception for every misuse (closed simulations, bad times and counts, out-of-range
64-bit indices, NUL bytes in paths, two threads, Ctrl-C during run)."""
import _thread
import ctypes
import os
import threading

import numpy as np
import pytest

import sinew

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MEMBRANE = os.path.join(ROOT, "scenes", "tendon_membrane_2d.yaml")    # three tendons, 2D
DRAWSTRING = os.path.join(ROOT, "scenes", "cloth_drawstring.yaml")    # one tendon, 3D


def trajectory(sim, n):
    """n steps: the positions, tendon tensions and tension XY after each, copied."""
    out = []
    for _ in range(n):
        sim.step()
        out.append((sim.time, sim.positions.copy(), sim.tendon_tension.copy(),
                    sim.tension_xy.copy()))
    return out


def assert_same(a, b):
    assert len(a) == len(b)
    for (ta, xa, ha, ya), (tb, xb, hb, yb) in zip(a, b):
        assert ta == tb
        assert np.array_equal(xa, xb) and np.array_equal(ha, hb) and np.array_equal(ya, yb)


# ------------------------------------------------------------------ misuse

def test_step_after_close_raises():
    sim = sinew.load(MEMBRANE)
    sim.step()
    sim.close()
    assert sim.closed
    with pytest.raises(sinew.SinewError, match="closed"):
        sim.step()
    with pytest.raises(sinew.SinewError, match="closed"):
        sim.run(1.0)
    with pytest.raises(sinew.SinewError, match="closed"):
        sim.tendon_rest = [0.5, 0.5, 0.5]
    assert np.isfinite(sim.positions).all() and sim.time == 0.01  # still readable


def test_del_then_step_raises():
    sim = sinew.load(MEMBRANE)
    x = sim.positions
    sim.__del__()
    with pytest.raises(sinew.SinewError, match="closed"):
        sim.step()
    assert np.array_equal(x, sim.initial_positions)  # the memory is still there


def test_closed_in_c():
    """libsinew itself refuses a step after sw_sim_close."""
    sim = sinew.load(MEMBRANE)
    sim.close()
    lib, err = sinew._library(), ctypes.create_string_buffer(256)
    assert lib.sw_sim_step(sim._ptr, err, 256) != 0
    assert b"closed" in err.value


@pytest.mark.parametrize("until", [float("nan"), float("inf"), -float("inf"), 0.005])
def test_run_bad_times_raise(until):
    sim = sinew.load(MEMBRANE)
    sim.step()  # t = 0.01: 0.005 is in the past
    with pytest.raises(ValueError, match="until"):
        sim.run(until)
    # and libsinew refuses them too, without stepping
    lib, err = sinew._library(), ctypes.create_string_buffer(256)
    assert lib.sw_sim_run_steps(sim._ptr, until, -1, err, 256) != 0
    assert b"until" in err.value and sim.time == 0.01


def test_bad_step_counts_raise():
    sim = sinew.load(MEMBRANE)
    with pytest.raises(ValueError, match="n = -5"):
        sim.step(-5)
    with pytest.raises(TypeError):
        sim.step(2.5)
    sim.step(0)
    assert sim.time == 0.0


@pytest.mark.parametrize("index", [2**32 + 1560, -1, 441, 2**63 + 5])
def test_vertex_out_of_range_raises(index):
    sim = sinew.load(MEMBRANE)
    with pytest.raises(IndexError, match="vertex"):
        sim.set_pin(index, [0.0, 0.0])
    with pytest.raises(IndexError, match="vertex"):
        sim.set_load(index, [0.0, 0.0])
    assert np.array_equal(sim.positions, sim.initial_positions)


def test_nul_in_paths_raises(tmp_path):
    with pytest.raises(ValueError, match="NUL"):
        sinew.load(MEMBRANE + "\0.ignored")
    with pytest.raises(ValueError, match="NUL"):
        sinew.load(MEMBRANE, out=str(tmp_path / "a\0b"))
    assert not list(tmp_path.iterdir())


def test_two_threads_one_simulation():
    """A second thread using the simulation while one steps it gets a SinewError at once."""
    sim = sinew.load(MEMBRANE)
    held, release = threading.Event(), threading.Event()

    def hold():  # a thread in the middle of a step, as far as the lock knows
        with sim._using("step"):
            held.set()
            release.wait(10)

    t = threading.Thread(target=hold)
    t.start()
    held.wait(10)
    try:
        with pytest.raises(sinew.SinewError, match="another thread"):
            sim.step()
        with pytest.raises(sinew.SinewError, match="another thread"):
            sim.tendons["left"].rest_length = 0.5
    finally:
        release.set()
        t.join()
    # two threads stepping for real: each call steps or raises that error, nothing else
    errors, steps = [], []

    def stepper():
        for _ in range(30):
            try:
                sim.step()
                steps.append(1)
            except sinew.SinewError as e:
                errors.append(str(e))

    threads = [threading.Thread(target=stepper) for _ in range(2)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert all("another thread" in e for e in errors)
    assert len(steps) + len(errors) == 60
    assert sim.counters["nstep"] == len(steps) and np.isfinite(sim.positions).all()


def test_ctrl_c_stops_run_within_a_step():
    sim = sinew.load(MEMBRANE)
    sim.step()
    seen = []

    def interrupt():  # Ctrl-C as the main thread sees it, with the step count at that moment
        seen.append(sim.counters["nstep"])
        _thread.interrupt_main()

    timer = threading.Timer(0.3, interrupt)
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.run(1e6)  # years of steps without the interrupt
    timer.join()
    n = sim.counters["nstep"]
    assert seen[0] <= n <= seen[0] + 1
    assert sim.time == pytest.approx(n * 0.01, abs=1e-12)
    sim.step()  # whole and usable
    assert sim.counters["nstep"] == n + 1


# ------------------------------------------------------------------ counters

def test_counters_follow_every_change():
    """counters is read from libsinew again after every change (it keeps the last read between
    changes): after each it equals libsinew's counters one by one, and a read is a copy."""
    sim = sinew.load(DRAWSTRING, grid=(8, 8))
    lib = sinew._library()

    def from_lib():
        return {k: lib.sw_sim_counter(sim._ptr, k.encode()) for k in sinew._COUNTERS}

    assert sim.counters == from_lib()
    sim.counters["nstep"] = 99  # a copy: the simulation's counters are not changed
    assert sim.counters["nstep"] == 0
    sim.step()
    copy = sim.state()
    changes = [sim.step, lambda: setattr(sim.tendons["drawstring"], "rest_length", 0.9),
               lambda: sim.run(0.05), lambda: sim.set_state(copy), sim.reset]
    for change in changes:
        before = sim.counters
        change()
        assert sim.counters == from_lib()
    assert before["nstep"] == 1 and sim.counters["nstep"] == 0  # set_state, then reset


# ------------------------------------------------------------------ reset, dt, state copies

def test_reset_is_a_fresh_load():
    fresh = trajectory(sinew.load(MEMBRANE), 5)
    sim = sinew.load(MEMBRANE)
    x = sim.positions
    sim.run(0.13)
    sim.reset()
    assert sim.time == 0.0 and sim.counters["nstep"] == 0
    assert x is sim.positions and np.array_equal(x, sim.initial_positions)
    assert_same(trajectory(sim, 5), fresh)


def test_reset_refused_with_a_run_folder(tmp_path):
    with sinew.load(MEMBRANE, out=tmp_path / "run") as sim:
        with pytest.raises(sinew.SinewError, match="run folder"):
            sim.reset()


@pytest.mark.parametrize("method", ["backward-euler", "bdf2", "newmark", "implicit-midpoint"])
def test_state_round_trip_is_bit_identical(method):
    sim = sinew.load(MEMBRANE, method=method, dt=0.01)
    sim.run(0.05)
    copy = sim.state()
    assert copy.time == 0.05 and np.array_equal(copy.positions, sim.positions)
    after = trajectory(sim, 6)
    sim.set_state(copy)
    assert sim.time == 0.05 and np.array_equal(sim.positions, copy.positions)
    assert_same(trajectory(sim, 6), after)
    # into another simulation of the same scene and method
    other = sinew.load(MEMBRANE, method=method, dt=0.01)
    other.set_state(copy)
    assert_same(trajectory(other, 6), after)


def test_state_of_another_scene_raises():
    copy = sinew.load(MEMBRANE).state()
    sim = sinew.load(DRAWSTRING)
    with pytest.raises(sinew.SinewError, match="expected this simulation's"):
        sim.set_state(copy)


def test_dt_read_and_write():
    sim = sinew.load(MEMBRANE, dt=0.01)
    assert sim.dt == 0.01
    sim.step(3)
    sim.dt = 0.0025
    assert sim.dt == 0.0025
    sim.step(2)
    assert sim.time == pytest.approx(0.035, abs=1e-15)
    with pytest.raises(sinew.SinewError, match="dt"):
        sim.dt = -1.0
    with pytest.raises(sinew.SinewError, match="dt"):
        sim.dt = float("nan")
    with pytest.raises(sinew.SinewError, match="static"):
        sinew.load(MEMBRANE, method="static").dt = 0.1
    # halving dt converges: backward Euler's error at t = 0.2 s against a fine reference falls
    # by about 2 per halving (first order)
    def at(dt):
        s = sinew.load(MEMBRANE, dt=0.02)
        s.dt = dt
        s.run(0.2)
        return s.positions.copy()
    ref = at(0.000625)
    e1, e2 = (np.abs(at(dt) - ref).max() for dt in (0.01, 0.005))
    assert 1.6 < e1 / e2 < 2.6


# ------------------------------------------------------------------ arrays over all tendons

def test_tendon_arrays_match_each_tendon():
    sim = sinew.load(MEMBRANE)
    sim.run(0.3)
    tendons = list(sim.tendons.values())
    assert len(tendons) == 3 == len(sim.tendon_length)
    assert np.array_equal(sim.tendon_length, [t.length for t in tendons])
    assert np.array_equal(sim.tendon_tension, [t.tension for t in tendons])
    assert np.array_equal(sim.tendon_rest, [t.rest_length for t in tendons])
    assert (sim.tendon_tension > 0).all()
    rest = sim.tendon_rest.copy() * [0.99, 1.0, 0.98]
    sim.tendon_rest = rest
    assert np.array_equal(sim.tendon_rest, rest)
    assert np.array_equal(rest, [t.rest_length for t in tendons])
    # the diagnostics follow at once: a cable's tension is K (length - rest) (stiffness 5000 N/m)
    assert np.allclose(sim.tendon_tension, 5000 * (sim.tendon_length - rest), rtol=1e-12)
    with pytest.raises(ValueError, match="tendon_rest"):
        sim.tendon_rest = [1.0, 1.0]
    with pytest.raises(sinew.SinewError, match="rest length"):
        sim.tendon_rest = [1.0, -1.0, 1.0]
    assert np.array_equal(sim.tendon_rest, rest)  # nothing changed


def test_views_are_persistent_and_read_only():
    sim = sinew.load(MEMBRANE)
    x, h = sim.positions, sim.tendon_tension
    sim.step()
    assert x is sim.positions and h is sim.tendon_tension
    assert np.array_equal(h, [t.tension for t in sim.tendons.values()])
    for a in (x, h, sim.tendon_length, sim.tendon_rest, sim.tension_xy):
        with pytest.raises(ValueError):
            a[0] = 1.0


def test_bending_matrix_override():
    """bending_matrix= reaches the terms: the compact and exact matrices follow the same
    trajectory to Newton's tolerance (1e-2 m/s, 10 ms steps: 0.1 mm a step), and a bad name is
    refused."""
    runs = {}
    for mx in ("exact", "compact"):
        sim = sinew.load(DRAWSTRING, grid=(8, 8), bending_matrix=mx)
        runs[mx] = trajectory(sim, 10)
        sim.close()
    diff = np.abs(runs["exact"][-1][1] - runs["compact"][-1][1]).max()
    assert 0 < diff < 10 * 1e-4
    with pytest.raises(sinew.SinewError, match="bending_matrix"):
        sinew.load(DRAWSTRING, bending_matrix="lumped")
