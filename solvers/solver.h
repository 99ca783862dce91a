/* solver.h — the shared linear-algebra path of every implicit method (docs/integrators.md):
 * a fixed upper-triangle CSC pattern on the free DOFs built once from the terms' stencils,
 * CHOLMOD analysed once and refactorised per Newton iteration, Newton's method on an
 * incremental potential, and the table of operations every integrator fills. */
#ifndef SW_SOLVER_H
#define SW_SOLVER_H

#include <suitesparse/cholmod.h>

#include "sinew.h"
#include "util.h"

/* ---------------------------------------------------------------- pattern.c */
/* The entries are stored by position: DOF c sits at position pos[c] (NULL: at c), and
 * column j of the CSC holds the rows i >= j (lower) or i <= j of the positions' triangle.
 * Built in DOF order, upper (sw_pattern_build); sw_chol_init stores it in its factorisation's
 * elimination order (sw_pattern_order), so that CHOLMOD factorises it as it stands.  The
 * functions below take and give DOFs and slots; only the index arrays are in positions. */
typedef struct sw_pattern {
  int n;                 /* free DOFs */
  long nnz;              /* stored entries (one triangle) */
  int *colptr;           /* (n + 1) by position (nnz < 2^31: CHOLMOD's 32-bit interface) */
  int *rowind;           /* (nnz) positions, sorted within each column */
  long *diag;            /* (n) slot of each DOF's diagonal entry */
  int lower;             /* 1: column j holds rows i >= j; 0: i <= j */
  int *pos, *dofat;      /* (n) position of each DOF and DOF at each position, or NULL (the
                            identity) */
  int nv;                /* the model's vertices */
  long *pptr;            /* (nv + 1) the vertex pairs' slots (sw_slots, sinew.h): where every */
  int *pvert;            /* entry of the terms' blocks adds, by its two vertices; built from */
  int *pslot;            /* the same vertex graph as the pattern */
  sw_slots slots;        /* a view of the three */
  /* The terms' low-rank vectors (sw_term.lptr) on the free DOFs: the system is
   * S = (values on the pattern) + sum_r v_r v_r^T, v_r stored sparse (CSC, n x nlr). */
  int nlr;               /* vectors of all terms */
  long *lrptr;           /* (nlr + 1) vector r: entries lrptr[r] .. lrptr[r+1]-1 */
  long *lrrow;           /* (lrptr[nlr]) free DOF of each entry */
  long *lrsrc;           /* (lrptr[nlr]) index of each entry in d->lowrank */
} sw_pattern;

int sw_pattern_build(sw_pattern *p, const sw_model *m, char *err, size_t errsz);
/* The pattern of the terms' stencils and of nextra more vertex pairs (extra: 2 vertices each;
 * the couplings self-contact adds). */
int sw_pattern_build_ex(sw_pattern *p, const sw_model *m, const int *extra, long nextra,
                        char *err, size_t errsz);
/* Whether the pattern couples vertices i and j (1 when either has no free component, or is a
 * mesh obstacle's vertex, index >= nv). */
int sw_pattern_has_pair(const sw_pattern *p, const sw_model *m, int i, int j);
/* vto (on pattern to, which holds every entry of from) = vfrom (on pattern from). */
void sw_pattern_remap(const sw_pattern *from, const double *vfrom, const sw_pattern *to,
                      double *vto);
/* values += coef * block, a dense (nvert dim)^2 block over vertices v (vertex-major, row-major;
 * nvert dim <= 12: a contact pair), on the entries the pattern holds (pinned components and mesh
 * obstacle vertices, index >= nv, dropped). */
void sw_pattern_add_block(const sw_pattern *p, const sw_model *m, const int *v, int nvert,
                          const double *block, double coef, double *values);
/* The slots of such a block's entries, w x w (w = nvert dim <= 12; -1: not held, or below the
 * diagonal), and the addition with them: sw_pattern_add_block in two parts, for a block whose
 * slots are kept. */
void sw_pattern_block_slots(const sw_pattern *p, const sw_model *m, const int *v, int nvert,
                            int *slot);
