"""Reading AAMA DXF and ASTM D6673 pattern files with ezdxf (Debian's python3-ezdxf).

One BLOCK per piece (and per size in graded files), placed by INSERTs in the model space (a
block no INSERT places is taken where it is drawn).  The layers of ASTM D6673 (numbered, not
named) say what each entity is:

    1  piece boundary (the cut line) and the piece's text      7  grain line (the warp, u)
    4  notches (also 80-83: T, castle, check and U notches)   8  internal lines
    11 internal cutouts (holes)                                13 drill holes
    14 sew line (replaces the cut line when present and closed, or open only along the fold)
    6  mirror line: a piece cut on the fold is unfolded (mirrored about it, one whole piece)
    2, 3 turn and curve points of the lines (turn points on the boundary become corners)
    5, 9, 10, 15, 84-87: grading, stripe and plaid references, annotation, quality
       validation curves: read and not used (listed as ignored)

TEXT and MTEXT "Key: value" lines give `Piece Name:`, `Size:`, `Quantity:`, `Category:` (in a
block) and the style's `Sample Size:` and `Units:` (in the model space).  `Quantity: N` makes N
pieces of a block the file places fewer times (the 2nd, 4th, ... mirrored); a graded piece's
other sizes take the quantity and category of the size that states them.  Anything else is listed as skipped,
with its block, layer, type and handle; nothing is dropped without a word.

Units, first found: the style text `Units: ENGLISH|METRIC` (AAMA; metric is mm), the header's
$INSUNITS (1 in, 2 ft, 4 mm, 5 cm, 6 m), its $MEASUREMENT (0 inches, 1 mm), else inches (AAMA's
default).  Everything returned is in metres."""
import logging
import math
import re
from dataclasses import dataclass, field

import numpy as np

from . import geometry as geo

INCH = 0.0254
INSUNITS = {1: (INCH, "in"), 2: (0.3048, "ft"), 4: (1e-3, "mm"), 5: (1e-2, "cm"),
            6: (1.0, "m")}
UNIT_NAMES = {"in": INCH, "mm": 1e-3, "cm": 1e-2, "m": 1.0}
FLATTEN_TOL = 1e-5   # m: largest distance of a flattened curve from the curve
JOIN_TOL = 5e-4      # m: largest gap closed between two boundary parts, and duplicate points
NOTCH_TOL = 2e-3     # m: a notch farther than this from the cut line is not on the piece

NOTCH_LAYERS = {4, 80, 81, 82, 83}
IGNORED = {2: "turn point off the boundary", 3: "curve point (the lines' own vertices)",
           5: "grade reference (grading rules are not applied)",
           9: "stripe reference", 10: "plaid reference", 15: "annotation text",
           84: "boundary quality validation curve", 85: "internal line validation curve",
           86: "cutout validation curve", 87: "sew line validation curve"}
CURVES = {"LINE", "ARC", "CIRCLE", "ELLIPSE", "SPLINE", "LWPOLYLINE", "POLYLINE"}


class PatternError(Exception):
    """A pattern file that cannot be imported, with a message naming the file, piece and DXF
    entity (or line) where the problem is."""


@dataclass
class Skipped:
    where: str   # "block 'FRONT'" or "model space"
    what: str    # "SPLINE on layer 9 (handle 2F)"
    why: str


@dataclass
class Piece:
    """One piece of one size, as placed (all coordinates in m, in the file's plane).  What
    sewing code reads: name, category, copy, mirrored, boundary (counter-clockwise), its
    corners (turn_points on it, and the turns mesh.py finds), notches, grain, fold."""
    name: str                            # the `Piece Name:` text (default: the block's name)
    block: str
    size: str = None
    quantity: int = None                 # `Quantity:` (None: not stated)
    texts: dict = field(default_factory=dict)   # other "Key: value" texts, keys lower case
    category: str = ""                   # FRONT, BACK, SLEEVE, COLLAR, ... ("" not known)
    copy: int = 1                        # 1, 2, ...: which copy of the block (placement or
                                         # a copy made for `Quantity:`)
    mirrored: bool = False               # a mirror image of the block as drawn
    boundary: np.ndarray = None          # (n, 2) m, counter-clockwise
    boundary_from: str = "cut line (layer 1)"
    turn_points: list = field(default_factory=list)   # [((2,) m, DXF entity)] on the boundary
    notches: list = field(default_factory=list)    # (2,) points on the boundary, m
    holes: list = field(default_factory=list)      # (k, 2) polygons, m
    internal: list = field(default_factory=list)   # (k, 2) open polylines, m
    drills: list = field(default_factory=list)     # (2,) points, m
    grain: tuple = None                            # ((2,), (2,)) m, start and end: the warp
    grains: list = field(default_factory=list)     # every grain line (an unfolded piece: the
                                                   # drawn one and its mirror image)
    fold: tuple = None                   # ((2,), (2,)) m: the mirror line it was unfolded
                                         # about (now inside the piece), or None
    handles: list = field(default_factory=list)    # of the boundary's DXF entities
    warnings: list = field(default_factory=list)   # printed on import (open sew line, ...)
    group: str = None                    # the OBJ group name, set by select()
    excluded: str = None                 # why select() leaves it out (None: imported)
    error: str = None                    # why it cannot be imported (raised when chosen)

    @property
    def label(self):
        h = ", boundary handle %s" % " ".join(self.handles[:4]) if self.handles else ""
        return "piece '%s' (block '%s'%s)" % (self.name, self.block, h)

    @property
    def category_text(self):
        """The file's `Category:` text ("" when it has none)."""
        return self.texts.get("category", "")


