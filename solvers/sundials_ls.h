/* sundials_ls.h — what CVODE (cvode.c) and IDA (ida.c) share: the state y = [x; v] on the free
 * DOFs, force evaluation, the Hessian kept on the fixed pattern, and a custom SUNLinearSolver
 * that solves SUNDIALS' 2n x 2n Newton systems through the n x n Schur complement
 *   S = cm M + cd D + ch H    (CVODE: cm = 1, ch = gamma^2;  IDA: cm = cj^2, ch = 1)
 * factorised by CHOLMOD (docs/integrators.md).  D is the damping matrix: there is none yet
 * D = alpha M + beta K is Rayleigh damping (damping.c): the forces use D at the current
 * state; the Newton matrices use alpha M + beta H with the H they hold (an approximate
 * Jacobian, as for every term's dD/dx, which is left out).
 *
 * The pairing that works with SUNDIALS 6.4.1: a linear solver of type SUNLINEARSOLVER_DIRECT
 * (gettype, setup, solve, free) with a "token" SUNMatrix (getid SUNMATRIX_CUSTOM, a no-op zero,
 * a destroy that leaves the content alone).  The method's callback (CVODE's linsys, IDA's
 * jac) re-evaluates H when asked and sets the coefficients; setup fills S and factorises it;
 * solve does the reduction with the coefficient frozen at that setup, as SUNDIALS' solution
 * scaling (2 / (1 + gamma/gamma_setup)) assumes. */
#ifndef SW_SUNDIALS_LS_H
#define SW_SUNDIALS_LS_H

#include <math.h>

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

#include "solver.h"
#include "sundials_compat.h"

typedef struct sw_sunls sw_sunls;
/* The method's block solve: x = (2n) solution of its Newton matrix for the rhs b (2n), using
 * sys->coef and the factorisation of the last setup.  SW_OK or SW_FATAL. */
typedef int (*sw_sunls_reduce_fn)(sw_sunls *sys, const double *b, double *x);

struct sw_sunls {
  const sw_model *m;
  sw_data *d;                  /* the run's data: counters, timers, err */
  int n;                       /* free DOFs; y has 2n entries */
  sw_pattern pat;
  sw_chol chol;
  double *mdiag;               /* (n) lumped mass of each free DOF, kg */
  double *hval;                /* (pat.nnz) the Hessian H on the pattern (upper CSC), N/m */
  double *hlr;                 /* (pat.lrptr[pat.nlr]) and its low-rank vectors: H is hval +
                                  sum_r v_r v_r^T (S gets them scaled by ch), sqrt(N/m) */
  double *xfull;               /* (nv x dim) positions for evaluations (pinned ones fixed) */
  double *vfull, *dvfull;      /* (nv x dim) velocity and D v for damped forces, or NULL */
  double *xlin;                /* (nv x dim) positions at which hval was evaluated */
  double tlin;                 /* time at which hval was evaluated, s */
  int h_projected;             /* hval holds the projected Hessian */
  double cm, cd, ch;           /* coefficients of M, D, H in S for the next setup */
  double coef_next;            /* gamma (CVODE) or cj (IDA) set with them by the callback */
  double coef;                 /* ... frozen by the last setup: what solve uses */
  double *w1, *w2;             /* (n) workspaces */
  sw_sunls_reduce_fn reduce;
  SUNContext ctx;
  SUNLinearSolver LS;
  SUNMatrix A;                 /* the token matrix: its content is this struct */
  char msg[SW_ERRSZ];          /* the last error message of SUNDIALS (sundials_compat.h) */
};

/* Pattern, CHOLMOD analysis, workspaces, the SUNContext, LS and A; xfull = d->x. */
int sw_sunls_init(sw_sunls *sys, const sw_model *m, sw_data *d, sw_sunls_reduce_fn reduce,
                  char *err, size_t errsz);
void sw_sunls_free(sw_sunls *sys);
/* The pinned positions of the evaluations (sys->xfull) from x (nv x dim), after they moved. */
void sw_sunls_pins(sw_sunls *sys, const double *x);

/* y (2n) <- the free components of x and v (nv x dim each); and back (pinned: v = 0). */
void sw_sunls_gather(const sw_sunls *sys, const double *x, const double *v, double *y);
void sw_sunls_scatter(const sw_sunls *sys, const double *y, double *x, double *v);
/* f (n) = -dU/dx - D(x) v at y = [x; v] (2n, free DOFs), time t, pinned positions from
 * sys->xfull (D: Rayleigh damping at the current state, damping.c; none: f = -dU/dx).
 * One force evaluation (d->nforce counts it).  SW_OK, SW_RECOVER (not finite, or a term
 * failed recoverably; d->err says why) or SW_FATAL. */
