/* csv.c — the CSV logs of a run (writer.h), one line per logged state:
 *   tension.csv  time, max/mean/p95 of tension XY, max warp/weft stretch, max shear
 *   energy.csv   time, kinetic and per-term energies, step size and per-step solver counts;
 *                damping power and dissipated energy; actuation power and work in
 *   tendons.csv  a scene with tendons only: per tendon time, name, length, delta, tension
 *   contact.csv  a scene with obstacles or self-contact only: time, contacts, smallest
 *                distance, total contact and friction force; self-contact pairs, gap, force
 *   seams.csv    a scene with seams only: per seam time, name, largest and mean gap, force,
 *                length ratio of its curves
 * Each is a log (file.c): NAME.part until the run closes, a line in one write(2).  Numbers are
 * the shortest that read back exactly; "nan", "inf", "-inf" as such. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact.h"
#include "terms.h"
#include "util.h"
#include "writer.h"

#define NUMSZ SW_OUT_NUMSZ

typedef struct csv_log {
  out_log log;           /* first: the log operations of file.c take the state as an out_log */
  char *line;            /* (linesz) one line (or header), formatted before writing */
  size_t linesz;
  long prev[7];          /* energy.csv: cumulative counters at the previous line */
  double prev_time_step; /* energy.csv: cumulative step wall time at the previous line, s */
} csv_log;

/* ------------------------------------------------------------------ lines */

/* Append a string to o->line (sized for the longest header and line, see csv_init). */
static void line_str(csv_log *o, size_t *len, const char *s) {
  size_t n = strlen(s);
  if (*len + n + 2 > o->linesz) return; /* cannot happen */
  memcpy(o->line + *len, s, n + 1);
  *len += n;
}

/* Append a term name, replacing what would break a CSV header (separators, quotes, blanks). */
static void line_csv_name(csv_log *o, size_t *len, const char *name) {
  char buf[SW_NAMESZ];
  size_t n = strnlen(name, SW_NAMESZ - 1);
  for (size_t i = 0; i < n; i++) {
    unsigned char c = (unsigned char)name[i];
    buf[i] = (c <= ' ' || c == ',' || c == '"' || c == 0x7f) ? '_' : (char)c;
  }
  buf[n] = '\0';
  line_str(o, len, buf);
}

/* Append one field to o->line (a comma before all but the first). */
static void line_num(csv_log *o, size_t *len, double v) {
  if (*len + NUMSZ >= o->linesz) return; /* cannot happen: linesz is sized for every field */
  if (*len) o->line[(*len)++] = ',';
  *len += (size_t)out_fmt_num(o->line + *len, o->linesz - *len, v);
}

static void line_long(csv_log *o, size_t *len, long v) {
  if (*len + NUMSZ >= o->linesz) return;
  if (*len) o->line[(*len)++] = ',';
  *len += (size_t)snprintf(o->line + *len, o->linesz - *len, "%ld", v);
}

/* Start a line of a per-item log (appended at *len): the time, then the item's name. */
static void line_time_name(csv_log *o, size_t *len, double t, const char *name) {
  *len += (size_t)out_fmt_num(o->line + *len, o->linesz - *len, t); /* first field: no comma */
  o->line[(*len)++] = ',';
  o->line[*len] = '\0';
  line_csv_name(o, len, name);
}

static void line_end(csv_log *o, size_t len) {
  o->line[len] = '\n';
  o->line[len + 1] = '\0';
}

