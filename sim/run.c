/* run.c — a whole run: the stepping API (sim.c) from t = 0 to the scene's duration, writing the
 * run folder.  A run that cannot go on stops with a message naming the time, the method and the
 * reason, keeps its logs, writes the last good state as a frame and a summary.json with status
 * "failed". */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "output.h"
#include "solver.h"
#include "util.h"

/* The scene to its duration through the stepping API, writing the run folder.  sw_run leaves m
 * as it was: the sim changes its model only through the sw_sim_set_* calls, which it makes
 * none of, and for the fit stage's length (its damping, Newton tolerance and gravity ramp,
 * restored when it ends, sim.c). */
static int run_to_end(const sw_model *m, int progress, int resume, char *err, size_t errsz) {
  int flags = SW_SIM_OUTPUT | (progress ? SW_SIM_PROGRESS : 0) | (resume > 1 ? SW_SIM_FORCE : 0);
  int start = SW_OK;
  sw_sim *s = resume ? sw_sim_resume((sw_model *)m, flags, &start, err, errsz)
                     : sw_sim_start((sw_model *)m, flags, &start, err, errsz);
  if (!s) return start;
  /* the duration counts from the end of the fit stage (0 without one) */
  int rc = sw_sim_run(s, sw_sim_data(s)->fit_end + m->opt.duration, err, errsz);
  char cerr[SW_ERRSZ];
  int crc = sw_sim_close(s, cerr, sizeof cerr);
  if (!rc && crc) sw_errf(err, errsz, "%s", cerr), rc = SW_FATAL;
  sw_sim_free(s);
  return rc;
}

int sw_run(const sw_model *m, int progress, char *err, size_t errsz) {
  return run_to_end(m, progress, 0, err, errsz);
}

int sw_resume(const sw_model *m, int progress, char *err, size_t errsz) {
  return run_to_end(m, progress, 1, err, errsz);
}

int sw_resume_ex(const sw_model *m, int progress, int force, char *err, size_t errsz) {
  return run_to_end(m, progress, force ? 2 : 1, err, errsz);
}
