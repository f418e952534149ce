#include "deployfx/multibody/outputs.hpp"

#include <algorithm>

#include "deployfx/multibody/forces.hpp"
#include "deployfx/multibody/momentum.hpp"

namespace deployfx::multibody {

Outputs outputs(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                const Eigen::VectorXd& a, double t) {
  forward_kinematics(m, d, q, v, &a, t);
  const int N = m.num_hinges();
  Outputs o;
  o.theta.resize(N);
  o.rate.resize(N);
  o.spring_torque.resize(N);
  o.lock_force = o.lock_torque = o.latched = o.strain_energy = Eigen::VectorXd::Zero(N);
  o.hinge_force.resize(3, N);
  o.hinge_moment.resize(3, N);
  std::vector<Vector6<double>> f(N);
  for (int k = 0; k < N; ++k) f[k] = inertial_wrench(m, d, k, nullptr);
  Wrenches<double> W;
  backward_pass<double>(m, d.motion, f, W);
  o.kinetic = 0;
  o.potential = 0;
  for (int k = 0; k < N; ++k) {
    const HingeSpec& h = m.hinge(k);
    const Body& b = m.body(k);
    const JointState<double>& J = d.joints[k];
    const BodyMotion<double>& C = d.motion.body[k];
    o.theta(k) = J.theta;
    o.rate(k) = J.rate;
    o.spring_torque(k) = h.tau0 - h.k_theta * J.theta;
    o.potential += -h.tau0 * J.theta + 0.5 * h.k_theta * J.theta * J.theta;
    if (h.lock) {
      const HingeTorque ht = hinge_torque(m, d, k);
      o.lock_force(k) = std::max(ht.lock.normal_force, 0.0);
      o.lock_torque(k) = ht.lock.torque;
      o.latched(k) = joint::latched(*h.lock, d.locks[k]) ? 1.0 : 0.0;
    }
    // Newton-Euler of the subtree: its inertial wrench is the reaction plus the applied torque
    // along the axis (spring, damper, lock), so the reaction is the wrench with its axial moment
    // removed (what the bearings carry; the axial torque is the spring's and the lock's).
    const Eigen::Vector3d n_C = C.R_PC.transpose() * C.n;
    const Eigen::Vector3d M = W.subtree[k].tail<3>();
    o.hinge_force.col(k) = W.subtree[k].head<3>();
    o.hinge_moment.col(k) = M - n_C.dot(M) * n_C;
    o.kinetic += b.rigid.kinetic_energy(C.V, C.w);
    if (b.panel) {
      PanelState& s = d.elastic[k];
      auto& ws = d.panels[k];
      o.kinetic += b.panel->inertia().kinetic_energy(C.V, C.w, s.d, s.dd, &ws.products);
      o.strain_energy(k) = b.panel->strain_energy(s, &ws);
      o.potential += o.strain_energy(k);
    }
  }
  Vector6<double> Pi = base_momentum(m, d);
  o.P_base_W = Pi.head<3>();
  o.H_base_W = Pi.tail<3>();
  o.P_scale = o.P_base_W.norm();
  o.H_scale = o.H_base_W.norm();
  for (int k = 0; k < N; ++k) {
    const BodyMotion<double>& C = d.motion.body[k];
    const Vector6<double> p = body_momentum(m, d, k);
    const Eigen::Vector3d P_W = C.R_WC * p.head<3>(), H_W = C.o_W.cross(P_W) + C.R_WC * p.tail<3>();
    Pi.head<3>() += P_W;
    Pi.tail<3>() += H_W;
    o.P_scale += P_W.norm();
    o.H_scale += H_W.norm();
  }
  o.P_W = Pi.head<3>();
  o.H_W = Pi.tail<3>();
  if (m.base_free()) {
    const BaseMotion<double>& b = d.motion.base;
    o.kinetic += m.spec().base.inertia.kinetic_energy(b.V_B, b.w_B);
  }
  return o;
}

void body_frames(const Model& m, Data& d, const Eigen::VectorXd& q, double t, Eigen::MatrixXd& R, Eigen::MatrixXd& o) {
  forward_kinematics(m, d, q, Eigen::VectorXd::Zero(m.num_velocities()), nullptr, t);
  const int N = m.num_hinges();
  R.resize(3, 3 * N);
  o.resize(3, N);
  for (int k = 0; k < N; ++k) {
    R.middleCols<3>(3 * k) = d.motion.body[k].R_WC;
    o.col(k) = d.motion.body[k].o_W;
  }
}

}  // namespace deployfx::multibody