/* Write o->line as the log's next line. */
static int put_line(csv_log *o, const sw_output *out, char *err, size_t errsz) {
  return out_log_put(&o->log, out, o->line, strlen(o->line), err, errsz);
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

/* ------------------------------------------------------------- tension.csv */

static int tension_open(void *self, sw_output *out, const sw_model *m, char *err,
                        size_t errsz) {
  (void)m;
  static const char head[] =
      "time,txy_max,txy_mean,txy_p95,stretch_u_max,stretch_v_max,shear_max\n";
  csv_log *o = self;
  return out_log_open(&o->log, "tension.csv", out, head, strlen(head), err, errsz);
}

static int tension_write(void *self, sw_output *out, const sw_model *m, const sw_data *d,
                         char *err, size_t errsz) {
  csv_log *o = self;
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
  return put_line(o, out, err, errsz);
}

/* -------------------------------------------------------------- energy.csv */

/* Whether energy.csv logs dissipation: damping, or contact friction. */
static int dissipates(const sw_model *m) {
  return sw_damped(m) || m->fit.on || sw_terms_dissipate(m);
}

static void energy_header(csv_log *o, const sw_model *m) {
  size_t len = 0;
  line_str(o, &len, "time,kinetic");
  for (int i = 0; i < m->nterm; i++) {
    line_str(o, &len, ",E_");
    line_csv_name(o, &len, m->term[i].name);
  }
  line_str(o, &len, ",potential,total,dt,steps,newton_iterations,factorizations,"
                    "force_evaluations,error_test_failures,linesearch_backtracks,cg_iterations,"
                    "step_wall_s");
  if (dissipates(m)) line_str(o, &len, ",damping_power,dissipated");
  if (sw_actuated(m)) line_str(o, &len, ",actuation_power,work_in");
  line_end(o, len);
}

static int energy_open(void *self, sw_output *out, const sw_model *m, char *err,
                       size_t errsz) {
  csv_log *o = self;
  energy_header(o, m);
  return out_log_open(&o->log, "energy.csv", out, o->line, strlen(o->line), err, errsz);
}

static int energy_write(void *self, sw_output *out, const sw_model *m, const sw_data *d,
                        char *err, size_t errsz) {
  csv_log *o = self;
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
  const long now[7] = {d->nstep,   d->nnewton,     d->nfactor, d->nforce,
                       d->nerrfail, d->nlinesearch, d->ncg};
  for (int k = 0; k < 7; k++) line_long(o, &len, now[k] - o->prev[k]);
  line_num(o, &len, d->time_step - o->prev_time_step);
  if (dissipates(m)) {
    line_num(o, &len, d->damp_power); /* W */
    line_num(o, &len, d->dissipated); /* J */
  }
  if (sw_actuated(m)) {
    line_num(o, &len, d->actuation_power); /* W */
    line_num(o, &len, d->work_in);         /* J */
  }
  line_end(o, len);
  if (put_line(o, out, err, errsz)) return -1;
  for (int k = 0; k < 7; k++) o->prev[k] = now[k];
  o->prev_time_step = d->time_step;
  return 0;
}

/* ------------------------------------------------------------- tendons.csv */

static int tendons_wanted(const sw_model *m) { return m->ntendon > 0; }

static int tendons_open(void *self, sw_output *out, const sw_model *m, char *err,
                        size_t errsz) {
  (void)m;
  static const char head[] = "time,tendon,length,delta,tension\n";
  csv_log *o = self;
  return out_log_open(&o->log, "tendons.csv", out, head, strlen(head), err, errsz);
}

/* One line per tendon (time, name, m, m, N), written in one piece. */
static int tendons_write(void *self, sw_output *out, const sw_model *m, const sw_data *d,
                         char *err, size_t errsz) {
  csv_log *o = self;
  size_t len = 0;
  for (int k = 0; k < m->ntendon; k++) {
    line_time_name(o, &len, d->t, m->tendon[k].name);
    line_num(o, &len, d->tendon_length[k]);
    line_num(o, &len, d->tendon_delta[k]);
    line_num(o, &len, d->tendon_tension[k]);
    o->line[len++] = '\n';
  }
  o->line[len] = '\0';
  return put_line(o, out, err, errsz);
}

/* ------------------------------------------------------------- contact.csv */

static int contact_wanted(const sw_model *m) { return m->nobstacle > 0 || sw_mesh_contact_on(m); }

static int contact_open(void *self, sw_output *out, const sw_model *m, char *err,
                        size_t errsz) {
  (void)m;
  static const char head[] = "time,contacts,min_distance,force_x,force_y,force_z,force,"
                             "friction_x,friction_y,friction_z,friction,self_contacts,"
                             "self_min_gap,self_force\n";
  csv_log *o = self;
  return out_log_open(&o->log, "contact.csv", out, head, strlen(head), err, errsz);
}

/* Time (s), vertex-obstacle pairs closer than dhat, the smallest distance (m), the total force
 * of the obstacles on the cloth and of friction, each with its magnitude (N); self-contact
 * pairs closer than dhat beyond the thickness, their smallest gap (m) and force (N). */
static int contact_write(void *self, sw_output *out, const sw_model *m, const sw_data *d,
                         char *err, size_t errsz) {
  (void)m;
  csv_log *o = self;
  size_t len = 0;
  line_num(o, &len, d->t);
  line_long(o, &len, d->contact_count);
  line_num(o, &len, d->contact_min);
  const double *f[2] = {d->contact_force, d->friction_force};
  for (int k = 0; k < 2; k++) {
    for (int a = 0; a < 3; a++) line_num(o, &len, f[k][a]);
    line_num(o, &len, sqrt(f[k][0] * f[k][0] + f[k][1] * f[k][1] + f[k][2] * f[k][2]));
  }
  line_long(o, &len, d->self_count);
  line_num(o, &len, d->self_min);
  line_num(o, &len, d->self_force);
  line_end(o, len);
  return put_line(o, out, err, errsz);
}

/* ------------------------------------------------------------- seams.csv */

static int seams_wanted(const sw_model *m) { return m->nseam > 0; }

static int seams_open(void *self, sw_output *out, const sw_model *m, char *err, size_t errsz) {
  (void)m;
  static const char head[] = "time,seam,gap_max,gap_mean,force,length_ratio\n";
  csv_log *o = self;
  return out_log_open(&o->log, "seams.csv", out, head, strlen(head), err, errsz);
}

/* One line per seam (time s, name, largest and mean gap m, force N, curve length ratio b/a),
 * written in one piece. */
static int seams_write(void *self, sw_output *out, const sw_model *m, const sw_data *d,
                       char *err, size_t errsz) {
  csv_log *o = self;
  size_t len = 0;
  for (int k = 0; k < m->nseam; k++) {
    line_time_name(o, &len, d->t, m->seam[k].name);
    for (int q = 0; q < 4; q++) line_num(o, &len, d->seam_state[4 * k + q]);
    o->line[len++] = '\n';
  }
  o->line[len] = '\0';
  return put_line(o, out, err, errsz);
}

/* ---------------------------------------------------- operations of all four */

static int csv_init(void *self, const sw_model *m) {
  csv_log *o = self;
  /* the energy line or header is the longest: at most NUMSZ per field, or a term name */
  o->linesz = ((size_t)m->nterm + 18) * (NUMSZ + SW_NAMESZ);
  size_t tendon_lines = (size_t)m->ntendon * (4 * NUMSZ + SW_NAMESZ + 4) + 64;
  if (tendon_lines > o->linesz) o->linesz = tendon_lines;
  size_t seam_lines = (size_t)m->nseam * (5 * NUMSZ + SW_NAMESZ + 4) + 64;
  if (seam_lines > o->linesz) o->linesz = seam_lines;
  o->line = sw_calloc(o->linesz, 1);
  o->log.fd = -1;
  return o->line ? 0 : -1;
}

static void csv_free(void *self) {
  csv_log *o = self;
  out_log_free(&o->log);
  sw_free(o->line);
}

/* The log's size and energy.csv's counters at the previous line. */
static void csv_io(void *self, sw_io *io) {
  csv_log *o = self;
  out_log_io(&o->log, io);
  sw_io_bytes(io, o->prev, sizeof o->prev);
  sw_io_bytes(io, &o->prev_time_step, sizeof o->prev_time_step);
}

/* The four logs differ in name, open and write only. */
#define CSV_OPS(NAME)                                                                         \
  .name = #NAME ".csv",                                                                      \
  .event = SW_OUT_STEP, .size = sizeof(csv_log), .init = csv_init, .open = NAME##_open,      \
  .write = NAME##_write, .undo = out_log_undo, .close = out_log_close,                      \
  .files = out_log_files, .io = csv_io, .free = csv_free

const sw_out_ops sw_out_tension = {CSV_OPS(tension)};
const sw_out_ops sw_out_energy = {CSV_OPS(energy)};
const sw_out_ops sw_out_tendons = {CSV_OPS(tendons), .wanted = tendons_wanted};
const sw_out_ops sw_out_contact = {CSV_OPS(contact), .wanted = contact_wanted};
const sw_out_ops sw_out_seams = {CSV_OPS(seams), .wanted = seams_wanted};
