/* output.c — the writers of a run's folder (output.h): the folder, and the formats it holds,
 * each behind the operations of writer.h.
 *
 * Folder layout (relative to m->opt.out_dir), in the order of the formats below:
 *   tension.csv    csv.c: time, max/mean/p95 of tension XY, max warp/weft stretch, max shear
 *   energy.csv     csv.c: time, kinetic and per-term energies, step size and solver counts
 *   tendons.csv    csv.c: a scene with tendons: time, tendon, length, delta, tension
 *   positions.bin  positions.c: with opt.positions_every > 0, every vertex position at sampled
 *                  times, binary
 *   frames.pvd     vtu.c: ParaView collection of the complete frames
 *   frames/frame_NNNNNN.vtu
 *   summary.json   summary.c: scene, method, counters, wall time, status, the files above
 *   sinew.lock     lock.c: the id of the process writing the folder, while it runs
 *   sinew.manifest manifest.c: the files this run wrote (the next run removes those only)
 * Logs (and positions.bin) live as NAME.part until sw_output_close; every other file is written
 * to NAME.tmp and renamed, so a reader never sees a half-written file under a final name.  A log
 * line (a record of positions.bin) goes out in one write(2) (no stdio buffer), so a killed run
 * leaves whole lines; a logged state whose lines fail part-way (disk full, file size limit) is
 * taken back from every log, which then ends at the previous one.  Every write is checked;
 * errors read "PATH: what failed: strerror(errno)".  sw_output_record allocates nothing.
 */
#include "output.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util.h"
#include "writer.h"

/* Every format, in the order of the summary's file list (the summary last: it lists the others'
 * files as they are when it is written); the lock first, so that its prepare refuses a folder
 * in use before any other removes a file. */
static const sw_out_ops *const formats[] = {&sw_out_lock,      &sw_out_tension, &sw_out_energy,
                                            &sw_out_tendons,   &sw_out_contact,
                                            &sw_out_seams,     &sw_out_seam_defs,
                                            &sw_out_positions, &sw_out_vtu,
                                            &sw_out_summary};
#define NFORMAT ((int)(sizeof formats / sizeof formats[0]))

/* ------------------------------------------------------------ the folder */

/* The folder made, locked (formats[0], the lock's prepare), a folder of earlier files left by
 * a stopped run dealt with (aside.c), the earlier manifest read, and every other format's
 * prepare passed; nothing of an earlier run touched. */
static int take_folder(sw_output *o, const sw_model *m, char *err, size_t errsz) {
  size_t n = strnlen(m->opt.out_dir, SW_PATHSZ);
  if (n == 0 || n == SW_PATHSZ) {
    sw_errf(err, errsz, "output folder: %s", n ? "path too long" : "no folder given");
    return -1;
  }
  memcpy(o->dir, m->opt.out_dir, n);
  while (n > 1 && o->dir[n - 1] == '/') n--;
  o->dir[n] = '\0';
  struct stat st;
  o->made_dir = lstat(o->dir, &st) != 0;
  if (out_make_dirs(o->dir, o->tmp, err, errsz)) return -1;
  for (int k = 0; k < o->nw; k++) {
    const sw_out_ops *f = o->w[k].ops;
    if (f->prepare && f->prepare(o->w[k].self, o, m, err, errsz)) return -1;
    if (k == 0 && (out_aside_recover(o, err, errsz) || out_manifest_read(o, err, errsz)))
      return -1;
    if (k == 0) o->earlier = o->old != NULL;
  }
  return 0;
}

/* The folder taken; then, the run can start: the files of an earlier run in the folder are
 * moved aside (removed once this run has started), so results never mix. */
static int prepare_folder(sw_output *o, const sw_model *m, char *err, size_t errsz) {
  return take_folder(o, m, err, errsz) || out_manifest_commit(o, err, errsz) ? -1 : 0;
}

/* A run that could not start (err says why): its files removed, the earlier run's moved back;
 * err then ends with what became of the folder. */
