/* output.h — the writers of a run's folder, as the run loop (sim/sim.c) calls them.  Each
 * format is one file of sim/output/ behind the operations of writer.h; output.c drives them.
 *
 * While a run is going, the CSV logs (and positions.bin) are written as NAME.part, each line
 * (or record) in one write(2) after every step; sw_output_close renames them to NAME.  A step
 * whose lines cannot all be written (disk full, file size limit) is cut from every log again
 * (ftruncate), so the logs end at the same step with whole lines; the log that failed keeps its
 * .part name.  summary.json is
 * written through a temporary file and rename, first with status "running", finally "ok" or
 * "failed".  So a killed run leaves *.part files and a summary saying "running": nothing looks
 * complete that is not.  Frames are written to a temporary name and renamed when complete. */
#ifndef SW_OUTPUT_H
#define SW_OUTPUT_H

#include "sinew.h"
#include "util.h"

typedef struct sw_output sw_output;


/* Create m->opt.out_dir (and frames/), open the logs and write their headers. */
sw_output *sw_output_open(const sw_model *m, char *err, size_t errsz);
/* One line of tension.csv and energy.csv (and tendons.csv) for the state after an accepted
 * step and, when positions is nonzero, one record of positions.bin (t and every vertex
 * position; the file exists only with opt.positions_every > 0).  Allocates nothing.  On failure
 * no log has a line (or record) of this step. */
int sw_output_record(sw_output *o, const sw_model *m, const sw_data *d, int positions, char *err,
                     size_t errsz);
/* sw_output_record without a positions record. */
int sw_output_step(sw_output *o, const sw_model *m, const sw_data *d, char *err, size_t errsz);
/* frames/frame_NNNNNN.vtu of the current state, and its entry in frames.pvd. */
int sw_output_frame(sw_output *o, const sw_model *m, const sw_data *d, char *err, size_t errsz);
/* Write summary.json with status ("running", "ok", "failed", "interrupted") and a message. */
int sw_output_summary(sw_output *o, const sw_model *m, const sw_data *d, const char *status,
                      const char *message, double wall, char *err, size_t errsz);
/* Add every format's state (log sizes, the frame list) to io, whose first part the run loop
 * filled (its state and the integrator's), and write it as restart.bin (through a .tmp). */
int sw_output_restart(sw_output *o, sw_io *io, char *err, size_t errsz);
/* The folder of an interrupted (or failed, or finished) run, opened to go on from its
 * restart.bin: io positioned after the run loop's part, d the restored state.  The logs are
 * cut to what they held at the restart and appended to (as NAME.part again), the frames go
 * on from there, the manifest keeps its names.  NULL with err on failure (nothing changed). */
sw_output *sw_output_resume(const sw_model *m, const sw_data *d, sw_io *io, char *err,
                            size_t errsz);
/* Flush and rename the logs, write the final summary, free.  status "ok", "failed" or
 * "interrupted". */
int sw_output_close(sw_output *o, const sw_model *m, const sw_data *d, const char *status,
                    const char *message, double wall, char *err, size_t errsz);

#endif
