#include "deployfx/integrate/generalized_alpha.hpp"

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <sstream>

#include "deployfx/integrate/anderson.hpp"
#include "deployfx/math/check.hpp"

namespace deployfx::integrate {
namespace {
// Newton sweeps on a system's slaved rows at a step's predictor (GeneralizedAlpha::relax_slaved).
constexpr int kSlavedSweeps = 3;
}  // namespace

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

GeneralizedAlpha::GeneralizedAlpha(SecondOrderSystem& system, AlphaParameters p,
                                   NewtonOptions newton)
    : sys_(system), p_(p), newton_(newton), slaved_(system.slaved_velocities()), mixing_(newton.anderson_depth) {}

AlphaState GeneralizedAlpha::initial_state(double t0, const Eigen::VectorXd& q0,
                                           const Eigen::VectorXd& v0) {
  AlphaState s;
  s.t = t0;
  s.q = q0;
  s.v = v0;
  s.vdot = Eigen::VectorXd::Zero(v0.size());
  // r is affine in vdot: one Newton step with S = dr/da is exact, a second polishes round-off.
  BorderedSolver mass;
  for (int k = 0; k < 2; ++k) {
    const Eigen::VectorXd r = sys_.residual(s.q, s.v, s.vdot, t0);
    if (!mass.factorize(sys_.iteration_matrix(s.q, s.v, s.vdot, t0, 1.0, 0.0, 0.0)))
      throw StepFailure("the mass matrix is singular at t = " + std::to_string(t0) + " s");
    s.vdot -= mass.solve(r);
  }
  if (!s.vdot.allFinite()) throw StepFailure("initial accelerations are not finite at t = " + std::to_string(t0));
  s.a = s.vdot;
  s.base_accel = s.vdot.head(sys_.num_conserved());
  return s;
}

void GeneralizedAlpha::polish_momentum(const Eigen::VectorXd& q, Eigen::VectorXd& v, double t,
                                       const Eigen::VectorXd& Pi) {
  // Pi is linear in v: one solve with dPi/dv on the conserved velocities is exact.
  const int nc = sys_.num_conserved();
  const Eigen::MatrixXd J = sys_.conserved_velocity_jacobian(q, v, t);
  v.head(nc) += J.partialPivLu().solve(Pi - sys_.momentum(q, v, t));
}

void GeneralizedAlpha::restore(const Solver& state) {
  full_steps_ = state.full_steps;
  refreshes_ = state.elastic_refreshes;
  factor_h_ = -1;
  // The slaved block as it was (factorized when a sweep first needs it).
  slaved_h_ = -1;
  slaved_block_.reset();
  if (!slaved_.empty() && state.slaved_h > 0) {
    if (state.slaved_block.E.rows() != static_cast<Eigen::Index>(slaved_.size()))
      throw std::invalid_argument("a checkpoint's slaved block does not fit this system");
    slaved_block_.restore(state.slaved_block);
    slaved_h_ = state.slaved_h;
  }
  if (!(state.h > 0)) return;
  matrix_ = state.S;
  if (!solver_.factorize(matrix_)) throw StepFailure("a checkpoint's iteration matrix is singular");
  momentum_jacobian_ = state.momentum_jacobian;
  if (const int nc = sys_.num_conserved()) momentum_lu_.compute(momentum_jacobian_.leftCols(nc));
  factor_h_ = state.h;
}

int GeneralizedAlpha::step(AlphaState& s, double h, const Eigen::VectorXd* guess) {
  const double am = p_.alpha_m, af = p_.alpha_f, beta = p_.beta, gamma = p_.gamma;
  const double t1 = s.t + h;
  const int nc = sys_.num_conserved();
  const Eigen::VectorXd Pi_n = nc ? sys_.momentum(s.q, s.v, s.t) : Eigen::VectorXd();
  // c = d a_{n+1} / d vdot_{n+1} (iterate()).
  const double c = (1 - af) / (1 - am);
  auto fail = [&](const std::string& why) {
    std::ostringstream e;
    e << "Newton failed at t = " << t1 << " s (step " << h << " s): " << why;
    factor_h_ = slaved_h_ = -1;  // the next attempt starts from a fresh matrix
    return StepFailure(e.str());
  };
  auto not_converged = [&](const std::string& why) {
    factor_h_ = slaved_h_ = -1;
    if (newton_.reuse_jacobian && solver_.dense()) full_steps_ = newton_.full_newton_steps;  // the retry: full Newton
    std::ostringstream e;
    e << "Newton did not converge at t = " << t1 << " s (step " << h << " s): " << why;
    return StepFailure(e.str());
  };
  auto out_of_iterations = [&] { return not_converged(std::to_string(newton_.max_iterations) + " iterations"); };
  // Predictor. Generalized-alpha carries the part of vdot it cannot resolve (stiff root modes,
  // a contact's impulse, the start-up) as a transient that alternates in sign and decays by the
  // high-frequency root -rs = -alpha_f/(1 - alpha_f) (= -rho_inf) per step: the panel's
  // accelerations after the lock's first impact fall by 0.80 a step for rho_inf = 0.8. With the
  // previous step of the same size, (1 - rs) vdot_n + rs vdot_n-1 follows such a transient on
  // top of a constant (5-10 times closer than vdot_n after the impact); otherwise, and for
  // Newmark (alpha_f = 0), the constant acceleration vdot_n.
  const double rs = af / (1 - af);
  const bool history = s.h_prev > 0 && std::abs(s.h_prev - h) <= 1e-12 * h && s.vdot_prev.size() == s.vdot.size();
  Eigen::VectorXd vdot = guess && guess->size() == s.vdot.size() && guess->allFinite() ? *guess
                         : history ? Eigen::VectorXd((1 - rs) * s.vdot + rs * s.vdot_prev)
                                   : s.vdot;
  // With conserved momenta the base's accelerations play two parts (docs/engine-design.md,
  // "Momentum rows and the base's acceleration"): vdot.head(nc) is the base's algorithmic
  // acceleration, set by Pi(q_{n+1}, v_{n+1}) = Pi_n through the Newmark update, and w is the
  // base acceleration the equations of motion see at t_{n+1}, set by the balance rows. Using
  // vdot.head(nc) there instead lets the alpha recursion's parasitic root -alpha_f/(1 - alpha_f)
  // into the appendage's rows, amplified by the inverse of the Schur complement (a light base).
  const int n = static_cast<int>(vdot.size());
  Eigen::VectorXd w = vdot.head(nc);
  // Newton starts from a membrane state consistent with the predicted bending (relax_slaved).
  Eigen::VectorXd r_start = relax_slaved(s, h, vdot, w);
  // Convergence is judged against the accelerations at the step's start: an iterate that has run
  // away cannot make its own increments look small.
  const double scale = std::max(1.0, s.vdot.lpNorm<Eigen::Infinity>());
  // Full Newton (a matrix renewed at every iteration: whole, or its elastic blocks refreshed,
  // NewtonOptions::elastic_refreshes) while a reused matrix has lately proved slow.
  bool full = newton_.reuse_jacobian && full_steps_ > 0;
  if (full) --full_steps_;
  // A step of about the same size keeps the matrix (NewtonOptions::step_reuse): the steps of a
  // run differ from dt in the last bits (output times are t0 + k dt), and an event search's
  // trial steps converge on the switch.
  bool refactor = !newton_.reuse_jacobian || !(std::abs(factor_h_ - h) <= newton_.step_reuse * h) || full;
  double previous = 0;
  int diverging = 0;  // exact Newton steps that grew the increment (NewtonOptions::diverging_steps)
  Eigen::VectorXd last;  // the previous applied increment (dv, db)
  bool certify = false;  // a refreshed matrix's step stalled at the floor: only a whole one can end it
  mixing_.reset();  // a kept matrix's Anderson mixing: one step's history only
  for (int it = 1; it <= newton_.max_iterations; ++it) {
    const Iterate x1 = iterate(s, h, vdot, w);
    const Eigen::VectorXd &q1 = x1.q, &v1 = x1.v, &ve = x1.ve;
    // An iterate that left the doubles (an increment that overflowed in the update) fails the
    // step, to be retried smaller, before the system's own input checks see it.
    if (!x1.finite()) throw fail("the iterate is not finite");
    // The predictor's residual, or the one the last relaxation left (relax_slaved).
    const Eigen::VectorXd r = r_start.size() ? Eigen::VectorXd(std::move(r_start)) : sys_.residual(q1, v1, ve, t1);
    r_start.resize(0);
    // Eq. 42-43, integrated: the momentum rows, scaled like accelerations.
    const Eigen::VectorXd rm = nc ? Eigen::VectorXd((sys_.momentum(q1, v1, t1) - Pi_n) / (h * gamma * c)) : Eigen::VectorXd();
    if (!r.allFinite() || !rm.allFinite()) throw fail("the residual is not finite");
    // A matrix formed at this iterate and factorized: in full Newton on a system with slaved
    // coordinates, for a step of about the kept matrix's size, up to
    // NewtonOptions::elastic_refreshes in a row only the kept matrix's elastic blocks
    // (SecondOrderSystem::refresh_elastic_blocks, where `refresh` allows it), otherwise the whole
    // matrix. Returns whether it is whole, an exact Newton matrix.
    auto factorize_here = [&](bool refresh) {
      const double c_v = h * gamma * c, c_q = h * h * beta * c;
      refresh = refresh && full && !slaved_.empty() && refreshes_ < newton_.elastic_refreshes && factor_h_ > 0 &&
                std::abs(factor_h_ - h) <= newton_.step_reuse * h;
      factor_h_ = -1;  // no kept matrix until the one below is factorized (a throw leaves none)
      refresh = refresh && sys_.refresh_elastic_blocks(matrix_, q1, v1, ve, t1, 1.0, c_v, c_q);
      if (refresh) ++refreshes_;  // the momentum rows' Jacobian stays the whole matrix's
      if (!factorize_at(x1, t1, h, !refresh)) throw fail("the iteration matrix is singular");
      refactor = !newton_.reuse_jacobian || full;
      return !refresh;
    };
    // renewed: a matrix factorized at this iterate; fresh: and whole (exact Newton).
    bool renewed = refactor, fresh = renewed && factorize_here(!certify);
    // Newton on (w, the other accelerations) with the iteration matrix of the balance rows, then
    // the base's algorithmic acceleration from the momentum rows. (The residual's dependence on
    // vdot.head(nc) through q_{n+1}, v_{n+1} is attributed to w: the two differ by O(h).)
    // Only a fresh matrix's solve is exact: the convergence test below trusts an exact Newton
    // step at the round-off floor; an old matrix's step is inexact by more than the solve's
    // dropped skew part (BorderedSolver::solve).
    Eigen::VectorXd dv, db;
    double size = 0, rho = 0;
    const double contraction = solver_.dense() ? newton_.contraction_dense : newton_.contraction;
    for (;;) {
      dv = solver_.solve(r, fresh);
      if (nc) db = momentum_lu_.solve(rm - momentum_jacobian_.rightCols(n - nc) * dv.tail(n - nc));
      size = nc ? std::max(dv.lpNorm<Eigen::Infinity>(), db.lpNorm<Eigen::Infinity>()) : dv.lpNorm<Eigen::Infinity>();
      if (!std::isfinite(size)) throw fail("the Newton increment is not finite");
      rho = previous > 0 ? size / previous : 0.0;
      if (!renewed && rho > contraction && solver_.dense() && !slaved_.empty() && newton_.full_newton_steps > 0) {
        // A kept matrix's stale coupling of the stiff in-plane coordinates to the bending: full
        // Newton for the rest of this step and the next few (NewtonOptions::full_newton_steps),
        // from a whole matrix (then every other one refreshed: elastic_refreshes).
        full_steps_ = newton_.full_newton_steps;
        full = true;
        refreshes_ = newton_.elastic_refreshes;
      }
      if (fresh || rho < 1) break;
      // An old matrix that no longer contracts: a fresh one here, for the same residual, as the
      // next iteration (its residual would be this one again).
      if (++it > newton_.max_iterations) throw out_of_iterations();
      renewed = fresh = factorize_here(false);
    }
    // A 2-cycle of exact Newton: a fresh matrix's increment that undoes the previous one at the
    // same size (Newton on a tanh-like law, e.g. the lock's regularized friction at stick, jumps
    // across the steep zone for ever). Half a step lands inside it.
    Eigen::VectorXd inc(n + db.size());
    inc << dv, db;
    const bool cycle = fresh && rho >= 0.9 && rho <= 1.1 && last.size() == inc.size() &&
                       inc.dot(last) < -0.9 * inc.norm() * last.norm();
    // The system's limit on the step (SecondOrderSystem::newton_step_limit), from the velocity
    // change it would make: v_{n+1} moves by h gamma c times the change of vdot.
    Eigen::VectorXd dvel(n);
    dvel.head(nc) = db;  // the base's algorithmic acceleration
    dvel.tail(n - nc) = dv.tail(n - nc);
    const double limit = sys_.newton_step_limit(q1, v1, -(h * gamma * c) * dvel);
    const bool limited = limit < (cycle ? 0.5 : 1.0);
    const double lambda = limited ? limit : cycle ? 0.5 : 1.0;
    // A renewed matrix's step, and a damped one, are plain Newton steps; the history restarts there.
    if (renewed || cycle || limited) mixing_.reset();
    // A kept matrix's iterations are Anderson-mixed (NewtonOptions::anderson_depth), but for a
    // dense one on a system with slaved coordinates (the reduced Green-strain panel), which runs
    // full Newton once its kept matrix is slow: there the mixing saved 1 % of the iterations for
    // 0.3 % more instructions and moved the undamped run's sensitivity to tau0 (tests/test_extremes.py).
    const bool mixed = newton_.anderson_depth > 0 && !(solver_.dense() && !slaved_.empty());
    if (cycle || limited || !mixed) {
      last = lambda * inc;
      vdot.tail(n - nc) -= lambda * dv.tail(n - nc);
      if (nc) w -= lambda * dv.head(nc), vdot.head(nc) -= lambda * db;
    } else {
      // The unknowns x = (vdot, w) and the kept matrix's increment f = -(the applied inc), in
      // vectors kept over the step's iterations; x becomes the mixed iterate.
      mixed_x_.resize(n + nc), mixed_f_.resize(n + nc);
      mixed_x_ << vdot, w;
      mixed_f_.head(n).tail(n - nc) = -dv.tail(n - nc);
      if (nc) mixed_f_.head(nc) = -db, mixed_f_.tail(nc) = -dv.head(nc);
      mixing_.update(mixed_x_, mixed_f_);
      last.resize(inc.size());  // the step taken, in inc's layout (dv, db)
      last.head(nc) = w - mixed_x_.tail(nc);
      last.segment(nc, n - nc) = vdot.tail(n - nc) - mixed_x_.head(n).tail(n - nc);
      last.tail(nc) = vdot.head(nc) - mixed_x_.head(nc);
      vdot = mixed_x_.head(n);
      w = mixed_x_.tail(nc);
    }
    if (cycle || limited) {
      previous = lambda * size;
      if (limited) refactor = true;  // the matrix of the far side no longer holds
      continue;
    }
    if (fresh && rho > 1 && ++diverging >= newton_.diverging_steps)
      throw not_converged(std::to_string(diverging) + " exact Newton steps grew the increment");
    // Contraction rate of the (possibly modified) Newton iteration; its error estimate
    // rho/(1 - rho) |dv| (Hairer & Wanner, Solving ODEs II, Sec. IV.8) decides convergence.
    const double error = rho > 0 && rho < 1 ? size * rho / (1 - rho) : size;
    // At the round-off floor: only an exact Newton step (a fresh matrix) below the floor is
    // accepted (its update leaves an error of order size^2 / scale, or round-off); an old
    // matrix's small steps prove nothing (review finding), so they trigger a fresh one, unless
    // the old matrix still contracts fast (NewtonOptions::floor_contraction).
    const bool stalling = it > 1 && size <= newton_.floor * scale;
    const bool stalled = fresh && stalling;
    if (error <= newton_.tolerance * scale || stalled) {
      Iterate end = iterate(s, h, vdot, w);
      if (!end.finite()) throw fail("the converged state is not finite");
      if (nc) polish_momentum(end.q, end.v, t1, Pi_n);
      s.q = std::move(end.q);
      s.v = std::move(end.v);
      s.vdot_prev = std::move(s.vdot);
      s.h_prev = h;
      s.vdot = vdot;
      s.base_accel = w;
      s.a = std::move(end.a);
      s.t = t1;
      return it;
    }
    if (!fresh && (rho > contraction || (stalling && rho > newton_.floor_contraction))) refactor = true;  // slow or stalled, old matrix
    certify = renewed && !fresh && stalling;
    previous = size;
    // After a kept matrix's update (a fresh one's leaves the membrane misfit at second order).
    if (newton_.relax_every_iteration && !solver_.dense() && !fresh) r_start = relax_slaved(s, h, vdot, w);
  }
  throw out_of_iterations();
}

bool GeneralizedAlpha::factorize_at(const Iterate& x, double t1, double h, bool whole) {
  const double c = (1 - p_.alpha_f) / (1 - p_.alpha_m);
  const double c_v = h * p_.gamma * c, c_q = h * h * p_.beta * c;
  const int nc = sys_.num_conserved();
  factor_h_ = -1;  // no kept matrix until this one is factorized
  if (whole) {
    // With the momentum rows, their d/dvdot (up to the factor h gamma c): dPi/dv + (h beta /
    // gamma) dPi/dq.
    matrix_ = nc ? sys_.iteration_matrix_and_momentum_jacobian(x.q, x.v, x.ve, t1, 1.0, c_v, c_q, momentum_jacobian_)
                 : sys_.iteration_matrix(x.q, x.v, x.ve, t1, 1.0, c_v, c_q);
    refreshes_ = 0;
  }
  if (!solver_.factorize(matrix_)) return false;
  // The slaved block (slaved_block_'s comment): a dense matrix's every time, a sparse one's at a
  // new step size.
  if (!slaved_.empty() && (solver_.dense() || slaved_block_.empty() || !(std::abs(slaved_h_ - h) <= newton_.step_reuse * h)))
    slaved_block_.set(matrix_, slaved_), slaved_h_ = h;
  if (nc && whole) momentum_lu_.compute(momentum_jacobian_.leftCols(nc));
  factor_h_ = h;
  return true;
}

GeneralizedAlpha::Iterate GeneralizedAlpha::iterate(const AlphaState& s, double h, const Eigen::VectorXd& vdot,
                                                    const Eigen::VectorXd& w) const {
  const double am = p_.alpha_m, af = p_.alpha_f, beta = p_.beta, gamma = p_.gamma;
  Iterate x;
  x.a = ((1 - af) * vdot + af * s.vdot - am * s.a) / (1 - am);  // a_{n+1}(vdot_{n+1})
  x.q = sys_.retract(s.q, h * s.v + h * h * ((0.5 - beta) * s.a + beta * x.a));
  x.v = s.v + h * ((1 - gamma) * s.a + gamma * x.a);
  x.ve = vdot;
  x.ve.head(sys_.num_conserved()) = w;
  return x;
}

// A consistent predictor. A Green-strain panel's in-plane coordinates are stiff (omega h = 14-670
// at h = 10 ms on the paper's panel) and slaved to its bending through the quadratic membrane
// strain. Extrapolated with the rest, they leave a membrane strain inconsistent with the
// predicted bending: their rows then dominate the residual (1e2-1e4 times the others'), and
// Newton's linearization of that misfit makes its first increments up to 200 times the step's
// final correction, bouncing for 10-20 iterations and at times landing on another root of the
// step equation (docs/research/undamped-stability.md). Newton sweeps on the slaved rows alone,
// the other coordinates held, bring them to the membrane equilibrium of the predicted bending
// (nonlinear elimination: Lanzkron, Rose & Wilkes, SIAM J. Sci. Comput. 17, 1996, 945-960),
// until their residual no longer exceeds the other rows' (at most kSlavedSweeps; a sweep that does
// not reduce it is undone; where the system forms the slaved rows alone, the first sweep is taken
// unless they are exactly zero, SecondOrderSystem::slaved_residual); Newton on all rows starts
// from there. The sweeps' matrix is the slaved block of the last factorization for this step size
// (nearly constant: M, K and small in-plane geometric terms), or one formed here when the step
// size changed (the kept matrix with its elastic blocks refreshed, else a whole one). The
// converged step solves the same equations: only Newton's start moves.
// With a sparse iteration matrix (the full meshes) the sweeps also follow every Newton iteration
// with a kept matrix (NewtonOptions::relax_every_iteration; their last residual is the next
// iteration's): each such increment leaves the in-plane rows 50-100 times the others (the bending
// moved, the membrane strain with it), and the kept matrix, whose geometric stiffness reflects
// another membrane state, then stops contracting at the third iteration (0.5-1) until a fresh
// matrix is formed, about once a step. Relaxed, the same kept matrix contracts by 2-4e-3 per
// iteration. After a fresh matrix's update the misfit is of second order and the sweeps do not
// pay (the error-controlled paper run: 13.0 s with them, 11.8 without).
// Paper scene, 15 x 10, 30 s: factorizations 6060 -> 2115, CPU -22 % together with
// NewtonOptions::floor_contraction (docs/performance-history.md, session 21). Not for a dense (reduced) matrix: there a
// factorization costs about one residual and the extra residual per iteration does not pay
// (reduced-nonlinear +19 %).
Eigen::VectorXd GeneralizedAlpha::relax_slaved(const AlphaState& s, double h, Eigen::VectorXd& vdot,
                                               const Eigen::VectorXd& w) {
  if (slaved_.empty()) return {};
  const double am = p_.alpha_m, af = p_.alpha_f, beta = p_.beta, gamma = p_.gamma;
  const double t1 = s.t + h, c = (1 - af) / (1 - am);
  Eigen::VectorXd r, r_before, vdot_before;  // the residual at vdot; before the last sweep
  double slaved_before = std::numeric_limits<double>::infinity();
  // The whole residual at vdot (what Newton continues from).
  auto residual_at = [&](const Eigen::VectorXd& x) {
    const Iterate x1 = iterate(s, h, x, w);
    return sys_.residual(x1.q, x1.v, x1.ve, t1);
  };
  for (int sweep = 0;; ++sweep) {
    // The state vdot gives at t_{n+1}, and its residual.
    const Iterate x1 = iterate(s, h, vdot, w);
    const Eigen::VectorXd &q1 = x1.q, &v1 = x1.v, &ve = x1.ve;
    if (!x1.finite()) {  // a sweep that overflowed: undo it
      if (sweep == 0) {
        factor_h_ = slaved_h_ = -1;
        throw StepFailure("Newton failed at t = " + std::to_string(t1) + " s (step " + std::to_string(h) +
                          " s): the iterate is not finite");
      }
      vdot = std::move(vdot_before);
      return r_before.size() ? r_before : residual_at(vdot);
    }
    // The slaved rows, and the other rows' largest entry. Before the first sweep, with a slaved
    // block at hand for this step size, the system may form the slaved rows alone, for about half
    // a residual (SecondOrderSystem::slaved_residual); the others are then unknown and the sweep
    // is taken (the rows after a kept matrix's update exceed them 50-100 times, below), and the
    // residual after it is whole. Where the block would have to be formed first (a new step
    // size: a whole Newton matrix), the whole residual decides whether a sweep is worth it (an
    // error-controlled run, whose every step has its own size, took 38 % longer sweeping always).
    Eigen::VectorXd rs(slaved_.size());
    double others = std::numeric_limits<double>::quiet_NaN();
    const bool block_ready = !slaved_block_.empty() && std::abs(slaved_h_ - h) <= newton_.step_reuse * h;
    const bool whole = !(sweep == 0 && block_ready && sys_.slaved_residual(q1, v1, ve, t1, rs));
    if (whole) {
      r = sys_.residual(q1, v1, ve, t1);
      for (std::size_t i = 0; i < slaved_.size(); ++i) rs(i) = r(slaved_[i]), r(slaved_[i]) = 0.0;
      others = r.lpNorm<Eigen::Infinity>();
      for (std::size_t i = 0; i < slaved_.size(); ++i) r(slaved_[i]) = rs(i);
    }
    const double slaved = rs.lpNorm<Eigen::Infinity>();
    if (!whole && slaved == 0) return residual_at(vdot);  // at equilibrium already: no sweep
    if (!(slaved < slaved_before)) {  // the last sweep did not reduce the slaved rows: undo it
      if (sweep == 0) return whole ? r : residual_at(vdot);
      vdot = std::move(vdot_before);
      return r_before.size() ? r_before : residual_at(vdot);
    }
    if (whole && (sweep == kSlavedSweeps || slaved <= others)) return r;
    if (!block_ready) {
      // The block for this step size: the kept matrix with its elastic blocks formed anew here
      // (SecondOrderSystem::refresh_elastic_blocks: the slaved rows and columns lie in them, and
      // their values are the whole matrix's), else a whole matrix.
      const double c_v = h * gamma * c, c_q = h * h * beta * c;
      bool refreshed = false;
      if (factor_h_ > 0) {
        slaved_source_ = matrix_;
        refreshed = sys_.refresh_elastic_blocks(slaved_source_, q1, v1, ve, t1, 1.0, c_v, c_q);
      }
      if (!refreshed) slaved_source_ = sys_.iteration_matrix(q1, v1, ve, t1, 1.0, c_v, c_q);
      slaved_block_.set(slaved_source_, slaved_);
      slaved_h_ = h;
    }
    Eigen::VectorXd d;
    if (!slaved_block_.solve(rs, &d)) return whole ? r : residual_at(vdot);
    vdot_before = vdot, r_before = whole ? std::move(r) : Eigen::VectorXd(), slaved_before = slaved;
    for (std::size_t i = 0; i < slaved_.size(); ++i) vdot(slaved_[i]) -= d(i);
  }
}

}  // namespace deployfx::integrate
