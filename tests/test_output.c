/* test_output.c — the run folder writers (sim/output/) on a hand-built 4-vertex, 2-face model.
 * No term operation is called: the fake term "bw98" has ops == NULL. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <zlib.h>

#include "harness.h"
#include "output.h"
#include "sinew.h"
#include "util.h"

/* A scene name that needs every kind of JSON escape: quote, backslash, tab, a byte that is
 * not UTF-8, and a well-formed non-ASCII character (kept as is). */
#define SCENE_NAME "we\"ird\\name\t\xff caf\xc3\xa9"
#define SCENE_JSON "\"scene\": \"we\\\"ird\\\\name\\u0009\\ufffd caf\xc3\xa9\""

typedef struct fixture {
  sw_model m;
  sw_data d;
  sw_term term;
  char root[64]; /* temporary folder of the test */
} fixture;

/* ----------------------------------------------------------------- helpers */

static char *slurp_in(const fixture *fx, const char *name) {
  return th_slurp_in(fx->m.opt.out_dir, name);
}

static int exists_in(const fixture *fx, const char *name) {
  return th_exists_in(fx->m.opt.out_dir, name);
}

static void touch_in(const fixture *fx, const char *name) {
  char path[SW_PATHSZ + 64];
  snprintf(path, sizeof path, "%s/%s", fx->m.opt.out_dir, name);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs("stale\n", f);
  fclose(f);
}

static int count_str(const char *s, const char *what) {
  int n = 0;
  for (const char *p = strstr(s, what); p; p = strstr(p + 1, what)) n++;
  return n;
}

static int count_char(const char *s, char c) {
  int n = 0;
  for (; *s; s++) n += *s == c;
  return n;
}

/* Line i (0-based) of s copied into buf, or 0 if there is none. */
static int line_at(const char *s, int i, char *buf, size_t sz) {
  for (; i > 0 && s; i--) {
    s = strchr(s, '\n');
    if (s) s++;
  }
  if (!s || !*s) return 0;
  size_t n = strcspn(s, "\n");
  if (n >= sz) n = sz - 1;
  memcpy(buf, s, n);
  buf[n] = '\0';
  return 1;
}

/* The numbers of a CSV line; returns how many. */
static int csv_fields(const char *line, double *out, int max) {
  int n = 0;
  const char *p = line;
  while (n < max) {
    char *end;
    out[n++] = strtod(p, &end);
    if (*end != ',') break;
    p = end + 1;
  }
  return n;
}

/* ----------------------------------------------------------------- fixture */

static void *zalloc(size_t n, size_t size) {
  void *p = sw_calloc(n, size);
  assert_non_null(p);
  return p;
}

static void build_model(fixture *fx, int nf) {
  sw_model *m = &fx->m;
  snprintf(m->name, sizeof m->name, "%s", SCENE_NAME);
  snprintf(m->path, sizeof m->path, "/scenes/a\"b.yaml");
  m->dim = 3;
  m->nv = 4;
  m->nf = nf;
  m->x0 = zalloc(12, sizeof(double));
  m->v0 = zalloc(12, sizeof(double));
  m->face = zalloc((size_t)nf * 3, sizeof(int));
  for (int f = 0; f < nf; f++) { /* two triangles of a unit square, repeated */
    static const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
    memcpy(m->face + 3 * f, tri[f % 2], sizeof tri[0]);
  }
  m->mass = zalloc(4, sizeof(double));
  m->pinned = zalloc(4, 1);
  m->dof = zalloc(12, sizeof(int));
  for (int i = 0; i < 4; i++) {
    m->mass[i] = 0.25 * (i + 1); /* kg */
    m->pinned[i] = i == 0;
    for (int a = 0; a < 3; a++) m->dof[3 * i + a] = i == 0 ? -1 : 3 * (i - 1) + a;
  }
  m->ndof = 9;
  snprintf(fx->term.name, sizeof fx->term.name, "bw98");
  m->nterm = 1;
  m->term = &fx->term;
  snprintf(m->opt.method, sizeof m->opt.method, "backward_euler");
  m->opt.dt = 0.01;
  m->opt.duration = 0.03;
  m->opt.frames_every = 0.02;
  snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "%s/run/nested", fx->root);
}

static void build_data(fixture *fx) {
  sw_data *d = &fx->d;
  size_t nf = (size_t)fx->m.nf;
  d->x = zalloc(12, sizeof(double));
  d->v = zalloc(12, sizeof(double));
  for (int i = 0; i < 4; i++) {
    d->x[3 * i] = i == 1 || i == 2;
    d->x[3 * i + 1] = i >= 2;
    for (int a = 0; a < 3 && i; a++) d->v[3 * i + a] = 0.1 * (a + 1) * i; /* m/s */
  }
  d->term_energy = zalloc(1, sizeof(double));
  d->txy = zalloc(nf, sizeof(double));
  d->stretch_u = zalloc(nf, sizeof(double));
  d->stretch_v = zalloc(nf, sizeof(double));
  d->shear = zalloc(nf, sizeof(double));
  d->scratch = zalloc(nf, sizeof(double));
}

