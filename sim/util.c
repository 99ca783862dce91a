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

double sw_cpu_now(void) {
  struct timespec ts;
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts)) return 0.0;
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ------------------------------------------------ hashing (util.h) */

uint64_t sw_hash64(uint64_t h, const void *p, size_t n) {
  const unsigned char *b = p;
  for (size_t i = 0; i < n; i++) h = (h ^ b[i]) * 1099511628211u;
  return h;
}

/* The slot holding name, or the empty slot where it goes. */
static size_t names_slot(const sw_names *t, const char *name) {
  size_t mask = t->nslot - 1, i = (size_t)sw_hash64(SW_HASH0, name, strlen(name)) & mask;
  while (t->key[i] && strcmp(t->key[i], name)) i = (i + 1) & mask;
  return i;
}

int sw_names_find(const sw_names *t, const char *name) {
  if (!t->nslot) return -1;
  size_t i = names_slot(t, name);
  return t->key[i] ? t->val[i] : -1;
}

/* Room for one more name with the table at most half full; -1 when out of memory. */
static int names_grow(sw_names *t) {
  if (2 * (t->n + 1) <= t->nslot) return 0;
  sw_names b = {.nslot = t->nslot ? 2 * t->nslot : 64, .n = t->n};
  b.key = sw_calloc(b.nslot, sizeof *b.key);
  b.val = sw_calloc(b.nslot, sizeof *b.val);
  if (!b.key || !b.val) return sw_free(b.key), sw_free(b.val), -1;
  for (size_t i = 0; i < t->nslot; i++)
    if (t->key[i]) {
      size_t j = names_slot(&b, t->key[i]);
      b.key[j] = t->key[i], b.val[j] = t->val[i];
    }
  sw_names_free(t);
  *t = b;
  return 0;
}

int sw_names_add(sw_names *t, const char *name, int val) {
  if (names_grow(t)) return -2;
  size_t i = names_slot(t, name);
  if (t->key[i]) return t->val[i];
  t->key[i] = name, t->val[i] = val, t->n++;
  return -1;
}

void sw_names_free(sw_names *t) {
  sw_free(t->key);
  sw_free(t->val);
  memset(t, 0, sizeof *t);
}

/* ------------------------------------------------ restart files (util.h) */

void sw_io_bytes(sw_io *io, void *p, size_t n) {
  uint64_t size = n;
  io->shape = sw_hash64(io->shape ? io->shape : SW_HASH0, &size, sizeof size);
  if (io->bad || n == 0) return; /* n == 0: p may be NULL (an empty array) */
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
