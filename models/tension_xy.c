/* tension_xy.c — the per-face "tension XY" diagnostic of Optitex's tension map
 * (Optitex, "Tension XY calculations explanation"), and the warp and
 * weft stretch and shear angle logged beside it.
 *
 * With F = [wu wv] (Optitex): lu = |wu|, lv = |wv|; ampU = max((lu - rlu) min(clip, k_u), 0),
 * ampV likewise; wu and wv are rescaled to lengths ampU and ampV and the face value is
 * |wu + wv|, or |wu - wv| when wu.wv < 0 (N/m).  rlu, rlv: the stretch in the initial
 * configuration, or 1 when the scene chooses the (u,v) layout as reference.  k_u, k_v are the
 * panel's (the membrane's warp and weft stiffness); for a measured fabric (the dde membrane)
 * they are its data's at the face's own strain, 2 (c11 - c12^2/c22) and 2 (c22 - c12^2/c11)
 * of c(e) (models/dde.c), since a knit stiffens tenfold and more as it stretches. */
#include <math.h>

#include "dde.h"
#include "terms.h"

static double norm(const double *w, int d) {
  double s = 0.0;
  for (int a = 0; a < d; a++) s += w[a] * w[a];
  return sqrt(s);
}

void sw_tension_xy_reference(const sw_model *m, sw_data *d) {
  for (int f = 0; f < m->nf; f++) {
    double wu[3], wv[3];
    if (m->opt.tx_reference_uv || m->area[f] == 0.0) {
      d->rlu[f] = d->rlv[f] = 1.0;
      continue;
    }
    sw_face_F(m, f, m->x0, wu, wv);
    d->rlu[f] = norm(wu, m->dim);
    d->rlv[f] = norm(wv, m->dim);
  }
}

/* Optitex's tension XY face value from the two stretched directions. */
static double face_tension(const double *wu, const double *wv, double lu, double lv, double rlu,
                           double rlv, double ku, double kv, int d) {
  double ampu = fmax((lu - rlu) * ku, 0.0), ampv = fmax((lv - rlv) * kv, 0.0); /* N/m */
  double dot = 0.0, s = 0.0;
  for (int a = 0; a < d; a++) dot += wu[a] * wv[a];
  double sign = dot < 0.0 ? -1.0 : 1.0;
  for (int a = 0; a < d; a++) {
    double tu = lu > 0.0 ? wu[a] / lu * ampu : 0.0;
    double tv = lv > 0.0 ? wv[a] / lv * ampv : 0.0;
    double c = tu + sign * tv;
    s += c * c;
  }
  return sqrt(s);
}

void sw_tension_xy(const sw_model *m, sw_data *d) {
  const int dim = m->dim;
  for (int f = 0; f < m->nf; f++) {
    const sw_material *mt = &m->mat[m->face_mat[f]]; /* the panel's k_u, k_v (sw_model_finish) */
    double wu[3], wv[3], ku = mt->tx_k_u, kv = mt->tx_k_v; /* N/m */
    sw_face_F(m, f, d->x, wu, wv);
    if (mt->tx_dde) { /* a measured fabric: its stiffness at this face's strain */
      double e[3], c[4];
      sw_green_voigt(wu, wv, dim, e);
      sw_dde_stiffness(&mt->dde, e, c);
      sw_dde_strip_stiffness(c, &ku, &kv);
    }
    ku = ku > 0 ? fmin(m->opt.tx_clip, ku) : 0.0;
    kv = kv > 0 ? fmin(m->opt.tx_clip, kv) : 0.0;
    double lu = norm(wu, dim), lv = norm(wv, dim), dot = 0.0;
    for (int a = 0; a < dim; a++) dot += wu[a] * wv[a];
    d->stretch_u[f] = lu;
    d->stretch_v[f] = lv;
    /* shear angle: how far wu and wv are from orthogonal, rad, signed */
    double c = (lu > 0.0 && lv > 0.0) ? dot / (lu * lv) : 0.0;
    d->shear[f] = asin(fmax(-1.0, fmin(1.0, c)));
    d->txy[f] = face_tension(wu, wv, lu, lv, d->rlu[f], d->rlv[f], ku, kv, dim);
  }
}
