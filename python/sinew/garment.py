"""sinew garment: from a DXF pattern to a fitted garment in one command (docs/garments.md, "From
a DXF to a fitted garment").

    python3 -m sinew.garment FILE.dxf [--size S | --sizes all|S1,S2,...] [--fabric '{...}']
                             [--edge M] [--out DIR] [--pieces A,B,...] [--seams FILE]
                             [--body '...' | --body-table FILE] [--arrange FILE]

(`sinew garment ...` runs the same.)  Per size: the pieces imported and meshed
(sinew.pattern), turned u up, sewn automatically (sinew.pattern.sew: seams by corner and
notch names, those of --seams replacing proposed ones of the same name), arranged from the
landmarks of the mannequin (scenes/meshes/mannequin_arms.obj) or of a body of the size's
measurements (sinew.body; FRONT at -y, BACK at +y, sleeves about the arms)
and fitted by `sinew run` at the fit's defaults; then a summary from the run folder.  Exit 0
when every fit ends ok, 1 on an error (nothing is left in DIR of a size that failed before its
run) or a failed fit, 2 on bad arguments."""
import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile

import numpy as np

from . import body as bodies
from . import pattern
from .pattern import dxf, sew
from .pattern.write import MATERIAL, obj_text, write_atomic
from .pattern.mesh import layout

HERE = os.path.dirname(os.path.abspath(__file__))
BODY = os.path.join(HERE, "..", "..", "scenes", "meshes", "mannequin_arms.obj")
# The DXF T-shirt's arrangement (scenes/garment_tshirt_dxf.yaml): the tops 1.47 m up, above
# the mannequin's shoulder ridge (1.42-1.43 m), 2 cm clear of it; a sleeve about its arm's axis
# (45 degrees down from the shoulder joint at x = +-0.206 m, z = 1.371 m).
TOP, CLEAR = 1.47, 0.02
ARM = (0.206336, 1.37071)
# The tops' height on another body: as far above its neck base (sinew.body's landmark) as
# TOP is above the mannequin's (0.848 x 1.70 m), scaled with the height.
TOP_ABOVE_NECK, REF_HEIGHT = TOP - 0.848 * 1.70, 1.70
DURATION = 0.1   # s of dynamics after the fit: one frame at rest


class GarmentError(Exception):
    pass


def _repo_file(path):
    path = os.path.normpath(path)
    if not os.path.exists(path):
        raise GarmentError("the mannequin %s is not found (sinew garment runs from a source "
                           "checkout, which holds scenes/meshes)" % path)
    return path


class Points:
    """Arrangement points on a body: top, the height of the body pieces' tops (m); arms,
    {+1 (left), -1 (right): (the cap's top on the arm's axis, the unit axis towards the
    fingertips)}; neck, the centre of the neck's base section."""

    def __init__(self, top, arms, neck):
        self.top, self.arms, self.neck = top, arms, neck

    @classmethod
    def of(cls, marks, height):
        """From sinew.body's landmarks of a body of this height."""
        return cls(marks["neck_base"][2] + TOP_ABOVE_NECK * height / REF_HEIGHT,
                   {s: (marks[k + "_arm"], marks[k + "_arm_direction"])
                    for s, k in ((1, "left"), (-1, "right"))}, marks["neck_base"])


# the shipped mannequin's (its OBJ header's arm axes)
MANNEQUIN = Points(TOP, {s: ((s * ARM[0], 0.0, ARM[1]), (s * 0.707107, 0.0, -0.707107))
                         for s in (1, -1)}, (0.0, 0.0, 0.848 * 1.70))


def _vec(v):
    return "[%s]" % ", ".join("%g" % (x + 0.0) for x in v)   # + 0.0: no -0


