/* newton.c — Newton's method with a backtracking line search on an incremental potential
 *   Phi(x) = a/2 (x - xhat)^T M (x - xhat) + U(x, t)
 * over the free DOFs (backward Euler is its minimiser with a = 1/h^2).  An iteration solves
 * S dx = -grad Phi with S = a M + H (+ cd D), H the terms' Hessian filtered per element as the
 * `hessian` mode asks: by a fresh factorisation, or (reuse) by conjugate gradients on this S
 * preconditioned with the last factorisation (reuse step: the factorisation of the solve's
 * first S), renewed only when CG slows down (Newton-Krylov
 * with a lagged preconditioner: Knoll and Keyes, "Jacobian-free Newton-Krylov methods: a
 * survey of approaches and applications", J. Comput. Phys. 2004; the direction stays Newton's
 * to CG's tolerance, so the iterates do not change beyond it).
 * It stops when max |dx| <= tol_dx (a velocity tolerance times the step), or when max |dx| is
 * at the round-off of the positions themselves (1e3 eps max |x|): a strict tolerance then
 * still converges, it never fails on round-off (docs/integrators.md). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "solver.h"
#include "terms.h"
#include "util.h"

/* The per-stencil flags and the buffer of clamped blocks of `hessian: progressive`. */
static int stencil_init(sw_newton *nw, const sw_model *m) {
  if (m->opt.hessian != SW_HESSIAN_PROGRESSIVE) return 0;
  nw->soff = sw_calloc((size_t)m->nterm + 1, sizeof(long));
  if (!nw->soff) return -1;
  long nh = 0;
  for (int k = 0; k < m->nterm; k++) {
    nw->soff[k + 1] = nw->soff[k] + m->term[k].nstencil;
    nh += m->term[k].hptr[m->term[k].nstencil];
  }
  nw->flag = sw_calloc((size_t)nw->soff[m->nterm] + 1, 1);
  nw->hfilt = sw_calloc((size_t)nh + 1, sizeof(double));
  nw->vres = sw_calloc((size_t)m->nv + 1, sizeof(double));
  return (!nw->flag || !nw->hfilt || !nw->vres) ? -1 : 0;
}

/* The weights of the RMS norm: w_c = dim m_c / sum m_c over the free DOFs, so that
 * sqrt(sum w_c dx_c^2) is the mass-weighted RMS of the vertices' |dx_i| (uniform if massless). */
static int weights_init(sw_newton *nw, const sw_model *m) {
  nw->wdof = sw_calloc((size_t)nw->n + 1, sizeof(double));
  if (!nw->wdof) return -1;
  double total = 0.0;
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] >= 0) total += m->mass[i / m->dim];
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] >= 0)
      nw->wdof[m->dof[i]] = total > 0.0 ? m->dim * m->mass[i / m->dim] / total
                                        : (double)m->dim / nw->n;
  return 0;
}

int sw_newton_init(sw_newton *nw, const sw_model *m, char *err, size_t errsz) {
  memset(nw, 0, sizeof *nw);
  nw->n = m->ndof;
  nw->nterm = m->nterm;
  nw->friction = sw_terms_dissipate(m);
  int rc = sw_pattern_build(&nw->pat, m, err, errsz);
  if (rc) return rc;
  nw->factor_mode = SW_CHOL_MODE(m->opt.factorization, m->opt.ordering);
  if (nw->n > 0 && (rc = sw_chol_init(&nw->chol, &nw->pat, nw->factor_mode, err, errsz)))
    return rc;
  nw->g = sw_calloc((size_t)nw->n, sizeof(double));
  nw->dx = sw_calloc((size_t)nw->n, sizeof(double));
  nw->xtry = sw_calloc((size_t)m->nv * (size_t)m->dim, sizeof(double));
  int nclip = 0;
  for (int k = 0; k < m->nterm; k++) {
    nclip += m->term[k].ops->clip != NULL;
    nw->nblock_terms += m->term[k].ops->blocks != NULL;
  }
  nw->tfrac = sw_calloc((size_t)m->nterm + 1, sizeof(double));
  if (nclip > 0) nw->vfrac = sw_calloc((size_t)m->nv, sizeof(double));
  if (nclip > 0) nw->vheld = sw_calloc((size_t)m->nv, sizeof(double));
  if (nclip > 1) nw->vtmp = sw_calloc((size_t)m->nv, sizeof(double));
  if (!nw->tfrac || (nclip > 0 && (!nw->vfrac || !nw->vheld)) || (nclip > 1 && !nw->vtmp)) {
    sw_errf(err, errsz, "out of memory for Newton's workspaces (%d DOFs)", nw->n);
    return SW_FATAL;
  }
  size_t nlrent = (size_t)nw->pat.lrptr[nw->pat.nlr];
  if (nw->n > 0) nw->sval = sw_chol_values(&nw->chol); /* sval_for sets it per solve */
  else nw->sval = nw->sown = sw_calloc(1, sizeof(double));
  nw->lrcur = sw_calloc(nlrent + 1, sizeof(double));
  int nocg = !nw->sval || !nw->lrcur; /* CG's own vectors at its first solve (pcg) */
  int damped = sw_damped(m);
  if (damped) {
    nw->dval = sw_calloc((size_t)nw->pat.nnz + 1, sizeof(double));
    nw->r = sw_calloc((size_t)nw->n + 1, sizeof(double));
    nw->dr = sw_calloc((size_t)nw->n + 1, sizeof(double));
  }
  if (!nw->g || !nw->dx || !nw->xtry || nocg || (damped && (!nw->dval || !nw->r || !nw->dr)) ||
      stencil_init(nw, m) || weights_init(nw, m)) {
    sw_errf(err, errsz, "out of memory for Newton's workspaces (%d DOFs)", nw->n);
    return SW_FATAL;
  }
  return SW_OK;
}

void sw_newton_free(sw_newton *nw) {
  sw_chol_free(&nw->chol);
  sw_pattern_free(&nw->pat);
  sw_free(nw->g);
  sw_free(nw->dx);
  sw_free(nw->xtry);
  sw_free(nw->dval);
  sw_free(nw->r);
  sw_free(nw->dr);
  sw_free(nw->soff);
  sw_free(nw->flag);
  sw_free(nw->hfilt);
  sw_free(nw->vres);
  sw_free(nw->wdof);
  sw_free(nw->vfrac);
  sw_free(nw->vtmp);
  sw_free(nw->vheld);
  sw_free(nw->tfrac);
  sw_free(nw->xpair);
  sw_free(nw->ktab);
  sw_free(nw->kv);
  sw_free(nw->kslot);
  sw_free(nw->sown);
  sw_free(nw->lrcur);
  sw_free(nw->cr);
  sw_free(nw->cz);
  sw_free(nw->cp);
  sw_free(nw->cq);
  memset(nw, 0, sizeof *nw);
}

void sw_newton_forget(sw_newton *nw) {
  nw->fac_valid = nw->fac_stale = nw->backoff = nw->skip = 0;
  nw->theta = 0.0;
}

