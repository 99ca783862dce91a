/* manifest.c — sinew.manifest (writer.h): the files this run wrote, so that the next run into
 * the folder removes those and nothing else.
 *
 * The file is text: a first line "# sinew manifest 1", then one name per line, relative to the
 * folder (e.g. "tension.csv", "frames/frame_000003.vtu").  A name is appended (one write(2))
 * before the file is created, so a killed run's manifest names every file it left; a name
 * stands for the file, its temporary forms NAME.tmp and NAME.part too.  The next run reads it
 * at its start (out_manifest_read), and only once everything it needs has been checked (the
 * lock taken, the folders writable, no file of another origin in its way) moves those files
 * aside (aside.c; removed once the new run has started) and starts its own manifest
 * (out_manifest_commit).  A name that is not one sinew writes
 * (a path outside the folder, "..", a hidden file) is ignored, so a hand-edited manifest cannot
 * make sinew remove anything else. */
#include <errno.h>
#include <fcntl.h>
#include <linux/fs.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util.h"
#include "writer.h"

#define HEADER "# sinew manifest 1\n"
#define MANIFEST_MAX (64 << 20) /* bytes: 1.6 million frames of names */

/* A name sinew may have written: [A-Za-z0-9_.-], not hidden, optionally under "frames/". */
static int valid_name(const char *s) {
  if (!strncmp(s, "frames/", 7)) s += 7;
  if (!*s || *s == '.' || !strcmp(s, "sinew.lock") || !strcmp(s, "sinew.manifest")) return 0;
  for (; *s; s++)
    if (!(('a' <= *s && *s <= 'z') || ('A' <= *s && *s <= 'Z') || ('0' <= *s && *s <= '9') ||
          *s == '_' || *s == '.' || *s == '-'))
      return 0;
  return 1;
}

/* Read fd whole into a fresh buffer of *n bytes (NUL-terminated); NULL with errno. */
static char *read_all(int fd, size_t *n) {
  struct stat st;
  if (fstat(fd, &st)) return NULL;
  if (!S_ISREG(st.st_mode) || st.st_size > MANIFEST_MAX) return errno = EFBIG, NULL;
  char *buf = sw_calloc((size_t)st.st_size + 1, 1);
  if (!buf) return errno = ENOMEM, NULL;
  size_t got = 0;
  while (got < (size_t)st.st_size) {
    ssize_t r = read(fd, buf + got, (size_t)st.st_size - got);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;
    got += (size_t)r;
  }
  buf[got] = '\0';
  *n = got;
  return buf;
}

int out_manifest_read(sw_output *o, char *err, size_t errsz) {
  o->mfd = -1;
  if (out_join(o->path, o->dir, "sinew.manifest", err, errsz)) return -1;
  int fd = open(o->path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0 && errno == ENOENT) return 0; /* a new folder, or one sinew never wrote to */
  size_t n = 0;
  char *buf = fd < 0 ? NULL : read_all(fd, &n);
  int e = errno;
  if (fd >= 0) close(fd);
  if (!buf)
    return sw_errf(err, errsz, "%s: cannot read the list of an earlier run's files: %s",
                   o->path, strerror(e)),
           -1;
  if (strncmp(buf, HEADER, strlen(HEADER))) { /* not ours: nothing in it is trusted */
    sw_free(buf);
    return 0;
  }
  for (size_t i = 0; i < n; i++) /* names, NUL-separated */
    if (buf[i] == '\n') buf[i] = '\0';
  o->old = buf;
  o->nold = n;
  return 0;
}

/* Each valid name of the earlier manifest, in turn: fn(ctx, name) until it returns nonzero. */
static int each_old(const sw_output *o, int (*fn)(void *ctx, const char *name), void *ctx) {
  size_t skip = strlen(HEADER);
  for (size_t i = skip; o->old && i < o->nold; i += strlen(o->old + i) + 1) {
    if (!valid_name(o->old + i)) continue;
    int rc = fn(ctx, o->old + i);
    if (rc) return rc;
  }
  return 0;
}

static int same_name(void *ctx, const char *name) { return !strcmp(ctx, name); }

int out_owned(const sw_output *o, const char *name) {
  char base[SW_OUT_PATHMAX];
  snprintf(base, sizeof base, "%s", name);
  base[out_name_base(base)] = '\0';
  return each_old(o, same_name, base);
}

typedef struct removal {
  sw_output *o;
  char *err;
  size_t errsz;
} removal;

/* One form of a name of a run that could not start (absent is fine; a folder of that name, in
 * the way of the file, is not sinew's: it stays). */
