#!/usr/bin/python3
"""tools/bench_charts.py — the charts of a `sinew bench` folder.

    /usr/bin/python3 tools/bench_charts.py DIR [--title TEXT] [--series METHOD=VALUE[,...]]
                                               [--time cpu|wall]

Makes every chart whose CSV exists in DIR, each PNG beside its CSV, and prints the paths it
wrote. Exit 0; exit 2 on a missing DIR, a DIR without any bench CSV, a CSV missing a required
column (the message names the file and the column) or a --series run that does not exist.
A CSV with no usable rows gives a chart that says "no data". Needs numpy and matplotlib
(Debian's, hence /usr/bin/python3); the output is deterministic (same CSVs, same PNG bytes).
Each method has the same colour and marker in every chart.

--time: the time axis of work_precision.png, the runs' CPU time (user + system, column cpu_s)
or their wall time (wall_s); default: the folder's `time` setting (bench_*.cfg, `sinew bench
--time`), else cpu. A folder whose CSV has no CPU time (an older sinew) is drawn by wall time,
and its footnote says so.

work_precision.png (work_precision.csv, optional reference.csv)
    Relative error against median CPU (or wall) time, log-log, one line per method through its ok
    runs sorted by setting value, each point labelled with its value ("h=0.01" for a time
    step, "1e-3" for a tolerance). Panels: (a) pos_err_max, (b) txy_max_l2, (c) tendon_err
    when any run has one. Zero or empty errors are left out (log axes). A failed or crashed
    run is an x at the top edge of each panel at its time, and is listed under the
    panels with its `how`. With reference.csv, a dashed line at the reference's agreement
    level (pos_err, txy_err, tendon_err: the reference against its confirmation run):
    errors below it are not resolved.
stability.png (stability.csv, optional stability_limits.csv)
    The stability map: one panel per stiffness scale, one row per method, one cell per time
    step (sorted), coloured by status: stable, over-damped, failed, crashed, damaged, missing. With
    stability_limits.csv, the largest stable dt of each method and scale is outlined.
scaling.png (scaling.csv; also writes scaling_fit.csv)
    (a) wall time per step against DOFs (the median over the steps after the first; runs one at
    a time), log-log, with the least-squares exponent p of
    step_s ~ dofs^p (ok rows, >= 2 distinct sizes) in the legend and a dashed slope-1 line;
    (b) the factorisation's share of the step, against DOFs; (c) peak RSS against DOFs,
    log-log, with its exponent. scaling_fit.csv: method,time_exponent,memory_exponent,points.
tension_series.png (work_precision.csv and reference.csv, the runs' tension.csv)
    (a) txy_max and (b) txy_mean against time: the reference run thick black, one run per
    method thin in its colour: by default its ok run with the largest value (coarsest
    setting), or the one --series picks (e.g. --series bdf2=0.01,cvode=1e-4; any status).
    When the runs have tendons.csv, (c) the tension of the tendon with the largest
    reference tension (named in the panel title). A panel whose runs exceed 3x the
    reference's maximum is clipped there, and says so.
"""
import argparse
import csv
import math
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch, Rectangle  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter  # noqa: E402

DPI = 120
RC = {"font.size": 10, "axes.titlesize": 10, "axes.labelsize": 10, "legend.fontsize": 8.5,
      "xtick.labelsize": 8.5, "ytick.labelsize": 8.5, "figure.titlesize": 12,
      "axes.grid": True, "grid.alpha": 0.3, "svg.hashsalt": "sinew-bench"}

KNOWN = ["backward-euler", "baraff-witkin", "bdf2", "implicit-midpoint", "newmark",
         "symplectic-euler", "cvode", "ida"]
COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
           "#17becf", "#bcbd22", "#7f7f7f", "#393b79", "#ad494a", "#637939", "#8c6d31",
           "#7b4173", "#3182bd"]
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "h", "<", ">", "p", "*", "d", "H", "8", "o"]
ORDER = list(KNOWN)  # unknown methods are appended (sorted) by prime_styles

STATUS = [("stable", "#2ca02c"), ("over-damped", "#ff9f1c"), ("short", "#9ecae1"), ("failed", "#d62728"),
          ("crashed", "#3b0000"), ("damaged", "#6a3d9a"), ("missing", "#c8c8c8")]

