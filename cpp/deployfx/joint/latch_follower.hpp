#pragma once
// A spring-loaded latch pin as a massless radial follower (the optional latch spring of
// joint/pin_groove.hpp). Model and assumptions:
// - The pin slides in a straight radial bore of the child body (direction pin_angle in its hinge
//   plane); its centre's distance from the hinge axis is s = stop + kappa w, with w in [0, travel]
//   the spring's compression from its stop and kappa = +1 when the spring pushes the pin toward
//   the axis (-1: away). The spring force is F_s = preload + stiffness w, along e_b = -kappa e_r.
// - The pin has no mass: it rests on one facet of the groove profile, its support (a history
//   variable), at the contact point where gap = 0 (a rigid follower: the support's penetration,
//   ~(F_s/K)^(2/3), is neglected against the travel), or on its bore stop (w = 0) without one.
//   Rolling over a convex corner it follows the corner's fan.
// - The support ends when the bore no longer meets the support's rho-offset within the travel
//   (the pin drops off an edge): the event function drop_margin = rho - (distance from the bore
//   segment to the facet) is continuous and crosses 0 there, linearly in theta at a sharp edge.
//   The pin then falls, at once, to the next support below (next_support), or its bore stop; the
//   spring work of that fall goes into the pin's impact on the new support: lost. It falls at
//   the located event (the history's update); within the step that finds it, past the drop, it
//   is held where the drop left it (follow()).
// Limits: the pin never climbs onto another facet (a facet it runs into is a compliant contact
// of pin_groove.hpp); the support's slope dominates the radial motion near the end of a roll-over
// (ds/dtheta grows as 1/sqrt near a vertical flank: a massless pin follows any edge at once, a
// real one lags by its drop time sqrt(2 m d / F_s), ~4 ms for a 5 g pin falling 2 mm under 1.5 N).
#include <Eigen/Core>
#include <cstdint>

#include "deployfx/contact/groove_profile.hpp"

namespace deployfx::joint {

struct LatchSpring {
  bool toward_axis = true;  ///< the spring pushes the pin toward the hinge axis (else away from it)
  double stop = 0;          ///< m, the pin centre's distance from the axis at its bore stop (w = 0)
  double travel = 0;        ///< m, how far the spring can be compressed from the stop (> 0)
  double preload = 0;       ///< N, the spring force at the stop (>= 0)
  double stiffness = 0;     ///< N/m (>= 0)
  /// Throws std::invalid_argument naming the parameter: stop > 0, travel > 0, the bore on one
  /// side of the axis (stop - travel > 0 when pushing away from it), preload >= 0, stiffness >= 0.
  void validate() const;
  double kappa() const { return toward_axis ? 1.0 : -1.0; }
  double force(double w) const { return preload + stiffness * w; }  ///< N at compression w (m)
};

/// The pin's radial position on a support at hinge angle theta.
struct FollowerState {
  bool found = false;     ///< the bore meets the support's rho-offset within the travel (true on the stop)
  bool beyond = false;    ///< past the drop: held where the drop left it (follow())
  bool bottomed = false;  ///< the profile pushes the pin to the end of its travel (w = travel)
  double w = 0;           ///< m, compression (0 on the bore stop)
  double s = 0, ds = 0, d2s = 0;  ///< m, m/rad, m/rad^2: distance from the axis and its theta-derivatives
  double drop_margin = 0;         ///< m, rho - distance(bore, support): > 0 while supported
};

/// A one-entry memo of follow(): its inputs and its answer. follow() is a pure function of them,
/// so a hit returns the same bits as a call. One per lock history (a run's own: not for
/// concurrent use): a step asks for the pin's position at one hinge angle from its residual, its
/// friction limit, its events and the history's update (rigid paper scene: 65 % of the calls
/// repeat the one before, and the follower's root search was half of the run).
class FollowerMemo {
 public:
  /// The memo's answer if it holds these inputs, else null.
  const FollowerState* find(const contact::GrooveProfile& profile, const LatchSpring& spring, double pin_angle,
                            double rho, int support, double theta) const;
  void store(const contact::GrooveProfile& profile, const LatchSpring& spring, double pin_angle, double rho,
             int support, double theta, const FollowerState& state);

 private:
  bool valid_ = false;
  std::uint64_t profile_ = 0;
  LatchSpring spring_;
  double pin_angle_ = 0, rho_ = 0, theta_ = 0;
  int support_ = -1;
  FollowerState state_;
};

/// The pin on facet `support` (psi = theta + pin_angle its direction in the parent's hinge plane);
/// support < 0: on its bore stop (s = stop, ds = d2s = 0, drop_margin = +inf). Past the drop
/// (drop_margin < 0: a trial state beyond the event, which the history's update then switches to
/// the next support), found is false and the pin is held where the drop left it (`beyond`: s and
/// w of the last supported angle, ds = d2s = 0), so the support's force continues past it. The
/// support is fixed within a step, as a wall's mode is (an active set): the pin falling there
/// instead made the hinge torque drop at the drop (on the paper's groove from 0.165 N m to 0, the
/// pin by 1.9 mm), and an implicit step that ended just past it had no solution (its end-point
/// torque, lower, put its end before the drop): Newton cycled to its limit and the steps halved
/// (15-41 failures at the first lock of each 30 s paper run). The located drop's step is then
/// taken again with the pin dropped (integrate/trajectory.cpp), so that the next step starts from
/// the dropped pin's forces.
FollowerState follow(const contact::GrooveProfile& profile, const LatchSpring& spring, double pin_angle,
                     double rho, int support, double theta);
/// The support the pin falls onto from compression w_from (m): the facet other than `exclude`
/// with the highest contact point below w_from (largest w), or -1 (the bore stop). With
/// w_from = +inf and exclude = -1: the pin's support when it is mounted (the facet that holds it
/// farthest from its stop).
int next_support(const contact::GrooveProfile& profile, const LatchSpring& spring, double pin_angle, double rho,
                 double theta, double w_from, int exclude);

}  // namespace deployfx::joint
