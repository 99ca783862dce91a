/* writer.h — internal to sim/output/: the operations every output format implements, the run
 * folder they share (struct sw_output), and the helpers below them (log.c, manifest.c, aside.c,
 * file.c).
 *
 * Each format is one file holding one or more `const sw_out_ops` tables (SUNDIALS' table of
 * operations, dav1d's muxers): csv.c (tension.csv, energy.csv, tendons.csv), positions.c
 * (positions.bin), vtu.c (frames/frame_NNNNNN.vtu, tendons_NNNNNN.vtp and frames.pvd, through
 * vtkxml.c), summary.c
 * (summary.json).  output.c lists them and drives them: it is the only caller of the
 * operations.  A new format is one new
 * file with its table, and its name in output.c's list.  Dependencies point down:
 * output.c -> the formats -> log.c (logs) -> manifest.c (the run's file list) -> aside.c (the
 * earlier run's files) -> file.c -> util.h, sinew.h. */
#ifndef SW_OUTPUT_WRITER_H
#define SW_OUTPUT_WRITER_H

#include <stdio.h>
#include <sys/types.h>

#include "output.h"

#define SW_OUT_PATHMAX (SW_PATHSZ + 64) /* out_dir plus a file name inside it */
#define SW_OUT_NUMSZ 32                 /* room for one %.17g number and its separator */
#define SW_OUT_MAXW 16                  /* formats at most */

/* When a format's write is called. */
enum {
  SW_OUT_STEP,      /* every logged state (sw_output_record) */
  SW_OUT_POSITIONS, /* a logged state that is a positions sample (sw_output_record) */
  SW_OUT_FRAME,     /* a frame (sw_output_frame) */
  SW_OUT_STATUS     /* the run's status (sw_output_summary: at open and at close) */
};

/* The operations of one format.  self is its private state (size bytes, zeroed; NULL when
 * size is 0 or the run does not write the format).  Each int operation returns 0, or -1 with
 * the message in err ("PATH: what failed: strerror(errno)").  NULL operations are skipped. */
typedef struct sw_out_ops {
  const char *name; /* the format, for messages */
  int event;        /* SW_OUT_*: when write is called */
  size_t size;      /* bytes of private state */
  /* Whether this run writes the format (NULL: always). */
  int (*wanted)(const sw_model *m);
  /* Allocate buffers for m (no files yet); -1 when out of memory. */
  int (*init)(void *self, const sw_model *m);
  /* Take the folder (lock), make the folders it needs and check that they can be written,
   * touching no file of an earlier run (called for every format, wanted or not (self NULL
   * then), before the earlier run's files are removed (manifest.c) and any file is opened). */
  int (*prepare)(void *self, sw_output *o, const sw_model *m, char *err, size_t errsz);
  /* Create its files (headers). */
  int (*open)(void *self, sw_output *o, const sw_model *m, char *err, size_t errsz);
  /* Write the state d at its event. */
  int (*write)(void *self, sw_output *o, const sw_model *m, const sw_data *d, char *err,
               size_t errsz);
  /* Take back the last write: another format of the same logged state failed. */
  void (*undo)(void *self);
  /* Finish its files (final names). */
  int (*close)(void *self, sw_output *o, char *err, size_t errsz);
  /* Name each of its files (relative to the folder, under their current names). */
  void (*files)(const void *self, void (*add)(void *ctx, const char *name), void *ctx);
  /* Save or load (io->load) what a resumed run needs to go on writing (restart.c); open is
   * then called with o->resume set and reopens its files as they were at the restart. */
  void (*io)(void *self, sw_io *io);
  /* Release what init and open took (not self itself). */
  void (*free)(void *self);
} sw_out_ops;

typedef struct sw_writer {
  const sw_out_ops *ops;
  void *self;
  int on;    /* this run writes the format */
  int tried; /* written to since sw_output_record began (undo on a failure) */
} sw_writer;

