#pragma once
// The interface an integrator needs from a mechanical system written in residual form
//   r(q, v, a, t) = M(q) a - f(q, v, t) = 0,
// with configuration q (which may live on a manifold: retract() maps a tangent increment onto it),
// velocity v and acceleration a (both of size num_velocities()). One object per run: its
// evaluations may update the run's own data (memos, contact history; multibody::TreeSystem holds
// an immutable model and a run's Data), so they are not const.
#include <Eigen/Core>
#include <vector>

#include "deployfx/integrate/block_matrix.hpp"

namespace deployfx::integrate {

class SecondOrderSystem {
 public:
  virtual ~SecondOrderSystem() = default;
  virtual int num_positions() const = 0;
  virtual int num_velocities() const = 0;
  /// q (+) dq: the configuration reached from q by the tangent increment dq. Default q + dq.
  virtual Eigen::VectorXd retract(const Eigen::VectorXd& q, const Eigen::VectorXd& dq) const {
    return q + dq;
  }
  /// r(q, v, a, t).
  virtual Eigen::VectorXd residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                   const Eigen::VectorXd& a, double t) = 0;
  /// S = c_a dr/da + c_v dr/dv + c_q dr/dq, the Newton iteration matrix of an implicit scheme
  /// (dr/dq taken along retract()), with the velocity ordering's leading dofs as the border.
  virtual BlockMatrix iteration_matrix(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                       const Eigen::VectorXd& a, double t, double c_a,
                                       double c_v, double c_q) = 0;
  /// A kept iteration matrix S (from iteration_matrix) brought partly up to date at a new state:
  /// the flexible bodies' own elastic blocks (their tangent stiffness, which goes stale first in
  /// a Green-strain panel: GeneralizedAlpha's NewtonOptions::elastic_refreshes) formed anew with
  /// the coefficients given, in place, the rest of S as it was. Returns false, S unchanged, where
  /// the system cannot (default).
  virtual bool refresh_elastic_blocks(BlockMatrix& /*S*/, const Eigen::VectorXd& /*q*/, const Eigen::VectorXd& /*v*/,
                                      const Eigen::VectorXd& /*a*/, double /*t*/, double /*c_a*/, double /*c_v*/,
                                      double /*c_q*/) {
    return false;
  }

  /// The largest fraction in (0, 1] of a Newton increment worth taking from the iterate (q, v),
  /// given the velocity change dv the whole increment would make. A system whose residual turns
  /// sharply in a velocity (a regularized friction law at stick, steep over a narrow band) limits
  /// the steps that would carry Newton across the band, where it overshoots and cycles. Default 1.
  virtual double newton_step_limit(const Eigen::VectorXd& /*q*/, const Eigen::VectorXd& /*v*/,
                                   const Eigen::VectorXd& /*dv*/) {
    return 1.0;
  }

  /// Velocity indices of stiff coordinates slaved to the others (default none): the in-plane
  /// coordinates of a Green-strain panel, which follow its bending quadratically and
  /// quasi-statically. The integrator relaxes their rows at each step's predictor, so that Newton
  /// starts from a membrane state consistent with the predicted bending (GeneralizedAlpha::step).
  virtual std::vector<int> slaved_velocities() const { return {}; }
  /// r(q, v, a, t)'s rows at slaved_velocities() alone (in that order) into `rows`, where the
  /// system forms them for clearly less than a whole residual (a sweep on them needs no other
  /// row). False (rows untouched) where it cannot (default): the caller takes the residual.
  virtual bool slaved_residual(const Eigen::VectorXd& /*q*/, const Eigen::VectorXd& /*v*/,
                               const Eigen::VectorXd& /*a*/, double /*t*/, Eigen::VectorXd& /*rows*/) {
    return false;
  }

