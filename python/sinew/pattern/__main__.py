"""The command line of sinew.pattern: `python3 -m sinew.pattern import FILE.dxf ...` (and
`sinew pattern import ...`).  Exit 0 on success, 1 when the file cannot be imported (a message
naming the file, piece and entity; nothing written), 2 on bad arguments."""
import argparse
import collections
import os
import sys

from . import DEFAULT_EDGE, dxf, mesh
from .geometry import signed_area
from .mesh import layout
from .write import obj_text, scene_text, write_atomic

PLAUSIBLE = (0.01, 3.0)  # m: a piece outside this size range suggests wrong units


def _edge(s):
    try:
        v = float(s)
    except ValueError:
        raise argparse.ArgumentTypeError("expects a length in m, got '%s'" % s) from None
    if not (v > 0 and v < 10):
        raise argparse.ArgumentTypeError("expects a length in m in (0, 10), got '%s'" % s)
    return v


def _parser():
    ap = argparse.ArgumentParser(
        prog="sinew pattern",
        description="Pattern pieces of an AAMA or ASTM D6673 DXF file meshed into an OBJ (a "
                    "group per piece, per-corner (u,v) in metres, u along the grain line) and "
                    "a scene skeleton naming each piece's corners and notches (docs/patterns.md).")
    sub = ap.add_subparsers(dest="command", metavar="import", required=True)
    im = sub.add_parser("import", help="import FILE.dxf",
                        description="Import FILE.dxf: OBJ and scene skeleton (YAML); --list "
                        "only prints what the file holds.  Exit 0 on success, 1 when the "
                        "file cannot be imported (nothing is written), 2 on bad arguments.")
    im.add_argument("file", metavar="FILE.dxf")
    im.add_argument("--out", metavar="DIR", help="folder of the outputs (default: FILE's): "
                    "DIR/STEM.obj and DIR/STEM.yaml")
    im.add_argument("--obj", metavar="F", help="the OBJ written (default DIR/STEM.obj)")
    im.add_argument("--scene", metavar="F", help="the scene skeleton written "
                    "(default DIR/STEM.yaml)")
    im.add_argument("--size", metavar="S", help="the size of a graded file (default: its "
                    "base size, 'Sample Size:')")
    im.add_argument("--edge", metavar="M", type=_edge, default=DEFAULT_EDGE,
                    help="target edge length of the triangles, m (default %g)" % DEFAULT_EDGE)
    im.add_argument("--units", choices=sorted(dxf.UNIT_NAMES),
                    help="the drawing unit, overriding what the file says")
    im.add_argument("--pieces", metavar="LIST", help="comma-separated piece names, block "
                    "names or categories (FRONT, SLEEVE, ...; case ignored): import exactly "
                    "these (default: all but Quantity 0 pieces and alternates)")
    im.add_argument("--list", action="store_true", help="print the pieces, sizes and the "
                    "entities skipped, and write nothing")
    im.add_argument("--quiet", action="store_true", help="print only errors and warnings")
    return ap


def _extent(xy):
    lo, hi = xy.min(0), xy.max(0)
    return hi - lo


def _list(pat, size, pieces):
    print("file: %s" % pat.path)
    print("units: %s" % pat.units)
    for k, v in pat.style.items():
        print("style: %s: %s" % (k, v))
    if pat.sizes:
        print("sizes: %s (base %s)" % (", ".join(pat.sizes), pat.base_size))
    else:
        print("sizes: not graded")
    failed = None
    try:
        chosen, size = dxf.select(pat, size, pieces)
    except dxf.PatternError as e:  # listed all the same, then raised
        failed, chosen, size = e, [], size or pat.base_size
    print("pieces: %d; size %s: %d imported%s" % (
        len(pat.pieces), size or "-", len(chosen), "".join("; " + n for n in pat.notes)))
    for p in pat.pieces:
        bits = ["block '%s'" % p.block, "size %s" % (p.size or "-"),
                "quantity %s" % (p.quantity if p.quantity is not None else "-"),
                "category %s" % (p.category or "-"), "copy %d" % p.copy]
        if p.mirrored:
            bits.append("mirrored")
        if p.fold is not None:
            bits.append("unfolded")
        if p.group is not None:
            bits.append("imported as %s" % p.group if p.excluded is None
                        else "not imported: %s" % p.excluded)
        print("  %s: %s" % (p.name, ", ".join(bits)))
        if p.error is not None:
            print("    error: %s" % p.error)
            continue
        w, h = _extent(p.boundary)
        print("    %s: %.4g x %.4g m, %.6g m², %d points" %
              (p.boundary_from, w, h, signed_area(p.boundary), len(p.boundary)))
        print("    grain line: %s; notches %d, drill holes %d, internal lines %d, cutouts %d" %
              ("yes" if p.grain is not None else "none (u along the file's x axis)",
               len(p.notches), len(p.drills), len(p.internal), len(p.holes)))
        for k, v in p.texts.items():
            print("    text: %s: %s" % (k, v))
        for wn in p.warnings:
            print("    warning: %s" % wn)
    print("skipped: %d" % len(pat.skipped))
    for s in pat.skipped:
        print("  %s: %s: %s" % (s.where, s.what, s.why))
    for r in pat.repaired:
        print("repaired by ezdxf: %s" % r)
    if failed is not None:
        raise failed