WP_REQ = ["method", "setting", "value", "status", "wall_s", "pos_err_max", "txy_max_l2"]
REF_REQ = ["method", "pos_err", "txy_err", "run_dir"]
ST_REQ = ["method", "stiffness_scale", "dt", "status"]
LIM_REQ = ["method", "stiffness_scale", "largest_stable_dt"]
SC_REQ = ["method", "dofs", "step_s", "status"]
TENSION_REQ = ["time", "txy_max", "txy_mean"]
CLIP = 3.0  # tension series: y limit as a multiple of the reference's maximum
TENDON_REQ = ["time", "tendon", "tension"]
WP_PANELS = [("pos_err_max", "pos_err", "RMS position error / cloth size\n(max over samples)"),
             ("txy_max_l2", "txy_err", "tension XY max: L2 error"),
             ("tendon_err", "tendon_err", "tendon error")]


class BenchError(Exception):
    pass


class Timing:
    """The time the work-precision charts use: column 'cpu_s' or 'wall_s'."""
    col = "cpu_s"
    fallback = False  # asked for CPU time, the CSV has none: wall time


TIME = Timing()
TIME_NAME = {"cpu_s": "CPU time", "wall_s": "wall time"}


# ---------------------------------------------------------------- reading

def read_csv(path, required):
    """Rows of a CSV as dicts of stripped strings; an empty file has no rows."""
    with open(path, newline="", encoding="utf-8-sig") as f:
        lines = list(csv.reader(f))
    if not lines:
        return []
    header = [h.strip() for h in lines[0]]
    for col in required:
        if col not in header:
            raise BenchError(f"{path}: missing required column '{col}'")
    return [dict(zip(header, (v.strip() for v in line)))
            for line in lines[1:] if any(v.strip() for v in line)]


def num(row, key):
    """A field as a float; NaN when empty, absent or not a number."""
    try:
        return float(row.get(key) or "nan")
    except ValueError:
        return math.nan


def positive(v):
    return math.isfinite(v) and v > 0


def read_reference(d):
    path = os.path.join(d, "reference.csv")
    if not os.path.exists(path):
        return None
    rows = read_csv(path, REF_REQ)
    return rows[0] if rows else None


def warn(text):
    print(f"bench_charts: warning: {text}", file=sys.stderr)


# ---------------------------------------------------------------- styles and text

def prime_styles(d):
    """Give the methods of every CSV in DIR their colours now, so that all charts agree."""
    names = set()
    for name in ("work_precision.csv", "stability.csv", "scaling.csv", "stability_limits.csv"):
        path = os.path.join(d, name)
        if os.path.exists(path):
            names |= {r.get("method", "") for r in read_csv(path, [])}
    ORDER.extend(sorted(names - set(ORDER) - {""}))


def style(method):
    if method not in ORDER:
        ORDER.append(method)
    i = ORDER.index(method) % len(COLOURS)
    return {"color": COLOURS[i], "marker": MARKERS[i]}


def method_order(methods):
    return sorted(set(methods), key=lambda m: (ORDER.index(m) if m in ORDER else len(ORDER), m))


def compact(v):
    """0.001 -> '1e-3', 0.01 -> '0.01', 2.5e-05 -> '2.5e-5'."""
    if not math.isfinite(v):
        return "?"
    plain = f"{v:g}"
    mant, _, exp = f"{v:.3e}".partition("e")
    sci = f"{mant.rstrip('0').rstrip('.')}e{int(exp)}"
    return sci if len(sci) < len(plain) else plain


def ms(v):
    """A time step in milliseconds, one format for all: 0.01 -> '10 ms', 0.00125 -> '1.25 ms'."""
    return f"{round(v * 1e3, 9):g}\u00a0ms" if math.isfinite(v) else "?"  # no break before ms


def setting_text(setting, v):
    """A dt in ms ('2.5 ms'), a tolerance compact ('1e-3')."""
    return ms(v) if setting == "dt" else compact(v)


def run_label(row):
    """'dt=10 ms' or 'rtol=1e-3'."""
    setting = row.get("setting") or "value"
    return f"{setting}={setting_text(setting, num(row, 'value'))}"


def point_label(row):
    v = setting_text(row.get("setting"), num(row, "value"))
    return f"h={v}" if row.get("setting") == "dt" else v


def method_handle(method, label=None):
    return Line2D([], [], lw=1.5, ms=6, label=label or method, **style(method))


def no_data(ax, text="no data"):
    ax.text(0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center",
            fontsize=14, color="0.45")


def widen_log(ax, decades=1.2):
    """Widens a log axis spanning less than `decades` about its centre, so that it has a
    labelled power of ten and no crowded minor labels."""
    for get, set_, scale in ((ax.get_xlim, ax.set_xlim, ax.get_xscale),
                             (ax.get_ylim, ax.set_ylim, ax.get_yscale)):
        lo, hi = get()
        if scale() == "log" and 0 < lo < hi < lo * 10 ** decades:
            mid, half = math.sqrt(lo * hi), 10 ** (decades / 2)
            set_(mid / half, mid * half)


