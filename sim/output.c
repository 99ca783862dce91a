/* output.c — the writers of a run's folder (DESIGN.md "Outputs").
 *
 * Folder layout (relative to m->opt.out_dir):
 *   tension.csv    time, max/mean/p95 of tension XY, max warp/weft stretch, max shear
 *   energy.csv     time, kinetic and per-term energies, step size and per-step solver counts;
 *                  damping power and dissipated energy; actuation power and work in
 *   positions.bin  with opt.positions_every > 0: every vertex position at sampled times, binary
 *                  (a 16-byte header "SWPOS001", int32 nv, int32 dim; then per record float64 t
 *                  and nv x dim float64 positions; host byte order)
 *   summary.json   scene, method, counters, wall time, status
 *   frames.pvd     ParaView collection of the complete frames
 *   frames/frame_NNNNNN.vtu
 * Logs (and positions.bin) live as NAME.part until sw_output_close; every other file is written
 * to NAME.tmp and renamed, so a reader never sees a half-written file under a final name.  A log
 * line (a record of positions.bin) goes out in one write(2) (no stdio buffer), so a killed run
 * leaves whole lines (a record of many pages may still be cut by the kill: readers take whole
 * records); a step whose lines fail part-way (disk full, file size limit) is cut back from
 * every log, which then ends at the previous step.
 * With opt.frames_every < 0 no frame is written (frames/ is not even made) except the last good
 * state of a failed run.  Every write is checked; errors read "PATH: what failed:
 * strerror(errno)".  sw_output_record allocates nothing.
 */
#include "output.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util.h"

#define PATHMAX (SW_PATHSZ + 64) /* out_dir plus a file name inside it */
#define NUMSZ 32                 /* room for one %.17g number and its separator */

/* tendons.csv is only written by a scene with tendons, positions.bin only with
 * opt.positions_every > 0 (their fds stay -1 otherwise) */
enum { LOG_TENSION, LOG_ENERGY, LOG_TENDONS, LOG_POSITIONS, NLOG };
static const char *const log_name[NLOG] = {"tension.csv", "energy.csv", "tendons.csv",
                                           "positions.bin"};
#define POS_MAGIC "SWPOS001"  /* positions.bin: 8 bytes of magic, then int32 nv, int32 dim */
#define POS_HEADER 16         /* bytes */

struct sw_output {
  char dir[SW_PATHSZ];         /* the run folder, without trailing '/' */
  int log[NLOG];               /* fd of NAME.csv.part while the run goes, -1 when closed */
  off_t size[NLOG];            /* bytes of the whole lines written to each log */
  int werr[NLOG];              /* errno of a failed write to each log (0: none) */
  int final[NLOG];             /* 1 once renamed to NAME.csv */
  int opened[NLOG];            /* 1 if this run writes the log */
  char *line;                  /* (linesz) one log line (or header), formatted before writing */
  size_t linesz;
  double *rec;                 /* (1 + nv x dim) one record of positions.bin: t (s), x (m) */
  size_t recn;                 /* doubles in rec (0: no positions.bin) */
  int frames_dir;              /* 1 once frames/ exists */
  long prev[6];                /* cumulative counters at the previous log line (see counters) */
  double prev_time_step;       /* cumulative step wall time at the previous log line, s */
  int nframe, frame_cap;
  double *frame_t;             /* (frame_cap) time of each complete frame, s */
  char path[PATHMAX], tmp[PATHMAX]; /* path scratch */
};

/* ------------------------------------------------------------ checked writes */

/* A FILE that remembers the errno of its first failed write; later writes are skipped. */
typedef struct writer {
  FILE *f;
  int err;
} writer;

static void w_fail(writer *w) {
  if (!w->err) w->err = errno ? errno : EIO;
}

static void w_puts(writer *w, const char *s) {
  if (w->err) return;
  errno = 0;
  if (fputs(s, w->f) == EOF) w_fail(w);
}

__attribute__((format(printf, 2, 3))) static void w_printf(writer *w, const char *fmt, ...) {
  if (w->err) return;
  va_list ap;
  va_start(ap, fmt);
  errno = 0;
  if (vfprintf(w->f, fmt, ap) < 0) w_fail(w);
  va_end(ap);
}

/* The shortest of %.15g, %.16g, %.17g that reads back as exactly v (so 0.03 is written "0.03",
 * and every number still round-trips); "nan", "inf", "-inf" otherwise (pandas reads all). */
static int fmt_num(char *buf, size_t sz, double v) {
  if (isnan(v)) return snprintf(buf, sz, "nan");
  if (isinf(v)) return snprintf(buf, sz, v > 0 ? "inf" : "-inf");
  for (int prec = 15; prec < 17; prec++) {
    int n = snprintf(buf, sz, "%.*g", prec, v);
    if (strtod(buf, NULL) == v) return n;
  }
  return snprintf(buf, sz, "%.17g", v);
}

static void w_num(writer *w, double v, const char *after) {
  char buf[NUMSZ];
  fmt_num(buf, sizeof buf, v);
  w_puts(w, buf);
  w_puts(w, after);
}

static int join(char *buf, const char *dir, const char *name, char *err, size_t errsz) {
  int n = snprintf(buf, PATHMAX, "%s/%s", dir, name);
  if (n >= 0 && n < PATHMAX) return 0;
  sw_errf(err, errsz, "%s: path of %s is too long", dir, name);
  return -1;
}