@dataclass
class Pattern:
    path: str
    units: str          # how the units were found
    scale: float        # m per drawing unit
    style: dict
    pieces: list        # every piece of every size
    sizes: list         # in file order
    base_size: str
    skipped: list
    repaired: list      # what ezdxf's recover mode fixed
    notes: list = field(default_factory=list)   # select()'s warnings (all Quantity 0, ...)


def _layer(e):
    m = re.fullmatch(r"\s*0*(\d+)(\.0*)?\s*", str(e.dxf.get("layer", "")))
    return int(m.group(1)) if m else None


def _what(e):
    return "%s on layer '%s' (handle %s)" % (e.dxftype(), e.dxf.get("layer", "?"),
                                            e.dxf.get("handle", "?"))


def _text(e):
    if e.dxftype() == "MTEXT":
        return e.plain_text()
    return e.dxf.get("text", "")


def _key_values(text):
    out = {}
    for line in str(text).splitlines():
        k, sep, v = line.partition(":")
        if sep:
            out[re.sub(r"\s+", " ", k.strip().lower())] = v.strip()
    return out


def _read_doc(path):
    import ezdxf
    from ezdxf import recover
    try:
        with open(path, "rb") as f:
            head = f.read(4096)
    except OSError as e:
        raise PatternError("%s: cannot read: %s" % (path, e.strerror)) from None
    if b"SECTION" not in head.upper() and b"EOF" not in head.upper():
        raise PatternError("%s: not a DXF file (no SECTION in its first 4096 bytes); expected "
                           "an AAMA or ASTM D6673 DXF file" % path)
    log = logging.getLogger("ezdxf")
    notes = _Notes()
    log.addHandler(notes)
    propagate, log.propagate = log.propagate, False  # its repairs are listed, not printed
    try:
        doc, auditor = recover.readfile(path)
    except ezdxf.DXFStructureError as e:
        raise PatternError("%s: not a readable DXF file: %s" % (path, e)) from None
    except Exception as e:  # ezdxf on hostile input: any failure is the file's, said as such
        raise PatternError("%s: not a readable DXF file (%s: %s)" %
                           (path, type(e).__name__, e)) from None
    finally:
        log.removeHandler(notes)
        log.propagate = propagate
    return doc, list(dict.fromkeys(notes.messages + [str(e.message) for e in auditor.errors]))


class _Notes(logging.Handler):
    """What ezdxf's recovery mode logs while it reads ("recovered invalid integer value ...
    near line 52"), kept for --list."""

    def __init__(self):
        super().__init__(logging.INFO)
        self.messages = []

    def emit(self, record):
        self.messages.append(record.getMessage())


def _units(doc, style, override):
    if override:
        return UNIT_NAMES[override], "%s (--units)" % override
    u = style.get("units", "").strip().upper()
    if u in ("ENGLISH", "IMPERIAL"):
        return INCH, "in (style text 'Units: %s')" % style["units"]
    if u == "METRIC":
        return 1e-3, "mm (style text 'Units: METRIC')"
    h = doc.header
    try:
        ins = int(float(h.get("$INSUNITS", 0)))
    except (TypeError, ValueError):
        ins = 0
    if ins in INSUNITS:
        return INSUNITS[ins][0], "%s ($INSUNITS = %d)" % (INSUNITS[ins][1], ins)
    if "$MEASUREMENT" in h:
        try:
            metric = int(float(h.get("$MEASUREMENT"))) == 1
        except (TypeError, ValueError):
            metric = False
        return (1e-3, "mm ($MEASUREMENT = 1)") if metric else (INCH, "in ($MEASUREMENT = 0)")
    return INCH, "in (no units in the file: AAMA's default)"