def _outputs(a):
    stem = os.path.splitext(os.path.basename(a.file))[0] or "pattern"
    folder = a.out if a.out is not None else (os.path.dirname(a.file) or ".")
    obj = a.obj or os.path.join(folder, stem + ".obj")
    scene = a.scene or os.path.join(folder, stem + ".yaml")
    real = {os.path.realpath(p) for p in (a.file,)}
    for p in (obj, scene):
        if os.path.realpath(p) in real:
            raise dxf.PatternError("%s would overwrite the input; expected another path" % p)
        folder = os.path.dirname(os.path.abspath(p))
        if not os.path.isdir(folder) and not (a.out and folder == os.path.abspath(a.out)):
            raise dxf.PatternError("%s: its folder does not exist" % p)
    if os.path.realpath(obj) == os.path.realpath(scene):
        raise dxf.PatternError("--obj and --scene name the same file %s" % obj)
    return obj, scene, stem


def _import(a):
    pat = dxf.read(a.file, units=a.units)
    if a.list:
        return _list(pat, a.size, a.pieces)
    obj, scene, stem = _outputs(a)
    meshed = mesh(pat, size=a.size, edge=a.edge, pieces=a.pieces)
    size = a.size or pat.base_size
    for n in pat.notes:
        print("sinew pattern: note: %s" % n, file=sys.stderr)
    for m in meshed:
        for wn in m.piece.warnings:
            print("sinew pattern: warning: %s" % wn, file=sys.stderr)
    for m in meshed:
        w, h = _extent(m.uv)
        if max(w, h) > PLAUSIBLE[1] or max(w, h) < PLAUSIBLE[0]:
            print("sinew pattern: warning: %s is %.3g x %.3g m: are the units right (%s)? "
                  "--units sets them" % (m.piece.label, w, h, pat.units), file=sys.stderr)
    positions, laid = layout(meshed)
    cmd = "sinew pattern import %s%s --edge %g%s" % (
        os.path.basename(a.file), " --size %s" % size if size else "", a.edge,
        " --pieces '%s'" % a.pieces if a.pieces is not None else "")
    body = ["  " + cmd,
            "units %s; %d pieces, %d vertices, %d triangles; edges about %g m." %
            (pat.units, len(meshed), sum(len(m.xy) for m in meshed),
             sum(len(m.tris) for m in meshed), a.edge),
            "The pieces lie flat in the plane z = 0, %s; (u,v) are in metres with u along"
            % ("laid side by side (their places in the file overlap)" if laid
               else "where the file places them"),
            "each piece's grain line (the warp)."]

    def header(path):
        return ["%s: the pattern %s, written by" % (os.path.basename(path),
                                                   os.path.basename(a.file))] + body
    obj_rel = os.path.relpath(os.path.abspath(obj), os.path.dirname(os.path.abspath(scene)))
    if a.out is not None:
        try:
            os.makedirs(a.out, exist_ok=True)
        except OSError as e:
            raise dxf.PatternError("--out %s: cannot make the folder: %s" % (a.out, e.strerror))
    write_atomic([(obj, obj_text(meshed, positions, header(obj))),
                  (scene, scene_text(meshed, obj_rel, header(scene), stem))])
    if not a.quiet:
        left = [p for p in pat.pieces if p.excluded is not None and p.group is not None]
        if left:
            print("not imported (--pieces names them): %s" % "; ".join(
                "%s (%s)" % (p.group, p.excluded) for p in left))
        for m in meshed:
            print("%s: %d vertices, %d triangles, %.6g m², %d corners, %d notches%s" %
                  (m.group, len(m.xy), len(m.tris), m.area, len(m.corners), len(m.notches),
                   "" if m.grain_from_line else ", no grain line (u along x)"))
        print("wrote %s and %s" % (obj, scene))
    if pat.repaired:
        print("sinew pattern: ezdxf repaired %d things in %s while reading it (--list names "
              "each)" % (len(pat.repaired), a.file), file=sys.stderr)
    if pat.skipped:
        why = collections.Counter(s.why.split(" (")[0] for s in pat.skipped)
        print("sinew pattern: %d entities not used (sinew pattern import --list %s names "
              "each): %s" % (len(pat.skipped), a.file,
                             "; ".join("%d %s" % (n, w) for w, n in why.most_common())),
              file=sys.stderr)
    return None


def main(argv=None):
    a = _parser().parse_args(argv)
    try:
        _import(a)
    except dxf.PatternError as e:
        print("sinew pattern: %s" % e, file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:  # `... --list | head`: the reader left
        sys.stderr.close()
        return 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
