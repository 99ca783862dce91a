"""sinew.drape: the shadow area, the drape coefficient and the node count against shapes whose
answers are known exactly (docs/drape.md)."""
import os
import subprocess
import sys

import numpy as np
import pytest

from sinew import drape

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import make_disc  # noqa: E402


def polygon_area(p):
    """Shoelace area of a simple polygon (n, 2)."""
    x, y = p[:, 0], p[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def outline(p, tri):
    """The boundary ring of the disc mesh, in angle order (its outermost vertices)."""
    r = np.hypot(p[:, 0], p[:, 1])
    ring = p[r > r.max() - 1e-9]
    return ring[np.argsort(np.arctan2(ring[:, 1], ring[:, 0]))]


@pytest.fixture(scope="module")
def disc():
    p, tri = make_disc.disc_mesh(0.15, 0.01)
    return np.column_stack([p, np.zeros(len(p))]), tri


def test_flat_specimen_has_dc_one(disc):
    x, tri = disc
    r = drape.coefficient_of(x, x, tri)
    # the shadow of the flat specimen is the mesh's own outline polygon
    exact = polygon_area(outline(x[:, :2], tri))
    assert abs(r["specimen_area"] - exact) < 1e-12
    assert abs(r["shadow_area"] / exact - 1) < 5e-4
    assert abs(r["dc"] - 1) < 1e-3


def test_scaled_specimen_dc(disc):
    """The specimen pulled in radially to 0.8 of its size and lowered: its shadow is the
    outline scaled by 0.8, so DC = (0.64 A - disc) / (A - disc) exactly."""
    x, tri = disc
    y = x.copy()
    y[:, :2] *= 0.8
    y[:, 2] = -np.hypot(x[:, 0], x[:, 1])
    res = drape.coefficient_of(x, y, tri)
    a = polygon_area(outline(x[:, :2], tri))
    want = (0.64 * a - res["disc_area"]) / (a - res["disc_area"])
    assert abs(res["dc"] / want - 1) < 1e-3      # what it reaches at the default pixel


def test_star_union_of_overlapping_triangles():
    """A star of 7 points fanned from its centre, plus the fan of the same star shrunk to 0.6
    about its centre (inside the star, overlapping every triangle of the first fan): the union
    is the star, whose area the shoelace formula gives."""
    n, ro, ri = 7, 0.14, 0.07
    a = np.arange(2 * n) * np.pi / n
    rad = np.where(np.arange(2 * n) % 2 == 0, ro, ri)
    star = np.column_stack([rad * np.cos(a), rad * np.sin(a)])
    pts = np.vstack([[0, 0], star, 0.6 * star])
    m = len(star)
    fan = np.array([[0, 1 + k, 1 + (k + 1) % m] for k in range(m)])
    inner = fan + np.array([0, m, m])
    tri = np.vstack([fan, inner])
    got = drape.shadow_area(pts, tri)
    assert abs(got / polygon_area(star) - 1) < 5e-4


@pytest.mark.parametrize("nodes", [4, 6, 9, 12])
def test_node_count_of_a_synthetic_profile(nodes):
    """r(theta) = 12 cm + 1 cm cos(n theta + 0.3) + 0.3 mm of noise: n nodes."""
    rng = np.random.default_rng(nodes)
    th = np.arange(720) * 2 * np.pi / 720
    r = 0.12 + 0.01 * np.cos(nodes * th + 0.3) + 3e-4 * rng.standard_normal(720)
    count, _ = drape.count_nodes(r)
    assert count == nodes


def test_node_count_ignores_shallow_bumps():
    """A profile with 6 folds and 6 bumps of 1 mm between them (below the 2 mm prominence):
    6 nodes, not 12; a flat profile has none."""
    th = np.arange(720) * 2 * np.pi / 720
    r = 0.12 + 0.01 * np.cos(6 * th) ** 2 * (np.cos(6 * th) > 0) + 0.001 * np.cos(6 * th) ** 2 * (
        np.cos(6 * th) < 0)
    assert drape.count_nodes(r)[0] == 6
    assert drape.count_nodes(np.full(720, 0.15))[0] == 0


def test_radius_profile_of_a_polygon(disc):
    """The flat specimen's outline radius lies between the polygon's apothem and 0.15 m."""
    x, tri = disc
    r = drape.radius_profile(x[:, :2], tri, (0, 0))
    n = len(outline(x[:, :2], tri))
    assert r.max() <= 0.15 + 1e-3 and r.min() >= 0.15 * np.cos(np.pi / n) - 1e-3


def test_refined_disc_rings():
    """make_disc's refined rings: the clamp's edge is a ring, the spacing is at most H inside
    each band and at most the coarse spacing elsewhere, the rings end on the radius, and the
    triangles tile the outline polygon (their areas sum to its area)."""
    bands = [(0.08, 0.11, 0.0025), (0.0875, 0.0925, 0.00125)]
    r = make_disc.refined_radii(0.15, 0.01, bands, rings=[0.09])
    steps = np.diff(np.concatenate([[0.0], r]))
    mid = r - steps / 2
    assert np.isclose(r, 0.09, atol=1e-12).any() and abs(r[-1] - 0.15) < 1e-12
    for r0, r1, h in bands:
        inside = (mid > r0) & (mid < r1)
        assert inside.any() and (steps[inside] <= h * (1 + 1e-9)).all()
    assert (steps <= 0.01 * (1 + 1e-9)).all()
    p, tri = make_disc.disc_mesh(0.15, 0.01, bands, [0.09])
    a = p[tri[:, 1]] - p[tri[:, 0]]
    b = p[tri[:, 2]] - p[tri[:, 0]]
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    assert (cross > 0).all()
    assert abs(0.5 * cross.sum() / polygon_area(outline(p, tri)) - 1) < 1e-12


SINEW = os.environ.get("SINEW_EXE", os.path.join(ROOT, "build", "sinew"))
SCENE = os.path.join(ROOT, "scenes", "cusick_drape.yaml")


def test_shipped_scene_clamps_the_disc_to_its_edge_ring():
    """The disc selection of the shipped scene pins every vertex within 0.09 m of the centre,
    the clamp's edge ring of round(2 pi 0.09 / 1.25 mm) = 452 vertices included, and nothing
    of the next ring, 1.25 mm further out (tools/make_disc.py --ring 0.09 --refine ...)."""
    import sinew
    sim = sinew.load(SCENE)
    r = np.hypot(sim.positions[:, 0], sim.positions[:, 1])
    edge = np.abs(r - 0.09) < 1e-8
    assert edge.sum() == 452 and sim.pinned[edge].all()
    assert (sim.pinned == (r < 0.09 + 1e-8)).all()
    assert abs(r[~sim.pinned].min() - 0.09125) < 1e-8


def test_command_on_the_start_of_the_shipped_scene(tmp_path):
    """`sinew drape` on the scene's first frame (run for no time): the specimen is flat but for
    the 1 mm perturbation, so DC = 1 within the raster's error and there is no node."""
    out = tmp_path / "run"
    subprocess.run([SINEW, "run", SCENE, "--duration", "0", "--out", str(out), "--quiet"],
                   check=True)
    p = subprocess.run([SINEW, "drape", str(out), "--json"], check=True, capture_output=True,
                       text=True)
    import json
    r = json.loads(p.stdout)
    assert abs(r["dc"] - 1) < 1e-3 and r["nodes"] == 0 and r["time"] == 0
    bad = subprocess.run([SINEW, "drape", str(tmp_path / "none")], capture_output=True,
                         text=True)
    assert bad.returncode != 0 and "frames.pvd" in bad.stderr