def _flatten(e, m, scale):
    """The entity's curve(s) as (k, 2) arrays in m, placed by the matrix m (None: as drawn),
    and whether each is closed."""
    from ezdxf import path
    p = path.make_path(e)
    if m is not None:
        p = p.transform(m)
    out = []
    for sub in p.sub_paths():
        pts = np.array([(v.x, v.y) for v in sub.flattening(FLATTEN_TOL / scale, segments=8)])
        if len(pts) == 0:
            continue
        pts = pts * scale
        closed = len(pts) > 2 and np.hypot(*(pts[-1] - pts[0])) <= JOIN_TOL
        out.append((pts, closed))
    return out


def _point(e, m, scale):
    from ezdxf.math import Vec3
    v = Vec3(e.dxf.center if e.dxftype() == "CIRCLE" else e.dxf.location)
    if m is not None:
        v = m.transform(v)
    return np.array([v.x, v.y]) * scale


def _join(parts, where):
    """Join open polylines end to end into closed loops (gaps up to JOIN_TOL); raises on an
    open boundary."""
    loops = [p for p, closed in parts if closed]
    open_ = [p for p, closed in parts if not closed]
    while open_:
        chain = open_.pop(0)
        while True:
            if np.hypot(*(chain[-1] - chain[0])) <= JOIN_TOL and len(chain) > 2:
                loops.append(chain)
                break
            best, k, flip = None, -1, False
            for i, q in enumerate(open_):
                for rev in (False, True):
                    d = np.hypot(*((q[-1] if rev else q[0]) - chain[-1]))
                    if best is None or d < best:
                        best, k, flip = d, i, rev
            if best is None or best > JOIN_TOL:
                gap = np.hypot(*(chain[-1] - chain[0]))
                raise PatternError(
                    "%s: open boundary: it ends at (%.4g, %.4g) m and starts at (%.4g, %.4g) m, "
                    "%.3g mm apart; expected a closed line (a gap of at most %.3g mm)" %
                    (where, chain[-1][0], chain[-1][1], chain[0][0], chain[0][1], gap * 1e3,
                     JOIN_TOL * 1e3))
            q = open_.pop(k)
            chain = np.vstack([chain, q[::-1] if flip else q])
    return [geo.dedupe(loop, JOIN_TOL) for loop in loops]


def _closed_loops(parts, what, where, skipped):
    loops = []
    for loop in _join(parts, where + " " + what):
        if len(loop) < 3 or abs(geo.signed_area(loop)) <= 0:
            skipped.append(Skipped(where, what, "a degenerate closed line (no area)"))
            continue
        loops.append(loop if geo.signed_area(loop) > 0 else loop[::-1])
    return loops