static void not_started(sw_output *o, char *err, size_t errsz) {
  char why[SW_ERRSZ], undo[SW_ERRSZ] = "", back[SW_ERRSZ] = "", tail[2 * SW_ERRSZ + SW_PATHSZ + 256];
  snprintf(why, sizeof why, "%s", err);
  int wrote = o->mfd >= 0, moved = o->aside;
  struct stat st;
  int earlier = o->earlier || (!wrote && o->dir[0] && !out_join(o->path, o->dir, "sinew.manifest",
                                                               undo, sizeof undo) &&
                               lstat(o->path, &st) == 0);
  int kept = !out_manifest_undo(o, undo, sizeof undo);
  int restored = kept && !out_aside_back(o, back, sizeof back);
  if (!kept)
    snprintf(tail, sizeof tail, "this run's first files could not all be removed (%s)%s%s/%s",
             undo, moved ? "; the earlier run's files are in " : "", moved ? o->dir : "",
             moved ? ".sinew-earlier/" : "");
  else if (!restored)
    snprintf(tail, sizeof tail, "this run's first files removed; the earlier run's files could "
             "not all be moved back (%s): the rest are in %s/.sinew-earlier/", back, o->dir);
  else if (!earlier)
    snprintf(tail, sizeof tail, "nothing written%s%s%s", o->dir[0] ? " in " : "", o->dir,
             o->dir[0] ? "/" : "");
  else
    snprintf(tail, sizeof tail, "%s; the files of the earlier run in %s/ are as they were",
             wrote ? "this run's first files removed" : "nothing written", o->dir);
  size_t room = errsz > strlen(tail) + 3 ? errsz - strlen(tail) - 3 : 0;
  sw_errf(err, errsz, "%.*s; %s", (int)room, why, tail);
}

/* Folders this run made and left empty (a run that did not start), removed. */
static void unmake(const char *dir, int made_dir, int made_frames) {
  char path[SW_OUT_PATHMAX];
  snprintf(path, sizeof path, "%s/frames", dir);
  if (made_frames || made_dir) rmdir(path);
  if (made_dir) rmdir(dir);
}

/* ------------------------------------------------------------ the formats */

/* The formats this run writes, their private state allocated; -1 when out of memory. */
static int output_alloc(sw_output *o, const sw_model *m) {
  for (int k = 0; k < NFORMAT; k++) {
    const sw_out_ops *f = formats[k];
    sw_writer *w = &o->w[o->nw++];
    w->ops = f;
    w->on = !f->wanted || f->wanted(m);
    if (!w->on || !f->size) continue;
    if (!(w->self = sw_calloc(1, f->size))) return -1;
    if (f->init && f->init(w->self, m)) return -1;
  }
  return 0;
}

static void output_free(sw_output *o) {
  out_manifest_free(o);
  for (int k = 0; k < o->nw; k++)
    if (o->w[k].self) {
      if (o->w[k].ops->free) o->w[k].ops->free(o->w[k].self);
      sw_free(o->w[k].self);
    }
  sw_free(o);
}

/* The number of formats of this run that write at event. */
static int count(const sw_output *o, int event) {
  int n = 0;
  for (int k = 0; k < o->nw; k++) n += o->w[k].on && o->w[k].ops->event == event;
  return n;
}

/* Write d to every format of event; each one tried (the failed one too) is marked. */
static int write_event(sw_output *o, int event, const sw_model *m, const sw_data *d, char *err,
                       size_t errsz) {
  for (int k = 0; k < o->nw; k++) {
    sw_writer *w = &o->w[k];
    if (!w->on || w->ops->event != event || !w->ops->write) continue;
    w->tried = 1;
    if (w->ops->write(w->self, o, m, d, err, errsz)) return -1;
  }
  return 0;
}

/* Take back the last write of every format marked by write_event. */
static void undo_tried(sw_output *o) {
  for (int k = 0; k < o->nw; k++)
    if (o->w[k].tried && o->w[k].ops->undo) o->w[k].ops->undo(o->w[k].self);
}

/* ---------------------------------------------------------------- output.h */

int sw_output_record(sw_output *o, const sw_model *m, const sw_data *d, int positions, char *err,
                     size_t errsz) {
  if (!o || (positions && count(o, SW_OUT_POSITIONS) == 0)) {
    sw_errf(err, errsz, "output: the logs are not open");
    return -1;
  }
  for (int k = 0; k < o->nw; k++) o->w[k].tried = 0;
  if (write_event(o, SW_OUT_STEP, m, d, err, errsz) == 0 &&
      (!positions || write_event(o, SW_OUT_POSITIONS, m, d, err, errsz) == 0))
    return 0;
  /* Failed part-way: every log ends at the previous logged state again, whole lines only. */
  undo_tried(o);
  return -1;
}

