#pragma once
// The derivative passes of the Newton matrix and the momentum Jacobian: the kinematics
// (kinematics.hpp) run on Duals (math/dual.hpp) whose directions are seeded along
// (dq, dv, dvdot) = (c_q, c_v, c_a) e of up to kDualDirections coordinates of Model::seeds(): the
// border coordinates (the base's six, each undriven hinge angle) and the six attachment
// coordinates z of each hinge on a panel (attachment.hpp), which the parent panel's coordinates
// move through z = P eta. Direction j's tangent is that coordinate's column, c_a d/dvdot +
// c_v d/dv + c_q d/dq, of whatever the pass computes. The panels' own coordinates enter only
// their own body's forces and are differentiated in closed form instead.
#include <vector>

#include "deployfx/multibody/data.hpp"
#include "deployfx/multibody/dual_seed.hpp"

namespace deployfx::multibody {

/// The state of Data (staged by forward_kinematics) on Duals, direction j seeded along
/// Model::seeds()[first + j] (j < count <= kDualDirections) with the coefficients (c_q, c_v,
/// c_a); the base's attitude moves along retract(), R_WB exp(dpsi~).
void seeded_state(const Model& m, const Data& d, int first, int count, double c_q, double c_v, double c_a,
                  BaseMotion<Dual>& base, std::vector<JointState<Dual>>& joints);

/// (a, al, w) of a body frame on Duals: direction j of their tangent, stacked (9).
inline Eigen::Matrix<double, 9, 1> motion_tangent(const Vector3<Dual>& a, const Vector3<Dual>& al,
                                                  const Vector3<Dual>& w, int j) {
  Eigen::Matrix<double, 9, 1> t;
  t << tangent(a, j), tangent(al, j), tangent(w, j);
  return t;
}

}  // namespace deployfx::multibody
