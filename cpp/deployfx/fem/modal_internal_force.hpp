#pragma once
// The shell model's internal force in a Ritz basis, d = Phi eta, exactly. With Green strain
// (You et al. 2016 Eq. 14) the strain is quadratic in d, so the strain energy is quartic and the
// projected tangent T(eta) = Phi^T K_T(Phi eta) Phi is a quadratic polynomial in eta:
//   T(eta) = K + A(eta) + B(eta) / 2,   A(eta) = sum_k eta_k A_k,  B(eta) = sum_kl eta_k eta_l B_kl,
//   f(eta) = K eta + A(eta) eta / 2 + B(eta) eta / 6,
//   U(eta) = eta^T K eta / 2 + eta^T A(eta) eta / 6 + eta^T B(eta) eta / 24,
// the geometric stiffening of the reduced model in modal form (Mignolet et al., J. Sound Vib.
// 332, 2013). The coefficients are computed exactly from the elements' Green-strain operators at
// their Gauss points (ShellElement::green_operators; the derivation is in the .cpp), in one pass
// over the mesh. Linear strain keeps K only.
#include <Eigen/Core>
#include <utility>
#include <vector>

#include "deployfx/fem/shell_model.hpp"

namespace deployfx::fem {

class ModalInternalForce {
 public:
  /// Phi: (ndof x r) basis. green_strain: the nonlinear coefficients (once, O(r^4 n_gauss));
  /// otherwise f = K eta.
  ModalInternalForce(const ShellModel& model, const Eigen::MatrixXd& Phi, bool green_strain);
  /// A quartic energy from its coefficients (e.g. a condensed one: fem/quadratic_manifold.hpp):
  /// K (r x r, symmetric), A (P x r) and B (P x P, symmetric) on the pairs P = r (r + 1) / 2 in
  /// the order (0, 0), (0, 1), ..., (0, r - 1), (1, 1), ...: A(p(i, j), k) = d^3 U / d eta_i d eta_j
  /// d eta_k at 0, B(p(i, j), p(k, l)) the fourth derivative. std::invalid_argument on other sizes.
  ModalInternalForce(Eigen::MatrixXd K, Eigen::MatrixXd A, Eigen::MatrixXd B);

  int size() const { return static_cast<int>(K_.rows()); }
  bool green_strain() const { return green_; }
  /// The sizes of B's diagonal blocks (empty for linear strain; see B_blocks_).
  std::vector<int> quartic_blocks() const;
  /// K = Phi^T K_L Phi, (r x r).
  const Eigen::MatrixXd& linear_stiffness() const { return K_; }
  /// The coefficients d^3 U / d eta_i d eta_j d eta_k and d^4 U / d eta_i d eta_j d eta_k d eta_l at
  /// eta = 0 (0 for linear strain).
  double cubic(int i, int j, int k) const;
  double quartic(int i, int j, int k, int l) const;
  /// A run's memo of the polynomial's last evaluation, A(eta) and B(eta) (Newton evaluates the
  /// residual and then, for a fresh matrix, the tangent at the same eta: one product, not two).
  /// Per-run data (multibody::Data): the model stays immutable, runs on it independent.
  struct Memo {
    Eigen::VectorXd eta;
    Eigen::MatrixXd A, B;
    Eigen::VectorXd pairs, a, b;  // polynomial()'s work space (kept sized: no allocation)
  };
  /// f(eta) and/or T(eta) (either may be null); `memo` (may be null) is read and updated.
  void evaluate(const Eigen::VectorXd& eta, Eigen::VectorXd* f, Eigen::MatrixXd* T, Memo* memo = nullptr) const;
  /// U(eta), J. Near the eta of the memo's last evaluation (within kTaylorReach of it, relative,
  /// in the energy norm of K), from that evaluation by Taylor's series, exact to round-off.
  double strain_energy(const Eigen::VectorXd& eta, const Memo* memo = nullptr) const;
  static constexpr double kTaylorReach = 1e-8;

 private:
  // A(eta) and B(eta) as (r x r) matrices into memo.A and memo.B, unless it holds them for eta.
  void polynomial(const Eigen::VectorXd& eta, Memo& memo) const;
  bool green_ = false;
  Eigen::MatrixXd K_;
  // The coefficients on the pairs i <= j (every A_k and B_kl is symmetric, as T is), packed in
  // slots_ order: A_ is (r (r + 1) / 2 x r), column k the packed A_k; B is (r (r + 1) / 2)^2,
  // column s the packed B_kl of slot s = (k, l), and symmetric
  // (B_kl(i, j) = d^4 U / d eta_i d eta_j d eta_k d eta_l), stored whole: a general product
  // streaming both triangles from cache is faster than a symmetric one reading the upper (the
  // paper's 249 + 216 blocks: 9.0 against 10.0 us; 30 s of reduced-nonlinear 0.71 -> 0.68 s,
  // session 24). B is kept as its diagonal blocks over consecutive slots, B_blocks_, which are all of
  // it: one block in general; two (the pairs of equal parity, then the mixed ones) when every
  // basis vector is exactly bending or exactly in-plane (parity.hpp) and B has no entry between
  // the two, half the entries of one.
  std::vector<std::pair<int, int>> slots_;
  std::vector<int> slot_of_;  // slot of the pair (i, j) at i r + j and j r + i
  std::vector<int> block_of_;  // the B block of each slot, and the first slot of each block
  std::vector<int> block_start_;
  void index_slots();
  Eigen::MatrixXd A_;
  std::vector<Eigen::MatrixXd> B_blocks_;
};

}  // namespace deployfx::fem
