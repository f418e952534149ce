#include "deployfx/joint/latch_follower.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "deployfx/math/check.hpp"

namespace deployfx::joint {
namespace {

using Eigen::Vector2d;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = std::numeric_limits<double>::epsilon();

struct Bore {
  Vector2d er, ep;  // radial and tangential unit vectors at psi
  double s0, kappa, W;
  Vector2d at(double w) const { return (s0 + kappa * w) * er; }
};

Bore bore(const LatchSpring& spring, double pin_angle, double theta) {
  const double psi = theta + pin_angle;
  return {{std::cos(psi), std::sin(psi)}, {-std::sin(psi), std::cos(psi)}, spring.stop, spring.kappa(), spring.travel};
}

// The gap of the pin at compression w against facet f; +inf when out of the facet's range.
double gap_at(const contact::GrooveProfile& p, int f, const Bore& b, double rho, double w, contact::PinQuery* q) {
  *q = p.query(f, b.at(w), rho);
  return q->in_range ? q->gap : kInf;
}

// The highest contact point (largest w) of facet f along the bore within [0, w_top]: the root of
// gap(w) = 0 with gap > 0 above it. Safeguarded Newton (dgap/dw = kappa n·e_r) from w_top, with
// bisection on the bracket [w_near, w_top] that the bore's nearest point to the facet opens.
// Returns false when the bore stays clear of the facet's rho-offset.
// Without one, w_out is the bore's point nearest the facet (the contact point's limit at the
// drop, where the root and that point meet).
bool top_contact(const contact::GrooveProfile& p, int f, const Bore& b, double rho, double w_top, double* w_out,
                 bool* bottomed, double* margin) {
  const auto sd = p.segment_distance(f, b.at(0.0), b.at(w_top));
  *margin = rho - sd.distance;
  *bottomed = false;
  *w_out = sd.param * w_top;
  if (!(sd.distance < rho)) return false;
  contact::PinQuery q;
  if (gap_at(p, f, b, rho, w_top, &q) <= 0) {
    *bottomed = true;
    *w_out = w_top;
    return true;
  }
  double lo = sd.param * w_top, hi = w_top, w = w_top;
  const double tol_w = 8 * kEps * (std::abs(b.s0) + b.W + rho);
  for (int it = 0; it < 200 && hi - lo > tol_w; ++it) {
    const double g = gap_at(p, f, b, rho, w, &q);
    if (g == 0) break;
    (g > 0 ? hi : lo) = w;
    const double slope = q.in_range ? b.kappa * q.n.dot(b.er) : 0.0;
    double next = slope > 0 ? w - g / slope : -1.0;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - w) <= tol_w) {
      w = next;
      break;
    }
    w = next;
  }
  *w_out = w;
  return true;
}

}  // namespace

void LatchSpring::validate() const {
  require_positive("latch.stop", stop, "(m)");
  require_positive("latch.travel", travel, "(m)");
  if (!toward_axis && !(stop - travel > 0))
    throw_out_of_range("latch.travel", travel, "< latch.stop when the spring pushes away from the axis (m)");
  if (!(std::isfinite(preload) && preload >= 0)) throw_out_of_range("latch.preload", preload, ">= 0 (N)");
  if (!(std::isfinite(stiffness) && stiffness >= 0)) throw_out_of_range("latch.stiffness", stiffness, ">= 0 (N/m)");
}

namespace {

// The pin on facet f: its contact point and the theta-derivatives of its position.
FollowerState on_facet(const contact::GrooveProfile& profile, const LatchSpring& spring, const Bore& b, double rho,
                       int f) {
  FollowerState st;
  st.found = top_contact(profile, f, b, rho, spring.travel, &st.w, &st.bottomed, &st.drop_margin);
  st.s = spring.stop + b.kappa * st.w;
  if (!st.found || st.bottomed) return st;  // bottomed: held at the end of its travel, ds = d2s = 0
  // gap(s e_r(psi)) = 0 along theta (psi' = 1): s' = -(n·s e_psi)/(n·e_r), and from the second
  // derivative, c_th^T H c_th + n·c_thth = 0 with c_th = s' e_r + s e_psi and
  // c_thth = s'' e_r + 2 s' e_psi - s e_r.
  const contact::PinQuery q = profile.query(f, b.at(st.w), rho);
  double ner = q.n.dot(b.er);
  if (std::abs(ner) < 1e-12) ner = ner < 0 ? -1e-12 : 1e-12;  // the end of a roll-over: vertical
  st.ds = -st.s * q.n.dot(b.ep) / ner;
  const Vector2d c_th = st.ds * b.er + st.s * b.ep;
  st.d2s = -(c_th.dot(q.dn_dc * c_th) + q.n.dot(2 * st.ds * b.ep - st.s * b.er)) / ner;
  return st;
}

}  // namespace