void sw_newton_history(sw_newton *nw, sw_io *io) {
  int keep = nw->fac_valid && nw->nxpair == 0 && nw->n > 0;
  sw_io_bytes(io, &keep, sizeof keep);
  sw_io_bytes(io, &nw->fac_stale, sizeof nw->fac_stale);
  sw_io_bytes(io, &nw->backoff, sizeof nw->backoff);
  sw_io_bytes(io, &nw->skip, sizeof nw->skip);
  sw_io_bytes(io, &nw->theta, sizeof nw->theta);
  if (!keep) {
    nw->fac_valid = 0;
    return;
  }
  sw_io_bytes(io, sw_chol_values(&nw->chol), (size_t)nw->pat.nnz * sizeof(double));
  if (nw->pat.nlr)
    sw_io_bytes(io, sw_chol_lowrank(&nw->chol, 1.0),
                (size_t)nw->pat.lrptr[nw->pat.nlr] * sizeof(double));
  if (io->load) {
    char err[SW_ERRSZ];
    nw->fac_valid = sw_chol_factor(&nw->chol, err, sizeof err) == SW_OK;
  }
}

int sw_newton_damping(sw_newton *nw, const sw_model *m, sw_data *d, const double *x, double t) {
  if (!nw->dval) return SW_OK;
  double u, beta = m->damp_stiffness, t0 = sw_now();
  memset(nw->dval, 0, (size_t)nw->pat.nnz * sizeof(double));
  if (beta > 0.0) { /* the clamped blocks straight into D */
    int rc = sw_eval_terms_into(m, d, x, t, 0, 1, nw->dval, &nw->pat.slots, &u);
    if (rc) return rc;
    sw_pattern_finish(&nw->pat, m, m->damp_mass, beta, nw->dval);
  } else { /* alpha M alone: no Hessian needed */
    for (int i = 0; i < m->nv * m->dim; i++)
      if (m->dof[i] >= 0) nw->dval[nw->pat.diag[m->dof[i]]] = m->damp_mass * m->mass[i / m->dim];
  }
  sw_damping_tendons_fill(&nw->pat, m, x, nw->dval);
  d->time_assemble += sw_now() - t0;
  return SW_OK;
}

/* cd/2 r.D r with r = x - xd on the free DOFs; its gradient cd D r into nw->dr. */
static double damping_phi(sw_newton *nw, const sw_model *m, const double *x) {
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] >= 0) nw->r[m->dof[i]] = x[i] - nw->xd[i];
  sw_pattern_symv(&nw->pat, nw->dval, nw->r, nw->dr);
  double e = 0.0;
  for (int c = 0; c < nw->n; c++) {
    nw->dr[c] *= nw->cd;
    e += 0.5 * nw->r[c] * nw->dr[c];
  }
  return e;
}

/* The terms at x, their Hessian (when asked) into d->hess, or with into straight into nw->sval
 * from zero (sw_eval_terms_into through the pattern's slots). */
static int eval_terms(sw_newton *nw, const sw_model *m, sw_data *d, const double *x, double t,
                      int want_grad, int want_hess, int project, int into, double *u) {
  if (!want_hess || !into) return sw_eval_terms(m, d, x, t, want_grad, want_hess, project, u);
  memset(nw->sval, 0, (size_t)nw->pat.nnz * sizeof(double));
  return sw_eval_terms_into(m, d, x, t, want_grad, project, nw->sval, &nw->pat.slots, u);
}

/* sw_newton_phi, the Hessian into nw->sval with into. */
static int phi_eval(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                    const double *xhat, double a, double t, int want_grad, int want_hess,
                    int project, int into, double *phi) {
  double u;
  int rc = eval_terms(nw, m, d, x, t, want_grad, want_hess, project, into, &u);
  if (rc) return rc;
  double inertia = 0.0;
  const int dim = m->dim;
  for (int i = 0; i < m->nv; i++)
    for (int al = 0; al < dim; al++) {
      int c = m->dof[i * dim + al];
      if (c < 0) continue;
      double r = x[i * dim + al] - xhat[i * dim + al];
      inertia += 0.5 * a * m->mass[i] * r * r;
      if (want_grad) nw->g[c] = a * m->mass[i] * r + d->grad[i * dim + al];
    }
  *phi = inertia + u;
  if (nw->cd > 0.0 && nw->dval) {
    *phi += damping_phi(nw, m, x);
    if (want_grad)
      for (int c = 0; c < nw->n; c++) nw->g[c] += nw->dr[c];
  }
  if (!isfinite(*phi)) {
    sw_errf(d->err, sizeof d->err, "the energy is not finite (NaN or Inf) at t = %g s", t);
    return SW_RECOVER;
  }
  return SW_OK;
}

int sw_newton_phi(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                  const double *xhat, double a, double t, int want_grad, int want_hess,
                  int project, double *phi) {
  return phi_eval(nw, m, d, x, xhat, a, t, want_grad, want_hess, project, 0, phi);
}

static void add_step(const sw_model *m, const double *x, const double *dx, double alpha,
                     double *out) {
  const int dim = m->dim;
  for (int i = 0; i < m->nv * dim; i++) {
    int c = m->dof[i];
    out[i] = c < 0 ? x[i] : x[i] + alpha * dx[c];
  }
}

/* 1 when the whole step dx from x leaves every term's constraints settled (sw_term_ops
 * settled, in term order until one is not), else 0. */
static double settled(sw_newton *nw, const sw_model *m, sw_data *d, const double *x, double t) {
  double r = 1.0;
  int any = 0;
  for (int k = 0; k < m->nterm && r == 1.0; k++) {
    const sw_term *tm = &m->term[k];
    if (!tm->ops->settled) continue;
    if (!any++) add_step(m, x, nw->dx, 1.0, nw->xtry);
    r = tm->ops->settled(tm, m, d, d->tdata[k], x, nw->xtry, t);
  }
  return r;
}

/* The largest fraction of the whole step dx from x that every term's bound admits (1 without
 * any). */
static double bound(sw_newton *nw, const sw_model *m, sw_data *d, const double *x, double t) {
  double r = 1.0;
  int any = 0;
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *tm = &m->term[k];
    if (!tm->ops->bound) continue;
    if (!any++) add_step(m, x, nw->dx, 1.0, nw->xtry);
    r = fmin(r, tm->ops->bound(tm, m, d, d->tdata[k], x, nw->xtry, t));
  }
  return r;
}

/* alpha cut by the terms' continuous collision detection (sw_term_ops ccd): the fraction of
 * the whole step dx from x they allow, each term on the part alpha dx the earlier ones left
 * (nw->tfrac[k]: term k's result); alpha without any. */
static double ccd(sw_newton *nw, const sw_model *m, sw_data *d, const double *x, double t,
                  double alpha) {
  double a = alpha;
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *tm = &m->term[k];
    if (!tm->ops->ccd || a <= 0.0) continue;
    add_step(m, x, nw->dx, a, nw->xtry);
    double s = tm->ops->ccd(tm, m, d, d->tdata[k], x, nw->xtry, t);
    nw->tfrac[k] = s * a;
    a *= s;
  }
  return a;
}

