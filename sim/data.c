/* data.c — the mutable state of a run (sw_data) and the evaluation of all terms. */
#include <math.h>
#include <string.h>

#include "terms.h"
#include "util.h"

sw_data *sw_data_new(const sw_model *m) {
  sw_data *d = sw_calloc(1, sizeof *d);
  if (!d) return NULL;
  size_t nd = (size_t)m->nv * (size_t)m->dim, nf = (size_t)m->nf;
  d->hoff = sw_calloc((size_t)m->nterm + 1, sizeof(long));
  d->loff = sw_calloc((size_t)m->nterm + 1, sizeof(long));
  if (!d->hoff || !d->loff) return sw_data_free(d), NULL;
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    d->hoff[k + 1] = d->hoff[k] + t->hptr[t->nstencil];
    d->loff[k + 1] = d->loff[k] + (t->nlowrank ? (long)t->lptr[t->nlowrank] * m->dim : 0);
  }
  d->lowrank = sw_calloc((size_t)d->loff[m->nterm] + 1, sizeof(double));
  d->x = sw_calloc(nd, sizeof(double));
  d->v = sw_calloc(nd, sizeof(double));
  d->grad = sw_calloc(nd, sizeof(double));
  long blk = 1; /* the largest block, doubles */
  for (int k = 0; k < m->nterm; k++)
    for (int s = 0; s < m->term[k].nstencil; s++)
      if (m->term[k].hptr[s + 1] - m->term[k].hptr[s] > blk)
        blk = m->term[k].hptr[s + 1] - m->term[k].hptr[s];
  d->hblk = sw_calloc((size_t)blk, sizeof(double));
  d->term_energy = sw_calloc((size_t)m->nterm, sizeof(double));
  d->term_time = sw_calloc((size_t)m->nterm + 1, sizeof(double));
  d->txy = sw_calloc(nf, sizeof(double));
  d->stretch_u = sw_calloc(nf, sizeof(double));
  d->stretch_v = sw_calloc(nf, sizeof(double));
  d->shear = sw_calloc(nf, sizeof(double));
  d->rlu = sw_calloc(nf, sizeof(double));
  d->rlv = sw_calloc(nf, sizeof(double));
  d->scratch = sw_calloc(nf, sizeof(double));
  size_t nt = (size_t)m->ntendon + 1;
  d->tendon_length = sw_calloc(nt, sizeof(double));
  d->tendon_delta = sw_calloc(nt, sizeof(double));
  d->tendon_tension = sw_calloc(nt, sizeof(double));
  d->seam_state = sw_calloc(4 * (size_t)m->nseam + 1, sizeof(double));
  if (!d->tendon_length || !d->tendon_delta || !d->tendon_tension || !d->seam_state)
    return sw_data_free(d), NULL;
  if (!d->x || !d->v || !d->grad || !d->hblk ||
      !d->lowrank || !d->term_energy || !d->term_time || !d->txy ||
      !d->stretch_u || !d->stretch_v || !d->shear || !d->rlu || !d->rlv || !d->scratch)
    return sw_data_free(d), NULL;
  /* each term's workspace (the model and the terms' param stay immutable) */
  d->tdata = sw_calloc((size_t)m->nterm + 1, sizeof(void *));
  d->tdata_free = sw_calloc((size_t)m->nterm + 1, sizeof *d->tdata_free);
  if (!d->tdata || !d->tdata_free) return sw_data_free(d), NULL;
  d->ntdata = m->nterm;
  int forces = 0;
  for (int k = 0; k < m->nterm; k++) {
    const sw_term_ops *ops = m->term[k].ops;
    if (ops->data_new && !(d->tdata[k] = ops->data_new(&m->term[k], m, d)))
      return sw_data_free(d), NULL;
    d->tdata_free[k] = ops->data_free;
    forces += ops->vertex_force != NULL;
  }
  if (forces) { /* the faces' contact pressure (sw_terms_pressure) */
    d->contact_pressure = sw_calloc(nf + 1, sizeof(double));
    d->vertex_area = sw_calloc((size_t)m->nv + 1, sizeof(double));
    if (!d->contact_pressure || !d->vertex_area) return sw_data_free(d), NULL;
    for (int f = 0; f < m->nf; f++)
      for (int c = 0; c < 3; c++) d->vertex_area[m->face[3 * f + c]] += m->area[f] / 3.0;
  }
  d->contact_min = d->self_min = INFINITY;
  d->factor_super = -1;
  d->factor_ordering = -1;
  memcpy(d->x, m->x0, nd * sizeof(double));
  memcpy(d->v, m->v0, nd * sizeof(double));
  for (int i = 0; i < m->nv; i++)
    if (m->pinned[i]) memset(d->v + (size_t)i * m->dim, 0, (size_t)m->dim * sizeof(double));
  d->last_dt = 0.0;
  sw_tension_xy_reference(m, d);
  return d;
}

