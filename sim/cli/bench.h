/* bench.h — `sinew bench` (docs/benchmarks.md): a scene under each method and setting, each run
 * its own `sinew run` process, then errors against a reference and costs into CSV files and
 * charts.  One file each part, each calling only the ones listed below it:
 *   bench.c        the command line, the plan (which runs) and its files plan_MODE.csv
 *   bench_exec.c   running the plan: local processes (--jobs N), or a job list (--emit-jobs)
 *   bench_merge.c  errors and costs of every run -> MODE CSV files -> tools/bench_charts.py
 *   bench_read.c   reading a run folder: summary.json, the CSV logs, positions.bin
 *   bench_util.c   the helpers they share: paths, whole files, numbers, method specs
 * Only the public API (sinew.h) is used: a bench is a client of `sinew run`. */
#ifndef SW_BENCH_H
#define SW_BENCH_H

#include <stddef.h>
#include <stdio.h>

#include "sinew.h"

/* What one invocation measures; each mode has its own plan and CSV files in the folder. */
enum { BM_WORK = 0, BM_STABILITY, BM_SCALING, BM_NMODE };
/* The role of a run in its mode's plan. */
enum { BR_REFERENCE = 0, BR_CONFIRM, BR_RUN };

#define BENCH_IDSZ 192
#define BENCH_MAXLIST 64
#define BENCH_MAX_JOBS 1000000 /* runs in a plan read by --merge, at most */
/* A fixed-step reference or confirm run halves a failed step up to this many times (or the
 * bench's --max-halvings when larger): a halved step is only finer, and it still ends on the
 * grid of its dt, so the sample times are still logged. */
#define BENCH_REF_HALVINGS 4
/* m/s: the default Newton tolerance of a fixed-step reference or confirm run; with the scene's
 * 1e-2 Newton's error is a quarter of a fine step's own on a draped cloth (docs/benchmarks.md) */
#define BENCH_REF_NEWTON_TOL 1e-5
#define BENCH_ORDER_NEWTON_TOL 1e-6 /* m/s: the --newton-tol the order warning suggests */
#define BENCH_NEWTON_TOL 0.0 /* m/s: the scene's (docs/benchmarks.md, "Newton's tolerance") */
/* Observed order (bench_order.c): errors below FLOOR x the reference's agreement are not
 * resolved; a converged range has local slopes above MIN_SLOPE that differ by at most SPREAD. */
#define BENCH_ORDER_FLOOR 3.0
#define BENCH_ORDER_MIN_SLOPE 0.25
#define BENCH_ORDER_SPREAD 0.3
/* Stability: a run of fewer steps than this proves nothing ("short", not "stable"). */
#define BENCH_MIN_STABLE_STEPS 10
/* Timings: the default --repeat (the median of 3 runs) */
#define BENCH_REPEAT 3
/* Timings: the default --time, 1: CPU time (user + system), 0: wall time; on a shared machine
 * CPU time moves less (docs/benchmarks.md, "Timing on a shared machine") */
#define BENCH_TIME_CPU 1
/* A run fails when a tension error exceeds this fraction of the reference's largest tension */
#define BENCH_TENSION_DIVERGED 1.0

typedef struct bench_job {
  char id[BENCH_IDSZ];         /* folder under DIR/runs and log name under DIR/logs */
  int role;                    /* BR_* */
  char method[SW_NAMESZ];
  int adaptive;                /* 1: setting is rtol; 0: setting is dt */
  double dt;                   /* s: the step (fixed) or the log interval (adaptive) */
  double rtol, atol;           /* adaptive methods: tolerances (atol in m and m/s) */
  double scale;                /* stiffness scale (1: the scene's) */
  int grid;                    /* scaling: the grid is grid x grid vertices (0: the scene's) */
  int rep;                     /* 1..repeat */
} bench_job;

/* The settings of a bench: what `sinew bench` was told, kept in DIR/bench_MODE.cfg so that
 * `sinew bench --merge DIR` sees the same. */
