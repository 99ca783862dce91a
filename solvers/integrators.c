/* integrators.c — the registry of time integrators (each one file in solvers/) and of the
 * static solve, which the run loop treats as a method of its own. */
#include <string.h>

#include "solver.h"

static const sw_integrator_ops *const registry[] = {
    &sw_backward_euler_ops,
    &sw_baraff_witkin_ops,
    &sw_bdf2_ops, &sw_implicit_midpoint_ops, &sw_newmark_ops, &sw_symplectic_euler_ops,
    &sw_cvode_ops, &sw_ida_ops,
    NULL,
};

static const char *const names[] = {"backward-euler", "baraff-witkin", "bdf2", "implicit-midpoint",
                                     "newmark", "symplectic-euler", "cvode", "ida", "static", NULL};

const sw_integrator_ops *sw_integrator_find(const char *name) {
  for (int k = 0; registry[k]; k++)
    if (!strcmp(registry[k]->name, name)) return registry[k];
  return NULL;
}

const char *const *sw_method_names(void) { return names; }

const char *sw_method_summary(const char *name) {
  if (!name) return NULL;
  if (!strcmp(name, "static")) return "equilibrium: minimise U(x) by Newton (no dynamics)";
  const sw_integrator_ops *ops = sw_integrator_find(name);
  return ops ? ops->summary : NULL;
}

int sw_method_adaptive(const char *name) {
  if (!name) return -1;
  if (!strcmp(name, "static")) return 0;
  const sw_integrator_ops *ops = sw_integrator_find(name);
  return ops ? (ops->adaptive != 0) : -1;
}
