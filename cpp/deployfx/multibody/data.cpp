#include "deployfx/multibody/data.hpp"

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>

namespace deployfx::multibody {

Data::Data(const Model& m)
    : locks(static_cast<std::size_t>(m.num_hinges())),
      panels(static_cast<std::size_t>(m.num_hinges())),
      joints(static_cast<std::size_t>(m.num_hinges())),
      elastic(static_cast<std::size_t>(m.num_hinges())),
      hinges_(m.num_hinges()),
      nq_(m.num_positions()),
      nv_(m.num_velocities()) {
  reset_history(m, m.initial_positions());
}

void Data::reset_history(const Model& m, const Eigen::VectorXd& q) {
  for (joint::LockState& h : locks) h = joint::LockHistory{};
  for (int k : m.locks()) locks[static_cast<std::size_t>(k)] = joint::start_state(*m.hinge(k).lock, q(m.body(k).iq_theta));
  impacts.clear();
}

bool Data::fits(const Model& m) const {
  return hinges_ == m.num_hinges() && nq_ == m.num_positions() && nv_ == m.num_velocities();
}

void check_data(const Model& m, const Data& d) {
  if (!d.fits(m))
    throw std::invalid_argument("data was made for another model (" + std::to_string(d.joints.size()) +
                                " hinges): make it with this model's make_data()");
}

BaseMotion<double> base_motion(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                               const Eigen::VectorXd* a) {
  BaseMotion<double> b;
  if (!m.base_free()) return b;
  b.r_W = q.head<3>();
  b.R_WB = Eigen::Quaterniond(q(3), q(4), q(5), q(6)).normalized().toRotationMatrix();
  b.v_W = v.head<3>();
  b.w_B = v.segment<3>(3);
  if (a) b.a_W = a->head<3>(), b.wd_B = a->segment<3>(3);
  b.V_B = b.R_WB.transpose() * b.v_W;
  b.a_B = b.R_WB.transpose() * b.a_W;
  return b;
}

namespace {

// z = P eta on the attachment's nonzero columns.
Vector6<double> attachment_coordinates(const Attachment& att, const Eigen::VectorXd& eta) {
  Vector6<double> z = Vector6<double>::Zero();
  for (std::size_t c = 0; c < att.cols.size(); ++c) z += att.P_cols.col(static_cast<Eigen::Index>(c)) * eta(att.cols[c]);
  return z;
}

}  // namespace

void forward_kinematics(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                        const Eigen::VectorXd* a, double t) {
  // Staged already at this state (a caller without accelerations reads none).
  if ((t == d.t || !m.driven()) && q.size() == d.staged_q.size() && q == d.staged_q && v == d.staged_v &&
      (!a || (d.staged_a && *a == d.staged_accel)))
    return;
  d.t = t;
  d.staged_q = q;
  d.staged_v = v;
  d.staged_a = a != nullptr;
  if (a) d.staged_accel = *a;
  for (int k : m.panels()) {
    const Body& b = m.body(k);
    PanelState& s = d.elastic[static_cast<std::size_t>(k)];
    s.q = q.segment(b.iq_el, b.n_el);
    s.v = v.segment(b.iv_el, b.n_el);
    if (a) s.a = a->segment(b.iv_el, b.n_el);
    else s.a.setZero(b.n_el);
    // In place: staging runs at every residual and matrix, and its vectors keep their sizes.
    b.panel->stage(s);
  }
  for (int k = 0; k < m.num_hinges(); ++k) {
    const Body& b = m.body(k);
    JointState<double>& J = d.joints[static_cast<std::size_t>(k)];
    if (const auto& driver = m.hinge(k).driver) {
      driver->evaluate(t, &J.theta, &J.rate, &J.accel);
    } else {
      J.theta = q(b.iq_theta);
      J.rate = v(b.iv_theta);
      J.accel = a ? (*a)(b.iv_theta) : 0.0;
    }
    if (b.attachment) {  // on a manifold, from the staged Ritz coordinates g(q), G q', G q'' + C(q', q')
      const PanelState& p = d.elastic[static_cast<std::size_t>(b.parent)];
      const bool on_eta = b.attachment->manifold;
      J.z = attachment_coordinates(*b.attachment, on_eta ? p.d : p.q);
      J.z_rate = attachment_coordinates(*b.attachment, on_eta ? p.dd : p.v);
      J.z_accel = attachment_coordinates(*b.attachment, on_eta ? p.ddd : p.a);
    }
  }
  forward_kinematics<double>(m, base_motion(m, q, v, a), d.joints, d.motion);
}

}  // namespace deployfx::multibody
