/* restart.c — restart.bin, the state a run can go on from (output.h, `sinew run --resume`):
 * the run loop's part (sim.c: time, step grid, sampling times, counters, positions and
 * velocities, the integrator's history) then each format's (writer.h `io`: the bytes of each
 * log, the list of frames).  One function per part visits every field in a fixed order, for
 * saving and loading alike (sw_io), so the two cannot disagree.  Native byte order: a restart
 * file is read by the sinew that wrote it, on the same machine.  The file begins with
 * SW_RESTART_MAGIC (its format version) and ends with a checksum of the bytes before it, so a
 * damaged or cut file is refused before anything of it is used. */
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util.h"
#include "writer.h"

#define RESTART_MAX (1L << 30) /* bytes */

/* The magic, version and checksum of a restart file read whole; the checksum is then dropped
 * from io->len.  -1 with err when the file is not one, of another version or damaged. */
static int check_frame(sw_io *io, const char *path, char *err, size_t errsz) {
  const size_t nm = sizeof SW_RESTART_MAGIC - 1;
  uint64_t sum;
  if (io->len < nm + sizeof sum || memcmp(io->buf, SW_RESTART_MAGIC, nm - 2))
    return sw_errf(err, errsz, "%s: not a restart file of sinew (%zu bytes, no '%.*s' at its "
                   "start); expected the restart.bin a run wrote", path, io->len, (int)nm - 2,
                   SW_RESTART_MAGIC),
           -1;
  if (memcmp(io->buf, SW_RESTART_MAGIC, nm))
    return sw_errf(err, errsz, "%s: a restart file of format %.2s; expected format %s (resume it "
                   "with the sinew that wrote it)", path, (const char *)io->buf + nm - 2,
                   SW_RESTART_MAGIC + nm - 2),
           -1;
  memcpy(&sum, io->buf + io->len - sizeof sum, sizeof sum);
  if (sum != sw_hash64(SW_HASH0, io->buf, io->len - sizeof sum))
    return sw_errf(err, errsz, "%s: damaged: its checksum does not match its contents; expected "
                   "the file as the run wrote it", path),
           -1;
  io->len -= sizeof sum;
  return 0;
}

int sw_io_read(sw_io *io, const char *dir, char *err, size_t errsz) {
  char path[SW_OUT_PATHMAX];
  memset(io, 0, sizeof *io);
  io->load = 1;
  if (out_join(path, dir, "restart.bin", err, errsz)) return -1;
  int fd = open(path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  struct stat st;
  if (fd < 0 || fstat(fd, &st) || !S_ISREG(st.st_mode) || st.st_size > RESTART_MAX) {
    int e = fd < 0 ? errno : EFBIG;
    if (fd >= 0) close(fd);
    return sw_errf(err, errsz, "%s: cannot read the restart file: %s (a run writes it with "
                   "each frame and when it stops)", path, strerror(e)),
           -1;
  }
  io->buf = sw_calloc((size_t)st.st_size + 1, 1);
  size_t got = 0;
  while (io->buf && got < (size_t)st.st_size) {
    ssize_t r = read(fd, io->buf + got, (size_t)st.st_size - got);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;
    got += (size_t)r;
  }
  close(fd);
  io->len = io->cap = got;
  if (io->buf && got == (size_t)st.st_size && !check_frame(io, path, err, errsz)) return 0;
  if (!io->buf || got != (size_t)st.st_size)
    sw_errf(err, errsz, "%s: cannot read the restart file: %s", path,
            io->buf ? "short read" : "out of memory");
  sw_io_free(io);
  return -1;
}

void sw_io_free(sw_io *io) {
  sw_free(io->buf);
  memset(io, 0, sizeof *io);
}

/* Every format's part, in the order of the formats. */
static void formats_io(sw_output *o, sw_io *io) {
  for (int k = 0; k < o->nw; k++)
    if (o->w[k].on && o->w[k].ops->io) o->w[k].ops->io(o->w[k].self, io);
}

int sw_output_restart(sw_output *o, sw_io *io, char *err, size_t errsz) {
  formats_io(o, io);
  uint64_t sum = sw_hash64(SW_HASH0, io->buf, io->len);
  sw_io_bytes(io, &sum, sizeof sum);
  if (io->bad) return sw_errf(err, errsz, "%s: out of memory for the restart file", o->dir), -1;
  if (out_own(o, "restart.bin", err, errsz) || out_join(o->tmp, o->dir, "restart.bin.tmp", err, errsz) ||
      out_join(o->path, o->dir, "restart.bin", err, errsz))
    return -1;
  out_file w;
  if (out_tmp_open(&w, o->tmp, err, errsz)) return -1;
  errno = 0;
  if (fwrite(io->buf, 1, io->len, w.f) != io->len) w.err = errno ? errno : EIO;
  return out_tmp_commit(&w, o->tmp, o->path, err, errsz);
}

int out_resume_formats(sw_output *o, sw_io *io, char *err, size_t errsz) {
  formats_io(o, io);
  if (!io->bad && io->pos == io->len) return 0;
  return sw_errf(err, errsz, "%s/restart.bin: %s; expected the restart file of a run of this "
                 "scene with the same output settings", o->dir,
                 io->bad ? "shorter than its contents say" : "longer than its contents say"),
         -1;
}