def readable_log(ax):
    """A log axis spanning less than two decades gets ticks at 1, 2 and 5 of each decade,
    labelled as plain numbers, so that it never shows a single power of ten."""
    for axis, lim, scale in ((ax.xaxis, ax.get_xlim, ax.get_xscale),
                             (ax.yaxis, ax.get_ylim, ax.get_yscale)):
        lo, hi = lim()
        if scale() != "log" or not (0 < lo < hi) or hi > lo * 100:
            continue
        axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        axis.set_major_formatter(FuncFormatter(tick_text))
        axis.set_minor_formatter(NullFormatter())


def tick_text(v, _pos=None):
    """A tick label: plain from 0.001 to 99999 (0.005, 20, 1000), else compact (5e-4)."""
    return f"{v:g}" if 1e-3 <= v < 1e5 else compact(v)


def read_cfg(d):
    """The key = value lines of the folder's bench_*.cfg files (the first file's win)."""
    cfg = {}
    for name in sorted(os.listdir(d)):
        if name.startswith("bench_") and name.endswith(".cfg"):
            for line in open(os.path.join(d, name), encoding="utf-8", errors="replace"):
                key, sep, val = line.strip().partition(" = ")
                if sep and not key.startswith("#"):
                    cfg.setdefault(key, val)
    return cfg


def footnote(d, timing=None):
    """What was measured where: scene, sinew version, machine, what the times are and their
    repeats (timing: the time's name, None: no times on the chart)."""
    cfg = read_cfg(d)
    parts = [f"scene {os.path.basename(cfg.get('scene', '?'))}",
             f"sinew {cfg.get('version', '(version not recorded)')}",
             cfg.get("cpu", "machine not recorded")]
    if timing:
        parts.append(f"{timing}: median of {cfg.get('repeat', '?')} repeats")
    return " · ".join(parts)


def suptitle(fig, name, title, d=None):
    scene = os.path.basename(read_cfg(d).get("scene", "")) if d else ""
    name = f"{name} — {scene}" if scene else name
    fig.suptitle(f"{title}: {name}" if title else name)


def put_footnote(fig, d, timing=None):
    fig.text(0.99, 0.005, footnote(d, timing), fontsize=7, ha="right", va="bottom", color="0.35")


def choose_time(d, rows, asked):
    """Sets TIME from --time (asked), else the folder's setting, else CPU time; wall time when
    the rows have no CPU time (a folder of an older sinew)."""
    want = asked or read_cfg(d).get("time", "cpu")
    TIME.col = "cpu_s" if want == "cpu" else "wall_s"
    TIME.fallback = TIME.col == "cpu_s" and not any(positive(num(r, "cpu_s")) for r in rows)
    if TIME.fallback:
        TIME.col = "wall_s"
        warn(f"{d}: no CPU time in work_precision.csv (an older sinew): drawn by wall time")


def time_note():
    """The footnote's timing part: 'CPU time (user + system)' or 'wall time'."""
    if TIME.col == "cpu_s":
        return "CPU time (user + system)"
    return "wall time (no CPU time recorded)" if TIME.fallback else "wall time"


def save(fig, path):
    fig.savefig(path, dpi=DPI, metadata={"Software": None}, bbox_inches="tight", pad_inches=0.15)
    plt.close(fig)
    print(path, flush=True)


def margins(fig, left, right, bottom, top, wspace=None):
    """subplots_adjust with margins in inches."""
    w, h = fig.get_size_inches()
    fig.subplots_adjust(left=left / w, right=1 - right / w, bottom=bottom / h, top=1 - top / h,
                        wspace=wspace)


# ---------------------------------------------------------------- work-precision

def chart_work_precision(d, title, asked_time=None):
    rows = read_csv(os.path.join(d, "work_precision.csv"), WP_REQ)
    choose_time(d, rows, asked_time)
    ref = read_reference(d)
    panels = WP_PANELS[:2] + [p for p in WP_PANELS[2:]
                              if any(positive(num(r, p[0])) for r in rows)]
    bad = [r for r in rows if r["status"] != "ok"]
    figw = 3.9 * len(panels) + 2.6
    note = failure_note(bad, figw)
    fig, axes = plt.subplots(1, len(panels), figsize=(figw, 5 + 0.16 * len(note)), squeeze=False)
    labels = [wp_panel(ax, rows, panel, ref, "abc"[k]) for k, (ax, panel) in
              enumerate(zip(axes[0], panels))]
    axes[0][0].set_ylabel("relative error")
    fig.legend(handles=wp_handles(rows, ref, panels, bad, read_orders(d)), loc="upper left",
               bbox_to_anchor=(1 - 2.45 / figw, 0.88), frameon=False)
    if note:
        fig.text(0.01, 0.03, "\n".join(note), fontsize=7.5, va="bottom", color="0.2")
    suptitle(fig, "Work-precision", title, d)
    put_footnote(fig, d, time_note())
    margins(fig, 0.75, 2.6, 0.8 + 0.16 * len(note), 0.75, wspace=0.3)
    for ax, cands in zip(axes[0], labels):
        readable_log(ax)
        place_labels(ax, cands)
    save(fig, os.path.join(d, "work_precision.png"))


