/* aside.c — a rerun into a folder that holds an earlier run (writer.h).
 *
 * The earlier run's files (those its sinew.manifest names, with their .tmp and .part forms, then
 * the manifest itself) are renamed into the hidden folder DIR/.sinew-earlier/ (frames into
 * .sinew-earlier/frames/), each in one rename(2) inside the folder's own filesystem, so none is
 * ever half-moved.  The new run then starts; only once its first files are written
 * (sw_output_open succeeded) is .sinew-earlier/ removed.  A move that fails part-way, or a new
 * run that cannot start, puts every moved file back (after the new run's files are removed),
 * so the earlier run is either wholly kept or wholly replaced.
 *
 * A .sinew-earlier/ found when a run starts is the leftover of a run killed in between: its
 * files are moved back when the folder holds no complete earlier or new run (either manifest
 * missing: the kill came before the new run began), and removed otherwise (the new run had
 * begun, or only its removal was cut short). */
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util.h"
#include "writer.h"

#define ASIDE ".sinew-earlier"

/* buf = DIR/.sinew-earlier/name (name NULL: the folder itself). */
static int aside_path(char *buf, const sw_output *o, const char *name, char *err, size_t errsz) {
  char rel[SW_OUT_PATHMAX];
  if (name) snprintf(rel, sizeof rel, ASIDE "/%s", name);
  else snprintf(rel, sizeof rel, ASIDE);
  return out_join(buf, o->dir, rel, err, errsz);
}

static int exists(const char *path) {
  struct stat st;
  return lstat(path, &st) == 0;
}

/* fn(o, name, ctx) for each entry of .sinew-earlier/frames/ ("frames/NAME") and then of
 * .sinew-earlier/ (but frames/ itself), until one returns nonzero (then that value); -1 with
 * err when a folder cannot be listed. */
static int each_aside(sw_output *o, int (*fn)(sw_output *o, const char *name, void *ctx),
                      void *ctx, char *err, size_t errsz) {
  static const char *const sub[] = {"frames/", ""};
  for (int k = 0; k < 2; k++) {
    char dir[SW_OUT_PATHMAX];
    if (aside_path(dir, o, k == 0 ? "frames" : NULL, err, errsz)) return -1;
    DIR *dp = opendir(dir);
    if (!dp && errno == ENOENT) continue;
    if (!dp) return sw_errf(err, errsz, "%s: cannot list: %s", dir, strerror(errno)), -1;
    int rc = 0;
    for (struct dirent *e; !rc && (e = readdir(dp));) {
      if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..") || (k == 1 && !strcmp(e->d_name, "frames")))
        continue;
      char name[SW_OUT_PATHMAX];
      snprintf(name, sizeof name, "%s%s", sub[k], e->d_name);
      rc = fn(o, name, ctx);
    }
    closedir(dp);
    if (rc) return rc;
  }
  return 0;
}

typedef struct tally {
  int failed;          /* files that could not be moved back (removed) */
  char *err;           /* the first failure's message */
  size_t errsz;
} tally;

/* Move .sinew-earlier/name back to DIR/name (it replaces a file of that name). */
static int move_back(sw_output *o, const char *name, void *ctx) {
  tally *t = ctx;
  char from[SW_OUT_PATHMAX], to[SW_OUT_PATHMAX];
  if (aside_path(from, o, name, t->err, t->errsz) || out_join(to, o->dir, name, t->err, t->errsz) ||
      rename(from, to)) {
    if (!t->failed++ && errno) sw_errf(t->err, t->errsz, "%s: cannot move back: %s", from, strerror(errno));
  }
  return 0;
}

/* Remove .sinew-earlier/name. */
static int drop(sw_output *o, const char *name, void *ctx) {
  tally *t = ctx;
  char path[SW_OUT_PATHMAX];
  if (aside_path(path, o, name, t->err, t->errsz) || unlink(path)) {
    if (!t->failed++ && errno) sw_errf(t->err, t->errsz, "%s: cannot remove: %s", path, strerror(errno));
  }
  return 0;
}

/* Each file of .sinew-earlier/ moved back (back) or removed, then the folder removed; -1 with
 * the first failure in err (the files that failed stay in .sinew-earlier/). */
