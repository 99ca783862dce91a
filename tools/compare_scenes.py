#!/usr/bin/python3
"""Run every shipped scene (scenes/*.yaml) into a folder and compare its logs bit for bit
against a reference folder recorded the same way (by an earlier build).

  tools/compare_scenes.py record REF  [--sinew BUILD/sinew] [--duration T] [--only NAME...]
  tools/compare_scenes.py compare REF OUT [--sinew BUILD/sinew] [--duration T] [--only NAME...]

Each scene runs with `sinew run SCENE --out DIR/NAME --quiet --duration T'` where T' is the
smaller of the scene's own duration and --duration (default 0.3 s; static scenes keep theirs).
Compared: every CSV log (energy.csv, tension.csv, ...) without its wall-clock columns,
summary.json without its timing and memory fields, frames.pvd, frames/* and positions files,
byte for byte.  Exit 0 when all match, 1 when any differs (each difference printed), 2 on a
failed run or bad arguments.

  tools/compare_scenes.py diff REF OUT [--tolerance R]

compares two folders already run, without running anything.  --tolerance R (compare and diff)
is for a change meant to move results by round-off only: each CSV log then passes when every
numeric column is within R of the reference's, relative to the column's largest |value|
(its largest difference is printed), and summary.json, frames and positions are not compared;
a log whose rows differ in number (a run that took other steps) fails."""
import argparse
import csv
import json
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# fields that measure the machine, not the simulation
VOLATILE = re.compile(r"(^time_.*_s$|^time_terms_s$|wall|cpu_time|max_rss|^scene_file$)")


def scene_duration(path):
    with open(path) as f:
        for line in f:
            m = re.match(r"^duration:\s*([0-9.eE+-]+)", line)
            if m:
                return float(m.group(1))
    return None


def run_all(sinew, out, cap, only):
    os.makedirs(out, exist_ok=True)
    names = sorted(n[:-5] for n in os.listdir(os.path.join(ROOT, "scenes")) if n.endswith(".yaml"))
    for name in names:
        if only and name not in only:
            continue
        scene = os.path.join("scenes", name + ".yaml")
        dur = scene_duration(os.path.join(ROOT, scene))
        cmd = [sinew, "run", scene, "--out", os.path.join(out, name), "--quiet"]
        if dur is not None and dur > cap:
            cmd += ["--duration", repr(cap)]
        r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
        print(f"{name}: exit {r.returncode}", flush=True)
        if r.returncode not in (0, 1):
            print(r.stderr, file=sys.stderr)
            sys.exit(2)
        with open(os.path.join(out, name, "exit_code"), "w") as f:
            f.write(f"{r.returncode}\n")
    return names


def stable_csv(path):
    with open(path) as f:
        rows = [line.rstrip("\n").split(",") for line in f]
    if not rows:
        return []
    keep = [i for i, h in enumerate(rows[0]) if not VOLATILE.search(h)]
    return [",".join(r[i] for i in keep if i < len(r)) for r in rows]


def stable_json(path):
    with open(path) as f:
        d = json.load(f)
    return {k: v for k, v in d.items() if not VOLATILE.search(k)}


def files_of(d):
    out = []
    for base, _, fs in os.walk(d):
        for f in fs:
            rel = os.path.relpath(os.path.join(base, f), d)
            if rel.endswith(("restart.bin", "sinew.manifest", ".lock")):
                continue
            out.append(rel)
    return sorted(out)


def csv_difference(pa, pb):
    """The largest difference of two logs' numeric columns, relative to the column's largest
    |value| in the first (wall-clock columns left out), and the column it is in; None when the
    row counts or headers differ."""
    with open(pa) as f:
        ra = list(csv.reader(f))
    with open(pb) as f:
        rb = list(csv.reader(f))
    if len(ra) != len(rb) or not ra or ra[0] != rb[0]:
        return None
    worst = (0.0, "")
    for j, h in enumerate(ra[0]):
        if VOLATILE.search(h):
            continue
        try:
            ca = [float(r[j]) for r in ra[1:]]
            cb = [float(r[j]) for r in rb[1:]]
        except (ValueError, IndexError):
            continue
        scale = max([abs(x) for x in ca] + [1e-300])
        d = max([abs(x - y) for x, y in zip(ca, cb)] + [0.0]) / scale
        if d > worst[0]:
            worst = (d, h)
    return worst


def compare(ref, out, tol=0.0):
    bad = 0
    for name in sorted(os.listdir(ref)):
        a, b = os.path.join(ref, name), os.path.join(out, name)
        if not os.path.isdir(a):
            continue
        if not os.path.isdir(b):
            print(f"{name}: not run")
            bad += 1
            continue
        fa, fb = files_of(a), files_of(b)
        if fa != fb:
            print(f"{name}: files differ: {sorted(set(fa) ^ set(fb))}")
            bad += 1
        for rel in sorted(set(fa) & set(fb)):
            pa, pb = os.path.join(a, rel), os.path.join(b, rel)
            if rel.endswith(".csv"):
                same = stable_csv(pa) == stable_csv(pb)
                if not same and tol > 0.0:
                    d = csv_difference(pa, pb)
                    why = ("rows or columns differ" if d is None else
                           f"largest relative difference {d[0]:.2e} ({d[1]})")
                    same = d is not None and d[0] <= tol
                    print(f"{name}: {rel} {why}" + ("" if same else f", above {tol:g}"))
            elif tol > 0.0:
                same = True  # summary, frames and positions: round-off moves them all
            elif rel.endswith(".json"):
                same = stable_json(pa) == stable_json(pb)
            else:
                with open(pa, "rb") as x, open(pb, "rb") as y:
                    same = x.read() == y.read()
            if not same:
                if not (rel.endswith(".csv") and tol > 0.0):
                    print(f"{name}: {rel} differs")
                bad += 1
    what = "identical" if tol == 0.0 else f"within {tol:g} (logs) or identical"
    print(f"all {what}" if not bad else f"{bad} differences")
    return 1 if bad else 0


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("mode", choices=["record", "compare", "diff"])
    p.add_argument("ref")
    p.add_argument("out", nargs="?")
    p.add_argument("--sinew", default=os.path.join(ROOT, "build", "sinew"))
    p.add_argument("--duration", type=float, default=0.3)
    p.add_argument("--only", nargs="*")
    p.add_argument("--tolerance", type=float, default=0.0,
                   help="compare: a CSV log passes when each numeric column is within this of "
                        "the reference's, relative to the column's largest |value|, and the "
                        "frames and positions are not compared (round-off changes)")
    a = p.parse_args()
    sinew = os.path.abspath(a.sinew)
    if a.mode == "record":
        run_all(sinew, os.path.abspath(a.ref), a.duration, a.only)
        return 0
    if not a.out:
        p.error("compare and diff need REF and OUT")
    if a.mode == "diff":
        return compare(os.path.abspath(a.ref), os.path.abspath(a.out), a.tolerance)
    run_all(sinew, os.path.abspath(a.out), a.duration, a.only)
    return compare(os.path.abspath(a.ref), os.path.abspath(a.out), a.tolerance)


if __name__ == "__main__":
    sys.exit(main())