def arrangement(meshed, seams, pts=MANNEQUIN, given=None):
    """`arrange` lines: each piece by its category, from the body's arrangement points: FRONT
    wrapped in front of the torso (-y), BACK behind it (+y), their tops at pts.top; the sleeve
    sewn to the left armholes about the left arm (+x), the other about the right, its cap at
    the arm's cap; a COLLAR round the neck from its base up.  given: {piece: one-line YAML}
    replacing a piece's entry (--arrange)."""
    left = {s.b.panel for s in seams if s.name == "left_armhole_front"}
    given = dict(given or {})
    unknown = sorted(set(given) - {m.group for m in meshed})
    if unknown:
        raise GarmentError("--arrange: no piece %s; expected one of: %s"
                           % (", ".join(unknown), ", ".join(m.group for m in meshed)))
    out = []
    for m in meshed:
        cat = sew.category(m)
        name = json.dumps(m.group)
        if m.group in given:
            out.append("  %s: %s    # given" % (name, given[m.group]))
        elif cat in ("FRONT", "BACK"):
            out.append("  %s: {cylinder: {angle: %d, top: %g, clearance: %g, up: u}}"
                       % (name, 270 if cat == "FRONT" else 90, pts.top, CLEAR))
        elif cat == "SLEEVE":
            s = 1 if m.group in left else -1
            cap, d = pts.arms[s]
            out.append("  %s: {cylinder: {angle: %d, top: 0, clearance: %g, up: u, axis: "
                       "%s, center: %s}}" % (name, 0 if s > 0 else 180, CLEAR,
                                             _vec(-np.asarray(d, float)), _vec(cap)))
        elif cat == "COLLAR":
            # the long way round the neck: u round (up: v) when the piece is longer in u
            du, dv = np.ptp(np.asarray(m.uv, float), axis=0)
            out.append("  %s: {cylinder: {angle: 90, top: %g, clearance: %g, up: %s, "
                       "center: %s}}" % (name, pts.neck[2] + min(du, dv), CLEAR,
                                         "v" if du >= dv else "u", _vec(pts.neck[:2])))
        else:
            raise GarmentError("%s (%s): no arrangement for this category; expected FRONT, "
                               "BACK, SLEEVE or COLLAR pieces (--pieces chooses them; "
                               "--arrange places others)" % (m.group, cat or "no category"))
    return out


def _given_arrange(path):
    """--arrange FILE: {piece: one-line YAML of its entry} from its `arrange:` map."""
    import yaml
    try:
        with open(path, encoding="utf-8") as f:
            doc = yaml.safe_load(f)
    except OSError as e:
        raise GarmentError("--arrange %s: %s" % (path, e.strerror)) from None
    except yaml.YAMLError as e:
        raise GarmentError("--arrange %s: not YAML: %s" % (path, e)) from None
    items = doc.get("arrange") if isinstance(doc, dict) else None
    if not isinstance(items, dict) or not all(isinstance(v, dict) for v in items.values()):
        raise GarmentError("--arrange %s: expected an `arrange:` map from piece to its entry"
                           % path)
    return {str(k): json.dumps(v) for k, v in items.items()}


def _given_seams(path):
    """--seams FILE: [(name, one-line YAML of the entry)] from its `seams:` list."""
    import yaml
    try:
        with open(path, encoding="utf-8") as f:
            doc = yaml.safe_load(f)
    except OSError as e:
        raise GarmentError("--seams %s: %s" % (path, e.strerror)) from None
    except yaml.YAMLError as e:
        raise GarmentError("--seams %s: not YAML: %s" % (path, e)) from None
    items = doc.get("seams") if isinstance(doc, dict) else None
    if not isinstance(items, list) or not all(isinstance(s, dict) and s.get("name")
                                              for s in items):
        raise GarmentError("--seams %s: expected a `seams:` list of entries with a `name`"
                           % path)
    return [(str(s["name"]), json.dumps(s)) for s in items]


def build(path, size, edge, pieces=None):
    """One size's pieces meshed, turned u up and sewn: (meshed, seams, flat positions)."""
    pat = pattern.read(path)
    return _sewn(pattern.mesh(pat, size=size, edge=edge,
                              pieces=",".join(pieces) if pieces else None))


def _sewn(meshed):
    meshed = sew.upright(meshed)
    seams = sew.propose(meshed)
    positions, _ = layout(meshed)
    return meshed, seams, positions