/* When the bounds cut the whole step dx short (alpha < 1), each vertex's part of dx is
 * clipped at what that vertex alone may take instead (sw_term_ops clip; the smallest of the
 * terms' fractions), so that a vertex running into an obstacle does not hold back the rest of
 * the cloth.  Newton's quadratic model does not see an obstacle beyond the barrier's reach, so
 * without this one vertex can cut every step to a few percent for many iterations.  The
 * clipped step is kept (then *alpha = 1 and *slope is its own) when it promises at least
 * SW_CLIP_KEEP of the first-order decrease of the step cut short, alpha grad Phi . dx:
 * clipping some vertices and not their neighbours stretches the cloth between them, and a
 * clipped step whose slope had fallen to 1e-3 ... 1e-6 of that took the line search up to 19
 * halvings an iteration, iteration after iteration.  0.01 by measurement: 0.1 and 1 moved the
 * folding sheet's pile (1809 and 1084 Newton iterations against 1710, the latter at 2.3 times
 * the CPU), 0.01 leaves it as it was and ends those halvings (docs/contact.md, "Never
 * inside", point 2). */
#ifndef SW_CLIP_KEEP
#define SW_CLIP_KEEP 0.01
#endif
static void clip_step(sw_newton *nw, const sw_model *m, sw_data *d, const double *x, double t,
                      double *alpha, double *slope) {
  if (*alpha >= 1.0 || !nw->vfrac) return;
  double s = 0.0;
  int any = 0;
  add_step(m, x, nw->dx, 1.0, nw->xtry);
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *tm = &m->term[k];
    if (!tm->ops->clip) continue;
    tm->ops->clip(tm, m, d, d->tdata[k], x, nw->xtry, t, any ? nw->vtmp : nw->vfrac);
    for (int i = 0; any && i < m->nv; i++) nw->vfrac[i] = fmin(nw->vfrac[i], nw->vtmp[i]);
    any = 1;
  }
  for (int i = 0; i < m->nv; i++) nw->vheld[i] = fmin(nw->vheld[i], nw->vfrac[i]);
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] >= 0) s += nw->g[m->dof[i]] * nw->dx[m->dof[i]] * nw->vfrac[i / m->dim];
  /* nw->g is -grad Phi here: -s is the clipped slope grad Phi . dx_clipped */
  if (-s < 0.0 && -s <= SW_CLIP_KEEP * *alpha * *slope) {
    for (int i = 0; i < m->nv * m->dim; i++)
      if (m->dof[i] >= 0) nw->dx[m->dof[i]] *= nw->vfrac[i / m->dim];
    *alpha = 1.0;
    *slope = -s;
  }
}

int sw_newton_line_search(sw_newton *nw, const sw_model *m, sw_data *d, double *x,
                          const double *xhat, const sw_newton_opts *o, double phi0, double slope) {
  /* Differences below this are round-off in Phi itself. */
  double noise = 1e-13 * (fabs(phi0) + 1e-300);
  double alpha = bound(nw, m, d, x, o->t);
  clip_step(nw, m, d, x, o->t, &alpha, &slope);
  alpha = ccd(nw, m, d, x, o->t, alpha);
  for (int k = 0; k < 40 && alpha > 0.0; k++, alpha *= 0.5) {
    add_step(m, x, nw->dx, alpha, nw->xtry);
    double phi;
    int rc = sw_newton_phi(nw, m, d, nw->xtry, xhat, o->a, o->t, 0, 0, 0, &phi);
    if (rc < 0) return rc;
    if (rc == SW_OK && phi <= phi0 + 1e-4 * alpha * slope + noise) {
      memcpy(x, nw->xtry, (size_t)m->nv * (size_t)m->dim * sizeof(double));
      return SW_OK;
    }
    d->nlinesearch++;
  }
  sw_errf(d->err, sizeof d->err, "line search found no decrease at t = %g s", o->t);
  return SW_RECOVER;
}


/* max |v_i|, or NaN when any v_i is NaN (fmax would drop it, and a NaN step would "converge"). */
static double max_abs(const double *v, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) {
    if (isnan(v[i])) return NAN;
    s = fmax(s, fabs(v[i]));
  }
  return s;
}

/* The size of Newton's update in the solve's norm, m: the mass-weighted RMS, or max |dx|/cap
 * if larger (no coordinate beyond cap x the tolerance), or max |dx|; NaN if any is NaN. */
static double update_size(const sw_newton *nw, int norm, double dxmax) {
  if (norm != SW_NORM_RMS || isnan(dxmax)) return dxmax;
  double s = 0.0;
  for (int c = 0; c < nw->n; c++) s += nw->wdof[c] * nw->dx[c] * nw->dx[c];
  return fmax(sqrt(s), dxmax / SW_NEWTON_RMS_CAP);
}

int sw_hessian_filter(int hessian) {
  if (hessian == SW_HESSIAN_PROJECTED) return SW_FILTER_CLAMP;
  if (hessian == SW_HESSIAN_ABS) return SW_FILTER_ABS;
  return SW_FILTER_NONE;
}

static int cmp_pair(const void *a, const void *b) {
  const int *p = a, *q = b;
  return p[0] != q[0] ? (p[0] > q[0]) - (p[0] < q[0]) : (p[1] > q[1]) - (p[1] < q[1]);
}

/* Add vertex pair (i, j) to nw->xpair; -1 when out of memory. */
static int push_xpair(sw_newton *nw, int i, int j) {
  if (nw->nxpair == nw->capxpair) {
    long cap = nw->capxpair + nw->capxpair / 2 + 256;
    int *p = sw_realloc(nw->xpair, (size_t)cap * 2, sizeof(int));
    if (!p) return -1;
    nw->xpair = p, nw->capxpair = cap;
  }
  nw->xpair[2 * nw->nxpair] = i < j ? i : j;
  nw->xpair[2 * nw->nxpair + 1] = i < j ? j : i;
  nw->nxpair++;
  return 0;
}

/* Self-contact's kept slots: none (a new pattern, or too many kept). */
static void forget_slots(sw_newton *nw) {
  nw->nslot = 0;
  for (int q = 0; q < nw->captab; q++) nw->ktab[q] = -1;
}

/* The position in nw->ktab of the entry of vertices v, or of the free place where it goes. */
static int slot_place(const sw_newton *nw, const int *v) {
  unsigned h = 2166136261u; /* FNV-1a over the four indices */
  for (int i = 0; i < SW_BLOCK_MAXV; i++) h = (h ^ (unsigned)v[i]) * 16777619u;
  for (unsigned q = h & (unsigned)(nw->captab - 1);; q = (q + 1) & (unsigned)(nw->captab - 1)) {
    int e = nw->ktab[q];
    if (e < 0 || !memcmp(nw->kv + SW_BLOCK_MAXV * (size_t)e, v, SW_BLOCK_MAXV * sizeof(int)))
      return (int)q;
  }
}