int sw_sunls_force(sw_sunls *sys, const double *y, double t, double *f);
/* y (n) += D r (n) with the Jacobian's D = alpha M + beta H (H: hval). */
void sw_sunls_dmul_add(const sw_sunls *sys, const double *r, double *y);
/* Evaluate H at the free positions xf, time t, as m->opt.hessian asks (exact for auto) into
 * sys->hval.  SW_OK, SW_RECOVER or SW_FATAL. */
int sw_sunls_hessian(sw_sunls *sys, const double *xf, double t);
/* y (n) = H x (n), with the symmetric hval and the low-rank vectors hlr. */
void sw_sunls_hmul(const sw_sunls *sys, const double *x, double *y);

/* The two reductions (cvode.c, ida.c), declared here for the tests. */
/* SUNDIALS' cumulative counters at the last step.  sw_sun_counts_add adds to d what changed
 * since then (steps, Newton iterations, setups, error-test failures) and remembers the new ones. */
typedef struct sw_sun_counts {
  long nst, nni, nsetup, netf;
} sw_sun_counts;
void sw_sun_counts_add(sw_sun_counts *last, sw_data *d, long nst, long nni, long nsetup,
                       long netf);
/* Did the caller change d (t, x or v) since the last step, which ended at tlast in state ylast
 * (2n)?  Then the integrator must restart from d.  ytmp: (2n) workspace. */
int sw_sunls_changed(const sw_sunls *sys, const sw_data *d, double h, double tlast,
                     const double *ylast, double *ytmp);

int sw_cvode_reduce(sw_sunls *sys, const double *b, double *x);
int sw_ida_reduce(sw_sunls *sys, const double *b, double *x);

/* The largest BDF order: opt.max_order, or when it is 0 the automatic one, 2 for CVODE (cvode
 * = 1) at rtol > SW_AUTO_ORDER_RTOL, else 5 (sw_max_order). */
int sw_sun_max_order(const sw_options *o, int cvode);

/* The most internal steps CVODE or IDA may take towards one output time (their mxstep). */
#define SW_SUN_MXSTEP 1000000L

/* The smallest internal step for an output at tout, s: far below any step cloth needs, yet well
 * above the round-off of t.  Without it a force that turns NaN at some time (the step returns a
 * recoverable error) makes SUNDIALS creep towards that time with ever smaller steps until its
 * mxstep (1e6) steps per output are spent: 44 s on 24 DOFs, hours on a real cloth.  With it the
 * step fails at hmin after a few tries. */
static inline double sw_sun_hmin(double tout) { return fmax(1e-12, 1e-11 * fabs(tout)); }

/* An output interval whose internal steps stay below SW_SUN_TINY x the interval for
 * SW_SUN_TINY_STEPS steps in a row fails at once, as unresolvable at the tolerance, instead of
 * creeping on: a cloth of density 1e-9 kg/m^2 (10 x 10 vertices, CVODE at rtol 1e-6) took steps
 * of 1.3e-8 s, 295 557 of them (32 s) for one output interval of 0.01 s. */
#define SW_SUN_TINY 1e-5
#define SW_SUN_TINY_STEPS 10000L
/* Count the internal step h of an interval of length out in *tiny; 1 (with err) when the run
 * should stop (sw_sun_tiny_msg). */
int sw_sun_tiny(long *tiny, double h, double out, const sw_options *o, char *err, size_t errsz);

/* err <- "SOLVER WHAT: FLAG_NAME (SUNDIALS' message): cause" and SW_FATAL.  flag_name is the
 * malloc'ed string of CVodeGetReturnFlagName / IDAGetReturnFlagName (freed here); cause is
 * the last reason one of our callbacks gave (may be "", may alias err). */
int sw_sun_fail(char *err, size_t errsz, const char *solver, const char *what, char *flag_name,
                const char *msg, const char *cause);

/* SUNDIALS' return convention from ours: 0, 1 (recoverable), -1 (fatal). */
static inline int sw_sun_rc(int rc) { return rc == SW_OK ? 0 : rc > 0 ? 1 : -1; }

#endif