void sw_pattern_add_slots(const int *slot, int w, const double *block, double coef,
                          double *values);
void sw_pattern_free(sw_pattern *p);
/* values = mass_coef * M + hess_coef * (sum of the terms' blocks in d->hess), on the pattern. */
void sw_pattern_fill(const sw_pattern *p, const sw_model *m, const sw_data *d, double mass_coef,
                     double hess_coef, double *values);
/* Its last part, for values that hold the sum of the blocks already (sw_eval_terms_into
 * through p->map from zero): values = mass_coef * M + hess_coef * values. */
void sw_pattern_finish(const sw_pattern *p, const sw_model *m, double mass_coef,
                       double hess_coef, double *values);
/* The slot of entry (r, c) = (c, r) of DOFs r and c, or -1 if not in the pattern. */
long sw_pattern_slot(const sw_pattern *p, int r, int c);
/* The DOF at position i (the index arrays hold positions). */
static inline int sw_pattern_dof(const sw_pattern *p, long i) {
  return p->dofat ? p->dofat[i] : (int)i;
}
/* Store the pattern in a new order: position k holds what position perm[k] held (CHOLMOD's
 * Perm), and the triangle of the new positions that lower says; the slots of the maps, the
 * diagonal and the duplicates follow.  -1 when out of memory (p unchanged). */
int sw_pattern_order(sw_pattern *p, const int *perm, int lower);
/* y = A x for the symmetric A whose triangle is values on the pattern (n each, DOFs). */
void sw_pattern_symv(const sw_pattern *p, const double *values, const double *x, double *y);

/* ---------------------------------------------------------------- damping.c */
/* Rayleigh damping D = alpha M + beta K(x), K the PSD-projected Hessian of the terms
 * (docs/integrators.md: S = c^2 M + c D + H); sw_damped (sinew.h) says if there is any. */
/* values += sum_t c_t grad l_t grad l_t^T at x on the pattern (tendons of at most
 * tendon_dense_max waypoints: their dense stencil holds every slot). */
void sw_damping_tendons_fill(const sw_pattern *p, const sw_model *m, const double *x,
                             double *values);
/* out (nv x dim) = D(x) v, with the Hessian evaluated at (x, t) into d->hess; *power = v.D v (W,
 * >= 0).  Pinned components of out are 0. */
int sw_damping_force(const sw_model *m, sw_data *d, const double *x, double t, const double *v,
                     double *out, double *power);
/* lrval (lrptr[nlr]) <- the entries of the low-rank vectors in d->lowrank, on the free DOFs. */
void sw_pattern_fill_lowrank(const sw_pattern *p, const sw_data *d, double *lrval);

/* ---------------------------------------------------------------- cholmod.c */
/* The system is S = A + lrcoef V V^T: A sparse on the pattern (factorised by CHOLMOD), V the
 * pattern's low-rank vectors (n x nlr, sparse).  With them, factor also computes W = A^-1 V
 * (n x nlr dense, one multi-column solve) and the capacitance C = I + lrcoef V^T W (dpotrf),
 * and solve applies Woodbury: S^-1 b = y - lrcoef W C^-1 V^T y, y = A^-1 b (docs/tendons.md). */
typedef struct sw_chol {
  cholmod_common c;
  int started;
  cholmod_sparse *A;     /* symmetric, the pattern's triangle (stype -1 lower, +1 upper):
                            &Ahead, so an sw_chol is not to be copied */
  cholmod_sparse Ahead;  /* its column pointers and row indices are the pattern's own (which
                            CHOLMOD only reads: the pattern must outlive the factorisation);
                            its values its own */
  cholmod_factor *L;
  int ordering;          /* SW_ORDERING_* asked for */
  int used;              /* SW_ORDERING_* the analysis chose (L's own order is natural) */
  const int *pos;        /* the pattern's positions of the DOFs (CHOLMOD's rows), or NULL */
  cholmod_dense *b, *x, *Y, *E; /* persistent solve workspaces */
  int nlr;               /* low-rank vectors (0: S = A) */
  long *lrptr, *lrrow;   /* copies of the pattern's */
  double *lrval;         /* (lrptr[nlr]) V's entries, filled by the caller before factor */
  double lrcoef;         /* their coefficient (1 unless the caller scales H) */
  cholmod_dense *V, *W, *Y2, *E2; /* (n x nlr) V dense, A^-1 V, solve workspaces */
  double *C;             /* (nlr x nlr) Cholesky factor of the capacitance */
  double *z;             /* (nlr) */
} sw_chol;

