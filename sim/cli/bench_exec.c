/* bench_exec.c — running a bench plan: each job is one `sinew run` process, so that a crash, a
 * blow-up or a hang of one method is recorded (DIR/logs/ID.exit: "exit N", "signal N" or
 * "timeout S") and the others go on.  Locally up to --jobs processes at a time; or the same
 * command lines as a job list for GNU parallel or a Slurm array (--emit-jobs). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "bench.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

#define MAXARGS 40

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Append one argument (a copy in buf) to argv. */
static int arg(char **argv, int *n, int maxargs, char *buf, size_t bufsz, size_t *used,
               const char *s) {
  size_t len = strlen(s) + 1;
  if (*n + 1 >= maxargs || *used + len > bufsz) return -1;
  memcpy(buf + *used, s, len);
  argv[(*n)++] = buf + *used;
  argv[*n] = NULL;
  *used += len;
  return 0;
}

static int num_arg(char **argv, int *n, int maxargs, char *buf, size_t bufsz, size_t *used,
                   const char *opt, double v) {
  char s[32];
  bench_fmt(s, sizeof s, v);
  return arg(argv, n, maxargs, buf, bufsz, used, opt) ||
         arg(argv, n, maxargs, buf, bufsz, used, s);
}

/* --max-halvings of a run: the bench's; a fixed-step reference or confirm at least
 * BENCH_REF_HALVINGS (its halved steps are finer, not coarser). */
static int halvings(const bench_cfg *c, const bench_job *j) {
  int fixed_ref = j->role != BR_RUN && !j->adaptive;
  return fixed_ref && c->max_halvings < BENCH_REF_HALVINGS ? BENCH_REF_HALVINGS
                                                            : c->max_halvings;
}

int bench_job_argv(const bench_cfg *c, const bench_job *j, char **argv, int maxargs, char *buf,
                   size_t bufsz) {
  int n = 0, rc = 0;
  size_t used = 0;
  char out[SW_PATHSZ + BENCH_IDSZ + 8], grid[32], method[SW_NAMESZ];
  int order;
  if (bench_path(out, sizeof out, c->dir, "runs", j->id)) return -1;
  if (bench_method_split(j->method, method, sizeof method, &order)) return -1;
#define A(s) rc |= arg(argv, &n, maxargs, buf, bufsz, &used, s)
#define N(o, v) rc |= num_arg(argv, &n, maxargs, buf, bufsz, &used, o, v)
  A(c->exe), A("run"), A(c->scene), A("--out"), A(out), A("--quiet"), A("--threads"), A("1");
  A("--method"), A(method), A("--no-frames");
  if (order) N("--max-order", order);
  if (c->max_halvings >= 0) N("--max-halvings", halvings(c, j));
  if (j->role != BR_RUN && !j->adaptive && c->ref_newton_tol > 0)
    N("--newton-tol", c->ref_newton_tol);
  if (j->role == BR_RUN && !j->adaptive && c->newton_tol > 0) N("--newton-tol", c->newton_tol);
  N("--dt", j->dt);
  N("--duration", c->mode == BM_SCALING ? c->steps * j->dt : c->duration);
  if (j->adaptive) N("--rtol", j->rtol), N("--atol", j->atol);
  if (j->scale != 1.0) N("--stiffness-scale", j->scale);
  if (j->grid > 0) snprintf(grid, sizeof grid, "%dx%d", j->grid, j->grid), A("--grid"), A(grid);
  if (c->mode != BM_SCALING) N("--positions-every", c->sample);
#undef A
#undef N
  return rc ? -1 : n;
}

/* ------------------------------------------------------------- local runs */

typedef struct slot {
  pid_t pid;
  int job;
  double start, deadline;      /* s (monotonic); deadline 0: none */
  int timed_out;
} slot;

static int write_exit(const bench_cfg *c, const bench_job *j, const char *what) {
  char path[SW_PATHSZ + BENCH_IDSZ + 16];
  snprintf(path, sizeof path, "%s/logs/%s.exit", c->dir, j->id);
  FILE *f = fopen(path, "w");
  if (!f) return -1;
  fprintf(f, "%s\n", what);
  return fclose(f);
}

