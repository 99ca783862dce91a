"""Plane polygon helpers of the pattern importer: areas, corners, projection onto a boundary,
resampling at a target edge length, self-intersection and inside tests.

Polygons are (n, 2) arrays of distinct points, closed implicitly (the last point connects to the
first), in metres.  None of this triangulates: gmsh meshes (mesh.py)."""
import numpy as np


def signed_area(p):
    """Shoelace area, m²: positive when p runs counter-clockwise."""
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def dedupe(p, tol):
    """p without points within tol of their predecessor (and without a last point repeating the
    first: the duplicate closing points exporters write)."""
    keep = [p[0]]
    for q in p[1:]:
        if np.hypot(*(q - keep[-1])) > tol:
            keep.append(q)
    while len(keep) > 1 and np.hypot(*(keep[-1] - keep[0])) <= tol:
        keep.pop()
    return np.array(keep)


def turn_angles(p):
    """Angle (rad, in [0, pi]) by which the boundary turns at each point."""
    a = p - np.roll(p, 1, axis=0)
    b = np.roll(p, -1, axis=0) - p
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    dot = (a * b).sum(1)
    return np.abs(np.arctan2(cross, dot))


def arclength(p):
    """Cumulative length at each point of the closed polygon, and the perimeter, m."""
    seg = np.hypot(*(np.roll(p, -1, axis=0) - p).T)
    return np.concatenate(([0.0], np.cumsum(seg)[:-1])), float(seg.sum())


def project(p, q):
    """Nearest point of the closed polygon p to q: (distance m, arc-length position m)."""
    a, b = p, np.roll(p, -1, axis=0)
    d = b - a
    dd = np.maximum((d * d).sum(1), 1e-300)
    t = np.clip(((q - a) * d).sum(1) / dd, 0.0, 1.0)
    near = a + t[:, None] * d
    dist = np.hypot(*(near - q).T)
    k = int(np.argmin(dist))
    s, _ = arclength(p)
    return float(dist[k]), float(s[k] + t[k] * np.sqrt(dd[k]))


def point_at(p, s):
    """Points at arc-length positions s (array, m) along the closed polygon p."""
    s0, total = arclength(p)
    s = np.mod(s, total)
    k = np.clip(np.searchsorted(s0, s, side="right") - 1, 0, len(p) - 1)
    a, b = p[k], p[(k + 1) % len(p)]
    seg = np.hypot(*(b - a).T)
    t = np.where(seg > 0, (s - s0[k]) / np.maximum(seg, 1e-300), 0.0)
    return a + t[:, None] * (b - a)


def resample(p, marks, h):
    """The closed polygon p resampled at edge length about h (m) between the marks (sorted
    arc-length positions that must be points: corners and notches).  Each stretch from one
    mark to the next is cut into max(1, round(length / h)) equal arc-length parts.  Returns the
    points and the index of each mark among them."""
    _, total = arclength(p)
    marks = np.asarray(marks, float)
    pos, mark_idx = [], []
    for i, s in enumerate(marks):
        end = marks[i + 1] if i + 1 < len(marks) else marks[0] + total
        k = max(1, int(round((end - s) / h)))
        mark_idx.append(len(pos))
        pos.extend(s + (end - s) * np.arange(k) / k)
    return point_at(p, np.array(pos)), mark_idx


def _segments_cross(a, b, c, d):
    """Whether segment ab properly crosses or touches each segment c[i]d[i] (vectorised)."""
    def orient(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - \
            (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])
    o1, o2 = orient(a, b, c), orient(a, b, d)
    o3, o4 = orient(c, d, a), orient(c, d, b)
    return (o1 * o2 <= 0) & (o3 * o4 <= 0) & ~((o1 == 0) & (o2 == 0))