static fixture *fixture_new(int nf) {
  fixture *fx = calloc(1, sizeof *fx);
  assert_non_null(fx);
  snprintf(fx->root, sizeof fx->root, "/tmp/sinew_test_output_XXXXXX");
  assert_non_null(mkdtemp(fx->root));
  build_model(fx, nf);
  build_data(fx);
  return fx;
}

static void fixture_free(fixture *fx) {
  sw_model *m = &fx->m;
  sw_data *d = &fx->d;
  void *p[] = {m->x0,         m->v0,     m->face,         m->mass,    m->pinned,   m->dof,
               d->x,          d->v,      d->term_energy,  d->txy,     d->stretch_u, d->stretch_v,
               d->shear,      d->scratch};
  for (size_t i = 0; i < sizeof p / sizeof p[0]; i++) sw_free(p[i]);
  th_remove_tree(fx->root);
  free(fx);
}

/* The state after accepted step s (1-based): known diagnostics and cumulative counters. */
static void fake_step(fixture *fx, int s) {
  sw_data *d = &fx->d;
  d->t = 0.01 * s; /* s, not exactly representable: checks %.17g */
  d->last_dt = 0.01;
  d->last_newton = s + 1;
  d->nforce += 3;
  d->nerrfail += s;         /* per step: 1, 2, 3 */
  d->nstep = s;
  d->nnewton += s + 1;      /* per step: 2, 3, 4 */
  d->nfactor += s + 1;      /* per step: 2, 3, 4 */
  d->nlinesearch += 2 * s;  /* per step: 2, 4, 6 */
  d->time_step += 0.5 * s;  /* per step: 0.5, 1, 1.5 s */
  d->factor_nnz = 100 * s;  /* the last factor's */
  d->term_energy[0] = 1.0 / 3.0 * s;
  for (int f = 0; f < fx->m.nf; f++) {
    d->txy[f] = f == 0 ? -1.5 * s : 4.25 * s; /* max 4.25 s, mean 1.375 s, p95 4.25 s */
    d->stretch_u[f] = 1.0 + 0.1 * f;
    d->stretch_v[f] = 1.0 + 0.2 * f;
    d->shear[f] = 0.05 * (f + 1);
  }
}

static int step_and_check(sw_output *o, fixture *fx, int s) {
  char err[SW_ERRSZ] = "";
  fake_step(fx, s);
  int rc = sw_output_step(o, &fx->m, &fx->d, err, sizeof err);
  if (rc) print_error("sw_output_step: %s\n", err);
  return rc;
}

/* ------------------------------------------------------------------- tests */

static void check_tension(const fixture *fx) {
  char *s = slurp_in(fx, "tension.csv"), line[512];
  assert_non_null(s);
  assert_int_equal(count_char(s, '\n'), 4);
  assert_true(line_at(s, 0, line, sizeof line));
  assert_string_equal(line, "time,txy_max,txy_mean,txy_p95,stretch_u_max,stretch_v_max,shear_max");
  for (int k = 1; k <= 3; k++) {
    double v[16];
    assert_true(line_at(s, k, line, sizeof line));
    assert_int_equal(csv_fields(line, v, 16), 7);
    assert_true(v[0] == 0.01 * k); /* exact round trip */
    assert_true(v[1] == 4.25 * k);
    assert_true(v[2] == (-1.5 * k + 4.25 * k) / 2);
    assert_true(v[3] == 4.25 * k);
    assert_true(v[4] == 1.0 + 0.1 && v[5] == 1.0 + 0.2 && v[6] == 0.05 * 2);
  }
  free(s);
}

static void check_energy(const fixture *fx) {
  char *s = slurp_in(fx, "energy.csv"), line[1024];
  assert_non_null(s);
  assert_int_equal(count_char(s, '\n'), 4);
  assert_true(line_at(s, 0, line, sizeof line));
  assert_string_equal(line, "time,kinetic,E_bw98,potential,total,dt,steps,newton_iterations,"
                            "factorizations,force_evaluations,error_test_failures,"
                            "linesearch_backtracks,cg_iterations,step_wall_s");
  double kin = sw_kinetic(&fx->m, fx->d.v); /* J; v is the same at every step */
  for (int k = 1; k <= 3; k++) {
    double v[16], e = 1.0 / 3.0 * k;
    assert_true(line_at(s, k, line, sizeof line));
    assert_int_equal(csv_fields(line, v, 16), 14);
    assert_true(v[0] == 0.01 * k && v[1] == kin && v[2] == e && v[3] == e && v[4] == kin + e);
    assert_true(v[5] == 0.01 && v[6] == 1 && v[7] == k + 1 && v[8] == k + 1 && v[9] == 3);
    assert_true(v[10] == k && v[11] == 2 * k && v[12] == 0 && v[13] == 0.5 * k);
  }
  free(s);
}