/* Room for one more kept entry, the table at most half full; -1 when out of memory. */
static int slot_room(sw_newton *nw) {
  if (nw->nslot == nw->capslot) {
    int cap = nw->capslot + nw->capslot / 2 + 256;
    int *kv = sw_realloc(nw->kv, (size_t)cap * SW_BLOCK_MAXV, sizeof(int));
    if (kv) nw->kv = kv;
    int *ks = kv ? sw_realloc(nw->kslot, (size_t)cap * SW_BLOCK_MAXS, sizeof(int)) : NULL;
    if (!ks) return -1;
    nw->kslot = ks, nw->capslot = cap;
  }
  if (2 * (nw->nslot + 1) <= nw->captab) return 0;
  int cap = nw->captab ? 2 * nw->captab : 1024;
  int *t = sw_realloc(nw->ktab, (size_t)cap, sizeof(int));
  if (!t) return -1;
  nw->ktab = t, nw->captab = cap;
  for (int q = 0; q < cap; q++) t[q] = -1;
  for (int e = 0; e < nw->nslot; e++) t[slot_place(nw, nw->kv + SW_BLOCK_MAXV * (size_t)e)] = e;
  return 0;
}

/* The key of a block of nvb vertices v: its vertices, -1 past nvb. */
static void block_key(const int *v, int nvb, int key[SW_BLOCK_MAXV]) {
  for (int i = 0; i < SW_BLOCK_MAXV; i++) key[i] = i < nvb ? v[i] : -1;
}

/* The kept slots of the block of key, or NULL. */
static const int *kept_slots(const sw_newton *nw, const int *key) {
  if (!nw->captab) return NULL;
  int e = nw->ktab[slot_place(nw, key)];
  return e < 0 ? NULL : nw->kslot + SW_BLOCK_MAXS * (size_t)e;
}

/* The slots of the block of key (nvb vertices), found and kept when not kept yet; NULL when
 * they cannot be kept (out of memory). */
static const int *block_slots(sw_newton *nw, const sw_model *m, const int *key, int nvb) {
  const int *s = kept_slots(nw, key);
  if (s || slot_room(nw)) return s;
  int e = nw->nslot++, *slot = nw->kslot + SW_BLOCK_MAXS * (size_t)e;
  memcpy(nw->kv + SW_BLOCK_MAXV * (size_t)e, key, SW_BLOCK_MAXV * sizeof(int));
  sw_pattern_block_slots(&nw->pat, m, key, nvb, slot);
  nw->ktab[slot_place(nw, key)] = e;
  return slot;
}

/* Term k's extra blocks of the last evaluation (none when it has no blocks op, or a bad
 * size). */
static sw_blocks term_blocks(const sw_model *m, const sw_data *d, int k) {
  sw_blocks b = {0};
  const sw_term *tm = &m->term[k];
  if (tm->ops->blocks) tm->ops->blocks(tm, m, d, d->tdata[k], &b);
  if (b.n < 0 || b.nvb < 1 || b.nvb > SW_BLOCK_MAXV || !b.v || b.vstride < b.nvb) b.n = 0;
  return b;
}

/* Rebuild the pattern with nw->xpair and analyse it again (the damping matrix carried over,
 * and with carry the values in nw->sval). */
static int regrow(sw_newton *nw, const sw_model *m, sw_data *d, int carry) {
  sw_pattern np;
  int rc = sw_pattern_build_ex(&np, m, nw->xpair, nw->nxpair, d->err, sizeof d->err);
  if (rc) return rc;
  double *kept = carry ? sw_calloc((size_t)nw->pat.nnz + 1, sizeof(double)) : NULL;
  if (carry && !kept) {
    sw_pattern_free(&np);
    sw_errf(d->err, sizeof d->err, "out of memory growing the sparsity pattern");
    return SW_FATAL;
  }
  if (kept) memcpy(kept, nw->sval, (size_t)nw->pat.nnz * sizeof(double));
  double *sv = nw->sown ? sw_realloc(nw->sown, (size_t)np.nnz + 1, sizeof(double)) : NULL;
  if (sv) nw->sown = sv;
  double *dv = nw->dval ? sw_calloc((size_t)np.nnz + 1, sizeof(double)) : NULL;
  if ((nw->sown && !sv) || (nw->dval && !dv)) {
    sw_free(dv);
    sw_free(kept);
    sw_pattern_free(&np);
    sw_errf(d->err, sizeof d->err, "out of memory growing the sparsity pattern");
    return SW_FATAL;
  }
  sw_chol_free(&nw->chol);
  /* analysed first: that stores np in its factorisation's order, which D is carried into */
  int rc2 = sw_chol_init(&nw->chol, &np, nw->factor_mode, d->err, sizeof d->err);
  if (dv) {
    sw_pattern_remap(&nw->pat, nw->dval, &np, dv);
    sw_free(nw->dval);
    nw->dval = dv;
  }
  nw->sval = nw->sown ? nw->sown : sw_chol_values(&nw->chol);
  if (kept && !rc2) sw_pattern_remap(&nw->pat, kept, &np, nw->sval);
  sw_free(kept);
  sw_pattern_free(&nw->pat);
  nw->pat = np; /* the factorisation holds np's arrays, not its struct */
  nw->fac_valid = 0;
  forget_slots(nw); /* the kept slots were the old pattern's */
  d->npattern++;
  return rc2;
}

/* When the last evaluation's extra blocks (sw_term_ops blocks: self-contact's pairs, say)
 * couple vertices the pattern does not hold, add those pairs and rebuild it (a new symbolic
 * analysis).  The pattern only grows: a pair that left contact keeps its (zero) entries, so a
 * contact that comes and goes costs one analysis, not one per change (docs/contact.md, "The
 * sparsity pattern"). */
static int grow_pattern(sw_newton *nw, const sw_model *m, sw_data *d, int carry) {
  long before = nw->nxpair;
  for (int t = 0; t < m->nterm; t++) {
    sw_blocks b = term_blocks(m, d, t);
    for (int k = 0; k < b.n; k++) {
      const int *v = b.v + (size_t)k * b.vstride;
      int key[SW_BLOCK_MAXV];
      block_key(v, b.nvb, key);
      if (kept_slots(nw, key)) continue; /* its slots were found on this pattern: all held */
      for (int i = 0; i < b.nvb; i++)
        for (int j = i + 1; j < b.nvb; j++) {
          int a = v[i], c = v[j];
          if (a < 0 || c < 0 || a >= m->nv || c >= m->nv) continue; /* no DOF */
          if (a != c && !sw_pattern_has_pair(&nw->pat, m, a, c) && push_xpair(nw, a, c)) {
            sw_errf(d->err, sizeof d->err, "out of memory growing the sparsity pattern");
            return SW_FATAL;
          }
        }
    }
  }
  if (nw->nxpair == before) return SW_OK;
  double t0 = sw_now();
  qsort(nw->xpair, (size_t)nw->nxpair, 2 * sizeof(int), cmp_pair);
  long u = 0;
  for (long q = 0; q < nw->nxpair; q++)
    if (u == 0 || cmp_pair(nw->xpair + 2 * q, nw->xpair + 2 * (u - 1)))
      memmove(nw->xpair + 2 * u++, nw->xpair + 2 * q, 2 * sizeof(int));
  nw->nxpair = u;
  int rc = regrow(nw, m, d, carry);
  d->time_pattern += sw_now() - t0;
  return rc;
}

