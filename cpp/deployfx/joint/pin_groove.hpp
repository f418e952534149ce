#pragma once
// The lock of a hinge as a pin sliding in a groove (You et al. 2016, Fig. 1: "the cylindrical pin
// slides along the locking groove"; Eq. 45: F_n = (K_c delta^1.5 + D_c delta') n and
// F_t = -mu |F_n| t). A pin, a circle of radius rho on the child body C, against a groove profile
// (contact/groove_profile.hpp) on the parent body P, both in the hinge plane, as a function of
// the hinge angle theta and its rate theta'.
//
// Frames. The profile is given in P's hinge plane: 2-D coordinates (m) with the origin on the
// hinge axis and axes x_h, y_h = n x x_h perpendicular to the axis n; C's hinge-plane axes
// coincide with P's at theta = 0 and turn by theta about n. The pin's centre lies at angle
// pin_angle in C's plane, at distance pin_distance from the axis (or s(theta) on a latch spring,
// joint/latch_follower.hpp): c = s e_r(psi), psi = theta + pin_angle, in P's plane.
//
// Each facet of the profile is one contact, an active set like joint/hinge_lock.hpp's walls:
//   delta = -gap(c), delta' = -n·c', c' = theta' dc/dtheta,
//   F_n from the contact law without its clamp while the facet is closed
//   (contact/unclamped_force.hpp; Hunt-Crossley's v0 is the approach speed at onset),
//   F_t = friction(v_t, F_n) along t, v_t = t·c' (contact::CoulombFriction, tanh-regularised at
//   v_reg; only while F_n > 0), the force on the pin F = F_n n + F_t t.
// The sliding velocity is the tangential velocity of the pin's centre relative to the groove:
// the pin's own spin with C (theta' rho at its rim) is neglected against its centre's speed
// (theta' s), so the forces act at the centre. Where a facet's normal lies along the pin's path
// (a stop wall normal to the path) v_t = 0: friction leaves a normal impact unchanged to first
// order (pressed in by D rad, the pin's centre slides along a straight wall by r (1 - cos D):
// friction's work is at most 2 mu D_max of the impact energy, docs/research/pin-groove.md).
// The torque on theta is the generalized force of F at c: tau = (c x F)·n_axis = c_x F_y - c_y F_x.
// A facet takes part once armed: the pin has been on its free side (gap >= 0) within its range
// since it last left that range (so a latch face behind the pin, like hinge_lock's latch, acts
// only once the pin has passed it; a facet seen from behind never pulls the pin through it).
//
// Latch spring (optional): the pin is a massless radial follower on a support facet
// (latch_follower.hpp). The support carries the spring: from the pin's radial balance,
//   N (n_s + f t_s)·e_b = -(F_s + sum_k F_k·e_b),  f = F_t/F_n of the friction law at v_t,s,
// with e_b the spring's direction, F_k the other facets' forces; the pin transmits
// F = N (n_s + f t_s) + sum_k F_k to C at c. A support nearly along the bore (|(n_s + f t_s)·e_b|
// below kMinHold = 0.05, the end of a roll-over or a wedge jam) is held at that value: the wedge
// force is capped at 20 times the radial load; a real pin leaves the corner there. A profile that
// pushes the pin to the end of its travel (bottomed) holds it there as a fixed pin, the support
// then a compliant contact with the law's clamp (no history).
//
// Derivatives d/dtheta and d/dtheta' are exact: forward-mode dual numbers (math/dual.hpp) carried
// through the profile's analytic gap, normal and curvature (d n/d c) and the laws' partials.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "deployfx/contact/force_law.hpp"
#include "deployfx/contact/friction.hpp"
#include "deployfx/contact/groove_profile.hpp"
#include "deployfx/joint/hinge_lock.hpp"
#include "deployfx/joint/impact_record.hpp"
#include "deployfx/joint/latch_follower.hpp"

namespace deployfx::joint {

struct PinGrooveSpec {
  /// Throws std::invalid_argument naming the parameter: pin_distance > 0 (without a latch
  /// spring), pin_angle finite (rad), pin_radius >= 0 (m), the latch spring's ranges.
  PinGrooveSpec(contact::GrooveProfile profile, double pin_distance, double pin_angle, double pin_radius,
                contact::ContactLaw law, contact::CoulombFriction friction = contact::CoulombFriction(0.0),
                std::optional<LatchSpring> latch = std::nullopt);

