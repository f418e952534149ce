#pragma once
// A hinge's lock, whichever its geometry: the stop-and-latch walls in the hinge angle
// (joint/hinge_lock.hpp) or a pin sliding in a groove profile (joint/pin_groove.hpp, You et al.
// 2016 Fig. 1 and Eq. 45). The engine (multibody/) calls these and nothing of either geometry:
// each lock has contacts (the two walls, or the profile's facets), each contact a mode, an
// onset speed, an impact time scale and its impact records, and the lock a torque on theta with
// its derivatives, event functions, and a history updated on accepted steps only.
#include <variant>
#include <vector>

#include "deployfx/joint/hinge_lock.hpp"
#include "deployfx/joint/impact_record.hpp"
#include "deployfx/joint/pin_groove.hpp"

namespace deployfx::joint {

using LockSpec = std::variant<HingeLockSpec, PinGrooveSpec>;
using LockState = std::variant<LockHistory, PinGrooveHistory>;

/// The history at the start of a run at hinge angle theta (rad).
LockState start_state(const LockSpec& lock, double theta);
/// Throws std::invalid_argument naming the bad parameter.
void validate(const LockSpec& lock);

/// The torque on theta (N m), its derivatives and the normal force (N, every contact's; a groove's
/// latch-pin support excluded: it carries the spring, not an impact).
LockLoad load(const LockSpec& lock, const LockState& state, double theta, double rate);

/// The event functions (positive while each contact's mode holds; see joint::lock_events and
/// joint::pin_groove_events): their number, and their values into `g` (num_events of them).
int num_events(const LockSpec& lock);
void events(const LockSpec& lock, const LockState& state, double theta, double rate, double* g);
/// Updates the history after an accepted step (margins: num_events values, or null).
void update(const LockSpec& lock, LockState& state, double theta, double rate, const double* margins);
/// A latch pin's support facet (PinGrooveHistory::support); -1 for the stop-latch walls.
int support(const LockState& state);

/// The lock's contacts (the stop and the latch; the profile's facets).
int num_contacts(const LockSpec& lock);
/// Every contact's mode, normal force, penetration and rate at (theta, rate), in contact order
/// (num_contacts): the lock's kinematics (a latch pin's position on its track) once for all.
std::vector<WallState> contact_states(const LockSpec& lock, const LockState& state, double theta, double rate);
/// d delta / d theta of contact i (m/rad): the pin's effective mass along its normal is
/// 1 / (lever^2 e^T M^-1 e).
double contact_lever(const LockSpec& lock, const LockState& state, int i, double theta);
/// Contact i's approach speed at onset (m/s), its time scale T (s) and resolution (the fraction of
/// v0 T a step's local error may make: contact_resolution), set by the engine at onset, and its
/// impact tracker.
double contact_v0(const LockState& state, int i);
void set_contact_scale(LockState& state, int i, double T, double resolution);
ImpactTracker& contact_tracker(LockState& state, int i);
/// The contact law (every contact of a lock has the same).
const contact::ContactLaw& law(const LockSpec& lock);

/// The hinge-angle error a step may make while a contact is resolved (rad), and the shortest step
/// worth taking (s): joint::contact_resolution over the contacts in contact; +inf and 0 with none.
ContactResolution resolution(const LockSpec& lock, const LockState& state, double theta);
/// joint::friction_step_limit of the lock.
double friction_step_limit(const LockSpec& lock, const LockState& state, double theta, double rate,
                           double rate_change);
/// Whether the pin is held in the deployed position: latched past the latch wall, or in the
/// groove's notch (its latch facet armed).
bool latched(const LockSpec& lock, const LockState& state);

}  // namespace deployfx::joint
