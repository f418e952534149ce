#include "deployfx/multibody/events.hpp"

#include <algorithm>
#include <vector>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "deployfx/contact/impact.hpp"
#include "deployfx/integrate/bordered_solver.hpp"
#include "deployfx/multibody/newton_matrix.hpp"

namespace deployfx::multibody {

Eigen::VectorXd lock_events(const Model& m, const Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  Eigen::Index n = 0;
  for (int k : m.locks()) n += joint::num_events(*m.hinge(k).lock);
  Eigen::VectorXd g(n);
  Eigen::Index i = 0;
  for (int k : m.locks()) {
    const Body& b = m.body(k);
    const joint::LockSpec& lock = *m.hinge(k).lock;
    joint::events(lock, d.locks[k], q(b.iq_theta), v(b.iv_theta), g.data() + i);
    i += joint::num_events(lock);
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
  d.accepted_q = q;
  Eigen::Index i = 0;
  for (int k : m.locks()) {
    const Body& b = m.body(k);
    const joint::LockSpec& lock = *m.hinge(k).lock;
    joint::LockState& h = d.locks[k];
    const double theta = q(b.iq_theta), rate = v(b.iv_theta);
    const int contacts = joint::num_contacts(lock);
    std::vector<char> was(static_cast<std::size_t>(contacts));
    for (int c = 0; c < contacts; ++c) was[c] = joint::contact_state(lock, h, c, theta, rate).contact;
    joint::update(lock, h, theta, rate, margin.size() ? margin.data() + i : nullptr);
    double inverse_inertia = -1;  // e^T M^-1 e, once per accepted step at most
    for (int c = 0; c < contacts; ++c) {
      const joint::WallState w = joint::contact_state(lock, h, c, theta, rate);
      if (w.contact && !was[c]) {
        // A contact closes: the pin's effective mass along its normal, 1 / (lever^2 e^T M^-1 e),
        // and the impact's time scale.
        if (inverse_inertia < 0) inverse_inertia = hinge_inverse_inertia(m, d, q, t, k);
        const double lever = joint::contact_lever(lock, h, c, theta);
        const double mass = 1.0 / (lever * lever * inverse_inertia);
        joint::contact_time_scale(h, c) = contact::rebound_time_scale(joint::law(lock), mass, joint::contact_v0(h, c));
      }
      joint::contact_tracker(h, c).observe(k, c, w.contact, t, w.F, w.delta, w.delta_dot, d.impacts);
    }
    i += joint::num_events(lock);
  }
}

integrate::SecondOrderSystem::StepBounds step_bounds(const Model& m, const Data& d) {
  integrate::SecondOrderSystem::StepBounds out;
  for (int k : m.locks()) {
    const Body& b = m.body(k);
    const joint::ContactResolution res = joint::resolution(*m.hinge(k).lock, d.locks[k], d.accepted_q(b.iq_theta));
    if (!std::isfinite(res.error)) continue;
    if (!out.error.size()) out.error = Eigen::VectorXd::Constant(m.num_velocities(), std::numeric_limits<double>::infinity());
    out.error(b.iv_theta) = res.error;
    out.min_step = out.min_step > 0 ? std::min(out.min_step, res.min_step) : res.min_step;
  }
  return out;
}

double friction_step_limit(const Model& m, const Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                           const Eigen::VectorXd& dv) {
  double limit = 1.0;
  for (int k : m.locks()) {
    const Body& b = m.body(k);
    limit = std::min(limit, joint::friction_step_limit(*m.hinge(k).lock, d.locks[k], q(b.iq_theta), v(b.iv_theta),
                                                       dv(b.iv_theta)));
  }
  return limit;
}

}  // namespace deployfx::multibody
