#pragma once
// The Newton iteration matrix of a multibody system with flexible bodies: a few rigid-body rows
// and columns (base, hinges) bordering a large sparse elastic block,
//   S = [ A  B ]   A: nb x nb, B: nb x ne (dense)
//       [ C  E ]   C: ne x nb (dense), E: ne x ne (sparse, the elastic dofs),
// solved by the Schur complement on the border (architecture.md, "Performance shape"; a small or
// dense E: by one LU of S whole, integrate/bordered_solver.hpp).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <utility>

namespace deployfx::integrate {

struct BlockMatrix {
  Eigen::MatrixXd A, B, C;
  Eigen::SparseMatrix<double> E;

  BlockMatrix() = default;
  BlockMatrix(Eigen::MatrixXd A_, Eigen::MatrixXd B_, Eigen::MatrixXd C_, Eigen::SparseMatrix<double> E_)
      : A(std::move(A_)), B(std::move(B_)), C(std::move(C_)) {
    E.swap(E_);
  }
  BlockMatrix(const BlockMatrix&) = default;
  BlockMatrix& operator=(const BlockMatrix&) = default;
  // A move swaps E's storage: Eigen 3.4's SparseMatrix has no move constructor or assignment, so
  // `kept = fresh_matrix()` copied every value and index of E (a full mesh's 57,000 of each, with
  // fresh pages to fault in: 2 % of the paper's nonlinear run).
  BlockMatrix(BlockMatrix&& o) noexcept : A(std::move(o.A)), B(std::move(o.B)), C(std::move(o.C)) { E.swap(o.E); }
  BlockMatrix& operator=(BlockMatrix&& o) noexcept {
    A = std::move(o.A), B = std::move(o.B), C = std::move(o.C);
    E.swap(o.E);
    return *this;
  }

  int border() const { return static_cast<int>(A.rows()); }
  int elastic() const { return static_cast<int>(E.rows()); }
  int size() const { return border() + elastic(); }
  /// The assembled matrix (tests and small systems).
  Eigen::MatrixXd dense() const {
    Eigen::MatrixXd S(size(), size());
    S << A, B, C, Eigen::MatrixXd(E);
    return S;
  }
  /// A matrix with only a dense border (no elastic block).
  static BlockMatrix from_dense(Eigen::MatrixXd S) {
    BlockMatrix m;
    m.A = std::move(S);
    m.B.resize(m.A.rows(), 0);
    m.C.resize(0, m.A.cols());
    m.E.resize(0, 0);
    return m;
  }
};

}  // namespace deployfx::integrate