def read_orders(d):
    """{method: legend text} from orders.csv: 'order 1.86 (dt 2.5-10 ms)'."""
    path = os.path.join(d, "orders.csv")
    out = {}
    if os.path.exists(path):
        for r in read_csv(path, ["method", "setting", "order", "range_lo", "range_hi"]):
            o = num(r, "order")
            lo, hi = num(r, "range_lo"), num(r, "range_hi")
            rng = (f"{round(lo * 1e3, 9):g}\u2013{ms(hi)}" if r["setting"] == "dt"
                   else f"{compact(lo)}\u2013{compact(hi)}")
            out[r["method"]] = (f"order {o:.2f} ({r['setting']} {rng})" if math.isfinite(o)
                                else "order: no converged range")
    return out


def wp_handles(rows, ref, panels, bad, orders):
    handles = [method_handle(m, f"{m}\n  {orders[m]}" if m in orders else None)
               for m in method_order(r["method"] for r in rows)]
    if ref is not None and any(positive(num(ref, p[1])) for p in panels):
        handles.append(Line2D([], [], color="black", ls="--", lw=1.2, label=ref_label(ref)))
    if bad:
        handles.append(Line2D([], [], color="0.3", ls="none", marker="x", mew=2,
                              label=f"failed / crashed run\n(at its {TIME_NAME[TIME.col]})"))
    return handles


def wp_panel(ax, rows, panel, ref, letter):
    """One error column against CPU or wall time; returns the point labels to place."""
    col, refcol, label = panel
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_title(f"({letter}) {label}")
    ax.set_xlabel(f"{TIME_NAME[TIME.col]} (s, median)")
    cands = [c for m in method_order(r["method"] for r in rows)
             for c in wp_method(ax, rows, m, col)]
    if ref is not None and positive(num(ref, refcol)):
        ax.axhline(num(ref, refcol), color="black", ls="--", lw=1.2, zorder=1)
    if not cands and not (ref is not None and positive(num(ref, refcol))):
        ax.set_ylim(1e-6, 1)
        no_data(ax, "no data" if not rows else "no ok run with this error")
    n_failed = failed_marks(ax, rows)
    widen_log(ax)
    if n_failed:
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, hi * (hi / lo) ** 0.1)  # headroom for the x marks
    return cands


def wp_method(ax, rows, method, col):
    """Draws the ok runs of one method, sorted by value; returns their label candidates
    (priority, x, y, text, colour): the two ends of the line first."""
    pts = [r for r in rows if r["method"] == method and r["status"] == "ok"
           and positive(num(r, TIME.col)) and positive(num(r, col))]
    pts.sort(key=lambda r: (not math.isfinite(num(r, "value")), num(r, "value")))
    if not pts:
        return []
    st = style(method)
    x, y = [num(r, TIME.col) for r in pts], [num(r, col) for r in pts]
    ax.plot(x, y, lw=1.5, ms=6, **st)
    return [(0 if i in (0, len(pts) - 1) else 1, x[i], y[i], point_label(r), st["color"])
            for i, r in enumerate(pts)]


def place_labels(ax, cands):
    """Annotates the points greedily (by priority), right of the point, else left, else
    below, skipping a label that would overlap a marker or a label already placed, or leave
    the axes. Call once the axes' limits and position are final."""
    ax.get_xlim(), ax.get_ylim()  # applies any pending autoscaling
    s = ax.figure.dpi / 72  # pixels per point
    pix = [ax.transData.transform((x, y)) for _, x, y, _, _ in cands]
    taken = [(px - 4 * s, py - 4 * s, px + 4 * s, py + 4 * s) for px, py in pix]
    for k in sorted(range(len(cands)), key=lambda k: cands[k][0]):
        _, x, y, text, colour = cands[k]
        w = len(text) * 4.3 + 2  # points, with a margin
        for dx, dy in ((4, 2), (-4 - w, 2), (4, -9)):
            box = (pix[k][0] + dx * s, pix[k][1] + dy * s,
                   pix[k][0] + (dx + w) * s, pix[k][1] + (dy + 7) * s)
            if free(box, taken, ax.bbox):
                taken.append(box)
                ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points",
                            fontsize=6.5, color=colour, alpha=0.85)
                break