/* Analyse the pattern for a factorisation of kind and ordering mode (SW_CHOL_MODE), and store
 * it in that factorisation's elimination order (sw_pattern_order): values filled on p before
 * are in its old order, so fill it (through its maps and slots) after.  p must outlive ch. */
int sw_chol_init(sw_chol *ch, sw_pattern *p, int mode, char *err, size_t errsz);
/* CHOLMOD's parameters for mode: simplicial, supernodal, or (auto) CHOLMOD's own choice by
 * the flops of the factorisation per nonzero of L with the switch at SW_FACTOR_SWITCH; the
 * supernodes relaxed to nrelax {16, 48, 128}, zrelax {0.8, 0.3, 0.1} below SW_RELAX_SWITCH
 * unknowns, CHOLMOD's defaults from there.  Measured on the hanging cloth from 6 x 6 to
 * 120 x 120 and a garment (docs/performance.md, "Simplicial or supernodal"); and the
 * ordering (docs/performance.md, "Factorisation: ordering, kind and threads"). */
void sw_chol_mode(sw_chol *ch, int mode);
#define SW_FACTOR_SWITCH 30.0
#define SW_RELAX_SWITCH 10000
/* ordering auto: AMD, or NESDIS when it needs fewer flops and the system has at least
 * SW_ORDERING_SWITCH unknowns (docs/performance.md, "Factorisation: ordering, kind and
 * threads"). */
#define SW_ORDERING_SWITCH 40000
/* The mode of a factorisation of kind SW_FACTOR_* with the ordering SW_ORDERING_* (a plain
 * SW_FACTOR_* is that kind with the automatic ordering). */
#define SW_CHOL_MODE(kind, ordering) ((kind) + SW_FACTOR_N * (ordering))
#define SW_BLOCK_MAXS (9 * SW_BLOCK_MAXV * SW_BLOCK_MAXV) /* slots of a term's largest extra
                                                       block, in 3D */
/* 1: the analysis chose a supernodal factor, 0: simplicial, -1: not analysed. */
int sw_chol_super(const sw_chol *ch);
/* The SW_ORDERING_* the analysis used (never auto), -1 when not analysed. */
int sw_chol_ordering(const sw_chol *ch);
double *sw_chol_values(sw_chol *ch);
/* V's entries (the pattern's lrptr/lrrow order) and the coefficient they enter S with. */
double *sw_chol_lowrank(sw_chol *ch, double coef);
/* Numeric factorisation of the current values: SW_OK, SW_RECOVER (not positive definite). */
int sw_chol_factor(sw_chol *ch, char *err, size_t errsz);
/* Nonzeros of L (CHOLMOD's Common->lnz from the analysis: fixed for the run; 0 before it). */
long sw_chol_nnz(const sw_chol *ch);
/* sol = S^-1 rhs (n doubles each; may alias). */
int sw_chol_solve(sw_chol *ch, const double *rhs, double *sol, char *err, size_t errsz);
void sw_chol_free(sw_chol *ch);

/* ----------------------------------------------------------------- newton.c */
/* The filter the terms apply on the first evaluation of a Hessian in mode SW_HESSIAN_*:
 * projected -> clamp, abs -> abs, the others -> none (exact). */
int sw_hessian_filter(int hessian);

