#pragma once
// One-step implicit integrators of the generalized-alpha family for second-order systems, in the
// form of Arnold & Bruls (Multibody Syst. Dyn. 18, 2007, 185-202), which is Chung & Hulbert's
// scheme (J. Appl. Mech. 60, 1993, 371-375) with the equations of motion enforced at t_{n+1}:
//   (1 - alpha_m) a_{n+1} + alpha_m a_n = (1 - alpha_f) vdot_{n+1} + alpha_f vdot_n,
//   q_{n+1} = q_n (+) h v_n + h^2 (1/2 - beta) a_n + h^2 beta a_{n+1},
//   v_{n+1} = v_n + h (1 - gamma) a_n + h gamma a_{n+1},
//   r(q_{n+1}, v_{n+1}, vdot_{n+1}, t_{n+1}) = 0, solved by Newton on vdot_{n+1}.
// Newmark (beta, gamma) is alpha_m = alpha_f = 0; HHT-alpha is the alpha_m = 0 member.
#include <Eigen/Core>
#include <Eigen/LU>
#include <stdexcept>
#include <string>

#include "deployfx/integrate/anderson.hpp"
#include "deployfx/integrate/bordered_solver.hpp"
#include "deployfx/integrate/second_order_system.hpp"
#include "deployfx/integrate/slaved_block.hpp"

