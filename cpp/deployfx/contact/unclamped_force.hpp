#pragma once
// A compliant contact's normal force while it is closed (an active set: the contact's mode is
// fixed within a time step and switched at located events), without the clamp F >= 0 of
// ContactLaw::evaluate, so that the residual stays smooth while Newton iterates; the penetration
// may turn slightly negative within the step that ends at separation. The lock's walls
// (joint/hinge_lock.cpp) and the pin-groove facets (joint/pin_groove.cpp) both use it:
//   Kelvin-Voigt-Hertz:   F = K s|delta|^n + D delta_dot,  s = sign(delta);
//   Hunt-Crossley family: F = K delta^n (1 + c delta_dot / v0)       for delta >= 0,
//                         F = -K |delta|^n |1 + c delta_dot / v0|    below,
// so that the law's extension never pushes a pin that has left the surface (which would feed
// energy in and keep the contact from opening). v0 (m/s) is the approach speed at onset.
#include "deployfx/contact/force_law.hpp"

namespace deployfx::contact {

/// F (N) and its partials (N/m, N s/m) for a closed contact; v0 is floored at 1e-9 m/s.
ContactForce unclamped_force(const ContactLaw& law, double delta, double delta_dot, double v0);

/// A wall's event function (> 0 while its mode holds), penetration delta (m) and rate delta_dot
/// (m/s); the lock's walls and the pin-groove facets share it.
/// - closed: its force F; but where F vanishes with the penetration to order n (the
///   Hunt-Crossley family, and Kelvin-Voigt-Hertz without damping) its n-th root
///   s |F / K|^(1/n) (m, s = sign F), which has F's sign and roots and crosses zero with a slope:
///   an event search then closes on the separation in a few trial steps, where on F itself, flat
///   at its root, the secant only crept up on it (about 20 trial steps a separation);
/// - open: its gap -delta, but for a pin that was within the compliant layer at the last accepted
///   state (just separated; `inside`) and still is, minus the force it would push with, so it
///   recloses as soon as the pin pushes in again. Which of the two an open wall uses is fixed
///   within a step: the gap's root is where the law's force jumps to D delta' (Kelvin-Voigt), and
///   an event function switching to the force there would jump across its root (measured on the
///   paper's 30 s scene: 27 of the 66 event searches bisected such a jump to the 1e-8 s floor, 21
///   trial steps each).
double wall_event(const ContactLaw& law, bool closed, bool inside, double v0, double delta, double delta_dot);

}  // namespace deployfx::contact