FollowerState follow(const contact::GrooveProfile& profile, const LatchSpring& spring, double pin_angle, double rho,
                     int support, double theta) {
  if (support < 0) {  // on the bore stop
    FollowerState st;
    st.found = true;
    st.s = spring.stop;
    st.drop_margin = kInf;
    return st;
  }
  FollowerState st = on_facet(profile, spring, bore(spring, pin_angle, theta), rho, support);
  if (st.found) return st;
  // Past the drop (drop_margin < 0): the pin held where the drop left it, s at the drop angle
  // theta_d, the root of drop_margin below theta: bracketed by steps back that grow 4x, then the
  // Illinois secant (the margin is linear on either side of theta_d, kinked there).
  auto at = [&](double th) { return on_facet(profile, spring, bore(spring, pin_angle, th), rho, support); };
  double hi = theta, m_hi = st.drop_margin, back = 1e-9 * std::max(1.0, std::abs(theta));
  FollowerState below = at(theta - back);
  for (int k = 0; k < 40 && !below.found; ++k) {
    hi = theta - back, m_hi = below.drop_margin;
    back *= 4;
    below = at(theta - back);
  }
  if (below.found) {
    double lo = theta - back, m_lo = below.drop_margin;
    int side = 0;
    for (int it = 0; it < 60 && hi - lo > 4 * kEps * std::max(1.0, std::abs(theta)); ++it) {
      double mid = lo + (hi - lo) * m_lo / (m_lo - m_hi);
      if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);
      const FollowerState m = at(mid);
      if (m.found) {
        lo = mid, m_lo = m.drop_margin, below = m;
        if (side == -1) m_hi *= 0.5;
        side = -1;
      } else {
        hi = mid, m_hi = m.drop_margin;
        if (side == 1) m_lo *= 0.5;
        side = 1;
      }
    }
    st.w = below.w;
    st.s = below.s;
  }
  st.beyond = true;
  st.ds = st.d2s = 0.0;
  return st;
}

const FollowerState* FollowerMemo::find(const contact::GrooveProfile& profile, const LatchSpring& spring,
                                        double pin_angle, double rho, int support, double theta) const {
  const bool hit = valid_ && profile.id() == profile_ && support == support_ && theta == theta_ &&
                   pin_angle == pin_angle_ && rho == rho_ && spring.toward_axis == spring_.toward_axis &&
                   spring.stop == spring_.stop && spring.travel == spring_.travel &&
                   spring.preload == spring_.preload && spring.stiffness == spring_.stiffness;
  return hit ? &state_ : nullptr;
}

void FollowerMemo::store(const contact::GrooveProfile& profile, const LatchSpring& spring, double pin_angle,
                         double rho, int support, double theta, const FollowerState& state) {
  valid_ = true;
  profile_ = profile.id();
  spring_ = spring;
  pin_angle_ = pin_angle, rho_ = rho, theta_ = theta;
  support_ = support;
  state_ = state;
}

int next_support(const contact::GrooveProfile& profile, const LatchSpring& spring, double pin_angle, double rho,
                 double theta, double w_from, int exclude) {
  const Bore b = bore(spring, pin_angle, theta);
  const double w_top = std::min(w_from, spring.travel);
  int best = -1;
  double w_best = -kInf;
  for (int f = 0; f < profile.num_facets(); ++f) {
    if (f == exclude) continue;
    double w = 0, margin = 0;
    bool bottomed = false;
    if (!top_contact(profile, f, b, rho, w_top, &w, &bottomed, &margin)) continue;
    // Below w_from only (a fall), and the contact must face the spring: n·e_b < 0.
    const contact::PinQuery q = profile.query(f, b.at(w), rho);
    if (!q.in_range || !(b.kappa * q.n.dot(b.er) > 0)) continue;
    if (w > w_best) {
      w_best = w;
      best = f;
    }
  }
  return best;
}

}  // namespace deployfx::joint