  // Conserved momenta. A free-floating system's first rows are the balance of its total momentum,
  // d(Pi)/dt = 0 with no external load (You et al. 2016, Eq. 36-43). An integrator may replace
  // those rows by Pi(q_{n+1}, v_{n+1}) = Pi(q_n, v_n) to conserve momentum to round-off.
  /// Number of leading residual rows that are momentum balances (0: none).
  virtual int num_conserved() const { return 0; }
  /// Pi(q, v, t), size num_conserved(), in a fixed (inertial) frame (t matters where a motion is
  /// prescribed: conserved all the same when it acts between the system's own bodies).
  virtual Eigen::VectorXd momentum(const Eigen::VectorXd& /*q*/, const Eigen::VectorXd& /*v*/, double /*t*/) {
    return {};
  }
  /// c_v dPi/dv + c_q dPi/dq, (num_conserved() x num_velocities()).
  virtual Eigen::MatrixXd momentum_jacobian(const Eigen::VectorXd& /*q*/, const Eigen::VectorXd& /*v*/,
                                            double /*c_v*/, double /*c_q*/) {
    return {};
  }
  /// iteration_matrix and, with conserved momenta, (1/c_v)(c_v dPi/dv + c_q dPi/dq) into
  /// `momentum_jacobian` at the same state (c_v > 0): one evaluation where the system can share
  /// the work. Default: the two separately.
  virtual BlockMatrix iteration_matrix_and_momentum_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                                             const Eigen::VectorXd& a, double t, double c_a,
                                                             double c_v, double c_q,
                                                             Eigen::MatrixXd& momentum_jacobian) {
    BlockMatrix S = iteration_matrix(q, v, a, t, c_a, c_v, c_q);
    momentum_jacobian = this->momentum_jacobian(q, v, 1.0, c_q / c_v);
    return S;
  }
  /// dPi/dv on the conserved velocities alone (num_conserved() square): Pi is linear in v, so
  /// this is what a momentum polish solves with. Default: momentum_jacobian's leading columns.
  virtual Eigen::MatrixXd conserved_velocity_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double /*t*/) {
    return momentum_jacobian(q, v, 1.0, 0.0).leftCols(num_conserved());
  }

  // Contacts and their history. A system with one-sided contacts reports their signed gaps
  // (> 0 open) so the stepper can locate each closing in time, and keeps what the contacts
  // remember (latches, onset speeds) as per-run history, updated only on accepted steps.
  /// Signed gaps of the contacts that can close (empty: none).
  virtual Eigen::VectorXd gaps(const Eigen::VectorXd& /*q*/, const Eigen::VectorXd& /*v*/,
                               double /*t*/) {
    return {};
  }
  /// Bounds on a step's local displacement error, per velocity coordinate (its units: m, rad),
  /// while a fast process is under way at the last accepted state (a contact in progress: a
  /// fraction of its penetration scale, on its hinge angle; +inf where there is none), and the
  /// shortest step worth taking for it (s). `error` empty when nothing asks. The stepper
  /// shortens its steps below dt to respect them (integrate/trajectory.hpp), so that an impact
  /// is resolved at any output step.
  struct StepBounds {
    Eigen::VectorXd error;
    double min_step = 0;
  };
  virtual StepBounds step_bounds() { return {}; }
  /// Called after every accepted step. An event function at or below its `margin` (same order
  /// as gaps(); empty: all 0) has switched: at a located event, the stepper gives every event a
  /// margin of the location tolerance, so that events simultaneous to round-off (two symmetric
  /// wings locking together) switch together. Returns true when a switch moved a massless part
  /// (a latch pin's drop), whose forces jump with no impact to resolve: the stepper then takes
  /// the event's step again under the new mode, so that the next step starts from its forces.
  virtual bool accept(const Eigen::VectorXd& /*q*/, const Eigen::VectorXd& /*v*/, double /*t*/,
                      const Eigen::VectorXd& /*margin*/ = Eigen::VectorXd()) {
    return false;
  }
};

}  // namespace deployfx::integrate