/* The terms' extra blocks into val, by their kept slots. */
static void add_extra_blocks(sw_newton *nw, const sw_model *m, const sw_data *d, double *val) {
  long nb = 0;
  for (int t = 0; t < m->nterm; t++) nb += term_blocks(m, d, t).n;
  if (nw->nslot > 4 * nb + 4096) forget_slots(nw); /* blocks long gone: keep memory bounded */
  for (int t = 0; t < m->nterm; t++) {
    sw_blocks b = term_blocks(m, d, t);
    const int nd = b.nvb * m->dim;
    for (int k = 0; b.val && k < b.n; k++) {
      const int *v = b.v + (size_t)k * b.vstride;
      const double *blk = b.val + (size_t)nd * nd * k;
      int key[SW_BLOCK_MAXV];
      block_key(v, b.nvb, key);
      const int *slot = block_slots(nw, m, key, b.nvb);
      if (slot) sw_pattern_add_slots(slot, nd, blk, 1.0, val);
      else sw_pattern_add_block(&nw->pat, m, v, b.nvb, blk, 1.0, val);
    }
  }
}

/* S = a M + H (H from the last evaluation: blocks, self-contact pairs and low-rank vectors)
 * + cd D into nw->sval and nw->lrcur (the pattern grown first for new self-contact pairs);
 * with into, the blocks are in nw->sval already (eval_terms). */
static int assemble(sw_newton *nw, const sw_model *m, sw_data *d, double a, int into) {
  int rc = nw->nblock_terms ? grow_pattern(nw, m, d, into) : SW_OK;
  if (rc) return rc;
  double t0 = sw_now();
  double *val = nw->sval;
  if (into) sw_pattern_finish(&nw->pat, m, a, 1.0, val);
  else sw_pattern_fill(&nw->pat, m, d, a, 1.0, val);
  if (nw->nblock_terms) add_extra_blocks(nw, m, d, val);
  sw_pattern_fill_lowrank(&nw->pat, d, nw->lrcur);
  if (nw->cd > 0.0 && nw->dval)
    for (long q = 0; q < nw->pat.nnz; q++) val[q] += nw->cd * nw->dval[q];
  d->time_assemble += sw_now() - t0;
  return SW_OK;
}

int sw_newton_hessian(sw_newton *nw, const sw_model *m, sw_data *d, double a) {
  int rc = nw->nblock_terms ? grow_pattern(nw, m, d, 0) : SW_OK;
  if (rc) return rc;
  double *val = sw_chol_values(&nw->chol);
  sw_pattern_fill(&nw->pat, m, d, a, 1.0, val);
  if (nw->nblock_terms) add_extra_blocks(nw, m, d, val);
  return SW_OK;
}

/* Factorise the assembled S; on success it is the kept factorisation. */
static int factor(sw_newton *nw, sw_data *d) {
  double t0 = sw_now();
  double *val = sw_chol_values(&nw->chol);
  if (val != nw->sval) memcpy(val, nw->sval, (size_t)nw->pat.nnz * sizeof(double));
  if (nw->pat.nlr) /* the low-rank vectors (CHOLMOD's copy is NULL without them) */
    memcpy(sw_chol_lowrank(&nw->chol, 1.0), nw->lrcur,
           (size_t)nw->pat.lrptr[nw->pat.nlr] * sizeof(double));
  int rc = sw_chol_factor(&nw->chol, d->err, sizeof d->err);
  d->time_factor += sw_now() - t0;
  d->nfactor++;
  d->factor_nnz = sw_chol_nnz(&nw->chol);
  d->factor_super = sw_chol_super(&nw->chol);
  d->factor_ordering = sw_chol_ordering(&nw->chol);
  nw->fac_valid = rc == SW_OK;
  nw->fac_stale = 0;
  return rc;
}

/* hessian: progressive.  Flag (for the rest of the step) every stencil with a free vertex
 * whose mass-scaled residual |g_i| / (a m_i) exceeds tol_dx: where Newton is still far from
 * converged its block is clamped, elsewhere it stays exact (after Fernandez-Fernandez, Loschner
 * and Bender, "Progressively Projected Newton's Method", Eurographics 2026).  Returns the
 * number of flagged stencils. */
static long flag_stencils(sw_newton *nw, const sw_model *m, const sw_newton_opts *o) {
  const int dim = m->dim;
  for (int i = 0; i < m->nv; i++) {
    double s = 0.0;
    for (int al = 0; al < dim; al++) {
      int c = m->dof[i * dim + al];
      if (c >= 0) s += nw->g[c] * nw->g[c];
    }
    nw->vres[i] = o->a > 0.0 && m->mass[i] > 0.0 ? sqrt(s) / (o->a * m->mass[i]) : INFINITY;
  }
  long nflag = 0;
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    for (int s = 0; s < t->nstencil; s++) {
      unsigned char *f = &nw->flag[nw->soff[k] + s];
      for (int q = t->sptr[s]; !*f && q < t->sptr[s + 1]; q++)
        if (nw->vres[t->sidx[q]] > o->tol_dx && !m->pinned[t->sidx[q]]) *f = 1;
      nflag += *f;
    }
  }
  return nflag;
}

/* Replace the flagged stencils' exact blocks in d->hess by the terms' clamped ones (in
 * nw->hfilt, from an evaluation at the same x). */
static void use_filtered(sw_newton *nw, const sw_model *m, sw_data *d) {
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    for (int s = 0; s < t->nstencil; s++)
      if (nw->flag[nw->soff[k] + s]) {
        long at = d->hoff[k] + t->hptr[s], len = t->hptr[s + 1] - t->hptr[s];
        memcpy(d->hess + at, nw->hfilt + at, (size_t)len * sizeof(double));
      }
  }
}

/* The terms' Hessian at x filtered by `filter` into d->hess, or with into straight into
 * nw->sval (gradient and energy untouched). */
static int eval_hessian(sw_newton *nw, const sw_model *m, sw_data *d, const double *x, double t,
                        int filter, int into) {
  double u, t0 = sw_now();
  int rc = eval_terms(nw, m, d, x, t, 0, 1, filter, into, &u);
  d->time_assemble += sw_now() - t0;
  return rc;
}

/* Progressive: exact blocks, the flagged ones clamped.  The gradient is in nw->g already. */
static int progressive_hessian(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                               const sw_newton_opts *o) {
  long nflag = flag_stencils(nw, m, o);
  int rc;
  if (nflag > 0) {
    if ((rc = eval_hessian(nw, m, d, x, o->t, SW_FILTER_CLAMP, 0))) return rc;
    memcpy(nw->hfilt, d->hess, (size_t)d->hoff[m->nterm] * sizeof(double));
  }
  if ((rc = eval_hessian(nw, m, d, x, o->t, SW_FILTER_NONE, 0))) return rc;
  if (nflag > 0) use_filtered(nw, m, d);
  return SW_OK;
}