/* Minimise Phi(x) = a/2 (x - xhat)^T M (x - xhat) + U(x, t) + cd/2 (x - xd)^T D (x - xd) over
 * the free DOFs (pinned components of x stay as given).  a = 1/h^2 for backward Euler (the
 * incremental potential); with damping, the stage velocity is v = cd (x - xd) (BE: cd = 1/h,
 * xd = x_n) and D is frozen for the step (sw_newton_damping), so Phi stays a potential whose
 * gradient is the residual a M (x - xhat) + grad U + D v and whose Hessian is a M + H + cd D.
 * The solver (docs/integrators.md, "Newton"): S from the Hessian the mode asks for, filtered
 * per element; each direction by a fresh factorisation of S, or (reuse) by conjugate
 * gradients on S preconditioned with a factorisation kept across iterations and steps;
 * a line search on Phi; converged when max |dx| <= tol_dx, or when the decrease Newton
 * predicts is below the round-off of Phi. */
typedef struct sw_newton {
  sw_pattern pat;
  sw_chol chol;
  int n;
  double *g, *dx;        /* (n) gradient and step on the free DOFs */
  double *xtry;          /* (nv x dim) line-search trial */
  int nterm;
  int factor_mode;       /* SW_CHOL_MODE of the options */
  double *dval;          /* (pat.nnz) D on the pattern, or NULL when the model has no damping */
  double *r, *dr;        /* (n) x - xd and D (x - xd) */
  double cd;             /* the current solve's damping coefficient, 1/s (0: none) */
  const double *xd;      /* (nv x dim) its anchor */
  /* per-element filtering (hessian: progressive) */
  long *soff;            /* (nterm + 1) first stencil of each term in flag */
  unsigned char *flag;   /* (soff[nterm]) 1: this stencil's block is filtered in this step */
  double *hfilt;         /* (d->hess's size) the terms' clamped blocks, or NULL */
  double *vres;          /* (nv) each vertex's mass-scaled residual |g_i| / (a m_i), m */
  /* S of the current iterate (the factorisation may be of an earlier one): its values on the
   * pattern and its low-rank vectors' entries (pattern order), coefficient 1.  A solve that
   * never reuses a factorisation assembles S straight into the factorisation's own values
   * (sval = sw_chol_values: one copy of the system, not two); one that may reuse keeps S
   * apart, in sown (sval_for). */
  double *sval;          /* (pat.nnz) */
  double *sown;          /* (pat.nnz) or NULL */
  double *lrcur;         /* (pat.lrptr[pat.nlr]) */
  /* preconditioned conjugate gradients (reuse): workspaces and what the last solve took */
  double *cr, *cz, *cp, *cq; /* (n) residual, preconditioned residual, direction, S p */
  /* the factorisation in the CHOLMOD object: valid (of some earlier S), and stale (CG needed
   * too many iterations with it: renew it at the next iteration) */
  int fac_valid, fac_stale;
  /* solves that start with a fresh factorisation because the last ones could not carry the
   * kept one over (doubling after each such failure, up to SW_CG_BACKOFF), and how many are
   * left */
  int backoff, skip;
  double theta;          /* the last observed contraction |dx_k| / |dx_k-1| */
  double *wdof;          /* (n) each free DOF's share of the free mass, m_i / sum m_i */
  int iter;              /* the current iteration of the solve */
  int friction;          /* 1: a term dissipates (friction): its bound after a backtrack */
  /* the terms' step limits (sw_term_ops bound, clip, ccd) */
  double *vfrac;         /* (nv) with a term that clips: each vertex's allowed fraction of a
                            step */
  double *vtmp;          /* (nv) with two or more such terms: the next one's fractions */
  double *vheld;         /* (nv) with a term that clips: each vertex's smallest fraction in
                            this solve, what a failure names (sw_term_ops held) */
  double *tfrac;         /* (nterm) the fraction of the last update each term's ccd allowed */
  int nblock_terms;      /* terms with extra Hessian blocks (sw_term_ops.blocks) */
  /* the vertex pairs the terms' extra blocks have coupled so far, on top of the stencils'
   * pattern (it only grows: a pair once coupled keeps its entries for the run) */
  int *xpair;            /* (2 nxpair) */
  long nxpair, capxpair;
  /* the pattern's slots of the extra blocks, kept for the pattern by the blocks' vertices (an
     open-addressing hash table of entries into kv and kslot) */
  int *ktab;             /* (captab, a power of 2) an entry, or -1 */
  int *kv;               /* (capslot x SW_BLOCK_MAXV) each entry's vertices (-1 past nvb) */
  int *kslot;            /* (capslot x SW_BLOCK_MAXS) its block's slots
                            (sw_pattern_block_slots) */
  int captab, nslot, capslot;
} sw_newton;

