/* test_failures.c — injected failures through the whole run (sw_run), each checked for what it
 * leaves behind (docs/reliability.md):
 *   - a term whose energy (or gradient) turns NaN at a chosen time;
 *   - a term with a negative-definite Hessian under `hessian: exact` (S not positive definite);
 *   - the k-th allocation failing (sw_alloc_fail_after), for every k until the run succeeds, with
 *     every method (leaks are caught by the ASan build of .ci/run);
 *   - an output folder that cannot be made;
 *   - a write that fails part-way (RLIMIT_FSIZE in a forked child).
 * Each must give a message naming what failed, a nonzero return, logs holding whole lines up to
 * the failure, and a summary.json saying "failed" (never "ok"). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"
#include "sinew.h"
#include "terms.h"
#include "util.h"

static char root[64]; /* temporary folder of this test program */

/* ----------------------------------------------------------------- helpers */

/* A CSV log of whole lines: it ends in a newline and every line has the header's number of
 * fields.  Returns the number of lines, header included. */
static int check_csv(const char *dir, const char *name) {
  char *s = th_slurp_in(dir, name);
  if (!s) fail_msg("%s/%s: missing", dir, name);
  size_t n = strlen(s);
  if (n == 0 || s[n - 1] != '\n') fail_msg("%s/%s: does not end in a newline", dir, name);
  int lines = 0, fields = -1;
  for (char *p = s; *p;) {
    char *nl = strchr(p, '\n');
    int f = 1;
    for (char *q = p; q < nl; q++) f += *q == ',';
    if (fields < 0) fields = f;
    else if (f != fields)
      fail_msg("%s/%s: line %d has %d fields, the header %d", dir, name, lines + 1, f, fields);
    lines++;
    p = nl + 1;
  }
  free(s);
  return lines;
}

/* The last line of a log (without its newline) into buf. */
static void last_line(const char *dir, const char *name, char *buf, size_t sz) {
  char *s = th_slurp_in(dir, name);
  assert_non_null(s);
  size_t n = strlen(s);
  assert_true(n > 0 && s[n - 1] == '\n');
  s[n - 1] = '\0';
  char *p = strrchr(s, '\n');
  snprintf(buf, sz, "%s", p ? p + 1 : s);
  free(s);
}

/* Every file listed in frames.pvd exists and is complete XML; returns how many frames (cloth
 * files) are listed. */
static int check_frames(const char *dir) {
  char *pvd = th_slurp_in(dir, "frames.pvd");
  if (!pvd) return 0;
  assert_non_null(strstr(pvd, "</VTKFile>\n"));
  int n = 0;
  for (const char *p = strstr(pvd, "file=\""); p; p = strstr(p + 1, "file=\"")) {
    char name[256];
    size_t len = strcspn(p + 6, "\"");
    assert_true(len < sizeof name);
    memcpy(name, p + 6, len);
    name[len] = '\0';
    char path[SW_PATHSZ + 300];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    size_t vn = 0;
    char *vtu = th_slurp_n(path, &vn);
    if (!vtu) fail_msg("%s/%s is listed in frames.pvd but missing", dir, name);
    if (vn < 11 || strcmp(vtu + vn - 11, "</VTKFile>\n"))
      fail_msg("%s/%s does not end with </VTKFile>", dir, name);
    free(vtu);
    n += strstr(name, ".vtu") != NULL;
  }
  free(pvd);
  return n;
}

static int summary_has(const char *dir, const char *what) {
  char *s = th_slurp_in(dir, "summary.json");
  int has = s && strstr(s, what);
  free(s);
  return has;
}

/* ------------------------------------------------------------------ models */

/* A small hanging cloth: 5 x 5 vertices, 0.4 m square, top row pinned, bw98 and gravity. */
static sw_model *small_model(const char *out) {
  const double g[3] = {0.0, 0.0, -9.81};
  sw_model *m = th_grid_model(3, 5, 5, 0.4, 0.4, 0.1, 200.0, 10.0, g, 1);
  assert_non_null(m);
  snprintf(m->name, sizeof m->name, "failures");
  m->opt.dt = 0.01;
  m->opt.duration = 0.1;
  m->opt.frames_every = 0.05;
  snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "%s/%s", root, out);
  return m;
}