/* Phi, its gradient and the Hessian at x as the mode asks, assembled into S (nw->sval): the
 * blocks straight into it, but for progressive, which mixes two evaluations' blocks. */
static int linearise(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                     const double *xhat, const sw_newton_opts *o, double *phi) {
  int mode = o->hessian, first = sw_hessian_filter(mode);
  if (mode == SW_HESSIAN_ABS && nw->iter >= SW_NEWTON_ABS_ITERS) first = SW_FILTER_CLAMP;
  int into = mode != SW_HESSIAN_PROGRESSIVE;
  double t0 = sw_now();
  int rc = phi_eval(nw, m, d, x, xhat, o->a, o->t, 1, into, first, into, phi);
  d->time_assemble += sw_now() - t0;
  if (rc) return rc;
  if (mode == SW_HESSIAN_PROGRESSIVE && (rc = progressive_hessian(nw, m, d, x, o))) return rc;
  return assemble(nw, m, d, o->a, into);
}

/* A fresh factorisation of S and dx = S^-1 b, b = -grad Phi in nw->g (auto and progressive:
 * clamped everywhere when S is not positive definite; progressive keeps that for the rest of
 * the step). */
static int direct(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                  const sw_newton_opts *o) {
  int rc = factor(nw, d), mode = o->hessian;
  if (rc == SW_RECOVER && (mode == SW_HESSIAN_AUTO || mode == SW_HESSIAN_PROGRESSIVE)) {
    if (nw->flag) memset(nw->flag, 1, (size_t)nw->soff[m->nterm]);
    int into = mode != SW_HESSIAN_PROGRESSIVE;
    if (!(rc = eval_hessian(nw, m, d, x, o->t, SW_FILTER_CLAMP, into)) &&
        !(rc = assemble(nw, m, d, o->a, into)))
      rc = factor(nw, d);
  }
  if (rc) return rc;
  double t0 = sw_now();
  rc = sw_chol_solve(&nw->chol, nw->g, nw->dx, d->err, sizeof d->err);
  d->time_solve += sw_now() - t0;
  return rc;
}

static double dot(const double *a, const double *b, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) s += a[i] * b[i];
  return s;
}

/* y = S x for the current S: its sparse part and its low-rank vectors, sum_r v_r (v_r . x). */
static void apply_s(const sw_newton *nw, const double *x, double *y) {
  const sw_pattern *p = &nw->pat;
  sw_pattern_symv(p, nw->sval, x, y);
  for (int r = 0; r < p->nlr; r++) {
    double s = 0.0;
    for (long q = p->lrptr[r]; q < p->lrptr[r + 1]; q++) s += nw->lrcur[q] * x[p->lrrow[q]];
    for (long q = p->lrptr[r]; q < p->lrptr[r + 1]; q++) y[p->lrrow[q]] += s * nw->lrcur[q];
  }
}

/* Preconditioned conjugate gradients (Hestenes and Stiefel 1952; Saad, "Iterative Methods for
 * Sparse Linear Systems", 2003, alg. 9.1) on S dx = b from dx = 0, the kept factorisation as
 * preconditioner P.  The relative error of the direction is estimated by
 * rho = sqrt(r.P^-1 r / b.P^-1 b) (= |dx - S^-1 b|_S / |S^-1 b|_S when P = S); CG stops when
 * rho <= max(SW_CG_ETA, SW_CG_ABS tol_dx / |dx|) (capped at 1/2), |dx| in Newton's norm: the
 * error it leaves in a direction is below SW_CG_ABS of Newton's tolerance, or SW_CG_ETA of the
 * direction (so that Newton still contracts fast while its updates are large); with rel > 0
 * (a correction, whose size says nothing of the tolerance) when rho <= rel alone.  Returns the
 * iterations taken, 0 when it did not converge within SW_CG_MAX or met p.S p <= 0 (dx is
 * then meaningless), or a negative SW_* code.  Every iterate from 0 lowers Newton's quadratic
 * model, so dx is a descent direction whenever it returns > 0. */
static int pcg(sw_newton *nw, sw_data *d, const sw_newton_opts *o, double rel) {
  const int n = nw->n, kmax = SW_CG_MAX;
  const double eta = SW_CG_ETA, cabs = o->reuse == SW_REUSE_STEP ? SW_CG_STEP_ABS : SW_CG_ABS;
  double **cg[4] = {&nw->cr, &nw->cz, &nw->cp, &nw->cq}; /* allocated once, when first needed */
  for (int k = 0; k < 4; k++)
    if (!*cg[k] && !(*cg[k] = sw_calloc((size_t)n + 1, sizeof(double)))) {
      sw_errf(d->err, sizeof d->err, "out of memory for conjugate gradients (%d DOFs)", n);
      return SW_FATAL;
    }
  double *x = nw->dx, *r = nw->cr, *z = nw->cz, *p = nw->cp, *q = nw->cq;
  double t0 = sw_now();
  memset(x, 0, (size_t)n * sizeof(double));
  memcpy(r, nw->g, (size_t)n * sizeof(double));
  int rc = sw_chol_solve(&nw->chol, r, z, d->err, sizeof d->err), k, done = 0;
  double rz = dot(r, z, n), rz0 = rz;
  if (!rc) memcpy(p, z, (size_t)n * sizeof(double));
  for (k = 1; !rc && !done && k <= kmax; k++) {
    apply_s(nw, p, q);
    double pq = dot(p, q, n);
    if (!(pq > 0.0)) break;
    double alpha = rz / pq;
    for (int i = 0; i < n; i++) {
      x[i] += alpha * p[i];
      r[i] -= alpha * q[i];
    }
    rc = sw_chol_solve(&nw->chol, r, z, d->err, sizeof d->err);
    double rz1 = dot(r, z, n);
    d->ncg++;
    double size = update_size(nw, o->norm, max_abs(x, n));
    double want = rel > 0.0 ? rel : fmax(eta, fmin(0.5, cabs * o->tol_dx / size));
    if (rz1 <= want * want * rz0) done = k;
    for (int i = 0; i < n; i++) p[i] = z[i] + rz1 / rz * p[i];
    rz = rz1;
  }
  d->time_solve += sw_now() - t0;
  return rc ? rc : done;
}

int sw_newton_system(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                     const double *xhat, const sw_newton_opts *o, double *phi) {
  nw->cd = o->xd ? o->cd : 0.0;
  nw->xd = o->xd;
  int rc = linearise(nw, m, d, x, xhat, o, phi);
  for (int c = 0; !rc && c < nw->n; c++) nw->g[c] = -nw->g[c];
  return rc;
}

int sw_newton_factor(sw_newton *nw, sw_data *d) { return factor(nw, d); }

int sw_newton_pcg(sw_newton *nw, sw_data *d, const sw_newton_opts *o) { return pcg(nw, d, o, 0.0); }

