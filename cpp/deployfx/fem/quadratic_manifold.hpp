#pragma once
// The in-plane Ritz coordinates of a flat symmetric panel slaved to its bending ones
// (docs/research/quadratic-manifold.md): on a basis split by parity (parity.hpp), eta = [q; eta_m]
// with q the bending coordinates and
//   eta_m = g_m(q) = C(q, q) / 2,   C_k = -sum_n (K_mm^-1)_kn A_n,bb,
// the static in-plane response to the membrane load the bending puts on them, f_m(q, 0) =
// A_m(q, q) / 2 (Jain, Tiso, Rutzmoser & Rixen, Computers & Structures 188 (2017) 80-94: the
// quadratic manifold, here by Galerkin inside the Ritz span). Its energy is the one this map
// minimises exactly,
//   U(q) = U(q, 0) + eta_m^T f_m(q, 0) + eta_m^T K_mm eta_m / 2 = U(q, 0) - f_m^T K_mm^-1 f_m / 2,
// a quartic in q (Green strain without the in-plane vectors' own quadratic strains): with the
// exact Green-strain energy on the map, the membrane keeps a w_x^4 / 8 stretch and a panel bent
// to 20 % of its length is 65 % off (the note, section 1); with this one, 0.1 % (a clamped
// release there; the paper scene in the engine: node E 0.50 % off the full model, the 30-vector
// reduced model 0.57 %, section 5).
// Its coefficients, by the fourth derivative of (q^T A_m q)(q^T A_n q):
//   B'_ijkl = B_ijkl - sum_mn W_mn (A_m,ij A_n,kl + A_m,ik A_n,jl + A_m,il A_n,jk),  W = K_mm^-1.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "deployfx/fem/modal_internal_force.hpp"
#include "deployfx/fem/parity.hpp"

namespace deployfx::fem {

class QuadraticManifold {
 public:
  /// `force`: the Green-strain force on the whole basis; `parity`: each basis vector's
  /// (vector_parity). std::invalid_argument naming `name` unless every vector is exactly bending
  /// or in-plane with at least one bending vector (a curved or unsymmetric panel couples the two
  /// linearly: nothing to slave).
  QuadraticManifold(const ModalInternalForce& force, const std::vector<Parity>& parity, const std::string& name);

  int num_coordinates() const { return static_cast<int>(bending_.size()); }  ///< q's size
  int num_dofs() const { return num_dofs_; }                                  ///< eta's size
  const std::vector<int>& bending() const { return bending_; }    ///< q's place in eta
  const std::vector<int>& in_plane() const { return in_plane_; }  ///< eta_m's place in eta
  /// The condensed quartic energy on q (header), compiled from the basis's force.
  ModalInternalForce condensed_force(const ModalInternalForce& force) const;

  /// eta = g(q) into `eta` (size num_dofs()).
  void map(const Eigen::VectorXd& q, Eigen::VectorXd& eta) const;
  /// The same from G = jacobian(q): eta_m,k = G_k q / 2 (C(q, q) / 2 with C(q, .) = G's in-plane rows).
  void map(const Eigen::VectorXd& q, const Eigen::MatrixXd& G, Eigen::VectorXd& eta) const;
  /// X = d/dx C(x, y) at y: (num_dofs() x num_coordinates()), zero on the bending rows; G = dg/dq
  /// is the bending rows' identity plus derivative(q).
  void derivative(const Eigen::VectorXd& y, Eigen::MatrixXd& X) const;
  /// The Jacobian G = dg/dq at q into `G` (num_dofs() x num_coordinates()).
  void jacobian(const Eigen::VectorXd& q, Eigen::MatrixXd& G) const;
  /// out = C(x, y) on eta (zero on the bending rows), added to `out`.
  void add_curvature(const Eigen::VectorXd& x, const Eigen::VectorXd& y, Eigen::VectorXd& out) const;
  /// sum_k f_k d^2 g_k / dq^2 = sum over in-plane k of f_k C_k, (num_coordinates() square): the
  /// second-derivative term of G^T f's q-derivative.
  Eigen::MatrixXd contract(const Eigen::VectorXd& f) const;

 private:
  std::vector<int> bending_, in_plane_;
  int num_dofs_ = 0;
  Eigen::MatrixXd C_;  // C_k stacked, (n_m n_q x n_q): rows k n_q .. (k + 1) n_q - 1 the symmetric C_k
  Eigen::MatrixXd W_;  // K_mm^-1
};

}  // namespace deployfx::fem
