#pragma once
// Bending and in-plane motion of a flat plate. A flat laminate without membrane-bending coupling
// (B = 0, a mirror-symmetric lay-up: Jones, Mechanics of Composite Materials, 2nd ed. 1999,
// Sec. 4.3.1) bends (w, theta_x, theta_y) independently of its in-plane motion (u, v, theta_z):
// K and M have no entries between the two, and Green strain's quadratic term keeps the parity
// (Eq. 14: a bending shape stretches the mid-surface by w,x^2 / 2, an even function of w). A Ritz
// basis can then hold vectors of one parity each, exactly, and the reduced model's quartic
// coefficients split into two blocks (modal_internal_force.cpp).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "deployfx/fem/shell_element.hpp"

namespace deployfx::fem {

enum class Parity { kInPlane, kBending, kMixed };

/// A mesh dof's parity (node-major dofs, (u, v, w, theta_x, theta_y, theta_z) at each node).
inline Parity dof_parity(int dof) {
  const int c = dof % kNodeDofs;
  return (c >= 2 && c <= 4) ? Parity::kBending : Parity::kInPlane;
}

/// x on the mesh dofs: kBending if it is exactly zero on every in-plane dof, kInPlane if exactly
/// zero on every bending dof (a zero vector: kInPlane), else kMixed.
Parity vector_parity(const Eigen::Ref<const Eigen::VectorXd>& x);

/// True if the symmetric A (rows and columns on the mesh dofs `dofs`) couples no bending dof to an
/// in-plane one beyond round-off: |A_ij| <= tol sqrt(|A_ii A_jj|) for every such pair (the
/// Cauchy-Schwarz scale of a semi-definite matrix's entries).
bool parity_decoupled(const Eigen::SparseMatrix<double>& A, const std::vector<int>& dofs, double tol);

}  // namespace deployfx::fem
