#include "deployfx/system/chain_attachment.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "deployfx/math/so3.hpp"

namespace deployfx::system {
namespace {

// The coefficients of T = I + a psi~ + b psi~^2 and (1/f) da/df, (1/f) db/df, f = |psi|. Below
// f = 0.05 their Taylor series (the next term is below 1e-13 of the first): the closed forms
// lose digits to cancellation there.
struct Coefficients {
  double a, b, a1, b1;
};

Coefficients coefficients(double f) {
  const double f2 = f * f;
  if (f < 0.05) {
    return {0.5 - f2 / 24 + f2 * f2 / 720 - f2 * f2 * f2 / 40320,
            1.0 / 6 - f2 / 120 + f2 * f2 / 5040 - f2 * f2 * f2 / 362880,
            -1.0 / 12 + f2 / 180 - f2 * f2 / 6720 + f2 * f2 * f2 / 453600,
            -1.0 / 60 + f2 / 1260 - f2 * f2 / 60480 + f2 * f2 * f2 / 4989600};
  }
  const double s = std::sin(f), c = std::cos(f), f3 = f2 * f, f4 = f2 * f2;
  return {(1 - c) / f2, (f - s) / f3, s / f3 - 2 * (1 - c) / f4, (1 - c) / f4 - 3 * (f - s) / (f4 * f)};
}

}  // namespace

Eigen::Matrix3d so3_exp(const Eigen::Vector3d& psi) {
  const double f = psi.norm();
  if (f < 1e-8) {
    const Eigen::Matrix3d S = skew(psi);
    return Eigen::Matrix3d::Identity() + S + 0.5 * S * S;
  }
  return Eigen::AngleAxisd(f, psi / f).toRotationMatrix();
}

Eigen::Matrix3d so3_left_jacobian(const Eigen::Vector3d& psi) {
  const Coefficients k = coefficients(psi.norm());
  const Eigen::Matrix3d S = skew(psi);
  return Eigen::Matrix3d::Identity() + k.a * S + k.b * S * S;
}

Eigen::Vector3d so3_left_jacobian_rate(const Eigen::Vector3d& psi, const Eigen::Vector3d& psi_rate) {
  // d/dt (a psi~ + b psi~^2) psi' = a' psi x psi' + b' psi x (psi x psi') + b psi' x (psi x psi'),
  // a' = (1/f da/df) (psi . psi'), b' likewise (psi'~ psi' = 0 drops the other terms).
  const Coefficients k = coefficients(psi.norm());
  const double rate = psi.dot(psi_rate);
  const Eigen::Vector3d c = psi.cross(psi_rate);
  return k.a1 * rate * c + k.b1 * rate * psi.cross(c) + k.b * psi_rate.cross(c);
}

int nearest_node(const fem::ShellModel& model, const Eigen::Vector3d& point) {
  int best = -1;
  double dist = std::numeric_limits<double>::infinity();
  for (int i = 0; i < model.num_nodes(); ++i) {
    const double d = (model.nodes().row(i).transpose() - point).squaredNorm();
    if (d < dist) dist = d, best = i;
  }
  return best;
}

Eigen::MatrixXd node_unit_loads(const fem::ShellModel& model, int node) {
  Eigen::MatrixXd F = Eigen::MatrixXd::Zero(model.num_dofs(), fem::kNodeDofs);
  for (int k = 0; k < fem::kNodeDofs; ++k) F(fem::kNodeDofs * node + k, k) = 1.0;
  return F;
}

ChainAttachment make_attachment(const body::FlexibleBody& parent, int node, const Eigen::Vector3d& point) {
  ChainAttachment att;
  att.node = node;
  att.X = parent.spec().model->nodes().row(node).transpose();
  att.r = point - att.X;
  std::vector<int> dofs(fem::kNodeDofs);
  for (int k = 0; k < fem::kNodeDofs; ++k) dofs[k] = fem::kNodeDofs * node + k;
  const Eigen::MatrixXd rows = parent.mesh_rows(dofs);  // (u; theta) of the node per coordinate
  att.Phi = rows.topRows<3>();
  att.Psi = rows.bottomRows<3>();
  return att;
}

AttachmentMotion attachment_motion(const ChainAttachment& att, const Eigen::VectorXd& eta,
                                   const Eigen::VectorXd& eta_rate, const Eigen::VectorXd* eta_accel) {
  AttachmentMotion m;
  const Eigen::Vector3d psi = att.Psi * eta, psi_rate = att.Psi * eta_rate;
  m.R_att = so3_exp(psi);
  const Eigen::Vector3d rho = m.R_att * att.r;  // the arm, turned with the node
  m.o = att.X + att.Phi * eta + rho;
  m.G_w = so3_left_jacobian(psi) * att.Psi;
  m.G_o = att.Phi - skew(rho) * m.G_w;
  m.w_att = m.G_w * eta_rate;
  m.o_rate = m.G_o * eta_rate;
  const Eigen::Vector3d Tdot = so3_left_jacobian_rate(psi, psi_rate);
  m.al_att = Tdot;
  m.o_accel = Tdot.cross(rho) + m.w_att.cross(m.w_att.cross(rho));
  if (eta_accel) {
    m.al_att += m.G_w * *eta_accel;
    m.o_accel += m.G_o * *eta_accel;
  }
  return m;
}

}  // namespace deployfx::system