class _BlockReader:
    """Sorts the entities of one placed block into a Piece."""

    def __init__(self, block, matrix, scale, skipped):
        self.block, self.m, self.scale, self.skipped = block, matrix, scale, skipped
        self.where = "block '%s'" % block.name
        self.cut, self.sew, self.cutouts, self.mirrors = [], [], [], []
        self.piece = Piece(name=block.name, block=block.name)

    def skip(self, e, why):
        self.skipped.append(Skipped(self.where, _what(e), why))

    def curves(self, e):
        try:
            return _flatten(e, self.m, self.scale)
        except Exception as err:  # a curve ezdxf cannot make a path of (bad data)
            self.skip(e, "unreadable curve (%s)" % err)
            return []

    def text(self, e, layer):
        if layer == 15:
            return self.skip(e, "ignored: " + IGNORED[15])
        kv = _key_values(_text(e))
        if not kv:
            return self.skip(e, "text without 'Key: value' (%r)" % _text(e)[:40])
        p = self.piece
        for k, v in kv.items():
            if k == "piece name" and v:
                p.name = v
            elif k == "size" and v:
                p.size = v
            elif k == "quantity":
                try:
                    p.quantity = int(float(v))
                except ValueError:
                    self.skip(e, "Quantity '%s' is not a number" % v[:20])
            else:
                p.texts[k] = v

    def entity(self, e):
        t, layer = e.dxftype(), _layer(e)
        if t in ("TEXT", "MTEXT"):
            return self.text(e, layer)
        if layer is None:
            return self.skip(e, "layer is not an ASTM D6673 layer number")
        if layer in (1, 14, 11, 8) and t in CURVES:
            parts = self.curves(e)
            if layer in (1, 14):
                self.piece.handles.append("%s" % e.dxf.get("handle", "?"))
            if layer == 1:
                self.cut.extend(parts)
            elif layer == 14:
                self.sew.extend(parts)
            elif layer == 11:
                self.cutouts.extend(parts)
            else:
                self.piece.internal.extend(p for p, _ in parts)
            return None
        if layer == 7 and t in ("LINE", "LWPOLYLINE", "POLYLINE"):
            pts = np.vstack([p for p, _ in self.curves(e)] or [np.zeros((0, 2))])
            if self.piece.grain is not None:
                return self.skip(e, "a second grain line (the first is used)")
            if len(pts) < 2 or np.hypot(*(pts[-1] - pts[0])) <= 0:
                return self.skip(e, "a grain line of zero length")
            self.piece.grain = (pts[0], pts[-1])
            return None
        if layer in NOTCH_LAYERS and t in ("POINT", "LINE", "LWPOLYLINE", "POLYLINE"):
            if t == "POINT":
                self.piece.notches.append((_point(e, self.m, self.scale), e))
            else:
                pts = [p for p, _ in self.curves(e)]
                if pts:
                    self.piece.notches.append((np.vstack(pts), e))
            return None
        if layer == 13 and t in ("POINT", "CIRCLE"):
            self.piece.drills.append(_point(e, self.m, self.scale))
            return None
        if layer == 2 and t == "POINT":
            self.piece.turn_points.append((_point(e, self.m, self.scale), e))
            return None
        if layer == 6 and t in ("LINE", "LWPOLYLINE", "POLYLINE"):
            pts = np.vstack([p for p, _ in self.curves(e)] or [np.zeros((0, 2))])
            if len(pts) < 2 or np.hypot(*(pts[-1] - pts[0])) <= JOIN_TOL:
                return self.skip(e, "a mirror line of zero length")
            if self.mirrors:
                return self.skip(e, "a second mirror line (the piece is unfolded about the "
                                 "first)")
            self.mirrors.append(((pts[0], pts[-1]), e))
            return None
        if layer in IGNORED:
            return self.skip(e, "ignored: " + IGNORED[layer])
        return self.skip(e, "not understood on this layer")

    def finish(self):
        p = self.piece
        lab = "%s, %s" % (self.where, "piece '%s'" % p.name)
        if not self.cut and not self.sew:
            return None
        sew, self.sew_fold = self.sew, None
        if sew:
            try:
                _join(sew, lab)
            except PatternError as e:
                closed = self.closed_on_fold(sew, lab)
                if closed is not None:
                    sew = closed
                elif not self.cut:
                    raise
                else:
                    p.warnings.append("%s: its sew line (layer 14) is open (%s): the cut line "
                                      "(layer 1) is used instead" % (p.label, str(e).split(
                                          "open boundary: ")[-1].split("; expected")[0]))
                    sew = []
        loops = _closed_loops(sew or self.cut, "sew line (layer 14)" if sew
                              else "boundary (layer 1)", lab, self.skipped)
        if not loops:
            raise PatternError("%s: its boundary encloses no area; expected a closed line on "
                               "layer 1" % lab)
        loops.sort(key=lambda q: -geo.signed_area(q))
        p.boundary = loops[0]
        for extra in loops[1:]:
            self.skipped.append(Skipped(lab, "a second closed line on layer %d" %
                                        (14 if sew else 1),
                                        "not used: one boundary per piece (holes are layer 11)"))
        if sew:
            p.boundary_from = "sew line (layer 14)" + (", closed along its mirror line"
                                                        if self.sew_fold else "")
        cut = (_closed_loops(self.cut, "boundary (layer 1)", lab, []) or [None])[0] \
            if sew and self.cut else p.boundary
        p.grains = [p.grain] if p.grain is not None else []
        if self.mirrors:
            cut = self.unfold(cut, lab)
        p.holes = _closed_loops(self.cutouts, "internal cutout (layer 11)", lab, self.skipped)
        p.notches = _distinct(self.notches_on(cut, lab))
        on = []
        for q, e in p.turn_points:
            if geo.project(p.boundary, q)[0] <= JOIN_TOL:
                if all(np.hypot(*(q - t)) > JOIN_TOL for t, _ in on):
                    on.append((q, e))
            else:
                self.skipped.append(Skipped(lab, _what(e), "ignored: " + IGNORED[2]))
        p.turn_points = on
        return p

    def closed_on_fold(self, sew, lab):
        """The sew line's parts and the straight line between its two open ends, when both lie
        on the mirror line (a fold is not sewn: some exporters leave the sew line open there),
        if they then join into a closed line; else None."""
        if not self.mirrors:
            return None
        (a, b), _ = self.mirrors[0]
        ends = [q for pts, closed in sew if not closed for q in (pts[0], pts[-1])]
        on = [q for q in ends if geo.project(np.array([a, b]), q)[0] <= JOIN_TOL]
        if len(on) != 2 or np.hypot(*(on[1] - on[0])) <= JOIN_TOL:
            return None
        try:
            _join(sew + [(np.array(on), False)], lab)
        except PatternError:
            return None
        self.sew_fold = (on[0], on[1])
        return sew + [(np.array(on), False)]

    def unfold(self, cut, lab):
        """The piece joined to its mirror image about its mirror line (which must lie on its
        boundary), with everything on it mirrored too; returns the cut line unfolded likewise
        (the unfolded boundary when the mirror line is not on the cut line)."""
        p = self.piece
        (a, b), e = self.mirrors[0]
        same = cut is p.boundary
        fa, fb = self.sew_fold if self.sew_fold is not None else (a, b)
        try:
            whole = geo.unfold(p.boundary, fa, fb, JOIN_TOL)
        except ValueError as why:
            raise PatternError(
                "%s: its mirror line (layer 6, %s) from (%.4g, %.4g) to (%.4g, %.4g) m %s "
                "(its %s); expected the fold to be a straight stretch of the boundary with the "
                "piece on one side" % (lab, _what(e), a[0], a[1], b[0], b[1], why,
                                       p.boundary_from)) from None
        p.boundary, p.fold = whole[0], (whole[1][0], whole[1][1])
        try:
            cut = p.boundary if same else geo.unfold(cut, a, b, JOIN_TOL)[0]
        except ValueError:  # the mirror line not on the cut line: notches against the sew line
            cut = p.boundary

        def on_fold(q):
            return bool((geo.line_distance(q, a, b) <= JOIN_TOL).all())
        p.grains = p.grains + [tuple(geo.reflect(np.array(g), a, b)) for g in p.grains]
        p.notches = p.notches + [(geo.reflect(np.atleast_2d(q), a, b), ent)
                                 for q, ent in p.notches]
        p.drills = _distinct(p.drills + [geo.reflect(q, a, b) for q in p.drills])
        p.internal = p.internal + [geo.reflect(ln, a, b) for ln in p.internal
                                   if not on_fold(ln)]
        p.turn_points = p.turn_points + [(geo.reflect(q, a, b), ent)
                                         for q, ent in p.turn_points if not on_fold(q)]
        self.cutouts = self.cutouts + [(geo.reflect(c, a, b), closed)
                                       for c, closed in self.cutouts if not on_fold(c)]
        return cut

    def notches_on(self, cut, lab):
        """Each notch as the point of its entity nearest the cut line, if within NOTCH_TOL of
        it, then moved to the nearest point of the boundary used (the sew line, if any)."""
        out = []
        for pts, e in self.piece.notches:
            pts = np.atleast_2d(pts)
            ref = cut if cut is not None else self.piece.boundary
            d = [geo.project(ref, q)[0] for q in pts]
            q = pts[int(np.argmin(d))]
            if min(d) > NOTCH_TOL:
                self.skipped.append(Skipped(lab, _what(e), "notch %.3g mm from the cut line "
                                            "(more than %.3g mm): not on the piece" %
                                            (min(d) * 1e3, NOTCH_TOL * 1e3)))
                continue
            _, s = geo.project(self.piece.boundary, q)
            out.append(geo.point_at(self.piece.boundary, np.array([s]))[0])
        return out


