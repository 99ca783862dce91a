#!/usr/bin/python3
"""tools/bench_python.py — what a read of each property of sinew.Simulation costs (µs), and a
controller's loop (set one rest length, read the positions and one tension, step) against the
step alone, on scenes/cloth_drawstring.yaml at an 8 x 8 grid.

usage: PYTHONPATH=python SINEW_LIB=build/libsinew.so /usr/bin/python3 tools/bench_python.py
           [--old DIR] [--repeat N]

--old DIR: another version of the package (a folder holding sinew/__init__.py, e.g. from
`git show REV:python/sinew/__init__.py`), measured interleaved with this one on the same
libsinew: the table then has both and their ratio.  Each number is the median over N repeats
(default 5) of the mean over many calls (timeit)."""
import argparse
import importlib.util
import os
import statistics
import sys
import timeit

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "scenes", "cloth_drawstring.yaml")
GRID = (8, 8)  # a small scene (64 vertices): the step is short beside the reads

READS = [
    ("time", "sim.time"), ("dt", "sim.dt"), ("positions", "sim.positions"),
    ("velocities", "sim.velocities"), ("tension_xy", "sim.tension_xy"),
    ("tendon_length", "sim.tendon_length"), ("tendon_tension", "sim.tendon_tension"),
    ("tendon_rest", "sim.tendon_rest"), ("Tendon.length", "tendon.length"),
    ("Tendon.tension", "tendon.tension"), ("Tendon.rest_length", "tendon.rest_length"),
    ("energy", "sim.energy"), ("counters", "sim.counters"),
    # the first read after a change (a step) reads libsinew again: forgotten by hand here
    ("counters after a change", "(sim.__dict__.update(_counters_cache=None), sim.counters)"),
]
LOOP = "tendon.rest_length = 0.99; sim.positions[5, 0]; tendon.tension; sim.step()"
READ_LOOP = "sim.positions[5, 0]; tendon.tension; sim.step()"
STEP = "sim.step()"


def load_package(folder, name):
    """The package sinew in folder, imported under the module name `name`."""
    path = os.path.join(folder, "sinew", "__init__.py")
    spec = importlib.util.spec_from_file_location(
        name, path, submodule_search_locations=[os.path.dirname(path)])
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


def per_call(stmt, env, number):
    return timeit.timeit(stmt, globals=env, number=number) / number * 1e6  # µs


def measure(pkg):
    """{what: µs} for one package, one repeat."""
    sim = pkg.load(SCENE, grid=GRID)
    env = {"sim": sim, "tendon": sim.tendons["drawstring"]}
    out = {}
    for what, stmt in READS:
        try:
            eval(stmt, env)
        except AttributeError:  # an older package without it
            continue
        out[what] = per_call(stmt, env, 20000)
    out["loop (set rest, 2 reads, step)"] = per_call(LOOP, env, 200)
    out["loop (2 reads, step)"] = per_call(READ_LOOP, env, 200)
    out["step alone"] = per_call(STEP, env, 200)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--old", help="a folder with another sinew/__init__.py to compare with")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    pkgs = {"this": load_package(os.path.join(ROOT, "python"), "sinew_this")}
    if args.old:
        pkgs["old"] = load_package(args.old, "sinew_old")
    runs = {k: [] for k in pkgs}
    for _ in range(args.repeat):  # interleaved: old, this, old, this ...
        for k in sorted(pkgs):
            runs[k].append(measure(pkgs[k]))
    med = {k: {w: statistics.median(r[w] for r in runs[k] if w in r)
               for w in runs[k][0]} for k in runs}
    names = list(med["this"])
    if "old" in med:
        print("| read | old (µs) | this (µs) | old / this |\n| --- | ---: | ---: | ---: |")
        for w in names:
            o = med["old"].get(w)
            print("| `%s` | %s | %.2f | %s |" % (w, "%.2f" % o if o else "–", med["this"][w],
                                                 "%.1f" % (o / med["this"][w]) if o else "–"))
    else:
        print("| read | µs |\n| --- | ---: |")
        for w in names:
            print("| `%s` | %.2f |" % (w, med["this"][w]))


if __name__ == "__main__":
    main()
