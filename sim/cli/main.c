/* main.c — the sinew command line, a thin client of libsinew's public API (sinew.h). */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>

#include "bench.h"
#include "cli.h"
#include "sinew.h"

static void usage(FILE *fp) {
  fprintf(fp,
          "usage: sinew run SCENE [options]        (sinew run --help)\n"
          "       sinew check SCENE [options]      (sinew check --help)\n"
          "       sinew inverse SCENE --targets FILE [--out SCENE_OUT]  (sinew inverse --help)\n"
          "       sinew bench SCENE [options]      (sinew bench --help)\n"
          "       sinew render RUN_DIR [options]   (sinew render --help)\n"
          "       sinew pattern import FILE.dxf [options]  (sinew pattern import --help)\n"
          "       sinew drape RUN_DIR [options]    (sinew drape --help)\n"
          "       sinew garment FILE.dxf [options] (sinew garment --help)\n"
          "       sinew --help | --version\n"
          "\n"
          "  Every option takes its value as --opt VALUE or --opt=VALUE.\n"
          "\n"
          "  run     simulate SCENE (YAML) headless and write its logs and frames to the output\n"
          "          folder (the scene's output.dir, or --out DIR): tension.csv, energy.csv,\n"
          "          summary.json, frames/*.vtu, frames/*.vtp and frames.pvd\n"
          "  check   validate SCENE and print the model it describes\n"
          "  inverse tendon tensions (N) that exert target forces at SCENE's initial positions,\n"
          "          and the rest lengths that give them\n"
          "  bench   every method and setting on SCENE, each its own run: errors against a\n"
          "          reference, costs, stability and scaling sweeps, CSV files and charts\n"
          "  render  pictures of a run folder: the tension XY map of each frame on the flat\n"
          "          pattern and the 3D shape, tendons with their tension, and an animation\n"
          "  pattern import  pattern pieces of an AAMA/ASTM D6673 DXF file meshed into an OBJ\n"
          "          (a group per piece, (u,v) in metres along the grain line) and a scene skeleton\n"
          "  drape   the drape coefficient and node count of a Cusick drape test run folder\n"
          "  garment a DXF pattern's pieces sewn automatically, arranged on the mannequin and\n"
          "          fitted by run; a summary of each size's fit\n"
          "\n"
          "  methods:");
  for (const char *const *n = sw_method_names(); *n; n++) fprintf(fp, " %s", *n);
  fprintf(fp, "\n");
}

static void usage_check(FILE *fp) {
  fprintf(fp,
          "usage: sinew check SCENE [--grid NXxNY] [--stiffness-scale S]\n"
          "\n"
          "Validate SCENE (YAML; errors as file:line:column) and print the model it describes:\n"
          "vertices, pins, faces, rest area, mass, free DOFs, panels, tendons, terms and the\n"
          "nonzeros of the system.  Exit 0 when the scene is valid, 1 when it is not, 2 on bad\n"
          "arguments.\n"
          "\n"
          "  --grid NXxNY    vertices of the scene's grid (replaces mesh.grid.vertices)\n"
          "  --stiffness-scale S\n"
          "                  multiply every elastic stiffness by S > 0\n");
}

static void usage_inverse(FILE *fp) {
  fprintf(fp,
          "usage: sinew inverse SCENE --targets FILE [--out SCENE_OUT]\n"
          "\n"
          "The tendon tensions (N) that exert the target forces of FILE (CSV: a header\n"
          "vertex,fx,fy or vertex,fx,fy,fz, then a line per vertex) at SCENE's initial\n"
          "positions, by non-negative least squares; the rest lengths that give them, written\n"
          "into a copy of SCENE; and a forward static check of that copy (docs/inverse.md).\n"
          "\n"
          "  --targets FILE  the target forces (required)\n"
          "  --out SCENE_OUT the scene written (default: <scene stem>_inverse.yaml beside FILE)\n"
          "\n"
          "Exit 0 when the check passes, 1 when the targets are unreachable or the check fails,\n"
          "2 on bad input.\n");
}