def _distinct(points):
    """points without those within JOIN_TOL of an earlier one (a mirrored copy of a point on
    the fold is the point itself)."""
    out = []
    for q in points:
        if all(np.hypot(*(q - t)) > JOIN_TOL for t in out):
            out.append(q)
    return out


def _style(doc, skipped):
    style = {}
    for e in doc.modelspace():
        if e.dxftype() in ("TEXT", "MTEXT"):
            kv = _key_values(_text(e))
            if kv:
                style.update(kv)
            else:
                skipped.append(Skipped("model space", _what(e), "text without 'Key: value'"))
    return style


def _placements(doc, skipped):
    """{block name: [matrix or None, ...]} from the model space's INSERTs; other model-space
    entities are listed as skipped."""
    out = {}
    for e in doc.modelspace():
        t = e.dxftype()
        if t in ("TEXT", "MTEXT"):
            continue
        if t != "INSERT":
            skipped.append(Skipped("model space", _what(e), "not in a piece's BLOCK"))
            continue
        name = e.dxf.get("name", "")
        if name not in doc.blocks:
            skipped.append(Skipped("model space", _what(e), "INSERT of a block '%s' that "
                                   "the file does not define" % name))
            continue
        if e.dxf.get("row_count", 1) > 1 or e.dxf.get("column_count", 1) > 1:
            skipped.append(Skipped("model space", _what(e), "an INSERT array (MINSERT)"))
            continue
        try:
            m = e.matrix44()
        except Exception as err:
            skipped.append(Skipped("model space", _what(e), "bad placement (%s)" % err))
            continue
        out.setdefault(name, []).append(m)
    return out


