"""sinew render RUN_DIR: pictures of a run's tension XY map, headless (matplotlib's Agg backend).

For every frame of the run folder (or those chosen) one PNG: on the left the flat pattern, each
panel in its rest (u,v) layout; on the right the 3D shape; both coloured by tension XY (N/m,
one colour bar, one scale for the whole run), the tendons drawn over them coloured by their
tension (N, a second colour bar) and labelled with it.  Then an animation of all of them: a GIF
(Pillow) or, where ffmpeg is installed and asked for, an MP4.

    python3 -m sinew.render RUN_DIR [--out DIR] [--every K] [--last] [--animation gif|mp4|none]
                                    [--dpi N] [--quiet]
"""
import argparse
import os
import shutil
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import animation, cm, colors  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402

from . import frames  # noqa: E402

GAP = 0.05  # gap between panels laid side by side, as a share of the widest panel


def face_uv(cloth):
    """(nf, 3, 2) rest (u,v) of each face's corners, m: uv_corners at seams, else the points'."""
    nf = len(cloth.offsets)
    if "uv_corners" in cloth.cell_data:
        return cloth.cell_data["uv_corners"].reshape(nf, 3, 2)
    if "uv" not in cloth.point_data:
        return cloth.points[:, :2][cloth.connectivity.reshape(nf, 3)]
    return cloth.point_data["uv"][cloth.connectivity.reshape(nf, 3)]


def pattern_layout(cloth):
    """Each face's corners in the flat view, m: each panel in its (u,v) layout, panels whose
    boxes overlap moved side by side; and the shift of each panel (panel id -> (du, dv))."""
    uv = face_uv(cloth).copy()
    panel = cloth.cell_data.get("panel", np.zeros(len(uv), dtype=np.int32))
    ids = sorted(set(panel.tolist()))
    boxes = {p: (uv[panel == p].reshape(-1, 2).min(0), uv[panel == p].reshape(-1, 2).max(0))
             for p in ids}
    overlap = any(np.all(boxes[a][0] < boxes[b][1]) and np.all(boxes[b][0] < boxes[a][1])
                  for i, a in enumerate(ids) for b in ids[i + 1:])
    shift = {p: np.zeros(2) for p in ids}
    if overlap:
        gap = GAP * max(hi[0] - lo[0] for lo, hi in boxes.values())
        x = 0.0
        for p in ids:
            lo, hi = boxes[p]
            shift[p] = np.array([x - lo[0], -lo[1]])
            x += hi[0] - lo[0] + gap
    for p in ids:
        uv[panel == p] += shift[p]
    return uv, panel, shift


def tendon_pattern(cloth, tend, panel, shift):
    """Each tendon's waypoints in the flat view: the (u,v) of the vertex in its first face."""
    nf = len(cloth.offsets)
    tri = cloth.connectivity.reshape(nf, 3)
    first = np.full(len(cloth.points), -1)
    for f in range(nf - 1, -1, -1):
        first[tri[f]] = f
    uv = cloth.point_data.get("uv", cloth.points[:, :2])
    lines = []
    for cell in tend.cells():
        verts = tend.point_data["vertex"][cell]
        lines.append(np.array([uv[v] + shift[panel[first[v]]] if first[v] >= 0 else uv[v]
                               for v in verts]))
    return lines


def scales(run):
    """One colour scale per quantity over the whole run: tension XY (N/m), tendon tension (N)."""
    txy = np.concatenate([p["cloth"].cell_data["tension_xy"] for _, p in run])
    tt = [p["tendons"].cell_data["tension"] for _, p in run if "tendons" in p]
    lo, hi = float(txy.min()), float(txy.max())
    if hi <= lo:
        hi = lo + 1.0
    tmax = float(np.concatenate(tt).max()) if tt else 0.0
    return colors.Normalize(lo, hi), colors.Normalize(0.0, tmax if tmax > 0 else 1.0)


