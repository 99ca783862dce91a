"""sinew pattern import: AAMA DXF and ASTM D6673 pattern files → an OBJ of meshed pieces (a
group per piece, per-corner (u,v) in metres with u along the grain line) and a scene skeleton.

    python3 -m sinew.pattern import FILE.dxf [--out DIR | --obj F --scene F] [--size S]
                                             [--edge M] [--units in|mm|cm|m]
                                             [--pieces LIST] [--list]

(`sinew pattern import ...` runs the same.)  Reading: dxf.py (ezdxf); meshing: mesh.py (gmsh);
writing: write.py.  docs/patterns.md is the guide.  From Python:

    pat = sinew.pattern.read("skirt.dxf")           # every piece of every size, in m
    pieces = sinew.pattern.mesh(pat, size="M", edge=0.02)
"""
from .dxf import (Pattern, PatternError, Piece, Skipped, category_of, read,  # noqa: F401
                  select)
from .mesh import Meshed, layout, mesh_piece  # noqa: F401

# Target edge length, m: docs/patterns.md, "Edge length", has the measurement behind it.
DEFAULT_EDGE = 0.02


def mesh(pattern, size=None, edge=DEFAULT_EDGE, pieces=None):
    """The pieces of one size (None: the base size) meshed at target edge length edge (m):
    a list of Meshed, in file order.  pieces: None (every piece but Quantity 0 ones and
    alternates) or a comma-separated list of names and categories (dxf.select).  Pieces that
    cannot be meshed raise PatternError."""
    pieces, _ = select(pattern, size, pieces)
    out = []
    for p in pieces:
        try:
            out.append(mesh_piece(p, p.group, edge, pattern.skipped))
        except PatternError as e:
            raise PatternError("%s: %s" % (pattern.path, e)) from None
    return out