static void check_summary_ok(const fixture *fx) {
  char *s = slurp_in(fx, "summary.json");
  assert_non_null(s);
  assert_non_null(strstr(s, "\"status\": \"ok\""));
  assert_non_null(strstr(s, SCENE_JSON));
  assert_non_null(strstr(s, "\"scene_file\": \"/scenes/a\\\"b.yaml\""));
  assert_non_null(strstr(s, "\"terms\": [\"bw98\"]"));
  assert_non_null(strstr(s, "\"steps\": 3"));
  assert_non_null(strstr(s, "\"factorizations\": 9"));
  assert_non_null(strstr(s, "\"dt\": 0.01"));
  assert_non_null(strstr(s, "\"wall_time_s\": null")); /* non-finite wall time */
  assert_non_null(strstr(s, "\"time_step_s\": 3,"));    /* 0.5 + 1 + 1.5 s */
  assert_non_null(strstr(s, "\"factor_nnz\": 300,"));
  const char *rss = strstr(s, "\"max_rss_mb\": ");
  assert_non_null(rss);
  double mb = strtod(rss + strlen("\"max_rss_mb\": "), NULL);
  assert_true(mb > 0.5 && mb < 1e5); /* MiB: this test program, well above 0.5 MiB */
  assert_non_null(strstr(s, "\"tension.csv\", \"energy.csv\", \"frames.pvd\", "
                            "\"frames/frame_000000.vtu\", \"frames/frame_000001.vtu\"]"));
  assert_null(strstr(s, ".part"));
  assert_int_equal(count_char(s, '{'), count_char(s, '}'));
  assert_int_equal(count_char(s, '['), count_char(s, ']'));
  assert_int_equal(s[0], '{');
  assert_string_equal(s + strlen(s) - 2, "}\n");
  free(s);
}

static void check_frames(const fixture *fx) {
  char *pvd = slurp_in(fx, "frames.pvd");
  assert_non_null(pvd);
  assert_non_null(strstr(pvd, "<VTKFile type=\"Collection\""));
  assert_int_equal(count_str(pvd, "<DataSet "), 2);
  assert_non_null(strstr(pvd, "timestep=\"0.01\" group=\"\" part=\"0\" name=\"cloth\" "
                              "file=\"frames/frame_000000.vtu\"/>"));
  assert_null(strstr(pvd, "tendons")); /* a scene without tendons */
  assert_non_null(strstr(pvd, "file=\"frames/frame_000001.vtu\""));
  free(pvd);
  char *vtu = slurp_in(fx, "frames/frame_000001.vtu");
  assert_non_null(vtu);
  assert_non_null(strstr(vtu, "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
                              "byte_order=\"LittleEndian\">"));
  assert_non_null(strstr(vtu, "NumberOfPoints=\"4\" NumberOfCells=\"2\""));
  assert_non_null(strstr(vtu, "ascii\">\n0\n1\n2\n0\n2\n3\n")); /* connectivity */
  assert_non_null(strstr(vtu, "ascii\">\n3\n6\n"));    /* offsets */
  assert_non_null(strstr(vtu, "ascii\">\n5\n5\n"));    /* types */
  assert_non_null(strstr(vtu, "Name=\"pinned\" format=\"ascii\">\n1\n0\n0\n0\n"));
  assert_non_null(strstr(vtu, "Name=\"tension_xy\" format=\"ascii\">\n-3\n8.5\n"));
  const char *names[] = {"stretch_u", "stretch_v", "shear", "velocity"};
  for (int i = 0; i < 4; i++) assert_non_null(strstr(vtu, names[i]));
  assert_int_equal(count_str(vtu, "<DataArray"), count_str(vtu, "</DataArray>"));
  free(vtu);
  assert_false(exists_in(fx, "frames/frame_000002.vtu"));
  assert_false(exists_in(fx, "frames/frame_000000.vtu.tmp"));
  assert_false(exists_in(fx, "frames.pvd.tmp"));
}

