#include "deployfx/integrate/generalized_alpha.hpp"

#include <Eigen/LU>
#include <cmath>
#include <sstream>

#include "deployfx/math/check.hpp"

namespace deployfx::integrate {

AlphaParameters AlphaParameters::newmark(double beta, double gamma) {
  require_open_interval("beta", beta, 0.0, 0.5 + 1e-12);
  if (!(gamma >= 0.5 && gamma <= 1.0)) throw_out_of_range("gamma", gamma, "in [0.5, 1]");
  return {0.0, 0.0, beta, gamma};
}

AlphaParameters AlphaParameters::hht(double alpha) {
  if (!(alpha >= -1.0 / 3.0 && alpha <= 0.0)) throw_out_of_range("alpha", alpha, "in [-1/3, 0]");
  return {0.0, -alpha, (1 - alpha) * (1 - alpha) / 4, 0.5 - alpha};
}

AlphaParameters AlphaParameters::generalized_alpha(double rho) {
  if (!(rho >= 0.0 && rho <= 1.0)) throw_out_of_range("rho_inf", rho, "in [0, 1]");
  const double am = (2 * rho - 1) / (rho + 1), af = rho / (rho + 1);
  const double g = 0.5 - am + af;
  return {am, af, 0.25 * (g + 0.5) * (g + 0.5), g};
}

GeneralizedAlpha::GeneralizedAlpha(const SecondOrderSystem& system, AlphaParameters p,
                                   NewtonOptions newton)
    : sys_(system), p_(p), newton_(newton) {}

AlphaState GeneralizedAlpha::initial_state(double t0, const Eigen::VectorXd& q0,
                                           const Eigen::VectorXd& v0) const {
  AlphaState s{t0, q0, v0, Eigen::VectorXd::Zero(v0.size()), Eigen::VectorXd()};
  // r is affine in vdot: one Newton step with S = dr/da is exact, a second polishes round-off.
  for (int k = 0; k < 2; ++k) {
    const Eigen::VectorXd r = sys_.residual(s.q, s.v, s.vdot, t0);
    s.vdot -= sys_.iteration_matrix(s.q, s.v, s.vdot, t0, 1.0, 0.0, 0.0).partialPivLu().solve(r);
  }
  if (!s.vdot.allFinite()) throw StepFailure("initial accelerations are not finite at t = " + std::to_string(t0));
  s.a = s.vdot;
  return s;
}

int GeneralizedAlpha::step(AlphaState& s, double h) const {
  const double am = p_.alpha_m, af = p_.alpha_f, beta = p_.beta, gamma = p_.gamma;
  const double t1 = s.t + h;
  // a_{n+1} as a function of vdot_{n+1}; c = d a_{n+1} / d vdot_{n+1}.
  const double c = (1 - af) / (1 - am);
  Eigen::VectorXd vdot = s.vdot;  // predictor: constant acceleration
  auto a_of = [&](const Eigen::VectorXd& vd) { return ((1 - af) * vd + af * s.vdot - am * s.a) / (1 - am); };
  const double scale = std::max(1.0, s.vdot.lpNorm<Eigen::Infinity>());
  for (int it = 1; it <= newton_.max_iterations; ++it) {
    const Eigen::VectorXd a1 = a_of(vdot);
    const Eigen::VectorXd dq = h * s.v + h * h * ((0.5 - beta) * s.a + beta * a1);
    const Eigen::VectorXd q1 = sys_.retract(s.q, dq);
    const Eigen::VectorXd v1 = s.v + h * ((1 - gamma) * s.a + gamma * a1);
    const Eigen::VectorXd r = sys_.residual(q1, v1, vdot, t1);
    if (!r.allFinite()) {
      std::ostringstream e;
      e << "Newton failed at t = " << t1 << " s (step " << h << " s): the residual is not finite";
      throw StepFailure(e.str());
    }
    const Eigen::MatrixXd S = sys_.iteration_matrix(q1, v1, vdot, t1, 1.0, h * gamma * c, h * h * beta * c);
    const Eigen::VectorXd dv = S.partialPivLu().solve(r);
    vdot -= dv;
    if (dv.lpNorm<Eigen::Infinity>() <= newton_.tolerance * std::max(scale, vdot.lpNorm<Eigen::Infinity>())) {
      const Eigen::VectorXd a_new = a_of(vdot);
      s.q = sys_.retract(s.q, h * s.v + h * h * ((0.5 - beta) * s.a + beta * a_new));
      s.v += h * ((1 - gamma) * s.a + gamma * a_new);
      s.vdot = vdot;
      s.a = a_new;
      s.t = t1;
      return it;
    }
  }
  std::ostringstream e;
  e << "Newton did not converge at t = " << t1 << " s (step " << h << " s) in "
    << newton_.max_iterations << " iterations";
  throw StepFailure(e.str());
}

}  // namespace deployfx::integrate