def _mirrored(m):
    if m is None:
        return False
    ux, uy = m.ux, m.uy
    return ux.x * uy.y - ux.y * uy.x < 0


def read(path, units=None):
    """The Pattern of an AAMA/ASTM D6673 DXF file (every piece of every size, in m).
    units: None (from the file) or 'in', 'mm', 'cm', 'm'."""
    doc, repaired = _read_doc(path)
    skipped = []
    try:
        style = _style(doc, skipped)
        scale, how = _units(doc, style, units)
        placed = _placements(doc, skipped)
        pieces = []
        for block in doc.blocks:
            if block.name.startswith("*") or block.block_record.is_any_layout:
                continue
            matrices = placed.get(block.name, [None])
            for copy, m in enumerate(matrices, 1):
                r = _BlockReader(block, m, scale, skipped)
                for e in block:
                    if e.dxftype() == "INSERT":
                        r.skip(e, "a nested INSERT (a piece is one block)")
                    else:
                        r.entity(e)
                try:
                    piece = r.finish()
                except PatternError as err:  # raised if this piece is chosen (select)
                    piece = r.piece
                    piece.error, piece.boundary = str(err), None
                if piece is None:
                    if len(block):
                        skipped.append(Skipped(r.where, "%d entities" % len(block),
                                               "no boundary on layer 1: not a piece"))
                    break
                piece.mirrored, piece.copy = _mirrored(m), copy
                pieces.append(piece)
        pieces = _copies(_inherit(pieces))
    except PatternError as e:
        raise PatternError("%s: %s" % (path, e)) from None
    except Exception as e:  # data ezdxf accepted but that is not what a pattern holds
        raise PatternError("%s: cannot read the pattern (%s: %s)" %
                           (path, type(e).__name__, e)) from None
    if not pieces or all(p.error for p in pieces) and len(pieces) == 1:
        if pieces:
            raise PatternError("%s: %s" % (path, pieces[0].error))
        raise PatternError("%s: no pieces: no BLOCK has a closed boundary on layer 1; expected "
                           "an AAMA or ASTM D6673 pattern (one BLOCK per piece)" % path)
    sizes = []
    for p in pieces:
        if p.size is not None and p.size not in sizes:
            sizes.append(p.size)
    base = style.get("sample size") or (sizes[0] if sizes else None)
    if base is not None and sizes and base not in sizes:
        base = sizes[0]
    return Pattern(path, how, scale, style, pieces, sizes, base, skipped, repaired)


# Categories inferred from a piece's `Category:` text, else from its name: the first of these
# words found in the text (spaces and punctuation removed; "WITH CUFF" and the like dropped
# first: a sleeve with a cuff is a sleeve), else a whole-word abbreviation (of the text, or of
# the name's last word: Gerber's piece codes, GMX1006S18BK).
CATEGORY_WORDS = [("INTERLINING", ("INTERLI", "FUSING")), ("CUFF", ("CUFF",)),
                  ("PLACKET", ("PLACKET",)), ("BINDING", ("BINDING",)),
                  ("FACING", ("FACING",)),
                  ("WAISTBAND", ("WAISTBAND",)), ("POCKET", ("POCKET",)),
                  ("FRONT", ("FRONT",)), ("BACK", ("BACK",)), ("SLEEVE", ("SLEEVE",)),
                  ("COLLAR", ("COLLAR", "NECK")), ("YOKE", ("YOKE",)), ("HOOD", ("HOOD",)),
                  ("LEG", ("LEG",)), ("SKIRT", ("SKIRT",))]
CATEGORY_CODES = {"FR": "FRONT", "FRT": "FRONT", "BK": "BACK", "SL": "SLEEVE", "SLV": "SLEEVE",
                  "CO": "COLLAR", "CU": "CUFF", "WB": "WAISTBAND", "PKT": "POCKET"}