namespace deployfx::integrate {

struct AlphaParameters {
  double alpha_m = 0, alpha_f = 0, beta = 0.25, gamma = 0.5;
  /// Newmark: 0 < beta <= 1/2, gamma >= 1/2 (beta = 1/4, gamma = 1/2: average acceleration).
  static AlphaParameters newmark(double beta, double gamma);
  /// Hilber-Hughes-Taylor: alpha in [-1/3, 0], gamma = (1 - 2 alpha)/2, beta = (1 - alpha)^2/4.
  static AlphaParameters hht(double alpha);
  /// Chung-Hulbert with spectral radius at infinite frequency rho_inf in [0, 1]:
  /// alpha_m = (2 rho - 1)/(rho + 1), alpha_f = rho/(rho + 1), gamma = 1/2 - alpha_m + alpha_f,
  /// beta = (1 - alpha_m + alpha_f)^2 / 4.
  static AlphaParameters generalized_alpha(double rho_inf);
};

struct NewtonOptions {
  int max_iterations = 20;
  /// On the estimated error of vdot relative to max(|vdot_n|, 1). The error this leaves in each
  /// step accumulates in the energy at a rate independent of dt (1e-8 costs 5e-8 of the energy per
  /// second on the rigid deployment), hence 1e-10.
  double tolerance = 1e-10;
  /// Accept an exact Newton step (fresh matrix, after the first iteration) below this relative
  /// size: the round-off floor of the acceleration solve, about cond(M) eps (a light hinge
  /// fitting against stiff root elements: 1e-7..1e-6), where 1e-10 cannot be reached.
  double floor = 1e-5;
  /// Modified Newton: keep the factorized iteration matrix across iterations and steps while
  /// the iterations contract by at least `contraction` per iteration; refactor otherwise. How
  /// fast is fast enough depends on what a factorization costs against an iteration (Hairer &
  /// Wanner's RADAU5 recomputes its Jacobian unless theta < 1e-3 for cheap ones, 0.1 for costly
  /// ones): `contraction` for an iteration matrix with a sparse elastic block (the full models:
  /// a sparse LU costs many residuals), `contraction_dense` for a dense one (rigid and reduced
  /// models, where forming and factorizing the matrix costs 2-3 iterations of a rigid or
  /// linear-strain model, about one of a reduced Green-strain one, 3 of the quadratic manifold's).
  /// A slow kept matrix is replaced by a fresh one, which is kept in its turn, except where the
  /// system has slaved coordinates (slaved_velocities(): a reduced Green-strain panel's stiff
  /// in-plane coordinates): there a slow kept dense matrix, whose stale coupling of those to the
  /// bending makes its steps lead away, switches the rest of the step and the next
  /// `full_newton_steps` steps to full Newton (a matrix renewed every iteration). Measured on the
  /// paper's scene, the reduced-nonlinear model's previous-step matrix contracts by only 0.02-0.2
  /// and was refactored about 3 times a step anyway, doubling the iterations; without full Newton
  /// its start-up whip at dt = 0.02 s alternates kept and exact steps until three exact ones grow
  /// and the step fails. Until session 24 every system's slow kept dense matrix switched: on the
  /// paper's 30 s scene (15 x 10) that cost reduced-manifold 15 % and reduced-linear 7 % of their
  /// CPU (docs/performance-history.md, session 24). A looser contraction_dense refactors less
  /// but accepts more steps from a kept matrix, whose last increment leaves an error of the
  /// tolerance's size (a fresh one's, its square): bench/newton_reuse.py (30 s paper scene,
  /// 15 x 10) measured against 0.01 (the value until session 20): 0.03 saves 8-10 % of
  /// reduced-linear's CPU (3-7 % without the lock, 2-4 % of rigid's, reduced-nonlinear's the same
  /// within the noise) and leaves the rigid undamped 1000 s run's energy error at 9.1e-7 of the
  /// peak kinetic energy (8.6e-7 at 0.01); 0.3 saves 10-14 % but takes it to 1.2e-6, past the
  /// 1e-6 that tests/test_extremes.py holds it to. With session 24's floor rule the error is
  /// 8.6e-7 at 0.03 and 0.1 but 1.16e-6 at 0.01 (not monotone in the threshold: the kept steps'
  /// errors have signs), and reduced-manifold's CPU is flat from 0.01 to 0.1.
  bool reuse_jacobian = true;
  /// A matrix built for a step size within this relative distance of h is kept for a step of
  /// size h: its c_q = h^2 beta c is off by twice that, so the iteration contracts at about
  /// 2 step_reuse on the stiff elastic modes. (An event search's later sizes lie within 1e-3..2e-2
  /// of each other.)
  double step_reuse = 0.02;
  /// A step fails (and is retried at half the size) once this many exact Newton steps (fresh
  /// matrices) have each grown the increment: it lies outside Newton's region of convergence,
  /// and the iterations left would cycle there up to max_iterations. Measured on the paper's
  /// scene, 15 x 10, 30 s (docs/performance-history.md, session 23): the trial steps of the
  /// first lock's event search that end just past the latch's drop (where the pin falls to its
  /// seat and the hinge torque drops, so that such a step has no solution) cycled for 20
  /// iterations, then again at each halving; at 3, the runs' states are bit for bit those at 20
  /// (no step that converges grows its increment three times) and 9 % of reduced-manifold's and
  /// 5 % of reduced-nonlinear's factorizations go.
  int diverging_steps = 3;
  double contraction = 0.25;
  double contraction_dense = 0.03;
  int full_newton_steps = 10;
  /// In full Newton on a system with slaved coordinates (a reduced Green-strain panel), up to
  /// this many iterations in a row refresh only the kept matrix's elastic blocks
  /// (SecondOrderSystem::refresh_elastic_blocks: the panels' tangent stiffness and their own
  /// inertial terms at the iterate, in place; the border rows and columns, base and hinges, and
  /// the momentum rows' Jacobian stay) before a whole matrix is formed again, for a step within
  /// step_reuse of its size; full Newton starts from a whole matrix; 0: whole every time. What
  /// goes stale in that panel's matrix is its elastic block: on the paper's 30 s scene (15 x 10),
  /// one matrix in two swapped for the kept one's parts took the iterations from 13026 to 14169
  /// with the elastic block kept, to 13216 with the border kept; a refresh costs about a sixth of
  /// a whole matrix (2-3 against 18 us). At 1: 13637 iterations, CPU -6 % (2 the same, 3 less;
  /// docs/performance-history.md, session 26). A refreshed matrix is not an exact Newton
  /// matrix: the round-off floor's acceptance and the cycle and divergence tests wait for a
  /// whole one.
  int elastic_refreshes = 1;
  /// Near the round-off floor (`floor`) a kept matrix's step is trusted while it contracts by
  /// at least this much (else a fresh matrix is formed: an old matrix's small steps alone prove
  /// nothing), sparse or dense. Measured on the paper's 30 s scene, 15 x 10
  /// (docs/performance-history.md, sessions 21 and 24): a kept sparse matrix whose iterations
  /// contract by 2-4e-3 at the floor's size converges in its next iteration; 1e-3 there
  /// refactored about once a step for nothing (linear model: 3583 against 2363 factorizations,
  /// 7.5-9.0 against 6.3-6.9 s); a kept dense matrix that contracts by 1e-2 near the floor ends its
  /// step in one or two more iterations, where 1e-3 (the dense value until session 24) formed a
  /// fresh one in about half the steps (reduced-manifold: 3185 against 1673 factorizations).
  double floor_contraction = 0.03;
  /// With a sparse matrix, relax the slaved rows (relax_slaved) after every iteration, not only
  /// at the predictor: see GeneralizedAlpha::relax_slaved.
  bool relax_every_iteration = true;
  /// The kept matrix's iterations within a step are Anderson-accelerated over this many past
  /// increments (integrate/anderson.hpp; 0: plain modified Newton). Measured on the paper's 30 s
  /// scene, 15 x 10 (docs/performance-history.md, sessions 22 and 30): depth 2 takes the
  /// nonlinear model's factorizations from 2380 to 2160 and its CPU by 3-5 %, the linear model's
  /// by 9 %; on a dense (reduced) matrix 10-12 % of the iterations, which paid once the mixing
  /// stopped allocating (session 30, instructions counted: reduced-manifold and reduced-linear
  /// -6 %, rigid +2.7 %, a millisecond). Not for a dense matrix with slaved coordinates (the
  /// reduced Green-strain panel, in full Newton whenever its kept matrix is slow: 1 % fewer
  /// iterations, 0.3 % more instructions).
  int anderson_depth = 2;
};

/// The state the integrator carries from step to step.
/// With conserved momenta (SecondOrderSystem::num_conserved), the base's velocities are set by
/// Pi(q_{n+1}, v_{n+1}) = Pi(q_n, v_n) (and the converged velocity is polished onto that level
/// set: Pi is linear in v), so momentum holds to round-off over any number of steps; the base's
/// vdot is then its algorithmic acceleration, and the equations of motion at t_{n+1} see the
/// base acceleration their own balance rows give (see GeneralizedAlpha::step).
struct AlphaState {
  double t = 0;
  Eigen::VectorXd q, v, vdot, a;  // a: the algorithmic acceleration
  /// With conserved momenta: the accelerations of the momentum rows' coordinates (the base's)
  /// that the equations of motion see at t (vdot's are algorithmic there); empty otherwise.
  Eigen::VectorXd base_accel;
  /// vdot with base_accel in place: the accelerations that satisfy the equations of motion.
  Eigen::VectorXd accelerations() const {
    Eigen::VectorXd x = vdot;
    x.head(base_accel.size()) = base_accel;
    return x;
  }
  /// The Newton predictor's history: vdot one step back and that step's size (0: none).
  Eigen::VectorXd vdot_prev;
  double h_prev = 0;
};

/// Thrown when Newton fails; says when and why.
struct StepFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One run's integrator: the scheme's parameters and Newton's options, and the run's solver state
/// (the factorized iteration matrix, the step size it was built for, the reuse policy's counters).
class GeneralizedAlpha {
 public:
  GeneralizedAlpha(SecondOrderSystem& system, AlphaParameters p, NewtonOptions newton = {});
  /// A consistent start: solves r(q0, v0, vdot0, t0) = 0 for vdot0; a0 = vdot0.
  AlphaState initial_state(double t0, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0);
  /// Advances `s` by h. Throws StepFailure (the state is left unchanged) if Newton fails.
  /// Returns the number of Newton iterations. `guess`, if given, is Newton's starting vdot_{n+1}
  /// in place of the predictor (an event search's interpolation between the bracket's ends).
  int step(AlphaState& s, double h, const Eigen::VectorXd* guess = nullptr);
  SecondOrderSystem& system() const { return sys_; }
  const AlphaParameters& parameters() const { return p_; }
  /// Numeric factorizations of the iteration matrix so far.
  long factorizations() const { return solver_.factorizations(); }
  /// The solver state a run carries between steps, for a checkpoint: the iteration matrix last
  /// factorized, as built or refreshed (S, its step size h, -1: none; with conserved momenta the
  /// last whole matrix's momentum rows' Jacobian), the reuse policy's counters, and the slaved
  /// block (SlavedBlock::values) with its step size (-1: none).
  struct Solver {
    BlockMatrix S;
    double h = -1;
    Eigen::MatrixXd momentum_jacobian;
    int full_steps = 0;
    int elastic_refreshes = 0;
    BlockMatrix slaved_block;
    double slaved_h = -1;
  };
  Solver solver_state() const {
    return {matrix_, factor_h_, momentum_jacobian_, full_steps_, refreshes_,
            slaved_h_ > 0 ? slaved_block_.values() : BlockMatrix(), slaved_h_ > 0 ? slaved_h_ : -1.0};
  }
  /// Resumes from solver_state(): S factorized afresh, so the run goes on bit for bit as the one
  /// that saved it (a factorization is a function of S). Throws StepFailure if S is singular.
  void restore(const Solver& state);

