#pragma once
// Ready groove profiles for joint/pin_groove.hpp:
// - stop_latch_groove: today's lock (joint/hinge_lock.hpp: a stop at theta_lock, a latch one
//   clearance before it, the pin at pin_radius r from the axis) as one profile, a slot of three
//   facets: the stop wall, the slot's bottom (never touched), the latch wall. Each wall is a line
//   parallel to the radius through the pin's centre at its wall angle, offset by the pin's radius
//   rho, so the pin touches it at that angle with the normal along its path and
//     gap_stop = -r sin(theta - theta_lock),  gap_latch = r sin(theta - theta_latch)
//   for any rho, where hinge_lock.cpp uses the arc length r (theta - theta_lock): the two agree to
//   a relative (theta - theta_wall)^2 / 6 in delta and (theta - theta_wall)^2 / 2 in the lever
//   r cos(theta - theta_wall), ~1e-6 at the paper's penetrations (1e-4 m on r = 0.03 m). No
//   profile of lines and arcs can give the arc length exactly (only an involute of the pin's
//   circle has its normals along the path everywhere). The latch facet arms, like hinge_lock's
//   latch, when the pin reaches theta_latch.
// - paper_groove: the scene of You et al. (2016), docs/research/pin-groove.md: a spring-loaded pin
//   riding a circular track about the hinge axis (a cam disc's rim) that drops into a notch at the
//   deployed angle: its far flank is the stop, its near flank the latch, its bottom the seat.
#include "deployfx/joint/hinge_lock.hpp"
#include "deployfx/joint/pin_groove.hpp"

namespace deployfx::joint {

/// The facets of stop_latch_groove's profile.
constexpr int kStopFacet = 0, kSlotBottomFacet = 1, kLatchFacet = 2;

/// Today's HingeLockSpec as a pin-groove lock with a pin of radius rho (m, 0 <= rho <
/// lock.pin_radius / 2) at angle pin_angle (rad) in the child's hinge plane; the walls reach
/// rho + lock.pin_radius / 4 on either side of the pin's path. Friction is lock.friction, now
/// along the walls (so it does not act on a normal impact).
PinGrooveSpec stop_latch_groove(const HingeLockSpec& lock, double rho, double pin_angle = 0.0);
/// hinge_lock's LockHistory in stop_latch_groove's facets (the slot's bottom open and unarmed).
PinGrooveHistory stop_latch_history(const LockHistory& history);

struct PaperGrooveParameters {
  double theta_lock = 1.5707963267948966;  ///< rad, hinge travel at the stop (deployed: 90 deg from stowed)
  double pin_angle = 0.0;        ///< rad, the pin's bore in the child's hinge plane
  double seat = 0.03;            ///< m, the pin centre's distance from the axis seated in the notch
  double pin_radius = 2e-3;      ///< m, rho
  double notch_depth = 4e-3;     ///< m, track radius minus notch-bottom radius (> rho)
  double clearance = 0.2e-3;     ///< m, the pin's play in the notch along its path
  double stop_height = 6e-3;     ///< m, how far the stop flank rises above the track
  double track_start = -0.2;     ///< rad, hinge travel where the track begins (< 0: before the stowed pin)
  double preload = 1.0;          ///< N, latch spring force at its bore stop
  double stiffness = 100.0;      ///< N/m, latch spring rate
  double stop_below_seat = 1e-3; ///< m, the bore stop below the seated centre (the pin rests on the notch bottom)
  double travel = 7e-3;          ///< m, the pin's travel above its bore stop (> ride height - stop)
};
/// The paper's lock: facets 0 the stop flank, 1 the notch bottom, 2 the latch flank with the
/// track; a latch spring pushing the pin toward the axis. Throws std::invalid_argument naming the
/// parameter out of range.
PinGrooveSpec paper_groove(const PaperGrooveParameters& p, const contact::ContactLaw& law,
                           const contact::CoulombFriction& friction);

}  // namespace deployfx::joint
