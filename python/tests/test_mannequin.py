"""tools/make_mannequin.py: a tape measure around the generated mesh at the bust, waist and hip
heights reads the stated girths (1 %); the mesh is closed (every edge in exactly two triangles,
the two in opposite directions), outward (positive signed volume) and does not cross itself
(no edge passes through a triangle it does not touch); the shipped scenes/meshes/mannequin.obj
is what the command in its first line writes."""
import importlib.util
import os

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHIPPED = os.path.join(ROOT, "scenes", "meshes", "mannequin.obj")
spec = importlib.util.spec_from_file_location(
    "make_mannequin", os.path.join(ROOT, "tools", "make_mannequin.py"))
mm = importlib.util.module_from_spec(spec)
spec.loader.exec_module(mm)


def read_obj(path):
    verts, tris = [], []
    with open(path) as f:
        for line in f:
            s = line.split()
            if s and s[0] == "v":
                verts.append([float(x) for x in s[1:4]])
            elif s and s[0] == "f":
                tris.append([int(x.split("/")[0]) - 1 for x in s[1:4]])
    return np.array(verts), np.array(tris)


def tape_measure(verts, tris, z):
    """The girth at height z as a tape measure reads it: the perimeter of the convex hull of
    the mesh's cross section (the points where its edges meet the plane at z)."""
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    p, q = verts[e[:, 0]], verts[e[:, 1]]
    dz = q[:, 2] - p[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (z - p[:, 2]) / dz
    cut = (dz != 0) & (t >= 0) & (t <= 1)
    pts = (p[cut] + t[cut, None] * (q[cut] - p[cut]))[:, :2]
    pts = np.unique(np.round(pts, 12), axis=0)
    hull = convex_hull(pts)
    return float(np.sum(np.linalg.norm(np.roll(hull, -1, axis=0) - hull, axis=1)))


def convex_hull(pts):
    """Andrew's monotone chain; pts sorted by x then y."""
    pts = pts[np.lexsort((pts[:, 1], pts[:, 0]))]

    def half(points):
        out = []
        for pt in points:
            while len(out) >= 2 and np.cross(out[-1] - out[-2], pt - out[-2]) <= 0:
                out.pop()
            out.append(pt)
        return out[:-1]
    return np.array(half(pts) + half(pts[::-1]))


def edge_crosses_triangle(p, q, a, b, c, eps=1e-12):
    """Whether segments pq properly cross triangles abc (arrays of n): the segment's ends on
    opposite sides of the triangle's plane and the crossing point inside the triangle."""
    n = np.cross(b - a, c - a)
    dp, dq = np.einsum("ij,ij->i", p - a, n), np.einsum("ij,ij->i", q - a, n)
    opposite = dp * dq < 0
    t = dp / np.where(opposite, dp - dq, 1.0)
    x = p + t[:, None] * (q - p)
    inside = np.ones(len(p), bool)
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= np.einsum("ij,ij->i", np.cross(v - u, x - u), n) > eps * np.einsum(
            "ij,ij->i", n, n)
    return opposite & inside


@pytest.fixture(scope="module", params=[(1.70, 0.88, 0.70, 0.96, 32, 30, "none"),
                                        (1.85, 1.02, 0.86, 1.00, 24, 20, "down"),
                                        (1.55, 0.80, 0.62, 0.92, 48, 44, "out"),
                                        (1.70, 0.88, 0.70, 0.96, 32, 30, "down")])
def body(request):
    height, bust, waist, hip, around, rings, arms = request.param
    verts, tris, _ = mm.mannequin(height, bust, waist, hip, around, rings, arms)
    return request.param, verts, tris


def torso(param, tris):
    """The torso's triangles (its vertices come first: around * rings + 2)."""
    return tris[np.all(tris < param[4] * param[5] + 2, axis=1)]


def test_girths_at_the_stated_heights(body):
    """Measured on the torso: a tape measure goes around the body under the arms."""
    param, verts, tris = body
    (height, bust, waist, hip, _, _, _) = param
    tris = torso(param, tris)
    for frac, girth in ((mm.BUST, bust), (mm.WAIST, waist), (mm.HIP, hip)):
        measured = tape_measure(verts, tris, frac * height)
        assert measured == pytest.approx(girth, rel=0.01), (frac, measured, girth)
    # and nowhere between the waist and the bust is the body narrower than the waist
    zs = np.linspace(mm.WAIST * height, mm.BUST * height, 7)[1:]
    assert all(tape_measure(verts, tris, z) > waist for z in zs)


def test_closed_outward_consistent(body):
    """Every directed edge once and its reverse once; positive volume, also of the torso
    alone (so each arm's is too: an inward arm would take its volume off)."""
    param, verts, tris = body
    height, arms = param[0], param[6]
    directed = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    # consistent winding: each directed edge once, and its reverse present too
    keys = set(map(tuple, directed))
    assert len(keys) == len(directed)
    assert all((j, i) in keys for i, j in keys)
    def volume(t):
        a, b, c = verts[t[:, 0]], verts[t[:, 1]], verts[t[:, 2]]
        return np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0
    whole, trunk = volume(tris), volume(torso(param, tris))
    # a body of about 70 % of an adult's volume (no lower legs): tens of litres; each arm
    # about 2 litres (an adult's arm: 2 to 4)
    assert 0.02 < trunk < 0.12
    if arms == "none":
        assert whole == trunk
    else:
        assert 2 * 0.0015 < whole - trunk < 2 * 0.005
    assert verts[:, 2].min() == pytest.approx(mm.KNEE * height)
    assert verts[:, 2].max() == pytest.approx(height)
    assert 450 <= len(verts) <= 5000


def test_does_not_cross_itself(body):
    _, verts, tris = body
    edges = np.unique(np.sort(np.concatenate(
        [tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1), axis=0)
    lo, hi = verts[tris].min(axis=1), verts[tris].max(axis=1)
    for e in edges:
        p, q = verts[e[0]], verts[e[1]]
        near = np.all((lo <= np.maximum(p, q) + 1e-9) & (hi >= np.minimum(p, q) - 1e-9), axis=1)
        near &= ~np.isin(tris, e).any(axis=1)  # triangles sharing a vertex with the edge
        k = np.nonzero(near)[0]
        if len(k):
            hit = edge_crosses_triangle(np.tile(p, (len(k), 1)), np.tile(q, (len(k), 1)),
                                        verts[tris[k, 0]], verts[tris[k, 1]], verts[tris[k, 2]])
            assert not hit.any(), (e, k[hit])


@pytest.mark.parametrize("shipped", [SHIPPED, SHIPPED.replace("mannequin.obj", "mannequin_arms.obj")])
def test_shipped_file_is_its_command(tmp_path, shipped):
    with open(shipped) as f:
        first = f.readline()
    args = first.split("tools/make_mannequin.py")[1].split()
    out = tmp_path / "m.obj"
    mm.main(args + ["-o", str(out)])
    with open(shipped) as f:
        assert f.read() == out.read_text()
    verts, _ = read_obj(shipped)
    assert 450 <= len(verts) <= 3000


def test_arm_axes_in_the_header():
    """The header's arm axes are the arms' own: every arm vertex at its ring's radius about
    the stated axis (the rings of a surface of revolution lie across it)."""
    path = SHIPPED.replace("mannequin.obj", "mannequin_arms.obj")
    with open(path) as f:
        axes = [line for line in f if line.startswith("# ") and " arm: axis from" in line]
    assert len(axes) == 2
    verts, _ = read_obj(path)
    torso = 30 * 32 + 2
    n = (len(verts) - torso) // 2
    for line, k in zip(axes, (torso, torso + n)):
        nums = [float(v) for v in line.replace("(", " ").replace(")", " ").replace(",", " ").split()
                if v.lstrip("-").replace(".", "", 1).isdigit()]
        top, d = np.array(nums[0:3]), np.array(nums[3:6])
        arm = verts[k:k + n] - top
        along = arm @ d
        radial = np.linalg.norm(arm - np.outer(along, d), axis=1)
        assert abs(np.linalg.norm(d) - 1) < 1e-5
        # each ring (around vertices at one `along`) has one radius
        for a in np.unique(np.round(along, 4)):
            ring = radial[np.abs(along - a) < 5e-5]
            assert ring.max() - ring.min() < 1e-5
