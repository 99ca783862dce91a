#!/usr/bin/python3
"""garment_check.py — the fit check of a garment run (docs/garments.md, tools/bench_garment.sh):

    /usr/bin/python3 tools/garment_check.py RUN_DIR --line-z 0.85 [--band 0.02] [--gap 1e-3]
        [--top-z Z]

From the run folder's summary.json: the largest seam gap at the end (m) below --gap and no
self- or obstacle intersection; from its last frame: the mean tension XY (N/m) of the faces
whose centroid lies within --band of the garment's tight line (z = --line-z: a skirt's hip
line, a top's bust line; --hip-z is the same option) and of those within --band of the hem
(the lowest centroid), the tight line's above the hem's; with --top-z, the garment's highest
vertex at least that high (a top still hanging from the shoulders).  Prints one line of numbers;
exit 1 when a check fails."""
import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
from sinew import frames  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run")
    ap.add_argument("--line-z", "--hip-z", type=float, required=True,
                    help="height of the tight line (hips, bust), m")
    ap.add_argument("--band", type=float, default=0.02, help="half width of each band, m")
    ap.add_argument("--gap", type=float, default=1e-3, help="largest seam gap allowed, m")
    ap.add_argument("--top-z", type=float, help="lowest height allowed of the highest vertex, m")
    a = ap.parse_args()
    with open(os.path.join(a.run, "summary.json")) as f:
        s = json.load(f)
    t, parts = list(frames.read_run(a.run))[-1]
    cloth = parts["cloth"]
    tri = cloth.connectivity.reshape(-1, 3)
    z = cloth.points[tri][:, :, 2].mean(axis=1)
    txy = cloth.cell_data["tension_xy"]
    line = txy[np.abs(z - a.line_z) < a.band].mean()
    hem = txy[z < z.min() + a.band].mean()
    ok = (s["status"] == "ok" and s["seam_gap_max"] < a.gap and s["self_intersections"] == 0
          and s["obstacle_intersections"] == 0 and line > hem)
    top = float(cloth.points[:, 2].max())
    ok = ok and (a.top_z is None or top >= a.top_z)
    print("t %.4g s  fit_end %.4g s  seam_gap_max %.3g m  self_intersections %d  "
          "obstacle_intersections %d  tension_xy line %.4g N/m  hem %.4g N/m  top %.4g m  %s"
          % (t, s.get("fit_end_s", 0.0), s["seam_gap_max"], s["self_intersections"],
             s["obstacle_intersections"], line, hem, top, "ok" if ok else "FAILED"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
