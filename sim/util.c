/* util.c — allocation hook, error buffers, clocks. */
#include "util.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static long alloc_fail_at;   /* 0: never fail */
static long alloc_count;

void sw_alloc_fail_after(long k) {
  alloc_fail_at = k;
  alloc_count = 0;
}

static int alloc_should_fail(void) {
  if (alloc_fail_at <= 0) return 0;
  return ++alloc_count >= alloc_fail_at;
}

void *sw_calloc(size_t n, size_t size) {
  if (alloc_should_fail()) return NULL;
  if (n == 0 || size == 0) n = size = 1;
  if (size && n > SIZE_MAX / size) return NULL;
  return calloc(n, size);
}

void *sw_realloc(void *p, size_t n, size_t size) {
  if (alloc_should_fail()) return NULL;
  if (n == 0 || size == 0) n = size = 1;
  if (size && n > SIZE_MAX / size) return NULL;
  return realloc(p, n * size);
}

void sw_free(void *p) { free(p); }

void sw_errf(char *err, size_t errsz, const char *fmt, ...) {
  if (!err || errsz == 0) return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err, errsz, fmt, ap);
  va_end(ap);
}

double sw_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ------------------------------------------------ restart files (util.h) */

void sw_io_bytes(sw_io *io, void *p, size_t n) {
  if (io->bad) return;
  if (io->load) {
    if (n > io->len - io->pos) {
      io->bad = 1;
      memset(p, 0, n);
      return;
    }
    memcpy(p, io->buf + io->pos, n);
    io->pos += n;
    return;
  }
  if (io->len + n > io->cap) {
    size_t cap = io->cap ? 2 * io->cap : 4096;
    while (cap < io->len + n) cap *= 2;
    unsigned char *b = sw_realloc(io->buf, cap, 1);
    if (!b) {
      io->bad = 1;
      return;
    }
    io->buf = b;
    io->cap = cap;
  }
  memcpy(io->buf + io->len, p, n);
  io->len += n;
}