def free(box, taken, bbox):
    inside = bbox.x0 <= box[0] and box[2] <= bbox.x1 and bbox.y0 <= box[1] and box[3] <= bbox.y1
    return inside and not any(b[0] < box[2] and box[0] < b[2] and b[1] < box[3] and box[1] < b[3]
                              for b in taken)


def failed_marks(ax, rows):
    """An x at the top edge of the panel at the time of each failed or crashed run;
    returns how many were drawn."""
    bad = [r for r in rows if r["status"] != "ok" and positive(num(r, TIME.col))]
    for r in bad:
        ax.plot([num(r, TIME.col)], [0.965], transform=ax.get_xaxis_transform(), ls="none",
                marker="x", ms=7, mew=2, color=style(r["method"])["color"], clip_on=False)
    return len(bad)


def failure_note(bad, width_in):
    """Lines listing failed and crashed runs, at most 4 lines."""
    if not bad:
        return []
    items = []
    for r in bad:
        why = r.get("how") or r.get("message") or ""
        why = f": {why[:40]}" if why else ""
        items.append(f"{r['method']} {run_label(r)}{why}")
    text = "failed/crashed: " + "; ".join(items)
    lines = textwrap.wrap(text, width=int(width_in * 72 / 4.3))
    return lines if len(lines) <= 4 else lines[:3] + [lines[3][:-20] + " ... (see the CSV)"]


def ref_label(ref):
    other = ref.get("confirm_method") or ""
    return f"reference agreement\n({ref['method']} vs {other})" if other else \
        f"reference agreement\n({ref['method']})"


# ---------------------------------------------------------------- stability map

def chart_stability(d, title):
    rows = read_csv(os.path.join(d, "stability.csv"), ST_REQ)
    rows = [r for r in rows if r["method"] and math.isfinite(num(r, "stiffness_scale"))
            and positive(num(r, "dt"))]
    path = os.path.join(d, "stability.png")
    if not rows:
        return empty_chart(path, "Stability map", title)
    limits = read_limits(d)
    scales = sorted({num(r, "stiffness_scale") for r in rows})
    dts = sorted({num(r, "dt") for r in rows})
    methods = method_order(r["method"] for r in rows)
    panel_w, figh = 0.42 * len(dts) + 0.35, 2.1 + 0.36 * len(methods)
    fig, axes = plt.subplots(1, len(scales), squeeze=False, sharey=True,
                             figsize=(max(8.0, panel_w * len(scales) + 2.0), figh))
    for k, (ax, s) in enumerate(zip(axes[0], scales)):
        stability_panel(ax, rows, s, dts, methods, limits.get(s, {}))
        ax.tick_params(labelleft=(k == 0))
    handles = [Patch(color=c, label="short (< 10 steps)" if name == "short" else name)
               for name, c in STATUS]
    if limits:
        handles.append(Patch(fill=False, ec="black", lw=2, label="largest stable dt"))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), frameon=False,
               bbox_to_anchor=(0.5, 0.2 / fig.get_size_inches()[1]))  # above the footnote
    suptitle(fig, "Stability map", title, d)
    put_footnote(fig, d)
    margins(fig, 1.45, 0.2, 1.4, 0.7, wspace=0.08)
    save(fig, path)


def status_grid(rows, scale, dts, methods):
    """Status codes (index into STATUS), methods x dts; the last row of a cell wins."""
    names = [name for name, _ in STATUS]
    grid = np.full((len(methods), len(dts)), names.index("missing"))
    for r in rows:
        if num(r, "stiffness_scale") != scale:
            continue
        if r["status"] not in names:
            warn(f"stability.csv: unknown status '{r['status']}' (drawn as missing)")
            continue
        grid[methods.index(r["method"]), dts.index(num(r, "dt"))] = names.index(r["status"])
    return grid


def stability_panel(ax, rows, scale, dts, methods, limits):
    grid = status_grid(rows, scale, dts, methods)
    cmap = ListedColormap([c for _, c in STATUS])
    ax.imshow(grid, cmap=cmap, vmin=-0.5, vmax=len(STATUS) - 0.5, aspect="auto",
              interpolation="nearest")
    ax.grid(False)
    ax.set_xticks(range(len(dts)), [f"{v * 1e3:g}" for v in dts], rotation=45, ha="right",
                  rotation_mode="anchor")
    ax.set_yticks(range(len(methods)), methods)
    ax.set_xticks(np.arange(len(dts) + 1) - 0.5, minor=True)
    ax.set_yticks(np.arange(len(methods) + 1) - 0.5, minor=True)
    ax.grid(which="minor", color="white", lw=1.5, alpha=1)
    ax.tick_params(which="minor", length=0)
    ax.set_xlabel("dt (ms)")
    ax.set_title(f"stiffness \u00d7 {compact(scale)}")
    for i, m in enumerate(methods):
        j = nearest_index(dts, limits.get(m, math.nan))
        if j is not None:
            ax.add_patch(Rectangle((j - 0.42, i - 0.4), 0.84, 0.8, fill=False, ec="black",
                                   lw=2.2, zorder=3))


