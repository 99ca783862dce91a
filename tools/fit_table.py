#!/usr/bin/python3
"""fit_table.py CSV POSDIR -- the table of tools/bench_fit.sh: per garment and fit mode the
median CPU time and Newton iterations over the repetitions, their ratios to the dynamic fit's
(the runs in the order of the CSV: the fit modes, `dt=H` the dynamic fit with steps of H s;
without a dynamic run the ratios are to the first run listed),
and each fit's last state against the reference (the dynamic fit followed by a static
solve) of the same repetition: RMS and largest distance of the positions (m), the relative
change of tension XY's mean and 95th percentile, its seam gap and self-intersections.  With
accurate fits in the CSV (runs `ref:...`, tools/bench_fit.sh's REFS), a second table: every
run's final positions against each accurate fit's (RMS over the vertices, mm; the largest of
the repetitions), the spread of the accurate fits among themselves (the largest pairwise RMS),
and tension XY's mean and 95th percentile against the accurate fits' average."""
import csv
import os
import statistics
import sys

import numpy as np

from positions_diff import records


def last_positions(path):
    """The last record of a positions.bin (nv x dim)."""
    return records(path)[1][-1]


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    pos = sys.argv[2]
    runs = {}
    for r in rows:
        runs.setdefault(r["garment"], {}).setdefault(r["run"], []).append(r)
    print("| garment | fit | CPU s | Newton iterations | status | CPU / dynamic | Newton / "
          "dynamic | positions vs dynamic + static: RMS / max mm | tension XY mean / p95 vs it "
          "| seam gap mm | self-intersections |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for g, by in runs.items():
        med = lambda run, k: statistics.median(float(r[k]) for r in by[run])
        # the ratios' base: the dynamic fit, or without it in RUNS the first run listed
        base = "dynamic" if "dynamic" in by else next(iter(by))
        cd, nd = med(base, "cpu_s"), med(base, "newton_iterations")
        for run in by:
            if run == "static":
                continue
            dist, dmax, dm, dp = [], [], [], []
            for o, ref in zip(by[run], by["static"]):
                a, b = (os.path.join(pos, f"{g}-{x}-{o['rep']}.bin") for x in (run, "static"))
                if os.path.exists(a) and os.path.exists(b):
                    e = np.linalg.norm(last_positions(a) - last_positions(b), axis=1)
                    dist.append(np.sqrt(np.mean(e * e))), dmax.append(e.max())
                dm.append(float(o["txy_mean"]) / float(ref["txy_mean"]) - 1)
                dp.append(float(o["txy_p95"]) / float(ref["txy_p95"]) - 1)
            c, n = med(run, "cpu_s"), med(run, "newton_iterations")
            st = "/".join(sorted({r["status"] for r in by[run]}))
            gap = max(float(r["seam_gap_max_m"]) for r in by[run])
            sx = max(int(r["self_intersections"]) for r in by[run])
            pd = "%.2f / %.2f" % (1e3 * max(dist), 1e3 * max(dmax)) if dist else "-"
            print(f"| {g} | {run} | {c:.2f} | {n:.0f} | {st} | {c / cd:.2f} | {n / nd:.2f} | "
                  f"{pd} | {100 * max(dm, key=abs):+.1f} % / {100 * max(dp, key=abs):+.1f} % | "
                  f"{1e3 * gap:.2f} | {sx} |")
    against_accurate(runs, pos)


def against_accurate(runs, pos):
    """The second table: each run against the accurate fits `ref:...`."""
    refs = sorted({run for by in runs.values() for run in by if run.startswith("ref:")})
    if not refs:
        return
    print()
    print("| garment | fit | " + " | ".join(f"RMS vs {r[4:]} mm" for r in refs)
          + " | tension XY mean / p95 vs the accurate fits' |")
    print("| --- | --- |" + " --: |" * len(refs) + " --: |")
    for g, by in runs.items():
        def rms(a, b):
            worst = 0.0
            for oa, ob in zip(by[a], by[b]):
                fa, fb = (os.path.join(pos, f"{g}-{x}-{o['rep']}.bin")
                          for x, o in ((a, oa), (b, ob)))
                if os.path.exists(fa) and os.path.exists(fb):
                    e = np.linalg.norm(last_positions(fa) - last_positions(fb), axis=1)
                    worst = max(worst, float(np.sqrt(np.mean(e * e))))
            return worst
        mean = lambda run, k: statistics.mean(float(o[k]) for o in by[run])
        ref_m = statistics.mean(mean(r, "txy_mean") for r in refs if r in by)
        ref_p = statistics.mean(mean(r, "txy_p95") for r in refs if r in by)
        for run in by:
            cells = " | ".join("-" if r == run or r not in by else f"{1e3 * rms(run, r):.2f}"
                               for r in refs)
            print(f"| {g} | {run} | {cells} | {100 * (mean(run, 'txy_mean') / ref_m - 1):+.1f} % "
                  f"/ {100 * (mean(run, 'txy_p95') / ref_p - 1):+.1f} % |")
        here = [r for r in refs if r in by]
        spread = max((rms(a, b) for i, a in enumerate(here) for b in here[i + 1:]), default=0)
        print(f"| {g} | spread of the accurate fits | largest pairwise RMS "
              f"{1e3 * spread:.2f} mm |" + " |" * len(refs))


if __name__ == "__main__":
    main()