# Words that tell two pieces of one category apart as parts of one garment (an upper and a
# lower collar, a collar stand) rather than as alternates.
PART_WORDS = ("UPPER", "LOWER", "UNDER", "TOP", "STAND", "INNER", "OUTER", "NECKHOLE",
              "ARMHOLE", "LEFT", "RIGHT", "HEM")
NO_ALTERNATES = ("", "INTERLINING")


def category_of(text, name):
    """The category (FRONT, BACK, SLEEVE, COLLAR, CUFF, PLACKET, ...; "" when none fits) of a
    piece with the `Category:` text text and the name name (docs/patterns.md, "Categories")."""
    for src, last_word in ((text, False), (name, True)):
        up = re.sub(r"\bWITH\s+\w+", " ", str(src or "").upper())
        squashed = re.sub(r"[^A-Z]", "", up)
        if not squashed:
            continue
        for cat, words in CATEGORY_WORDS:  # (not LEG in a name: Gerber's ORILEG...)
            if any(w in squashed for w in words) and not (last_word and cat == "LEG"):
                return cat
        toks = [t for t in re.split(r"[^A-Z0-9]+", up) if t]
        if last_word:
            toks = toks[-1:]
        for t in toks:
            for code in (t, re.search(r"[A-Z]*$", t).group()):
                if code in CATEGORY_CODES:
                    return CATEGORY_CODES[code]
    return ""


def _inherit(pieces):
    """A graded piece's sizes that state no quantity or category (Gerber writes them in the
    base size's block only) take them from the first size that does; then each piece's
    category."""
    donor = {}
    for p in pieces:
        if p.quantity is not None and p.name not in donor:
            donor[p.name] = p
    for p in pieces:
        d = donor.get(p.name)
        if d is not None and p.quantity is None:
            p.quantity = d.quantity
            if "category" in d.texts and "category" not in p.texts:
                p.texts["category"] = d.texts["category"]
        p.category = category_of(p.category_text, p.name)
    return pieces


def _count(p):
    """How many pieces a block makes: its `Quantity:`, or more when its cutting annotation
    says so: the N of an `Annotation: NX<material>` text (Gerber's "2XFABRIC", cut two in the
    fabric) when the Quantity is 1 (a sleeve marked `Quantity: 1` and "2XFABRIC" is a left and a
    right) or 0 (a piece imported only when asked for); else 1.  An annotation such as "10X2"
    (no material named) is not a count."""
    m = re.match(r"\s*(\d+)\s*X\s*[A-Z]", p.texts.get("annotation", ""), re.I)
    n = int(m.group(1)) if m else 0
    if p.quantity is not None and p.quantity > 1:
        return p.quantity
    return n if n > 0 and p.quantity in (0, 1) else (p.quantity or 1)


def _copies(pieces):
    """Each block placed fewer times than its quantity gets the copies missing, in the order
    of the file after its last placement: copy k is the first placement mirrored when k is
    even (a left and a right), shifted beside it (by k - 1 widths and 5 cm gaps)."""
    out = []
    for i, p in enumerate(pieces):
        out.append(p)
        if i + 1 < len(pieces) and pieces[i + 1].block == p.block:
            continue
        first = next(q for q in out if q.block == p.block)
        if first.error is not None:
            continue
        lo, hi = first.boundary.min(0), first.boundary.max(0)
        for k in range(p.copy + 1, _count(first) + 1):
            shift = (k - 1) * (hi[0] - lo[0] + 0.05)
            if k % 2 == 0:
                def f(q, shift=shift):
                    q = np.array(q, float)
                    q[..., 0] = lo[0] + hi[0] - q[..., 0] + shift
                    return q
            else:
                def f(q, shift=shift):
                    return np.array(q, float) + np.array([shift, 0.0])
            out.append(_moved(first, f, k % 2 == 0, k))
    return out


def _moved(p, f, flip, copy):
    """A copy of the piece p with every point mapped by f (a reflection when flip: its
    boundary reversed to stay counter-clockwise)."""
    import copy as _copy
    q = _copy.copy(p)
    q.boundary = f(p.boundary)[::-1] if flip else f(p.boundary)
    q.turn_points = [(f(t), e) for t, e in p.turn_points]
    q.notches = [f(n) for n in p.notches]
    q.holes = [f(h)[::-1] if flip else f(h) for h in p.holes]
    q.internal = [f(ln) for ln in p.internal]
    q.drills = [f(d) for d in p.drills]
    q.grains = [(f(a), f(b)) for a, b in p.grains]
    q.grain = q.grains[0] if q.grains else None
    q.fold = (f(p.fold[0]), f(p.fold[1])) if p.fold is not None else None
    q.texts, q.warnings = dict(p.texts), list(p.warnings)
    q.mirrored, q.copy = p.mirrored != flip, copy
    return q