def nearest_index(values, v):
    """Index of v in the sorted values (relative tolerance 1e-6), or None."""
    if not positive(v):
        return None
    for j, x in enumerate(values):
        if abs(x - v) <= 1e-6 * v:
            return j
    return None


def read_limits(d):
    """{stiffness_scale: {method: largest_stable_dt}} from stability_limits.csv, if any."""
    path = os.path.join(d, "stability_limits.csv")
    if not os.path.exists(path):
        return {}
    limits = {}
    for r in read_csv(path, LIM_REQ):
        limits.setdefault(num(r, "stiffness_scale"), {})[r["method"]] = num(r, "largest_stable_dt")
    return limits


def empty_chart(path, name, title):
    fig, ax = plt.subplots(figsize=(8, 5))
    ax.set_axis_off()
    no_data(ax)
    suptitle(fig, name, title)
    save(fig, path)


# ---------------------------------------------------------------- scaling

def chart_scaling(d, title):
    rows = read_csv(os.path.join(d, "scaling.csv"), SC_REQ)
    ok = [r for r in rows if r["status"] == "ok" and r["method"] and positive(num(r, "dofs"))]
    methods = method_order(r["method"] for r in ok)
    fits = {m: scaling_fit([r for r in ok if r["method"] == m]) for m in methods}
    write_fit_csv(os.path.join(d, "scaling_fit.csv"), methods, fits)
    n = len(methods)
    fig, axes = plt.subplots(1, 3, figsize=(12.5, 5.2 + 0.19 * n))
    scaling_panel(axes[0], ok, "step_s", "(a) time per step", "time per step (s)", fits, 0)
    scaling_panel(axes[1], ok, "factor_share", "(b) factorisation share of the step",
                  "factor_s / step_s", None, None)
    scaling_panel(axes[2], ok, "max_rss_mb", "(c) peak memory (RSS)", "max RSS (MB)", fits, 1)
    slope_one(axes[0], ok)
    axes[1].set_ylim(0, 1)
    for ax in (axes[0], axes[2]):
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), frameon=False)
    suptitle(fig, "Scaling", title, d)
    put_footnote(fig, d, "wall time per step")
    margins(fig, 0.75, 0.25, 1.0 + 0.19 * n, 0.7, wspace=0.32)
    save(fig, os.path.join(d, "scaling.png"))


def share(r):
    """factor_share, or factor_s / step_s when the share is empty."""
    v = num(r, "factor_share")
    return v if math.isfinite(v) else num(r, "factor_s") / num(r, "step_s")


def column(rows, col):
    """(dofs, values) of the rows with a positive dofs and a finite value, sorted by dofs."""
    pts = sorted((num(r, "dofs"), share(r) if col == "factor_share" else num(r, col))
                 for r in rows)
    pts = [(x, y) for x, y in pts if math.isfinite(y) and (col == "factor_share" or y > 0)]
    return np.array([p[0] for p in pts]), np.array([p[1] for p in pts])


def fit_exponent(x, y):
    """Least-squares slope of log y against log x; NaN with fewer than 2 distinct x."""
    if len(set(x.tolist())) < 2:
        return math.nan
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def scaling_fit(rows):
    """(time exponent, memory exponent, points of the time fit) of one method."""
    xt, yt = column(rows, "step_s")
    xm, ym = column(rows, "max_rss_mb")
    return fit_exponent(xt, yt), fit_exponent(xm, ym), len(xt)


def write_fit_csv(path, methods, fits):
    def cell(v):
        return f"{v:.6f}" if math.isfinite(v) else ""
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["method", "time_exponent", "memory_exponent", "points"])
        for m in methods:
            pt, pm, n = fits[m]
            w.writerow([m, cell(pt), cell(pm), n])
    print(path, flush=True)


def scaling_panel(ax, rows, col, title, ylabel, fits, which):
    ax.set_xscale("log")
    if col != "factor_share":
        ax.set_yscale("log")
    ax.set_title(title)
    ax.set_xlabel("degrees of freedom")
    ax.set_ylabel(ylabel)
    drawn = 0
    for m in method_order(r["method"] for r in rows):
        x, y = column([r for r in rows if r["method"] == m], col)
        if len(x):
            p = fits[m][which] if fits else math.nan
            label = f"{m}  p = {p:.2f}" if math.isfinite(p) else m
            ax.plot(x, y, lw=1.5, ms=6, label=label, **style(m))
            drawn += 1
    if not drawn:
        if col != "factor_share":
            ax.set_ylim(1e-3, 1)
        no_data(ax)
    widen_log(ax)
    readable_log(ax)


