#include "deployfx/fem/quadratic_manifold.hpp"

#include <Eigen/Cholesky>
#include <stdexcept>
#include <string>

namespace deployfx::fem {
namespace {

std::vector<int> with_parity(const std::vector<Parity>& parity, Parity p) {
  std::vector<int> out;
  for (std::size_t i = 0; i < parity.size(); ++i)
    if (parity[i] == p) out.push_back(static_cast<int>(i));
  return out;
}

// The condensed quartic's coefficients (header) on the bending coordinates, pairs in
// ModalInternalForce's coefficient order.
ModalInternalForce condensed(const ModalInternalForce& f, const std::vector<int>& b, const std::vector<int>& m,
                             const Eigen::MatrixXd& W) {
  const int nb = static_cast<int>(b.size()), nm = static_cast<int>(m.size());
  const int np = nb * (nb + 1) / 2;
  std::vector<int> pair(static_cast<std::size_t>(nb) * nb);
  for (int i = 0, p = 0; i < nb; ++i)
    for (int j = i; j < nb; ++j, ++p) pair[i * nb + j] = pair[j * nb + i] = p;
  auto P = [&](int i, int j) { return pair[static_cast<std::size_t>(i) * nb + j]; };
  Eigen::MatrixXd K(nb, nb), A(np, nb), B(np, np);
  Eigen::MatrixXd H(nm, np);  // H(n, p(i, j)) = A_n,ij: the membrane load's coefficients
  for (int i = 0; i < nb; ++i)
    for (int j = 0; j < nb; ++j) K(i, j) = f.linear_stiffness()(b[i], b[j]);
  for (int i = 0; i < nb; ++i)
    for (int j = i; j < nb; ++j) {
      for (int k = 0; k < nb; ++k) A(P(i, j), k) = f.cubic(b[i], b[j], b[k]);
      for (int n = 0; n < nm; ++n) H(n, P(i, j)) = f.cubic(m[n], b[i], b[j]);
    }
  const Eigen::MatrixXd T = H.transpose() * W * H;  // (np x np)
  for (int i = 0; i < nb; ++i)
    for (int j = i; j < nb; ++j)
      for (int k = 0; k < nb; ++k)
        for (int l = k; l < nb; ++l)
          B(P(i, j), P(k, l)) = f.quartic(b[i], b[j], b[k], b[l]) -
                                (T(P(i, j), P(k, l)) + T(P(i, k), P(j, l)) + T(P(i, l), P(j, k)));
  return ModalInternalForce(K, A, B);
}

}  // namespace

QuadraticManifold::QuadraticManifold(const ModalInternalForce& force, const std::vector<Parity>& parity,
                                     const std::string& name)
    : bending_(with_parity(parity, Parity::kBending)),
      in_plane_(with_parity(parity, Parity::kInPlane)),
      num_dofs_(force.size()) {
  if (!force.green_strain() || static_cast<int>(parity.size()) != force.size())
    throw std::invalid_argument(name + ": the quadratic manifold needs the Green-strain force on the whole basis");
  if (bending_.empty() || bending_.size() + in_plane_.size() != parity.size())
    throw std::invalid_argument(name + ".fidelity = 'reduced-manifold' needs a flat panel whose lay-up is "
                                "mirror-symmetric (no membrane-bending coupling: every basis vector purely bending "
                                "or in-plane, fem/parity.hpp); use 'reduced-nonlinear' for this panel");
  const int nb = num_coordinates(), nm = static_cast<int>(in_plane_.size());
  Eigen::MatrixXd Kmm(nm, nm);
  for (int i = 0; i < nm; ++i)
    for (int j = 0; j < nm; ++j) Kmm(i, j) = force.linear_stiffness()(in_plane_[i], in_plane_[j]);
  W_ = Eigen::MatrixXd::Zero(nm, nm);
  if (nm > 0) {
    const Eigen::LLT<Eigen::MatrixXd> llt(Kmm);
    if (llt.info() != Eigen::Success)
      throw std::invalid_argument(name + ": the in-plane stiffness on the basis is not positive definite");
    W_ = llt.solve(Eigen::MatrixXd::Identity(nm, nm));
  }
  // C_k = -sum_n W_kn A_n,bb (header).
  C_ = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(nm) * nb, nb);
  for (int n = 0; n < nm; ++n) {
    Eigen::MatrixXd An(nb, nb);
    for (int i = 0; i < nb; ++i)
      for (int j = 0; j < nb; ++j) An(i, j) = force.cubic(in_plane_[n], bending_[i], bending_[j]);
    for (int k = 0; k < nm; ++k) C_.middleRows(static_cast<Eigen::Index>(k) * nb, nb) -= W_(k, n) * An;
  }
}

ModalInternalForce QuadraticManifold::condensed_force(const ModalInternalForce& force) const {
  return condensed(force, bending_, in_plane_, W_);
}

void QuadraticManifold::map(const Eigen::VectorXd& q, Eigen::VectorXd& eta) const {
  Eigen::MatrixXd G;
  jacobian(q, G);
  map(q, G, eta);
}

void QuadraticManifold::map(const Eigen::VectorXd& q, const Eigen::MatrixXd& G, Eigen::VectorXd& eta) const {
  eta.resize(num_dofs_);
  for (int i = 0; i < num_coordinates(); ++i) eta(bending_[i]) = q(i);
  for (const int k : in_plane_) eta(k) = 0.5 * G.row(k).dot(q);
}

void QuadraticManifold::derivative(const Eigen::VectorXd& y, Eigen::MatrixXd& X) const {
  const int nb = num_coordinates();
  const Eigen::VectorXd Cy = C_ * y;  // every C_k y at once
  X.setZero(num_dofs_, nb);
  for (std::size_t k = 0; k < in_plane_.size(); ++k)
    X.row(in_plane_[k]) = Cy.segment(static_cast<Eigen::Index>(k) * nb, nb).transpose();
}

void QuadraticManifold::jacobian(const Eigen::VectorXd& q, Eigen::MatrixXd& G) const {
  derivative(q, G);
  for (int i = 0; i < num_coordinates(); ++i) G(bending_[i], i) = 1.0;
}

void QuadraticManifold::add_curvature(const Eigen::VectorXd& x, const Eigen::VectorXd& y, Eigen::VectorXd& out) const {
  const int nb = num_coordinates();
  const Eigen::VectorXd Cy = C_ * y;
  for (std::size_t k = 0; k < in_plane_.size(); ++k)
    out(in_plane_[k]) += x.dot(Cy.segment(static_cast<Eigen::Index>(k) * nb, nb));
}

Eigen::MatrixXd QuadraticManifold::contract(const Eigen::VectorXd& f) const {
  const int nb = num_coordinates();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(nb, nb);
  for (std::size_t k = 0; k < in_plane_.size(); ++k)
    out += f(in_plane_[k]) * C_.middleRows(static_cast<Eigen::Index>(k) * nb, nb);
  return out;
}

}  // namespace deployfx::fem