static pid_t spawn(const bench_cfg *c, const bench_job *j) {
  char *argv[MAXARGS], buf[4 * SW_PATHSZ], log[SW_PATHSZ + BENCH_IDSZ + 16];
  if (bench_job_argv(c, j, argv, MAXARGS, buf, sizeof buf) < 0) return -1;
  snprintf(log, sizeof log, "%s/logs/%s.log", c->dir, j->id);
  fflush(NULL);
  pid_t pid = fork();
  if (pid != 0) return pid;
  /* its own process group: a Ctrl-C at the terminal reaches the runs once, through the bench
   * (forward_stop); and SIGTERM when the bench itself dies, so that no run is orphaned */
  setpgid(0, 0);
#ifdef __linux__
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() == 1) _exit(128 + SIGTERM); /* the bench died before prctl */
#endif
  int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) dup2(fd, 1), dup2(fd, 2), close(fd);
  execv(argv[0], argv);
  fprintf(stderr, "sinew bench: cannot run %s: %s\n", argv[0], strerror(errno));
  _exit(127);
}

/* What became of a finished job, into its .exit file and one progress line. */
static void finished(const bench_plan *p, const slot *s, int status, int done) {
  const bench_job *j = &p->job[s->job];
  char what[48];
  if (s->timed_out) snprintf(what, sizeof what, "timeout %g", p->cfg.timeout);
  else if (WIFSIGNALED(status)) snprintf(what, sizeof what, "signal %d", WTERMSIG(status));
  else snprintf(what, sizeof what, "exit %d", WEXITSTATUS(status));
  write_exit(&p->cfg, j, what);
  fprintf(stderr, "  [%d/%d] %-44s %-12s %7.2f s\n", done, p->njob, j->id,
          !strcmp(what, "exit 0") ? "ok" : what, now() - s->start);
}

static void check_timeouts(slot *slots, int n) {
  double t = now();
  for (int k = 0; k < n; k++)
    if (slots[k].pid > 0 && slots[k].deadline > 0 && t > slots[k].deadline &&
        !slots[k].timed_out)
      kill(slots[k].pid, SIGKILL), slots[k].timed_out = 1;
}

/* Reap one finished child (waiting at most ~20 ms); its slot index, or -1. */
static int reap(slot *slots, int n, int *status) {
  pid_t pid = waitpid(-1, status, WNOHANG);
  if (pid <= 0) {
    struct timespec ts = {0, 20000000};
    nanosleep(&ts, NULL);
    return -1;
  }
  for (int k = 0; k < n; k++)
    if (slots[k].pid == pid) return k;
  return -1;
}

/* ------------------------------------------------------------ SIGINT, SIGTERM */

static volatile sig_atomic_t stop_signal; /* the signal the bench received, 0: none */

static void on_stop(int sig) { stop_signal = sig; }

static void catch_stop(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
}

/* The bench was asked to stop: the signal goes to every run going (each closes its folder as
 * "interrupted"), and the bench waits for them all and records how each ended. */
static int forward_stop(const bench_plan *p, slot *slots, int n, int *done) {
  int sig = stop_signal;
  fprintf(stderr, "sinew bench: %s: stopping the runs going, no new ones\n",
          sig == SIGINT ? "SIGINT" : "SIGTERM");
  for (int k = 0; k < n; k++)
    if (slots[k].pid > 0) kill(slots[k].pid, sig);
  for (int k = 0; k < n; k++) {
    int status;
    if (slots[k].pid <= 0) continue;
    while (waitpid(slots[k].pid, &status, 0) < 0 && errno == EINTR) {}
    finished(p, &slots[k], status, ++*done);
    slots[k].pid = 0;
  }
  return 128 + sig;
}

