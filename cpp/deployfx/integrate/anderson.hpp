#pragma once
// Anderson acceleration of a fixed-point iteration x <- x + f(x) (type II; Walker & Ni, SIAM J.
// Numer. Anal. 49(4), 2011, 1715-1735, Eq. 2.1 in the difference form of their Sec. 3):
//   x_{k+1} = x_k + f_k - (dX_k + dF_k) gamma_k,   gamma_k = argmin |f_k - dF_k gamma|_2,
// with dX_k, dF_k the differences of the last m + 1 iterates x_i and their increments f_i. On a
// linear iteration x + f(x) = x - P^-1 (J x - b) it is GMRES on P^-1 J over the last m directions,
// so the mixed increment leaves no more of the linearized residual than the plain one.
// Used for modified Newton with a kept matrix (GeneralizedAlpha::step), where f is the
// kept matrix's increment -S_old^-1 r(x); the history is one matrix's and one step's only.
#include <Eigen/Core>
#include <vector>

namespace deployfx::integrate {

class AndersonMixing {
 public:
  /// m: the number of differences kept (0: the plain iteration x + f).
  explicit AndersonMixing(int m = 0) : m_(m) {}
  /// Forgets the history (another matrix, or a damped step that is not part of the iteration).
  void reset() { count_ = 0; }
  /// Records (x, f(x)) and moves x to the next iterate (in place: no allocation once sized).
  void update(Eigen::VectorXd& x, const Eigen::VectorXd& f);

 private:
  // gamma = argmin |f - dF gamma|_2 over dF's first k columns, into gamma_ (size k).
  bool least_squares(int k, const Eigen::VectorXd& f);
  int m_;
  int count_ = 0;   // pairs held, at most m + 1
  int newest_ = 0;  // the newest pair's column in the rings
  // The last m + 1 iterates and increments, ring buffers (n x (m + 1)); the differences and the
  // least-squares work space (n x m). Sized once for a system: a reduced model's step mixes
  // vectors of a few dozen entries, where allocating them had cost more than the arithmetic.
  Eigen::MatrixXd x_, f_, dX_, dF_, Q_, R_;
  Eigen::VectorXd gamma_, c_, r_;
  std::vector<int> perm_;
};

}  // namespace deployfx::integrate
