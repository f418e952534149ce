#include "deployfx/multibody/seeds.hpp"

#include "deployfx/math/so3.hpp"

namespace deployfx::multibody {

void seeded_state(const Model& m, const Data& d, const Seed& s, double c_q, double c_v, double c_a,
                  BaseMotion<Dual>& base, std::vector<JointState<Dual>>& joints) {
  const BaseMotion<double>& b = d.motion.base;
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  Eigen::Vector3d e = zero;
  const bool base_seed = s.kind == Seed::kBase;
  if (base_seed) e(s.index % 3) = 1.0;
  const bool translation = base_seed && s.index < 3, rotation = base_seed && s.index >= 3;
  base.R_WB = dual(b.R_WB, rotation ? Eigen::Matrix3d(c_q * b.R_WB * skew(e)) : Eigen::Matrix3d::Zero().eval());
  base.r_W = dual(b.r_W, translation ? Eigen::Vector3d(c_q * e) : zero);
  base.v_W = dual(b.v_W, translation ? Eigen::Vector3d(c_v * e) : zero);
  base.a_W = dual(b.a_W, translation ? Eigen::Vector3d(c_a * e) : zero);
  base.w_B = dual(b.w_B, rotation ? Eigen::Vector3d(c_v * e) : zero);
  base.wd_B = dual(b.wd_B, rotation ? Eigen::Vector3d(c_a * e) : zero);
  base.V_B = base.R_WB.transpose() * base.v_W;
  base.a_B = base.R_WB.transpose() * base.a_W;

  joints.resize(d.joints.size());
  for (std::size_t k = 0; k < d.joints.size(); ++k) {
    const JointState<double>& J = d.joints[k];
    JointState<Dual>& D = joints[k];
    const bool hinge = s.kind == Seed::kHinge && static_cast<std::size_t>(s.index) == k;
    D.theta = Dual(J.theta, hinge ? c_q : 0.0);
    D.rate = Dual(J.rate, hinge ? c_v : 0.0);
    D.accel = Dual(J.accel, hinge ? c_a : 0.0);
    Vector6<double> u = Vector6<double>::Zero();
    if (s.kind == Seed::kAttachment && static_cast<std::size_t>(s.index) == k) u(s.component) = 1.0;
    D.z = dual(J.z, Vector6<double>(c_q * u));
    D.z_rate = dual(J.z_rate, Vector6<double>(c_v * u));
    D.z_accel = dual(J.z_accel, Vector6<double>(c_a * u));
  }
}

}  // namespace deployfx::multibody
