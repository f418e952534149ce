#include "deployfx/multibody/events.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <vector>
#include <cmath>
#include <limits>
#include <optional>
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

HingeInverseInertia hinge_inverse_inertia(const Model& m, Data& d, const Eigen::VectorXd& q, double t, int k) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(m.num_velocities());
  const integrate::BlockMatrix M = newton_matrix(m, d, q, zero, zero, t, 1.0, 0.0, 0.0);
  integrate::BorderedSolver& solver = d.mass_solver;
  if (!solver.factorize(M)) throw std::runtime_error("the mass matrix is singular at t = " + std::to_string(t) + " s");
  const int i = m.body(k).iv_theta;
  Eigen::VectorXd e = zero;
  e(i) = 1.0;
  HingeInverseInertia out;
  out.free = solver.solve(e)(i);
  // The border holds the base and the hinges, the elastic block every panel's coordinates: the
  // border's own block is the mass matrix with the panels' deformation rates held at zero.
  out.rigid = out.free;
  if (i < M.border()) {
    Eigen::VectorXd eb = Eigen::VectorXd::Unit(M.border(), i);
    const Eigen::VectorXd x = M.A.partialPivLu().solve(eb);
    if (std::isfinite(x(i)) && x(i) > 0) out.rigid = x(i);
  }
  return out;
}

bool accept(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t,
            const Eigen::VectorXd& margin) {
  d.accepted_q = q;
  bool dropped = false;
  Eigen::Index i = 0;
  for (int k : m.locks()) {
    const Body& b = m.body(k);
    const joint::LockSpec& lock = *m.hinge(k).lock;
    joint::LockState& h = d.locks[k];
    const double theta = q(b.iq_theta), rate = v(b.iv_theta);
    const int contacts = joint::num_contacts(lock);
    const std::vector<joint::WallState> was = joint::contact_states(lock, h, theta, rate);
    const int support = joint::support(h);
    joint::update(lock, h, theta, rate, margin.size() ? margin.data() + i : nullptr);
    dropped = dropped || joint::support(h) != support;
    const std::vector<joint::WallState> now = joint::contact_states(lock, h, theta, rate);
    std::optional<HingeInverseInertia> inverse_inertia;  // once per accepted step at most
    for (int c = 0; c < contacts; ++c) {
      const joint::WallState& w = now[static_cast<std::size_t>(c)];
      if (w.contact && !was[static_cast<std::size_t>(c)].contact) {
        // A contact closes: the pin's effective mass along its normal, 1 / (lever^2 e^T M^-1 e),
        // and the impact's time scale. On a deforming panel that mass is the fitting's and the
        // root's, which a damped law (the paper's D) stops within m / D: no rebound of the pin
        // alone to resolve (rebound_time_scale 0). The panel behind it still rebounds on the
        // wall's Hertz stiffness, over the time scale of the hinge's inertia with the panel held
        // rigid (the paper's panel: 6 ms at the first lock's 33 mm/s, against the pin's m/D =
        // 22 us): that contact is resolved, to kPanelContactResolution of its penetration scale.
        // Stepped over at dt instead (omega h ~ 1 at the latch's 1e3 N), the undamped rattle on
        // the walls pumped energy into the panel on one trajectory in ten, and the damped scene's
        // largest tip displacement was 3.6e-3 off (issue 29, docs/research/undamped-stability.md).
        if (!inverse_inertia) inverse_inertia = hinge_inverse_inertia(m, d, q, t, k);
        const double lever = joint::contact_lever(lock, h, c, theta);
        const double v0 = joint::contact_v0(h, c);
        const double T = contact::rebound_time_scale(joint::law(lock), 1.0 / (lever * lever * inverse_inertia->free), v0);
        if (T > 0) {
          joint::set_contact_scale(h, c, T, joint::kContactResolution);
        } else {
          const double mass = 1.0 / (lever * lever * inverse_inertia->rigid);
          joint::set_contact_scale(h, c, contact::rebound_time_scale(joint::law(lock), mass, v0),
                                   joint::kPanelContactResolution);
        }
      }
      joint::contact_tracker(h, c).observe(k, c, w.contact, t, w.F, w.delta, w.delta_dot, d.impacts);
    }
    i += joint::num_events(lock);
  }
  return dropped;
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
