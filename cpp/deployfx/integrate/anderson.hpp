#pragma once
// Anderson acceleration of a fixed-point iteration x <- x + f(x) (type II; Walker & Ni, SIAM J.
// Numer. Anal. 49(4), 2011, 1715-1735, Eq. 2.1 in the difference form of their Sec. 3):
//   x_{k+1} = x_k + f_k - (dX_k + dF_k) gamma_k,   gamma_k = argmin |f_k - dF_k gamma|_2,
// with dX_k, dF_k the differences of the last m + 1 iterates x_i and their increments f_i. On a
// linear iteration x + f(x) = x - P^-1 (J x - b) it is GMRES on P^-1 J over the last m directions,
// so the mixed increment leaves no more of the linearized residual than the plain one.
// Used for modified Newton with a kept sparse matrix (GeneralizedAlpha::step), where f is the
// kept matrix's increment -S_old^-1 r(x); the history is one matrix's and one step's only.
#include <Eigen/Core>
#include <vector>

namespace deployfx::integrate {

class AndersonMixing {
 public:
  /// m: the number of differences kept (0: the plain iteration x + f).
  explicit AndersonMixing(int m = 0) : m_(m) {}
  /// Forgets the history (another matrix, or a damped step that is not part of the iteration).
  void reset() { x_.clear(), f_.clear(); }
  /// Records (x, f(x)) and returns the next iterate.
  Eigen::VectorXd next(const Eigen::VectorXd& x, const Eigen::VectorXd& f);

 private:
  int m_;
  std::vector<Eigen::VectorXd> x_, f_;  // oldest first, at most m + 1
};

}  // namespace deployfx::integrate
