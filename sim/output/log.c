/* log.c — the logs of the output formats (writer.h): appended in whole lines (or records) to
 * NAME.part, each named in the manifest before it is created, and renamed to NAME when the run
 * closes.  Above the manifest (manifest.c) and the file helpers (file.c). */
#include "writer.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util.h"

/* The log's NAME.part is open (a zeroed out_log is not). */
static int live(const out_log *l) { return l->opened && l->fd >= 0; }

int out_log_put(out_log *l, const sw_output *o, const char *s, size_t n, char *err,
                size_t errsz) {
  int e = l->werr;
  size_t done = 0;
  l->mark = l->size;
  while (!e && done < n) {
    ssize_t w = write(l->fd, s + done, n - done);
    if (w > 0) done += (size_t)w;
    else if (w < 0 && errno == EINTR) continue;
    else e = w < 0 ? errno : EIO;
  }
  if (!e) {
    l->size += (off_t)n;
    return 0;
  }
  l->werr = e;
  sw_errf(err, errsz, "%s/%s.part: cannot write: %s", o->dir, l->name, strerror(e));
  return -1;
}

void out_log_undo(void *self) {
  out_log *l = self;
  if (!live(l)) return;
  l->size = l->mark;
  if (ftruncate(l->fd, l->size) != 0 && !l->werr) l->werr = errno ? errno : EIO;
}

int out_log_open(out_log *l, const char *name, sw_output *o, const char *head, size_t n,
                 char *err, size_t errsz) {
  if (o->resume) return out_log_reopen(l, name, o, err, errsz);
  char part[32];
  l->name = name;
  snprintf(part, sizeof part, "%s.part", name);
  if (out_own(o, name, err, errsz) || out_join(o->path, o->dir, part, err, errsz)) return -1;
  /* O_APPEND: after a cut, the next line (if any) goes to the new end */
  l->fd = out_create(o->path, O_APPEND, err, errsz);
  if (l->fd < 0) return -1;
  l->size = 0;
  l->opened = 1;
  if (out_log_put(l, o, head, n, err, errsz) == 0) return 0;
  out_log_undo(l);
  return -1;
}

void out_log_io(void *self, sw_io *io) {
  out_log *l = self;
  sw_io_bytes(io, &l->size, sizeof l->size);
}

int out_log_reopen(out_log *l, const char *name, sw_output *o, char *err, size_t errsz) {
  char part[32];
  l->name = name;
  snprintf(part, sizeof part, "%s.part", name);
  if (out_join(o->path, o->dir, part, err, errsz) || out_join(o->tmp, o->dir, name, err, errsz))
    return -1;
  struct stat st;
  if (lstat(o->path, &st) && rename(o->tmp, o->path)) /* a finished log: NAME again NAME.part */
    return sw_errf(err, errsz, "%s: cannot resume the log: %s", o->tmp, strerror(errno)), -1;
  l->fd = open(o->path, O_WRONLY | O_APPEND | O_NOFOLLOW | O_CLOEXEC);
  if (l->fd < 0 || fstat(l->fd, &st) || st.st_size < l->size || ftruncate(l->fd, l->size)) {
    int e = l->fd < 0 || st.st_size >= l->size ? errno : 0;
    sw_errf(err, errsz, "%s: cannot resume the log: %s", o->path,
            e ? strerror(e) : "shorter than at the restart");
    return -1;
  }
  l->opened = 1;
  return 0;
}

int out_log_close(void *self, sw_output *o, char *err, size_t errsz) {
  out_log *l = self;
  if (!live(l)) return 0;
  int e = l->werr; /* a write failed: the log keeps its .part name */
  if (close(l->fd) != 0 && !e) e = errno ? errno : EIO;
  l->fd = -1;
  char part[32];
  snprintf(part, sizeof part, "%s.part", l->name);
  if (out_join(o->tmp, o->dir, part, err, errsz) || out_join(o->path, o->dir, l->name, err, errsz))
    return -1;
  if (e) {
    sw_errf(err, errsz, "%s: cannot write: %s", o->tmp, strerror(e));
    return -1;
  }
  if (rename(o->tmp, o->path)) {
    sw_errf(err, errsz, "%s: cannot rename to %s: %s", o->tmp, o->path, strerror(errno));
    return -1;
  }
  l->final = 1;
  return 0;
}

void out_log_files(const void *self, void (*add)(void *ctx, const char *name), void *ctx) {
  const out_log *l = self;
  char name[40];
  if (!l->opened) return;
  snprintf(name, sizeof name, "%s%s", l->name, l->final ? "" : ".part");
  add(ctx, name);
}

void out_log_free(out_log *l) {
  if (live(l)) close(l->fd);
  l->fd = -1;
}
