"""Writing an imported pattern: the OBJ (a group per piece, per-corner (u,v) in metres) and the
scene skeleton (YAML), each to a temporary file in its folder and renamed into place only when
both are written, so a failure leaves nothing half-written."""
import json
import os
import tempfile

# The skeleton's material: scenes/skirt.yaml's front panel, a light woven (150 g/m²), to be
# replaced by the fabric's own numbers (docs/scenes.md).  Bending is `morley`: on the unstructured
# meshes gmsh makes it reads the rigidity given within 0.1 % at 40 cells, where `quadratic` reads it
# 1-4 % too high (docs/models.md, the unstructured-mesh study), for 1.1-1.5x the time per step.
MATERIAL = ("material:                       # the fabric: replace with yours (docs/scenes.md,\n"
            "                                # or fabric: in measured units, docs/fabrics.md)\n"
            "  density: 0.15                 # kg/m²\n"
            "  membrane: {model: bw98, k_u: 2000, k_v: 1500, k_shear: 50}   # N/m\n"
            "  bending: {model: morley, stiffness: 1e-5}                    # N m\n")


def obj_text(meshed, positions, header):
    out = ["# %s" % line for line in header]
    base = 0
    for m, pos in zip(meshed, positions):
        out.append("g %s" % m.group)
        out += ["v %.9g %.9g %.9g" % tuple(q) for q in pos]
        out += ["vt %.9g %.9g" % tuple(q) for q in m.uv]
        out += ["f %d/%d %d/%d %d/%d" % (a, a, b, b, c, c)
                for a, b, c in (m.tris + base + 1)]
        base += len(pos)
    return "\n".join(out) + "\n"


def _wrapped(key, values, indent):
    """`key: [a, b, ...]` as YAML comment lines of at most 100 characters."""
    lines, cur = [], "#%s%s: [" % (" " * indent, key)
    for i, v in enumerate(values):
        tok = str(v) + (", " if i + 1 < len(values) else "")
        if len(cur) + len(tok) > 100:
            lines.append(cur.rstrip())
            cur = "#%s" % (" " * (indent + len(key) + 3))
        cur += tok
    return lines + [cur + "]"]


def scene_text(meshed, obj_rel, header, name):
    out = ["# %s" % line for line in header]
    out += ["#",
            "# Vertex indices below are 0-based, as scene selections count them",
            "# ({select: {vertices: [...]}}); each boundary runs counter-clockwise in (u,v),",
            "# starting at a corner; corners and notches are in boundary order.  `panels` below",
            "# lists each piece's corners and notches again, so that seams can name their ends",
            "# by them: a: {panel: NAME, from: {corner: 0}, to: {corner: 1}} (docs/garments.md).",
            "#", "# pieces:"]
    base = 0
    for m in meshed:
        p = m.piece
        info = ["block '%s'" % p.block]
        if p.size is not None:
            info.append("size %s" % p.size)
        if p.quantity is not None:
            info.append("quantity %d" % p.quantity)
        if p.category:
            info.append("category %s" % p.category)
        if p.mirrored:
            info.append("mirrored")
        if p.fold is not None:
            info.append("unfolded about its mirror line")
        info.append("%.6g m²" % m.area)
        out.append("#   %s:    # %s" % (json.dumps(m.group), ", ".join(info)))
        n = len(m.xy)
        out.append("#     vertices: [%d, %d]    # first and last" % (base, base + n - 1))
        for key, vals in (("corners", m.corners), ("notches", m.notches),
                          ("drill_holes", m.drills), ("boundary", m.boundary)):
            out += _wrapped(key, [v + base for v in vals], 5)
        for k, line in enumerate(m.internal):
            out += _wrapped("internal_line_%d" % (k + 1), [v + base for v in line], 5)
        for k, loop in enumerate(m.holes):
            out += _wrapped("cutout_%d" % (k + 1), [v + base for v in loop], 5)
        base += n
    out += ["", "name: %s" % json.dumps(name), "dimension: 3",
            "mesh: {obj: %s}" % json.dumps(obj_rel), MATERIAL.rstrip(), "panels:"]
    first = 0
    for m in meshed:
        marks = ["%s: [%s]" % (key, ", ".join(str(v + first) for v in vals))
                 for key, vals in (("corners", m.corners), ("notches", m.notches)) if vals]
        out.append("  %s: {%s}" % (json.dumps(m.group), ", ".join(marks)))
        first += len(m.xy)
    return "\n".join(out) + "\n"


def write_atomic(files):
    """files: [(path, text)].  Each is written to a temporary file beside it; all are renamed
    into place only when every one is written (and removed on any failure)."""
    temps = []
    umask = os.umask(0)  # mkstemp makes its file 0600: give the result the usual 0666 & ~umask
    os.umask(umask)
    try:
        for path, text in files:
            folder = os.path.dirname(os.path.abspath(path))
            fd, tmp = tempfile.mkstemp(prefix=".%s." % os.path.basename(path), dir=folder)
            temps.append(tmp)
            os.fchmod(fd, 0o666 & ~umask)
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                f.write(text)
        for (path, _), tmp in zip(files, temps):
            os.replace(tmp, path)
    except BaseException:
        for tmp in temps:
            if os.path.exists(tmp):
                os.unlink(tmp)
        raise
