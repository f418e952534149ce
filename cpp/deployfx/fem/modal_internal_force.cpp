#include "deployfx/fem/modal_internal_force.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "deployfx/fem/parity.hpp"

namespace deployfx::fem {

ModalInternalForce::ModalInternalForce(const ShellModel& model, const Eigen::MatrixXd& Phi,
                                       bool green_strain)
    : green_(green_strain) {
  if (Phi.rows() != model.num_dofs() || Phi.cols() < 1 || !Phi.allFinite())
    throw std::invalid_argument("ModalInternalForce: the basis must be finite with one row per dof (" +
                                std::to_string(model.num_dofs()) + ") and at least one column");
  const int r = static_cast<int>(Phi.cols());
  K_ = Phi.transpose() * (model.stiffness() * Phi);
  K_ = 0.5 * (K_ + K_.transpose()).eval();
  if (!green_) return;
  // Green strain (You et al. 2016 Eq. 14) at a Gauss point, with d = Phi eta:
  //   eps = E eta + q(eta) / 2,  q_a(eta) = eta^T Q_a eta  (Q_x = Px^T Px, Q_y = Py^T Py,
  //   Q_xy = Px^T Py + Py^T Px; Px, Py the rows psi_x, psi_y of G Phi_e, Eq. 20);
  // bending, shear and drilling strains are linear. The strain energy density
  // eps^T A eps / 2 + eps^T B kappa + ... then has the cubic part q^T N_L / 2 (N_L = L Phi_e eta,
  // the linear strains' resultant) and the quartic part q^T A q / 8. Summed over the Gauss
  // points, with D_ijk = sum w Q_a,ij N_a,k and C_ijkl = sum w A_ab Q_a,ij Q_b,kl, the fully
  // symmetric coefficients of U = ... + A_ijk eta^3 / 6 + B_ijkl eta^4 / 24 are
  //   A_ijk = D_ij,k + D_ik,j + D_jk,i,   B_ijkl = C_ij,kl + C_ik,jl + C_il,jk.
  // Both D and C are products of one (pairs x 3 Gauss points) array: exact and one pass over the
  // elements (the intrusive evaluation; probing tangents instead, Muravyov & Rizzi, Comput.
  // Struct. 81 (2003), took r (r + 1) assemblies).
  const int np = r * (r + 1) / 2;
  const int ng = 4 * model.num_elements();
  Eigen::MatrixXd Q(np, 3 * ng);   // column 3 g + a: the packed Q_a of Gauss point g
  Eigen::MatrixXd QA(np, 3 * ng);  // the same times w A: column 3 g + b = sum_a w A_ab Q_a
  Eigen::MatrixXd NL(3 * ng, r);   // row 3 g + a: w (L Phi_e)_a
  Eigen::Matrix<double, kElementDofs, Eigen::Dynamic> Phi_e(kElementDofs, r);
  Eigen::Matrix<double, 6, Eigen::Dynamic> Psi(6, r);
  for (int e = 0; e < model.num_elements(); ++e) {
    for (int a = 0; a < 4; ++a) Phi_e.middleRows<kNodeDofs>(kNodeDofs * a) = Phi.middleRows<kNodeDofs>(kNodeDofs * model.quads()(e, a));
    for (int g = 0; g < 4; ++g) {
      const ShellElement::GreenOperators op = model.elements()[e].green_operators(g);
      const int c = 3 * (4 * e + g);
      Psi.noalias() = op.G * Phi_e;
      NL.middleRows<3>(c).noalias() = op.weight * op.L * Phi_e;
      int p = 0;
      for (int i = 0; i < r; ++i)
        for (int j = i; j < r; ++j, ++p) {
          const auto xi = Psi.col(i).head<3>(), yi = Psi.col(i).tail<3>();
          const auto xj = Psi.col(j).head<3>(), yj = Psi.col(j).tail<3>();
          Q(p, c) = xi.dot(xj);
          Q(p, c + 1) = yi.dot(yj);
          Q(p, c + 2) = xi.dot(yj) + yi.dot(xj);
        }
      QA.middleCols<3>(c).noalias() = Q.middleCols<3>(c) * (op.weight * op.A);  // A symmetric
    }
  }
  const Eigen::MatrixXd D = Q * NL;  // (np x r)
  Eigen::MatrixXd C(np, np);
  C.noalias() = QA * Q.transpose();
  std::vector<int> pair(static_cast<std::size_t>(r) * r);  // p(i, j) = p(j, i)
  for (int i = 0, p = 0; i < r; ++i)
    for (int j = i; j < r; ++j, ++p) pair[i * r + j] = pair[j * r + i] = p;
  auto P = [&](int i, int j) { return pair[static_cast<std::size_t>(i) * r + j]; };
  // The slots: when every vector has one parity, the pairs of equal parity first, then the mixed.
  std::vector<Parity> parity(r);
  for (int i = 0; i < r; ++i) parity[i] = vector_parity(Phi.col(i));
  const bool pure = std::none_of(parity.begin(), parity.end(), [](Parity p) { return p == Parity::kMixed; });
  auto first_pass = [&](int i, int j) { return !pure || parity[i] == parity[j]; };
  for (int i = 0; i < r; ++i)
    for (int j = i; j < r; ++j)
      if (first_pass(i, j)) slots_.emplace_back(i, j);
  const int n_equal = static_cast<int>(slots_.size());
  for (int i = 0; i < r; ++i)
    for (int j = i; j < r; ++j)
      if (!first_pass(i, j)) slots_.emplace_back(i, j);
  auto B = [&](int s, int t) {
    const auto [i, j] = slots_[s];
    const auto [k, l] = slots_[t];
    return C(P(i, j), P(k, l)) + C(P(i, k), P(j, l)) + C(P(i, l), P(j, k));
  };
  A_.resize(np, r);
  for (int s = 0; s < np; ++s) {
    const auto [i, j] = slots_[s];
    for (int k = 0; k < r; ++k) A_(s, k) = D(P(i, j), k) + D(P(i, k), j) + D(P(j, k), i);
  }
  // Two blocks if B has no entry between them, exactly (it has none by parity: each of its three
  // terms has a mixed pair, whose Q_a vanish).
  bool split = n_equal > 0 && n_equal < np;
  for (int t = n_equal; split && t < np; ++t)
    for (int s = 0; split && s < n_equal; ++s) split = B(s, t) == 0.0;
  const std::vector<int> blocks = split ? std::vector<int>{0, n_equal, np} : std::vector<int>{0, np};
  for (std::size_t b = 0; b + 1 < blocks.size(); ++b) {
    const int first = blocks[b], n = blocks[b + 1] - first;
    Eigen::MatrixXd& Bb = B_blocks_.emplace_back(n, n);
    for (int t = 0; t < n; ++t)
      for (int s = 0; s <= t; ++s) Bb(s, t) = Bb(t, s) = B(first + s, first + t);
  }
  index_slots();
}

ModalInternalForce::ModalInternalForce(Eigen::MatrixXd K, Eigen::MatrixXd A, Eigen::MatrixXd B)
    : green_(true), K_(std::move(K)) {
  const Eigen::Index r = K_.rows(), np = r * (r + 1) / 2;
  if (r < 1 || K_.cols() != r || A.rows() != np || A.cols() != r || B.rows() != np || B.cols() != np ||
      !K_.allFinite() || !A.allFinite() || !B.allFinite())
    throw std::invalid_argument("ModalInternalForce: coefficients must be finite, K (r x r), A (P x r) and B (P x P) "
                                "with P = r (r + 1) / 2; got K " + std::to_string(K_.rows()) + " x " +
                                std::to_string(K_.cols()) + ", A " + std::to_string(A.rows()) + " x " +
                                std::to_string(A.cols()) + ", B " + std::to_string(B.rows()) + " x " +
                                std::to_string(B.cols()));
  for (int i = 0; i < r; ++i)
    for (int j = i; j < r; ++j) slots_.emplace_back(i, j);
  A_ = std::move(A);
  B_blocks_.push_back(0.5 * (B + B.transpose()));
  index_slots();
}

void ModalInternalForce::index_slots() {
  const int r = size();
  slot_of_.assign(static_cast<std::size_t>(r) * r, -1);
  for (std::size_t s = 0; s < slots_.size(); ++s) {
    const auto [i, j] = slots_[s];
    slot_of_[static_cast<std::size_t>(i) * r + j] = slot_of_[static_cast<std::size_t>(j) * r + i] = static_cast<int>(s);
  }
  block_of_.assign(slots_.size(), 0);
  block_start_.clear();
  int first = 0;
  for (std::size_t b = 0; b < B_blocks_.size(); ++b) {
    block_start_.push_back(first);
    const int n = static_cast<int>(B_blocks_[b].rows());
    std::fill(block_of_.begin() + first, block_of_.begin() + first + n, static_cast<int>(b));
    first += n;
  }
}

double ModalInternalForce::cubic(int i, int j, int k) const {
  if (!green_) return 0.0;
  return A_(slot_of_[static_cast<std::size_t>(i) * size() + j], k);
}

double ModalInternalForce::quartic(int i, int j, int k, int l) const {
  if (!green_) return 0.0;
  const int s = slot_of_[static_cast<std::size_t>(i) * size() + j];
  const int t = slot_of_[static_cast<std::size_t>(k) * size() + l];
  const int b = block_of_[s];
  if (block_of_[t] != b) return 0.0;  // between two blocks B is exactly zero (constructor)
  return B_blocks_[b](s - block_start_[b], t - block_start_[b]);
}

std::vector<int> ModalInternalForce::quartic_blocks() const {
  std::vector<int> sizes;
  for (const Eigen::MatrixXd& Bb : B_blocks_) sizes.push_back(static_cast<int>(Bb.rows()));
  return sizes;
}

void ModalInternalForce::polynomial(const Eigen::VectorXd& eta, Memo& memo) const {
  if (memo.eta.size() == eta.size() && memo.eta == eta) return;
  const int r = size();
  const int np = static_cast<int>(slots_.size());
  Eigen::VectorXd& pairs = memo.pairs;  // eta_k eta_l, twice for k < l (B_kl = B_lk)
  pairs.resize(np);
  for (int s = 0; s < np; ++s) {
    const auto [k, l] = slots_[s];
    pairs(s) = (l == k ? 1.0 : 2.0) * eta(k) * eta(l);
  }
  memo.a.noalias() = A_ * eta;
  memo.b.setZero(np);
  int first = 0;
  for (const Eigen::MatrixXd& Bb : B_blocks_) {
    const int n = static_cast<int>(Bb.rows());
    memo.b.segment(first, n).noalias() += Bb * pairs.segment(first, n);
    first += n;
  }
  memo.A.resize(r, r);
  memo.B.resize(r, r);
  for (int s = 0; s < np; ++s) {
    const auto [i, j] = slots_[s];
    memo.A(i, j) = memo.A(j, i) = memo.a(s);
    memo.B(i, j) = memo.B(j, i) = memo.b(s);
  }
  memo.eta = eta;
}

void ModalInternalForce::evaluate(const Eigen::VectorXd& eta, Eigen::VectorXd* f, Eigen::MatrixXd* T,
                                  Memo* memo) const {
  if (eta.size() != size())
    throw std::invalid_argument("eta has wrong size: expected " + std::to_string(size()) + ", got " +
                                std::to_string(eta.size()));
  if (!green_) {
    if (f) *f = K_ * eta;
    if (T) *T = K_;
    return;
  }
  Memo local;  // without a run's memo
  Memo& m = memo ? *memo : local;
  polynomial(eta, m);
  if (f) *f = K_ * eta + (0.5 * m.A + m.B / 6.0) * eta;
  if (T) *T = K_ + m.A + 0.5 * m.B;
}

double ModalInternalForce::strain_energy(const Eigen::VectorXd& eta, const Memo* memo) const {
  if (eta.size() != size())
    throw std::invalid_argument("eta has wrong size: expected " + std::to_string(size()));
  if (!green_) return 0.5 * eta.dot(K_ * eta);
  if (memo) {
    // Within kTaylorReach of the memo's eta_m in the energy norm (a converged Newton step's
    // state against its last iterate), the energy's Taylor series about eta_m to second order,
    // from the memo's A, B: U_m + f_m.delta + delta^T T_m delta / 2. The terms dropped, the
    // third and fourth derivatives' (cubic and quartic in delta), are of order
    // (|delta|_K / |eta_m|_K)^3 of the nonlinear energy: round-off, without the quartic product
    // (the outputs' energy at each accepted state took 9 % of a reduced-nonlinear run). The
    // energy norm weighs each coordinate by its stiffness: a stiff in-plane vector's small
    // coordinate moves little in it, where the largest coordinate is no measure. (After the
    // paper's lock, U is 1/50000 of eta^T K eta / 2, the in-plane coordinates cancelling the
    // membrane strain: either way U carries that round-off, 1e-10 J of 4 J.)
    const Eigen::VectorXd& m = memo->eta;
    const Eigen::VectorXd delta =
        m.size() == eta.size() ? Eigen::VectorXd(eta - m) : Eigen::VectorXd();
    if (delta.size() && delta.dot(K_ * delta) <= kTaylorReach * kTaylorReach * m.dot(K_ * m)) {
      const Eigen::VectorXd Am = memo->A * m, Bm = memo->B * m;
      const double U_m = 0.5 * m.dot(K_ * m) + m.dot(Am) / 6.0 + m.dot(Bm) / 24.0;
      const Eigen::VectorXd f_m = K_ * m + 0.5 * Am + Bm / 6.0;
      const Eigen::VectorXd T_delta = K_ * delta + memo->A * delta + 0.5 * (memo->B * delta);
      return U_m + f_m.dot(delta) + 0.5 * delta.dot(T_delta);
    }
  }
  Memo m;  // scratch: the run's memo (read-only here) keeps its last Newton evaluation
  polynomial(eta, m);
  return 0.5 * eta.dot(K_ * eta) + eta.dot(m.A * eta) / 6.0 + eta.dot(m.B * eta) / 24.0;
}

}  // namespace deployfx::fem
