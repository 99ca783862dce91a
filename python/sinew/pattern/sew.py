"""Automatic sewing: seams proposed from the pieces' outlines, corners, notches and categories
(docs/garments.md, "Automatic sewing").

    pieces = sinew.pattern.mesh(pat, size="M")
    pieces = sew.upright(pieces)            # u up the body on every piece (the hem lowest)
    seams = sew.propose(pieces)             # [Seam], in garment order; SewError if it cannot
    print(sew.table(seams)); text = sew.seams_yaml(seams)

A piece's boundary runs counter-clockwise in (u,v) from a corner; with u up the body, v > 0
is the drawing's left.  A piece is drawn as seen from outside (the face up), so the front's
drawing left (v > 0) lands on the body's right and the back's drawing left on the body's left;
a sleeve drawn so is a left sleeve when its front half (the half of the cap sewn to the front)
is its v > 0 half.  The runs between corners are found by position (below), then each pair's
lengths are checked against EASE."""
import re
from dataclasses import dataclass

import numpy as np

# The largest relative difference of a seam's two lengths, of the shorter: 0.1, the simulator's
# sewing.ease_max default (docs/garments.md, "`sewing`"), which refuses a longer pair.  Eased
# seams in real patterns stay within it: a back shoulder eased 3-6 mm onto a 12-15 cm front
# one (2-5 %), a woven sleeve's cap 2-4 cm longer than its 45-55 cm armhole (4-8 %); a knit's
# rib stretched 15-25 % onto a neckline does not, and is not sewn automatically.
EASE = 0.10
TIE = 2e-3     # m: corners this close in height or width count as level
HEM_BAND = 0.1  # a hem drawn in several runs lies in the lowest tenth of the piece's height
LOW = 0.3      # an armpit or a cap's foot lies above this fraction of the piece's height

CATEGORIES = ("FRONT", "BACK", "SLEEVE", "COLLAR", "CUFF", "PLACKET", "INTERLINING")


class SewError(Exception):
    """Pieces that cannot be sewn, with a message naming the pieces and runs left unmatched."""


@dataclass
class End:
    kind: str      # "corner" or "notch"
    k: int         # index in the panel's corners / notches list

    def yaml(self):
        return "{%s: %d}" % (self.kind, self.k)


@dataclass
class Run:
    panel: str
    start: End
    end: End
    length: float  # m, along the boundary in (u,v)

    def label(self):
        return "%s %s %d-%s %d" % (self.panel, self.start.kind, self.start.k,
                                   self.end.kind, self.end.k)


@dataclass
class Seam:
    name: str
    a: Run
    b: Run

    @property
    def mismatch(self):
        """(longer - shorter) / shorter."""
        lo, hi = sorted((self.a.length, self.b.length))
        return (hi - lo) / lo if lo > 0 else float("inf")


def category(m):
    """FRONT, BACK, SLEEVE, COLLAR, CUFF, PLACKET, INTERLINING or None, from the piece's own
    category (the importer's, or the file's 'Category:' text) else its name."""
    p = m.piece
    texts = getattr(p, "texts", {}) or {}
    for text in (getattr(p, "category", None), texts.get("category"), p.name, m.group):
        if not text:
            continue
        t = str(text).upper()
        for key, pat in (("INTERLINING", r"INTERLIN"), ("CUFF", r"CUFF"),
                         ("PLACKET", r"PLACKET"), ("COLLAR", r"COLLAR|\bRIB\b|NECK ?BAND"),
                         ("SLEEVE", r"SLEEVE|SS\d*$|ST$"), ("FRONT", r"FRONT|FR$|\bFR\b"),
                         ("BACK", r"BACK|BK$|\bBK\b")):
            if re.search(pat, t):
                return key
    return None


