#pragma once
// The hinge lock of You et al. (2016), Fig. 1 and 4: a pin on the hinge fitting, at radius
// r_pin from the axis, enters a curved groove at the deployed angle. Modelled in the hinge angle
// theta (the travel from stowed) as two one-sided walls (paper2016-scenario.md, "choice"):
//   the stop at theta_lock:        penetration delta = r_pin (theta - theta_lock),
//   the latch at theta_latch = theta_lock - clearance / r_pin, active once the pin has passed
//   it (it forbids return past the groove): delta = r_pin (theta_latch - theta).
// Each wall pushes with a normal force F_n(delta, delta') of a contact::ContactLaw, and the pin
// rubs the groove with Coulomb friction mu F_n opposing the slip r_pin theta'. The torque on the
// hinge is tau = r_pin (F_latch - F_stop) + r_pin F_t.
// Each wall is either open or in contact, and its mode is fixed within a time step (an active
// set): in contact the law is used without its clamp, so the residual is smooth while Newton
// iterates. The stepper locates the switches as events: an open wall closes when its gap reaches
// 0; a wall in contact opens when its (unclamped) force reaches 0. Between events the force
// therefore never pulls, and the paper's law, whose force jumps to D v0 at onset, needs no
// smoothing.
#include "deployfx/contact/force_law.hpp"
#include "deployfx/contact/friction.hpp"
#include "deployfx/joint/impact_record.hpp"

namespace deployfx::joint {

struct HingeLockSpec {
  double theta_lock = 0;   ///< rad of hinge travel where the pin seats (the deployed angle)
  double pin_radius = 0;   ///< m, from the hinge axis
  double clearance = 0;    ///< m, the pin's free play in the groove once latched
  contact::ContactLaw law{contact::ContactLaw::Kind::kKelvinVoigtHertz, 1.0};
  contact::CoulombFriction friction{0.0};
  /// Throws std::invalid_argument naming the parameter (pin_radius > 0, clearance >= 0).
  void validate() const;
  double theta_latch() const { return theta_lock - clearance / pin_radius; }
};

/// Fraction of a contact's penetration scale v0 T that a step's local error may reach: at 1e-3
/// every law's restitution comes within 1 % of its closed form at any output step from 1e-3 to
/// 0.05 s, about 50 steps a contact (tests/test_lock_accuracy.py).
inline constexpr double kContactResolution = 1e-3;
/// The same for the panel behind a pin the law's dashpot stops alone (its T from the hinge's
/// inertia with the panels held rigid; multibody/events.cpp): at 1e-2 the damped paper scene's
/// largest tip displacement is within 0.1 mm of a run at dt = 0.25 ms (1e-3: 0.19 mm; stepped
/// over at dt: 1.47 mm) for 1.15x the CPU of stepping over it (1e-3: 1.6-2.5x), and no undamped
/// trajectory of the rattle gains energy (issue 29, docs/research/undamped-stability.md).
inline constexpr double kPanelContactResolution = 1e-2;
inline constexpr double kMaxStepsPerImpactTime = 100.0;

/// What the lock remembers between steps (a run's Data): the latch and each wall's contact,
/// with the approach speed at onset (the Hunt-Crossley family needs it).
struct LockHistory {
  bool latched = false;
  bool stop_contact = false, latch_contact = false;  ///< the walls' modes
  /// An open wall whose pin was within its compliant layer (delta > 0) at the last accepted
  /// state: it recloses when the pin pushes in again (its event is then that force), not when a
  /// gap closes (lock_events).
  bool stop_inside = false, latch_inside = false;
  double stop_v0 = 0, latch_v0 = 0;  ///< approach speed at onset, m/s (at least 1 mm/s)
  /// The time scale T of each wall's contact in progress, s (set by the engine at onset:
  /// contact::rebound_time_scale of the pin's effective mass, or for a pin the law's dashpot
  /// stops alone, of the hinge's with the panels held rigid; 0 while open, and where neither
  /// rebounds): the stepper resolves the contact to the fraction `*_resolution` of its
  /// penetration scale v0 T (contact_resolution).
  double stop_T = 0, latch_T = 0;
  double stop_resolution = kContactResolution, latch_resolution = kContactResolution;
  ImpactTracker stop_track, latch_track;  ///< the walls' impact records
};

/// One wall under a history: its mode, normal force (N; 0 while open), penetration and rate (m,
/// m/s; positive into the wall).
struct WallState {
  bool contact = false;
  double F = 0, delta = 0, delta_dot = 0;
};

struct LockLoad {
  double torque = 0;        ///< N m, on theta
  double normal_force = 0;  ///< N, sum over both walls (>= 0 between events)
  double d_theta = 0;       ///< d torque / d theta, N m/rad
  double d_rate = 0;        ///< d torque / d theta', N m s/rad
};

LockLoad lock_load(const HingeLockSpec& lock, const LockHistory& history, double theta, double rate);
/// The stop's and the latch's states (the latch is open until the pin has passed it).
void wall_states(const HingeLockSpec& lock, const LockHistory& history, double theta, double rate, WallState* stop,
                 WallState* latch);
/// How finely a step in contact must go: the local displacement error (m, of the pin along the
/// wall's normal) it may make, its resolution times v0 T, and the shortest step worth taking,
/// T / kMaxStepsPerImpactTime (s), the smallest of each over the walls in contact whose impact
/// rebounds; +inf and 0 with none.
struct ContactResolution {
  double error = 0, min_step = 0;
};
ContactResolution contact_resolution(const LockHistory& history);
/// The event functions of the two walls (stop, latch), positive while their modes hold: an open
/// wall's gap (m), or for a pin within the layer the force the wall would push with, negated
/// (N); a closed wall's normal force (N); the latch's is +inf until latched. Each is continuous
/// in the state within a step (the history is fixed there), so the stepper's secant search
/// converges on its root instead of bisecting a jump (the force law's D delta' at onset).
void lock_events(const HingeLockSpec& lock, const LockHistory& history, double theta, double rate,
                 double* stop, double* latch);
/// The fraction in (0, 1] of a Newton step worth taking that changes the hinge rate from `rate`
/// by `rate_change` (rad/s), for a lock whose wall is in contact with friction: the friction
/// torque turns over the band |theta'| < v_reg / r_pin, steeply (slope mu F_n r_pin^2 / v_reg);
/// against a small effective inertia (a hinge riding on a flexible panel) exact Newton from the
/// slip on one side jumps far past the band to the other and cycles about it at any time step.
/// A step that would carry theta' from outside the band across it to far beyond (10 widths) is
/// cut to land on theta' = 0, from where Newton on the regularized law converges without
/// overshoot to a root on either side (the law is concave on one side of 0, convex on the
/// other). 1 otherwise (no wall in contact, no friction, no such crossing).
double friction_step_limit(const HingeLockSpec& lock, const LockHistory& history, double rate, double rate_change);
/// Updates the history after an accepted step ending at (theta, rate): a wall switches mode when
/// its event function (lock_events) is at or below its margin (stop's, latch's; 0 but at a
/// located event, see integrate::SecondOrderSystem::accept).
void update_lock_history(const HingeLockSpec& lock, LockHistory& history, double theta, double rate,
                         double stop_margin = 0.0, double latch_margin = 0.0);

}  // namespace deployfx::joint