struct sw_output {
  char dir[SW_PATHSZ];                             /* the run folder, without trailing '/' */
  char path[SW_OUT_PATHMAX], tmp[SW_OUT_PATHMAX]; /* path scratch */
  const char *status, *message;                   /* SW_OUT_STATUS: the run's status */
  double wall;                                    /* SW_OUT_STATUS: wall time so far, s */
  double cpu0;                                    /* s: the process's CPU time at open */
  double cpu;                                     /* SW_OUT_STATUS: CPU time since open, s */
  int resume;                                     /* opened by sw_output_resume */
  int mfd;                                        /* sinew.manifest, open to append; -1 */
  char *old;                                      /* the earlier run's manifest, NUL-separated */
  size_t nold;                                    /* its bytes */
  int earlier;      /* the folder held an earlier run (its manifest) when this run began */
  int aside;        /* some earlier run's files are in DIR/.sinew-earlier/ (aside.c) */
  int made_dir;     /* this run made the run folder */
  int made_frames;  /* this run made DIR/frames/ */
  int nw;
  sw_writer w[SW_OUT_MAXW]; /* in output.c's order: that of the summary's file list */
};

/* The formats (one file each). */
extern const sw_out_ops sw_out_tension, sw_out_energy, sw_out_tendons,
    sw_out_contact, sw_out_seams; /* csv.c */
extern const sw_out_ops sw_out_seam_defs;                              /* seams_json.c */
extern const sw_out_ops sw_out_positions;                              /* positions.c */
extern const sw_out_ops sw_out_vtu;                                    /* vtu.c */
extern const sw_out_ops sw_out_summary;                                /* summary.c */
extern const sw_out_ops sw_out_lock;                                   /* lock.c */

/* restart.c: every format's part of the restart file loaded; -1 when io does not fit. */
int out_resume_formats(sw_output *o, sw_io *io, char *err, size_t errsz);

/* ------------------------------------------ manifest.c: the files of the run (sinew.manifest) */

/* Resuming: reopen the manifest to append to it (its names stay). */
int out_manifest_reopen(sw_output *o, char *err, size_t errsz);
/* Read the earlier run's manifest, if any (nothing is removed yet). */
int out_manifest_read(sw_output *o, char *err, size_t errsz);
/* 1 if the earlier run's manifest names name (or name without its .tmp / .part). */
int out_owned(const sw_output *o, const char *name);
/* Move the files the earlier manifest names aside (out_aside_move), then start this run's
 * manifest. */
int out_manifest_commit(sw_output *o, char *err, size_t errsz);
/* A run that could not start: remove the files its manifest names, then the manifest. */
int out_manifest_undo(sw_output *o, char *err, size_t errsz);

/* ---------------------- aside.c: the earlier run's files moved aside until the new run starts */

/* A DIR/.sinew-earlier/ left by a stopped run: moved back or removed (after the lock, before
 * the manifest is read). */
int out_aside_recover(sw_output *o, char *err, size_t errsz);
/* Rename each file each() yields (the earlier manifest's names) and then sinew.manifest into
 * DIR/.sinew-earlier/; on failure some may have moved (o->aside: out_aside_back). */
int out_aside_move(sw_output *o, int (*each)(const sw_output *, int (*)(void *, const char *), void *),
                   char *err, size_t errsz);
/* Every moved file back in its place (replacing a file of the new run of the same name). */
int out_aside_back(sw_output *o, char *err, size_t errsz);
/* The new run has started: remove the moved files (a failure is a warning on stderr). */
void out_aside_drop(sw_output *o);
/* Append name (relative to the folder) to the manifest, before the file is created; name NULL:
 * the header. */
int out_own(sw_output *o, const char *name, char *err, size_t errsz);
void out_manifest_free(sw_output *o);

/* ------------------------------------------------ file.c: text files written whole */

/* A FILE that remembers the errno of its first failed write; later writes are skipped. */
typedef struct out_file {
  FILE *f;
  int err;
} out_file;

