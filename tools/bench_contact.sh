#!/usr/bin/env bash
# tools/bench_contact.sh [SINEW] — what contact costs: scenes/drape_sphere.yaml (41 x 41 cloth
# dropped on a sphere, backward Euler, dt 10 ms, 2 s) as shipped, with self-contact ("self"),
# the same scene without self-contact ("contact": the sphere only) and without its obstacle and
# contact keys (the cloth falls freely: "free"), interleaved REPS times (default 2) so all see the same
# machine load.  Per run: steps, Newton iterations, factorisations, line-search cuts, step time,
# its assembly (every term, the contact terms included), factorisation, solve, obstacle checks
# (time_contact_s: conservative advancement, the settling test, each step's start), and for
# self-contact the term's own evaluations (broad phase, pairs, their blocks), its continuous
# collision detection (and the broad phase's part of it) and the pattern's growths with their
# CHOLMOD analyses, per step, per Newton iteration and as shares of the step time.  Writes
# docs/bench/contact/drape.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/sinew}
reps=${REPS:-2}
out=${OUT:-docs/bench/contact}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
scene=scenes/drape_sphere.yaml
# the scene without contact: drop the obstacles and contact blocks (and their comments)
awk '/^obstacles:/ || /^contact:/ { skip = 1; next } skip && /^[^ #]/ { skip = 0 } !skip' \
  "$scene" >"$work/free.yaml"
# the scene without self-contact
grep -q '^  self: true' "$scene" || { echo "$scene has no self: true" >&2; exit 1; }
grep -v '^  self: true' "$scene" >"$work/contact.yaml"
field() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "$1/summary.json" | head -1; }
echo "case,rep,status,steps,newton_iterations,factorizations,linesearch_backtracks,time_step_s,time_assemble_s,time_factor_s,time_solve_s,time_contact_s,step_ms_per_step,step_ms_per_iteration,contact_share,self_term_s,self_ccd_s,self_broadphase_s,pattern_s,pattern_growths,self_term_share,self_ccd_share,self_broadphase_share,pattern_share" >"$out/drape.csv"
for r in $(seq "$reps"); do
  for c in contact free self; do
    s=$scene; [ "$c" = free ] && s=$work/free.yaml; [ "$c" = contact ] && s=$work/contact.yaml
    d="$work/$c$r"
    "$bin" run "$s" --out "$d" --no-frames --quiet --threads 1 >/dev/null 2>&1 || true
    st=$(sed -n 's/.*"status": "\([a-z]*\)".*/\1/p' "$d/summary.json")
    steps=$(field "$d" steps); it=$(field "$d" newton_iterations); fa=$(field "$d" factorizations)
    ls=$(field "$d" linesearch_backtracks); ts=$(field "$d" time_step_s)
    ta=$(field "$d" time_assemble_s); tf=$(field "$d" time_factor_s); tv=$(field "$d" time_solve_s)
    tc=$(field "$d" time_contact_s); tc=${tc:-0}
    sm=$(field "$d" mesh_contact); sm=${sm:-0}
    sc=$(field "$d" time_self_ccd_s); sc=${sc:-0}
    sb=$(field "$d" time_self_broadphase_s); sb=${sb:-0}
    tp=$(field "$d" time_pattern_s); tp=${tp:-0}
    np=$(field "$d" pattern_growths); np=${np:-0}
    awk -v c="$c" -v r="$r" -v st="$st" -v s="$steps" -v it="$it" -v fa="$fa" -v ls="$ls" \
      -v ts="$ts" -v ta="$ta" -v tf="$tf" -v tv="$tv" -v tc="$tc" -v sm="$sm" -v sc="$sc" \
      -v sb="$sb" -v tp="$tp" -v np="$np" 'BEGIN {
        printf "%s,%s,%s,%d,%d,%d,%d,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%.3f,", c, r, st, s, it,
          fa, ls, ts, ta, tf, tv, tc, 1e3 * ts / s, 1e3 * ts / it, tc / ts
        printf "%.4g,%.4g,%.4g,%.4g,%d,%.3f,%.3f,%.3f,%.3f\n", sm, sc, sb, tp, np, sm / ts,
          sc / ts, sb / ts, tp / ts }' >>"$out/drape.csv"
  done
done
cat "$out/drape.csv"