typedef struct sw_newton_opts {
  double a;              /* mass coefficient, 1/s^2 */
  double t;              /* time at which U is evaluated, s */
  int max_iter;
  double tol_dx;         /* converged when |dx| <= tol_dx (m) in the norm below */
  int norm;              /* SW_NORM_*: mass-weighted RMS (no coordinate above
                            SW_NEWTON_RMS_CAP tol_dx) or max */
  int line_search;       /* backtracking on Phi; 0: take full steps */
  int must_converge;     /* 0: stop after max_iter without failing (one-step variants) */
  int hessian;           /* SW_HESSIAN_* */
  int reuse;             /* SW_REUSE_*: Newton-Krylov, each direction by conjugate
                            gradients on the current S preconditioned by the last
                            factorisation (kept across iterations, line searches and solves;
                            step: a fresh one at each solve's first iteration, no final
                            correction); off: factorise every S */
  double cd;             /* damping: v = cd (x - xd) at the stage, 1/s (0: no damping term) */
  const double *xd;      /* (nv x dim) */
  double h;              /* s: the time step (contact friction's lag; 0 in a static solve) */
} sw_newton_opts;

/* hessian: abs filters by absolute value for this many iterations of a step, then clamps: far
 * from the minimiser the absolute value keeps the curvature a compressed element has, near it
 * clamping converges where abs would keep overshooting (measured, docs/integrators.md; the
 * idea of switching filters is Chen et al.'s, "Trust-Region Eigenvalue Filtering for Projected
 * Newton", SIGGRAPH Asia 2024). */
#define SW_NEWTON_ABS_ITERS 20

/* Newton-Krylov (reuse): conjugate gradients stop when the direction's estimated relative
 * error (in the S-norm) is at most max(SW_CG_ETA, SW_CG_ABS tol_dx / |dx|): below SW_CG_ABS of
 * Newton's tolerance, or SW_CG_ETA of the direction while Newton's updates are large.  A solve
 * that needed more than SW_CG_KEEP iterations renews the factorisation at the next
 * iteration; one that has not converged after SW_CG_MAX (or meets a direction of non-positive
 * curvature) is abandoned for a fresh factorisation of the current S.  A Newton contraction
 * |dx_k| / |dx_k-1| above SW_NEWTON_THETA renews it too.  When a solve's first iteration could
 * not use the factorisation kept from the last solve, the next 1, 3, 7, ... SW_CG_BACKOFF
 * solves start with a fresh one.  Chosen by measurement (docs/integrators.md,
 * "Newton-Krylov"). */
#define SW_CG_ETA 1e-2
#define SW_CG_ABS 0.1
/* reuse step: CG's SW_CG_ABS (no final correction follows it there); 0.1 left Newmark's 24 x 24
 * cloth 1.04 tol from the fresh-factorisation run at t = 0.1 s, 0.05 0.8 tol; 0.03 left
 * backward Euler's 0.13 tol, but one of its ten confirming solves fell back to a
 * factorisation (tests/test_newton.c, reuse_matches) */
#define SW_CG_STEP_ABS 0.05
#define SW_CG_KEEP 4
#define SW_CG_MAX 12
#define SW_CG_BACKOFF 15
#define SW_NEWTON_THETA 0.5
/* After Newton accepted a direction from CG, one more correction with a fresh gradient and the
 * same S, by CG to this relative tolerance (newton.c, polish): measured, 0.1 left BDF2 at
 * order 0.7 on the damped cloth strip of tests/test_damping.c, 1e-2 restored 2
 * (docs/integrators.md, "Newton-Krylov"). */
#define SW_CG_POLISH 1e-2

int sw_newton_init(sw_newton *nw, const sw_model *m, char *err, size_t errsz);
/* D = alpha M + beta K(x) on the pattern for the coming step, K the projected Hessian at (x, t)
 * (a predictor of the stage state); a no-op without damping. */
