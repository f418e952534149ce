#include "deployfx/multibody/seeds.hpp"

#include "deployfx/math/so3.hpp"

namespace deployfx::multibody {

void seeded_state(const Model& m, const Data& d, int first, int count, double c_q, double c_v, double c_a,
                  BaseMotion<Dual>& base, std::vector<JointState<Dual>>& joints) {
  const BaseMotion<double>& b = d.motion.base;
  base.R_WB = dual(b.R_WB);
  base.r_W = dual(b.r_W);
  base.v_W = dual(b.v_W);
  base.a_W = dual(b.a_W);
  base.w_B = dual(b.w_B);
  base.wd_B = dual(b.wd_B);
  joints.resize(d.joints.size());
  for (std::size_t k = 0; k < d.joints.size(); ++k) {
    const JointState<double>& J = d.joints[k];
    JointState<Dual>& D = joints[k];
    D.theta = J.theta, D.rate = J.rate, D.accel = J.accel;
    if (m.body(static_cast<int>(k)).attachment) {
      D.z = dual(J.z);
      D.z_rate = dual(J.z_rate);
      D.z_accel = dual(J.z_accel);
    }
  }
  for (int j = 0; j < count; ++j) {
    const Seed& s = m.seeds()[static_cast<std::size_t>(first + j)];
    if (s.kind == Seed::kBase) {
      const int i = s.index % 3;
      if (s.index < 3) {  // v_W (and r_W, a_W), W axes
        base.r_W(i).d[j] = c_q, base.v_W(i).d[j] = c_v, base.a_W(i).d[j] = c_a;
      } else {  // w_B, B axes; R_WB -> R_WB exp(dpsi~)
        Eigen::Vector3d e = Eigen::Vector3d::Zero();
        e(i) = 1.0;
        seed(base.R_WB, j, Eigen::Matrix3d(c_q * b.R_WB * skew(e)));
        base.w_B(i).d[j] = c_v, base.wd_B(i).d[j] = c_a;
      }
    } else if (s.kind == Seed::kHinge) {
      JointState<Dual>& D = joints[static_cast<std::size_t>(s.index)];
      D.theta.d[j] = c_q, D.rate.d[j] = c_v, D.accel.d[j] = c_a;
    } else {
      JointState<Dual>& D = joints[static_cast<std::size_t>(s.index)];
      D.z(s.component).d[j] = c_q, D.z_rate(s.component).d[j] = c_v, D.z_accel(s.component).d[j] = c_a;
    }
  }
  base.V_B = base.R_WB.transpose() * base.v_W;
  base.a_B = base.R_WB.transpose() * base.a_W;
}

}  // namespace deployfx::multibody