static int tmp_open(writer *w, const char *tmp, char *err, size_t errsz) {
  w->err = 0;
  w->f = fopen(tmp, "w");
  if (w->f) return 0;
  sw_errf(err, errsz, "%s: cannot open for writing: %s", tmp, strerror(errno));
  return -1;
}

/* Flush and close w (the file tmp), then rename it to path.  On failure tmp is removed. */
static int tmp_commit(writer *w, const char *tmp, const char *path, char *err, size_t errsz) {
  errno = 0;
  if (!w->err && fflush(w->f) == EOF) w_fail(w);
  errno = 0;
  if (fclose(w->f) == EOF) w_fail(w);
  w->f = NULL;
  if (w->err) {
    sw_errf(err, errsz, "%s: cannot write: %s", tmp, strerror(w->err));
    remove(tmp);
    return -1;
  }
  if (rename(tmp, path) == 0) return 0;
  sw_errf(err, errsz, "%s: cannot rename to %s: %s", tmp, path, strerror(errno));
  remove(tmp);
  return -1;
}

/* ------------------------------------------------------------------ folder */

#define ELIDE 160 /* a path longer than 2 ELIDE bytes is shown as its ends around "..." */

/* p, or its first and last ELIDE bytes around "...", so that a message with a very long path
 * still fits an error buffer and ends with the reason. */
static const char *elide(const char *p, char buf[2 * ELIDE + 4]) {
  size_t n = strlen(p);
  if (n <= 2 * ELIDE) return p;
  memcpy(buf, p, ELIDE);
  memcpy(buf + ELIDE, "...", 3);
  memcpy(buf + ELIDE + 3, p + n - ELIDE, ELIDE + 1);
  return buf;
}

static int make_dir(const char *path, const char *dir, char *err, size_t errsz) {
  if (mkdir(path, 0777) == 0) return 0;
  int e = errno;
  struct stat st;
  if (e == EEXIST && stat(path, &st) == 0 && S_ISDIR(st.st_mode)) return 0;
  if (e == EEXIST) e = ENOTDIR;
  char b1[2 * ELIDE + 4], b2[2 * ELIDE + 4];
  sw_errf(err, errsz, "%s: cannot create the output folder: mkdir %s: %s", elide(dir, b1),
          elide(path, b2), strerror(e));
  return -1;
}

/* mkdir -p dir, then check that it can be written. */
static int make_dirs(const char *dir, char *scratch, char *err, size_t errsz) {
  snprintf(scratch, PATHMAX, "%s", dir);
  for (char *s = scratch + 1; *s; s++) {
    if (*s != '/') continue;
    *s = '\0';
    int rc = make_dir(scratch, dir, err, errsz);
    *s = '/';
    if (rc) return rc;
  }
  if (make_dir(scratch, dir, err, errsz)) return -1;
  if (access(dir, W_OK | X_OK) == 0) return 0;
  char b[2 * ELIDE + 4];
  sw_errf(err, errsz, "%s: the output folder is not writable: %s", elide(dir, b), strerror(errno));
  return -1;
}

static int remove_stale(const char *path, char *err, size_t errsz) {
  if (unlink(path) == 0 || errno == ENOENT) return 0;
  sw_errf(err, errsz, "%s: cannot remove the file of an earlier run: %s", path, strerror(errno));
  return -1;
}

static int ends_with(const char *s, const char *tail) {
  size_t n = strlen(s), k = strlen(tail);
  return n >= k && strcmp(s + n - k, tail) == 0;
}

/* Remove the frames (NAME.vtu, and unfinished NAME.vtu.tmp) of an earlier run (none when
 * there is no frames/ folder). */
static int remove_stale_frames(sw_output *o, char *err, size_t errsz) {
  if (join(o->tmp, o->dir, "frames", err, errsz)) return -1;
  DIR *dp = opendir(o->tmp);
  if (!dp && errno == ENOENT) return 0;
  if (!dp) {
    sw_errf(err, errsz, "%s: cannot list: %s", o->tmp, strerror(errno));
    return -1;
  }
  int rc = 0;
  for (;;) {
    errno = 0;
    struct dirent *e = readdir(dp);
    if (!e) {
      if (errno) rc = -1, sw_errf(err, errsz, "%s: cannot list: %s", o->tmp, strerror(errno));
      break;
    }
    if (!ends_with(e->d_name, ".vtu") && !ends_with(e->d_name, ".vtu.tmp")) continue;
    if (join(o->path, o->tmp, e->d_name, err, errsz) || remove_stale(o->path, err, errsz)) {
      rc = -1;
      break;
    }
  }
  closedir(dp);
  return rc;
}

/* Files of an earlier run in the same folder, so that results never mix.  tendons.csv and
 * positions.bin are included: they would otherwise survive next to a run without them. */
static int clean_folder(sw_output *o, char *err, size_t errsz) {
  static const char *const stale[] = {"tension.csv",      "energy.csv",    "tendons.csv",
                                      "summary.json",     "frames.pvd",    "summary.json.tmp",
                                      "frames.pvd.tmp",   "positions.bin", "positions.bin.part"};
  for (size_t i = 0; i < sizeof stale / sizeof stale[0]; i++)
    if (join(o->path, o->dir, stale[i], err, errsz) || remove_stale(o->path, err, errsz))
      return -1;
  return remove_stale_frames(o, err, errsz);
}

/* frames/ in the run folder (once). */
static int make_frames_dir(sw_output *o, char *err, size_t errsz) {
  if (o->frames_dir) return 0;
  if (join(o->path, o->dir, "frames", err, errsz)) return -1;
  if (make_dir(o->path, o->dir, err, errsz)) return -1;
  o->frames_dir = 1;
  return 0;
}

