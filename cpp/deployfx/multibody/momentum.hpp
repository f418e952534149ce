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

namespace deployfx::multibody {

/// Body k's momentum about C's origin, C axes, at its staged motion (p; h).
Vector6<double> body_momentum(const Model& m, Data& d, int k);
/// Pi(q, v), (6); stages the kinematics (without accelerations) in d.
Eigen::VectorXd momentum(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v);
/// The base's own momentum in W (P; H about W's origin), at the staged motion.
Vector6<double> base_momentum(const Model& m, const Data& d);
/// c_v dPi/dv + c_q dPi/dq (dq along Model::retract), (6 x nv); stages the kinematics in d.
Eigen::MatrixXd momentum_jacobian(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                  double c_v, double c_q);

}  // namespace deployfx::multibody
