/* cli.h — argument checks shared by the subcommands of the sinew executable (main.c, bench.c):
 * each prints "sinew: OPT expects ..., got 'S'" and returns -1 on a bad value. */
#ifndef SW_CLI_H
#define SW_CLI_H

#include <stddef.h>

/* A positive number (>= 0 when allow_zero). */
int cli_number(const char *opt, const char *s, int allow_zero, double *out);
/* An integer in [lo, hi]. */
int cli_int(const char *opt, const char *s, int lo, int hi, int *out);
/* 1 if name is a method of sw_method_names(). */
int cli_known_method(const char *name);
/* `sinew render ARGS` (render.c): runs Python's sinew.render in this process; returns only on
 * failure (2). */
int cli_render(int argc, char **argv);
/* `sinew pattern ARGS` (render.c): runs Python's sinew.pattern (DXF pattern import) likewise. */
int cli_pattern(int argc, char **argv);
int cli_drape(int argc, char **argv);
int cli_garment(int argc, char **argv);
/* The folder holding the package sinew/ installed beside this program (render.c): 0, or -1. */
int cli_package_dir(char *dir, size_t size);

#endif