/* Whether a solve with options o may solve by CG with an earlier factorisation (auto: when it
 * is simplicial). */
static int reuses(const sw_newton *nw, const sw_newton_opts *o) {
  return o->reuse == SW_REUSE_AUTO ? sw_chol_super(&nw->chol) == 0 : o->reuse != SW_REUSE_OFF;
}

/* Where the solve assembles S: a solve that may reuse a factorisation keeps S apart from the
 * factorised values (sown, allocated at the first such solve); one that never does writes S
 * into them, and sown is freed.  -1 when out of memory. */
static int sval_for(sw_newton *nw, int reuse) {
  if (!reuse) {
    sw_free(nw->sown);
    nw->sown = NULL;
    nw->sval = sw_chol_values(&nw->chol);
    return 0;
  }
  if (!nw->sown && !(nw->sown = sw_calloc((size_t)nw->pat.nnz + 1, sizeof(double)))) return -1;
  nw->sval = nw->sown;
  return 0;
}

/* Newton's direction dx = S^-1 b, b = -grad Phi in nw->g: with reuse and a kept
 * factorisation, by conjugate gradients (the factorisation marked stale when they needed more
 * than SW_CG_KEEP iterations); otherwise, or when they do not converge, by a fresh
 * factorisation.  reuse step marks the factorisation stale at each solve's start, so its first
 * iteration factorises and the later ones use that factorisation.  *fresh says which. */
static int direction(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                     const sw_newton_opts *o, int *fresh) {
  *fresh = 0;
  int reuse = reuses(nw, o);
  if (reuse && nw->fac_valid && !nw->fac_stale) {
    int k = pcg(nw, d, o, 0.0);
    if (k < 0) return k;
    nw->fac_stale = k == 0 || k > SW_CG_KEEP;
    if (nw->iter == 0) { /* a factorisation from an earlier solve */
      int more = nw->backoff < SW_CG_BACKOFF ? 2 * nw->backoff + 1 : nw->backoff;
      nw->backoff = nw->fac_stale ? more : 0;
      nw->skip = nw->backoff;
    }
    if (k > 0) return SW_OK;
  }
  *fresh = 1;
  return direct(nw, m, d, x, o);
}

/* After Newton accepted a direction from CG (x already moved by it): the error CG left in it,
 * at most SW_CG_ABS of Newton's tolerance, removed by one more correction
 * dx = S^-1 (-grad Phi(x)) with the last iteration's S, by CG to SW_CG_POLISH relative (a
 * simplified Newton step: one gradient and a few CG iterations, no factorisation).  Applied
 * only when it is of the size of CG's error (at most SW_CG_ABS tol_dx): a larger one is the
 * remainder of Newton's own iteration under the filtered Hessian, which a fresh factorisation
 * leaves too and which the filtered S does not model (measured on the hanging cloth: applied,
 * it moved the first step away from the converged answer, 7e-6 to 1.5e-5 m).  A first
 * estimate P^-1 (-grad Phi) above twice that skips CG.  Skipped too when CG does not converge
 * or the correction would move a contact. */
static int polish(sw_newton *nw, const sw_model *m, sw_data *d, double *x, const double *xhat,
                  const sw_newton_opts *o) {
  double phi, t0 = sw_now(), cap = SW_CG_ABS * o->tol_dx;
  int rc = sw_newton_phi(nw, m, d, x, xhat, o->a, o->t, 1, 0, 0, &phi);
  d->time_assemble += sw_now() - t0;
  if (rc) return rc;
  for (int c = 0; c < nw->n; c++) nw->g[c] = -nw->g[c];
  t0 = sw_now();
  rc = sw_chol_solve(&nw->chol, nw->g, nw->dx, d->err, sizeof d->err);
  d->time_solve += sw_now() - t0;
  if (rc) return rc;
  if (!(update_size(nw, o->norm, max_abs(nw->dx, nw->n)) <= 2.0 * cap)) return SW_OK;
  int k = pcg(nw, d, o, SW_CG_POLISH);
  if (k < 0) return k;
  if (k == 0) {
    nw->fac_stale = 1;
    return SW_OK;
  }
  if (!(update_size(nw, o->norm, max_abs(nw->dx, nw->n)) <= cap) ||
      settled(nw, m, d, x, o->t) != 1.0 || ccd(nw, m, d, x, o->t, 1.0) < 1.0)
    return SW_OK;
  add_step(m, x, nw->dx, 1.0, x);
  return SW_OK;
}

/* The round-off floor of a Newton step, m: positions of magnitude up to max |x| are resolved to
 * about eps max |x|; a step a thousand times that is as far as iterating can usefully go. */
static double round_off_floor(const sw_model *m, const double *x) {
  double xmax = 0.0;
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] >= 0) xmax = fmax(xmax, fabs(x[i]));
  return 1e3 * DBL_EPSILON * xmax;
}

/* After Newton failed: the first term that held an update of the solve below half (sw_term_ops
 * held: the obstacles' clip of a vertex, at its smallest over the solve, or a mesh obstacle's
 * pair in the CCD of the last update) names the obstacle and the vertex in d->err, so that a
 * failure at a fast obstacle says which one and where.  The clip's smallest, not its last: a
 * solve can crawl for all its iterations behind an obstacle that no longer cuts its last. */
static void name_obstacle(const sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                          double t) {
  int iv = -1, item = -1;
  double frac = 1.0;
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *tm = &m->term[k];
    if (tm->ops->held && tm->ops->held(tm, m, d, d->tdata[k], x, t, nw->vheld, nw->tfrac[k],
                                       &item, &iv, &frac))
      break;
  }
  if (item < 0) return;
  size_t n = strlen(d->err);
  snprintf(d->err + n, sizeof d->err - n, ": obstacles[%d] held vertex %d to %.2g of an update "
           "at t = %g s (a smaller dt or more max_halvings)", item, iv, frac, t);
}

#ifdef SW_NEWTON_PROBE
/* A diagnostic build (-DSW_NEWTON_PROBE, tools/newton_certificate.sh) measures two cheaper
 * certificates of convergence against Newton's own test, at every iteration after the first
 * (docs/performance.md, "Newton's last iteration"):
 * - the chord step dx' = S_prev^-1 (-grad Phi(x)), a solve with the factorisation at hand;
 * - the residual bound |dx|_M <= |grad Phi|_(M^-1) / a, exact when the filtered S >= a M.
 * One line per iteration on stderr.  Allocates: never in a normal build. */
static struct { double *chord, *resid; double chord_size, resid_size; } probe;

static double probe_size(const sw_newton *nw, int norm, const double *v) {
  double vmax = max_abs(v, nw->n), s = 0.0;
  if (norm != SW_NORM_RMS || isnan(vmax)) return vmax;
  for (int c = 0; c < nw->n; c++) s += nw->wdof[c] * v[c] * v[c];
  return fmax(sqrt(s), vmax / SW_NEWTON_RMS_CAP);
}