 private:
  void polish_momentum(const Eigen::VectorXd& q, Eigen::VectorXd& v, double t, const Eigen::VectorXd& Pi);
  /// The state an iterate vdot_{n+1} gives at t + h by the scheme's update (from s at t_n): the
  /// algorithmic acceleration a, q and v, and the accelerations the equations of motion see, ve
  /// (vdot with the balance rows' base accelerations w in place; AlphaState).
  struct Iterate {
    Eigen::VectorXd a, q, v, ve;
    bool finite() const { return q.allFinite() && v.allFinite() && ve.allFinite(); }
  };
  Iterate iterate(const AlphaState& s, double h, const Eigen::VectorXd& vdot, const Eigen::VectorXd& w) const;
  /// Factorizes the Newton matrix for steps of size h: formed whole at the iterate x (at t1, with
  /// the momentum rows' Jacobian), or matrix_ as it is (its elastic blocks refreshed by the
  /// caller: whole false); sets the slaved block from it. False if it is singular (no kept matrix
  /// then: factor_h_ < 0).
  bool factorize_at(const Iterate& x, double t1, double h, bool whole);
  /// The consistent predictor (step()): relaxes the slaved coordinates' accelerations in vdot
  /// at the predictor; returns the whole residual at the relaxed predictor (empty: the system has
  /// no slaved coordinates).
  Eigen::VectorXd relax_slaved(const AlphaState& s, double h, Eigen::VectorXd& vdot, const Eigen::VectorXd& w);
  SecondOrderSystem& sys_;
  AlphaParameters p_;
  NewtonOptions newton_;
  // The run's solver state: the factorized iteration matrix and the step size it was built for.
  BorderedSolver solver_;
  double factor_h_ = -1;
  // The system's slaved coordinates (SecondOrderSystem::slaved_velocities), and their block of the
  // iteration matrix with the step size it is for. With a dense matrix, the last factorization's
  // (set with it: a reduced panel's block costs next to nothing). With a sparse one (a mesh), the first
  // factorization's at its step size, kept while the steps keep that size (its values, M, K and
  // small in-plane geometric terms, change little: refactorizing it with every Newton matrix cost
  // 3 % of the paper's nonlinear run for 0.2 % fewer iterations; docs/performance-history.md,
  // session 29), or one formed at a predictor when the step size changed (the step then
  // factorizes its own: kept for Newton instead, the matrix of the unrelaxed predictor, whose
  // membrane misfit is what the sweeps remove, served it worse; session 27).
  std::vector<int> slaved_;
  SlavedBlock slaved_block_;
  double slaved_h_ = -1;
  BlockMatrix slaved_source_;  // relax_slaved's matrix for a block at a new step size (kept storage)
  // Steps left that renew the matrix at every iteration (NewtonOptions::full_newton_steps), and
  // the elastic blocks' refreshes since the last whole matrix (NewtonOptions::elastic_refreshes).
  int full_steps_ = 0;
  int refreshes_ = 0;
  // With conserved momenta: dPi/dvdot of the momentum rows at the last factorization, and the LU
  // of its base columns.
  Eigen::MatrixXd momentum_jacobian_;
  Eigen::PartialPivLU<Eigen::MatrixXd> momentum_lu_;
  // The matrix factorized at factor_h_, as built or with its elastic blocks refreshed in place
  // (NewtonOptions::elastic_refreshes): what a refresh updates and a checkpoint saves
  // (solver_state); unused while factor_h_ < 0 (it may then be one that failed to factorize).
  BlockMatrix matrix_;
  // A kept matrix's Anderson mixing within a step (NewtonOptions::anderson_depth) and its iterate
  // and increment: history reset at each step's start, storage kept (not checkpoint state).
  AndersonMixing mixing_;
  Eigen::VectorXd mixed_x_, mixed_f_;
};

}  // namespace deployfx::integrate
