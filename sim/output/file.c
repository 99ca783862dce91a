/* file.c — the file helpers of the output formats (writer.h): text files written to NAME.tmp
 * and renamed when whole, numbers that read back exactly, folders, the forms of a file's name.
 * Every write is checked; errors read "PATH: what failed: strerror(errno)". */
#include "writer.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util.h"

/* ------------------------------------------------------------ checked writes */

static void w_fail(out_file *w) {
  if (!w->err) w->err = errno ? errno : EIO;
}

void out_puts(out_file *w, const char *s) {
  if (w->err) return;
  errno = 0;
  if (fputs(s, w->f) == EOF) w_fail(w);
}

void out_printf(out_file *w, const char *fmt, ...) {
  if (w->err) return;
  va_list ap;
  va_start(ap, fmt);
  errno = 0;
  if (vfprintf(w->f, fmt, ap) < 0) w_fail(w);
  va_end(ap);
}

/* The shortest of %.15g, %.16g, %.17g that reads back as exactly v (so 0.03 is written "0.03",
 * and every number still round-trips); "nan", "inf", "-inf" otherwise (pandas reads all). */
int out_fmt_num(char *buf, size_t sz, double v) {
  if (isnan(v)) return snprintf(buf, sz, "nan");
  if (isinf(v)) return snprintf(buf, sz, v > 0 ? "inf" : "-inf");
  for (int prec = 15; prec < 17; prec++) {
    int n = snprintf(buf, sz, "%.*g", prec, v);
    if (strtod(buf, NULL) == v) return n;
  }
  return snprintf(buf, sz, "%.17g", v);
}

void out_num(out_file *w, double v, const char *after) {
  char buf[SW_OUT_NUMSZ];
  out_fmt_num(buf, sizeof buf, v);
  out_puts(w, buf);
  out_puts(w, after);
}

int out_join(char *buf, const char *dir, const char *name, char *err, size_t errsz) {
  int n = snprintf(buf, SW_OUT_PATHMAX, "%s/%s", dir, name);
  if (n >= 0 && n < SW_OUT_PATHMAX) return 0;
  sw_errf(err, errsz, "%s: path of %s is too long", dir, name);
  return -1;
}

int out_create(const char *path, int flags, char *err, size_t errsz) {
  if (unlink(path) && errno != ENOENT) {
    sw_errf(err, errsz, "%s: cannot replace: %s", path, strerror(errno));
    return -1;
  }
  int fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC | flags, 0666);
  if (fd < 0) sw_errf(err, errsz, "%s: cannot open for writing: %s", path, strerror(errno));
  return fd;
}

int out_tmp_open(out_file *w, const char *tmp, char *err, size_t errsz) {
  w->err = 0;
  int fd = out_create(tmp, 0, err, errsz);
  if (fd < 0) return -1;
  w->f = fdopen(fd, "w");
  if (w->f) return 0;
  sw_errf(err, errsz, "%s: cannot open for writing: %s", tmp, strerror(errno));
  close(fd);
  unlink(tmp);
  return -1;
}

int out_tmp_commit(out_file *w, const char *tmp, const char *path, char *err, size_t errsz) {
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

/* ------------------------------------------------------------------ folders */

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

int out_make_dir(const char *path, const char *dir, char *err, size_t errsz) {
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

/* mkdir -p dir, then check that it can be written (output.c). */
int out_make_dirs(const char *dir, char *scratch, char *err, size_t errsz) {
  snprintf(scratch, SW_OUT_PATHMAX, "%s", dir);
  for (char *s = scratch + 1; *s; s++) {
    if (*s != '/') continue;
    *s = '\0';
    int rc = out_make_dir(scratch, dir, err, errsz);
    *s = '/';
    if (rc) return rc;
  }
  if (out_make_dir(scratch, dir, err, errsz)) return -1;
  if (access(dir, W_OK | X_OK) == 0) return 0;
  char b[2 * ELIDE + 4];
  sw_errf(err, errsz, "%s: the output folder is not writable: %s", elide(dir, b), strerror(errno));
  return -1;
}

int out_remove_path(const char *path, char *err, size_t errsz) {
  if (unlink(path) == 0 || errno == ENOENT) return 0;
  sw_errf(err, errsz, "%s: cannot remove: %s", path, strerror(errno));
  return -1;
}

int out_remove(sw_output *o, const char *name, char *err, size_t errsz) {
  if (out_join(o->path, o->dir, name, err, errsz)) return -1;
  return out_remove_path(o->path, err, errsz);
}

/* -------------------------------------------------------------- name forms */

static const char *const forms[] = {"", ".tmp", ".part"};

int out_name_forms(const char *name, int (*fn)(void *ctx, const char *file), void *ctx) {
  for (int k = 0; k < 3; k++) {
    char file[SW_OUT_PATHMAX];
    snprintf(file, sizeof file, "%s%s", name, forms[k]);
    int rc = fn(ctx, file);
    if (rc) return rc;
  }
  return 0;
}

size_t out_name_base(const char *name) {
  size_t n = strlen(name);
  for (int k = 1; k < 3; k++) {
    size_t f = strlen(forms[k]);
    if (n > f && !strcmp(name + n - f, forms[k])) return n - f;
  }
  return n;
}