/* The defaults the help names are the code's: those of a scene that sets nothing. */
static void usage_run(FILE *fp) {
  sw_model *defaults = sw_model_new();
  if (!defaults) return;
  const sw_options *dflt = &defaults->opt;
  fprintf(fp,
          "usage: sinew run SCENE [--out DIR] [--method M] [--dt DT] [--duration T]\n"
          "                 [--rtol R] [--atol A] [--max-order N|auto] [--max-halvings N]\n"
          "                 [--threads N] [--quiet]\n"
          "                 [--frames-every S | --no-frames] [--frames-format F]\n"
          "                 [--positions-every S] [--grid NXxNY] [--stiffness-scale S]\n"
          "                 [--newton-tol V] [--newton-norm rms|max] [--hessian MODE]\n"
          "                 [--factorization auto|simplicial|supernodal]\n"
          "                 [--ordering auto|amd|metis|nesdis]\n"
          "                 [--bending-matrix exact|compact|auto]\n"
          "                 [--newton-reuse on|off|auto|step]\n"
          "       sinew run --resume DIR [--duration T] [--threads N] [--force] [--quiet]\n"
          "\n"
          "Simulate SCENE (YAML) headless and write its logs and frames to the output folder\n"
          "(docs/scenes.md).  Exit 0 on success, 1 when the scene or the run fails, 2 on bad\n"
          "arguments, 130 (143) when stopped by SIGINT (SIGTERM) after a step.  --resume DIR\n"
          "goes on with the run in DIR (interrupted, failed or ended) from its last frame or the\n"
          "state it stopped at, with its scene and options, to T if given, appending to its logs;\n"
          "it refuses a damaged restart.bin, and a scene, a file the scene reads or an option\n"
          "changed since the run unless --force is given (for a change that leaves the model as\n"
          "it was, such as an edited comment).\n"
          "\n"
          "  --out DIR       output folder (overrides output.dir)\n"
          "  --method M      integrator (overrides integrator.method); one of:\n");
  for (const char *const *n = sw_method_names(); *n; n++) {
    const char *sum = sw_method_summary(*n);
    fprintf(fp, "                    %-18s %s\n", *n, sum ? sum : "");
  }
  fprintf(fp,
          "  --dt DT         time step in s (overrides integrator.dt)\n"
          "  --duration T    simulated time in s (overrides duration)\n"
          "  --rtol R        relative tolerance of adaptive methods (overrides integrator.rtol)\n"
          "  --atol A        absolute tolerance of adaptive methods, m and m/s (integrator.atol)\n"
          "  --max-order N   largest BDF order 1..5 of adaptive methods, or auto (overrides\n"
          "                  integrator.max_order; auto: cvode 2 at rtol > 1e-4, else 5)\n"
          "  --max-halvings N  a failed step is retried with half the step at most N times\n"
          "                  (overrides integrator.max_halvings; 0: a failed step fails the run)\n"
          "  --newton-tol V  Newton's tolerance, m/s: a step converges when its update dx\n"
          "                  is at most V dt in the norm below (overrides integrator.newton.tol;\n"
          "                  e.g. 1e-9 for a reference run)\n"
          "  --newton-norm rms|max\n"
          "                  rms: mass-weighted RMS of dx, each coordinate at most 10 V dt;\n"
          "                  max: every coordinate (overrides integrator.newton.norm; default %s)\n"
          "  --hessian MODE  Newton's matrix: projected, exact, auto, abs or progressive\n"
          "                  (overrides integrator.hessian)\n"
          "  --newton-reuse on|off|auto|step\n"
          "                  on: each Newton direction by conjugate gradients preconditioned\n"
          "                  with the last factorisation; off: a factorisation per iteration;\n"
          "                  auto: on with a simplicial factorisation; step: a\n"
          "                  factorisation at each step's first iteration, CG on it at the\n"
          "                  later ones (overrides integrator.newton.reuse)\n"
          "  --factorization auto|simplicial|supernodal\n"
          "                  CHOLMOD's factorisation; auto: chosen from the matrix (overrides\n"
          "                  integrator.factorization)\n"
          "  --ordering auto|amd|metis|nesdis\n"
          "                  CHOLMOD's fill-reducing ordering; auto: the measured rule\n"
          "                  (overrides integrator.ordering)\n"
          "  --bending-matrix exact|compact|auto\n"
          "                  the quadratic and morley bending's part of Newton's matrix:\n"
          "                  exact, or compact (couplings beyond a face moved onto the\n"
          "                  diagonal; auto, the default: compact but for the static\n"
          "                  method and the optimisation fits; overrides\n"
          "                  integrator.bending_matrix)\n"
          "  --threads N     OpenBLAS threads for CHOLMOD (default: $OPENBLAS_NUM_THREADS, else 1)\n"
          "  --quiet         nothing printed when the run succeeds (no progress line, no\n"
          "                  summary); warnings and errors still go to stderr\n"
          "  --frames-every S\n"
          "                  s between VTU frames; 0: first and last only (overrides\n"
          "                  output.frames_every)\n"
          "  --no-frames     no VTU frames and no frames.pvd (a failed run still writes its last\n"
          "                  good state as a frame)\n"
          "  --frames-format binary|binary32|ascii\n"
          "                  frames zlib-compressed and exact, zlib-compressed in Float32, or\n"
          "                  ascii (overrides output.frames_format; default %s)\n"
          "  --positions-every S\n"
          "                  s between records of positions.bin (every vertex position, binary;\n"
          "                  docs/scenes.md); 0: no file (overrides output.positions_every)\n"
          "  --grid NXxNY    vertices of the scene's grid (replaces mesh.grid.vertices; e.g.\n"
          "                  512x512); vertex indices in the scene stay indices\n"
          "  --stiffness-scale S\n"
          "                  multiply every elastic stiffness (membrane, bending, tendons,\n"
          "                  tension XY's) by S > 0\n",
          sw_norm_names()[dflt->newton_norm], sw_frames_format_names()[dflt->frames_format]);
  sw_model_free(defaults);
}