/* Open (creating nested folders), 3 steps, 2 frames (ascii), close "ok". */
static void test_full_run(void **state) {
  (void)state;
  fixture *fx = fixture_new(2);
  fx->m.opt.frames_format = SW_FRAMES_ASCII;
  char err[SW_ERRSZ] = "";
  sw_output *o = sw_output_open(&fx->m, err, sizeof err);
  assert_non_null(o);
  for (int s = 1; s <= 3; s++) {
    assert_int_equal(step_and_check(o, fx, s), 0);
    if (s <= 2) assert_int_equal(sw_output_frame(o, &fx->m, &fx->d, err, sizeof err), 0);
  }
  assert_int_equal(sw_output_close(o, &fx->m, &fx->d, "ok", "", INFINITY, err, sizeof err), 0);
  check_tension(fx);
  check_energy(fx);
  check_summary_ok(fx);
  check_frames(fx);
  const char *gone[] = {"tension.csv.part", "energy.csv.part", "summary.json.tmp"};
  for (int i = 0; i < 3; i++) assert_false(exists_in(fx, gone[i]));
  fixture_free(fx);
}

/* --------------------------------------------------------- binary frames */

/* The bytes of the appended array `name` of a binary frame (vtu, n bytes in all), read as VTK
 * reads them: the offset after the '_' marker, the UInt64 header [blocks, block size, last
 * partial block, compressed sizes], each block through zlib.  Their number in *len. */
static unsigned char *appended_array(const char *vtu, size_t n, const char *name, size_t *len) {
  char key[96];
  snprintf(key, sizeof key, "Name=\"%s\"", name);
  const char *a = strstr(vtu, key), *app = strstr(vtu, "<AppendedData encoding=\"raw\">");
  assert_non_null(a);
  assert_non_null(app);
  const char *off = strstr(a, "format=\"appended\" offset=\"");
  assert_true(off && off < strchr(a, '>'));
  const unsigned char *blob = (const unsigned char *)strchr(app, '_') + 1;
  blob += strtoull(off + strlen("format=\"appended\" offset=\""), NULL, 10);
  uint64_t h[3];
  memcpy(h, blob, sizeof h);
  assert_true(h[1] == 32768);
  size_t total = h[0] ? (h[0] - 1) * h[1] + (h[2] ? h[2] : h[1]) : 0, done = 0;
  unsigned char *out = malloc(total + 1);
  assert_non_null(out);
  const unsigned char *z = blob + 8 * (3 + h[0]);
  for (uint64_t b = 0; b < h[0]; b++) {
    uint64_t zs;
    memcpy(&zs, blob + 8 * (3 + b), 8);
    assert_true(z + zs <= (const unsigned char *)vtu + n);
    uLongf got = (uLongf)(total - done);
    assert_int_equal(uncompress(out + done, &got, z, (uLong)zs), Z_OK);
    done += got, z += zs;
  }
  assert_true(done == total);
  *len = total;
  return out;
}

/* The folder of fx opened and step 1 logged. */
static sw_output *open_and_step(fixture *fx) {
  char err[SW_ERRSZ] = "";
  sw_output *o = sw_output_open(&fx->m, err, sizeof err);
  assert_non_null(o);
  assert_int_equal(step_and_check(o, fx, 1), 0);
  return o;
}

/* Array `name` of the binary frame equals the n bytes at want, to the bit. */
static void check_array(const char *vtu, size_t n, const char *name, const void *want,
                        size_t bytes) {
  size_t len = 0;
  unsigned char *got = appended_array(vtu, n, name, &len);
  assert_int_equal(len, bytes);
  assert_memory_equal(got, want, bytes);
  free(got);
}

/* A binary frame (the default) decodes to the state it was written from, bit for bit: time,
 * positions, velocities, tension XY, connectivity, pins; ParaView's header. */
static void test_binary_frames(void **state) {
  (void)state;
  fixture *fx = fixture_new(2);
  char err[SW_ERRSZ] = "";
  sw_output *o = open_and_step(fx);
  assert_int_equal(sw_output_frame(o, &fx->m, &fx->d, err, sizeof err), 0);
  assert_int_equal(sw_output_close(o, &fx->m, &fx->d, "ok", "", 1.0, err, sizeof err), 0);
  char path[SW_PATHSZ + 64];
  snprintf(path, sizeof path, "%s/frames/frame_000000.vtu", fx->m.opt.out_dir);
  size_t n = 0;
  char *vtu = th_slurp_n(path, &n);
  assert_non_null(vtu);
  assert_non_null(strstr(vtu, "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                              "byte_order=\"LittleEndian\" header_type=\"UInt64\" "
                              "compressor=\"vtkZLibDataCompressor\">"));
  assert_string_equal(vtu + n - 11, "</VTKFile>\n");
  check_array(vtu, n, "TimeValue", &fx->d.t, sizeof(double));
  check_array(vtu, n, "Points", fx->d.x, 12 * sizeof(double));
  check_array(vtu, n, "velocity", fx->d.v, 12 * sizeof(double));
  check_array(vtu, n, "tension_xy", fx->d.txy, 2 * sizeof(double));
  check_array(vtu, n, "connectivity", fx->m.face, 6 * sizeof(int));
  check_array(vtu, n, "pinned", fx->m.pinned, 4);
  const int64_t offsets[2] = {3, 6};
  check_array(vtu, n, "offsets", offsets, sizeof offsets);
  free(vtu);
  fixture_free(fx);
}

