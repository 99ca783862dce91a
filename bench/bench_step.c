/* bench_step.c — per-step wall time of an implicit integrator on the hanging cloth, N x N grid.
 *
 *   bench_step [--header] [--verbose] [--hessian=MODE] [--model=M]
 *              [--bending=dihedral|quadratic|morley|dde] [--fabric=PRESET] [--obj=FILE]
 *              N [steps] [method]
 *
 * --model picks the membrane with matched small-strain stiffness (docs/models.md): bw98
 * (default; k_u = k_v = 5000, k_shear = 100), stvk (e_u = e_v = 5000, shear_modulus 100,
 * poisson 0), corotated (k 5000), springs (stretch 5000, shear 100 per spring); --bending adds
 * that bending model with stiffness 1e-4 N m.  --fabric=PRESET makes the cloth the measured
 * fabric (docs/fabrics.md: its density, the dde membrane, and the bending model --bending names
 * with the fabric's rigidities, quadratic when not given; --bending=dde needs --fabric).
 * --obj=FILE takes the mesh from an OBJ of the unit square in the xy plane (e.g. an
 * unstructured one from tools/bending_study.py --square) instead of the grid; N is then only
 * printed, and the corners (0, 1) and (1, 1) are pinned by boxes.
 * Builds scenes/hanging_cloth.yaml in code with N x N vertices instead of 40 x 40 (1 m square
 * in the xy plane, 3D, density 0.1 kg/m^2, bw98 k_u = k_v = 5000, k_shear = 100 N/m, gravity
 * (0, 0, -9.81), the two corners of the edge y = 1 pinned; the scene loader's default options:
 * Hessian "abs" in 3D, Newton tol 1e-2 m/s, at most 50 iterations), then takes `steps`
 * (default 20) steps of dt = 0.01 s
 * of `method` (default backward-euler) through the integrator's operations directly: no scene
 * file, no output, no diagnostics.  A step that fails recoverably is retried with dt/2, dt/4, ...
 * exactly as sim/run.c does, and the failed attempts count in its time (--verbose: one line per
 * step on stderr with its Newton iterations and retries; --hessian: Newton's matrix, default
 * the scene's, abs in 3D).  Prints one CSV line on stdout (--header: the header line first;
 * --header alone: only the header):
 *
 *   N, dofs, nnz (lower triangle of the system), steps, newton_iterations, factorizations,
 *   step_s (mean wall s per step), assembly_s, factor_s, solve_s, rest_s (each per step;
 *   rest = step - assembly - factor - solve), nonfactor_share (1 - (factor + solve) / step),
 *   peak_rss_mib (the process's peak resident set, VmHWM; see bench_rss.h),
 *   assembly_per_iter_s, factor_per_iter_s (per Newton iteration).
 *
 * "assembly" is the solver's own timer (term gradients and Hessian blocks at each Newton
 * iterate plus the scatter into the CSC values); "rest" is mostly the line search's energy
 * evaluations and the vector work of Newton and the step.  The setup (pattern, CHOLMOD's
 * analysis) is outside the step and reported on stderr with a checksum of the final positions,
 * so that a change meant to leave results alone can be checked bit for bit. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_rss.h"
#include "scene.h"
#include "solver.h"
#include "util.h"


static const char *header =
    "N,dofs,nnz,steps,newton_iterations,factorizations,step_s,assembly_s,factor_s,solve_s,"
    "rest_s,nonfactor_share,peak_rss_mib,assembly_per_iter_s,factor_per_iter_s";

/* The membrane of each --model, with matched small-strain stiffness (N/m). */
static const char *const models[][2] = {
    {"bw98", "{model: bw98, k_u: 5000, k_v: 5000, k_shear: 100}"},
    {"stvk", "{model: stvk, e_u: 5000, e_v: 5000, shear_modulus: 100}"},
    {"corotated", "{model: corotated, k: 5000}"},
    {"springs", "{model: springs, stretch: 5000, shear: 100}"},
};

