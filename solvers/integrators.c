/* integrators.c — the registry of time integrators (each one file in solvers/) and of the
 * static solve, which the run loop treats as a method of its own. */
#include <string.h>

#include "solver.h"

static const sw_integrator_ops *const registry[] = {
    &sw_backward_euler_ops,
    &sw_baraff_witkin_ops,
    NULL,
};

static const char *const names[] = {"backward-euler", "baraff-witkin", "static", NULL};

const sw_integrator_ops *sw_integrator_find(const char *name) {
  for (int k = 0; registry[k]; k++)
    if (!strcmp(registry[k]->name, name)) return registry[k];
  return NULL;
}

const char *const *sw_method_names(void) { return names; }