static int prepare_folder(sw_output *o, const sw_model *m, char *err, size_t errsz) {
  size_t n = strnlen(m->opt.out_dir, SW_PATHSZ);
  if (n == 0 || n == SW_PATHSZ) {
    sw_errf(err, errsz, "output folder: %s", n ? "path too long" : "no folder given");
    return -1;
  }
  memcpy(o->dir, m->opt.out_dir, n);
  while (n > 1 && o->dir[n - 1] == '/') n--;
  o->dir[n] = '\0';
  if (make_dirs(o->dir, o->tmp, err, errsz)) return -1;
  if (m->opt.frames_every >= 0.0 && make_frames_dir(o, err, errsz)) return -1;
  return clean_folder(o, err, errsz);
}

/* -------------------------------------------------------------------- logs */

/* Append a string to o->line (sized for the longest header and line, see output_alloc). */
static void line_str(sw_output *o, size_t *len, const char *s) {
  size_t n = strlen(s);
  if (*len + n + 2 > o->linesz) return; /* cannot happen */
  memcpy(o->line + *len, s, n + 1);
  *len += n;
}

/* Append a term name, replacing what would break a CSV header (separators, quotes, blanks). */
static void line_csv_name(sw_output *o, size_t *len, const char *name) {
  char buf[SW_NAMESZ];
  size_t n = strnlen(name, SW_NAMESZ - 1);
  for (size_t i = 0; i < n; i++) {
    unsigned char c = (unsigned char)name[i];
    buf[i] = (c <= ' ' || c == ',' || c == '"' || c == 0x7f) ? '_' : (char)c;
  }
  buf[n] = '\0';
  line_str(o, len, buf);
}

static void line_end(sw_output *o, size_t len);

/* The header of log k into o->line. */
static void log_header(sw_output *o, int k, const sw_model *m) {
  size_t len = 0;
  if (k == LOG_TENSION) {
    line_str(o, &len, "time,txy_max,txy_mean,txy_p95,stretch_u_max,stretch_v_max,shear_max");
  } else if (k == LOG_TENDONS) {
    line_str(o, &len, "time,tendon,length,delta,tension");
  } else {
    line_str(o, &len, "time,kinetic");
    for (int i = 0; i < m->nterm; i++) {
      line_str(o, &len, ",E_");
      line_csv_name(o, &len, m->term[i].name);
    }
    line_str(o, &len, ",potential,total,dt,steps,newton_iterations,factorizations,"
                      "force_evaluations,error_test_failures,linesearch_backtracks,step_wall_s");
    if (sw_damped(m)) line_str(o, &len, ",damping_power,dissipated");
    if (sw_actuated(m)) line_str(o, &len, ",actuation_power,work_in");
  }
  line_end(o, len);
}

/* Write n bytes of s to log k in one piece (write(2) again only after a short write).  On
 * failure the log's error is remembered and o->size[k] still counts only the whole lines. */
static int put_bytes(sw_output *o, int k, const char *s, size_t n, char *err, size_t errsz) {
  int e = o->werr[k];
  size_t done = 0;
  while (!e && done < n) {
    ssize_t w = write(o->log[k], s + done, n - done);
    if (w > 0) done += (size_t)w;
    else if (w < 0 && errno == EINTR) continue;
    else e = w < 0 ? errno : EIO;
  }
  if (!e) {
    o->size[k] += (off_t)n;
    return 0;
  }
  o->werr[k] = e;
  sw_errf(err, errsz, "%s/%s.part: cannot write: %s", o->dir, log_name[k], strerror(e));
  return -1;
}

/* Write o->line to log k (put_bytes). */
static int put_line(sw_output *o, int k, char *err, size_t errsz) {
  return put_bytes(o, k, o->line, strlen(o->line), err, errsz);
}

/* The header of positions.bin: magic, int32 nv, int32 dim (host byte order). */
static int put_positions_header(sw_output *o, const sw_model *m, char *err, size_t errsz) {
  char h[POS_HEADER];
  int32_t nv = m->nv, dim = m->dim;
  memcpy(h, POS_MAGIC, 8);
  memcpy(h + 8, &nv, 4);
  memcpy(h + 12, &dim, 4);
  return put_bytes(o, LOG_POSITIONS, h, sizeof h, err, errsz);
}

/* Cut log k back to its whole lines (o->size[k]) after a write that failed part-way. */
static void cut_log(sw_output *o, int k, off_t size) {
  o->size[k] = size;
  if (ftruncate(o->log[k], size) != 0 && !o->werr[k]) o->werr[k] = errno ? errno : EIO;
}

static int open_log(sw_output *o, int k, const sw_model *m, char *err, size_t errsz) {
  char name[32];
  snprintf(name, sizeof name, "%s.part", log_name[k]);
  if (join(o->path, o->dir, name, err, errsz)) return -1;
  /* O_APPEND: after a cut, the next line (if any) goes to the new end */
  o->log[k] = open(o->path, O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0666);
  if (o->log[k] < 0) {
    sw_errf(err, errsz, "%s: cannot open for writing: %s", o->path, strerror(errno));
    return -1;
  }
  o->size[k] = 0;
  o->opened[k] = 1;
  if (k == LOG_POSITIONS) {
    if (put_positions_header(o, m, err, errsz) == 0) return 0;
  } else {
    log_header(o, k, m);
    if (put_line(o, k, err, errsz) == 0) return 0;
  }
  cut_log(o, k, 0);
  return -1;
}