def slope_one(ax, rows):
    """A faint dashed line of slope 1 through the geometric mean of all time points."""
    x, y = column(rows, "step_s")
    if len(set(x.tolist())) < 2:
        return
    lx, ly = np.log(x), np.log(y)
    xs = np.array([x.min(), x.max()])
    ax.plot(xs, np.exp(ly.mean() + np.log(xs) - lx.mean()), color="0.5", ls="--", lw=1,
            alpha=0.6, label="slope 1", zorder=1)


# ---------------------------------------------------------------- tension series

def chart_tension(d, title, series):
    wp = os.path.join(d, "work_precision.csv")
    rows = read_csv(wp, WP_REQ)
    if rows and "run_dir" not in rows[0]:
        raise BenchError(f"{wp}: missing required column 'run_dir' (for tension_series.png)")
    ref = read_reference(d)
    runs = [(f"{r['method']} {run_label(r)}" + ("" if r["status"] == "ok" else f" ({r['status']})"),
             r["method"], load_run(d, r["run_dir"])) for r in choose_runs(rows, series)]
    runs = [run for run in runs if run[2] is not None]
    ref_data = load_run(d, ref["run_dir"]) if ref and ref.get("run_dir") else None
    path = os.path.join(d, "tension_series.png")
    if ref_data is None and not runs:
        return empty_chart(path, "Tension series", title)
    tendon = pick_tendon(ref_data, runs)
    ncols = 3 if tendon is not None else 2
    fig, axes = plt.subplots(1, ncols, figsize=(3.9 * ncols + 2.8, 5), squeeze=False)
    tension_panels(axes[0], ref_data, runs, tendon)
    handles = [Line2D([], [], color=style(m)["color"], lw=1.2, label=label) for label, m, _ in runs]
    if ref_data is not None:
        handles.insert(0, Line2D([], [], color="black", lw=2.8, label=ref_run_label(ref)))
    fig.legend(handles=handles, loc="upper left",
               bbox_to_anchor=(1 - 2.65 / fig.get_size_inches()[0], 0.88), frameon=False)
    suptitle(fig, "Tension series", title, d)
    put_footnote(fig, d)
    margins(fig, 0.75, 2.8, 0.8, 0.75, wspace=0.3)
    save(fig, path)


def ref_run_label(ref):
    """The reference's method and rtol (adaptive) or dt (fixed-step, older folders: neither)."""
    rtol, dt = num(ref, "rtol"), num(ref, "dt")
    setting = f" rtol={compact(rtol)}" if math.isfinite(rtol) else \
        f" dt={ms(dt)}" if math.isfinite(dt) else ""
    return f"reference ({ref['method']}{setting})"


def choose_runs(rows, series):
    """One row per method: the --series pick, or the ok run with the largest value."""
    chosen = []
    for m in method_order(r["method"] for r in rows):
        mine = [r for r in rows if r["method"] == m and r.get("run_dir")]
        if m in series:
            pick = [r for r in mine if nearest_index([num(r, "value")], series[m]) == 0]
            if not pick:
                have = ", ".join(compact(num(r, "value")) for r in mine) or "none"
                raise BenchError(f"--series {m}={compact(series[m])}: no such run in "
                                 f"work_precision.csv (values with a run_dir: {have})")
            chosen.append(pick[-1])
            continue
        ok = [r for r in mine if r["status"] == "ok" and math.isfinite(num(r, "value"))]
        if ok:
            chosen.append(max(ok, key=lambda r: num(r, "value")))
    for m in series:
        if m not in {r["method"] for r in rows}:
            raise BenchError(f"--series {m}=...: no method '{m}' in work_precision.csv")
    return chosen


def load_run(d, run_dir):
    """{'time', 'txy_max', 'txy_mean': arrays, 'tendons': {name: (time, tension)}} or None."""
    path = os.path.join(d, run_dir, "tension.csv")
    if not os.path.exists(path):
        warn(f"{path} not found (run left out of the tension series)")
        return None
    rows = read_csv(path, TENSION_REQ)
    data = {k: np.array([num(r, k) for r in rows]) for k in TENSION_REQ}
    data["tendons"] = load_tendons(os.path.join(d, run_dir, "tendons.csv"))
    return data


def load_tendons(path):
    if not os.path.exists(path):
        return {}
    out = {}
    for r in read_csv(path, TENDON_REQ):
        out.setdefault(r["tendon"], ([], []))
        out[r["tendon"]][0].append(num(r, "time"))
        out[r["tendon"]][1].append(num(r, "tension"))
    return {k: (np.array(t), np.array(f)) for k, (t, f) in out.items()}