def scene_text(meshed, seams, stem, size, edge, given=(), fabric=None, body=BODY,
               pts=MANNEQUIN, measured=None, placed=None):
    out = ["# %s: written by sinew garment (size %s, edges about %g m): the pieces turned u up,"
           % (stem, size or "-", edge),
           "# sewn automatically (docs/garments.md, \"Automatic sewing\"), arranged round the "
           + ("mannequin" if measured is None else "body of %s" % measured.text()),
           "name: %s" % json.dumps(stem), "dimension: 3",
           "mesh: {obj: pieces.obj}"]
    if fabric:
        out += ["material:", "  fabric: %s" % fabric]
    else:
        out.append(MATERIAL.rstrip())
    out += ["gravity: [0, 0, -9.81]", "obstacles:", "  - {mesh: %s}" % json.dumps(body),
            "contact: {self: true, thickness: 5e-4, friction: 0.5}", "arrange:"]
    out += arrangement(meshed, seams, pts, placed)
    out.append("panels:")
    first = 0
    for m in meshed:
        marks = ["%s: [%s]" % (key, ", ".join(str(v + first) for v in vals))
                 for key, vals in (("corners", m.corners), ("notches", m.notches)) if vals]
        out.append("  %s: {%s}" % (json.dumps(m.group), ", ".join(marks)))
        first += len(m.xy)
    out.append(sew.seams_yaml(seams, given))
    out += ["damping: {mass: 0.5}", "integrator: {method: backward-euler, dt: 0.01}",
            "duration: %g" % DURATION, "output: {frames_every: %g}" % DURATION]
    return "\n".join(out) + "\n"


def sinew_exe():
    exe = os.environ.get("SINEW_EXE") or shutil.which("sinew")
    if not exe:
        build = os.path.join(HERE, "..", "..", "build", "sinew")
        exe = build if os.path.exists(build) else None
    if not exe:
        raise GarmentError("the sinew program is not found (run as `sinew garment`, or put it "
                           "on the PATH)")
    return exe


def tension_per_piece(run_dir, scene_path):
    """{piece: (max, p95)} of the last frame's tension XY, N/m, per OBJ group."""
    from . import frames, render
    run = list(frames.read_run(run_dir))
    cloth = run[-1][1]["cloth"]
    scene = render.Scene(run_dir, scene_path)
    piece, names = scene.pieces(cloth)
    t = cloth.cell_data["tension_xy"]
    return {names[p]: (float(t[piece == p].max()), float(np.percentile(t[piece == p], 95)))
            for p in sorted(set(piece.tolist()))}, run[-1], scene


