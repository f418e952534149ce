#pragma once
// The Newton iteration matrix of an implicit scheme, S = c_a dr/dvdot + c_v dr/dv + c_q dr/dq
// (dr/dq along Model::retract), analytic for every fidelity and topology:
// - the border columns (base, hinge angles) and the attachment coordinates z of each hinge on a
//   panel: the residual's passes (kinematics.hpp) run on Duals seeded along that coordinate
//   (seeds.hpp), with each body's force differentiated in closed form in its motion (a, al, w)
//   (FloatingFrameInertia::inertial_force_jacobians, body/rigid_force_jacobian.hpp) and the
//   lock's torque in (theta, theta') (joint/lock.hpp); a z column reaches the parent panel's
//   coordinates through z = P eta;
// - each panel's own coordinates: its elastic block c_a L_c + c_v 2 G_y(w) + c_q (G_y(al) +
//   G_w(w) + K_T) with damping (docs/engine-design.md), and its wrench's derivatives in
//   (eta'', eta', eta) carried to the rows above it by the backward pass's linear map.
// The result is bordered: [A B; C E], A the border, E sparse on Model::pattern().
#include <Eigen/Core>

#include "deployfx/integrate/block_matrix.hpp"
#include "deployfx/multibody/data.hpp"

namespace deployfx::multibody {

/// S at (q, v, a, t) with the coefficients (c_a, c_v, c_q); stages the kinematics in d. With
/// `momentum_jacobian` (and c_v > 0), also (1/c_v)(c_v dPi/dv + c_q dPi/dq) from the same
/// derivative passes (momentum.hpp): what an integrator's momentum rows need with the matrix.
integrate::BlockMatrix newton_matrix(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                     const Eigen::VectorXd& a, double t, double c_a, double c_v, double c_q,
                                     Eigen::MatrixXd* momentum_jacobian = nullptr);

/// A kept S's panels' own elastic blocks formed anew at (q, v, a, t) with (c_a, c_v, c_q), in
/// place; the border rows and columns and the panels' wrench derivatives stay as S was built
/// (SecondOrderSystem::refresh_elastic_blocks). False, S unchanged, where m has no panel, where
/// another term may share a panel's values (any hinge attached to a panel) or a panel lies on a
/// manifold (its block needs the whole force on its coordinates), or S is not of m's shape.
bool refresh_panel_blocks(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                          const Eigen::VectorXd& a, double t, double c_a, double c_v, double c_q,
                          integrate::BlockMatrix& S);

}  // namespace deployfx::multibody