def _matches(p, item):
    item = item.strip().upper()
    return item in {str(x).upper() for x in (p.group, p.name, p.block, p.category,
                                               p.category_text) if x}


def select(pattern, size=None, pieces=None):
    """The pieces of one size (size None: the base size) to import, and the size.  Every piece
    of the size gets a distinct group name (p.group; a name that comes again, a block placed
    twice or a left and a mirrored right, gets _2, _3, ...) and p.excluded, why it is left out
    (None: imported).  Left out by default: `Quantity: 0` pieces (unless every piece of the
    size says 0: the file's quantities then say nothing and all are imported, with a note in
    pattern.notes) and alternates, the pieces after the first of one category and the same
    part words (a short sleeve after a long one; docs/patterns.md, "Alternates").  pieces, a
    comma-separated list, imports exactly the pieces whose group name, piece name, block,
    category or Category text equals one of its names (ignoring case)."""
    if size is not None and size not in pattern.sizes:
        raise PatternError("%s: no size '%s'; expected one of: %s" %
                           (pattern.path, size, ", ".join(pattern.sizes) or "(the file is "
                            "not graded)"))
    size = size if size is not None else pattern.base_size
    chosen = [p for p in pattern.pieces if p.size is None or p.size == size]
    for p in pattern.pieces:
        p.group = p.excluded = None
    seen = {}
    for p in chosen:
        base = re.sub(r"[^\x21-\x7e]+", "_", p.name).strip("_") or "piece"
        n = seen.get(base, 0) + 1
        seen[base] = n
        p.group = base if n == 1 else "%s_%d" % (base, n)
        p.excluded = None
    if pieces is not None:
        items = [x for x in pieces.split(",") if x.strip()]
        for p in chosen:
            if not any(_matches(p, x) for x in items):
                p.excluded = "not named by --pieces"
        unused = [x for x in items if not any(_matches(p, x) for p in chosen)]
        if unused or not items:
            names = sorted({p.group for p in chosen})
            cats = sorted({p.category for p in chosen if p.category})
            raise PatternError("%s: --pieces %s: no piece%s is named %s; expected "
                               "names of: pieces %s; categories %s" % (
                                   pattern.path, pieces, " of size %s" % size if size else "",
                                   ", ".join("'%s'" % x.strip() for x in unused) or "(empty)",
                                   ", ".join(names), ", ".join(cats) or "(none)"))
        return _checked(pattern, [p for p in chosen if p.excluded is None]), size
    if all(p.quantity == 0 for p in chosen):
        pattern.notes.append("every piece of size %s says Quantity 0: all are imported "
                             "(--pieces chooses)" % size)
    else:
        for p in chosen:
            if p.quantity == 0:
                p.excluded = "Quantity 0"
    kept = {}
    for p in chosen:
        if p.excluded or p.category in NO_ALTERNATES:
            continue
        words = re.sub(r"[^A-Z]", "", (p.category_text or p.name).upper())
        key = (p.category, tuple(w for w in PART_WORDS if w in words))
        first = kept.setdefault(key, p)
        if first.name != p.name:
            p.excluded = "alternate of '%s' (category %s%s)" % (
                first.group, p.category, "".join(" " + w.lower() for w in key[1]))
    return _checked(pattern, [p for p in chosen if p.excluded is None]), size


def _checked(pattern, chosen):
    """chosen, or the PatternError of the first chosen piece that cannot be imported."""
    for p in chosen:
        if p.error is not None:
            raise PatternError("%s: %s" % (pattern.path, p.error))
    return chosen


def grain_frame(piece):
    """Unit vector of the warp (u) in the plane, and whether it came from a grain line; checks
    the grain line lies in the piece."""
    if piece.grain is None:
        return np.array([1.0, 0.0]), False
    a, b = piece.grain
    mid = (a + b) / 2
    if not geo.inside(piece.boundary, mid):
        raise PatternError("%s: its grain line (layer 7) from (%.4g, %.4g) to (%.4g, %.4g) m "
                           "lies outside the piece; expected it inside the boundary" %
                           (piece.label, a[0], a[1], b[0], b[1]))
    d = b - a
    return d / math.hypot(*d), True