def fit(scene_path, run_dir, quiet):
    """sinew run; (exit code, CPU s of the child)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run([sinew_exe(), "run", scene_path, "--out", run_dir, "--quiet"],
                       stdout=subprocess.DEVNULL if quiet else None)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.returncode, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def one_size(a, size, out_dir, given, measured=None, placed=None):
    """One size fitted into out_dir: on the body of Measurements `measured` (written as
    out_dir/body.obj), else on a.mannequin."""
    stem = os.path.splitext(os.path.basename(a.file))[0]
    meshed, seams, positions = build(a.file, size, a.edge, a.pieces)
    if not a.quiet:
        print("%s, size %s: %d pieces, %d vertices" % (a.file, size or "-", len(meshed),
                                                       sum(len(m.xy) for m in meshed)))
        print(sew.table(seams))
    extra, pts = [], MANNEQUIN
    if measured is not None:
        verts, tris, marks = bodies.body_mesh(measured)
        pts, body = Points.of(marks, measured.height), "body.obj"
        extra = [("body.obj", bodies.obj_text(verts, tris, marks, measured))]
    else:
        body = os.path.relpath(_repo_file(a.mannequin), os.path.abspath(out_dir))
    parent = os.path.dirname(os.path.abspath(out_dir))
    os.makedirs(parent, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix=".%s." % os.path.basename(out_dir), dir=parent)
    try:
        scene = os.path.join(tmp, "scene.yaml")
        write_atomic([(os.path.join(tmp, "pieces.obj"),
                       obj_text(meshed, positions, ["%s: the pieces of %s, size %s"
                                                    % ("pieces.obj", a.file, size or "-")])),
                      (scene, scene_text(meshed, seams, stem, size, a.edge, given, a.fabric,
                                         body, pts, measured, placed))]
                     + [(os.path.join(tmp, name), text) for name, text in extra])
        if os.path.exists(out_dir):
            shutil.rmtree(out_dir)
        os.replace(tmp, out_dir)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    try:
        rc, cpu = fit(os.path.join(out_dir, "scene.yaml"), os.path.join(out_dir, "run"),
                      a.quiet)
    except BaseException:
        shutil.rmtree(out_dir, ignore_errors=True)
        raise
    if not os.path.exists(os.path.join(out_dir, "run", "summary.json")):
        shutil.rmtree(out_dir, ignore_errors=True)
        raise GarmentError("sinew run on the scene of %s failed before its first step "
                           "(exit %d); nothing is left of it" % (a.file, rc))
    with open(os.path.join(out_dir, "run", "summary.json")) as f:
        summ = json.load(f)
    res = {"size": size, "dir": out_dir, "rc": rc, "cpu_s": cpu, "summary": summ}
    if os.path.exists(os.path.join(out_dir, "run", "frames.pvd")):
        res["tension"], res["last"], res["scene"] = tension_per_piece(
            os.path.join(out_dir, "run"), os.path.join(out_dir, "scene.yaml"))
    return res


def report(res):
    s = res["summary"]
    gap = s.get("seam_gap_max")
    lines = ["size %s: status %s, seam_gap_max %s, intersections self %s obstacle %s, fit %s s "
             "wall (%s steps), sinew run %.1f s CPU"
             % (res["size"] or "-", s.get("status"),
                "%.3g mm" % (1e3 * gap) if gap is not None else "-",
                s.get("self_intersections"), s.get("obstacle_intersections"),
                s.get("fit_wall_s"), s.get("fit_steps"), res["cpu_s"])]
    for name, (mx, p95) in (res.get("tension") or {}).items():
        lines.append("  %-24s tension XY max %.4g N/m, p95 %.4g N/m" % (name, mx, p95))
    lines.append("  run folder: %s" % os.path.join(res["dir"], "run"))
    return "\n".join(lines)


def sizes_table(results):
    rows = ["| size | piece | tension XY max (N/m) | p95 (N/m) | seam gap (mm) | fit CPU (s) |",
            "| --- | --- | --- | --- | --- | --- |"]
    for r in results:
        gap = r["summary"].get("seam_gap_max")
        for name, (mx, p95) in (r.get("tension") or {}).items():
            rows.append("| %s | %s | %.4g | %.4g | %s | %.1f |"
                        % (r["size"], name, mx, p95, "%.3g" % (1e3 * gap) if gap is not None
                           else "-", r["cpu_s"]))
    return "\n".join(rows) + "\n"


def sizes_picture(results, path):
    """Each size's tension map on its flat pattern, side by side at one colour scale."""
    from . import render
    from matplotlib import cm, colors
    plt = render.plt
    done = [r for r in results if r.get("last")]
    top = max(render.percentile_top([r["last"][1]["cloth"]], 99) for r in done)
    norm = colors.Normalize(0.0, top if top > 0 else 1.0)
    fig = plt.figure(figsize=(5.5 * len(done) + 0.5, 5.0))
    w = 0.92 / len(done)
    for k, r in enumerate(done):
        ax = fig.add_axes([0.06 + k * w, 0.22, w * 0.88, 0.68])
        render.draw_flat(ax, r["last"][1]["cloth"], None, norm, None, r["scene"])
        ax.set_title("size %s" % r["size"], fontsize=10)
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap="viridis"), orientation="horizontal",
                 cax=fig.add_axes([0.2, 0.11, 0.6, 0.03]), extend="max",
                 label="tension XY (N/m), one scale (99th percentile of all)")
    fig.savefig(path, dpi=100)
    plt.close(fig)


