#include "deployfx/joint/pin_groove.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "deployfx/contact/unclamped_force.hpp"
#include "deployfx/math/check.hpp"
#include "deployfx/math/dual.hpp"

namespace deployfx::joint {
namespace {

using Eigen::Vector2d;
using V = Eigen::Matrix<Dual, 2, 1>;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMinOnsetSpeed = 1e-3;  // m/s, as joint/hinge_lock.cpp
constexpr double kMinHold = 0.05;        // see the header: the cap on the latch's wedge force
constexpr double kFarPastBand = 10.0;    // as joint/hinge_lock.cpp's friction_step_limit
// Dual directions: 0 is d/dtheta, 1 is d/dtheta'.
constexpr int kTh = 0, kRate = 1;

Dual seeded(double v, double d_theta, double d_rate) {
  Dual x(v);
  x.d[kTh] = d_theta;
  x.d[kRate] = d_rate;
  return x;
}
// F(a, b) with partials dF/da, dF/db, on Duals: the chain rule.
Dual lift(double F, double dFa, const Dual& a, double dFb = 0.0, const Dual& b = Dual(0.0)) {
  Dual r(F);
  for (int j = 0; j < Dual::K; ++j) r.d[j] = dFa * a.d[j] + dFb * b.d[j];
  return r;
}
Dual dot(const V& a, const V& b) { return a(0) * b(0) + a(1) * b(1); }
V vec(const Vector2d& v) { return {Dual(v.x()), Dual(v.y())}; }
Vector2d val(const V& v) { return {v(0).v, v(1).v}; }
Vector2d dir(const V& v, int j) { return {v(0).d[j], v(1).d[j]}; }

// The facet's normal at c as a Dual: n + (dn/dc) dc per direction; its tangent t = (n_y, -n_x).
V lift_normal(const contact::PinQuery& q, const V& C) {
  V N = vec(q.n);
  for (int j = 0; j < Dual::K; ++j) {
    const Vector2d dn = q.dn_dc * dir(C, j);
    N(0).d[j] = dn.x();
    N(1).d[j] = dn.y();
  }
  return N;
}
V tangent(const V& N) { return {N(1), -N(0)}; }

// The pin's centre and velocity, as Duals in (theta, theta').
struct Kinematics {
  FollowerState st;
  V C, C_th, C_dot, ER;  // ER: e_r(psi)
  Vector2d er, ep;
};

Kinematics kinematics(const PinGrooveSpec& spec, const PinGrooveHistory& h, double theta, double rate) {
  Kinematics k;
  k.st = pin_position(spec, h, theta);
  const double psi = theta + spec.pin_angle;
  k.er = {std::cos(psi), std::sin(psi)};
  k.ep = {-std::sin(psi), std::cos(psi)};
  const V ER{seeded(k.er.x(), k.ep.x(), 0), seeded(k.er.y(), k.ep.y(), 0)};
  const V EP{seeded(k.ep.x(), -k.er.x(), 0), seeded(k.ep.y(), -k.er.y(), 0)};
  k.ER = ER;
  const Dual S = seeded(k.st.s, k.st.ds, 0), S1 = seeded(k.st.ds, k.st.d2s, 0), R = seeded(rate, 0, 1);
  k.C = S * ER;                // c = s e_r
  k.C_th = S1 * ER + S * EP;   // dc/dtheta = s' e_r + s e_psi
  k.C_dot = R * k.C_th;        // c' = theta' dc/dtheta
  return k;
}

// A closed facet's force on the pin (a Dual 2-vector); adds its normal force to *Fn_sum. The law
// without its clamp (an active-set contact), or with it (`clamped`, a contact without history).
V facet_force(const PinGrooveSpec& spec, const FacetContact& fc, const contact::PinQuery& q, const Kinematics& k,
              double* Fn_sum, bool clamped = false) {
  const V N = lift_normal(q, k.C), T = tangent(N);
  Dual delta = Dual(-q.gap);  // delta = -gap(c): d delta = -n·dc
  for (int j = 0; j < Dual::K; ++j) delta.d[j] = -q.n.dot(dir(k.C, j));
  const Dual delta_dot = -dot(N, k.C_dot);
  const auto f = clamped ? spec.law.evaluate(delta.v, delta_dot.v, fc.v0)
                         : contact::unclamped_force(spec.law, delta.v, delta_dot.v, fc.v0);
  const Dual Fn = lift(f.F, f.dF_ddelta, delta, f.dF_ddelta_dot, delta_dot);
  *Fn_sum += Fn.v;
  V F = Fn * N;
  if (Fn.v > 0) {  // friction only while the facet pushes
    const Dual vt = dot(T, k.C_dot);
    const auto fr = spec.friction.evaluate(vt.v, Fn.v);
    F += lift(fr.F_t, fr.dF_dv_t, vt, fr.dF_dF_n, Fn) * T;
  }
  return F;
}

void check_history(const PinGrooveSpec& spec, const PinGrooveHistory& h) {
  if (static_cast<int>(h.facets.size()) != spec.profile.num_facets())
    throw std::invalid_argument("history.facets has " + std::to_string(h.facets.size()) +
                                " entries: expected one per profile facet, " +
                                std::to_string(spec.profile.num_facets()) + " (use start_history)");
  if (h.support >= spec.profile.num_facets() || (h.support >= 0 && !spec.latch))
    throw std::invalid_argument("history.support = " + std::to_string(h.support) +
                                " is out of range: must be -1, or a facet index with a latch spring");
}

}  // namespace

PinGrooveSpec::PinGrooveSpec(contact::GrooveProfile profile_, double pin_distance_, double pin_angle_,
                             double pin_radius_, contact::ContactLaw law_, contact::CoulombFriction friction_,
                             std::optional<LatchSpring> latch_)
    : profile(std::move(profile_)),
      pin_distance(pin_distance_),
      pin_angle(pin_angle_),
      pin_radius(pin_radius_),
      law(law_),
      friction(friction_),
      latch(latch_) {
  if (latch)
    latch->validate();
  else
    require_positive("groove.pin_distance", pin_distance, "(m)");
  require_finite("groove.pin_angle", pin_angle, "(rad)");
  if (!(std::isfinite(pin_radius) && pin_radius >= 0)) throw_out_of_range("groove.pin_radius", pin_radius, ">= 0 (m)");
}

FollowerState pin_position(const PinGrooveSpec& spec, const PinGrooveHistory& h, double theta) {
  if (spec.latch) {
    const LatchSpring& L = *spec.latch;
    if (const FollowerState* st = h.follower.find(spec.profile, L, spec.pin_angle, spec.pin_radius, h.support, theta))
      return *st;
    const FollowerState st = follow(spec.profile, L, spec.pin_angle, spec.pin_radius, h.support, theta);
    h.follower.store(spec.profile, L, spec.pin_angle, spec.pin_radius, h.support, theta, st);
    return st;
  }
  FollowerState st;
  st.found = true;
  st.s = spec.pin_distance;
  st.drop_margin = kInf;
  return st;
}

PinGrooveHistory start_history(const PinGrooveSpec& spec, double theta) {
  PinGrooveHistory h;
  h.facets.resize(static_cast<std::size_t>(spec.profile.num_facets()));
  if (spec.latch) h.support = next_support(spec.profile, *spec.latch, spec.pin_angle, spec.pin_radius, theta, kInf, -1);
  const Kinematics k = kinematics(spec, h, theta, 0.0);
  for (int f = 0; f < spec.profile.num_facets(); ++f) {
    const auto q = spec.profile.query(f, val(k.C), spec.pin_radius);
    h.facets[static_cast<std::size_t>(f)].armed = f == h.support || (q.in_range && q.gap >= 0);
  }
  return h;
}

PinGrooveLoad pin_groove_load(const PinGrooveSpec& spec, const PinGrooveHistory& h, double theta, double rate) {
  check_history(spec, h);
  const Kinematics k = kinematics(spec, h, theta, rate);
  const Vector2d c = val(k.C);
  PinGrooveLoad out;
  out.pin_position = k.st.s;
  V F{Dual(0.0), Dual(0.0)};  // the contact forces on the pin, N (P's hinge plane)
  for (int f = 0; f < spec.profile.num_facets(); ++f) {
    const FacetContact& fc = h.facets[static_cast<std::size_t>(f)];
    if (f == h.support || !fc.closed) continue;
    const auto q = spec.profile.query(f, c, spec.pin_radius);
    if (q.in_range) F += facet_force(spec, fc, q, k, &out.normal_force);
  }
  if (spec.latch && h.support >= 0) {
    const auto q = spec.profile.query(h.support, c, spec.pin_radius);
    out.support_lost = !k.st.found;
    if (k.st.bottomed && q.in_range) {  // a fixed pin at the end of its travel: the law, clamped
      FacetContact fc;
      fc.closed = true;
      const Dual delta_dot = -dot(lift_normal(q, k.C), k.C_dot);
      fc.v0 = std::max(std::abs(delta_dot.v), kMinOnsetSpeed);
      F += facet_force(spec, fc, q, k, &out.normal_force, true);
    } else if ((k.st.found || k.st.beyond) && q.in_range) {
      // The massless pin's balance along the bore e_b: N (n + f t)·e_b = -(F_s + F_others·e_b).
      const LatchSpring& L = *spec.latch;
      const V N = lift_normal(q, k.C), T = tangent(N);
      const auto fr = spec.friction.evaluate(dot(T, k.C_dot).v, 1.0);  // f = F_t / F_n
      const Dual f_ratio = lift(fr.F_t, fr.dF_dv_t, dot(T, k.C_dot));
      const V EB = -L.kappa() * k.ER;  // e_b = -kappa e_r
      const Dual Fs = L.preload + L.stiffness * L.kappa() * (seeded(k.st.s, k.st.ds, 0) - L.stop);
      const V dirn = N + f_ratio * T;
      Dual den = dot(dirn, EB);
      if (den.v > -kMinHold) den = Dual(-kMinHold);
      const Dual Nsup = -(Fs + dot(F, EB)) / den;
      out.support_force = Nsup.v;
      out.normal_force += Nsup.v;
      F += Nsup * dirn;
    }
  }
  const Dual tau = k.C(0) * F(1) - k.C(1) * F(0);  // (c x F)·n_axis
  out.torque = tau.v;
  out.d_theta = tau.d[kTh];
  out.d_rate = tau.d[kRate];
  return out;
}

namespace {

// facet_state at the pin's kinematics k.
WallState facet_state_at(const PinGrooveSpec& spec, const PinGrooveHistory& h, int facet, const Kinematics& k) {
  const auto q = spec.profile.query(facet, val(k.C), spec.pin_radius);
  WallState w;
  if (facet == h.support || !q.in_range) return w;
  const FacetContact& fc = h.facets[static_cast<std::size_t>(facet)];
  w.delta = -q.gap;
  w.delta_dot = -q.n.dot(val(k.C_dot));
  w.contact = fc.closed;
  if (fc.closed) w.F = contact::unclamped_force(spec.law, w.delta, w.delta_dot, fc.v0).F;
  return w;
}

}  // namespace

WallState facet_state(const PinGrooveSpec& spec, const PinGrooveHistory& h, int facet, double theta, double rate) {
  check_history(spec, h);
  return facet_state_at(spec, h, facet, kinematics(spec, h, theta, rate));
}

std::vector<WallState> facet_states(const PinGrooveSpec& spec, const PinGrooveHistory& h, double theta, double rate) {
  check_history(spec, h);
  const Kinematics k = kinematics(spec, h, theta, rate);
  std::vector<WallState> out;
  out.reserve(static_cast<std::size_t>(spec.profile.num_facets()));
  for (int f = 0; f < spec.profile.num_facets(); ++f) out.push_back(facet_state_at(spec, h, f, k));
  return out;
}

double facet_lever(const PinGrooveSpec& spec, const PinGrooveHistory& h, int facet, double theta) {
  check_history(spec, h);
  const Kinematics k = kinematics(spec, h, theta, 0.0);
  return -spec.profile.query(facet, val(k.C), spec.pin_radius).n.dot(val(k.C_th));  // delta = -gap
}

ContactResolution contact_resolution(const PinGrooveSpec& spec, const PinGrooveHistory& h, double theta) {
  ContactResolution out{kInf, 0.0};
  for (int f = 0; f < spec.profile.num_facets(); ++f) {
    const FacetContact& fc = h.facets[static_cast<std::size_t>(f)];
    if (!fc.closed || !(fc.T > 0) || f == h.support) continue;
    const double lever = std::abs(facet_lever(spec, h, f, theta));
    if (lever > 0) out.error = std::min(out.error, fc.resolution * fc.v0 * fc.T / lever);
    const double step = fc.T / kMaxStepsPerImpactTime;
    out.min_step = out.min_step > 0 ? std::min(out.min_step, step) : step;
  }
  return out;
}

int num_events(const PinGrooveSpec& spec) { return spec.profile.num_facets() + (spec.latch ? 1 : 0); }

void pin_groove_events(const PinGrooveSpec& spec, const PinGrooveHistory& h, double theta, double rate,
                       double* events) {
  check_history(spec, h);
  const Kinematics k = kinematics(spec, h, theta, rate);
  const Vector2d c = val(k.C), c_dot = val(k.C_dot);
  for (int f = 0; f < spec.profile.num_facets(); ++f) {
    const FacetContact& fc = h.facets[static_cast<std::size_t>(f)];
    double& e = events[f];
    e = kInf;
    if (f == h.support || !fc.armed) continue;
    const auto q = spec.profile.query(f, c, spec.pin_radius);
    if (!q.in_range) {
      if (fc.closed) e = 0.0;  // slid off the facet's end while in contact: it opens
      continue;
    }
    e = contact::wall_event(spec.law, fc.closed, fc.inside, fc.v0, -q.gap, -q.n.dot(c_dot));
  }
  if (spec.latch) events[spec.profile.num_facets()] = h.support >= 0 ? k.st.drop_margin : kInf;
}

void update_history(const PinGrooveSpec& spec, PinGrooveHistory& h, double theta, double rate,
                    const double* margins) {
  check_history(spec, h);
  const int nf = spec.profile.num_facets();
  auto margin = [&](int i) { return margins ? margins[i] : 0.0; };
  // The drop first: it moves the pin, and the facets are then updated where it lands.
  if (spec.latch && h.support >= 0) {
    const FollowerState st = pin_position(spec, h, theta);
    if (st.drop_margin <= margin(nf)) {
      const int old = h.support;
      const LatchSpring& L = *spec.latch;
      h.support = next_support(spec.profile, L, spec.pin_angle, spec.pin_radius, theta, L.travel, old);
      // The old support, left at its tangency (gap ~ 0 to round-off), is handed over as a facet
      // that has just separated (hinge_lock's `inside`): it closes again only if it would push.
      FacetContact& was = h.facets[static_cast<std::size_t>(old)];
      was.armed = true;
      was.closed = false;
      was.inside = true;
      was.T = 0.0;
    }
  }
  const Kinematics k = kinematics(spec, h, theta, rate);
  const Vector2d c = val(k.C), c_dot = val(k.C_dot);
  for (int f = 0; f < nf; ++f) {
    FacetContact& fc = h.facets[static_cast<std::size_t>(f)];
    if (f == h.support) {  // carried by the spring, no contact of its own (its records kept)
      fc.armed = true;
      fc.closed = fc.inside = false;
      fc.T = 0.0;
      continue;
    }
    const auto q = spec.profile.query(f, c, spec.pin_radius);
    if (!q.in_range) {
      fc.armed = fc.closed = fc.inside = false;
      fc.T = 0.0;
      continue;
    }
    if (q.gap >= 0) fc.armed = true;  // as hinge_lock's latch: armed first, then its mode
    if (!fc.armed) continue;
    const double delta = -q.gap, delta_dot = -q.n.dot(c_dot);
    // An open facet the pin touches without penetrating (delta = 0 to the last bit, as at a drop
    // located on the latch flank) while moving away does not close: no contact to make.
    const bool leaving = !fc.closed && delta <= 0 && delta_dot <= 0;
    if (!leaving && contact::wall_event(spec.law, fc.closed, fc.inside, fc.v0, delta, delta_dot) <= margin(f)) {
      fc.closed = !fc.closed;
      // The Hunt-Crossley family's damping scales as 1/v0: floored as in hinge_lock.cpp.
      if (fc.closed) fc.v0 = std::max(delta_dot, kMinOnsetSpeed);
      if (!fc.closed) fc.T = 0.0;  // the engine sets T when a facet closes
    }
    fc.inside = !fc.closed && delta > 0;
  }
}

double friction_step_limit(const PinGrooveSpec& spec, const PinGrooveHistory& h, double theta, double rate,
                           double rate_change) {
  check_history(spec, h);
  if (!(spec.friction.mu() > 0)) return 1.0;
  const Kinematics k = kinematics(spec, h, theta, rate);
  const Vector2d c = val(k.C), c_th = val(k.C_th);
  double band = kInf;  // rad/s
  for (int f = 0; f < spec.profile.num_facets(); ++f) {
    if (!(f == h.support || h.facets[static_cast<std::size_t>(f)].closed)) continue;
    const auto q = spec.profile.query(f, c, spec.pin_radius);
    const double lever = std::abs(q.t.dot(c_th));  // v_t = theta' t·dc/dtheta
    if (q.in_range && lever > 0) band = std::min(band, spec.friction.v_reg() / lever);
  }
  if (!std::isfinite(band)) return 1.0;
  const double next = rate + rate_change;
  if (!(rate * next < 0) || std::abs(next) <= kFarPastBand * band || std::abs(rate) <= 0.1 * band) return 1.0;
  return rate / (rate - next);
}

}  // namespace deployfx::joint
