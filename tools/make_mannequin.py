#!/usr/bin/python3
"""make_mannequin.py — the OBJ of a dress form (a tailor's mannequin) from a few body
measurements, for mesh obstacles that garments are fitted on:

    /usr/bin/python3 tools/make_mannequin.py [--height 1.70] [--bust 0.88] [--waist 0.70]
        [--hip 0.96] [--around 32] [--rings 30] [--arms none|down|out]
        [-o scenes/meshes/mannequin.obj]

All lengths in metres.  The form is the body from the knees up: the two thighs together as one
piece (as on a dress form with legs to the knee), hips, waist, bust, shoulders, neck and head;
with --arms, two arms as separate closed surfaces (surfaces of revolution about a straight
axis, from a rounded shoulder cap to the fingertips), hung just under the shoulder points at
6 degrees from the vertical (down) or 45 degrees (out), turned further out and moved outward
until they clear the torso by 5 mm: the mesh is then three closed surfaces that do not touch.
The construction is python/sinew/body.py's (sinew.body, which also makes the bodies of
`sinew garment --body`).  Coordinates: z up, z = 0 the floor the body would stand on (the
form's flat base is at knee height, 0.285 of the height), the body's axis is the z axis, its
front faces -y, its left side +x.

Each horizontal section is an ellipse whose perimeter is the stated girth at the bust, waist
and hip heights (0.72, 0.62, 0.50 of the height), interpolated smoothly between levels; the
surface is a stack of rings (a graph r(theta, z), closed and never crossing itself), each ring
scaled so that a tape measure around the mesh reads the girths (sinew.body's docstring has the
construction and its sources).  The output is a function of the arguments only: the same
command, the same file."""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
from sinew.body import BUST, HIP, KNEE, WAIST, BodyError, mannequin  # noqa: E402,F401


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--height", type=float, default=1.70, help="standing height, m")
    ap.add_argument("--bust", type=float, default=0.88, help="bust girth, m")
    ap.add_argument("--waist", type=float, default=0.70, help="waist girth, m")
    ap.add_argument("--hip", type=float, default=0.96, help="hip girth, m")
    ap.add_argument("--around", type=int, default=32, help="vertices around each ring (>= 8)")
    ap.add_argument("--rings", type=int, default=30, help="rings from base to crown (>= 12)")
    ap.add_argument("--arms", choices=("none", "down", "out"), default="none",
                    help="no arms (a dress form), arms hanging down, or out at 45 degrees")
    ap.add_argument("-o", "--output", default="scenes/meshes/mannequin.obj")
    args = ap.parse_args(argv)
    if not (1.0 <= args.height <= 2.5):
        ap.error("--height %g: expected 1.0 to 2.5 m" % args.height)
    for name in ("bust", "waist", "hip"):
        g = getattr(args, name)
        if not (0.25 * args.height <= g <= 1.0 * args.height):
            ap.error("--%s %g: expected between 0.25 and 1.0 times the height" % (name, g))
    if args.around < 8 or args.rings < 12:
        ap.error("--around must be >= 8 and --rings >= 12")
    try:
        verts, tris, zr = mannequin(args.height, args.bust, args.waist, args.hip,
                                    args.around, args.rings, args.arms)
    except BodyError as e:
        sys.exit("make_mannequin: %s" % e)
    cmd = "tools/make_mannequin.py --height %g --bust %g --waist %g --hip %g --around %d " \
          "--rings %d --arms %s" % (args.height, args.bust, args.waist, args.hip, args.around,
                                    args.rings, args.arms)
    with open(args.output, "w") as f:
        f.write("# dress form: /usr/bin/python3 %s\n" % cmd)
        f.write("# %d vertices, %d triangles; z up, z = 0 the floor, front -y, metres; girths at "
                "z = %.4g (hip), %.4g (waist), %.4g (bust)\n"
                % (len(verts), len(tris), HIP * args.height, WAIST * args.height,
                   BUST * args.height))
        if args.arms != "none":  # each arm's first vertex is its cap's top, its last the fingertips
            torso = len(zr) * args.around + 2
            n = (len(verts) - torso) // 2
            for name, k in (("left", torso), ("right", torso + n)):
                top, tip = verts[k], verts[k + n - 1]
                d = (tip - top) / np.linalg.norm(tip - top)
                f.write("# %s arm: axis from the cap's top (%.6f, %.6f, %.6f) towards the "
                        "fingertips (%.6f, %.6f, %.6f), %.4g m long\n"
                        % ((name,) + tuple(top) + tuple(d) + (np.linalg.norm(tip - top),)))
        for v in verts:
            f.write("v %.9g %.9g %.9g\n" % tuple(v))
        for t in tris:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


if __name__ == "__main__":
    main()