def _parser():
    ap = argparse.ArgumentParser(prog="sinew garment", description=__doc__.split("\n\n")[0])
    ap.add_argument("file", metavar="FILE.dxf")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--size", metavar="S", help="the size (default: the file's base size)")
    g.add_argument("--sizes", metavar="all|S1,S2", help="fit each size; a table and a picture "
                   "of every size's tension at one scale")
    ap.add_argument("--fabric", metavar="'{mass: ..}'", help="the material as a fabric: block "
                    "in measured units (docs/fabrics.md), a YAML flow mapping")
    ap.add_argument("--edge", type=float, default=pattern.DEFAULT_EDGE, metavar="M",
                    help="target edge length, m (default %g)" % pattern.DEFAULT_EDGE)
    ap.add_argument("--out", metavar="DIR", help="output folder (default: STEM_garment in "
                    "the current folder)")
    ap.add_argument("--pieces", metavar="A,B", help="only these pieces (the importer's names)")
    ap.add_argument("--seams", metavar="FILE", help="a YAML file whose `seams:` entries replace "
                    "proposed ones of the same name (others are added)")
    ap.add_argument("--mannequin", metavar="OBJ", default=BODY, help="the body, a closed mesh "
                    "with arms, standing as scenes/meshes/mannequin_arms.obj does (its default)")
    b = ap.add_mutually_exclusive_group()
    b.add_argument("--body", metavar="'height: M, bust: M, ...'", help="fit on a body of these "
                   "measurements (height, bust or chest, waist, hip, arm, sex: women or men; "
                   "m), every size on it")
    b.add_argument("--body-table", metavar="FILE.csv|yaml", help="fit each size on the body "
                   "of its row (one row a size of the pattern)")
    ap.add_argument("--arrange", metavar="FILE", help="a YAML file whose `arrange:` entries "
                    "replace the automatic placement of those pieces")
    ap.add_argument("--quiet", action="store_true")
    return ap


def _bodies(a, pat, sizes):
    """{size: Measurements} of --body (every size) or --body-table (each size its row; every
    size fitted must have one), {} for the mannequin."""
    if a.body:
        m = bodies.parse(a.body)
        return {s: m for s in sizes}
    if not a.body_table:
        return {}
    if a.mannequin != BODY:
        raise GarmentError("--mannequin and --body-table: give one body")
    table = bodies.read_table(a.body_table)
    if not pat.sizes:
        raise GarmentError("--body-table %s: %s is not graded (no sizes to look up); give its "
                           "body with --body" % (a.body_table, a.file))
    missing = [s for s in sizes if s not in table]
    if missing:
        raise GarmentError("--body-table %s: no row for size %s; its sizes: %s"
                           % (a.body_table, ", ".join(missing), ", ".join(table)))
    return {s: table[s] for s in sizes}


def main(argv=None):
    ap = _parser()
    a = ap.parse_args(argv)
    if a.body and a.mannequin != BODY:
        ap.error("--mannequin and --body: give one body")
    if not (0 < a.edge < 10):
        ap.error("--edge expects a length in m in (0, 10), got %g" % a.edge)
    a.pieces = [p for p in a.pieces.split(",") if p] if a.pieces else None
    stem = os.path.splitext(os.path.basename(a.file))[0]
    out = a.out or stem + "_garment"
    try:
        given = _given_seams(a.seams) if a.seams else ()
        pat = pattern.read(a.file)
        if a.sizes:
            sizes = pat.sizes if a.sizes == "all" else a.sizes.split(",")
            if not sizes:
                raise GarmentError("%s is not graded: --sizes needs sizes" % a.file)
        else:
            sizes = [a.size]
        for s in sizes:
            if s is not None and s not in pat.sizes:
                raise GarmentError("%s: no size '%s'; expected one of: %s" % (
                    a.file, s, ", ".join(pat.sizes) or "(the file is not graded)"))
        measured = _bodies(a, pat, sizes)
        placed = _given_arrange(a.arrange) if a.arrange else None
        multi = len(sizes) > 1 or a.sizes
        results = []
        for s in sizes:
            r = one_size(a, s, os.path.join(out, str(s)) if multi else out, given,
                         measured.get(s), placed)
            results.append(r)
            print(report(r))
        if multi:
            write_atomic([(os.path.join(out, "sizes.md"), sizes_table(results))])
            sizes_picture(results, os.path.join(out, "sizes.png"))
            print("wrote %s and %s" % (os.path.join(out, "sizes.md"),
                                        os.path.join(out, "sizes.png")))
    except (GarmentError, sew.SewError, dxf.PatternError, bodies.BodyError) as e:
        print("sinew garment: %s" % e, file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    ok = all(r["rc"] == 0 and r["summary"].get("status") == "ok" for r in results)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