void out_puts(out_file *w, const char *s);
void out_printf(out_file *w, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* A JSON string of at most maxlen bytes of s (NULL: null): quotes, backslashes and control
 * characters escaped, ill-formed UTF-8 replaced by U+FFFD (summary.c). */
void out_json_str(out_file *w, const char *s, size_t maxlen);
/* A number (out_fmt_num), then the string after. */
void out_num(out_file *w, double v, const char *after);
/* The shortest of %.15g, %.16g, %.17g that reads back as exactly v; "nan", "inf", "-inf"
 * otherwise.  Returns the length, as snprintf. */
int out_fmt_num(char *buf, size_t sz, double v);
/* buf (SW_OUT_PATHMAX bytes) = dir/name; -1 with a message when too long. */
int out_join(char *buf, const char *dir, const char *name, char *err, size_t errsz);
/* Create path afresh for writing (flags | O_WRONLY): a file of that name (sinew's own: a
 * temporary name, or one the earlier manifest named) is unlinked first, then the file is made
 * with O_CREAT | O_EXCL | O_NOFOLLOW, so no symbolic link is ever followed.  fd, or -1. */
int out_create(const char *path, int flags, char *err, size_t errsz);
/* Open tmp for writing (out_create). */
int out_tmp_open(out_file *w, const char *tmp, char *err, size_t errsz);
/* Flush and close w (the file tmp), then rename it to path.  On failure tmp is removed. */
int out_tmp_commit(out_file *w, const char *tmp, const char *path, char *err, size_t errsz);
/* mkdir path (a folder inside or above dir, which names the run folder in messages); an
 * existing folder is fine. */
int out_make_dir(const char *path, const char *dir, char *err, size_t errsz);
/* mkdir -p dir, then check that it can be written; scratch: SW_OUT_PATHMAX bytes. */
int out_make_dirs(const char *dir, char *scratch, char *err, size_t errsz);
/* Remove path, or o->dir/name (absent is fine). */
int out_remove_path(const char *path, char *err, size_t errsz);
int out_remove(sw_output *o, const char *name, char *err, size_t errsz);
/* The forms of a file name the manifest stands for: NAME, NAME.tmp and NAME.part in turn,
 * each into fn(ctx, file) until it returns nonzero (then that value), else 0. */
int out_name_forms(const char *name, int (*fn)(void *ctx, const char *file), void *ctx);
/* The length of name without a .tmp or .part ending (the NAME it is a form of). */
size_t out_name_base(const char *name);

/* ------------------------------- log.c: logs, appended in whole lines or records */

/* A log lives as NAME.part until closed.  A line (record) goes out in one write(2); a write
 * that fails part-way is cut back (ftruncate) to the whole lines. */
typedef struct out_log {
  const char *name; /* e.g. "tension.csv" */
  int fd;           /* of NAME.part while the run goes, -1 when closed */
  off_t size;       /* bytes of the whole lines (records) written */
  off_t mark;       /* size before the last write (undo) */
  int werr;         /* errno of a failed write (0: none) */
  int opened;       /* 1 if this run writes the log */
  int final;        /* 1 once renamed to NAME */
} out_log;

/* Name NAME in the manifest, create o->dir/NAME.part and write its header of n bytes (when
 * resuming: out_log_reopen). */
int out_log_open(out_log *l, const char *name, sw_output *o, const char *head, size_t n,
                 char *err, size_t errsz);
/* Write n bytes of s in one piece; the log's mark is its size before.  On failure the error
 * is remembered and l->size still counts only the whole lines. */
int out_log_put(out_log *l, const sw_output *o, const char *s, size_t n, char *err,
                size_t errsz);
/* The next three are the undo, close and files operations of a format whose private state
 * begins with its out_log (csv.c, positions.c): self points at that out_log. */
/* Resuming: reopen o->dir/NAME.part (or NAME, renamed to NAME.part) cut to l->size bytes,
 * the size it had at the restart (loaded by out_log_io). */
int out_log_reopen(out_log *l, const char *name, sw_output *o, char *err, size_t errsz);
/* The io operation of a log: its size. */
void out_log_io(void *self, sw_io *io);
/* Cut the log back to its mark (after a logged state whose writes failed part-way). */
void out_log_undo(void *self);
/* Close and rename NAME.part to NAME; it keeps its .part name if anything failed. */
int out_log_close(void *self, sw_output *o, char *err, size_t errsz);
/* NAME or NAME.part, when this run writes the log. */
void out_log_files(const void *self, void (*add)(void *ctx, const char *name), void *ctx);
/* Close the file descriptor, if open (no rename). */
void out_log_free(out_log *l);

#endif
