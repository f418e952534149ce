#include "deployfx/multibody/events.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "deployfx/contact/impact.hpp"
#include "deployfx/integrate/bordered_solver.hpp"
#include "deployfx/multibody/newton_matrix.hpp"

namespace deployfx::multibody {

Eigen::VectorXd lock_events(const Model& m, const Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  Eigen::VectorXd g(2 * static_cast<Eigen::Index>(m.locks().size()));
  Eigen::Index i = 0;
  for (int k : m.locks()) {
    const Body& b = m.body(k);
    joint::lock_events(*m.hinge(k).lock, d.locks[k], q(b.iq_theta), v(b.iv_theta), &g(i), &g(i + 1));
    i += 2;
  }
  return g;
}

double hinge_inverse_inertia(const Model& m, Data& d, const Eigen::VectorXd& q, double t, int k) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(m.num_velocities());
  integrate::BorderedSolver solver;
  if (!solver.factorize(newton_matrix(m, d, q, zero, zero, t, 1.0, 0.0, 0.0)))
    throw std::runtime_error("the mass matrix is singular at t = " + std::to_string(t) + " s");
  Eigen::VectorXd e = zero;
  e(m.body(k).iv_theta) = 1.0;
  return solver.solve(e)(m.body(k).iv_theta);
}

void accept(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t,
            const Eigen::VectorXd& margin) {
  Eigen::Index i = 0;
  for (int k : m.locks()) {
    const Body& b = m.body(k);
    const joint::HingeLockSpec& lock = *m.hinge(k).lock;
    joint::LockHistory& h = d.locks[k];
    const double theta = q(b.iq_theta), rate = v(b.iv_theta);
    const double stop_margin = margin.size() ? margin(i) : 0.0, latch_margin = margin.size() ? margin(i + 1) : 0.0;
    const bool stop_was = h.stop_contact, latch_was = h.latch_contact;
    joint::update_lock_history(lock, h, theta, rate, stop_margin, latch_margin);
    const bool stop_closes = h.stop_contact && !stop_was, latch_closes = h.latch_contact && !latch_was;
    if (stop_closes || latch_closes) {
      // The pin's effective mass along the wall's normal: J_eff / r^2.
      const double r = lock.pin_radius, mass = 1.0 / (r * r * hinge_inverse_inertia(m, d, q, t, k));
      if (stop_closes) h.stop_T = contact::rebound_time_scale(lock.law, mass, h.stop_v0);
      if (latch_closes) h.latch_T = contact::rebound_time_scale(lock.law, mass, h.latch_v0);
    }
    joint::WallState stop, latch;
    joint::wall_states(lock, h, theta, rate, &stop, &latch);
    h.stop_track.observe(k, 0, stop.contact, t, stop.F, stop.delta, stop.delta_dot, d.impacts);
    h.latch_track.observe(k, 1, latch.contact, t, latch.F, latch.delta, latch.delta_dot, d.impacts);
    i += 2;
  }
}

integrate::SecondOrderSystem::StepBounds step_bounds(const Model& m, const Data& d) {
  integrate::SecondOrderSystem::StepBounds out;
  for (int k : m.locks()) {
    const joint::ContactResolution res = joint::contact_resolution(d.locks[k]);
    if (!std::isfinite(res.error)) continue;
    if (!out.error.size()) out.error = Eigen::VectorXd::Constant(m.num_velocities(), std::numeric_limits<double>::infinity());
    out.error(m.body(k).iv_theta) = res.error / m.hinge(k).lock->pin_radius;
    out.min_step = out.min_step > 0 ? std::min(out.min_step, res.min_step) : res.min_step;
  }
  return out;
}

double friction_step_limit(const Model& m, const Data& d, const Eigen::VectorXd& v, const Eigen::VectorXd& dv) {
  double limit = 1.0;
  for (int k : m.locks()) {
    const int i = m.body(k).iv_theta;
    limit = std::min(limit, joint::friction_step_limit(*m.hinge(k).lock, d.locks[k], v(i), dv(i)));
  }
  return limit;
}

}  // namespace deployfx::multibody
