#!/usr/bin/python3
"""order_table.py OUT.csv NAME=BENCHDIR ... — one table of every CVODE and IDA run of `sinew bench`
folders swept over BDF orders (`--max-orders`): per scene, method, largest order and rtol, the
counts (steps, Newton iterations, linear setups, factorisations, error-test failures, the steps
taken at each order), the wall time and the errors against the bench's reference. Writes OUT.csv
and prints it as Markdown: per scene a summary (steps and position error per method, largest
order and rtol), then every run with all its counts, for docs/integrators.md."""
import csv
import json
import os
import sys

COLS = ["scene", "method", "max_order", "rtol", "status", "steps", "newton_iterations",
        "linear_setups", "factorizations", "error_test_failures", "steps_by_order", "wall_s",
        "pos_err_max", "txy_max_l2"]


def rows_of(name, d):
    for r in csv.DictReader(open(os.path.join(d, "work_precision.csv"))):
        if ":q" not in r["method"]:
            continue
        method, q = r["method"].split(":q")
        s = {}
        try:
            s = json.load(open(os.path.join(d, r["run_dir"], "summary.json")))
        except (OSError, ValueError):
            pass
        ok = r["status"] == "ok"
        order = s.get("steps_by_order") if ok else None
        yield {"scene": name, "method": method, "max_order": int(q), "rtol": r["value"],
               "status": r["status"] if ok else (r["how"] or r["status"]),
               "steps": r["steps"] if ok else "", "newton_iterations": r["newton_iterations"] if ok else "",
               "linear_setups": s.get("linear_setups", "") if ok else "",
               "factorizations": r["factorizations"] if ok else "",
               "error_test_failures": s.get("error_test_failures", "") if ok else "",
               "steps_by_order": " ".join(str(v) for v in order) if order else "",
               "wall_s": r["wall_s"] if ok else "", "pos_err_max": r["pos_err_max"],
               "txy_max_l2": r["txy_max_l2"]}


def fmt(v, f):
    try:
        return format(float(v), f)
    except ValueError:
        return v or "—"


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    rows = [r for a in sys.argv[2:] for r in rows_of(*a.split("=", 1))]
    with open(sys.argv[1], "w", newline="") as f:
        w = csv.DictWriter(f, COLS)
        w.writeheader()
        w.writerows(rows)
    rtols = list(dict.fromkeys(r["rtol"] for r in rows))
    for scene in dict.fromkeys(r["scene"] for r in rows):
        print(f"\n{scene}: steps (position error / size)\n")
        print("| method | max_order | " + " | ".join(f"rtol {v}" for v in rtols) + " |")
        print("| --- | --: | " + " | ".join("--:" for _ in rtols) + " |")
        for key in dict.fromkeys((r["method"], r["max_order"]) for r in rows if r["scene"] == scene):
            cells = []
            for v in rtols:
                hit = [r for r in rows if r["scene"] == scene and (r["method"], r["max_order"]) == key
                       and r["rtol"] == v]
                if not hit:
                    cells.append("")
                elif hit[0]["status"] != "ok":
                    cells.append("timed out" if "timed out" in hit[0]["status"] else hit[0]["status"])
                else:
                    cells.append(f"{hit[0]['steps']} ({fmt(hit[0]['pos_err_max'], '.1e')})")
            print(f"| {key[0]} | {key[1]} | " + " | ".join(cells) + " |")
    for scene in dict.fromkeys(r["scene"] for r in rows):
        print(f"\n{scene}: every run\n")
        print("| method | max_order | rtol | steps | Newton it. | factorisations | error-test fails "
              "| wall s | position error | tension XY error | steps at order 1–5 |")
        print("| --- | --: | --: | --: | --: | --: | --: | --: | --: | --: | --- |")
        for r in rows:
            if r["scene"] != scene:
                continue
            if r["status"] != "ok":
                print(f"| {r['method']} | {r['max_order']} | {r['rtol']} | {r['status']} "
                      "| | | | | | | |")
                continue
            print(f"| {r['method']} | {r['max_order']} | {r['rtol']} | {r['steps']} "
                  f"| {r['newton_iterations']} | {r['factorizations']} | {r['error_test_failures']} "
                  f"| {fmt(r['wall_s'], '.1f')} | {fmt(r['pos_err_max'], '.1e')} "
                  f"| {fmt(r['txy_max_l2'], '.1e')} | {r['steps_by_order']} |")


if __name__ == "__main__":
    main()
