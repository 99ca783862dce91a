/* lock.c — sinew.lock (writer.h): one run at a time in a folder.  Its prepare, the first of
 * every format's (before anything of an earlier run is removed), opens DIR/sinew.lock and takes
 * an exclusive flock(2) on it without waiting: a folder whose lock is held by another process
 * is refused with that process's id, read from the file.  The run then writes its own id
 * there and holds the lock to its end, when the file is removed (still locked, so no other run
 * can hold a lock on a file that is gone).  The kernel releases the lock of a process that dies
 * (kill -9, a crash): its sinew.lock stays with a dead process's id, and the next run takes
 * it over, as a stale lock.  A file swapped under the path between open and flock is opened
 * again.  Not listed in the summary's files: it is gone when the run is. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util.h"
#include "writer.h"

typedef struct lock {
  int fd; /* of DIR/sinew.lock while held, -1 otherwise */
  char path[SW_OUT_PATHMAX];
} lock;

static int lock_init(void *self, const sw_model *m) {
  (void)m;
  ((lock *)self)->fd = -1;
  return 0;
}

/* The process id written in an open lock file (0 if none can be read). */
static long holder(int fd) {
  char buf[32] = "";
  ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
  buf[n > 0 ? n : 0] = '\0';
  return strtol(buf, NULL, 10);
}

/* The lock file is still the one at the path (not removed or replaced by its holder). */
static int same_file(int fd, const char *path) {
  struct stat a, b;
  return fstat(fd, &a) == 0 && stat(path, &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

/* Open and lock path into l->fd: 0, 1 when another process holds it (its id in *pid), -1 with
 * errno on another failure. */
static int try_lock(lock *l, long *pid) {
  for (int attempt = 0; attempt < 8; attempt++) {
    int fd = open(l->path, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) return -1;
    if (flock(fd, LOCK_EX | LOCK_NB)) {
      int e = errno;
      *pid = holder(fd);
      close(fd);
      if (e == EWOULDBLOCK) return 1;
      errno = e;
      return -1;
    }
    if (same_file(fd, l->path)) {
      l->fd = fd;
      return 0;
    }
    close(fd); /* its holder removed it as we opened it: try the new one */
  }
  errno = EAGAIN;
  return -1;
}

static int lock_prepare(void *self, sw_output *o, const sw_model *m, char *err, size_t errsz) {
  (void)m;
  lock *l = self;
  long pid = 0;
  if (out_join(l->path, o->dir, "sinew.lock", err, errsz)) return -1;
  int rc = try_lock(l, &pid);
  if (rc > 0)
    return sw_errf(err, errsz, "%s: the folder is in use by another run (process %ld, "
                   "%s); expected a folder no other run is writing to", o->dir, pid, l->path),
           -1;
  if (rc < 0)
    return sw_errf(err, errsz, "%s: cannot lock the folder: %s", l->path, strerror(errno)), -1;
  char id[32];
  int n = snprintf(id, sizeof id, "%ld\n", (long)getpid());
  if (ftruncate(l->fd, 0) || pwrite(l->fd, id, (size_t)n, 0) != n)
    return sw_errf(err, errsz, "%s: cannot write: %s", l->path, strerror(errno)), -1;
  return 0;
}

/* Remove the file while it is still locked, then release it. */
static void lock_free(void *self) {
  lock *l = self;
  if (l->fd < 0) return;
  unlink(l->path);
  close(l->fd);
  l->fd = -1;
}

const sw_out_ops sw_out_lock = {
    .name = "lock",
    .event = -1, /* never written to */
    .size = sizeof(lock),
    .init = lock_init,
    .prepare = lock_prepare,
    .free = lock_free,
};