  contact::GrooveProfile profile;    ///< in P's hinge plane (m)
  double pin_distance;               ///< m, the fixed pin's centre from the axis (unused with a latch)
  double pin_angle;                  ///< rad, the pin's direction in C's hinge plane
  double pin_radius;                 ///< m, rho, the pin's own radius
  contact::ContactLaw law;
  contact::CoulombFriction friction;
  std::optional<LatchSpring> latch;
};

/// One facet's contact mode (the same semantics as joint::LockHistory's walls).
struct FacetContact {
  bool armed = false;   ///< the pin has been on the facet's free side since it last left its range
  bool closed = false;  ///< in contact: the law is used without its clamp
  bool inside = false;  ///< open but within the compliant layer (delta > 0) at the last accepted state
  double v0 = 0;        ///< m/s, approach speed at onset (at least 1 mm/s)
  /// s, the impact time scale of the contact in progress (as LockHistory::stop_T: set by the
  /// engine at onset from the pin's effective mass along the facet, facet_lever; 0 while open or
  /// for a plastic impact).
  double T = 0;
  double resolution = kContactResolution;  ///< the fraction of v0 T a step's local error may make (set with T)
  ImpactTracker track;  ///< the facet's impact records (Impact::wall = the facet's index)
};

/// What the lock remembers between steps (a run's Data).
struct PinGrooveHistory {
  std::vector<FacetContact> facets;  ///< one per profile facet
  int support = -1;                  ///< latch spring: the facet the pin rests on (-1: its bore stop)
  /// pin_position's last answer (not history: an exact memo, neither saved nor compared).
  mutable FollowerMemo follower;
};

struct PinGrooveLoad {
  double torque = 0;         ///< N m, on theta
  double d_theta = 0;        ///< d torque / d theta, N m/rad
  double d_rate = 0;         ///< d torque / d theta', N m s/rad
  double normal_force = 0;   ///< N, sum of the closed facets' normal forces and the support's
  double support_force = 0;  ///< N, the latch support's normal force N (0 without; < 0: the other
                             ///< contacts pull the pin off its support, outside the model)
  double pin_position = 0;   ///< m, s: the pin centre's distance from the axis
  /// Latch: the support no longer meets the bore (a trial state past the drop event); the pin
  /// then continues on it (FollowerState::beyond) until update_history drops it.
  bool support_lost = false;
};

/// The history at the start of a run at hinge angle theta: facets armed where the pin is on their
/// free side (in range), all open; the latch pin on the support that holds it farthest from its
/// stop (next_support with w_from = +inf).
PinGrooveHistory start_history(const PinGrooveSpec& spec, double theta);

/// The pin centre's distance from the axis and its theta-derivatives (m, m/rad, m/rad^2).
FollowerState pin_position(const PinGrooveSpec& spec, const PinGrooveHistory& history, double theta);

PinGrooveLoad pin_groove_load(const PinGrooveSpec& spec, const PinGrooveHistory& history, double theta, double rate);

/// Facet f under a history (joint::wall_states for a facet): its mode, normal force (N; the law
/// without its clamp while closed, 0 while open), penetration and its rate (m, m/s, positive into
/// the facet). The latch's support is no impact: reported open.
WallState facet_state(const PinGrooveSpec& spec, const PinGrooveHistory& history, int facet, double theta,
                      double rate);
/// facet_state of every facet, in facet order (the pin's position on its track found once).
std::vector<WallState> facet_states(const PinGrooveSpec& spec, const PinGrooveHistory& history, double theta,
                                    double rate);
/// The facet's lever, d delta / d theta = -n·dc/dtheta (m/rad; > 0 when theta drives the pin into
/// it): the pin's effective mass along the facet's normal is 1 / (lever^2 e^T M^-1 e) (today's
/// lock: r; here r cos D on the stop wall, -r cos D on the latch wall).
double facet_lever(const PinGrooveSpec& spec, const PinGrooveHistory& history, int facet, double theta);
/// joint::contact_resolution for the groove, over the closed facets with T > 0: the hinge-angle
/// error a step may make, the facet's resolution times v0 T / |lever| (rad, where today's returns
/// m and the engine divides by the pin radius), and the shortest step worth taking, T /
/// kMaxStepsPerImpactTime (s); +inf and 0 with none.
ContactResolution contact_resolution(const PinGrooveSpec& spec, const PinGrooveHistory& history, double theta);

/// The number of event functions: one per facet, plus one (the drop) with a latch spring.
int num_events(const PinGrooveSpec& spec);
/// The event functions, positive while the modes hold, each continuous within a step (the history
/// is fixed there): facet k (k < num_facets) as joint::lock_events' walls: closed, its unclamped
/// force (N); open, its gap (m), or for a pin within the layer the force it would push with,
/// negated (N); +inf when not armed, out of range (0 if closed: it opens), or the support. The
/// last, with a latch spring: drop_margin (m), +inf on the bore stop.
void pin_groove_events(const PinGrooveSpec& spec, const PinGrooveHistory& history, double theta, double rate,
                       double* events);
/// Updates the history after an accepted step ending at (theta, rate): arms facets, switches a
/// facet's mode when its event is at or below its margin (margins: num_events values, 0 but at a
/// located event; nullptr: all 0), and drops the latch pin to its next support (the old support
/// then counts as just separated, `inside`). An open facet touching the pin without penetration
/// (delta <= 0) while the pin moves away (delta' <= 0) does not close. Facets arm here: call it
/// after every accepted step.
void update_history(const PinGrooveSpec& spec, PinGrooveHistory& history, double theta, double rate,
                    const double* margins = nullptr);
/// joint::friction_step_limit for the groove: the friction torque of a closed facet (or the
/// support) turns over |theta'| < v_reg / |t·dc/dtheta|; a Newton step from outside the narrowest
/// such band to beyond 10 widths on the other side is cut to land on theta' = 0. 1 otherwise.
double friction_step_limit(const PinGrooveSpec& spec, const PinGrooveHistory& history, double theta, double rate,
                           double rate_change);

}  // namespace deployfx::joint