/* Append one field to o->line (a comma before all but the first). */
static void line_num(sw_output *o, size_t *len, double v) {
  if (*len + NUMSZ >= o->linesz) return; /* cannot happen: linesz is sized for every field */
  if (*len) o->line[(*len)++] = ',';
  *len += (size_t)fmt_num(o->line + *len, o->linesz - *len, v);
}

static void line_long(sw_output *o, size_t *len, long v) {
  if (*len + NUMSZ >= o->linesz) return;
  if (*len) o->line[(*len)++] = ',';
  *len += (size_t)snprintf(o->line + *len, o->linesz - *len, "%ld", v);
}

static void line_end(sw_output *o, size_t len) {
  o->line[len] = '\n';
  o->line[len + 1] = '\0';
}

/* ------------------------------------------------------------- statistics */

static double max_of(const double *a, int n) { /* NaN-propagating; 0 when n == 0 */
  if (n <= 0) return 0.0;
  double mx = a[0];
  for (int i = 1; i < n && !isnan(mx); i++)
    if (isnan(a[i]) || a[i] > mx) mx = a[i];
  return mx;
}

static double max_abs_of(const double *a, int n) { /* NaN-propagating; 0 when n == 0 */
  double mx = 0.0;
  for (int i = 0; i < n && !isnan(mx); i++)
    if (isnan(a[i]) || fabs(a[i]) > mx) mx = fabs(a[i]);
  return mx;
}

static double mean_of(const double *a, int n) {
  if (n <= 0) return 0.0;
  double s = 0.0;
  for (int i = 0; i < n; i++) s += a[i];
  return s / n;
}

static void swap(double *a, long i, long j) {
  double t = a[i];
  a[i] = a[j];
  a[j] = t;
}

static double median3(double a, double b, double c) {
  if (a > b) { double t = a; a = b; b = t; }
  if (b > c) b = c;
  return a > b ? a : b;
}

/* The k-th smallest (0-based) of a[0..n-1], n >= 1; reorders a.  Three-way partition, so many
 * equal values (a cloth at rest) cost O(n). */
static double select_kth(double *a, long n, long k) {
  long lo = 0, hi = n - 1;
  while (lo < hi) {
    double p = median3(a[lo], a[lo + (hi - lo) / 2], a[hi]);
    long lt = lo, i = lo, gt = hi;
    while (i <= gt) {
      if (a[i] < p) swap(a, lt++, i++);
      else if (a[i] > p) swap(a, i, gt--);
      else i++;
    }
    if (k < lt) hi = lt - 1;
    else if (k > gt) lo = gt + 1;
    else return p;
  }
  return a[lo];
}

/* Nearest-rank 95th percentile: the ceil(0.95 n)-th smallest.  scratch: (n) workspace. */
static double p95_of(const double *a, int n, double *scratch) {
  if (n <= 0) return 0.0;
  for (int i = 0; i < n; i++) {
    if (isnan(a[i])) return NAN;
    scratch[i] = a[i];
  }
  long rank = (95L * n + 99) / 100; /* exact ceil(95 n / 100), 1-based */
  return select_kth(scratch, n, rank - 1);
}

/* ------------------------------------------------------------------- steps */

static int step_tension(sw_output *o, const sw_model *m, const sw_data *d, char *err,
                        size_t errsz) {
  int nf = m->nf;
  /* d->scratch is the data's percentile workspace; sw_data is const here only because the
   * state itself is not changed. */
  double *scratch = d->scratch;
  size_t len = 0;
  line_num(o, &len, d->t);
  line_num(o, &len, max_of(d->txy, nf));
  line_num(o, &len, mean_of(d->txy, nf));
  line_num(o, &len, p95_of(d->txy, nf, scratch));
  line_num(o, &len, max_of(d->stretch_u, nf));
  line_num(o, &len, max_of(d->stretch_v, nf));
  line_num(o, &len, max_abs_of(d->shear, nf)); /* shear is signed; log its largest magnitude */
  line_end(o, len);
  return put_line(o, LOG_TENSION, err, errsz);
}

static int step_energy(sw_output *o, const sw_model *m, const sw_data *d, char *err,
                       size_t errsz) {
  double kin = sw_kinetic(m, d->v), pot = 0.0; /* J */
  size_t len = 0;
  line_num(o, &len, d->t);
  line_num(o, &len, kin);
  for (int k = 0; k < m->nterm; k++) {
    line_num(o, &len, d->term_energy[k]);
    pot += d->term_energy[k];
  }
  line_num(o, &len, pot);
  line_num(o, &len, kin + pot);
  line_num(o, &len, d->last_dt);
  /* what this line's interval cost: differences of the cumulative counters */
  const long now[6] = {d->nstep, d->nnewton, d->nfactor, d->nforce, d->nerrfail, d->nlinesearch};
  for (int k = 0; k < 6; k++) line_long(o, &len, now[k] - o->prev[k]);
  line_num(o, &len, d->time_step - o->prev_time_step);
  if (sw_damped(m)) {
    line_num(o, &len, d->damp_power); /* W */
    line_num(o, &len, d->dissipated); /* J */
  }
  if (sw_actuated(m)) {
    line_num(o, &len, d->actuation_power); /* W */
    line_num(o, &len, d->work_in);         /* J */
  }
  line_end(o, len);
  if (put_line(o, LOG_ENERGY, err, errsz)) return -1;
  for (int k = 0; k < 6; k++) o->prev[k] = now[k];
  o->prev_time_step = d->time_step;
  return 0;
}