class _Outline:
    """One piece's boundary with arc lengths, its corners and notches as boundary positions."""

    def __init__(self, m):
        self.m, self.name = m, m.group
        self.loop = list(m.boundary)
        pos = {v: i for i, v in enumerate(self.loop)}
        self.uv = np.asarray(m.uv, float)[self.loop]
        seg = np.linalg.norm(np.roll(self.uv, -1, 0) - self.uv, axis=1)
        self.cum = np.concatenate([[0.0], np.cumsum(seg)])
        self.perimeter = self.cum[-1]
        self.corners = [pos[c] for c in m.corners]
        self.notches = [pos[c] for c in m.notches]
        self.vc = 0.5 * (self.uv[:, 1].min() + self.uv[:, 1].max())
        self.u0, self.u1 = self.uv[:, 0].min(), self.uv[:, 0].max()

    def arc(self, i, j):
        """Length counter-clockwise from boundary position i to j, m."""
        d = self.cum[j] - self.cum[i]
        return d if d >= 0 else d + self.perimeter

    def u(self, i):
        return self.uv[i, 0]

    def w(self, i):
        """Signed distance from the centre line: > 0 on the drawing's left."""
        return self.uv[i, 1] - self.vc

    def end(self, i):
        if i in self.corners:
            return End("corner", self.corners.index(i))
        return End("notch", self.notches.index(i))

    def run(self, i, j, ccw):
        """The run from position i to j going counter-clockwise (ccw) or clockwise."""
        length = self.arc(i, j) if ccw else self.arc(j, i)
        if length > 0.5 * self.perimeter + 1e-9:
            raise SewError("%s: the run %s to %s is the longer way round its boundary; the "
                           "scene takes the shorter, so it cannot be named by its ends"
                           % (self.name, self.end(i).yaml(), self.end(j).yaml()))
        return Run(self.name, self.end(i), self.end(j), length)

    def between(self, i, j):
        """Corners strictly between positions i and j counter-clockwise."""
        out, k = [], self.corners.index(i)
        while True:
            k = (k + 1) % len(self.corners)
            c = self.corners[k]
            if c == j:
                return out
            out.append(c)

    def hem(self):
        """(start, end) of the hem: the lowest corner run lying across the piece (|dv| > |du|),
        run counter-clockwise from the drawing's left (v > 0) to its right."""
        cs, best = self.corners, None
        for k, a in enumerate(cs):
            b = cs[(k + 1) % len(cs)]
            du, dv = self.uv[b] - self.uv[a]
            mid = 0.5 * (self.u(a) + self.u(b))
            if abs(dv) > abs(du) and dv < 0 and (best is None or mid < best[0]):
                best = (mid, a, b)
        if best is None:
            raise SewError("%s: no hem found (a lowest corner-to-corner run across the piece)"
                           % self.name)
        a, b = best[1], best[2]
        n = len(cs)
        for _ in range(n):          # a hem drawn in several runs: the low runs across beside it
            c = cs[(cs.index(b) + 1) % n]
            if c == a or not self._low_across(b, c):
                break
            b = c
        for _ in range(n):
            c = cs[(cs.index(a) - 1) % n]
            if c == b or not self._low_across(c, a):
                break
            a = c
        return a, b

    def _low_across(self, a, b):
        """Whether the run a to b lies across the piece (|dv| > |du|, v falling) in its lowest
        HEM_BAND of height."""
        du, dv = self.uv[b] - self.uv[a]
        top = self.u0 + HEM_BAND * (self.u1 - self.u0)
        return abs(dv) > abs(du) and dv < 0 and max(self.u(a), self.u(b)) < top

    def widest(self, cands, what):
        """The candidate corner farthest from the centre line, the higher of level ones."""
        low = self.u0 + LOW * (self.u1 - self.u0)
        cands = [c for c in cands if self.u(c) >= low]
        if not cands:
            raise SewError("%s: no %s found (a corner in the upper %.0f %% of the piece on "
                           "that side)" % (self.name, what, 100 * (1 - LOW)))
        far = max(abs(self.w(c)) for c in cands)
        level = [c for c in cands if abs(self.w(c)) >= far - TIE]
        return max(level, key=self.u)


def _body(o):
    """A FRONT's or BACK's landmarks as boundary positions: hem, armpit, shoulder point and
    neck point on each side ('+': the drawing's left, v > 0)."""
    if len(o.corners) < 6:
        raise SewError("%s: %d corners; a body piece needs at least 6 (hem, armpit, shoulder "
                       "point on each side)" % (o.name, len(o.corners)))
    hem_p, hem_m = o.hem()
    f = {"hem+": hem_p, "hem-": hem_m}
    n = len(o.corners)
    for side, sign in (("+", 1), ("-", -1)):
        half = [c for c in o.corners if sign * o.w(c) > TIE]
        if not half:
            raise SewError("%s: no corner on its %s half" % (o.name, "left" if sign > 0
                                                            else "right"))
        top = max(o.u(c) for c in half)
        neck = min((c for c in half if o.u(c) >= top - TIE), key=lambda c: abs(o.w(c)))
        k = o.corners.index(neck)
        f["neck" + side] = neck
        f["shoulder" + side] = o.corners[(k + sign) % n]
    f["armpit-"] = o.widest(o.between(f["hem-"], f["shoulder-"]), "armpit")
    f["armpit+"] = o.widest(o.between(f["shoulder+"], f["hem+"]), "armpit")
    return f