/* Append a term with its own operations; stencils: one per vertex when with_hessian, else none. */
static void add_term(sw_model *m, const sw_term_ops *ops, const char *name, void *param,
                     int with_hessian) {
  sw_term *t = realloc(m->term, (size_t)(m->nterm + 1) * sizeof *t);
  assert_non_null(t);
  m->term = t;
  sw_term *nt = &t[m->nterm];
  memset(nt, 0, sizeof *nt);
  nt->ops = ops;
  snprintf(nt->name, sizeof nt->name, "%s", name);
  nt->param = param;
  assert_int_equal(sw_term_alloc_stencils(nt, with_hessian ? m->nv : 0, 1, m->dim), 0);
  for (int i = 0; with_hessian && i < m->nv; i++) nt->sidx[i] = i;
  m->nterm++;
}

/* A term that is 0 until t_nan, then NaN: in its energy (where 0) or its gradient (where 1). */
typedef struct nan_param {
  double t_nan; /* s */
  int where;
} nan_param;

static int nan_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  const nan_param *p = t->param;
  int bad = ev->t > p->t_nan;
  *energy = bad && p->where == 0 ? NAN : 0.0;
  if (bad && p->where == 1 && ev->grad)
    for (int k = 0; k < m->nv * m->dim; k++) ev->grad[k] += NAN;
  return SW_OK;
}

static const sw_term_ops nan_ops = {.kind = "nan", .eval = nan_eval};

/* E = -c/2 |x - x0|^2: a negative-definite Hessian -c I per vertex (0 when projected). */
static int negdef_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  const double c = *(const double *)t->param; /* N/m */
  const int dim = m->dim;
  double e = 0.0;
  for (int k = 0; k < m->nv * dim; k++) {
    double r = ev->x[k] - m->x0[k];
    e -= 0.5 * c * r * r;
    if (ev->grad) ev->grad[k] -= c * r;
  }
  if (ev->hess && !ev->project)
    for (int s = 0; s < t->nstencil; s++)
      for (int a = 0; a < dim; a++) ev->hess[t->hptr[s] + sw_hess_upper(a, a, dim)] -= c;
  *energy = e;
  return SW_OK;
}

static const sw_term_ops negdef_ops = {.kind = "negdef", .eval = negdef_eval};

/* ------------------------------------------------------------------- NaN */

/* NaN from t > 0.04 s: every step, however halved, ending after 0.04 s fails.  The run stops
 * at t = 0.04 s naming the time and the reason; the logs are renamed and hold t = 0 .. 0.04;
 * the last good state (t = 0.04 s) is the last frame; summary.json says "failed". */
static void run_nan(const char *method, int where, const char *reason) {
  char out[128], err[SW_ERRSZ] = "", line[512];
  snprintf(out, sizeof out, "nan_%s_%d", method, where);
  sw_model *m = small_model(out);
  snprintf(m->opt.method, sizeof m->opt.method, "%s", method);
  nan_param p = {0.04 + 1e-9, where};
  add_term(m, &nan_ops, "nan", &p, 0);
  const char *dir = m->opt.out_dir;
  assert_int_not_equal(sw_run(m, 0, err, sizeof err), 0);
  if (!strstr(err, "t = 0.04 s: ") || !strstr(err, method) || !strstr(err, reason) ||
      !strstr(err, "halved 8 times"))
    fail_msg("%s: message \"%s\"", method, err);
  print_message("%s\n", err);
  assert_true(summary_has(dir, "\"status\": \"failed\""));
  assert_true(summary_has(dir, reason));
  assert_true(summary_has(dir, "\"tension.csv\", \"energy.csv\""));
  assert_false(th_exists_in(dir, "tension.csv.part") || th_exists_in(dir, "energy.csv.part"));
  assert_int_equal(check_csv(dir, "tension.csv"), 6); /* header, t = 0, 0.01, ..., 0.04 */
  assert_int_equal(check_csv(dir, "energy.csv"), 6);
  last_line(dir, "tension.csv", line, sizeof line);
  assert_true(!strncmp(line, "0.04,", 5));
  last_line(dir, "energy.csv", line, sizeof line);
  assert_true(!strncmp(line, "0.04,", 5));
  assert_null(strstr(line, "nan")); /* no NaN was logged */
  assert_int_equal(check_frames(dir), 2); /* t = 0 and the last good state */
  char *pvd = th_slurp_in(dir, "frames.pvd");
  assert_non_null(strstr(pvd, "timestep=\"0.04\""));
  free(pvd);
  sw_model_free(m);
}