/* scenes/hanging_cloth.yaml with n x n vertices, through the scene loader itself. */
static sw_model *hanging_cloth(int n, const char *membrane, const char *bending,
                               const char *fabric, const char *obj, char *err, size_t errsz) {
  char yaml[4096], bend[128] = "", mesh[1200], pins[256], mat[256];
  if (bending && fabric) snprintf(bend, sizeof bend, "  bending: {model: %s}\n", bending);
  else if (bending)
    snprintf(bend, sizeof bend, "  bending: {model: %s, stiffness: 1e-4}\n", bending);
  if (fabric) snprintf(mat, sizeof mat, "  fabric: {preset: %s}\n", fabric);
  else snprintf(mat, sizeof mat, "  density: 0.1\n  membrane: %s\n", membrane);
  if (obj) {
    snprintf(mesh, sizeof mesh, "{obj: %s}", obj);
    snprintf(pins, sizeof pins, "[{select: {box: [[-1e-6, 0.999999, -1], [1e-6, 1.000001, 1]]}}, "
             "{select: {box: [[0.999999, 0.999999, -1], [1.000001, 1.000001, 1]]}}]");
  } else {
    snprintf(mesh, sizeof mesh, "{grid: {size: [1.0, 1.0], vertices: [%d, %d], plane: xy}}", n, n);
    snprintf(pins, sizeof pins, "[{select: {vertices: [%d, %d]}}]", (n - 1) * n, n * n - 1);
  }
  snprintf(yaml, sizeof yaml,
           "name: hanging cloth %d x %d\n"
           "mesh: %s\n"
           "material:\n"
           "%s"
           "%s"
           "gravity: [0, 0, -9.81]\n"
           "pins: %s   # the corners (0, 1) and (1, 1)\n"
           "integrator: {method: backward-euler, dt: 0.01}\n",
           n, n, mesh, mat, bend, pins);
  return sw_scene_parse("bench_step.yaml", yaml, strlen(yaml), err, errsz);
}

/* One step of the run from d->t to end, as sim/run.c takes it: a recoverable failure is retried
 * with half the step (opt.max_halvings times at most), and after a success with a reduced step
 * the rest of [t, end] is taken with it.  Every attempt's wall time counts in d->time_step. */
static int step_with_retries(const sw_integrator_ops *ops, void *st, const sw_model *m,
                             sw_data *d, double end) {
  const double dt = end - d->t;
  double h = dt;
  int rc = SW_OK;
  for (int k = 0; k <= m->opt.max_halvings; k++, h *= 0.5) {
    double t0 = sw_now();
    rc = ops->step(st, m, d, h < end - d->t ? h : end - d->t);
    d->time_step += sw_now() - t0;
    while (rc == SW_OK && d->t < end - 1e-12 * dt) {
      t0 = sw_now();
      rc = ops->step(st, m, d, h < end - d->t ? h : end - d->t);
      d->time_step += sw_now() - t0;
    }
    if (rc == SW_OK) {
      d->t = end;
      return SW_OK;
    }
    if (rc < 0) break;
    d->nretry++;
  }
  return rc;
}

static int usage(void) {
  fprintf(stderr, "usage: bench_step [--header] [--verbose]\n"
                  "                  [--hessian=abs|projected|progressive|auto|exact]\n"
                  "                  [--model=bw98|stvk|corotated|springs]\n"
                  "                  [--bending=dihedral|quadratic|morley|dde] [--fabric=PRESET]\n"
                  "                  [--obj=FILE] N [steps] [method]\n"
                  "  N >= 2 vertices per side, steps >= 1 (default 20), method (default "
                  "backward-euler)\n");
  return 2;
}