/* One line per tendon (time, name, m, m, N), written in one piece. */
static int step_tendons(sw_output *o, const sw_model *m, const sw_data *d, char *err,
                        size_t errsz) {
  if (m->ntendon == 0) return 0;
  size_t len = 0;
  for (int k = 0; k < m->ntendon; k++) {
    len += (size_t)fmt_num(o->line + len, o->linesz - len, d->t); /* first field: no comma */
    o->line[len++] = ',';
    o->line[len] = '\0';
    line_csv_name(o, &len, m->tendon[k].name);
    line_num(o, &len, d->tendon_length[k]);
    line_num(o, &len, d->tendon_delta[k]);
    line_num(o, &len, d->tendon_tension[k]);
    o->line[len++] = '\n';
  }
  o->line[len] = '\0';
  return put_line(o, LOG_TENDONS, err, errsz);
}

/* One record of positions.bin: t and every vertex position, in one write. */
static int step_positions(sw_output *o, const sw_model *m, const sw_data *d, char *err,
                          size_t errsz) {
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  if (o->recn != 1 + nd) { /* cannot happen: rec is sized at open for this model */
    sw_errf(err, errsz, "output: positions.bin record of %zu values; expected %zu", o->recn,
            1 + nd);
    return -1;
  }
  o->rec[0] = d->t;                            /* s */
  memcpy(o->rec + 1, d->x, nd * sizeof *d->x); /* m */
  return put_bytes(o, LOG_POSITIONS, (const char *)o->rec, o->recn * sizeof *o->rec, err, errsz);
}

int sw_output_record(sw_output *o, const sw_model *m, const sw_data *d, int positions, char *err,
                     size_t errsz) {
  if (!o || o->log[LOG_TENSION] < 0 || o->log[LOG_ENERGY] < 0 ||
      (m->ntendon > 0 && o->log[LOG_TENDONS] < 0) || (positions && o->log[LOG_POSITIONS] < 0)) {
    sw_errf(err, errsz, "output: the logs are not open");
    return -1;
  }
  off_t before[NLOG];
  for (int k = 0; k < NLOG; k++) before[k] = o->size[k];
  if (step_tension(o, m, d, err, errsz) == 0 && step_energy(o, m, d, err, errsz) == 0 &&
      step_tendons(o, m, d, err, errsz) == 0 &&
      (!positions || step_positions(o, m, d, err, errsz) == 0))
    return 0;
  /* Failed part-way: every log ends at the previous step again, with whole lines only. */
  for (int k = 0; k < NLOG; k++)
    if (o->log[k] >= 0) cut_log(o, k, before[k]);
  return -1;
}

int sw_output_step(sw_output *o, const sw_model *m, const sw_data *d, char *err, size_t errsz) {
  return sw_output_record(o, m, d, 0, err, errsz);
}

/* ------------------------------------------------------------------ frames */