static void test_nan_energy(void **state) {
  (void)state;
  run_nan("backward-euler", 0, "energy is not finite");
  run_nan("baraff-witkin", 0, "energy is not finite");
}

static void test_nan_gradient(void **state) {
  (void)state;
  run_nan("backward-euler", 1, "Newton step is not finite");
}

/* ------------------------------------------------------ not positive definite */

static void test_not_positive_definite(void **state) {
  (void)state;
  char err[SW_ERRSZ] = "", line[512];
  sw_model *m = small_model("negdef");
  m->opt.hessian = SW_HESSIAN_EXACT;
  double c = 1e9; /* N/m: beats M/h^2 even after 8 halvings */
  add_term(m, &negdef_ops, "negdef", &c, 1);
  const char *dir = m->opt.out_dir;
  assert_int_not_equal(sw_run(m, 0, err, sizeof err), 0);
  if (!strstr(err, "t = 0 s: backward-euler: ") || !strstr(err, "not positive definite") ||
      !strstr(err, "halved 8 times"))
    fail_msg("message \"%s\"", err);
  print_message("%s\n", err);
  assert_true(summary_has(dir, "\"status\": \"failed\""));
  assert_true(summary_has(dir, "not positive definite"));
  assert_true(summary_has(dir, "\"retries\": 9"));
  assert_int_equal(check_csv(dir, "tension.csv"), 2); /* header and t = 0 */
  assert_int_equal(check_csv(dir, "energy.csv"), 2);
  last_line(dir, "tension.csv", line, sizeof line);
  assert_true(!strncmp(line, "0,", 2));
  assert_int_equal(check_frames(dir), 2);
  sw_model_free(m);
}

/* ------------------------------------------------------- allocation failures */

/* For every method, allocation k of sw_run failing, k = 1, 2, ... until the run succeeds: a
 * nonzero return with a message, no crash, no leak, and no "ok" summary. */
static void test_alloc_failures(void **state) {
  (void)state;
  for (const char *const *meth = sw_method_names(); *meth; meth++) {
    char out[128], err[SW_ERRSZ], last[SW_ERRSZ] = "";
    snprintf(out, sizeof out, "alloc_%s", *meth);
    sw_model *m = small_model(out);
    snprintf(m->opt.method, sizeof m->opt.method, "%s", *meth);
    m->opt.duration = 0.02;
    m->opt.frames_every = 0.01;
    const char *dir = m->opt.out_dir;
    err[0] = '\0';
    if (sw_run(m, 0, err, sizeof err)) fail_msg("%s: the run fails without injection: %s", *meth, err);
    long k = 1, nfail = 0;
    for (; k < 100000; k++) {
      th_remove_tree(dir);
      err[0] = '\0';
      sw_alloc_fail_after(k);
      int rc = sw_run(m, 0, err, sizeof err);
      sw_alloc_fail_after(0);
      if (rc == 0) break;
      nfail++;
      if (!err[0]) fail_msg("%s: allocation %ld failing: no message", *meth, k);
      if (strcmp(err, last)) print_message("%s, allocation %ld: %s\n", *meth, k, err);
      snprintf(last, sizeof last, "%s", err);
      if (summary_has(dir, "\"status\": \"ok\""))
        fail_msg("%s: allocation %ld failing: summary.json says ok (%s)", *meth, k, err);
      if (th_exists_in(dir, "summary.json") && !summary_has(dir, "\"status\": \"failed\"") &&
          !summary_has(dir, "\"status\": \"running\""))
        fail_msg("%s: allocation %ld failing: summary.json has no status", *meth, k);
    }
    assert_true(k < 100000);
    assert_true(nfail > 0);
    assert_true(summary_has(dir, "\"status\": \"ok\""));
    print_message("%s: %ld allocations made to fail in turn\n", *meth, nfail);
    th_remove_tree(dir);
    sw_model_free(m);
  }
}

/* ------------------------------------------------------- the output folder */

