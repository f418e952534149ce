#include "deployfx/joint/hinge_lock.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "deployfx/contact/unclamped_force.hpp"
#include "deployfx/math/check.hpp"

namespace deployfx::joint {

constexpr double kMinOnsetSpeed = 1e-3;  // m/s
// friction_step_limit cuts the steps that land farther than this many band widths past it (the
// friction saturated there to 4e-9): exact Newton's cycles across the band were measured landing
// at 13-200 widths on a flexible chain; a nearer landing converges from there or is caught by the
// integrator's 2-cycle breaker (a 1-D model a theta' + b tanh(theta'/w) - c, b/(a w) = 1.5-200,
// roots in and out of the band: 126 of 3510 starts cycle without the limit, none with it).
constexpr double kFarPastBand = 10.0;

void HingeLockSpec::validate() const {
  require_positive("lock.pin_radius", pin_radius, "(m)");
  if (!(clearance >= 0 && std::isfinite(clearance))) throw_out_of_range("lock.clearance", clearance, ">= 0 (m)");
  require_finite("lock.theta_lock", theta_lock, "(rad)");
}

namespace {

// A wall's normal force without the clamp, for a wall in contact (contact/unclamped_force.hpp).
using contact::unclamped_force;

// One wall in contact: penetration delta = s r (theta - theta_w) with s = +1 (stop) or -1 (latch).
void add_wall(const HingeLockSpec& lock, double s, double theta_w, double v0, double theta, double rate,
              LockLoad& out) {
  const double r = lock.pin_radius;
  const auto Fn = unclamped_force(lock.law, s * r * (theta - theta_w), s * r * rate, v0);
  // Normal: torque -s r F_n; friction on the slip r theta' (opposing it), only while pushing.
  const auto Ft = Fn.F > 0 ? lock.friction.evaluate(r * rate, Fn.F) : contact::FrictionForce{};
  out.normal_force += Fn.F;
  out.torque += -s * r * Fn.F + r * Ft.F_t;
  // d delta/d theta = d delta'/d theta' = s r.
  const double dFn_dtheta = Fn.dF_ddelta * s * r, dFn_drate = Fn.dF_ddelta_dot * s * r;
  out.d_theta += -s * r * dFn_dtheta + r * Ft.dF_dF_n * dFn_dtheta;
  out.d_rate += -s * r * dFn_drate + r * (Ft.dF_dv_t * r + Ft.dF_dF_n * dFn_drate);
}

}  // namespace

LockLoad lock_load(const HingeLockSpec& lock, const LockHistory& h, double theta, double rate) {
  LockLoad out;
  if (h.stop_contact) add_wall(lock, +1.0, lock.theta_lock, h.stop_v0, theta, rate, out);
  if (h.latch_contact) add_wall(lock, -1.0, lock.theta_latch(), h.latch_v0, theta, rate, out);
  return out;
}

void wall_states(const HingeLockSpec& lock, const LockHistory& h, double theta, double rate, WallState* stop,
                 WallState* latch) {
  const double r = lock.pin_radius;
  auto state = [&](bool contact, double v0, double delta, double delta_dot) {
    WallState w{contact, 0.0, delta, delta_dot};
    if (contact) w.F = unclamped_force(lock.law, delta, delta_dot, v0).F;
    return w;
  };
  *stop = state(h.stop_contact, h.stop_v0, r * (theta - lock.theta_lock), r * rate);
  *latch = h.latched ? state(h.latch_contact, h.latch_v0, r * (lock.theta_latch() - theta), -r * rate) : WallState{};
}

ContactResolution contact_resolution(const LockHistory& h) {
  ContactResolution out{std::numeric_limits<double>::infinity(), 0.0};
  auto add = [&](bool contact, double T, double v0, double resolution) {
    if (!contact || !(T > 0)) return;
    out.error = std::min(out.error, resolution * v0 * T);
    out.min_step = out.min_step > 0 ? std::min(out.min_step, T / kMaxStepsPerImpactTime) : T / kMaxStepsPerImpactTime;
  };
  add(h.stop_contact, h.stop_T, h.stop_v0, h.stop_resolution);
  add(h.latch_contact, h.latch_T, h.latch_v0, h.latch_resolution);
  return out;
}

void lock_events(const HingeLockSpec& lock, const LockHistory& h, double theta, double rate, double* stop,
                 double* latch) {
  const double r = lock.pin_radius;
  *stop = contact::wall_event(lock.law, h.stop_contact, h.stop_inside, h.stop_v0, r * (theta - lock.theta_lock),
                              r * rate);
  *latch = h.latched ? contact::wall_event(lock.law, h.latch_contact, h.latch_inside, h.latch_v0,
                                           r * (lock.theta_latch() - theta), -r * rate)
                     : std::numeric_limits<double>::infinity();
}

double friction_step_limit(const HingeLockSpec& lock, const LockHistory& h, double rate, double rate_change) {
  if (!(h.stop_contact || h.latch_contact) || !(lock.friction.mu() > 0)) return 1.0;
  const double band = lock.friction.v_reg() / lock.pin_radius;  // rad/s
  const double next = rate + rate_change;
  // Near theta' = 0 already (within a tenth of the band) the step is free: the limit would stall.
  if (!(rate * next < 0) || std::abs(next) <= kFarPastBand * band || std::abs(rate) <= 0.1 * band) return 1.0;
  return rate / (rate - next);
}

void update_lock_history(const HingeLockSpec& lock, LockHistory& h, double theta, double rate, double stop_margin,
                         double latch_margin) {
  if (!h.latched && theta >= lock.theta_latch()) h.latched = true;
  const double r = lock.pin_radius;
  // A wall switches mode when its event function is no longer positive; a closing wall keeps
  // its approach speed (the Hunt-Crossley family's v0).
  auto update = [&](bool& closed, bool& inside, double& v0, double delta, double delta_dot, double margin) {
    if (contact::wall_event(lock.law, closed, inside, v0, delta, delta_dot) <= margin) {
      closed = !closed;
      // The Hunt-Crossley family's damping scales as 1/v0: a wall that recloses while the pin
      // rests on it would get an unbounded damper. Floor: kMinOnsetSpeed.
      if (closed) v0 = std::max(delta_dot, kMinOnsetSpeed);
    }
    inside = !closed && delta > 0;
  };
  update(h.stop_contact, h.stop_inside, h.stop_v0, r * (theta - lock.theta_lock), r * rate, stop_margin);
  if (h.latched)
    update(h.latch_contact, h.latch_inside, h.latch_v0, r * (lock.theta_latch() - theta), -r * rate,
           latch_margin);
}

}  // namespace deployfx::joint
