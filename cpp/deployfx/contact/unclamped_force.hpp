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

}  // namespace deployfx::contact