def _sleeve(o):
    """A SLEEVE's landmarks: hem ends, the cap's top and its feet ('+': v > 0)."""
    hem_p, hem_m = o.hem()
    cap = [i for i in range(len(o.loop)) if o.arc(hem_m, i) < o.arc(hem_m, hem_p)]
    peak = max(cap, key=o.u)
    path = o.arc(hem_m, hem_p)
    near = [c for c in o.notches + o.corners if c in cap
            and abs(o.arc(hem_m, c) - o.arc(hem_m, peak)) < 0.15 * path]
    if not near:
        raise SewError("%s: no notch or corner at the top of its cap (within 15 %% of the "
                       "cap from its highest point); expected a notch where the cap's front "
                       "and back halves meet" % o.name)
    top = min(near, key=lambda c: (c not in o.notches, min(o.arc(peak, c), o.arc(c, peak))))
    f = {"hem+": hem_p, "hem-": hem_m, "top": top}
    f["foot-"] = o.widest([c for c in o.corners if c in cap and o.arc(hem_m, c)
                           < o.arc(hem_m, top)], "cap foot")
    f["foot+"] = o.widest([c for c in o.corners if c in cap and o.arc(hem_m, c)
                           > o.arc(hem_m, top)], "cap foot")
    return f


def _notches_between(o, i, j):
    return sum(1 for c in o.notches if 0 < o.arc(i, c) < o.arc(i, j))


def upright(meshed):
    """The pieces with u up the body: a piece whose top (a body piece's neckline end, a
    sleeve's cap end) is at its smallest u is turned half round in (u,v) (u, v -> -u, -v: the
    same cloth, so the grain line is kept).  Returns new Meshed where turned, else the same."""
    import dataclasses
    out = []
    for m in meshed:
        cat = category(m)
        if cat in ("FRONT", "BACK", "SLEEVE") and _top_is_low(_Outline(m), cat):
            m = dataclasses.replace(m, uv=-np.asarray(m.uv, float))
        out.append(m)
    return out


def _top_is_low(o, cat):
    """Whether the piece's top is at its smallest u.  A body piece's top has the neckline, so
    its outline at the centre line lies below the top's highest point (the hem is straight or
    lowest at the centre); a sleeve's top is its cap, narrow at the end."""
    span = o.u1 - o.u0
    near_c = np.abs(o.uv[:, 1] - o.vc) < 0.1 * (o.uv[:, 1].max() - o.uv[:, 1].min())
    uc = o.uv[near_c, 0]
    if cat == "SLEEVE":
        band = 0.1 * span
        hi = np.ptp(o.uv[o.uv[:, 0] > o.u1 - band, 1])
        lo = np.ptp(o.uv[o.uv[:, 0] < o.u0 + band, 1])
        return lo < hi
    dip_top = o.u1 - uc.max()
    dip_low = uc.min() - o.u0
    return dip_low > dip_top


def propose(meshed, ease=EASE):
    """The seams of a top (FRONT, BACK, optional SLEEVEs) as [Seam] in garment order: the
    shoulders, the sides, the armholes, the underarms.  Pieces of other categories are not
    sewn (and named in the error if they are the only ones).  SewError when a category is
    missing or doubled, a landmark is not found, or a pair's lengths differ by more than ease."""
    by = {}
    for m in meshed:
        by.setdefault(category(m), []).append(m)
    fronts, backs, sleeves = by.get("FRONT", []), by.get("BACK", []), by.get("SLEEVE", [])
    if len(fronts) != 1 or len(backs) != 1:
        raise SewError("automatic sewing takes one FRONT and one BACK piece; found %s; "
                       "expected a top's pattern (pieces and categories: %s)"
                       % (", ".join("%d %s" % (len(x), c) for x, c in
                                    ((fronts, "FRONT"), (backs, "BACK"))),
                          ", ".join("%s %s" % (m.group, category(m)) for m in meshed)))
    if len(sleeves) not in (0, 2):
        raise SewError("automatic sewing takes two SLEEVE pieces or none; found %d (%s)"
                       % (len(sleeves), ", ".join(m.group for m in sleeves)))
    fr, bk = _Outline(fronts[0]), _Outline(backs[0])
    F, B = _body(fr), _body(bk)
    # body's right: the front's + side and the back's - side
    side = {"right": ("+", "-"), "left": ("-", "+")}
    seams = []
    for who in ("right", "left"):
        sf, sb = side[who]
        seams.append(Seam(who + "_shoulder",
                          fr.run(F["shoulder" + sf], F["neck" + sf], sf == "-"),
                          bk.run(B["shoulder" + sb], B["neck" + sb], sb == "-")))
    for who in ("right", "left"):
        sf, sb = side[who]
        seams.append(Seam(who + "_side", fr.run(F["armpit" + sf], F["hem" + sf], sf == "+"),
                          bk.run(B["armpit" + sb], B["hem" + sb], sb == "+")))
    if sleeves:
        seams += _sleeves(sleeves, fr, F, bk, B, side)
    bad = [s for s in seams if s.mismatch > ease]
    if bad:
        raise SewError("runs left unmatched (lengths differ by more than %g of the shorter): "
                       "%s" % (ease, "; ".join(
                           "%s: %s %.4g m against %s %.4g m (%.1f %%)"
                           % (s.name, s.a.label(), s.a.length, s.b.label(), s.b.length,
                              100 * s.mismatch) for s in bad)))
    return seams


