#include "deployfx/multibody/residual.hpp"

#include "deployfx/multibody/forces.hpp"

namespace deployfx::multibody {

Eigen::VectorXd residual(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                         const Eigen::VectorXd& a, double t) {
  forward_kinematics(m, d, q, v, &a, t);
  const int N = m.num_hinges();
  std::vector<Vector6<double>>& f = d.wrench;
  std::vector<Eigen::VectorXd>& Q = d.Q;
  f.resize(static_cast<std::size_t>(N));
  Q.resize(static_cast<std::size_t>(N));
  for (int k = 0; k < N; ++k) f[k] = inertial_wrench(m, d, k, &Q[k]);
  Wrenches<double>& W = d.wrenches;
  backward_pass<double>(m, d.motion, f, W);

  Eigen::VectorXd r = Eigen::VectorXd::Zero(m.num_velocities());
  if (m.base_free()) {
    const Vector6<double> fb = base_inertial_wrench(m, d) + W.root;
    r.head<3>() = d.motion.base.R_WB * fb.head<3>();
    r.segment<3>(3) = fb.tail<3>();
  }
  for (int k = 0; k < N; ++k) {
    const Body& b = m.body(k);
    if (b.iv_theta >= 0) r(b.iv_theta) = W.hinge[k] - hinge_torque(m, d, k).tau;
    if (b.attachment) {  // the subtree's generalized force on the parent's coordinates
      const Body& p = m.body(b.parent);
      const Attachment& att = *b.attachment;
      const Eigen::VectorXd Q = force_on_parent(att, *p.panel, d.elastic[b.parent], W.attach[k]);
      for (std::size_t c = 0; c < att.parent_cols.size(); ++c) r(p.iv_el + att.parent_cols[c]) += Q(static_cast<Eigen::Index>(c));
    }
  }
  for (int k : m.panels()) {
    const Body& b = m.body(k);
    const PanelState& s = d.elastic[k];
    b.panel->add_projected(s, Q[k], r.segment(b.iv_el, b.n_el));
    b.panel->add_elastic_force(s, r.segment(b.iv_el, b.n_el), &d.panels[k]);
  }
  return r;
}

std::vector<int> slaved_velocities(const Model& m) {
  std::vector<int> out;
  for (const int k : m.panels())
    for (const int i : m.body(k).panel->in_plane_coordinates()) out.push_back(m.body(k).iv_el + i);
  return out;
}

bool slaved_rows(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                 const Eigen::VectorXd& a, double t, Eigen::VectorXd& rows) {
  Eigen::Index count = 0;
  for (int k : m.panels()) {
    const Body& b = m.body(k);
    if (b.panel->in_plane_coordinates().empty()) continue;
    if (!b.panel->in_plane_rows()) return false;
    count += static_cast<Eigen::Index>(b.panel->in_plane_coordinates().size());
  }
  for (int k = 0; k < m.num_hinges(); ++k)
    if (m.body(k).attachment && !m.body(m.body(k).parent).panel->in_plane_coordinates().empty()) return false;
  forward_kinematics(m, d, q, v, &a, t);
  rows.resize(count);
  Eigen::Index first = 0;
  for (int k : m.panels()) {
    const Body& b = m.body(k);
    const auto n = static_cast<Eigen::Index>(b.panel->in_plane_coordinates().size());
    if (n == 0) continue;
    const BodyMotion<double>& C = d.motion.body[static_cast<std::size_t>(k)];
    b.panel->in_plane_force(d.elastic[k], C.a, C.al, C.w, rows.segment(first, n), &d.panels[k]);
    first += n;
  }
  return true;
}

}  // namespace deployfx::multibody