int bench_execute(const bench_plan *p) {
  const bench_cfg *c = &p->cfg;
  int n = c->jobs, next = 0, running = 0, done = 0;
  slot *slots = calloc((size_t)n, sizeof *slots);
  if (!slots) return fprintf(stderr, "sinew: bench: out of memory\n"), 2;
  fprintf(stderr, "sinew bench: %d runs of %s, %d at a time, into %s\n", p->njob, c->scene, n,
          c->dir);
  catch_stop();
  while (done < p->njob) {
    if (stop_signal) {
      int rc = forward_stop(p, slots, n, &done);
      free(slots);
      return rc;
    }
    for (int k = 0; k < n && next < p->njob; k++) {
      if (slots[k].pid > 0) continue;
      pid_t pid = spawn(c, &p->job[next]);
      if (pid < 0) {
        fprintf(stderr, "sinew: bench: cannot start run %s: %s\n", p->job[next].id,
                strerror(errno));
        free(slots);
        return 2;
      }
      double t = now();
      slots[k] = (slot){pid, next++, t, c->timeout > 0 ? t + c->timeout : 0.0, 0};
      running++;
    }
    int status, k = reap(slots, n, &status);
    check_timeouts(slots, n);
    if (k < 0) continue;
    finished(p, &slots[k], status, ++done);
    slots[k].pid = 0;
    running--;
  }
  free(slots);
  return 0;
}

/* --------------------------------------------------------------- job list */

/* s in single quotes for sh, with ' written as '\''. */
static void quote(FILE *f, const char *s) {
  fputc('\'', f);
  for (; *s; s++)
    if (*s == '\'') fputs("'\\''", f);
    else fputc(*s, f);
  fputc('\'', f);
}

static int write_slurm(const bench_plan *p, const char *jobs_abs) {
  char path[SW_PATHSZ + 16];
  snprintf(path, sizeof path, "%s/slurm.sh", p->cfg.dir);
  char tmp[SW_PATHSZ + 48];
  FILE *f = bench_create(path, tmp, sizeof tmp);
  if (!f) return -1;
  fprintf(f, "#!/bin/bash\n# A Slurm job array over the bench's job list: sbatch %s\n"
          "# then, when every task has ended: sinew bench --merge ", path);
  quote(f, p->cfg.dir);
  fprintf(f, "\n#SBATCH --array=1-%d\n#SBATCH --cpus-per-task=1\n#SBATCH --job-name=sinew-bench\n"
          "sed -n \"${SLURM_ARRAY_TASK_ID}p\" ", p->njob);
  quote(f, jobs_abs);
  fprintf(f, " | bash\n");
  return bench_commit(f, tmp);
}

/* One line per run: cd DIR && [timeout S] sinew run ... > logs/ID.log 2>&1; echo "exit $?" >
 * logs/ID.exit  (a run killed by signal N leaves "exit 128+N", one stopped by timeout(1) "exit 124"). */
int bench_emit(const bench_plan *p, const char *jobs_file, char *err, size_t errsz) {
  const bench_cfg *c = &p->cfg;
  char tmp[SW_PATHSZ + 16];
  FILE *f = bench_create(jobs_file, tmp, sizeof tmp);
  if (!f) return snprintf(err, errsz, "no job list written"), -1;
  for (int k = 0; k < p->njob; k++) {
    char *argv[MAXARGS], buf[4 * SW_PATHSZ];
    int n = bench_job_argv(c, &p->job[k], argv, MAXARGS, buf, sizeof buf);
    if (n < 0)
      return fclose(f), unlink(tmp), snprintf(err, errsz, "job %s: too long", p->job[k].id), -1;
    fputs("cd ", f);
    quote(f, c->dir);
    fputs(" && ", f);
    if (c->timeout > 0) fprintf(f, "timeout -k 10 %g ", c->timeout);
    for (int a = 0; a < n; a++) quote(f, argv[a]), fputc(' ', f);
    fprintf(f, "> logs/%s.log 2>&1; echo \"exit $?\" > logs/%s.exit\n", p->job[k].id,
            p->job[k].id);
  }
  if (bench_commit(f, tmp)) return snprintf(err, errsz, "%s: cannot write it", jobs_file), -1;
  char abs[SW_PATHSZ];
  if (!realpath(jobs_file, abs) || write_slurm(p, abs))
    return snprintf(err, errsz, "%s/slurm.sh: cannot write it", c->dir), -1;
  printf("wrote %d jobs to %s (and %s/slurm.sh)\nrun them, e.g.  parallel -j N < %s\n"
         "             or  sbatch %s/slurm.sh\nthen           sinew bench --merge %s\n", p->njob,
         jobs_file, c->dir, jobs_file, c->dir, c->dir);
  return 0;
}