static void test_unwritable_folder(void **state) {
  (void)state;
  char err[SW_ERRSZ] = "", file[128], taken[SW_PATHSZ + 16];
  snprintf(file, sizeof file, "%s/plain_file", root);
  FILE *f = fopen(file, "w");
  assert_non_null(f);
  fclose(f);
  const char *subs[] = {"/sub/run", ""}; /* below a regular file; the file itself */
  for (int i = 0; i < 2; i++) {
    sw_model *m = small_model("unused");
    snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "%s%s", file, subs[i]);
    assert_int_not_equal(sw_run(m, 0, err, sizeof err), 0);
    if (!strstr(err, m->opt.out_dir) || !strstr(err, "cannot create the output folder") ||
        !strstr(err, "Not a directory"))
      fail_msg("message \"%s\"", err);
    print_message("%s\n", err);
    sw_model_free(m);
  }
  /* frames/ taken by a regular file */
  sw_model *m = small_model("frames_taken");
  assert_int_equal(mkdir(m->opt.out_dir, 0755), 0);
  snprintf(taken, sizeof taken, "%s/frames", m->opt.out_dir);
  f = fopen(taken, "w");
  assert_non_null(f);
  fclose(f);
  assert_int_not_equal(sw_run(m, 0, err, sizeof err), 0);
  if (!strstr(err, taken) || !strstr(err, "Not a directory")) fail_msg("message \"%s\"", err);
  print_message("%s\n", err);
  assert_false(th_exists_in(m->opt.out_dir, "summary.json"));
  sw_model_free(m);
  if (geteuid() == 0) return; /* root may write into a read-only folder */
  m = small_model("read_only");
  assert_int_equal(mkdir(m->opt.out_dir, 0555), 0);
  assert_int_not_equal(sw_run(m, 0, err, sizeof err), 0);
  if (!strstr(err, m->opt.out_dir) || !strstr(err, "not writable")) fail_msg("message \"%s\"", err);
  chmod(m->opt.out_dir, 0755);
  sw_model_free(m);
}

/* ------------------------------------------------- a write failing part-way */

/* In a child: files limited to `limit` bytes (SIGXFSZ ignored, so write(2) fails with EFBIG),
 * run; the return code and message come back through a pipe. */
static int run_limited(sw_model *m, rlim_t limit, char *err, size_t errsz) {
  int fd[2];
  assert_int_equal(pipe(fd), 0);
  fflush(NULL);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    close(fd[0]);
    signal(SIGXFSZ, SIG_IGN);
    struct rlimit rl = {limit, limit};
    char msg[SW_ERRSZ + 8] = "";
    int rc = setrlimit(RLIMIT_FSIZE, &rl) ? -100 : sw_run(m, 0, msg + 4, SW_ERRSZ);
    memcpy(msg, &rc, sizeof rc);
    ssize_t w = write(fd[1], msg, sizeof msg);
    _exit(w == (ssize_t)sizeof msg ? 0 : 1);
  }
  close(fd[1]);
  char msg[SW_ERRSZ + 8];
  size_t got = 0;
  ssize_t r;
  while (got < sizeof msg && (r = read(fd[0], msg + got, sizeof msg - got)) > 0) got += (size_t)r;
  close(fd[0]);
  int status;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  assert_int_equal(got, sizeof msg);
  int rc;
  memcpy(&rc, msg, sizeof rc);
  msg[sizeof msg - 1] = '\0';
  size_t n = strnlen(msg + 4, errsz - 1);
  memcpy(err, msg + 4, n);
  err[n] = '\0';
  return rc;
}

/* energy.csv.part hits the limit in the middle of a line: that step's lines are cut from both
 * logs, which end at the same step with whole lines; energy.csv.part keeps its name (the write
 * failed), tension.csv is renamed; the last good state is a complete frame; "failed". */
