#pragma once
// The system's momentum about W's origin in W axes, Pi = [P_W; H_W] = sum_b X_b p_b (the paper's
// Eq. 36-43), each body's momentum about its frame's origin (its own axes),
//   rigid:  p_b = M_b (V, w) (spatial inertia, body/rigid_inertia.hpp),
//   panel:  p = m V + w x s(d) + S1 d',  h = s(d) x V + J(d) w + H(d) d'
//           (body/floating_frame_inertia.hpp),
// carried to W by X_b = [R_Wb 0; o_W~ R_Wb R_Wb]. Pi is linear in v; its Jacobian
// c_v dPi/dv + c_q dPi/dq is analytic: the kinematics' derivative passes (seeds.hpp) for the
// border and attachment coordinates, closed forms for each panel's own.
#include <Eigen/Core>

#include "deployfx/multibody/data.hpp"
#include "deployfx/math/dual.hpp"
#include <vector>

namespace deployfx::multibody {

/// Body k's momentum about C's origin, C axes, at its staged motion (p; h).
Vector6<double> body_momentum(const Model& m, Data& d, int k);
/// Pi(q, v) at time t (which matters for prescribed hinges only), (6); stages the kinematics
/// (without accelerations) in d.
Eigen::VectorXd momentum(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t);
/// The base's own momentum in W (P; H about W's origin), at the staged motion.
Vector6<double> base_momentum(const Model& m, const Data& d);
/// dPi/d(v_W, w_B) (6 x 6) for a free base: every body moving rigidly with the base, the
/// composite inertia of the whole system about W's origin, I_O = sum_b X_b M_b X_b^T, applied to
/// the base's velocity at W's origin, (v_W - w x r_W, w), w = R_WB w_B (Featherstone 2008,
/// Sec. 6.2: the composite rigid body). Equal to momentum_jacobian's base columns at c_q = 0;
/// stages the kinematics in d at (q, v). The velocities v do not enter it: given the caller's,
/// a momentum(q, v) that follows finds the kinematics staged (the momentum polish).
Eigen::Matrix<double, 6, 6> base_velocity_jacobian(const Model& m, Data& d, const Eigen::VectorXd& q,
                                                   const Eigen::VectorXd& v, double t);
/// The momentum's tangent along a derivative pass (seeds.hpp) at the staged state: each body's
/// spatial inertia and momentum there, prepared once for all the passes.
struct MomentumTangent {
  Eigen::Matrix<double, 6, 6> Mb;
  Vector6<double> pb;
  std::vector<Eigen::Matrix<double, 6, 6>> ME;
  std::vector<Vector6<double>> p;
  void prepare(const Model& m, Data& d);
  /// The tangents of Pi along the pass's first `count` directions (base and bodies on Duals), (6 x count).
  Eigen::Matrix<double, 6, Eigen::Dynamic> tangents(const Model& m, const BaseMotion<Dual>& base,
                                                    const TreeMotion<Dual>& motion, int count) const;
};
/// c_v dPi/dv + c_q dPi/dq from the derivative passes' tangents T (6 x Model::seeds(), taken
/// with these coefficients) and each panel's own columns in closed form, at the staged state.
/// `T_rate` (6 x seeds, read in the seed columns of hinges on a manifold panel only): those
/// seeds' tangents along z' alone (c_v = 1, c_q = 0), which the manifold's chain rule needs apart
/// (z' = P G q' moves with q).
Eigen::MatrixXd momentum_columns(const Model& m, Data& d, const Eigen::MatrixXd& T, double c_v, double c_q,
                                 const Eigen::MatrixXd* T_rate = nullptr);
/// c_v dPi/dv + c_q dPi/dq (dq along Model::retract), (6 x nv); stages the kinematics in d.
Eigen::MatrixXd momentum_jacobian(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                  double c_v, double c_q);

}  // namespace deployfx::multibody