/* --grid NXxNY: two integers >= 2. */
static int parse_grid(const char *s, int grid[2]) {
  char *end;
  errno = 0;
  long nx = strtol(s, &end, 10), ny = 0;
  int ok = end != s && (*end == 'x' || *end == 'X');
  if (ok) {
    const char *p = end + 1;
    ny = strtol(p, &end, 10);
    ok = end != p && !*end && !errno && nx >= 2 && ny >= 2 && nx <= 1L << 30 && ny <= 1L << 30;
  }
  if (!ok)
    return fprintf(stderr, "sinew: --grid expects NXxNY, two integers >= 2 (e.g. 512x512), got "
                   "'%s'\n", s), -1;
  grid[0] = (int)nx;
  grid[1] = (int)ny;
  return 0;
}

/* --grid and --stiffness-scale (run and check): 1 if argv[*i] was one (*i moved past its value),
 * 0 if not, -1 on a bad value. */
static int cli_choice(const char *opt, const char *s, const char *const *names, int *out);

static int parse_override(int argc, char **argv, int *i, sw_scene_overrides *ov) {
  const char *a = argv[*i];
  if (*i + 1 >= argc) return 0;
  if (!strcmp(a, "--grid")) return parse_grid(argv[++*i], ov->grid) ? -1 : 1;
  if (!strcmp(a, "--stiffness-scale"))
    return cli_number(a, argv[++*i], 0, &ov->stiffness_scale) ? -1 : 1;
  if (!strcmp(a, "--bending-matrix")) {
    int k = 0;
    if (cli_choice(a, argv[++*i], sw_bending_matrix_names(), &k)) return -1;
    ov->bending_matrix = k + 1;
    return 1;
  }
  return 0;
}

typedef struct cli {
  const char *scene, *out, *method;
  sw_scene_overrides ov;
  double dt, duration, rtol, atol;
  double frames_every, positions_every; /* s; < 0: not given */
  int quiet, threads, no_frames;
  int max_halvings;            /* < 0: not given */
  double newton_tol;           /* m/s; < 0: not given */
  int hessian, reuse, norm;    /* < 0: not given */
  int factor, ordering;        /* < 0: not given */
  int frames_format;           /* SW_FRAMES_*; < 0: not given */
  int max_order;               /* -1: not given; 0: auto */
} cli;

/* An index into a NULL-terminated list of names. */
static int cli_choice(const char *opt, const char *s, const char *const *names, int *out) {
  for (int k = 0; names[k]; k++)
    if (!strcmp(s, names[k])) return *out = k, 0;
  fprintf(stderr, "sinew: %s expects one of:", opt);
  for (int k = 0; names[k]; k++) fprintf(stderr, " %s", names[k]);
  fprintf(stderr, "; got '%s'\n", s);
  return -1;
}

