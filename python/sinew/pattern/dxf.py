"""Reading AAMA DXF and ASTM D6673 pattern files with ezdxf (Debian's python3-ezdxf).

One BLOCK per piece (and per size in graded files), placed by INSERTs in the model space (a
block no INSERT places is taken where it is drawn).  The layers of ASTM D6673 (numbered, not
named) say what each entity is:

    1  piece boundary (the cut line) and the piece's text      7  grain line (the warp, u)
    4  notches (also 80-83: T, castle, check and U notches)   8  internal lines
    11 internal cutouts (holes)                                13 drill holes
    14 sew line (replaces the cut line when present)
    2, 3 turn and curve points of the lines (turn points on the boundary become corners)
    5, 6, 9, 10, 15, 84-87: grading, mirror, stripe and plaid references, annotation, quality
       validation curves: read and not used (listed as ignored)

TEXT and MTEXT "Key: value" lines give `Piece Name:`, `Size:`, `Quantity:` (in a block) and the
style's `Sample Size:` and `Units:` (in the model space).  Anything else is listed as skipped,
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
           6: "mirror line (a piece cut on the fold is not unfolded)",
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
    name: str
    block: str
    size: str = None
    quantity: int = None
    texts: dict = field(default_factory=dict)
    mirrored: bool = False
    boundary: np.ndarray = None          # (n, 2) m, counter-clockwise
    boundary_from: str = "cut line (layer 1)"
    turn_points: list = field(default_factory=list)
    notches: list = field(default_factory=list)    # (2,) points on the boundary, m
    holes: list = field(default_factory=list)      # (k, 2) polygons, m
    internal: list = field(default_factory=list)   # (k, 2) open polylines, m
    drills: list = field(default_factory=list)     # (2,) points, m
    grain: tuple = None                            # ((2,), (2,)) m, start and end
    handles: list = field(default_factory=list)    # of the boundary's DXF entities

    @property
    def label(self):
        h = ", boundary handle %s" % " ".join(self.handles[:4]) if self.handles else ""
        return "piece '%s' (block '%s'%s)" % (self.name, self.block, h)


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
        self.cut, self.sew, self.cutouts = [], [], []
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
        if layer in IGNORED:
            return self.skip(e, "ignored: " + IGNORED[layer])
        return self.skip(e, "not understood on this layer")

    def finish(self):
        p = self.piece
        lab = "%s, %s" % (self.where, "piece '%s'" % p.name)
        if not self.cut and not self.sew:
            return None
        loops = _closed_loops(self.sew or self.cut, "sew line (layer 14)" if self.sew
                              else "boundary (layer 1)", lab, self.skipped)
        if not loops:
            raise PatternError("%s: its boundary encloses no area; expected a closed line on "
                               "layer 1" % lab)
        loops.sort(key=lambda q: -geo.signed_area(q))
        p.boundary = loops[0]
        for extra in loops[1:]:
            self.skipped.append(Skipped(lab, "a second closed line on layer %d" %
                                        (14 if self.sew else 1),
                                        "not used: one boundary per piece (holes are layer 11)"))
        if self.sew:
            p.boundary_from = "sew line (layer 14)"
        cut = (_closed_loops(self.cut, "boundary (layer 1)", lab, []) or [None])[0] \
            if self.sew and self.cut else p.boundary
        p.holes = _closed_loops(self.cutouts, "internal cutout (layer 11)", lab, self.skipped)
        p.notches = self.notches_on(cut, lab)
        on = []
        for q, e in p.turn_points:
            if geo.project(p.boundary, q)[0] <= JOIN_TOL:
                on.append((q, e))
            else:
                self.skipped.append(Skipped(lab, _what(e), "ignored: " + IGNORED[2]))
        p.turn_points = on
        return p

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
            for m in matrices:
                r = _BlockReader(block, m, scale, skipped)
                for e in block:
                    if e.dxftype() == "INSERT":
                        r.skip(e, "a nested INSERT (a piece is one block)")
                    else:
                        r.entity(e)
                piece = r.finish()
                if piece is None:
                    if len(block):
                        skipped.append(Skipped(r.where, "%d entities" % len(block),
                                               "no boundary on layer 1: not a piece"))
                    break
                piece.mirrored = _mirrored(m)
                pieces.append(piece)
    except PatternError as e:
        raise PatternError("%s: %s" % (path, e)) from None
    except Exception as e:  # data ezdxf accepted but that is not what a pattern holds
        raise PatternError("%s: cannot read the pattern (%s: %s)" %
                           (path, type(e).__name__, e)) from None
    if not pieces:
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


def select(pattern, size=None):
    """The pieces of one size (size None: the base size), each with a distinct name: a name
    that comes again (a block placed twice, a left and a mirrored right) gets _2, _3, ..."""
    if size is not None and size not in pattern.sizes:
        raise PatternError("%s: no size '%s'; expected one of: %s" %
                           (pattern.path, size, ", ".join(pattern.sizes) or "(the file is "
                            "not graded)"))
    size = size if size is not None else pattern.base_size
    chosen = [p for p in pattern.pieces if p.size is None or p.size == size]
    seen = {}
    for p in chosen:
        base = re.sub(r"[^\x21-\x7e]+", "_", p.name).strip("_") or "piece"
        n = seen.get(base, 0) + 1
        seen[base] = n
        p.group = base if n == 1 else "%s_%d" % (base, n)
    return chosen, size


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