int sw_output_step(sw_output *o, const sw_model *m, const sw_data *d, char *err, size_t errsz) {
  return sw_output_record(o, m, d, 0, err, errsz);
}

int sw_output_frame(sw_output *o, const sw_model *m, const sw_data *d, char *err, size_t errsz) {
  if (!o) {
    sw_errf(err, errsz, "output: not open");
    return -1;
  }
  return write_event(o, SW_OUT_FRAME, m, d, err, errsz);
}

int sw_output_summary(sw_output *o, const sw_model *m, const sw_data *d, const char *status,
                      const char *message, double wall, char *err, size_t errsz) {
  if (!o) {
    sw_errf(err, errsz, "output: not open");
    return -1;
  }
  o->status = status;
  o->message = message;
  o->wall = wall;
  return write_event(o, SW_OUT_STATUS, m, d, err, errsz);
}

/* Every format's files, headers written. */
static int open_formats(sw_output *o, const sw_model *m, char *err, size_t errsz) {
  for (int k = 0; k < o->nw; k++) {
    sw_writer *w = &o->w[k];
    if (w->on && w->ops->open && w->ops->open(w->self, o, m, err, errsz)) return -1;
  }
  return 0;
}

sw_output *sw_output_open(const sw_model *m, char *err, size_t errsz) {
  sw_output *o = sw_calloc(1, sizeof *o);
  if (o) o->mfd = -1, o->cpu0 = sw_cpu_now();
  if (!o || output_alloc(o, m)) {
    sw_errf(err, errsz, "%s: out of memory for the output writers", m->opt.out_dir);
    if (o) output_free(o);
    return NULL;
  }
  if (prepare_folder(o, m, err, errsz) || open_formats(o, m, err, errsz) ||
      sw_output_summary(o, m, NULL, "running", "", 0.0, err, errsz)) {
    not_started(o, err, errsz);
    char dir[SW_PATHSZ];
    snprintf(dir, sizeof dir, "%s", o->dir);
    int made_dir = o->made_dir, made_frames = o->made_frames;
    output_free(o); /* the lock released and its file removed */
    unmake(dir, made_dir, made_frames);
    return NULL;
  }
  out_aside_drop(o); /* started: the earlier run's files go */
  return o;
}

sw_output *sw_output_resume(const sw_model *m, const sw_data *d, sw_io *io, char *err,
                            size_t errsz) {
  sw_output *o = sw_calloc(1, sizeof *o);
  if (o) o->mfd = -1, o->resume = 1, o->cpu0 = sw_cpu_now();
  if (!o || output_alloc(o, m)) {
    sw_errf(err, errsz, "%s: out of memory for the output writers", m->opt.out_dir);
    if (o) output_free(o);
    return NULL;
  }
  /* the lock first (the lock's prepare); the others' prepare checks change nothing */
  if (take_folder(o, m, err, errsz) || out_resume_formats(o, io, err, errsz) ||
      out_manifest_reopen(o, err, errsz) || open_formats(o, m, err, errsz) ||
      sw_output_summary(o, m, d, "running", "", 0.0, err, errsz)) {
    output_free(o);
    return NULL;
  }
  return o;
}

/* Close every format (the logs get their final names); the first failure's message into err. */
static int close_formats(sw_output *o, char *err, size_t errsz) {
  int rc = 0;
  for (int k = 0; k < o->nw; k++) {
    sw_writer *w = &o->w[k];
    if (w->on && w->ops->close && w->ops->close(w->self, o, rc ? NULL : err, errsz)) rc = -1;
  }
  return rc;
}

int sw_output_close(sw_output *o, const sw_model *m, const sw_data *d, const char *status,
                    const char *message, double wall, char *err, size_t errsz) {
  if (!o) {
    sw_errf(err, errsz, "output: not open");
    return -1;
  }
  o->cpu = sw_cpu_now() - o->cpu0; /* s: to here, as the caller's wall time */
  char logerr[SW_ERRSZ] = "", msg[3 * SW_ERRSZ];
  int rc = close_formats(o, logerr, sizeof logerr);
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