static void test_write_fails_part_way(void **state) {
  (void)state;
  char err[SW_ERRSZ] = "", lt[512], le[512];
  sw_model *m = small_model("fsize");
  m->opt.duration = 2.0;
  m->opt.frames_every = 0.0; /* first and last frames only: the logs fill first */
  const char *dir = m->opt.out_dir;
  int rc = run_limited(m, 16384, err, sizeof err);
  assert_int_not_equal(rc, 0);
  assert_int_not_equal(rc, -100);
  char want[SW_PATHSZ + 128];
  snprintf(want, sizeof want, "%s/energy.csv.part: cannot write: %s", dir, strerror(EFBIG));
  if (!strstr(err, want)) fail_msg("message \"%s\", expected \"%s\"", err, want);
  print_message("%s\n", err);
  assert_true(summary_has(dir, "\"status\": \"failed\""));
  assert_true(summary_has(dir, "energy.csv.part: cannot write"));
  assert_true(summary_has(dir, "\"tension.csv\", \"energy.csv.part\""));
  assert_true(th_exists_in(dir, "energy.csv.part") && !th_exists_in(dir, "energy.csv"));
  assert_true(th_exists_in(dir, "tension.csv") && !th_exists_in(dir, "tension.csv.part"));
  int nt = check_csv(dir, "tension.csv"), ne = check_csv(dir, "energy.csv.part");
  assert_int_equal(nt, ne);
  assert_true(ne > 10);
  last_line(dir, "tension.csv", lt, sizeof lt);
  last_line(dir, "energy.csv.part", le, sizeof le);
  assert_int_equal(strcspn(lt, ","), strcspn(le, ",")); /* the same time */
  assert_memory_equal(lt, le, strcspn(lt, ","));
  print_message("both logs end at t = %.*s s\n", (int)strcspn(lt, ","), lt);
  assert_int_equal(check_frames(dir), 2);
  /* The same with no room at all: the logs cannot be opened; no summary says "ok". */
  th_remove_tree(dir);
  rc = run_limited(m, 0, err, sizeof err);
  assert_int_not_equal(rc, 0);
  assert_int_not_equal(rc, -100);
  if (!strstr(err, dir) || !strstr(err, strerror(EFBIG))) fail_msg("message \"%s\"", err);
  print_message("%s\n", err);
  assert_false(summary_has(dir, "\"status\": \"ok\""));
  sw_model_free(m);
}

/* positions.bin (a record every step, 608 bytes) hits the limit first, part-way through a
 * record: that step is cut from every log and from positions.bin, which holds whole records,
 * one per logged state; positions.bin.part keeps its name, the CSV logs are renamed. */
static void test_positions_write_fails(void **state) {
  (void)state;
  char err[SW_ERRSZ] = "";
  sw_model *m = small_model("fsize_positions");
  m->opt.duration = 2.0;
  m->opt.frames_every = -1.0; /* no frames: only the logs and the last good state */
  m->opt.positions_every = m->opt.dt;
  const char *dir = m->opt.out_dir;
  int rc = run_limited(m, 32768, err, sizeof err); /* above restart.bin at the start, 9 kB */
  assert_int_not_equal(rc, 0);
  assert_int_not_equal(rc, -100);
  char want[SW_PATHSZ + 128];
  snprintf(want, sizeof want, "%s/positions.bin.part: cannot write: %s", dir, strerror(EFBIG));
  if (!strstr(err, want)) fail_msg("message \"%s\", expected \"%s\"", err, want);
  print_message("%s\n", err);
  assert_true(summary_has(dir, "\"status\": \"failed\""));
  assert_true(summary_has(dir, "\"tension.csv\", \"energy.csv\", \"positions.bin.part\""));
  assert_true(th_exists_in(dir, "positions.bin.part") && !th_exists_in(dir, "positions.bin"));
  int nt = check_csv(dir, "tension.csv"), ne = check_csv(dir, "energy.csv");
  assert_int_equal(nt, ne);
  char path[SW_PATHSZ + 64];
  snprintf(path, sizeof path, "%s/positions.bin.part", dir);
  struct stat st;
  assert_int_equal(stat(path, &st), 0);
  const long recsz = 8L * (1 + m->nv * m->dim);
  assert_int_equal((st.st_size - 16) % recsz, 0);
  assert_int_equal((st.st_size - 16) / recsz, nt - 1); /* one record per logged state */
  assert_true(nt > 5);
  /* the last record is the last logged time */
  char lt[512];
  last_line(dir, "tension.csv", lt, sizeof lt);
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  double t;
  assert_int_equal(fseek(f, (long)st.st_size - recsz, SEEK_SET), 0);
  assert_int_equal(fread(&t, sizeof t, 1, f), 1);
  fclose(f);
  assert_true(t == strtod(lt, NULL));
  /* no frames but the last good state, listed in frames.pvd */
  assert_int_equal(check_frames(dir), 1);
  sw_model_free(m);
}

static int setup(void **state) {
  (void)state;
  snprintf(root, sizeof root, "/tmp/sinew_test_failures_XXXXXX");
  return mkdtemp(root) ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  th_remove_tree(root);
  return 0;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_nan_energy),
      cmocka_unit_test(test_nan_gradient),
      cmocka_unit_test(test_not_positive_definite),
      cmocka_unit_test(test_alloc_failures),
      cmocka_unit_test(test_unwritable_folder),
      cmocka_unit_test(test_write_fails_part_way),
      cmocka_unit_test(test_positions_write_fails),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