static void vtu_points(writer *w, const sw_model *m, const double *x) {
  w_puts(w, "      <Points>\n"
            "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
  for (int i = 0; i < m->nv; i++) {
    const double *p = x + (size_t)i * (size_t)m->dim;
    w_num(w, p[0], " ");
    w_num(w, p[1], " ");
    w_num(w, m->dim == 3 ? p[2] : 0.0, "\n"); /* m; z = 0 in 2D */
  }
  w_puts(w, "        </DataArray>\n      </Points>\n");
}

/* The faces as triangles, then each tendon as a polyline through its waypoints. */
static void vtu_cells(writer *w, const sw_model *m) {
  w_puts(w, "      <Cells>\n"
            "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
  for (int f = 0; f < m->nf; f++)
    w_printf(w, "%d %d %d\n", m->face[3 * f], m->face[3 * f + 1], m->face[3 * f + 2]);
  for (int k = 0; k < m->ntendon; k++)
    for (int i = 0; i < m->tendon[k].nway; i++)
      w_printf(w, "%d%s", m->tendon[k].way[i], i + 1 < m->tendon[k].nway ? " " : "\n");
  w_puts(w, "        </DataArray>\n"
            "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  long off = 0;
  for (int f = 0; f < m->nf; f++) w_printf(w, "%ld\n", off += 3);
  for (int k = 0; k < m->ntendon; k++) w_printf(w, "%ld\n", off += m->tendon[k].nway);
  w_puts(w, "        </DataArray>\n"
            "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
  for (int f = 0; f < m->nf; f++) w_puts(w, "5\n");          /* VTK_TRIANGLE */
  for (int k = 0; k < m->ntendon; k++) w_puts(w, "4\n");     /* VTK_POLY_LINE */
  w_puts(w, "        </DataArray>\n      </Cells>\n");
}

/* A cell array: a[0..n-1] on the faces (or 0 when a is NULL), then t[0..nt-1] on the tendon
 * polylines (or 0 when t is NULL). */
static void vtu_scalars(writer *w, const char *name, const double *a, int n, const double *t,
                        int nt) {
  w_printf(w, "        <DataArray type=\"Float64\" Name=\"%s\" format=\"ascii\">\n", name);
  for (int i = 0; i < n; i++) w_num(w, a ? a[i] : 0.0, "\n");
  for (int i = 0; i < nt; i++) w_num(w, t ? t[i] : 0.0, "\n");
  w_puts(w, "        </DataArray>\n");
}

static void vtu_cell_data(writer *w, const sw_model *m, const sw_data *d) {
  const int nf = m->nf, nt = m->ntendon;
  w_puts(w, "      <CellData Scalars=\"tension_xy\">\n");
  vtu_scalars(w, "tension_xy", d->txy, nf, NULL, nt);    /* N/m */
  vtu_scalars(w, "stretch_u", d->stretch_u, nf, NULL, nt);
  vtu_scalars(w, "stretch_v", d->stretch_v, nf, NULL, nt);
  vtu_scalars(w, "shear", d->shear, nf, NULL, nt);       /* rad */
  if (nt) vtu_scalars(w, "tendon_tension", NULL, nf, d->tendon_tension, nt); /* N */
  w_puts(w, "      </CellData>\n");
}

static void vtu_point_data(writer *w, const sw_model *m, const sw_data *d) {
  w_puts(w, "      <PointData Vectors=\"velocity\">\n"
            "        <DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" "
            "format=\"ascii\">\n");
  for (int i = 0; i < m->nv; i++) { /* m/s */
    const double *v = d->v + (size_t)i * (size_t)m->dim;
    w_num(w, v[0], " ");
    w_num(w, v[1], " ");
    w_num(w, m->dim == 3 ? v[2] : 0.0, "\n");
  }
  w_puts(w, "        </DataArray>\n"
            "        <DataArray type=\"UInt8\" Name=\"pinned\" format=\"ascii\">\n");
  for (int i = 0; i < m->nv; i++) w_puts(w, m->pinned && m->pinned[i] ? "1\n" : "0\n");
  w_puts(w, "        </DataArray>\n      </PointData>\n");
}

static void vtu_body(writer *w, const sw_model *m, const sw_data *d) {
  w_puts(w, "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
            "  <UnstructuredGrid>\n");
  w_printf(w, "    <Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n", m->nv,
           m->nf + m->ntendon);
  vtu_point_data(w, m, d);
  vtu_cell_data(w, m, d);
  vtu_points(w, m, d->x);
  vtu_cells(w, m);
  w_puts(w, "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
}

static int write_vtu(sw_output *o, const sw_model *m, const sw_data *d, char *err,
                     size_t errsz) {
  char name[64];
  if (make_frames_dir(o, err, errsz)) return -1;
  snprintf(name, sizeof name, "frames/frame_%06d.vtu.tmp", o->nframe);
  if (join(o->tmp, o->dir, name, err, errsz)) return -1;
  name[strlen(name) - 4] = '\0'; /* drop ".tmp" */
  if (join(o->path, o->dir, name, err, errsz)) return -1;
  writer w;
  if (tmp_open(&w, o->tmp, err, errsz)) return -1;
  vtu_body(&w, m, d);
  return tmp_commit(&w, o->tmp, o->path, err, errsz);
}

/* frames.pvd listing frames 0 .. o->nframe-1. */
static int write_pvd(sw_output *o, char *err, size_t errsz) {
  if (join(o->tmp, o->dir, "frames.pvd.tmp", err, errsz)) return -1;
  if (join(o->path, o->dir, "frames.pvd", err, errsz)) return -1;
  writer w;
  if (tmp_open(&w, o->tmp, err, errsz)) return -1;
  w_puts(&w, "<?xml version=\"1.0\"?>\n"
             "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
             "  <Collection>\n");
  for (int i = 0; i < o->nframe; i++) {
    w_puts(&w, "    <DataSet timestep=\"");
    w_num(&w, o->frame_t[i], "\"");
    w_printf(&w, " group=\"\" part=\"0\" file=\"frames/frame_%06d.vtu\"/>\n", i);
  }
  w_puts(&w, "  </Collection>\n</VTKFile>\n");
  return tmp_commit(&w, o->tmp, o->path, err, errsz);
}

static int grow_frames(sw_output *o, char *err, size_t errsz) {
  if (o->nframe < o->frame_cap) return 0;
  int cap = o->frame_cap < 4 ? 4 : 2 * o->frame_cap;
  double *t = sw_realloc(o->frame_t, (size_t)cap, sizeof *t);
  if (!t) {
    sw_errf(err, errsz, "%s: out of memory for the list of frames", o->dir);
    return -1;
  }
  o->frame_t = t;
  o->frame_cap = cap;
  return 0;
}

int sw_output_frame(sw_output *o, const sw_model *m, const sw_data *d, char *err, size_t errsz) {
  if (!o) {
    sw_errf(err, errsz, "output: not open");
    return -1;
  }
  if (grow_frames(o, err, errsz) || write_vtu(o, m, d, err, errsz)) return -1;
  o->frame_t[o->nframe++] = d->t;
  return write_pvd(o, err, errsz);
}

/* ---------------------------------------------------------------- summary */

/* Length of the well-formed UTF-8 sequence (RFC 3629) at s, of at most rem bytes; 0 if none. */
static int utf8_len(const unsigned char *s, size_t rem) {
  unsigned c = s[0], lo = 0x80, hi = 0xBF;
  int n;
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c >= 0xE0 && c <= 0xEF) n = 3, lo = c == 0xE0 ? 0xA0 : lo, hi = c == 0xED ? 0x9F : hi;
  else if (c >= 0xF0 && c <= 0xF4) n = 4, lo = c == 0xF0 ? 0x90 : lo, hi = c == 0xF4 ? 0x8F : hi;
  else return 0;
  if ((size_t)n > rem || s[1] < lo || s[1] > hi) return 0;
  for (int i = 2; i < n; i++)
    if (s[i] < 0x80 || s[i] > 0xBF) return 0;
  return n;
}

/* A JSON string of at most maxlen bytes of s: quotes, backslashes and control characters
 * escaped, ill-formed UTF-8 replaced by U+FFFD. */
static void w_json_str(writer *w, const char *s, size_t maxlen) {
  if (!s) {
    w_puts(w, "null");
    return;
  }
  const unsigned char *p = (const unsigned char *)s, *end = p + strnlen(s, maxlen);
  w_puts(w, "\"");
  while (p < end) {
    char buf[8];
    int n = utf8_len(p, (size_t)(end - p));
    if (n == 0) snprintf(buf, sizeof buf, "\\ufffd"), n = 1;
    else if (*p == '"' || *p == '\\') snprintf(buf, sizeof buf, "\\%c", *p);
    else if (*p < 0x20) snprintf(buf, sizeof buf, "\\u%04X", *p);
    else memcpy(buf, p, (size_t)n), buf[n] = '\0';
    w_puts(w, buf);
    p += n;
  }
  w_puts(w, "\"");
}

static void w_key(writer *w, const char *key) { w_printf(w, ",\n  \"%s\": ", key); }

static void w_json_num(writer *w, const char *key, double v) {
  w_key(w, key);
  char buf[NUMSZ];
  if (isfinite(v)) fmt_num(buf, sizeof buf, v), w_puts(w, buf);
  else w_puts(w, "null");
}

static void w_json_long(writer *w, const char *key, long v) {
  w_key(w, key);
  w_printf(w, "%ld", v);
}

static void summary_model(writer *w, const sw_model *m) {
  w_key(w, "method");
  w_json_str(w, m->opt.method, SW_NAMESZ);
  w_json_long(w, "dimension", m->dim);
  w_json_long(w, "vertices", m->nv);
  w_json_long(w, "faces", m->nf);
  w_json_long(w, "free_dofs", m->ndof);
  w_key(w, "terms");
  w_puts(w, "[");
  for (int k = 0; k < m->nterm; k++) {
    if (k) w_puts(w, ", ");
    w_json_str(w, m->term[k].name, SW_NAMESZ);
  }
  w_puts(w, "]");
  w_json_num(w, "dt", m->opt.dt);             /* s */
  w_json_num(w, "duration", m->opt.duration); /* s */
  w_json_num(w, "stiffness_scale", m->stiffness_scale > 0 ? m->stiffness_scale : 1.0);
  if (sw_method_adaptive(m->opt.method) == 1) {
    w_json_num(w, "rtol", m->opt.rtol);
    w_json_num(w, "atol", m->opt.atol);   /* m and m/s */
    w_json_long(w, "max_order", sw_max_order(m)); /* the order in use, automatic or not */
  }
}

/* Peak resident set size of the process so far, MiB (ru_maxrss is in KiB on Linux); 0 if
 * getrusage fails. */
static double max_rss_mb(void) {
  struct rusage ru;
  if (getrusage(RUSAGE_SELF, &ru) != 0) return 0.0;
  return (double)ru.ru_maxrss / 1024.0;
}

static void summary_counters(writer *w, const sw_model *m, const sw_data *d, double wall) {
  w_json_num(w, "time_reached", d->t);
  w_json_long(w, "steps", d->nstep);
  w_json_long(w, "newton_iterations", d->nnewton);
  w_json_long(w, "factorizations", d->nfactor);
  w_json_long(w, "assemblies", d->nassemble);
  w_json_long(w, "force_evaluations", d->nforce);
  w_json_long(w, "retries", d->nretry);
  w_json_long(w, "linesearch_backtracks", d->nlinesearch);
  w_json_long(w, "error_test_failures", d->nerrfail);
  w_json_long(w, "linear_setups", d->nsetup);
  if (sw_method_adaptive(m->opt.method) == 1) { /* steps at BDF order 1..5 */
    w_key(w, "steps_by_order");
    w_printf(w, "[%ld, %ld, %ld, %ld, %ld]", d->nstep_order[0], d->nstep_order[1],
             d->nstep_order[2], d->nstep_order[3], d->nstep_order[4]);
  }
  w_json_num(w, "time_assemble_s", d->time_assemble);
  w_json_num(w, "time_factor_s", d->time_factor);
  w_json_num(w, "time_solve_s", d->time_solve);
  w_json_num(w, "time_step_s", d->time_step);
  w_json_long(w, "factor_nnz", d->factor_nnz);
  w_json_num(w, "wall_time_s", wall);
  w_json_num(w, "max_rss_mb", max_rss_mb());
}

/* The files of the folder, relative to it, under their current names. */
static void summary_files(writer *w, const sw_output *o) {
  w_key(w, "files");
  w_puts(w, "[");
  for (int k = 0; k < NLOG; k++)
    if (o->opened[k])
      w_printf(w, "%s\"%s%s\"", k ? ", " : "", log_name[k], o->final[k] ? "" : ".part");
  if (o->nframe) w_puts(w, ", \"frames.pvd\"");
  for (int i = 0; i < o->nframe; i++) w_printf(w, ", \"frames/frame_%06d.vtu\"", i);
  w_puts(w, "]");
}

int sw_output_summary(sw_output *o, const sw_model *m, const sw_data *d, const char *status,
                      const char *message, double wall, char *err, size_t errsz) {
  static const sw_data not_started; /* zero counters for the summary written by open */
  if (!o) {
    sw_errf(err, errsz, "output: not open");
    return -1;
  }
  if (join(o->tmp, o->dir, "summary.json.tmp", err, errsz)) return -1;
  if (join(o->path, o->dir, "summary.json", err, errsz)) return -1;
  writer w;
  if (tmp_open(&w, o->tmp, err, errsz)) return -1;
  w_puts(&w, "{\n  \"scene\": ");
  w_json_str(&w, m->name, sizeof m->name);
  w_key(&w, "scene_file");
  w_json_str(&w, m->path, sizeof m->path);
  w_key(&w, "status");
  w_json_str(&w, status, SW_ERRSZ);
  w_key(&w, "message");
  w_json_str(&w, message, 4 * SW_ERRSZ);
  summary_model(&w, m);
  summary_counters(&w, m, d ? d : &not_started, wall);
  summary_files(&w, o);
  w_puts(&w, "\n}\n");
  return tmp_commit(&w, o->tmp, o->path, err, errsz);
}

/* ------------------------------------------------------------ open, close */

static void output_free(sw_output *o) {
  for (int k = 0; k < NLOG; k++)
    if (o->log[k] >= 0) close(o->log[k]);
  sw_free(o->line);
  sw_free(o->rec);
  sw_free(o->frame_t);
  sw_free(o);
}

static int output_alloc(sw_output *o, const sw_model *m, char *err, size_t errsz) {
  /* the energy line or header is the longest: at most NUMSZ per field, or a term name */
  o->linesz = ((size_t)m->nterm + 18) * (NUMSZ + SW_NAMESZ);
  size_t tendon_lines = (size_t)m->ntendon * (4 * NUMSZ + SW_NAMESZ + 4) + 64;
  if (tendon_lines > o->linesz) o->linesz = tendon_lines;
  o->line = sw_calloc(o->linesz, 1);
  int cap = 2; /* first and last frame */
  if (m->opt.frames_every > 0 && m->opt.duration > 0) {
    double n = m->opt.duration / m->opt.frames_every + 3;
    cap = n < 1 << 16 ? (int)n : 1 << 16; /* beyond that, sw_output_frame grows the list */
  }
  o->frame_t = sw_calloc((size_t)cap, sizeof(double));
  o->frame_cap = cap;
  if (m->opt.positions_every > 0) { /* one record, reused: a step allocates nothing */
    o->recn = 1 + (size_t)m->nv * (size_t)m->dim;
    o->rec = sw_calloc(o->recn, sizeof *o->rec);
  }
  if (o->line && o->frame_t && (o->rec || !o->recn)) return 0;
  sw_errf(err, errsz, "%s: out of memory for the output writers", m->opt.out_dir);
  return -1;
}

sw_output *sw_output_open(const sw_model *m, char *err, size_t errsz) {
  sw_output *o = sw_calloc(1, sizeof *o);
  if (!o) {
    sw_errf(err, errsz, "%s: out of memory for the output writers", m->opt.out_dir);
    return NULL;
  }
  for (int k = 0; k < NLOG; k++) o->log[k] = -1;
  if (output_alloc(o, m, err, errsz) || prepare_folder(o, m, err, errsz) ||
      open_log(o, LOG_TENSION, m, err, errsz) || open_log(o, LOG_ENERGY, m, err, errsz) ||
      (m->ntendon > 0 && open_log(o, LOG_TENDONS, m, err, errsz)) ||
      (m->opt.positions_every > 0 && open_log(o, LOG_POSITIONS, m, err, errsz)) ||
      sw_output_summary(o, m, NULL, "running", "", 0.0, err, errsz)) {
    output_free(o);
    return NULL;
  }
  return o;
}

/* Close log k and give it its final name; it keeps its .part name if anything failed. */
static int finish_log(sw_output *o, int k, char *err, size_t errsz) {
  int e = o->werr[k]; /* a write failed: the log keeps its .part name */
  if (close(o->log[k]) != 0 && !e) e = errno ? errno : EIO;
  o->log[k] = -1;
  char name[32];
  snprintf(name, sizeof name, "%s.part", log_name[k]);
  if (join(o->tmp, o->dir, name, err, errsz) || join(o->path, o->dir, log_name[k], err, errsz))
    return -1;
  if (e) {
    sw_errf(err, errsz, "%s: cannot write: %s", o->tmp, strerror(e));
    return -1;
  }
  if (rename(o->tmp, o->path)) {
    sw_errf(err, errsz, "%s: cannot rename to %s: %s", o->tmp, o->path, strerror(errno));
    return -1;
  }
  o->final[k] = 1;
  return 0;
}

int sw_output_close(sw_output *o, const sw_model *m, const sw_data *d, const char *status,
                    const char *message, double wall, char *err, size_t errsz) {
  if (!o) {
    sw_errf(err, errsz, "output: not open");
    return -1;
  }
  char logerr[SW_ERRSZ] = "", msg[3 * SW_ERRSZ];
  int rc = 0;
  for (int k = 0; k < NLOG; k++)
    if (o->log[k] >= 0 && finish_log(o, k, rc ? NULL : logerr, sizeof logerr)) rc = -1;
  if (rc) { /* the logs are incomplete: the run must not look like a success */
    int failed = status && strcmp(status, "failed") == 0 && message && *message;
    int said = failed && strstr(message, logerr); /* the run's message already says why */
    snprintf(msg, sizeof msg, "%s%s%s", failed ? message : "", failed && !said ? "; " : "",
             said ? "" : logerr);
    status = "failed";
    message = msg;
    sw_errf(err, errsz, "%s", logerr);
  }
  char sumerr[SW_ERRSZ] = "";
  if (sw_output_summary(o, m, d, status, message, wall, sumerr, sizeof sumerr) && !rc) {
    sw_errf(err, errsz, "%s", sumerr);
    rc = -1;
  }
  output_free(o);
  return rc;
}