static int remove_form(void *ctx, const char *file) {
  removal *r = ctx;
  struct stat st;
  if (out_join(r->o->path, r->o->dir, file, r->err, r->errsz)) return -1;
  if (lstat(r->o->path, &st) || S_ISDIR(st.st_mode)) return 0;
  if (out_remove_path(r->o->path, r->err, r->errsz)) return -1;
  return 0;
}

/* NAME, NAME.tmp and NAME.part of a run that could not start. */
static int remove_new(void *ctx, const char *name) { return out_name_forms(name, remove_form, ctx); }

/* NAME, NAME.tmp and NAME.part of the earlier run can be moved and removed: none is a folder
 * (sinew writes files only) or immutable or append-only (chattr +i, +a: rename(2) and unlink(2)
 * then fail, whatever the folder's permissions). */
static int check_form(void *ctx, const char *file) {
  removal *r = ctx;
  if (out_join(r->o->path, r->o->dir, file, r->err, r->errsz)) return -1;
  struct stat st;
  if (lstat(r->o->path, &st) == 0 && S_ISDIR(st.st_mode))
    return sw_errf(r->err, r->errsz, "%s: a folder where the earlier run wrote a file; expected "
                   "that file or nothing: move the folder or choose another output folder",
                   r->o->path),
           -1;
  int fd = open(r->o->path, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return 0; /* absent, or a link (moving a link needs only the folder) */
  int flags = 0;
  int fixed = !ioctl(fd, FS_IOC_GETFLAGS, &flags) &&
              (flags & (FS_IMMUTABLE_FL | FS_APPEND_FL));
  close(fd);
  if (fixed)
    return sw_errf(r->err, r->errsz, "%s: a file of an earlier run that cannot be removed "
                   "(%s); expected files sinew may replace", r->o->path,
                   flags & FS_IMMUTABLE_FL ? "immutable, chattr +i" : "append-only, chattr +a"),
           -1;
  return 0;
}

static int check_old(void *ctx, const char *name) { return out_name_forms(name, check_form, ctx); }

int out_manifest_commit(sw_output *o, char *err, size_t errsz) {
  removal r = {o, err, errsz};
  if (each_old(o, check_old, &r)) return -1;
  if (o->old && out_aside_move(o, each_old, err, errsz)) return -1;
  sw_free(o->old);
  o->old = NULL;
  o->nold = 0;
  if (out_join(o->path, o->dir, "sinew.manifest", err, errsz)) return -1;
  o->mfd = out_create(o->path, O_APPEND, err, errsz);
  if (o->mfd < 0) return -1;
  return out_own(o, NULL, err, errsz);
}

int out_manifest_undo(sw_output *o, char *err, size_t errsz) {
  if (o->mfd < 0) return 0; /* this run's manifest was not made */
  close(o->mfd);
  o->mfd = -1;
  sw_free(o->old);
  o->old = NULL;
  if (out_manifest_read(o, err, errsz)) return -1; /* this run's names, as the earlier's */
  removal r = {o, err, errsz};
  int rc = each_old(o, remove_new, &r);
  sw_free(o->old);
  o->old = NULL;
  o->nold = 0;
  return rc || out_remove(o, "sinew.manifest", err, errsz) ? -1 : 0;
}

int out_manifest_reopen(sw_output *o, char *err, size_t errsz) {
  if (out_join(o->path, o->dir, "sinew.manifest", err, errsz)) return -1;
  o->mfd = open(o->path, O_WRONLY | O_APPEND | O_NOFOLLOW | O_CLOEXEC);
  if (o->mfd >= 0) return 0;
  return sw_errf(err, errsz, "%s: cannot resume: %s", o->path, strerror(errno)), -1;
}

int out_own(sw_output *o, const char *name, char *err, size_t errsz) {
  char line[SW_OUT_PATHMAX];
  int n = name ? snprintf(line, sizeof line, "%s\n", name) : snprintf(line, sizeof line, HEADER);
  ssize_t w;
  do w = write(o->mfd, line, (size_t)n);
  while (w < 0 && errno == EINTR);
  if (w == n) return 0;
  sw_errf(err, errsz, "%s/sinew.manifest: cannot write: %s", o->dir,
          w < 0 ? strerror(errno) : "short write");
  return -1;
}

void out_manifest_free(sw_output *o) {
  sw_free(o->old);
  o->old = NULL;
  if (o->mfd >= 0) close(o->mfd);
  o->mfd = -1;
}