/* A run that stops without close (killed) leaves .part logs and a "running" summary. */
static void test_killed_run(void **state) {
  (void)state;
  fixture *fx = fixture_new(2);
  char err[SW_ERRSZ] = "";
  sw_output *o = open_and_step(fx);
  assert_true(exists_in(fx, "tension.csv.part") && exists_in(fx, "energy.csv.part"));
  assert_false(exists_in(fx, "tension.csv") || exists_in(fx, "energy.csv"));
  char *part = slurp_in(fx, "tension.csv.part"), *sum = slurp_in(fx, "summary.json");
  assert_non_null(part);
  assert_non_null(sum);
  assert_int_equal(count_char(part, '\n'), 2); /* flushed: header + 1 line */
  assert_non_null(strstr(sum, "\"status\": \"running\""));
  assert_non_null(strstr(sum, "\"tension.csv.part\""));
  free(part);
  free(sum);
  /* close "failed": the logs up to the failure are kept under their final names */
  assert_int_equal(sw_output_close(o, &fx->m, &fx->d, "failed", "Newton \"diverged\"", 2.5, err,
                                   sizeof err), 0);
  sum = slurp_in(fx, "summary.json");
  assert_non_null(strstr(sum, "\"status\": \"failed\""));
  assert_non_null(strstr(sum, "\"message\": \"Newton \\\"diverged\\\"\""));
  assert_non_null(strstr(sum, "\"wall_time_s\": 2.5"));
  assert_true(exists_in(fx, "tension.csv") && !exists_in(fx, "tension.csv.part"));
  free(sum);
  fixture_free(fx);
}

/* An output folder below a regular file cannot be made: NULL and a message naming it. */
static void test_dir_under_file(void **state) {
  (void)state;
  fixture *fx = fixture_new(2);
  char file[256], err[SW_ERRSZ] = "";
  snprintf(file, sizeof file, "%s/plain", fx->root);
  FILE *f = fopen(file, "w");
  assert_non_null(f);
  fclose(f);
  snprintf(fx->m.opt.out_dir, sizeof fx->m.opt.out_dir, "%s/sub/run", file);
  assert_null(sw_output_open(&fx->m, err, sizeof err));
  assert_non_null(strstr(err, fx->m.opt.out_dir));
  assert_non_null(strstr(err, "Not a directory"));
  fixture_free(fx);
}

/* A read-only folder (meaningless for root, who may write anywhere). */
static void test_readonly_dir(void **state) {
  (void)state;
  if (geteuid() == 0) skip();
  fixture *fx = fixture_new(2);
  char err[SW_ERRSZ] = "";
  snprintf(fx->m.opt.out_dir, sizeof fx->m.opt.out_dir, "%s/ro", fx->root);
  assert_int_equal(mkdir(fx->m.opt.out_dir, 0555), 0);
  assert_null(sw_output_open(&fx->m, err, sizeof err));
  assert_non_null(strstr(err, fx->m.opt.out_dir));
  chmod(fx->m.opt.out_dir, 0755);
  fixture_free(fx);
}

static void write_in(const fixture *fx, const char *name, const char *text) {
  char path[SW_PATHSZ + 64];
  snprintf(path, sizeof path, "%s/%s", fx->m.opt.out_dir, name);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
}

/* The earlier run's files go, those its sinew.manifest names (and their .tmp / .part forms);
 * a user's files stay, a ParaView export among the frames too. */
