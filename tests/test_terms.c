/* test_terms.c — bw98 and gravity through the conformance harness (tests/conformance.c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "harness.h"

static void conformance(int dim, int is_gravity) {
  const double g[3] = {0.5, -2.0, -9.81};
  sw_model *m = th_grid_model(dim, 4, 3, 0.3, 0.2, 0.2, 400.0, 35.0, is_gravity ? g : NULL, 0);
  assert_non_null(m);
  th_conformance(m, is_gravity ? "gravity" : "bw98", is_gravity ? 0 : TH_INTERNAL | TH_REST_FREE,
                 0.3, 12345 + (unsigned long)dim);
  sw_model_free(m);
}

static void bw98_3d(void **st) { (void)st, conformance(3, 0); }
static void bw98_2d(void **st) { (void)st, conformance(2, 0); }
static void gravity_3d(void **st) { (void)st, conformance(3, 1); }
static void gravity_2d(void **st) { (void)st, conformance(2, 1); }

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(bw98_3d),
      cmocka_unit_test(bw98_2d),
      cmocka_unit_test(gravity_3d),
      cmocka_unit_test(gravity_2d),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
