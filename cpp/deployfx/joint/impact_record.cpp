#include "deployfx/joint/impact_record.hpp"

#include <algorithm>

namespace deployfx::joint {

void parabola_peak(const double t[3], const double y[3], double* t_peak, double* y_peak) {
  // Newton's divided differences: p(s) = y0 + d1 (s - t0) + d2 (s - t0)(s - t1).
  const double d1 = (y[1] - y[0]) / (t[1] - t[0]), d12 = (y[2] - y[1]) / (t[2] - t[1]);
  const double d2 = (d12 - d1) / (t[2] - t[0]);
  *t_peak = t[1], *y_peak = y[1];
  if (!(d2 < 0)) return;
  const double s = std::clamp(0.5 * (t[0] + t[1]) - 0.5 * d1 / d2, t[0], t[2]);
  const double p = y[0] + d1 * (s - t[0]) + d2 * (s - t[0]) * (s - t[1]);
  if (p > *y_peak) *t_peak = s, *y_peak = p;
}

void ImpactTracker::observe(int hinge, int wall, bool in_contact, double t, double F, double delta,
                            double delta_dot, std::vector<Impact>& records) {
  if (!open_ && !in_contact) return;
  if (!open_) {
    Impact r;
    r.hinge = hinge, r.wall = wall, r.t_onset = t, r.v_approach = delta_dot;
    r.peak_force = F, r.t_peak = t, r.max_penetration = std::max(delta, 0.0);
    records.push_back(r);
    open_ = true, index_ = records.size() - 1, n_ = 0;
  }
  Impact& r = records[index_];
  if (n_ > 0) r.impulse += 0.5 * (F_[2] + F) * (t - t_[2]), ++r.steps;
  // Shift the samples in; at a sample that is below the one before it, the one before is a local
  // maximum: locate its vertex.
  std::copy(t_ + 1, t_ + 3, t_), std::copy(F_ + 1, F_ + 3, F_), std::copy(x_ + 1, x_ + 3, x_);
  t_[2] = t, F_[2] = F, x_[2] = delta;
  n_ = std::min(n_ + 1, 3);
  if (F > r.peak_force) r.peak_force = F, r.t_peak = t;
  if (delta > r.max_penetration) r.max_penetration = delta;
  if (n_ == 3) {
    double ts, ys;
    if (F_[1] >= F_[0] && F_[1] > F_[2]) {
      parabola_peak(t_, F_, &ts, &ys);
      if (ys > r.peak_force) r.peak_force = ys, r.t_peak = ts;
    }
    if (x_[1] >= x_[0] && x_[1] > x_[2]) {
      parabola_peak(t_, x_, &ts, &ys);
      r.max_penetration = std::max(r.max_penetration, ys);
    }
  }
  if (!in_contact) {
    r.t_separation = t, r.v_rebound = -delta_dot;
    open_ = false;
  }
}

}  // namespace deployfx::joint