static int parse_run_args(int argc, char **argv, cli *c) {
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    int has_val = i + 1 < argc, ov = parse_override(argc, argv, &i, &c->ov);
    if (ov < 0) return -1;
    if (ov) continue;
    if (!strcmp(a, "--quiet")) c->quiet = 1;
    else if (!strcmp(a, "--no-frames")) c->no_frames = 1;
    else if (!strcmp(a, "--frames-every") && has_val) {
      if (cli_number(a, argv[++i], 1, &c->frames_every)) return -1;
    } else if (!strcmp(a, "--frames-format") && has_val) {
      if (cli_choice(a, argv[++i], sw_frames_format_names(), &c->frames_format)) return -1;
    } else if (!strcmp(a, "--positions-every") && has_val) {
      if (cli_number(a, argv[++i], 1, &c->positions_every)) return -1;
    }
    else if (!strcmp(a, "--out") && has_val) {
      c->out = argv[++i];
      if (!*c->out || strlen(c->out) >= SW_PATHSZ)
        return fprintf(stderr, "sinew: --out expects a folder path of 1..%d bytes\n", SW_PATHSZ - 1),
               -1;
    }
    else if (!strcmp(a, "--method") && has_val) c->method = argv[++i];
    else if (!strcmp(a, "--dt") && has_val) {
      if (cli_number(a, argv[++i], 0, &c->dt)) return -1;
    } else if (!strcmp(a, "--duration") && has_val) {
      if (cli_number(a, argv[++i], 1, &c->duration)) return -1;
    } else if (!strcmp(a, "--rtol") && has_val) {
      if (cli_number(a, argv[++i], 0, &c->rtol)) return -1;
    } else if (!strcmp(a, "--atol") && has_val) {
      if (cli_number(a, argv[++i], 0, &c->atol)) return -1;
    } else if (!strcmp(a, "--max-order") && has_val) {
      const char *v = argv[++i];
      char *end;
      long q = strtol(v, &end, 10);
      if (!strcmp(v, "auto")) c->max_order = 0;
      else if (end != v && !*end && q >= 1 && q <= 5) c->max_order = (int)q;
      else return fprintf(stderr, "sinew: --max-order expects auto or an integer 1..5, got '%s'\n",
                          v), -1;
    } else if (!strcmp(a, "--max-halvings") && has_val) {
      if (cli_int(a, argv[++i], 0, 60, &c->max_halvings)) return -1;
    } else if (!strcmp(a, "--newton-tol") && has_val) {
      if (cli_number(a, argv[++i], 0, &c->newton_tol)) return -1;
    } else if (!strcmp(a, "--newton-norm") && has_val) {
      if (cli_choice(a, argv[++i], sw_norm_names(), &c->norm)) return -1;
    } else if (!strcmp(a, "--hessian") && has_val) {
      if (cli_choice(a, argv[++i], sw_hessian_names(), &c->hessian)) return -1;
    } else if (!strcmp(a, "--newton-reuse") && has_val) {
      static const char *const reuse[] = {"off", "on", "auto", "step", NULL};
      if (cli_choice(a, argv[++i], reuse, &c->reuse)) return -1;
    } else if (!strcmp(a, "--factorization") && has_val) {
      if (cli_choice(a, argv[++i], sw_factor_names(), &c->factor)) return -1;
    } else if (!strcmp(a, "--ordering") && has_val) {
      if (cli_choice(a, argv[++i], sw_ordering_names(), &c->ordering)) return -1;
    } else if (!strcmp(a, "--threads") && has_val) {
      if (cli_int(a, argv[++i], 1, 1024, &c->threads)) return -1;
    } else if (a[0] == '-' && a[1]) {
      fprintf(stderr, "sinew: unknown option or missing value: %s (see sinew run --help)\n", a);
      return -1;
    } else if (!c->scene) c->scene = a;
    else return fprintf(stderr, "sinew: more than one scene given: %s\n", a), -1;
  }
  if (!c->scene) return fprintf(stderr, "sinew: no scene file given (see sinew run --help)\n"), -1;
  if (c->no_frames && c->frames_every >= 0)
    return fprintf(stderr, "sinew: --no-frames and --frames-every exclude each other\n"), -1;
  if (c->method && !cli_known_method(c->method)) {
    fprintf(stderr, "sinew: unknown method '%s' (see sinew run --help)\n", c->method);
    return -1;
  }
  return 0;
}

/* SIGINT, SIGTERM: the run stops after its current step and closes its folder (status
 * "interrupted"); the handler is reset, so a second signal ends the process at once. */
static void on_signal(int sig) { sw_interrupt(sig); }

static void catch_stop_signals(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sa.sa_flags = SA_RESETHAND;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
}

static int finish_run(sw_model *m, int rc, const char *err, int quiet, int resumed);

/* A scene that could not be loaded: its message; 130 (143) when SIGINT (SIGTERM) stopped the
 * loading (nothing is written before the load), else 1. */
