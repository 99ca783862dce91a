/* term.c — what every energy term shares: stencil storage. */
#include "terms.h"
#include "util.h"

int sw_term_alloc_stencils(sw_term *t, int nstencil, int per, int dim) {
  t->nstencil = nstencil;
  t->sptr = sw_calloc((size_t)nstencil + 1, sizeof(int));
  t->sidx = sw_calloc((size_t)nstencil * (size_t)per, sizeof(int));
  t->hptr = sw_calloc((size_t)nstencil + 1, sizeof(long));
  if (!t->sptr || !t->sidx || !t->hptr) return -1;
  long block = (long)(per * dim) * (per * dim);
  for (int s = 0; s <= nstencil; s++) {
    t->sptr[s] = s * per;
    t->hptr[s] = (long)s * block;
  }
  return 0;
}

void sw_term_free(sw_term *t) {
  if (t->ops && t->ops->free_param) t->ops->free_param(t->param);
  sw_free(t->sptr);
  sw_free(t->sidx);
  sw_free(t->hptr);
  sw_free(t->lptr);
  sw_free(t->lidx);
  t->sptr = t->sidx = t->lptr = t->lidx = NULL;
  t->nlowrank = 0;
  t->hptr = NULL;
  t->param = NULL;
}