static void test_stale_files(void **state) {
  (void)state;
  fixture *fx = fixture_new(2);
  char err[SW_ERRSZ] = "";
  snprintf(fx->m.opt.out_dir, sizeof fx->m.opt.out_dir, "%s/old", fx->root);
  assert_int_equal(mkdir(fx->m.opt.out_dir, 0755), 0);
  char frames[SW_PATHSZ + 16];
  snprintf(frames, sizeof frames, "%s/frames", fx->m.opt.out_dir);
  assert_int_equal(mkdir(frames, 0755), 0);
  const char *stale[] = {"tension.csv",  "energy.csv",  "summary.json",      "frames.pvd",
                         "frames/frame_000007.vtu", "frames/frame_000008.vtu.tmp",
                         "tendons.csv.part", "positions.bin"};
  for (int i = 0; i < 8; i++) touch_in(fx, stale[i]);
  write_in(fx, "sinew.manifest", "# sinew manifest 1\ntension.csv\nenergy.csv\nsummary.json\n"
           "frames.pvd\nframes/frame_000007.vtu\nframes/frame_000008.vtu\ntendons.csv\n"
           "positions.bin\n../notes.txt\n");
  touch_in(fx, "notes.txt");
  touch_in(fx, "frames/keep.png");
  touch_in(fx, "frames/export.vtu");
  sw_output *o = sw_output_open(&fx->m, err, sizeof err);
  assert_non_null(o);
  for (int i = 0; i < 8; i++)
    if (i != 2) assert_false(exists_in(fx, stale[i]));
  assert_true(exists_in(fx, "notes.txt") && exists_in(fx, "frames/keep.png") &&
              exists_in(fx, "frames/export.vtu"));
  char *sum = slurp_in(fx, "summary.json");
  assert_non_null(strstr(sum, "\"status\": \"running\""));
  free(sum);
  assert_int_equal(sw_output_close(o, &fx->m, &fx->d, "ok", NULL, 0.0, err, sizeof err), 0);
  sum = slurp_in(fx, "summary.json");
  assert_non_null(strstr(sum, "\"message\": null"));
  free(sum);
  char *man = slurp_in(fx, "sinew.manifest"); /* this run's files */
  assert_string_equal(man, "# sinew manifest 1\ntension.csv\nenergy.csv\nsummary.json\n");
  free(man);
  fixture_free(fx);
}

/* Files sinew did not write are never removed: without a manifest a positions.bin, a frame
 * under sinew's own name stops the run before it touches anything. */
static void test_foreign_files(void **state) {
  (void)state;
  fixture *fx = fixture_new(2);
  char err[SW_ERRSZ] = "";
  snprintf(fx->m.opt.out_dir, sizeof fx->m.opt.out_dir, "%s/mine", fx->root);
  assert_int_equal(mkdir(fx->m.opt.out_dir, 0755), 0);
  touch_in(fx, "positions.bin");
  sw_output *o = sw_output_open(&fx->m, err, sizeof err);
  assert_non_null(o);
  assert_int_equal(sw_output_close(o, &fx->m, &fx->d, "ok", NULL, 0.0, err, sizeof err), 0);
  assert_true(exists_in(fx, "positions.bin"));
  write_in(fx, "summary.json", "earlier\n"); /* frames/ was made by the run */
  touch_in(fx, "frames/frame_000003.vtu");
  assert_null(sw_output_open(&fx->m, err, sizeof err));
  assert_non_null(strstr(err, "frames/frame_000003.vtu: a frame file that no earlier sinew run"));
  char *sum = slurp_in(fx, "summary.json");
  assert_string_equal(sum, "earlier\n");
  free(sum);
  fixture_free(fx);
}

/* ------------------------------------------------------------ positions.bin */

/* positions.bin read back: nv, dim and the records (t, then nv x dim positions), malloc'ed. */
typedef struct positions {
  int nv, dim, nrec;
  double *rec; /* (nrec x (1 + nv dim)) */
} positions;

static positions read_positions(const char *dir, const char *name) {
  char path[SW_PATHSZ + 64];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "rb");
  if (!f) fail_msg("%s: cannot open", path);
  char magic[8];
  int32_t h[2];
  positions p = {0};
  assert_int_equal(fread(magic, 1, 8, f), 8);
  assert_memory_equal(magic, "SWPOS001", 8);
  assert_int_equal(fread(h, 4, 2, f), 2);
  p.nv = h[0];
  p.dim = h[1];
  assert_true(fseek(f, 0, SEEK_END) == 0);
  long size = ftell(f), recsz = 8L * (1 + (long)p.nv * p.dim);
  if ((size - 16) % recsz) fail_msg("%s: %ld bytes: not whole records of %ld", path, size, recsz);
  p.nrec = (int)((size - 16) / recsz);
  p.rec = malloc((size_t)(size - 16) + 8);
  assert_non_null(p.rec);
  assert_true(fseek(f, 16, SEEK_SET) == 0);
  assert_int_equal(fread(p.rec, (size_t)recsz, (size_t)p.nrec, f), (size_t)p.nrec);
  fclose(f);
  return p;
}

/* Records at the steps asked for, each the state of that step; the file is positions.bin.part
 * while the run goes and positions.bin, listed in summary.json, after close. */
