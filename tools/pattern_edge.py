#!/usr/bin/python3
"""pattern_edge.py — the measurement behind `sinew pattern import`'s default edge length.

    PYTHONPATH=python SINEW_LIB=build/libsinew.so /usr/bin/python3 tools/pattern_edge.py \
        [--edges 0.05,0.04,0.03,0.02,0.015,0.01,0.0075] [--duration 3]

The skirt front of tests/data/patterns/make_patterns.py (a 20 x 24 in panel with a curved
waist: a light woven, 150 g/m², bending 1e-5 N m, whose bending length (B / (rho g))^(1/3) is
1.9 cm) is imported at each edge length, hung by its two waist corners under gravity with mass
damping 4 1/s (backward Euler, dt 0.01 s), and read at the end: where the hem notch and side notch
are (vertices of every mesh, so every mesh can be compared point by point with the finest), the
height of the centre of mass, the area-weighted mean and the 95th percentile of tension XY, and
the cost (Newton iterations, wall time).  Prints a Markdown table for docs/patterns.md."""
import argparse
import importlib.util
import os
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "python"))
import sinew  # noqa: E402
from sinew import pattern  # noqa: E402
from sinew.pattern.write import obj_text  # noqa: E402

SCENE = """name: edge {edge}
dimension: 3
mesh: {{obj: front.obj}}
material:
  density: 0.15
  membrane: {{model: bw98, k_u: 2000, k_v: 1500, k_shear: 50}}
  bending: {{model: quadratic, stiffness: 1e-5}}
gravity: [0, 0, -9.81]
pins: [{{select: {{vertices: [{pins}]}}}}]
damping: {{mass: 4}}
integrator: {{method: backward-euler, dt: 0.01}}
duration: {duration}
"""


def weighted_percentile(x, w, q):
    order = np.argsort(x)
    c = np.cumsum(w[order])
    return float(x[order][np.searchsorted(c, q * c[-1])])


def run(front, edge, folder, duration):
    m = pattern.mesh_piece(front, "front", edge, [])
    pos = np.column_stack([m.xy, np.zeros(len(m.xy))])
    with open(os.path.join(folder, "front.obj"), "w") as f:
        f.write(obj_text([m], [pos], ["front at edge %g" % edge]))
    top = max(m.xy[c, 1] for c in m.corners)
    waist = [c for c in m.corners if abs(m.xy[c, 1] - top) < 1e-9]
    scene = os.path.join(folder, "front.yaml")
    with open(scene, "w") as f:
        f.write(SCENE.format(edge=edge, pins=", ".join(map(str, waist)), duration=duration))
    sim = sinew.load(scene)
    t0 = time.perf_counter()
    sim.run(duration)
    wall = time.perf_counter() - t0
    x = np.array(sim.positions).reshape(-1, 3)
    e1, e2 = m.uv[m.tris[:, 1]] - m.uv[m.tris[:, 0]], m.uv[m.tris[:, 2]] - m.uv[m.tris[:, 0]]
    area = np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]) / 2
    mass = np.array(sim.masses)
    txy = np.array(sim.tension_xy)
    hem = min(m.notches, key=lambda i: m.xy[i, 1])
    side = max(m.notches, key=lambda i: m.xy[i, 0])
    return {"edge": edge, "nv": len(m.xy), "nf": len(m.tris), "hem": x[hem], "side": x[side],
            "zc": float((mass * x[:, 2]).sum() / mass.sum()),
            "tmean": float((txy * area).sum() / area.sum()),
            "t95": weighted_percentile(txy, area, 0.95),
            "newton": sim.counters["nnewton"], "wall": wall}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edges", default="0.05,0.04,0.03,0.02,0.015,0.01,0.0075")
    ap.add_argument("--duration", type=float, default=3.0)
    a = ap.parse_args()
    spec = importlib.util.spec_from_file_location(
        "make_patterns", os.path.join(ROOT, "tests", "data", "patterns", "make_patterns.py"))
    mp = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mp)
    with tempfile.TemporaryDirectory() as tmp:
        mp.no_units(os.path.join(tmp, "front.dxf"))
        front = pattern.read(os.path.join(tmp, "front.dxf")).pieces[0]
        rows = []
        for edge in sorted((float(e) for e in a.edges.split(",")), reverse=True):
            rows.append(run(front, edge, tmp, a.duration))
            r = rows[-1]
            print("edge %g: %d vertices, hem %s, side %s, z %.5g, tension %.5g %.5g, %.1f s" %
                  (edge, r["nv"], r["hem"], r["side"], r["zc"], r["tmean"], r["t95"], r["wall"]),
                  file=sys.stderr)
    ref = rows[-1]
    print("| edge (m) | vertices | triangles | hem notch moved (mm) | side notch moved (mm) | "
          "centre of mass z (mm) | mean tension XY (N/m) | 95th pct (N/m) | Newton its | "
          "wall (s) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        d_hem = np.linalg.norm(r["hem"] - ref["hem"]) * 1e3
        d_side = np.linalg.norm(r["side"] - ref["side"]) * 1e3
        ref_mark = " (reference)" if r is ref else ""
        print("| %g%s | %d | %d | %.1f | %.1f | %.1f | %.4g | %.4g | %d | %.1f |" %
              (r["edge"], ref_mark, r["nv"], r["nf"], d_hem, d_side, r["zc"] * 1e3,
               r["tmean"], r["t95"], r["newton"], r["wall"]))


if __name__ == "__main__":
    main()