int main(int argc, char **argv) {
  int want_header = 0, verbose = 0, npos = 0, hessian = SW_HESSIAN_DEFAULT, model = 0;
  const char *bending = NULL, *obj = NULL, *fabric = NULL;
  const char *pos[3] = {NULL, NULL, NULL};
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--header")) want_header = 1;
    else if (!strcmp(argv[i], "--verbose")) verbose = 1;
    else if (!strncmp(argv[i], "--hessian=", 10)) {
      const char *const *names = sw_hessian_names();
      for (hessian = 0; names[hessian] && strcmp(argv[i] + 10, names[hessian]); hessian++) continue;
      if (!names[hessian]) return usage();
    } else if (!strncmp(argv[i], "--model=", 8)) {
      for (model = 0; model < 4 && strcmp(argv[i] + 8, models[model][0]); model++) continue;
      if (model == 4) return usage();
    } else if (!strcmp(argv[i], "--bending=dihedral")) bending = "dihedral";
    else if (!strcmp(argv[i], "--bending=quadratic")) bending = "quadratic";
    else if (!strcmp(argv[i], "--bending=morley")) bending = "morley";
    else if (!strcmp(argv[i], "--bending=dde")) bending = "dde";
    else if (!strncmp(argv[i], "--fabric=", 9)) fabric = argv[i] + 9;
    else if (!strncmp(argv[i], "--obj=", 6)) obj = argv[i] + 6;
    else if (argv[i][0] == '-' && argv[i][1] != '\0') return usage();
    else if (npos < 3) pos[npos++] = argv[i];
    else return usage();
  }
  if (want_header) puts(header);
  if (npos == 0) return want_header ? 0 : usage();
  char *end;
  long n = strtol(pos[0], &end, 10);
  if (*end || n < 2 || n > 20000) return usage();
  long steps = 20;
  if (pos[1]) {
    steps = strtol(pos[1], &end, 10);
    if (*end || steps < 1) return usage();
  }
  const char *method = pos[2] ? pos[2] : "backward-euler";
  const sw_integrator_ops *ops = sw_integrator_find(method);
  if (!ops) {
    fprintf(stderr, "bench_step: unknown method '%s'\n", method);
    return 2;
  }
  /* the thread settings sw_run uses */
  sw_set_threads(0);

  char err[SW_ERRSZ];
  sw_model *m = hanging_cloth((int)n, models[model][1], bending, fabric, obj, err, sizeof err);
  if (!m) {
    fprintf(stderr, "bench_step: %s\n", err);
    return 1;
  }
  const double dt = m->opt.dt;
  m->opt.duration = (double)steps * dt;
  snprintf(m->opt.method, sizeof m->opt.method, "%s", method);
  if (hessian != SW_HESSIAN_DEFAULT) m->opt.hessian = hessian; /* else the scene's */
  long nnz = sw_system_nnz(m);
  sw_data *d = sw_data_new(m);
  if (!d || nnz < 0) {
    fprintf(stderr, "bench_step: out of memory\n");
    return 1;
  }
  void *st = NULL;
  double t0 = sw_now();
  if (ops->init(&st, m, d, err, sizeof err)) {
    fprintf(stderr, "bench_step: %s\n", err);
    return 1;
  }
  double t_init = sw_now() - t0;
  for (long k = 1; k <= steps; k++) {
    long nit0 = d->nnewton, nret0 = d->nretry;
    double w0 = sw_now();
    int rc = step_with_retries(ops, st, m, d, (double)k * dt);
    if (verbose)
      fprintf(stderr, "step %ld: t = %g s, %ld Newton iterations, %ld retries, %.4g s\n", k, d->t,
              d->nnewton - nit0, d->nretry - nret0, sw_now() - w0);
    if (rc) {
      fprintf(stderr, "bench_step: N = %ld, step %ld: %s\n", n, k, d->err);
      return 1;
    }
  }
  ops->free(st);

  double s = (double)steps, it = d->nnewton > 0 ? (double)d->nnewton : 1.0;
  double step = d->time_step / s, as = d->time_assemble / s, fa = d->time_factor / s,
         so = d->time_solve / s;
  printf("%ld,%d,%ld,%ld,%ld,%ld,%.6g,%.6g,%.6g,%.6g,%.6g,%.4f,%.1f,%.6g,%.6g\n", n, m->ndof, nnz,
         steps, d->nnewton, d->nfactor, step, as, fa, so, step - as - fa - so,
         step > 0 ? 1.0 - (fa + so) / step : 0.0, bench_peak_rss_mib(),
         d->time_assemble / it, d->time_factor / it);
  double sum = 0.0;
  for (int i = 0; i < m->nv * m->dim; i++) sum += d->x[i];
  fprintf(stderr, "bench_step: N = %ld %s: setup (pattern + analysis) %.4g s, "
                  "line-search halvings %ld, retried steps %ld, factor nonzeros %ld, "
                  "sum of x at t = %g s: %.17g\n",
          n, method, t_init, d->nlinesearch, d->nretry, d->factor_nnz, d->t, sum);
  sw_data_free(d);
  sw_model_free(m);
  return 0;
}