static int load_failed(const char *what, const char *err) {
  int sig = sw_interrupted();
  if (!sig) return fprintf(stderr, "sinew: %s%s\n", what, err), 1;
  fprintf(stderr, "sinew: stopped by %s while loading the scene: %s\nsinew: nothing written\n",
          sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal", err);
  return 128 + sig;
}

/* sinew run --resume DIR [--duration T] [--threads N] [--quiet]: the run in DIR goes on from
 * its restart.bin with its own scene and options (a longer duration if given). */
/* The start of the duration in the start message: a garment's duration counts from the end
 * of its fit stage (docs/garments.md). */
static const char *until_fit(const sw_model *m) { return m->fit.on ? "the fit's end + " : ""; }

static int cmd_resume(int argc, char **argv) {
  const char *dir = argv[3];
  double duration = -1.0;
  int quiet = 0, threads = 0, force = 0;
  for (int i = 4; i < argc; i++) {
    const char *a = argv[i];
    if (!strcmp(a, "--quiet")) quiet = 1;
    else if (!strcmp(a, "--force")) force = 1;
    else if (!strcmp(a, "--duration") && i + 1 < argc) {
      if (cli_number(a, argv[++i], 0, &duration)) return 2;
    } else if (!strcmp(a, "--threads") && i + 1 < argc) {
      if (cli_int(a, argv[++i], 1, 1024, &threads)) return 2;
    } else
      return fprintf(stderr, "sinew: with --resume only --duration, --threads, --force and --quiet are "
                     "taken (the run's own options go on): %s\n", a), 2;
  }
  char err[SW_ERRSZ], scene[SW_PATHSZ];
  sw_options opt;
  sw_scene_overrides ov;
  double t_from; /* s */
  if (strlen(dir) >= SW_PATHSZ ||
      sw_restart_options_ex(dir, scene, sizeof scene, &opt, &ov, &t_from, err, sizeof err))
    return fprintf(stderr, "sinew: cannot resume: %s\n", strlen(dir) >= SW_PATHSZ ? "path too long" : err), 1;
  catch_stop_signals(); /* loading a large mesh obstacle takes seconds */
  sw_model *m = sw_scene_load_ex(scene, &ov, err, sizeof err);
  if (!m) return load_failed("cannot resume: ", err);
  m->opt = opt;
  snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "%s", dir);
  if (duration >= 0) m->opt.duration = duration;
  if (threads > 0) m->opt.blas_threads = threads;
  if (!quiet)
    fprintf(stderr, "sinew: resuming %s in %s/ from t = %.9g s: %s, to t = %s%g s\n", m->name,
            dir, t_from, m->opt.method, until_fit(m), m->opt.duration);
  return finish_run(m, sw_resume_ex(m, !quiet, force, err, sizeof err), err, quiet, 1);
}

static int cmd_run(int argc, char **argv) {
  if (argc >= 4 && !strcmp(argv[2], "--resume")) return cmd_resume(argc, argv);
  cli c = {.dt = -1, .duration = -1, .frames_every = -1, .positions_every = -1,
           .max_halvings = -1, .newton_tol = -1, .hessian = -1, .reuse = -1, .norm = -1,
           .factor = -1, .ordering = -1, .max_order = -1, .frames_format = -1};
  if (parse_run_args(argc, argv, &c)) return 2;
  c.ov.method = c.method; /* before the terms are built: the bending matrix's auto reads it */
  char err[SW_ERRSZ];
  catch_stop_signals(); /* loading a large mesh obstacle takes seconds */
  sw_model *m = sw_scene_load_ex(c.scene, &c.ov, err, sizeof err);
  if (!m) return load_failed("", err);
  if (m->warning[0]) fprintf(stderr, "sinew: warning: %s\n", m->warning);
  if (c.out) snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "%s", c.out);
  if (c.method) snprintf(m->opt.method, sizeof m->opt.method, "%s", c.method);
  if (c.dt > 0) m->opt.dt = c.dt;
  if (c.duration >= 0) m->opt.duration = c.duration;
  if (c.threads > 0) m->opt.blas_threads = c.threads;
  if (c.max_halvings >= 0) m->opt.max_halvings = c.max_halvings;
  if (c.rtol > 0) m->opt.rtol = c.rtol;
  if (c.newton_tol > 0) m->opt.newton_tol = c.newton_tol;
  if (c.hessian >= 0) m->opt.hessian = c.hessian;
  if (c.norm >= 0) m->opt.newton_norm = c.norm;
  if (c.reuse >= 0) m->opt.newton_reuse = c.reuse;
  if (c.factor >= 0) m->opt.factorization = c.factor;
  if (c.ordering >= 0) m->opt.ordering = c.ordering;
  if (c.atol > 0) m->opt.atol = c.atol;
  if (c.max_order >= 0) m->opt.max_order = c.max_order;
  if (c.frames_every >= 0) m->opt.frames_every = c.frames_every;
  if (c.no_frames) m->opt.frames_every = -1.0; /* none */
  if (c.frames_format >= 0) m->opt.frames_format = c.frames_format;
  if (c.positions_every >= 0) m->opt.positions_every = c.positions_every;
  if (!c.quiet)
    fprintf(stderr, "sinew: %s: %d vertices, %d free DOFs, %s, dt = %g s, to t = %s%g s\n",
            m->name, m->nv, m->ndof, m->opt.method, m->opt.dt, until_fit(m), m->opt.duration);
  return finish_run(m, sw_run(m, !c.quiet, err, sizeof err), err, c.quiet, 0);
}