typedef struct bench_cfg {
  int mode;                    /* BM_* */
  char scene[SW_PATHSZ];       /* absolute path of the scene file */
  char dir[SW_PATHSZ];         /* the bench folder */
  char exe[SW_PATHSZ];         /* the sinew executable the runs use */
  double duration;             /* s */
  double sample;               /* s between the common sample times */
  double size;                 /* m: diagonal of the initial bounding box (relative errors) */
  double ref_rtol;             /* reference tolerance (adaptive reference and confirm) */
  double ref_dt, confirm_dt;   /* s: the steps of a fixed-step reference and confirm */
  double ref_newton_tol;       /* m/s: their Newton tolerance (--newton-tol); 0: the scene's */
  double newton_tol;           /* m/s: the Newton tolerance of the fixed-step runs (not the
                                  reference's); 0: the scene's */
  char ref_method[SW_NAMESZ], confirm_method[SW_NAMESZ];
  double confirm_tol;          /* the reference is confirmed when the two agree to this */
  double overdamped;           /* stability: energy lost beyond the reference's, fraction */
  double diverged;             /* a run whose position error exceeds this (x size) failed */
  double tension_diverged;     /* ... or whose tension XY or tendon error exceeds this
                                  (relative to the reference's largest) */
  double timeout;              /* s per run, 0: none */
  int repeat, jobs, steps, charts;
  int max_halvings;            /* passed to the runs (--max-halvings); < 0: the scene's */
  int time_cpu;                /* the tables and charts time runs by CPU time (1) or wall (0) */
} bench_cfg;

typedef struct bench_plan {
  bench_cfg cfg;
  bench_job *job;
  int njob;
} bench_plan;

/* bench.c */
int sw_bench_main(int argc, char **argv);
int bench_plan_read(const char *dir, int mode, bench_plan *p, char *err, size_t errsz);

/* bench_exec.c: the argv of a job's `sinew run` (into argv[], strings in buf). */
int bench_job_argv(const bench_cfg *c, const bench_job *j, char **argv, int maxargs, char *buf,
                   size_t bufsz);
int bench_execute(const bench_plan *p);
int bench_emit(const bench_plan *p, const char *jobs_file, char *err, size_t errsz);

/* bench_read.c: what a run left in its folder. */
typedef struct bench_result {
  int present;                 /* summary.json was read */
  char status[16];             /* ok | failed | crashed (no summary, "running", or a signal) */
  char how[48];                /* short reason of a failure */
  char message[512];
  double wall;                 /* s: wall time of the run (summary.json wall_time_s) */
  double cpu;                  /* s: its CPU time, user + system (cpu_time_s); NaN: none */
  double time_step, time_assemble, time_factor, time_solve, max_rss_mb;
  long steps, newton, factor, assemble, force, retries;
  long dofs, nv;
  /* the logs at the common sample times: ns samples */
  int ns;
  double *t;                   /* (ns) s */
  double *txy_max, *txy_mean;  /* (ns) N/m */
  double *energy, *kinetic;    /* (ns) J: K + U, and K */
  int ntendon;
  double *tendon;              /* (ns x ntendon) N */
  int npos, dim, pnv;          /* positions.bin: samples found, dim, vertices */
  double *pos;                 /* (ns x pnv x dim) m, NaN where a sample is missing */
  double step_median;          /* s: median of step_wall_s over the steps after the first */
} bench_result;

int bench_read(const bench_cfg *c, const bench_job *j, int want_positions, bench_result *r);
void bench_result_free(bench_result *r);
double bench_median(double *v, int n); /* sorts v; NaN when n == 0 */
int bench_nsample(const bench_cfg *c); /* samples 0, S, 2S, ..., and the final time */
double bench_sample_time(const bench_cfg *c, int k);

/* bench_merge.c */
int bench_merge(const bench_plan *p);

/* bench_order.c: the observed order of each method from its runs' position errors. */
typedef struct bench_point {
  const char *method;
  int adaptive, ok;
  double h, e;                 /* the setting (dt s, or rtol) and pos_err_max */
} bench_point;
int bench_orders(const bench_cfg *c, const bench_point *pt, int npt, double floor_e);

/* bench_util.c: small shared helpers, below every other part */
const char *bench_mode_name(int mode); /* work_precision, stability, scaling */
/* An adaptive method with its largest BDF order, "NAME:qN" (N in 1..5; `sinew run --method NAME
 * --max-order N`), or a plain method name "NAME" (order 0: the scene's).  name gets NAME;
 * -1 if SPEC is neither. */
int bench_method_split(const char *spec, char *name, size_t namesz, int *order);
int bench_path(char *out, size_t sz, const char *dir, const char *a, const char *b);
void bench_fmt(char *buf, size_t sz, double v); /* shortest %g that reads back exactly */
int bench_atoi(const char *s);                  /* strtol clamped to +-1e9 (0 if none) */
/* A file written whole or not at all: PATH.tmp (its name into tmp), then renamed to PATH by
 * bench_commit (removed, with a message, when a write failed). */
FILE *bench_create(const char *path, char *tmp, size_t sz);
int bench_commit(FILE *f, const char *tmp);

#endif
