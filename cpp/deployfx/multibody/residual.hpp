#pragma once
// The equations of motion in residual form (inverse dynamics), by virtual power over every body
// (docs/engine-design.md, "System assembly"):
//   r(q, v, vdot, t) = sum_b J_b^T f_b(q, v, vdot) - tau(q, v, t) + (f_int + damping on each panel) = 0,
// f_b each body's inertial wrench (forces.hpp), assembled by one forward pass of the motions and
// one backward pass of the wrenches (kinematics.hpp):
//   base rows:    [R_WB (F_b + F_root); M_b + M_root]  (virtual power of v_W, W axes, and w_B, B axes),
//   hinge k:      n . (R_PC M_k) - tau_k               (theta_k' turns its subtree about the axis),
//   panel k:      Q_k + sum_{hinges c on k} P_c^T tau_z,c + f_int,k(eta_k) + damping
//                 (the attachments' generalized forces, attachment.hpp).
#include <Eigen/Core>
#include <vector>

#include "deployfx/multibody/data.hpp"

namespace deployfx::multibody {

/// r(q, v, a, t) (size nv); stages the kinematics in d.
Eigen::VectorXd residual(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                         const Eigen::VectorXd& a, double t);

/// The panels' in-plane (slaved) coordinates' velocity indices, panel by panel
/// (body::FlexibleBody::in_plane_coordinates; TreeSystem::slaved_velocities()).
std::vector<int> slaved_velocities(const Model& m);

/// r's rows at the panels' in-plane coordinates alone (slaved_velocities(), in that order) into `rows`, for about half a residual's work where every such panel is a mesh with
/// Green strain (body::FlexibleBody::in_plane_force) and no hinge rides on it (the attachments'
/// forces, which act on its rows, come from the subtree's whole backward pass). False (rows
/// untouched) otherwise: the caller then takes the whole residual. Stages the kinematics in d.
bool slaved_rows(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                 const Eigen::VectorXd& a, double t, Eigen::VectorXd& rows);

}  // namespace deployfx::multibody