/* What a run (or a resumed run) left: its message, where the results are (not after a quiet
 * success); the exit code. */
static int finish_run(sw_model *m, int rc, const char *err, int quiet, int resumed) {
  if (rc == SW_INTERRUPTED) fprintf(stderr, "sinew: %s\n", err);
  else if (rc == SW_NOSTART && !resumed) /* err ends with what became of the folder */
    fprintf(stderr, "sinew: run not started: %s\n", err);
  else if (rc == SW_NOSTART) /* a resume refused: the folder untouched */
    fprintf(stderr, "sinew: run not started: %s\nsinew: nothing written; the files of an "
            "earlier run in %s/ are as they were\n", err, m->opt.out_dir);
  else if (rc) fprintf(stderr, "sinew: run failed: %s\n", err);
  struct stat st;
  if (rc != SW_NOSTART && !(quiet && rc == SW_OK) && stat(m->opt.out_dir, &st) == 0 &&
      S_ISDIR(st.st_mode))
    fprintf(stderr, "sinew: results in %s/ (summary.json, tension.csv, energy.csv%s%s%s)\n",
            m->opt.out_dir, m->ntendon ? ", tendons.csv" : "",
            m->opt.positions_every > 0 ? ", positions.bin" : "",
            m->opt.frames_every >= 0 ? ", frames.pvd" : "");
  sw_model_free(m);
  return rc == SW_INTERRUPTED ? 128 + sw_interrupted() : rc ? 1 : 0;
}

static int cmd_check(int argc, char **argv) {
  sw_scene_overrides ov = {{0, 0}, 0.0, 0, NULL};
  if (argc < 3 || argv[2][0] == '-') return usage_check(stderr), 2;
  for (int i = 3; i < argc; i++) {
    int rc = parse_override(argc, argv, &i, &ov);
    if (rc < 0) return 2;
    if (rc == 0)
      return fprintf(stderr, "sinew: unknown option or missing value: %s (see sinew check --help)\n",
                     argv[i]), 2;
  }
  char err[SW_ERRSZ];
  catch_stop_signals(); /* loading a large mesh obstacle takes seconds */
  sw_model *m = sw_scene_load_ex(argv[2], &ov, err, sizeof err);
  if (!m) return load_failed("", err);
  if (m->warning[0]) fprintf(stderr, "sinew: warning: %s\n", m->warning);
  sw_model_print(m, stdout);
  sw_model_free(m);
  return 0;
}

/* ------------------------------------------------------------------ inverse */

typedef struct inv_cli {
  const char *scene, *targets, *out;
  char out_default[SW_PATHSZ]; /* out when --out is not given */
} inv_cli;

static int parse_inverse_args(int argc, char **argv, inv_cli *c) {
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    int has_val = i + 1 < argc;
    if (!strcmp(a, "--targets") && has_val) c->targets = argv[++i];
    else if (!strcmp(a, "--out") && has_val) c->out = argv[++i];
    else if (a[0] == '-' && a[1])
      return fprintf(stderr, "sinew: unknown option or missing value: %s (see sinew inverse --help)\n",
                     a), -1;
    else if (!c->scene) c->scene = a;
    else return fprintf(stderr, "sinew: more than one scene given: %s\n", a), -1;
  }
  if (!c->scene) return fprintf(stderr, "sinew: no scene file given (see sinew inverse --help)\n"), -1;
  if (!c->targets) return fprintf(stderr, "sinew: inverse needs --targets FILE\n"), -1;
  if (c->out && (!*c->out || strlen(c->out) >= SW_PATHSZ))
    return fprintf(stderr, "sinew: --out expects a file path of 1..%d bytes\n", SW_PATHSZ - 1),
           -1;
  return 0;
}

