/* util.h — small shared helpers: allocation (one hook for the whole library), errors, clocks. */
#ifndef SW_UTIL_H
#define SW_UTIL_H

#include <stddef.h>
#include <stdint.h>

/* Every allocation of the library goes through these two, so that tests can make the k-th one
 * fail.  sw_calloc returns zeroed memory, or NULL (n == 0 gives a valid unique pointer). */
void *sw_calloc(size_t n, size_t size);
void *sw_realloc(void *p, size_t n, size_t size);
void sw_free(void *p);
/* Make allocation number k (counted from now, 1-based) and all later ones fail; 0 disables. */
void sw_alloc_fail_after(long k);

/* snprintf into a caller-owned error buffer (never overflows; NULL buffer is ignored). */
void sw_errf(char *err, size_t errsz, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

double sw_now(void); /* monotonic wall clock, s */
double sw_cpu_now(void); /* CPU time (user + system) of the process, every thread, s */

#define SW_MIN(a, b) ((a) < (b) ? (a) : (b))
#define SW_MAX(a, b) ((a) > (b) ? (a) : (b))

/* FNV-1a (Fowler, Noll and Vo) over n bytes at p, continuing from h (start from SW_HASH0):
 * detects any change of a single byte, and others but with probability 2^-64. */
#define SW_HASH0 1469598103934665603u
uint64_t sw_hash64(uint64_t h, const void *p, size_t n);

/* A hash table of names (open addressing, at most half full), each with an int value; the
 * names are the caller's and must outlive the table.  Finding and adding take O(1) expected
 * time, so loading n named things is O(n), not O(n^2) comparisons. */
typedef struct sw_names {
  size_t nslot, n;
  const char **key; /* (nslot) the name in each slot, or NULL */
  int *val;         /* (nslot) */
} sw_names;
/* The value of name, or -1 when absent. */
int sw_names_find(const sw_names *t, const char *name);
/* Add name with value val (>= 0) unless present: returns the value already there, -1 when
 * added, -2 when out of memory. */
int sw_names_add(sw_names *t, const char *name, int val);
void sw_names_free(sw_names *t);

/* A restart file's contents, written or read piece by piece in the same order (restart.c):
 * saving appends each piece to buf, loading copies it back out and fails past the end. */
typedef struct sw_io {
  int load;                /* 0: saving, 1: loading */
  unsigned char *buf;      /* the file's bytes */
  size_t len, cap, pos;    /* bytes held, allocated, read so far */
  int bad;                 /* loading: past the end, or a check failed; saving: out of memory */
  uint64_t shape;          /* FNV-1a of the pieces' sizes in order: the layout (its test) */
} sw_io;

/* restart.bin begins with this magic, whose last two characters are the format's version, and
 * ends with the FNV-1a 64 of all the bytes before it (restart.c). */
#define SW_RESTART_MAGIC "SWREST06"
/* The layout of the run loop's part of restart.bin for test_sim's scene: any change of it
 * (a field, an option, a counter) is a new format, so this and the magic's version change
 * together (test_sim's restart_layout). */
#define SW_RESTART_SHAPE 0xa00c2419ffe906b3u
struct sw_sim;
/* The shape (sw_io.shape) of the header and the run loop's part of a restart file of sim s. */
uint64_t sw_sim_restart_shape(struct sw_sim *s);

/* n bytes at p into (saving) or out of (loading) io. */
void sw_io_bytes(sw_io *io, void *p, size_t n);
/* sim.c: sw_sim_new, and in *rc (if not NULL) SW_NOSTART when the output folder could not be
 * opened, SW_FATAL on another failure (run.c). */
typedef struct sw_sim sw_sim;
typedef struct sw_model sw_model;
sw_sim *sw_sim_start(sw_model *m, int flags, int *rc, char *err, size_t errsz);
/* sim.c: a sim going on from the restart.bin of the run folder m->opt.out_dir (its folder
 * reopened with SW_SIM_OUTPUT); *rc as sw_sim_start. */
sw_sim *sw_sim_resume(sw_model *m, int flags, int *rc, char *err, size_t errsz);
/* util.c / restart.c: the restart file. */
int sw_io_read(sw_io *io, const char *dir, char *err, size_t errsz);
void sw_io_free(sw_io *io);

#endif
