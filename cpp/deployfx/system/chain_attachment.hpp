#pragma once
// Where a child hinge sits on a flexible parent body (system/hinge_chain.hpp): the hinge fitting
// is bolted to one node of the parent's mesh, the node nearest the hinge point, and is rigid
// from that node to the hinge point. The attachment frame moves with the node's elastic
// translation u and small rotation psi (the shell's nodal rotation-vector dofs), both linear in
// the parent's elastic coordinates eta (Ritz coordinates or free mesh dofs):
//   u = Phi eta,  psi = Psi eta,  R_att = exp(psi~),
//   o = X + u + R_att r,   r = point - X   (the hinge point, parent's frame P),
// and the child's hinge axis and stowed axes turn with R_att. This is the floating-frame
// treatment of a joint on a deformable body through a joint frame rigidly attached at a node
// (Shabana, "Dynamics of Multibody Systems", 4th ed., 2013, Ch. 5: the joint node's elastic
// translation and rotation enter the joint's kinematics) and Wallrapp's standard input data,
// whose "frame" (node) carries an origin moving with Phi eta and an orientation I + (Psi eta)~
// (Wallrapp, Mech. Struct. Mach. 22(3), 1994, 283-304); exp() keeps the child's axes
// orthonormal (its first order is Wallrapp's).
//
// Velocities and accelerations, in P axes, relative to P (exact derivatives of the above, so the
// equations stay conservative; left Jacobian of SO(3), e.g. Bauchau, "Flexible Multibody
// Dynamics", 2011, Ch. 13, the tangent tensor):
//   w_att = T(psi) psi',              al_att = T(psi) psi'' + T'(psi, psi') psi',
//   o'    = G_o eta',                 G_o = Phi - (R_att r)~ T Psi,
//   o''   = G_o eta'' + T' psi' x (R_att r) + w_att x (w_att x (R_att r)),
// T(psi) = I + a psi~ + b psi~^2, a = (1 - cos f)/f^2, b = (f - sin f)/f^3, f = |psi|.
#include <Eigen/Core>
#include <vector>

#include "deployfx/body/flexible_body.hpp"
#include "deployfx/fem/shell_model.hpp"

namespace deployfx::system {

/// The immutable attachment of a child hinge to a flexible parent.
struct ChainAttachment {
  int node = -1;                                    ///< the parent's mesh node
  Eigen::Vector3d X = Eigen::Vector3d::Zero();      ///< the node, P (undeformed), m
  Eigen::Vector3d r = Eigen::Vector3d::Zero();      ///< rigid arm node -> hinge point, P axes, m
  Eigen::Matrix<double, 3, Eigen::Dynamic> Phi;     ///< node translation per parent coordinate
  Eigen::Matrix<double, 3, Eigen::Dynamic> Psi;     ///< node rotation vector per parent coordinate
};

/// The mesh node nearest `point` (m, the mesh's frame); ties go to the lowest index.
int nearest_node(const fem::ShellModel& model, const Eigen::Vector3d& point);
/// Unit forces (x, y, z) and moments (x, y, z) at `node`, (mesh dofs x 6): the load shapes of a
/// child's hinge reaction, whose static responses join the parent's Ritz basis (the attachment
/// modes of Craig & Chang, AIAA paper 77-405, 1977; fem/ritz_basis.hpp).
Eigen::MatrixXd node_unit_loads(const fem::ShellModel& model, int node);
/// The attachment at `node` of the hinge through `point` (P), on the compiled `parent`.
ChainAttachment make_attachment(const body::FlexibleBody& parent, int node, const Eigen::Vector3d& point);

/// The attachment's configuration and motion at one instant (P axes, relative to P).
struct AttachmentMotion {
  Eigen::Matrix3d R_att = Eigen::Matrix3d::Identity();
  Eigen::Vector3d o = Eigen::Vector3d::Zero();         ///< the hinge point, m
  Eigen::Matrix<double, 3, Eigen::Dynamic> G_o, G_w;   ///< o' = G_o eta', w_att = G_w eta'
  Eigen::Vector3d o_rate = Eigen::Vector3d::Zero(), w_att = Eigen::Vector3d::Zero();
  /// o'' and al_att: with eta'' (a given) or their parts in eta' alone (a null).
  Eigen::Vector3d o_accel = Eigen::Vector3d::Zero(), al_att = Eigen::Vector3d::Zero();
};
AttachmentMotion attachment_motion(const ChainAttachment& att, const Eigen::VectorXd& eta,
                                   const Eigen::VectorXd& eta_rate, const Eigen::VectorXd* eta_accel);

/// T(psi), the left Jacobian of SO(3): exp(psi~)' exp(psi~)^T = (T(psi) psi')~.
Eigen::Matrix3d so3_left_jacobian(const Eigen::Vector3d& psi);
/// T'(psi, psi') psi', the rate of T along psi' applied to psi'.
Eigen::Vector3d so3_left_jacobian_rate(const Eigen::Vector3d& psi, const Eigen::Vector3d& psi_rate);
/// exp(psi~) (Rodrigues).
Eigen::Matrix3d so3_exp(const Eigen::Vector3d& psi);

}  // namespace deployfx::system