/* <folder of the targets>/<scene stem>_inverse.yaml */
static int default_out(const inv_cli *c, char *out, size_t sz) {
  const char *slash = strrchr(c->targets, '/'), *base = strrchr(c->scene, '/');
  base = base ? base + 1 : c->scene;
  const char *dot = strrchr(base, '.');
  int stem = dot && dot != base ? (int)(dot - base) : (int)strlen(base);
  int dir = slash ? (int)(slash - c->targets) + 1 : 0;
  int n = snprintf(out, sz, "%.*s%.*s_inverse.yaml", dir, c->targets, stem, base);
  return n < 0 || (size_t)n >= sz ? -1 : 0;
}

static const char *law_name(int law) { return law == SW_LAW_SPRING ? "spring" : "cable"; }

static void print_tensions(const sw_model *m, const sw_inverse *inv) {
  printf("%-16s %-6s %12s %12s %12s %12s\n", "tendon", "law", "K (N/m)", "length (m)",
         "tension (N)", "rest (m)");
  for (int t = 0; t < m->ntendon; t++) {
    const sw_tendon *td = &m->tendon[t];
    printf("%-16s %-6s %12.6g %12.6g %12.6g %12.6g\n", td->name, law_name(td->law),
           td->stiffness, inv->length[t], inv->tau[t], inv->rest[t]);
  }
  printf("residual |A tau - f| = %.6g N of |f| = %.6g N (relative %.3g; tolerance %g), "
         "%d NNLS iterations\n", inv->residual, inv->fnorm,
         inv->fnorm > 0 ? inv->residual / inv->fnorm : 0.0, SW_INVERSE_RTOL, inv->iterations);
}

/* Tendons that cannot realise their tension: K = 0 (warned) and rest length < 0 (refused). */
static int check_rest(const sw_model *m, const sw_inverse *inv) {
  int bad = 0;
  for (int t = 0; t < m->ntendon; t++) {
    const sw_tendon *td = &m->tendon[t];
    if (!(td->stiffness > 0.0))
      fprintf(stderr, "sinew: warning: tendon %s has stiffness 0 and cannot pull: left out "
              "(tension 0, rest length unchanged)\n", td->name);
    else if (inv->rest[t] < 0.0)
      bad = 1, fprintf(stderr, "sinew: tendon %s needs tension %g N > K l = %g N: its rest "
                       "length would be %g m < 0; expected a stiffness of at least %g N/m\n",
                       td->name, inv->tau[t], td->stiffness * inv->length[t], inv->rest[t],
                       inv->tau[t] / inv->length[t]);
  }
  return bad;
}

static void print_check(const sw_inverse *inv) {
  double lmax = 0.0;
  for (int t = 0; t < inv->ntendon; t++) lmax = inv->length[t] > lmax ? inv->length[t] : lmax;
  printf("forward check: static solve %s; max |x* - x| = %.3g m (tolerance %.3g m); force "
         "error %.3g at x, %.3g at x* (tolerance %g): %s\n",
         inv->check_rc == 0 ? "converged" : "did NOT converge", inv->check_dx,
         SW_INVERSE_XTOL * (lmax > 0 ? lmax : 1.0), inv->check_ferr0, inv->check_ferr,
         SW_INVERSE_RTOL, inv->check_pass ? "passed" : "FAILED");
}

/* Solve, report, write the scene and check; the exit status. */
static int inverse_run(const inv_cli *c, const sw_model *m, const sw_targets *tg) {
  char err[SW_ERRSZ], out[SW_PATHSZ];
  sw_inverse inv;
  if (sw_inverse_solve(m, m->x0, tg, &inv, err, sizeof err))
    return fprintf(stderr, "sinew: %s\n", err), 1;
  print_tensions(m, &inv);
  int rc = check_rest(m, &inv) ? 1 : 0;
  if (!rc && !inv.reachable)
    printf("targets unreachable: the residual is above %g |f|; the tensions above are the "
           "least-squares answer with tau >= 0\n", SW_INVERSE_RTOL);
  if (!rc) snprintf(out, sizeof out, "%s", c->out);
  if (!rc && sw_scene_write_rest(c->scene, out, m, inv.rest, err, sizeof err))
    rc = 2, fprintf(stderr, "sinew: %s\n", err);
  if (!rc) printf("wrote %s\n", out);
  if (!rc && sw_inverse_check(m, m->x0, tg, &inv, err, sizeof err))
    rc = 1, fprintf(stderr, "sinew: %s\n", err);
  else if (!rc) print_check(&inv);
  if (!rc && (!inv.reachable || !inv.check_pass)) rc = 1;
  sw_inverse_free(&inv);
  return rc;
}

