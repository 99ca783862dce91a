#!/usr/bin/python3
"""newton_certificate.py — tabulate the cheaper convergence certificates measured by a probe
build of sinew (solvers/newton.c built with -DSW_NEWTON_PROBE; tools/newton_certificate.sh).

    tools/newton_certificate.py LOG [LOG ...]      (one stderr log per scene)

Each `newton_probe` line is one Newton iteration after the first: Newton's own step (exact),
the chord step from the factorisation at hand (chord), their difference (diff), both sizes'
error estimates (left_*, Newton's geometric-series test) and the residual bound (resid), all
in m in Newton's norm, with the tolerance tol.  For each log, prints a Markdown row: how many
iterations Newton's test accepts, how many the chord test accepts with a safety factor s
(left_chord * s <= tol) and how many of those Newton's test rejects (false certificates), the
largest error accepting the chord step would leave (|chord - exact| / tol), and how many the
residual bound certifies."""
import os
import sys


def read(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("newton_probe "):
                kv = dict(w.split("=", 1) for w in line.split()[1:])
                rows.append({k: float(v) for k, v in kv.items()})
    return rows


def quantile(a, p):
    a = sorted(a)
    return a[min(len(a) - 1, int(p * len(a)))] if a else float("nan")


def row(name, rows, factors):
    accepted = [r for r in rows if r["left_exact"] <= r["tol"]]
    cells = [name, str(len(rows)), str(len(accepted))]
    ratio = [r["exact"] / r["chord"] for r in accepted if r["chord"] > 0]
    cells.append("%.2f / %.2f" % (quantile(ratio, 0.5), max(ratio) if ratio else float("nan")))
    for s in factors:
        cert = [r for r in rows if r["left_chord"] * s <= r["tol"]]
        false = sum(1 for r in cert if r["left_exact"] > r["tol"])
        worst = max((r["diff"] / r["tol"] for r in cert), default=0.0)
        cells.append("%d (%d false), %.1f" % (len(cert), false, worst))
    resid = [r["resid"] / r["tol"] for r in accepted]
    certified = sum(1 for r in rows if r["resid"] <= r["tol"])
    cells.append("%.0f / %d" % (quantile(resid, 0.5), certified))
    return "| " + " | ".join(cells) + " |"


def main(argv):
    if len(argv) < 2:
        sys.stderr.write(__doc__)
        return 2
    factors = (1, 2, 8)
    head = ["scene", "iterations after the 1st", "Newton accepts",
            "exact / chord step (median / max)"]
    head += ["chord, s = %d: certifies (false), worst error / tol" % s for s in factors]
    head += ["residual bound / tol (median) / certifies"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for path in argv[1:]:
        rows = read(path)
        if not rows:
            sys.stderr.write("%s: no newton_probe lines (not a probe build's log?)\n" % path)
            return 1
        print(row(os.path.basename(path).rsplit(".", 1)[0], rows, factors))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