static void probe_before(sw_newton *nw, const sw_model *m, sw_data *d, const sw_newton_opts *o,
                         int it) {
  probe.chord_size = probe.resid_size = -1.0;
  if (it == 0 || !nw->fac_valid) return;
  probe.chord = realloc(probe.chord, (size_t)nw->n * sizeof(double));
  probe.resid = realloc(probe.resid, (size_t)nw->n * sizeof(double));
  if (!probe.chord || !probe.resid) return;
  if (sw_chol_solve(&nw->chol, nw->g, probe.chord, d->err, sizeof d->err) != SW_OK) return;
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] >= 0) probe.resid[m->dof[i]] = nw->g[m->dof[i]] / (o->a * m->mass[i / m->dim]);
  probe.chord_size = probe_size(nw, o->norm, probe.chord);
  probe.resid_size = probe_size(nw, o->norm, probe.resid);
}

/* The error left by a step of this size after one of size prev (Newton's own test). */
static double probe_left(double step, double prev) {
  double rate = prev > 0.0 ? step / prev : 1.0;
  return rate < 0.5 ? step * rate / (1.0 - rate) : step;
}

static void probe_after(const sw_newton *nw, const sw_newton_opts *o, int it, double prev) {
  if (probe.chord_size < 0.0) return;
  double exact = update_size(nw, o->norm, max_abs(nw->dx, nw->n));
  for (int c = 0; c < nw->n; c++) probe.chord[c] -= nw->dx[c];
  fprintf(stderr, "newton_probe t=%.17g it=%d tol=%.6e exact=%.6e chord=%.6e diff=%.6e "
          "left_exact=%.6e left_chord=%.6e resid=%.6e\n", o->t, it, o->tol_dx, exact,
          probe.chord_size, probe_size(nw, o->norm, probe.chord), probe_left(exact, prev),
          probe_left(probe.chord_size, prev), probe.resid_size);
}
#endif

int sw_newton_solve(sw_newton *nw, const sw_model *m, sw_data *d, double *x, const double *xhat,
                    const sw_newton_opts *o) {
  d->last_newton = 0;
  if (nw->n == 0) return SW_OK;
  if (sval_for(nw, reuses(nw, o))) {
    sw_errf(d->err, sizeof d->err, "out of memory for Newton's system (%ld nonzeros)", nw->pat.nnz);
    return SW_FATAL;
  }
  nw->cd = o->xd ? o->cd : 0.0;
  nw->xd = o->xd;
  if (nw->flag) memset(nw->flag, 0, (size_t)nw->soff[m->nterm]);
  if (nw->skip > 0) { /* the last solves' factorisations did not carry over: a fresh one */
    nw->skip--;
    nw->fac_stale = 1;
  }
  if (o->reuse == SW_REUSE_STEP) nw->fac_stale = 1; /* each solve factorises its first S */
  const double xfloor = round_off_floor(m, x);
  for (int k = 0; k < m->nterm; k++) nw->tfrac[k] = 1.0;
  for (int i = 0; nw->vheld && i < m->nv; i++) nw->vheld[i] = 1.0;
  double prev = 0.0, phi = 0.0; /* max |dx| of the last iteration; Phi at x */
  int redo = 0; /* 1: the same iterate again, with a fresh factorisation */
  int use_bound = 0; /* 1: friction's bound in the matrix (sw_eval.bound), from a line search that
                    backtracked until an iteration with it passes the convergence test */
  for (int it = 0; it < o->max_iter; it++) {
    int rc, fresh;
    nw->iter = it;
    if (redo) {
      nw->fac_stale = 1;
      redo = 0;
    } else {
      d->hess_bound = use_bound;
      rc = linearise(nw, m, d, x, xhat, o, &phi);
      d->hess_bound = 0;
      if (rc) return rc;
      d->nbound += use_bound;
      for (int c = 0; c < nw->n; c++) nw->g[c] = -nw->g[c];
    }
#ifdef SW_NEWTON_PROBE
    probe_before(nw, m, d, o, it);
#endif
    if ((rc = direction(nw, m, d, x, o, &fresh))) return rc;
#ifdef SW_NEWTON_PROBE
    probe_after(nw, o, it, prev);
#endif
    d->nnewton++;
    d->last_newton++;
    double slope = 0.0; /* grad Phi . dx, negative for a descent direction */
    for (int c = 0; c < nw->n; c++) slope -= nw->g[c] * nw->dx[c];
    double dxmax = max_abs(nw->dx, nw->n), step = update_size(nw, o->norm, dxmax);
    if (!isfinite(step)) {
      sw_errf(d->err, sizeof d->err, "Newton step is not finite at t = %g s", o->t);
      return SW_RECOVER;
    }
    /* at the floor: the step no longer contracts and the decrease it predicts is at Phi's
     * round-off */
    int stalled = prev > 0.0 && step >= prev && -slope <= 1e-13 * fabs(phi);
    /* the error left after this step: the rest of a geometric series at the observed rate,
     * never counted above the step itself (CVODE's test, Hindmarsh et al. 2005) */
    double rate = prev > 0.0 ? step / prev : 1.0;
    double left = rate < 0.5 ? step * rate / (1.0 - rate) : step;
    /* converged: the last update is taken whole, so it must also pass the collision
     * detection every other update passes (a pair outside the barrier's reach at x is not
     * one settled looks at, and a loose tolerance admits a last update longer than d-hat) */
    int small = left <= o->tol_dx || dxmax <= xfloor || stalled;
    if (small && use_bound) small = use_bound = 0; /* the update that ends a solve is Newton's own */
    if (small && settled(nw, m, d, x, o->t) == 1.0 && ccd(nw, m, d, x, o->t, 1.0) >= 1.0) {
      add_step(m, x, nw->dx, 1.0, x);
      /* step: CG's preconditioner is this solve's own factorisation, no correction
       * (docs/integrators.md, "Newton-Krylov") */
      return fresh || o->reuse == SW_REUSE_STEP ? SW_OK : polish(nw, m, d, x, xhat, o);
    }
    if (o->line_search) {
      long halved = d->nlinesearch;
      rc = sw_newton_line_search(nw, m, d, x, xhat, o, phi, slope);
      /* friction (the terms that dissipate) has a bound to offer (sw_eval.bound) */
      use_bound = use_bound || (d->nlinesearch > halved && nw->friction);
      if (rc == SW_RECOVER && !fresh) { /* CG's direction led nowhere: an exact one */
        redo = 1;
        continue;
      }
      if (rc) return rc;
    } else { /* a full step, as far as the obstacles let it go */
      add_step(m, x, nw->dx, ccd(nw, m, d, x, o->t, bound(nw, m, d, x, o->t)), x);
    }
    nw->theta = prev > 0.0 ? rate : 0.0;
    prev = step;
    if (nw->theta > SW_NEWTON_THETA) nw->fac_stale = 1;
  }
  if (!o->must_converge) return SW_OK;
  sw_errf(d->err, sizeof d->err, "Newton did not converge in %d iterations at t = %g s",
          o->max_iter, o->t);
  name_obstacle(nw, m, d, x, o->t);
  return SW_RECOVER;
}
