#include "deployfx/multibody/forces.hpp"

namespace deployfx::multibody {

HingeTorque hinge_torque(const Model& m, const Data& d, int k) {
  const HingeSpec& h = m.hinge(k);
  const JointState<double>& J = d.joints[static_cast<std::size_t>(k)];
  HingeTorque out;
  out.tau = h.tau0 - h.k_theta * J.theta - h.c_theta * J.rate;
  out.d_theta = -h.k_theta;
  out.d_rate = -h.c_theta;
  if (h.lock) {
    out.lock = joint::load(*h.lock, d.locks[static_cast<std::size_t>(k)], J.theta, J.rate);
    out.tau += out.lock.torque;
    out.d_theta += out.lock.d_theta;
    out.d_rate += out.lock.d_rate;
  }
  return out;
}

Vector6<double> base_inertial_wrench(const Model& m, const Data& d) {
  const BaseMotion<double>& b = d.motion.base;
  return m.spec().base.inertia.inertial_forces(b.a_B, b.wd_B, b.w_B);
}

Vector6<double> inertial_wrench(const Model& m, Data& d, int k, Eigen::VectorXd* Q) {
  const Body& b = m.body(k);
  const BodyMotion<double>& C = d.motion.body[static_cast<std::size_t>(k)];
  Vector6<double> f = b.rigid.inertial_forces(C.a, C.al, C.w);
  if (b.panel) {
    const PanelState& s = d.elastic[static_cast<std::size_t>(k)];
    // Q with the panel's mass-proportional damping alpha_M L_c d' (one product with the inertial
    // L_c d''; FlexibleBody::add_elastic_force adds the rest of the elastic force).
    const auto fe = b.panel->inertia().inertial_forces(C.a, C.al, C.w, s.d, s.dd, s.ddd,
                                                       &d.panels[static_cast<std::size_t>(k)].products,
                                                       Q ? b.panel->spec().alpha_M : 0.0);
    f.head<3>() += fe.F;
    f.tail<3>() += fe.M;
    if (Q) *Q = fe.Q;
  }
  return f;
}

}  // namespace deployfx::multibody