def _sleeves(sleeves, fr, F, bk, B, side):
    """Armholes and underarms: each sleeve's front half (single notches, or the half whose
    length is nearer the front armhole's, or by the drawing: v > 0 on an unmirrored piece) to
    the front's armhole, the other to the back's."""
    arm_f = {s: fr.run(F["armpit" + s], F["shoulder" + s], s == "-") for s in "+-"}
    arm_b = {s: bk.run(B["armpit" + s], B["shoulder" + s], s == "-") for s in "+-"}
    placed = {}
    for m in sleeves:
        o = _Outline(m)
        S = _sleeve(o)
        halves = {"+": o.run(S["foot+"], S["top"], False), "-": o.run(S["foot-"], S["top"], True)}
        nb = {"+": _notches_between(o, S["top"], S["foot+"]),
              "-": _notches_between(o, S["foot-"], S["top"])}
        fl, bl = arm_f["-"].length, arm_b["+"].length
        if nb["+"] != nb["-"]:
            front = "+" if nb["+"] < nb["-"] else "-"   # the back half has the double notch
        elif abs(fl - bl) > 0.01 * min(fl, bl):
            d = {s: abs(halves[s].length - fl) - abs(halves[s].length - bl) for s in "+-"}
            front = "+" if d["+"] < d["-"] else "-"
        else:
            front = "-" if getattr(m.piece, "mirrored", False) else "+"
        who = "left" if front == "+" else "right"
        if who in placed:
            who = "right" if who == "left" else "left"
            front = "+" if who == "left" else "-"
        placed[who] = (o, S, halves, front)
    out = []
    for who in ("left", "right"):
        o, S, halves, front = placed[who]
        back = "-" if front == "+" else "+"
        sf, sb = side[who]
        out.append(Seam(who + "_armhole_front", arm_f[sf], halves[front]))
        out.append(Seam(who + "_armhole_back", arm_b[sb], halves[back]))
    for who in ("left", "right"):
        o, S, halves, front = placed[who]
        out.append(Seam(who + "_underarm", o.run(S["foot+"], S["hem+"], True),
                        o.run(S["foot-"], S["hem-"], False)))
    return out


def table(seams):
    """The proposal as a table: seam, the two runs, their lengths and the mismatch."""
    rows = [("seam", "piece A run", "piece B run", "A m", "B m", "mismatch %")]
    rows += [(s.name, s.a.label(), s.b.label(), "%.4f" % s.a.length, "%.4f" % s.b.length,
              "%.2f" % (100 * s.mismatch)) for s in seams]
    wid = [max(len(r[k]) for r in rows) for k in range(6)]
    return "\n".join("  ".join(c.ljust(w) for c, w in zip(r, wid)).rstrip() for r in rows)


def seams_yaml(seams, given=()):
    """`seams:` entries for a scene (lines, no trailing newline): the proposed ones, each
    replaced by a given one of the same name (given: [(name, yaml text of the entry)]), then
    the given ones with new names."""
    given = dict(given)
    out = ["seams:"]
    for s in seams:
        if s.name in given:
            out.append("  - " + given.pop(s.name) + "    # given")
            continue
        out += ["  - name: %s    # %.4g m and %.4g m (%.1f %%)" % (s.name, s.a.length,
                                                                   s.b.length, 100 * s.mismatch),
                "    a: {panel: %s, from: %s, to: %s}" % (s.a.panel, s.a.start.yaml(),
                                                          s.a.end.yaml()),
                "    b: {panel: %s, from: %s, to: %s}" % (s.b.panel, s.b.start.yaml(),
                                                          s.b.end.yaml())]
    out += ["  - " + text + "    # given" for text in given.values()]
    return "\n".join(out)
