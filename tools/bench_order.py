#!/usr/bin/env python3
"""bench_order.py CSV — the Markdown tables of tools/bench_order.sh's runs.

Per case and configuration (ordering, factorisation kind, OpenBLAS threads) the median
per-step CPU time and wall time over the repetitions (--min: the smallest, the least disturbed
run).  Table 1: the
factor's nonzeros per ordering (relative to AMD's) and the per-step CPU time of every
configuration relative to the case's best one-thread configuration (1.00); the default's
(auto) in its own column with what it chose.  Table 2: what a second BLAS thread does to a
supernodal factorisation's per-step wall and CPU time (ratio 2 threads / 1 thread).
"""
import csv
import statistics
import sys
from collections import defaultdict


def load(path, stat):
    rows = defaultdict(list)
    info = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            if r["status"] != "ok" or not r["cpu_step_s"]:
                continue
            key = (r["case"], r["ordering"], r["factorization"], int(r["threads"]))
            rows[key].append((float(r["cpu_step_s"]), float(r["wall_step_s"])))
            info[key] = r
    best = {k: (stat([c for c, _ in v]), stat([w for _, w in v]), len(v)) for k, v in rows.items()}
    return best, info


def case_order(cases):
    cloth = sorted((c for c in cases if c.isdigit()), key=int)
    return cloth + sorted(c for c in cases if not c.isdigit())


def main():
    args = [a for a in sys.argv[1:] if a != "--min"]
    use_min = len(args) < len(sys.argv) - 1
    best, info = load(args[0], min if use_min else statistics.median)
    cases = case_order({k[0] for k in best})
    orders = [o for o in ("amd", "metis", "nesdis") if any(k[1] == o for k in best)]
    kinds = ("simplicial", "supernodal")
    print("| case | DOFs | lnz AMD | lnz METIS / AMD | lnz NESDIS / AMD | best ms/step "
          "| auto chose | auto ms/step | " + " | ".join(f"{o} {k[:5]}." for o in orders for k in kinds)
          + " |")
    print("|---|--:|--:|--:|--:|--:|---|--:|" + "--:|" * (len(orders) * len(kinds)))
    for c in case_order(cases):
        one = {k: v for k, v in best.items() if k[0] == c and k[3] == 1 and k[1] != "auto"}
        if not one:
            continue
        ref = min(v[0] for v in one.values())
        nnz = {}
        for k in one:
            nnz[k[1]] = int(info[k]["factor_nnz"])
        a = nnz.get("amd")
        dofs = next(iter(info[k]["dofs"] for k in one))
        cells = [c if not c.isdigit() else f"cloth {c}", dofs, f"{a:,}" if a else ""]
        for o in ("metis", "nesdis"):
            cells.append(f"{nnz[o] / a:.2f}" if a and o in nnz else "")
        cells.append(f"{1e3 * ref:.3g}")
        au = (c, "auto", "auto", 1)
        if au in best:
            r = info[au]
            cells += [f"{r['ordering_used']} {r['factorization_used']}",
                      f"{1e3 * best[au][0]:.3g} ({best[au][0] / ref:.2f})"]
        else:
            cells += ["", ""]
        for o in orders:
            for k in kinds:
                v = best.get((c, o, k, 1))
                cells.append("" if not v else
                             (f"**{v[0] / ref:.2f}**" if v[0] == ref else f"{v[0] / ref:.2f}"))
        print("| " + " | ".join(str(x) for x in cells) + " |")
    print()
    print("| case | " + " | ".join(f"{o} wall 2/1 | {o} CPU 2/1" for o in orders) + " |")
    print("|---|" + "--:|--:|" * len(orders))
    for c in cases:
        cells = [c if not c.isdigit() else f"cloth {c}"]
        for o in orders:
            v1, v2 = best.get((c, o, "supernodal", 1)), best.get((c, o, "supernodal", 2))
            if v1 and v2:
                cells += [f"{v2[1] / v1[1]:.2f}", f"{v2[0] / v1[0]:.2f}"]
            else:
                cells += ["", ""]
        print("| " + " | ".join(cells) + " |")
    reps = sorted({v[2] for v in best.values()})
    print(f"\n({'best' if use_min else 'median'} of {'/'.join(map(str, reps))} repetitions; "
          "bold: the case's fastest one-thread configuration, per-step CPU time relative to it)")


if __name__ == "__main__":
    main()
