#pragma once
// A hinge on a flexible parent panel: the hinge fitting is bolted to one node of the parent's
// mesh, the node nearest the hinge point, and is rigid from that node to the hinge point. The
// attachment moves with the node's elastic translation u and small rotation psi (the shell's
// nodal rotation-vector dofs), both linear in the parent's elastic coordinates eta (Ritz
// coordinates or free mesh dofs): z = (u, psi) = P eta, and
//   R_att = exp(psi~),   o = X + u + R_att r,   r = point - X   (the hinge point, parent's frame),
// with the child's hinge axis and stowed axes turned by R_att. This is the floating-frame
// treatment of a joint on a deformable body through a joint frame rigidly attached at a node
// (Shabana, "Dynamics of Multibody Systems", 4th ed., 2013, Ch. 5) and Wallrapp's standard input
// data, whose node frame carries an origin moving with Phi eta and an orientation I + (Psi eta)~
// (Wallrapp, Mech. Struct. Mach. 22(3), 1994, 283-304); exp() keeps the child's axes orthonormal.
//
// The engine treats z as the coordinates of a six-dof joint between the parent's frame and the
// hinge (docs/engine-design.md, "One engine for a tree"). Velocities and accelerations, in P
// axes, relative to P (exact derivatives, so the equations stay conservative; T(psi) the left
// Jacobian of SO(3), math/so3.hpp), with rho = R_att r:
//   w_att = T psi',  al_att = T psi'' + T'(psi, psi') psi',
//   o'  = u' + w_att x rho,  o'' = u'' + al_att x rho + w_att x (w_att x rho).
// A wrench (F, M about o, P axes) on the child side does the power F.o' + M.w_att, so its
// generalized force on z is tau_z = [F; T^T (rho x F + M)], and on the parent's coordinates P^T tau_z.
#include <Eigen/Core>
#include <vector>

#include "deployfx/body/flexible_body.hpp"
#include "deployfx/fem/shell_model.hpp"
#include "deployfx/math/so3.hpp"

namespace deployfx::multibody {

template <class S>
using Vector6 = Eigen::Matrix<S, 6, 1>;

/// The immutable attachment of a hinge to a flexible parent.
struct Attachment {
  int node = -1;                                 ///< the parent's mesh node
  Eigen::Vector3d X = Eigen::Vector3d::Zero();   ///< the node, P (undeformed), m
  Eigen::Vector3d r = Eigen::Vector3d::Zero();   ///< rigid arm node -> hinge point, P axes, m
  /// z = (u, psi) per parent coordinate (FlexibleBody::mesh_rows: its elastic coordinates, or the
  /// Ritz coordinates eta on a manifold), (6 x n); its nonzero columns `cols` (the node's free
  /// dofs for a full panel, every Ritz coordinate for a reduced one) and P on them.
  Eigen::Matrix<double, 6, Eigen::Dynamic> P;
  std::vector<int> cols;
  Eigen::Matrix<double, 6, Eigen::Dynamic> P_cols;
  /// On a reduced-manifold parent P acts on its Ritz coordinates eta = g(q), which every elastic
  /// coordinate q moves: z = P g(q), z' = P G q', z'' = P (G q'' + C(q', q')), and a generalized
  /// force tau_z reaches q as G^T P^T tau_z (FlexibleBody::stage, add_projected, chain).
  bool manifold = false;
  /// The parent's elastic coordinates z moves with: `cols`, or all of them on a manifold.
  std::vector<int> parent_cols;
};

/// The mesh node nearest `point` (m, the mesh's frame); ties go to the lowest index.
int nearest_node(const fem::ShellModel& model, const Eigen::Vector3d& point);
/// Unit forces (x, y, z) and moments (x, y, z) at `node`, (mesh dofs x 6): the load shapes of a
/// child's hinge reaction, whose static responses join a reduced parent's Ritz basis (the
/// attachment modes of Craig & Chang, AIAA paper 77-405, 1977; fem/ritz_basis.hpp).
Eigen::MatrixXd node_unit_loads(const fem::ShellModel& model, int node);
/// The attachment at `node` of the hinge through `point` (P), on the compiled `parent`.
Attachment make_attachment(const body::FlexibleBody& parent, int node, const Eigen::Vector3d& point);
/// Generalized forces tau_z (columns of X, 6 x m) on the parent's coordinates `parent_cols`
/// (parent_cols.size() x m): P^T X on `cols`, or G^T P^T X on a manifold (s: the parent's staged state).
Eigen::MatrixXd force_on_parent(const Attachment& att, const body::FlexibleBody& parent,
                                const body::ElasticState& s, const Eigen::MatrixXd& X);

/// The attachment's configuration and motion at one instant (P axes, relative to P).
template <class S>
struct AttachmentMotion {
  Matrix3<S> R_att, T;
  Vector3<S> rho, o, o_rate, o_accel, w_att, al_att;
};

/// The attachment at (z, z', z''), see the header.
template <class S>
AttachmentMotion<S> attachment_motion(const Attachment& att, const Vector6<S>& z, const Vector6<S>& z_rate,
                                      const Vector6<S>& z_accel) {
  AttachmentMotion<S> m;
  const Vector3<S> u = z.template head<3>(), psi = z.template tail<3>();
  const Vector3<S> u_rate = z_rate.template head<3>(), psi_rate = z_rate.template tail<3>();
  m.R_att = so3_exp<S>(psi);
  m.T = so3_left_jacobian<S>(psi);
  m.rho = m.R_att * att.r.cast<S>();
  m.o = att.X.cast<S>() + u + m.rho;
  m.w_att = m.T * psi_rate;
  m.o_rate = u_rate + m.w_att.cross(m.rho);
  m.al_att = m.T * z_accel.template tail<3>() + so3_left_jacobian_rate<S>(psi, psi_rate);
  m.o_accel = z_accel.template head<3>() + m.al_att.cross(m.rho) + m.w_att.cross(m.w_att.cross(m.rho));
  return m;
}

}  // namespace deployfx::multibody
