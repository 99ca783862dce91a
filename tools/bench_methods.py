#!/usr/bin/python3
"""tools/bench_methods.py — each integrator at its default settings on one scene: wall time,
steps, Newton iterations, factorisations, and the final-state difference from a reference run.

    /usr/bin/python3 tools/bench_methods.py [--scene S] [--duration T] [--ref METHOD:OPTS]
        [--methods m1,m2,...] [--out DIR]

Every run is its own `sinew run` process (one BLAS thread), so a failure is recorded, not fatal.
The final state is read from each run's last VTU frame. The difference is the RMS over vertices
of |x - x_ref|, relative to the cloth's size (the diagonal of its initial bounding box).
Writes DIR/methods.csv and prints a Markdown table.
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
import time

import numpy as np


def last_points(run_dir):
    frames = sorted(f for f in os.listdir(os.path.join(run_dir, "frames")) if f.endswith(".vtu"))
    text = open(os.path.join(run_dir, "frames", frames[-1])).read()
    block = re.search(r'<Points>\s*<DataArray[^>]*>(.*?)</DataArray>', text, re.S).group(1)
    return np.array(block.split(), dtype=float).reshape(-1, 3)


def run(sinew, scene, method, extra, duration, out):
    cmd = [sinew, "run", scene, "--method", method, "--duration", str(duration), "--out", out,
           "--quiet", "--threads", "1"] + extra
    t0 = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    summary = json.load(open(os.path.join(out, "summary.json")))
    return proc.returncode, wall, summary


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sinew", default="build/sinew")
    ap.add_argument("--scene", default="scenes/hanging_cloth_80.yaml")
    ap.add_argument("--duration", type=float, default=1.0)
    ap.add_argument("--methods", default="backward-euler,baraff-witkin,bdf2,implicit-midpoint,"
                    "newmark,symplectic-euler,cvode,ida")
    ap.add_argument("--ref", default="cvode:--rtol=1e-8:--atol=1e-10",
                    help="reference: method and extra options separated by ':'")
    ap.add_argument("--out", default="out/bench_methods")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    ref_method, *ref_opts = a.ref.split(":")
    ref_opts = [o for opt in ref_opts for o in opt.split("=", 1)]
    rc, wall, s = run(a.sinew, a.scene, ref_method, ref_opts, a.duration, os.path.join(a.out, "ref"))
    if rc:
        sys.exit("reference run failed: %s" % s.get("message"))
    xref = last_points(os.path.join(a.out, "ref"))
    x0 = None
    rows = [dict(method="reference: " + " ".join([ref_method] + ref_opts), status=s["status"],
                 wall_s=round(wall, 2), steps=s["steps"], newton=s["newton_iterations"],
                 factorizations=s["factorizations"], rel_rms_diff=0.0)]
    for method in a.methods.split(","):
        out = os.path.join(a.out, method)
        rc, wall, s = run(a.sinew, a.scene, method, [], a.duration, out)
        diff = ""
        if s["status"] == "ok":
            x = last_points(out)
            if x0 is None:
                frames = sorted(os.listdir(os.path.join(out, "frames")))
                text = open(os.path.join(out, "frames", frames[0])).read()
                blk = re.search(r'<Points>\s*<DataArray[^>]*>(.*?)</DataArray>', text, re.S).group(1)
                x0 = np.array(blk.split(), dtype=float).reshape(-1, 3)
            size = np.linalg.norm(x0.max(axis=0) - x0.min(axis=0))
            diff = float(np.sqrt(np.mean(np.sum((x - xref) ** 2, axis=1))) / size)
        rows.append(dict(method=method, status=s["status"], wall_s=round(wall, 2),
                         steps=s["steps"], newton=s["newton_iterations"],
                         factorizations=s["factorizations"], rel_rms_diff=diff))
        print(method, rows[-1], file=sys.stderr, flush=True)
    with open(os.path.join(a.out, "methods.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("| method | status | wall s | steps | Newton it. | factorisations | RMS diff / size |")
    print("|---|---|--:|--:|--:|--:|--:|")
    for r in rows:
        d = r["rel_rms_diff"]
        print("| %s | %s | %s | %s | %s | %s | %s |" % (r["method"], r["status"], r["wall_s"],
              r["steps"], r["newton"], r["factorizations"], ("%.2e" % d) if d != "" else "—"))


if __name__ == "__main__":
    main()