/* The output must not be an input: the same file (device and inode, so also through a
 * symlink, a hard link or another path) as the scene or the targets is refused. */
static int out_is_input(const inv_cli *c) {
  struct stat o, in;
  if (stat(c->out, &o)) return 0; /* a new file */
  const char *inputs[2] = {c->scene, c->targets}, *what[2] = {"scene", "targets file"};
  for (int k = 0; k < 2; k++)
    if (!stat(inputs[k], &in) && in.st_dev == o.st_dev && in.st_ino == o.st_ino)
      return fprintf(stderr, "sinew: --out %s is the %s %s; expected another file (the "
                     "inputs are never overwritten)\n", c->out, what[k], inputs[k]), 1;
  return 0;
}

static int cmd_inverse(int argc, char **argv) {
  inv_cli c = {0};
  if (parse_inverse_args(argc, argv, &c)) return 2;
  if (!c.out && default_out(&c, c.out_default, sizeof c.out_default))
    return fprintf(stderr, "sinew: the output path is too long; give --out\n"), 2;
  if (!c.out) c.out = c.out_default;
  if (out_is_input(&c)) return 2;
  char err[SW_ERRSZ];
  sw_model *m = sw_scene_load(c.scene, err, sizeof err);
  if (!m) return fprintf(stderr, "sinew: %s\n", err), 2;
  sw_targets tg;
  int rc = 0;
  if (m->ntendon == 0) rc = 2, fprintf(stderr, "sinew: %s has no tendons\n", c.scene);
  else if (sw_targets_read(c.targets, m, &tg, err, sizeof err))
    rc = 2, fprintf(stderr, "sinew: %s\n", err);
  else {
    rc = inverse_run(&c, m, &tg);
    sw_targets_free(&tg);
  }
  sw_model_free(m);
  return rc;
}

/* --help or -h among a subcommand's arguments. */
static int wants_help(int argc, char **argv) {
  for (int i = 2; i < argc; i++)
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) return 1;
  return 0;
}

/* Every "--opt=value" argument after the subcommand becomes "--opt" "value", so that both forms
 * work for every option (the parsers see the two-argument form).  NULL when out of memory. */
static char **split_equals(int *argc, char **argv) {
  char **out = malloc((2 * (size_t)*argc + 1) * sizeof *out);
  if (!out) return NULL;
  int n = 0;
  for (int i = 0; i < *argc; i++) {
    char *eq = i >= 2 && !strncmp(argv[i], "--", 2) ? strchr(argv[i], '=') : NULL;
    if (!eq || eq == argv[i] + 2) {
      out[n++] = argv[i];
      continue;
    }
    *eq = '\0'; /* argv's strings are ours to change (C11 5.1.2.2.1) */
    out[n++] = argv[i];
    out[n++] = eq + 1;
  }
  out[n] = NULL;
  *argc = n;
  return out;
}

static int dispatch(int argc, char **argv);

int main(int argc, char **argv) {
  char **args = split_equals(&argc, argv);
  if (!args) return fprintf(stderr, "sinew: out of memory\n"), 2;
  int rc = dispatch(argc, args);
  free(args);
  return rc;
}

static int dispatch(int argc, char **argv) {
  if (argc < 2) return usage(stderr), 2;
  const char *cmd = argv[1];
  if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) return usage(stdout), 0;
  if (!strcmp(cmd, "--version")) return printf("sinew %s\n", SW_VERSION), 0;
  if (!strcmp(cmd, "run")) return wants_help(argc, argv) ? usage_run(stdout), 0 : cmd_run(argc, argv);
  if (!strcmp(cmd, "check"))
    return wants_help(argc, argv) ? usage_check(stdout), 0 : cmd_check(argc, argv);
  if (!strcmp(cmd, "inverse"))
    return wants_help(argc, argv) ? usage_inverse(stdout), 0 : cmd_inverse(argc, argv);
  if (!strcmp(cmd, "render")) return cli_render(argc, argv);
  if (!strcmp(cmd, "pattern")) return cli_pattern(argc, argv);
  if (!strcmp(cmd, "drape")) return cli_drape(argc, argv);
  if (!strcmp(cmd, "garment")) return cli_garment(argc, argv);
  if (!strcmp(cmd, "bench")) return sw_bench_main(argc, argv);
  fprintf(stderr, "sinew: unknown command '%s' (see sinew --help)\n", cmd);
  return 2;
}
