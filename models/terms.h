/* terms.h — constructors of the energy terms (one file each in models/) and the shared
 * helpers they use to declare their Hessian stencils. */
#ifndef SW_TERMS_H
#define SW_TERMS_H

#include <stddef.h>

#include "sinew.h"

/* Allocate nstencil stencils of `per` vertices each (sidx left for the caller to fill) and
 * set hptr for blocks of (per*dim)^2 doubles.  Nonzero when out of memory. */
int sw_term_alloc_stencils(sw_term *t, int nstencil, int per, int dim);
void sw_term_free(sw_term *t);

/* models/bw98.c: Baraff-Witkin stretch and shear on every face (seed 002, DESIGN.md). */
int sw_bw98_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* models/tendon.c: every tendon of the model in one term "tendons" (seed 003, DESIGN.md
 * "Tendons", docs/tendons.md): tendons of at most m->opt.tendon_dense_max waypoints as one
 * dense stencil each; longer ones as one 2-vertex stencil per segment (E' d2Delta) and one
 * low-rank vector sqrt(E'') grad(Delta). */
int sw_tendon_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* models/gravity.c: E = -sum_i m_i g.x_i (no Hessian, no stencils). */
int sw_gravity_build(sw_term *t, const sw_model *m, char *err, size_t errsz);

/* models/point_load.c: E = -sum_i f_i . x_i with f = m->load (no Hessian, no stencils). */
int sw_point_load_build(sw_term *t, const sw_model *m, char *err, size_t errsz);

/* models/tension_xy.c: the reference stretch rlu, rlv of every face (seed 000). */
void sw_tension_xy_reference(const sw_model *m, sw_data *d);

/* The deformation gradient F = Ds Dm^-1 = [wu wv] of face f at positions x (seeds 000/001),
 * with the coefficients that make it linear in the corners: wu = sum_i cu[i] x_i,
 * wv = sum_i cv[i] x_i.  wu, wv have m->dim components. */
void sw_face_coeffs(const sw_model *m, int f, double cu[3], double cv[3]);
void sw_face_F(const sw_model *m, int f, const double *x, double *wu, double *wv);

#endif