void sw_data_free(sw_data *d) {
  if (!d) return;
  sw_free(d->x);
  sw_free(d->v);
  sw_free(d->grad);
  sw_free(d->hess);
  sw_free(d->hblk);
  sw_free(d->hoff);
  sw_free(d->lowrank);
  sw_free(d->loff);
  sw_free(d->term_energy);
  sw_free(d->term_time);
  sw_free(d->txy);
  sw_free(d->stretch_u);
  sw_free(d->stretch_v);
  sw_free(d->shear);
  sw_free(d->rlu);
  sw_free(d->rlv);
  sw_free(d->scratch);
  sw_free(d->tendon_length);
  sw_free(d->tendon_delta);
  sw_free(d->tendon_tension);
  sw_free(d->seam_state);
  for (int k = 0; d->tdata && d->tdata_free && k < d->ntdata; k++)
    if (d->tdata[k] && d->tdata_free[k]) d->tdata_free[k](d->tdata[k]);
  sw_free(d->tdata);
  sw_free(d->tdata_free);
  sw_free(d->contact_pressure);
  sw_free(d->vertex_area);
  sw_free(d);
}

/* d->hess, allocated at its first use; SW_FATAL when out of memory. */
static int hess_room(const sw_model *m, sw_data *d) {
  if (d->hess) return SW_OK;
  d->hess = sw_calloc((size_t)d->hoff[m->nterm] + 1, sizeof(double));
  if (d->hess) return SW_OK;
  sw_errf(d->err, sizeof d->err, "out of memory for the terms' Hessian blocks (%ld doubles)",
          d->hoff[m->nterm]);
  return SW_FATAL;
}

/* Term k's blocks in d->hess, zeroed unless it sets every entry. */
static void zero_blocks(const sw_model *m, sw_data *d, int k) {
  if (!m->term[k].ops->sets_blocks)
    memset(d->hess + d->hoff[k], 0, (size_t)(d->hoff[k + 1] - d->hoff[k]) * sizeof(double));
}

/* For a term that writes its blocks in place (not sink_ok), into a system: its blocks kept in
 * d->hess first. */
static int kept_blocks(const sw_model *m, sw_data *d, int k) {
  int rc = hess_room(m, d);
  if (!rc) zero_blocks(m, d, k);
  return rc;
}

/* ... then added through the slots as sw_ev_block_done adds (sw_hsink). */
static void add_kept(const sw_model *m, const sw_data *d, int k, double *values,
                     const sw_slots *slots) {
  const sw_term *t = &m->term[k];
  const double *h = d->hess + d->hoff[k];
  for (int s = 0; s < t->nstencil; s++)
    sw_slots_add(slots, t->sidx + t->sptr[s], t->sptr[s + 1] - t->sptr[s], h + t->hptr[s],
                 values);
}

/* The terms' energies (and gradient, Hessian as asked) at x, t: the blocks into d->hess, or
 * with values into that system through its slots (sw_hsink). */