def self_intersection(p):
    """A point where the closed polygon p crosses itself (two non-adjacent edges meet), or
    None."""
    n = len(p)
    b = np.roll(p, -1, axis=0)
    for i in range(n - 2):
        j = np.arange(i + 2, n if i > 0 else n - 1)  # edges that share no end with edge i
        if len(j) == 0:
            continue
        hit = _segments_cross(p[i], b[i], p[j], b[j])
        if hit.any():
            k = j[np.argmax(hit)]
            return (p[i] + b[i] + p[k] + b[k]) / 4
    return None


def inside(p, q):
    """Whether q is inside the closed polygon p (even-odd rule)."""
    a, b = p, np.roll(p, -1, axis=0)
    up = (a[:, 1] > q[1]) != (b[:, 1] > q[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[:, 0] + (q[1] - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(up & (q[0] < x)) % 2)


def reflect(q, a, b):
    """Points q ((2,) or (k, 2), m) mirrored about the line through a and b."""
    d = (b - a) / np.hypot(*(b - a))
    r = np.asarray(q, float) - a
    along = r @ d if r.ndim == 1 else (r @ d)[:, None]
    return a + 2 * along * d - r


def line_distance(q, a, b):
    """Distance (m) of the points q ((k, 2)) from the infinite line through a and b."""
    d = (b - a) / np.hypot(*(b - a))
    r = np.atleast_2d(q) - a
    return np.abs(r[:, 0] * d[1] - r[:, 1] * d[0])


def unfold(p, a, b, tol):
    """The closed polygon p (counter-clockwise) joined to its mirror image about the fold line
    ab, which must lie on p's boundary: p's boundary with the fold's run removed (the whole
    run of consecutive points on the fold's line, from its first point to its last), then the
    mirror image of that, back to the start; the fold's two ends once each.  Returns the
    polygon (counter-clockwise) and the fold's two ends; raises ValueError saying why when ab
    is not on p's boundary (within tol) or p lies on both sides of it."""
    length = np.hypot(*(b - a))
    probe = a + np.linspace(0, 1, 9)[:, None] * (b - a)
    far = max(project(p, q)[0] for q in probe)
    if length <= tol or far > tol:
        raise ValueError("does not lie on the boundary (up to %.3g mm from it)" % (far * 1e3))
    p = _with_points(p, [a, b], tol)
    on = line_distance(p, a, b) <= tol
    n = len(p)
    if on.all():
        raise ValueError("is all of the boundary")
    k = int(np.argmin(np.hypot(*(p - a).T)))   # a is a point of p, on the run
    i0 = k
    while on[(i0 - 1) % n]:
        i0 = (i0 - 1) % n
    i1 = k
    while on[(i1 + 1) % n]:
        i1 = (i1 + 1) % n
    rest = np.array([p[(i1 + j) % n] for j in range(((i0 - i1) % n) + 1)])
    r = rest[1:-1] - a
    side = (b - a)[0] * r[:, 1] - (b - a)[1] * r[:, 0]
    side = side[np.abs(side) / length > tol]
    if len(side) == 0 or (side > 0).any() and (side < 0).any():
        raise ValueError("lies on the boundary, but the piece is on both sides of it (up to "
                         "%.3g and %.3g mm)" % (side.max() * 1e3 / length if len(side) else 0,
                                                -side.min() * 1e3 / length if len(side) else 0))
    whole = np.vstack([rest, reflect(rest[1:-1], a, b)[::-1]])
    if signed_area(whole) < 0:
        whole = whole[::-1]
    return whole, (rest[0], rest[-1])


def _with_points(p, qs, tol):
    """p with each point of qs that lies on an edge (within tol) and is not already a point
    (within tol) inserted on that edge."""
    for q in qs:
        if np.hypot(*(p - q).T).min() <= tol:
            continue
        a, b = p, np.roll(p, -1, axis=0)
        d = b - a
        t = np.clip(((q - a) * d).sum(1) / np.maximum((d * d).sum(1), 1e-300), 0, 1)
        k = int(np.argmin(np.hypot(*(a + t[:, None] * d - q).T)))
        p = np.vstack([p[:k + 1], q, p[k + 1:]])
    return p
