/* keyframe.c — curves of time: keyframes (tendon rest lengths, obstacles' motion) and ramps
 * (gravity, point loads), docs/scenes.md "Forcing".
 *
 * `smooth` uses the quintic blend b(u) = 6u^5 - 15u^4 + 10u^3 between consecutive keyframes
 * (K. Perlin, "Improving Noise", SIGGRAPH 2002): b(0) = 0, b(1) = 1 and b', b'' vanish at both
 * ends, so the interpolant is C^2 across every keyframe and at the first and last one (where
 * it meets the constant outside), and it stays between the two keyframe values (no
 * overshoot: a rest length never leaves the range its keyframes give).  `linear` is the
 * piecewise-linear interpolant: its slope jumps at every keyframe.  A ramp is the same blend
 * of t / T. */
#include "sinew.h"

/* b(u) for u in [0, 1], clamped outside. */
static double blend(double u) {
  if (u <= 0.0) return 0.0;
  if (u >= 1.0) return 1.0;
  return u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}

/* b'(u) = 30 u^2 (1 - u)^2 in [0, 1], 0 outside. */
static double blend_rate(double u) {
  if (u <= 0.0 || u >= 1.0) return 0.0;
  return 30.0 * u * u * (1.0 - u) * (1.0 - u);
}

/* The keyframe interval k (key_t[k] <= t < key_t[k + 1]) and the fraction u of it; -1 outside
 * the keyframes. */
static int interval(const double *kt, int n, double t, double *u) {
  if (n < 2 || t <= kt[0] || t >= kt[n - 1]) return -1;
  int k = 0;
  while (t > kt[k + 1]) k++;
  *u = (t - kt[k]) / (kt[k + 1] - kt[k]);
  return k;
}

double sw_keyframe_value(const double *kt, const double *kv, int n, int interp, double t) {
  double u = 0.0;
  int k = interval(kt, n, t, &u);
  if (k < 0) return n == 1 || t <= kt[0] ? kv[0] : kv[n - 1];
  double s = interp == SW_INTERP_SMOOTH ? blend(u) : u;
  return kv[k] + s * (kv[k + 1] - kv[k]);
}

double sw_keyframe_rate(const double *kt, const double *kv, int n, int interp, double t) {
  double u = 0.0;
  int k = interval(kt, n, t, &u);
  if (k < 0) return 0.0;
  double ds = interp == SW_INTERP_SMOOTH ? blend_rate(u) : 1.0; /* d s / d u */
  return ds * (kv[k + 1] - kv[k]) / (kt[k + 1] - kt[k]);
}

double sw_ramp(double t, double T) {
  return T > 0.0 ? blend(t / T) : 1.0;
}

double sw_ramp_rate(double t, double T) {
  return T > 0.0 ? blend_rate(t / T) / T : 0.0;
}