def pick_tendon(ref_data, runs):
    """(name, where) of the tendon with the largest tension in the reference (else the runs)."""
    for source, where in ([ref_data], "reference"), ([r[2] for r in runs], "runs"):
        best = None
        for data in source:
            for name, (_, f) in (data or {}).get("tendons", {}).items():
                peak = np.nanmax(f) if len(f) and np.isfinite(f).any() else -math.inf
                if best is None or peak > best[1]:
                    best = (name, peak)
        if best is not None:
            return best[0], where
    return None


def tension_panels(axes, ref_data, runs, tendon):
    specs = [("txy_max", "(a) tension XY max", "N/m"), ("txy_mean", "(b) tension XY mean", "N/m")]
    for ax, (key, title, unit) in zip(axes, specs):
        series_panel(ax, ref_data, runs, lambda data, k=key: (data["time"], data[k]))
        ax.set_title(title)
        ax.set_ylabel(f"tension ({unit})")
    if tendon is not None:
        name, where = tendon
        series_panel(axes[2], ref_data, runs,
                     lambda data: data["tendons"].get(name, (np.array([]), np.array([]))))
        axes[2].set_title(f"(c) tendon '{name}' tension\n(largest in the {where})")
        axes[2].set_ylabel("tension (N)")


def series_panel(ax, ref_data, runs, get):
    ax.set_xlabel("time (s)")
    peak = -math.inf
    if ref_data is not None:
        t, y = get(ref_data)
        ax.plot(t, y, color="black", lw=2.8, alpha=0.85, zorder=1)
        peak = np.nanmax(y) if np.isfinite(y).any() else -math.inf
        low = min(0.0, np.nanmin(y)) if np.isfinite(y).any() else 0.0
    top = -math.inf
    for _, m, data in runs:
        t, y = get(data)
        ax.plot(t, y, color=style(m)["color"], lw=1.1, zorder=2)
        top = max(top, np.nanmax(y) if np.isfinite(y).any() else -math.inf)
    if peak > 0 and top > CLIP * peak:  # a run that blew up would flatten everything else
        ax.set_ylim(low - 0.05 * (CLIP * peak - low), CLIP * peak * 1.05)
        ax.text(0.98, 0.97, f"clipped at {CLIP:g}\u00d7 the reference max\n(runs reach {top:.3g})",
                transform=ax.transAxes, ha="right", va="top", fontsize=7, color="0.3",
                bbox={"fc": "white", "ec": "none", "alpha": 0.8})


# ---------------------------------------------------------------- main

def parse_series(text, ap):
    series = {}
    for item in filter(None, (text or "").split(",")):
        method, sep, value = item.partition("=")
        try:
            series[method.strip()] = float(value)
        except ValueError:
            sep = ""
        if not sep or not method.strip():
            ap.error(f"--series: expected METHOD=VALUE, got '{item}'")
    return series


def main():
    ap = argparse.ArgumentParser(description="Charts of a sinew bench folder.")
    ap.add_argument("dir", metavar="DIR", help="the bench folder")
    ap.add_argument("--title", default="", help="prefix of every chart's title")
    ap.add_argument("--time", choices=["cpu", "wall"], default=None,
                    help="the work-precision chart's time (default: the folder's, else cpu)")
    ap.add_argument("--series", default="", metavar="METHOD=VALUE[,...]",
                    help="runs for the tension series (default: each method's coarsest ok run)")
    args = ap.parse_args()
    series = parse_series(args.series, ap)
    d = args.dir
    if not os.path.isdir(d):
        return fail([f"{d}: no such directory"])
    have = {n for n in os.listdir(d) if n.endswith(".csv")}
    jobs = [(lambda f=f: f(d, args.title, args.time) if f is chart_work_precision
             else f(d, args.title)) for name, f in CHARTS if name in have]
    if {"work_precision.csv", "reference.csv"} <= have:
        jobs.append(lambda: chart_tension(d, args.title, series))
    if not jobs:
        return fail([f"{d}: none of {', '.join(name for name, _ in CHARTS)}"])
    plt.rcParams.update(RC)
    errors = []
    for job in [lambda: prime_styles(d)] + jobs:
        try:
            job()
        except BenchError as e:
            plt.close("all")
            errors.append(str(e))
    return fail(errors) if errors else 0


def fail(errors):
    """Prints each distinct error once; returns the exit status 2."""
    for e in dict.fromkeys(errors):
        print(f"bench_charts: {e}", file=sys.stderr)
    return 2


CHARTS = [("work_precision.csv", chart_work_precision), ("stability.csv", chart_stability),
          ("scaling.csv", chart_scaling)]


if __name__ == "__main__":
    sys.exit(main())
