/* scene.h — internal entry of the scene loader: parse a scene file already in memory.
 * sw_scene_load (sinew.h) reads the file and calls this; the fuzzer calls it directly. */
#ifndef SW_SCENE_H
#define SW_SCENE_H

#include "sinew.h"

#include <stddef.h>

/* A grid with more vertices than this is refused (a fuzzing build may lower it with -D). */
#ifndef SW_SCENE_MAX_VERTICES
#define SW_SCENE_MAX_VERTICES 1000000L
#endif
#define SW_SCENE_MAX_BYTES (64L << 20) /* a larger scene file is refused, bytes */
#define SW_SCENE_MAX_DEPTH 32          /* deeper YAML nesting is refused */
/* More YAML values (scalars, sequences, mappings) than this are refused as they are read: each
 * costs up to about 520 bytes while the scene is parsed (our node, its text, and libfyaml's
 * tokens of a flow sequence), so the loader stays below about 1 GB. */
#ifndef SW_SCENE_MAX_VALUES
#define SW_SCENE_MAX_VALUES 2000000L
#endif

/* Parse len bytes of YAML (need not be NUL-terminated; a NUL byte is an error) as the scene
 * file `name`: name is used in messages ("name:line:column: ..."), gives the default scene
 * name and output folder (its stem) and the folder OBJ paths are relative to.  Returns a
 * finished model, or NULL with the message in err. */
sw_model *sw_scene_parse(const char *name, const char *buf, size_t len, char *err, size_t errsz);
/* The same with overrides (sinew.h, sw_scene_load_ex; ov NULL: none). */
sw_model *sw_scene_parse_ex(const char *name, const char *buf, size_t len,
                            const sw_scene_overrides *ov, char *err, size_t errsz);

#endif
