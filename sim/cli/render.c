/* render.c — `sinew render RUN_DIR ...`: the pictures of a run folder are drawn by the Python
 * module sinew.render (python/sinew/render.py, matplotlib); this runs it as
 * `PYTHON -m sinew.render ARGS` with the package's folders (the source tree's python/, then
 * where meson install puts it) before any PYTHONPATH already set.  SW_PYTHON and
 * SW_PYTHONPATH are set by meson.build. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

int cli_render(int argc, char **argv) {
  const char *old = getenv("PYTHONPATH");
  size_t n = strlen(SW_PYTHONPATH) + (old ? strlen(old) + 2 : 1);
  char *path = malloc(n);
  char **args = calloc((size_t)argc + 2, sizeof *args);
  if (!path || !args) return fprintf(stderr, "sinew render: out of memory\n"), 2;
  snprintf(path, n, "%s%s%s", SW_PYTHONPATH, old && *old ? ":" : "", old && *old ? old : "");
  if (setenv("PYTHONPATH", path, 1))
    return fprintf(stderr, "sinew render: cannot set PYTHONPATH: %s\n", strerror(errno)), 2;
  args[0] = SW_PYTHON;
  args[1] = "-m";
  args[2] = "sinew.render";
  for (int i = 2; i < argc; i++) args[i + 1] = argv[i];
  execv(SW_PYTHON, args);
  fprintf(stderr, "sinew render: cannot run %s: %s (the meson option python names it)\n",
          SW_PYTHON, strerror(errno));
  return 2;
}