int sw_newton_damping(sw_newton *nw, const sw_model *m, sw_data *d, const double *x, double t);
void sw_newton_free(sw_newton *nw);
/* Drop the kept factorisation and the Newton-Krylov state (contraction, back-off). */
void sw_newton_forget(sw_newton *nw);
/* Save or load (io->load) the kept factorisation, as the matrix it factorised (refactorised on
 * load, not counted), and the Newton-Krylov state, so that a resumed run takes the iterations
 * of a straight one.  Not kept once self-contact has grown the pattern. */
void sw_newton_history(sw_newton *nw, sw_io *io);
/* x: initial guess in, minimiser out.  SW_OK, SW_RECOVER (d->err says why), or SW_FATAL. */
int sw_newton_solve(sw_newton *nw, const sw_model *m, sw_data *d, double *x, const double *xhat,
                    const sw_newton_opts *o);
/* Phi at x; its free gradient into nw->g when want_grad; the terms' Hessian blocks (filtered
 * by `project`, SW_FILTER_*) into d->hess when want_hess. */
int sw_newton_phi(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                  const double *xhat, double a, double t, int want_grad, int want_hess,
                  int project, double *phi);

/* The pieces of an iteration, for tests: Phi at x, b = -grad Phi into nw->g and S into
 * nw->sval (sw_newton_system); a factorisation of that S, kept (sw_newton_factor); dx = S^-1 b
 * into nw->dx by conjugate gradients preconditioned with the kept factorisation
 * (sw_newton_pcg: its iterations, 0 when they did not converge). */
int sw_newton_system(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                     const double *xhat, const sw_newton_opts *o, double *phi);
int sw_newton_factor(sw_newton *nw, sw_data *d);
int sw_newton_pcg(sw_newton *nw, sw_data *d, const sw_newton_opts *o);

/* a M + H into the factorisation's value array (sw_chol_values), H from the last evaluation
 * with want_hess: the terms' blocks and the mesh-contact pairs' (the pattern grown first when a
 * pair couples vertices it does not hold yet); the low-rank part is left to the caller. */
int sw_newton_hessian(sw_newton *nw, const sw_model *m, sw_data *d, double a);

/* Backtracking (Armijo) along nw->dx from x, slope = grad Phi . dx < 0; on success x holds the
 * accepted point.  Each halving counts in d->nlinesearch. */
int sw_newton_line_search(sw_newton *nw, const sw_model *m, sw_data *d, double *x,
                          const double *xhat, const sw_newton_opts *o, double phi0, double slope);

/* ---------------------------------------------------------------- ipstep.c */
/* The step every Newton time integrator shares (backward Euler, BDF2, implicit midpoint,
 * Newmark): one minimisation of Phi(y) = a/2 (y - xhat)^T M (y - xhat) + U(y, t*) (+ the
 * damping term with v = cd (y - xd)).  The method fills xhat and xd, calls sw_ipstep_solve,
 * turns y into x_{n+1} and v_{n+1} in xnew and vnew, and commits them. */
typedef struct sw_ipstep {
  sw_newton nw;
  double *xhat, *xd, *xnew, *vnew; /* (nv x dim) */
  int committed; /* d holds the state the last step accepted, and D (nw.dval) is that step's */
} sw_ipstep;

int sw_ipstep_init(sw_ipstep *s, const sw_model *m, char *err, size_t errsz);
void sw_ipstep_free(sw_ipstep *s);
/* Newton options from the scene's for a step of size h: a (1/s^2), stage time t (s), damping
 * coefficient cd (1/s), tolerance max |dy| <= tol_scale * newton_tol * h. */
sw_newton_opts sw_ipstep_opts(const sw_model *m, const sw_ipstep *s, double a, double t,
                              double cd, double h, double tol_scale);
/* D at xhat (a predictor of the stage state; with contact, at the start guess the contact
 * checks made admissible) and Newton from y = y0 (NULL: xhat) on the free DOFs (the pinned
 * components from d->x) into s->xnew. */
int sw_ipstep_solve(sw_ipstep *s, const sw_model *m, sw_data *d, const sw_newton_opts *o,
                    const double *y0);