static void test_positions_writer(void **state) {
  (void)state;
  fixture *fx = fixture_new(2);
  fx->m.opt.positions_every = 0.02;
  char err[SW_ERRSZ] = "";
  sw_output *o = sw_output_open(&fx->m, err, sizeof err);
  assert_non_null(o);
  for (int s = 1; s <= 3; s++) {
    fake_step(fx, s);
    for (int k = 0; k < 12; k++) fx->d.x[k] = 100.0 * s + k / 3.0; /* m */
    assert_int_equal(sw_output_record(o, &fx->m, &fx->d, s != 2, err, sizeof err), 0);
    if (s == 1) {
      assert_true(exists_in(fx, "positions.bin.part") && !exists_in(fx, "positions.bin"));
      char *sum = slurp_in(fx, "summary.json");
      assert_non_null(strstr(sum, "\"positions.bin.part\""));
      free(sum);
    }
  }
  assert_int_equal(sw_output_close(o, &fx->m, &fx->d, "ok", "", 1.0, err, sizeof err), 0);
  assert_false(exists_in(fx, "positions.bin.part"));
  positions p = read_positions(fx->m.opt.out_dir, "positions.bin");
  assert_int_equal(p.nv, 4);
  assert_int_equal(p.dim, 3);
  assert_int_equal(p.nrec, 2); /* steps 1 and 3 */
  for (int r = 0; r < 2; r++) {
    int s = r ? 3 : 1;
    const double *rec = p.rec + r * 13;
    assert_true(rec[0] == 0.01 * s);
    for (int k = 0; k < 12; k++) assert_true(rec[1 + k] == 100.0 * s + k / 3.0);
  }
  free(p.rec);
  char *sum = slurp_in(fx, "summary.json");
  assert_non_null(strstr(sum, "\"tension.csv\", \"energy.csv\", \"positions.bin\"]"));
  free(sum);
  check_tension(fx); /* the logs are unchanged by the records */
  fixture_free(fx);
}

/* Without positions_every there is no positions.bin, and a record cannot be asked for; a stale
 * positions.bin of an earlier run is removed. */
static void test_positions_off(void **state) {
  (void)state;
  fixture *fx = fixture_new(2);
  char err[SW_ERRSZ] = "";
  char parent[SW_PATHSZ];
  snprintf(parent, sizeof parent, "%s/run", fx->root);
  assert_int_equal(mkdir(parent, 0755), 0);
  assert_int_equal(mkdir(fx->m.opt.out_dir, 0755), 0);
  touch_in(fx, "positions.bin");
  touch_in(fx, "positions.bin.part");
  write_in(fx, "sinew.manifest", "# sinew manifest 1\npositions.bin\n");
  sw_output *o = sw_output_open(&fx->m, err, sizeof err);
  assert_non_null(o);
  assert_false(exists_in(fx, "positions.bin") || exists_in(fx, "positions.bin.part"));
  fake_step(fx, 1);
  assert_int_equal(sw_output_step(o, &fx->m, &fx->d, err, sizeof err), 0);
  assert_int_not_equal(sw_output_record(o, &fx->m, &fx->d, 1, err, sizeof err), 0);
  assert_non_null(strstr(err, "not open"));
  assert_int_equal(sw_output_close(o, &fx->m, &fx->d, "ok", "", 1.0, err, sizeof err), 0);
  assert_false(exists_in(fx, "positions.bin") || exists_in(fx, "positions.bin.part"));
  fixture_free(fx);
}

/* A whole run (sw_run) with positions every 0.03 s to 0.1 s at dt = 0.01 s: records at t = 0,
 * 0.03, 0.06, 0.09 and the final 0.1; the first is x0, pinned vertices included; the last is the
 * final frame's positions, exactly (the VTU numbers round-trip). */
static void test_positions_run(void **state) {
  (void)state;
  const double g[3] = {0.0, 0.0, -9.81};
  sw_model *m = th_grid_model(3, 5, 4, 0.4, 0.3, 0.1, 200.0, 10.0, g, 1);
  assert_non_null(m);
  char root[64] = "/tmp/sinew_test_positions_XXXXXX", err[SW_ERRSZ] = "";
  assert_non_null(mkdtemp(root));
  snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "%s/run", root);
  m->opt.dt = 0.01;
  m->opt.duration = 0.1;
  m->opt.frames_every = 0.0; /* first and last */
  m->opt.frames_format = SW_FRAMES_BINARY; /* exact, to compare with positions.bin */
  m->opt.positions_every = 0.03;
  if (sw_run(m, 0, err, sizeof err)) fail_msg("sw_run: %s", err);
  positions p = read_positions(m->opt.out_dir, "positions.bin");
  const int nd = m->nv * m->dim, rs = 1 + nd;
  assert_int_equal(p.nv, 20);
  assert_int_equal(p.dim, 3);
  assert_int_equal(p.nrec, 5);
  const double want_t[5] = {0.0, 0.03, 0.06, 0.09, 0.1};
  for (int r = 0; r < 5; r++) assert_float_equal(p.rec[r * rs], want_t[r], 1e-12);
  assert_memory_equal(p.rec + 1, m->x0, (size_t)nd * sizeof(double));
  /* the final frame's positions */
  char path[SW_PATHSZ + 64];
  snprintf(path, sizeof path, "%s/frames/frame_000001.vtu", m->opt.out_dir);
  size_t n = 0, len = 0;
  char *vtu = th_slurp_n(path, &n);
  assert_non_null(vtu);
  double *pts = (double *)appended_array(vtu, n, "Points", &len);
  assert_int_equal(len, (size_t)nd * sizeof(double));
  const double *last = p.rec + 4 * rs + 1;
  double moved = 0.0;
  for (int k = 0; k < nd; k++) {
    assert_true(pts[k] == last[k]);
    moved = fmax(moved, fabs(last[k] - m->x0[k]));
  }
  free(pts);
  assert_true(moved > 1e-3); /* the cloth fell: the records are not all x0 */
  for (int k = 0; k < nd; k++) /* pinned vertices stay */
    if (m->pinned[k / 3]) assert_true(last[k] == m->x0[k]);
  free(vtu);
  free(p.rec);
  snprintf(path, sizeof path, "%s/summary.json", m->opt.out_dir);
  char *sum = th_slurp(path);
  assert_non_null(sum);
  assert_non_null(strstr(sum, "\"energy.csv\", \"positions.bin\", \"frames.pvd\""));
  free(sum);
  th_remove_tree(root);
  sw_model_free(m);
}

