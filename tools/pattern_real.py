#!/usr/bin/python3
"""pattern_real.py: `sinew pattern import` on a folder of real pattern CAD exports (default
../shared/patterns beside the checkout, where it exists): for each DXF file its base size
imported at --edge (default 0.02 m), each piece's name, category, copy, whether mirrored and
unfolded, size and mesh area, or the error that stopped it.

    PYTHONPATH=python /usr/bin/python3 tools/pattern_real.py [FOLDER] [--edge M]

Exit 0 when every file imports, 1 otherwise (the table is printed either way)."""
import argparse
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "python"))
from sinew import pattern  # noqa: E402


def one(path, edge):
    pat = pattern.read(path)
    meshed = pattern.mesh(pat, edge=edge)
    rows = []
    for m in meshed:
        p = m.piece
        w, h = m.uv.max(0) - m.uv.min(0)
        flags = [f for f, on in (("mirrored", p.mirrored), ("unfolded", p.fold is not None))
                 if on]
        rows.append("| | %s | %s | %d | %s | %.3f x %.3f | %.5f | %d |" % (
            m.group, p.category or "-", p.copy,
            " ".join(flags) or "-", w, h, m.area, len(m.xy)))
    left = [p for p in pat.pieces if p.excluded and p.group is not None]
    return meshed, rows, left


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder", nargs="?", default=os.path.join(ROOT, "..", "shared", "patterns"))
    ap.add_argument("--edge", type=float, default=0.02)
    a = ap.parse_args()
    if not os.path.isdir(a.folder):
        print("pattern_real.py: no folder %s: nothing to check" % a.folder, file=sys.stderr)
        return 0
    files = sorted(f for f in os.listdir(a.folder) if f.lower().endswith(".dxf"))
    failed = 0
    print("| file | piece | category | copy | | u x v (m) | area (m²) | vertices |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for f in files:
        try:
            meshed, rows, left = one(os.path.join(a.folder, f), a.edge)
        except pattern.PatternError as e:
            failed += 1
            print("| %s | **not imported**: %s | | | | | | |" % (f, str(e).replace("|", "/")))
            continue
        print("| %s | %d pieces | | | | | %.5f | %d |" % (
            f, len(meshed), sum(m.area for m in meshed), sum(len(m.xy) for m in meshed)))
        print("\n".join(rows))
        if left:
            print("| | not imported: %s | | | | | | |" % "; ".join(
                "%s (%s)" % (p.group, p.excluded) for p in left))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