/* After a change between steps (SW_CHANGED_*): a kept factorisation is dropped (the Hessian it
 * was built from changed), and with it what Newton-Krylov learnt (sw_newton_forget). */
void sw_ipstep_reset(sw_ipstep *s);
/* Save or load Newton's kept factorisation (sw_newton_history) for a resumed run. */
void sw_ipstep_history(sw_ipstep *s, sw_io *io);
/* Accept xnew, vnew as the state at d->t + h, after the energy check when check_energy. */
int sw_ipstep_commit(sw_ipstep *s, const sw_model *m, sw_data *d, double h, int check_energy);
/* *power = v.D v, W, over the free DOFs at d->v, with the D the last step froze at its
 * predictor: the power of the damping force that step applied, at the velocity it accepted.
 * Nonzero (and *power untouched) when there is no such step: none yet, or a reset since. */
int sw_ipstep_damping_power(sw_ipstep *s, const sw_model *m, const sw_data *d, double *power);

/* ------------------------------------------------------------ integrators.c */
typedef struct sw_integrator_ops {
  const char *name;
  const char *summary;   /* one line for --help */
  int adaptive;          /* 1: chooses its own internal steps to rtol/atol (dt is then the
                            output interval); 0: fixed steps of dt */
  int (*init)(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz);
  /* Advance d->t, d->x, d->v by dt.  On a nonzero return the state is unchanged and d->err
   * says why (positive: a smaller step may succeed). */
  int (*step)(void *state, const sw_model *m, sw_data *d, double dt);
  void (*free)(void *state);
  /* Between steps the caller (sim.c) changed what SW_CHANGED_* says: forget what no longer
   * holds and restart from d at the next step.  NULL: the method keeps nothing that could. */
  void (*reset)(void *state, const sw_model *m, sw_data *d, int what);
  /* Save or load (io->load) the history a step uses besides d (a restart file, `sinew run
   * --resume`), so that a resumed run takes the same steps.  NULL: a method with none, or
   * one that is restarted at the resumed state with reset(SW_CHANGED_STATE) (CVODE, IDA). */
  void (*history)(void *state, const sw_model *m, sw_io *io);
  /* The power, W, of the damping the last step applied, v.D v at d's state with the D that
   * step used (the Newton methods freeze D per step: sw_ipstep_damping_power).  Nonzero when
   * there is none (no step yet, or a reset since).  NULL, or nonzero: sim.c evaluates D at
   * the state (sw_damping_force). */
  int (*damping_power)(void *state, const sw_model *m, const sw_data *d, double *power);
} sw_integrator_ops;

/* What changed between two steps: the state (d->t, d->x, d->v: a history of past states no
 * longer leads to it), or the model (rest lengths, pin positions, loads: the equations of
 * motion changed at d->t, a history of states still holds). */
enum { SW_CHANGED_STATE = 1, SW_CHANGED_MODEL = 2 };

/* energy_check.c: SW_OK, or SW_RECOVER (with d->err) when K(v) + U(x, t) exceeds
 * d->energy_bound (> 0) or is not finite: an explicit method blowing up fails the step instead
 * of producing garbage. */
int sw_energy_check(const sw_model *m, sw_data *d, const double *x, const double *v, double t);
/* The automatic bound: E0 + 1e3 * (|E0| + sum of |term energies| + K0 + M |g| diam(x0) + 1 uJ). */
double sw_energy_bound(const sw_model *m, sw_data *d);

extern const sw_integrator_ops sw_backward_euler_ops;
extern const sw_integrator_ops sw_baraff_witkin_ops;
extern const sw_integrator_ops sw_proximal_ops; /* the optimisation fit's (not a scene method) */
extern const sw_integrator_ops sw_cvode_ops, sw_ida_ops; /* cvode.c, ida.c (SUNDIALS) */
extern const sw_integrator_ops sw_bdf2_ops, sw_implicit_midpoint_ops, sw_newmark_ops,
    sw_symplectic_euler_ops;
const sw_integrator_ops *sw_integrator_find(const char *name);

#endif