/* Nearest-rank p95 on 20 shuffled values, on all-equal values, and on no faces at all. */
static void test_percentile(void **state) {
  (void)state;
  static const int perm[20] = {7, 19, 3, 12, 1, 20, 15, 9, 4, 18, 11, 2, 16, 6, 14, 8, 13, 5, 17, 10};
  fixture *fx = fixture_new(20);
  char err[SW_ERRSZ] = "", line[512];
  sw_output *o = sw_output_open(&fx->m, err, sizeof err);
  assert_non_null(o);
  for (int f = 0; f < 20; f++) fx->d.txy[f] = perm[f];
  assert_int_equal(sw_output_step(o, &fx->m, &fx->d, err, sizeof err), 0);
  for (int f = 0; f < 20; f++) assert_true(fx->d.txy[f] == perm[f]); /* txy untouched */
  for (int f = 0; f < 20; f++) fx->d.txy[f] = 2.5;
  assert_int_equal(sw_output_step(o, &fx->m, &fx->d, err, sizeof err), 0);
  fx->m.nf = 0;
  assert_int_equal(sw_output_step(o, &fx->m, &fx->d, err, sizeof err), 0);
  fx->m.nf = 20;
  assert_int_equal(sw_output_close(o, &fx->m, &fx->d, "ok", "", 0.0, err, sizeof err), 0);
  char *s = slurp_in(fx, "tension.csv");
  double v[8];
  assert_true(line_at(s, 1, line, sizeof line));
  assert_int_equal(csv_fields(line, v, 8), 7);
  assert_true(v[1] == 20 && v[2] == 10.5 && v[3] == 19);
  assert_true(line_at(s, 2, line, sizeof line));
  assert_int_equal(csv_fields(line, v, 8), 7);
  assert_true(v[1] == 2.5 && v[2] == 2.5 && v[3] == 2.5);
  assert_true(line_at(s, 3, line, sizeof line));
  assert_string_equal(line, "0,0,0,0,0,0,0");
  free(s);
  fixture_free(fx);
}

/* Each allocation of open failing in turn: NULL with a message, nothing leaked (without and
 * with the record buffer of positions.bin). */
static void test_alloc_failure(void **state) {
  (void)state;
  for (int pos = 0; pos < 2; pos++) {
    fixture *fx = fixture_new(2);
    fx->m.opt.positions_every = pos ? 0.01 : 0.0;
    char err[SW_ERRSZ];
    sw_output *o = NULL;
    for (long k = 1; !o && k < 100; k++) {
      err[0] = '\0';
      sw_alloc_fail_after(k);
      o = sw_output_open(&fx->m, err, sizeof err);
      sw_alloc_fail_after(0);
      if (!o) assert_non_null(strstr(err, "out of memory"));
    }
    assert_non_null(o);
    assert_int_equal(sw_output_close(o, &fx->m, &fx->d, "ok", "", 0.0, err, sizeof err), 0);
    fixture_free(fx);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_full_run),      cmocka_unit_test(test_killed_run),
      cmocka_unit_test(test_dir_under_file), cmocka_unit_test(test_readonly_dir),
      cmocka_unit_test(test_stale_files), cmocka_unit_test(test_foreign_files),   cmocka_unit_test(test_percentile),
      cmocka_unit_test(test_alloc_failure),
      cmocka_unit_test(test_positions_writer), cmocka_unit_test(test_positions_off),
      cmocka_unit_test(test_positions_run),   cmocka_unit_test(test_binary_frames),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