def draw_flat(ax, cloth, tend, txy_norm, t_norm):
    uv, panel, shift = pattern_layout(cloth)
    ax.add_collection(PolyCollection(uv, array=cloth.cell_data["tension_xy"], cmap="viridis",
                                     norm=txy_norm, edgecolors="face", linewidths=0.2))
    if tend is not None:
        lines = tendon_pattern(cloth, tend, panel, shift)
        tension = tend.cell_data["tension"]
        ax.add_collection(LineCollection(lines, array=tension, cmap="autumn_r", norm=t_norm,
                                         linewidths=2.5))
        for line, tn in zip(lines, tension):
            ax.annotate("%.3g N" % tn, line[len(line) // 2], xytext=(0, 6),
                        textcoords="offset points", ha="center", fontsize=9, color="black",
                        bbox={"boxstyle": "round", "fc": "white", "alpha": 0.7, "lw": 0})
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("u (m)")
    ax.set_ylabel("v (m)")
    ax.set_title("flat pattern")


def draw_shape(ax, cloth, tend, txy_norm, t_norm):
    nf = len(cloth.offsets)
    tris = cloth.points[cloth.connectivity.reshape(nf, 3)]
    rgba = cm.viridis(txy_norm(cloth.cell_data["tension_xy"]))
    ax.add_collection3d(Poly3DCollection(tris, facecolors=rgba, edgecolors=rgba, linewidths=0.1))
    if tend is not None:
        lines = [tend.points[c] for c in tend.cells()]
        tension = tend.cell_data["tension"]
        ax.add_collection3d(Line3DCollection(lines, colors=cm.autumn_r(t_norm(tension)),
                                             linewidths=2.5))
        for line, tn in zip(lines, tension):
            ax.text(*line[len(line) // 2], " %.3g N" % tn, fontsize=9, zorder=10)
    lo, hi = cloth.points.min(0), cloth.points.max(0)
    mid, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-9)
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid):
        setter(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.set_title("3D shape")


def draw(fig, t, parts, txy_norm, t_norm, name):
    """One frame on fig (cleared first)."""
    fig.clf()
    cloth, tend = parts["cloth"], parts.get("tendons")
    flat = fig.add_axes([0.07, 0.24, 0.38, 0.64])
    shape = fig.add_axes([0.5, 0.2, 0.46, 0.72], projection="3d")
    draw_flat(flat, cloth, tend, txy_norm, t_norm)
    draw_shape(shape, cloth, tend, txy_norm, t_norm)
    fig.colorbar(cm.ScalarMappable(norm=txy_norm, cmap="viridis"), orientation="horizontal",
                 cax=fig.add_axes([0.08, 0.08, 0.38, 0.03]), label="tension XY (N/m)")
    if tend is not None:
        fig.colorbar(cm.ScalarMappable(norm=t_norm, cmap="autumn_r"), orientation="horizontal",
                     cax=fig.add_axes([0.56, 0.08, 0.38, 0.03]), label="tendon tension (N)")
    fig.suptitle("%s   t = %.4g s" % (name, t))


def writer_for(kind, out):
    """The animation writer and file: GIF through Pillow, MP4 through ffmpeg; None for none."""
    if kind == "none":
        return None, None
    if kind == "mp4":
        if not shutil.which("ffmpeg"):
            raise SystemExit("sinew render: --animation mp4 needs ffmpeg on the PATH")
        return animation.FFMpegWriter(fps=10), os.path.join(out, "tension.mp4")
    return animation.PillowWriter(fps=10), os.path.join(out, "tension.gif")


def render(run_dir, out=None, every=1, last=False, kind="gif", dpi=100, quiet=False):
    """Render the frames of run_dir into out (default RUN_DIR/render); the files written."""
    out = out or os.path.join(run_dir, "render")
    os.makedirs(out, exist_ok=True)
    run = list(frames.read_run(run_dir))
    if not run:
        raise SystemExit("sinew render: %s/frames.pvd lists no frames" % run_dir)
    chosen = [len(run) - 1] if last else list(range(0, len(run), every))
    if chosen[-1] != len(run) - 1:
        chosen.append(len(run) - 1)
    txy_norm, t_norm = scales(run)
    name = os.path.basename(os.path.normpath(run_dir))
    fig = plt.figure(figsize=(11, 6))
    writer, movie = writer_for("none" if len(chosen) < 2 else kind, out)
    written = []
    if writer:
        writer.setup(fig, movie, dpi=dpi)
    for i in chosen:
        t, parts = run[i]
        draw(fig, t, parts, txy_norm, t_norm, name)
        png = os.path.join(out, "tension_%06d.png" % i)
        fig.savefig(png, dpi=dpi)
        written.append(png)
        if writer:
            writer.grab_frame()
        if not quiet:
            print("sinew render: %s (t = %g s)" % (png, t), file=sys.stderr)
    if writer:
        writer.finish()
        written.append(movie)
        if not quiet:
            print("sinew render: %s (%d frames)" % (movie, len(chosen)), file=sys.stderr)
    plt.close(fig)
    return written


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="sinew render",
        description="Draw the tension XY map of every frame of a sinew run folder on the flat "
                    "pattern and on the 3D shape, tendons with their tension, as PNG files, and "
                    "an animation of the run (headless: matplotlib's Agg backend).")
    ap.add_argument("run_dir", metavar="RUN_DIR", help="a run folder (with frames.pvd)")
    ap.add_argument("--out", metavar="DIR", help="where the pictures go (default RUN_DIR/render)")
    ap.add_argument("--every", metavar="K", type=int, default=1,
                    help="every K-th frame (and the last; default 1: all)")
    ap.add_argument("--last", action="store_true", help="the last frame only, no animation")
    ap.add_argument("--animation", choices=("gif", "mp4", "none"), default="gif",
                    help="gif (Pillow, default), mp4 (needs ffmpeg) or none")
    ap.add_argument("--dpi", type=int, default=100, help="dots per inch (default 100: 1100x600)")
    ap.add_argument("--quiet", action="store_true", help="no line per file written")
    a = ap.parse_args(argv)
    if a.every < 1:
        ap.error("--every expects an integer >= 1")
    if not os.path.isfile(os.path.join(a.run_dir, "frames.pvd")):
        ap.error("%s has no frames.pvd (a run with --no-frames?)" % a.run_dir)
    render(a.run_dir, a.out, a.every, a.last, a.animation, a.dpi, a.quiet)
    return 0


if __name__ == "__main__":
    sys.exit(main())