static int empty_aside(sw_output *o, int back, char *err, size_t errsz) {
  tally t = {0, err, errsz};
  if (each_aside(o, back ? move_back : drop, &t, err, errsz)) return -1;
  char path[SW_OUT_PATHMAX];
  if (aside_path(path, o, "frames", err, errsz)) return -1;
  if (rmdir(path) && errno != ENOENT && !t.failed++)
    sw_errf(err, errsz, "%s: cannot remove: %s", path, strerror(errno));
  if (aside_path(path, o, NULL, err, errsz)) return -1;
  if (rmdir(path) && errno != ENOENT && !t.failed++)
    sw_errf(err, errsz, "%s: cannot remove: %s", path, strerror(errno));
  if (t.failed && !*err) sw_errf(err, errsz, "%s: %d files could not be moved", path, t.failed);
  return t.failed ? -1 : 0;
}

int out_aside_recover(sw_output *o, char *err, size_t errsz) {
  char path[SW_OUT_PATHMAX], manifest[SW_OUT_PATHMAX];
  struct stat st;
  if (aside_path(path, o, NULL, err, errsz)) return -1;
  if (lstat(path, &st) && errno == ENOENT) return 0;
  if (!S_ISDIR(st.st_mode))
    return sw_errf(err, errsz, "%s: not a folder; expected the folder where sinew moves an "
                   "earlier run's files: remove it", path),
           -1;
  if (aside_path(manifest, o, "sinew.manifest", err, errsz)) return -1;
  int whole = exists(manifest);
  if (out_join(manifest, o->dir, "sinew.manifest", err, errsz)) return -1;
  whole = whole && exists(manifest);
  char why[SW_ERRSZ] = "";
  if (!empty_aside(o, !whole, why, sizeof why)) return 0;
  return sw_errf(err, errsz, "%s: the files of an earlier run left there by a run that was "
                 "stopped cannot be %s (%s); expected to %s them: nothing written",
                 path, whole ? "removed" : "moved back", why, whole ? "remove" : "move back"),
         -1;
}

/* Move DIR/name (if present) into .sinew-earlier/. */
static int move_aside(sw_output *o, const char *name, char *err, size_t errsz) {
  char from[SW_OUT_PATHMAX], to[SW_OUT_PATHMAX];
  if (out_join(from, o->dir, name, err, errsz) || aside_path(to, o, name, err, errsz)) return -1;
  if (!exists(from)) return 0;
  o->aside = 1;
  if (rename(from, to) == 0) return 0;
  return sw_errf(err, errsz, "%s: cannot move the earlier run's file aside (to %s): %s", from, to,
                 strerror(errno)),
         -1;
}

typedef struct mover {
  sw_output *o;
  char *err;
  size_t errsz;
} mover;

static int move_form(void *ctx, const char *file) {
  mover *mv = ctx;
  return move_aside(mv->o, file, mv->err, mv->errsz) ? -1 : 0;
}

/* NAME, NAME.tmp and NAME.part into .sinew-earlier/. */
static int move_old(void *ctx, const char *name) { return out_name_forms(name, move_form, ctx); }

int out_aside_move(sw_output *o, int (*each)(const sw_output *, int (*)(void *, const char *), void *),
                   char *err, size_t errsz) {
  char path[SW_OUT_PATHMAX];
  if (aside_path(path, o, NULL, err, errsz)) return -1;
  if (mkdir(path, 0777))
    return sw_errf(err, errsz, "%s: cannot make the folder for the earlier run's files: %s", path,
                   strerror(errno)),
           -1;
  o->aside = 1;
  mover mv = {o, err, errsz};
  if (aside_path(path, o, "frames", err, errsz)) return -1;
  if (mkdir(path, 0777))
    return sw_errf(err, errsz, "%s: cannot make the folder for the earlier run's files: %s", path,
                   strerror(errno)),
           -1;
  /* the manifest last: a .sinew-earlier/ with a manifest holds the whole earlier run */
  return each(o, move_old, &mv) || move_aside(o, "sinew.manifest", err, errsz) ? -1 : 0;
}

int out_aside_back(sw_output *o, char *err, size_t errsz) {
  if (!o->aside) return 0;
  if (empty_aside(o, 1, err, errsz)) return -1;
  o->aside = 0;
  return 0;
}

void out_aside_drop(sw_output *o) {
  char err[SW_ERRSZ] = "";
  if (!o->aside) return;
  o->aside = 0;
  if (empty_aside(o, 0, err, sizeof err))
    fprintf(stderr, "sinew: warning: the earlier run's files, moved aside, could not all be "
            "removed (%s); the new run goes on; the next run into %s/ removes them\n", err, o->dir);
}