static int eval_all(const sw_model *m, sw_data *d, const double *x, double t, int want_grad,
                    int want_hess, int project, double *values, const sw_slots *slots,
                    double *energy) {
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  if (want_grad) memset(d->grad, 0, nd * sizeof(double));
  if (want_hess) memset(d->lowrank, 0, (size_t)d->loff[m->nterm] * sizeof(double));
  int rc;
  double total = 0.0;
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *tm = &m->term[k];
    sw_hsink sink = {.values = values, .slots = slots, .blk = d->hblk};
    int into = want_hess && values;
    int kept = into && !tm->ops->sink_ok && d->hoff[k + 1] > d->hoff[k];
    if (kept && (rc = kept_blocks(m, d, k))) return rc;
    sw_eval ev = {.t = t, .x = x, .grad = want_grad ? d->grad : NULL,
                  .hess = !want_hess ? NULL : into && !kept ? d->hblk : d->hess + d->hoff[k],
                  .sink = into && !kept ? &sink : NULL,
                  .lowrank = want_hess ? d->lowrank + d->loff[k] : NULL, .project = project,
                  .bound = want_hess && project != SW_FILTER_NONE && d->hess_bound,
                  .data = d->tdata[k]};
    double e = 0.0;
    char why[192] = "";
    ev.why = why, ev.whysz = sizeof why;
    double t0 = sw_now();
    rc = tm->ops->eval(tm, m, &ev, &e);
    d->term_time[k] += sw_now() - t0;
    if (kept && !rc) add_kept(m, d, k, values, slots);
    if (rc) {
      sw_errf(d->err, sizeof d->err, "term %s failed at t = %g s: %s", m->term[k].name, t,
              why[0] ? why : "its energy is not finite (no element named)");
      return rc;
    }
    if (!isfinite(e)) {
      sw_errf(d->err, sizeof d->err, "term %s: energy is not finite at t = %g s", m->term[k].name, t);
      return SW_RECOVER;
    }
    d->term_energy[k] = e;
    total += e;
  }
  if (want_grad) d->nforce++;
  if (want_hess) d->nassemble++;
  *energy = total;
  return SW_OK;
}

int sw_eval_terms(const sw_model *m, sw_data *d, const double *x, double t, int want_grad,
                  int want_hess, int project, double *energy) {
  int rc = want_hess ? hess_room(m, d) : SW_OK;
  if (rc) return rc;
  for (int k = 0; want_hess && k < m->nterm; k++) zero_blocks(m, d, k);
  return eval_all(m, d, x, t, want_grad, want_hess, project, NULL, NULL, energy);
}

int sw_eval_terms_into(const sw_model *m, sw_data *d, const double *x, double t, int want_grad,
                       int project, double *values, const sw_slots *slots, double *energy) {
  return eval_all(m, d, x, t, want_grad, 1, project, values, slots, energy);
}

double sw_kinetic(const sw_model *m, const double *v) {
  double k = 0.0;
  for (int i = 0; i < m->nv; i++) {
    double s = 0.0;
    for (int a = 0; a < m->dim; a++) s += v[i * m->dim + a] * v[i * m->dim + a];
    k += 0.5 * m->mass[i] * s; /* J */
  }
  return k;
}

void sw_terms_state(const sw_model *m, sw_data *d) {
  for (int k = 0; k < m->nterm; k++)
    if (m->term[k].ops->state) m->term[k].ops->state(&m->term[k], m, d, d->tdata[k]);
  if (!d->contact_pressure) return;
  for (int f = 0; f < m->nf; f++) {
    double p = 0.0;
    for (int c = 0; c < 3; c++) {
      int i = m->face[3 * f + c];
      double share = d->vertex_area[i], fi = 0.0; /* m^2, N */
      for (int k = 0; k < m->nterm; k++) {
        const sw_term *t = &m->term[k];
        const double *fk = t->ops->vertex_force ? t->ops->vertex_force(t, m, d, d->tdata[k]) : NULL;
        if (fk) fi += fk[i];
      }
      p += share > 0.0 ? fi / share / 3.0 : 0.0; /* N/m^2 */
    }
    d->contact_pressure[f] = p;
  }
}

void sw_terms_commit(const sw_model *m, sw_data *d) {
  for (int k = 0; k < m->nterm; k++)
    if (m->term[k].ops->commit) m->term[k].ops->commit(&m->term[k], m, d, d->tdata[k]);
}

int sw_terms_dissipate(const sw_model *m) {
  for (int k = 0; k < m->nterm; k++)
    if (m->term[k].ops && m->term[k].ops->dissipates &&
        m->term[k].ops->dissipates(&m->term[k], m))
      return 1;
  return 0;
}
