/* render.c — the subcommands written in Python: `sinew render RUN_DIR ...` (the pictures of a
 * run folder, python/sinew/render.py, matplotlib), `sinew pattern ...` (pattern import from
 * DXF, python/sinew/pattern/, ezdxf and gmsh) and `sinew drape RUN_DIR` (the drape coefficient
 * and nodes of a Cusick drape test run, python/sinew/drape.py, numpy) and `sinew garment FILE.dxf`
 * (a DXF pattern sewn, arranged and fitted, python/sinew/garment.py, which runs this program's
 * `run`: SINEW_EXE names it).  Each runs as `PYTHON -m sinew.MODULE ARGS`
 * with the package's folders (the installed package beside this program, when there is one;
 * the source tree's python/ and where meson install puts it, unless built as a wheel) before any
 * PYTHONPATH already set.  SW_PYTHON and SW_PYTHONPATH are set by meson.build. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

/* Replace this process by `SW_PYTHON -m module argv[2:]`; returns 2 only on failure. */
static int run_module(const char *cmd, const char *module, int argc, char **argv) {
  const char *old = getenv("PYTHONPATH");
  char pkg[4096] = "";
  int installed = !cli_package_dir(pkg, sizeof pkg);
  size_t n = strlen(pkg) + strlen(SW_PYTHONPATH) + (old ? strlen(old) : 0) + 3;
  char *path = malloc(n);
  char **args = calloc((size_t)argc + 2, sizeof *args);
  if (!path || !args) return fprintf(stderr, "sinew %s: out of memory\n", cmd), 2;
  snprintf(path, n, "%s%s%s", installed ? pkg : "", installed && *SW_PYTHONPATH ? ":" : "",
           SW_PYTHONPATH);
  if (old && *old) snprintf(path + strlen(path), n - strlen(path), "%s%s", *path ? ":" : "", old);
  if (setenv("PYTHONPATH", path, 1))
    return fprintf(stderr, "sinew %s: cannot set PYTHONPATH: %s\n", cmd, strerror(errno)), 2;
  char exe[4096];
  ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (len > 0) exe[len] = 0, setenv("SINEW_EXE", exe, 1);
  args[0] = SW_PYTHON;
  args[1] = "-m";
  args[2] = (char *)module;
  for (int i = 2; i < argc; i++) args[i + 1] = argv[i];
  execv(SW_PYTHON, args);
  fprintf(stderr, "sinew %s: cannot run %s: %s (the meson option python names it)\n", cmd,
          SW_PYTHON, strerror(errno));
  return 2;
}

int cli_render(int argc, char **argv) { return run_module("render", "sinew.render", argc, argv); }

int cli_pattern(int argc, char **argv) { return run_module("pattern", "sinew.pattern", argc, argv); }

int cli_drape(int argc, char **argv) { return run_module("drape", "sinew.drape", argc, argv); }

int cli_garment(int argc, char **argv) {
  return run_module("garment", "sinew.garment", argc, argv);
}
