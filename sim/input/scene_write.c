/* scene_write.c — write a scene back with new tendon rest lengths (the output of
 * `sinew inverse`, docs/inverse.md).  The original file is parsed with libfyaml's document API,
 * each item of `tendons` gets `rest_length: alpha` (replacing a number, {relative: ...} or
 * {keyframes: ...}, or added), and the document is emitted in block style (libfyaml 0.7.12
 * spreads flow sequences over many lines in its "original" mode; comments are not kept: its
 * comment support is experimental and misplaces them).  The file is written
 * to a temporary file beside `out` and renamed over it, so a reader never sees half of it. */
#include <errno.h>
#include <libfyaml.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sinew.h"
#include "util.h"

/* The shortest %.{15,16,17}g that reads back as v exactly. */
static void exact_number(double v, char *buf, size_t sz) {
  for (int p = 15; p <= 17; p++) {
    snprintf(buf, sz, "%.*g", p, v);
    if (strtod(buf, NULL) == v) return;
  }
}

/* Set rest_length of one tendon map to rest (m). */
static int set_rest(struct fy_document *fyd, struct fy_node *item, double rest) {
  char num[40];
  exact_number(rest, num, sizeof num);
  struct fy_node *val = fy_node_create_scalar_copy(fyd, num, strlen(num));
  if (!val) return -1;
  struct fy_node_pair *p = fy_node_mapping_lookup_pair_by_string(item, "rest_length", FY_NT);
  if (p) return fy_node_pair_set_value(p, val);
  struct fy_node *key = fy_node_create_scalar(fyd, "rest_length", FY_NT);
  if (!key) return fy_node_free(val), -1;
  if (fy_node_mapping_append(item, key, val)) return fy_node_free(key), fy_node_free(val), -1;
  return 0;
}

static int set_all(struct fy_document *fyd, const sw_model *m, const double *rest,
                   const char *scene, char *err, size_t errsz) {
  struct fy_node *root = fy_document_root(fyd);
  struct fy_node *td = root ? fy_node_mapping_lookup_by_string(root, "tendons", FY_NT) : NULL;
  if (!td || !fy_node_is_sequence(td) || fy_node_sequence_item_count(td) != m->ntendon)
    return sw_errf(err, errsz, "%s: its tendons sequence does not match the %d tendons of the "
                   "model", scene, m->ntendon), -1;
  for (int k = 0; k < m->ntendon; k++) {
    struct fy_node *item = fy_node_sequence_get_by_index(td, k);
    if (!item || !fy_node_is_mapping(item) || set_rest(fyd, item, rest[k]))
      return sw_errf(err, errsz, "%s: cannot set the rest length of tendon %s", scene,
                     m->tendon[k].name), -1;
  }
  return 0;
}

/* Emit fyd to a temporary file beside out, then rename it to out. */
static int emit_atomic(struct fy_document *fyd, const char *out, char *err, size_t errsz) {
  char tmp[SW_PATHSZ + 16];
  if (snprintf(tmp, sizeof tmp, "%s.XXXXXX", out) >= (int)sizeof tmp)
    return sw_errf(err, errsz, "%s: path too long", out), -1;
  int fd = mkstemp(tmp);
  if (fd < 0) return sw_errf(err, errsz, "%s: cannot create: %s", out, strerror(errno)), -1;
  FILE *fp = fchmod(fd, 0644) == 0 ? fdopen(fd, "w") : NULL; /* mkstemp made it 0600 */
  if (!fp) {
    sw_errf(err, errsz, "%s: cannot write: %s", out, strerror(errno));
    return close(fd), unlink(tmp), -1;
  }
  int bad = fy_emit_document_to_fp(fyd, FYECF_MODE_PRETTY | FYECF_WIDTH_INF | FYECF_INDENT_DEFAULT |
                                         FYECF_DOC_START_MARK_OFF, fp) != 0;
  bad |= fflush(fp) != 0 || fsync(fileno(fp)) != 0;
  int saved = errno;
  bad |= fclose(fp) != 0;
  if (!bad && rename(tmp, out) == 0) return 0;
  if (!bad) saved = errno;
  sw_errf(err, errsz, "%s: cannot write: %s", out, saved ? strerror(saved) : "emitter failed");
  unlink(tmp);
  return -1;
}

int sw_scene_write_rest(const char *scene, const char *out, const sw_model *m,
                        const double *rest, char *err, size_t errsz) {
  struct fy_parse_cfg cfg = {.flags = FYPCF_QUIET};
  struct fy_document *fyd = fy_document_build_from_file(&cfg, scene);
  if (!fyd) return sw_errf(err, errsz, "%s: cannot parse the scene again", scene), -1;
  int rc = set_all(fyd, m, rest, scene, err, errsz);
  if (!rc) rc = emit_atomic(fyd, out, err, errsz);
  fy_document_destroy(fyd);
  return rc;
}
