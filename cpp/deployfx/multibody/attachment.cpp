#include "deployfx/multibody/attachment.hpp"

#include <limits>

namespace deployfx::multibody {

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

Eigen::MatrixXd force_on_parent(const Attachment& att, const body::FlexibleBody& parent,
                                const body::ElasticState& s, const Eigen::MatrixXd& X) {
  if (att.manifold) return parent.projected(s, att.P.transpose() * X);
  return att.P_cols.transpose() * X;
}

Attachment make_attachment(const body::FlexibleBody& parent, int node, const Eigen::Vector3d& point) {
  Attachment att;
  att.node = node;
  att.X = parent.spec().model->nodes().row(node).transpose();
  att.r = point - att.X;
  std::vector<int> dofs(fem::kNodeDofs);
  for (int k = 0; k < fem::kNodeDofs; ++k) dofs[k] = fem::kNodeDofs * node + k;
  att.P = parent.mesh_rows(dofs);  // (u; theta) of the node per coordinate
  for (int c = 0; c < att.P.cols(); ++c)
    if (att.P.col(c).squaredNorm() > 0) att.cols.push_back(c);
  att.P_cols.resize(6, static_cast<Eigen::Index>(att.cols.size()));
  for (std::size_t k = 0; k < att.cols.size(); ++k) att.P_cols.col(static_cast<Eigen::Index>(k)) = att.P.col(att.cols[k]);
  att.manifold = parent.manifold();
  if (att.manifold) {
    att.parent_cols.resize(static_cast<std::size_t>(parent.num_elastic()));
    for (int c = 0; c < parent.num_elastic(); ++c) att.parent_cols[static_cast<std::size_t>(c)] = c;
  } else {
    att.parent_cols = att.cols;
  }
  return att;
}

}  // namespace deployfx::multibody
