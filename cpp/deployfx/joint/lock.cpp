#include "deployfx/joint/lock.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace deployfx::joint {
namespace {

template <class... F>
struct Overload : F... {
  using F::operator()...;
};
template <class... F>
Overload(F...) -> Overload<F...>;

// The stop-and-latch lock's contact i: 0 the stop, 1 the latch.
constexpr int kStop = 0, kLatch = 1;

}  // namespace

LockState start_state(const LockSpec& lock, double theta) {
  return std::visit(Overload{[](const HingeLockSpec&) -> LockState { return LockHistory{}; },
                             [&](const PinGrooveSpec& g) -> LockState { return start_history(g, theta); }},
                    lock);
}

void validate(const LockSpec& lock) {
  std::visit(Overload{[](const HingeLockSpec& w) { w.validate(); }, [](const PinGrooveSpec&) {}}, lock);
}

LockLoad load(const LockSpec& lock, const LockState& state, double theta, double rate) {
  if (const auto* w = std::get_if<HingeLockSpec>(&lock)) return lock_load(*w, std::get<LockHistory>(state), theta, rate);
  const PinGrooveLoad g = pin_groove_load(std::get<PinGrooveSpec>(lock), std::get<PinGrooveHistory>(state), theta, rate);
  LockLoad out;
  // The lock force is the contacts' (the walls of the notch); the latch pin's support, which
  // carries the spring's load while the pin rides its track, is not an impact.
  out.torque = g.torque, out.d_theta = g.d_theta, out.d_rate = g.d_rate;
  out.normal_force = g.normal_force - std::max(g.support_force, 0.0);
  return out;
}

int num_events(const LockSpec& lock) {
  return std::visit(Overload{[](const HingeLockSpec&) { return 2; },
                             [](const PinGrooveSpec& g) { return joint::num_events(g); }},
                    lock);
}

void events(const LockSpec& lock, const LockState& state, double theta, double rate, double* g) {
  if (const auto* w = std::get_if<HingeLockSpec>(&lock))
    return lock_events(*w, std::get<LockHistory>(state), theta, rate, g, g + 1);
  pin_groove_events(std::get<PinGrooveSpec>(lock), std::get<PinGrooveHistory>(state), theta, rate, g);
}

void update(const LockSpec& lock, LockState& state, double theta, double rate, const double* margins) {
  if (const auto* w = std::get_if<HingeLockSpec>(&lock))
    return update_lock_history(*w, std::get<LockHistory>(state), theta, rate, margins ? margins[0] : 0.0,
                               margins ? margins[1] : 0.0);
  update_history(std::get<PinGrooveSpec>(lock), std::get<PinGrooveHistory>(state), theta, rate, margins);
}

int support(const LockState& state) {
  const auto* g = std::get_if<PinGrooveHistory>(&state);
  return g ? g->support : -1;
}

int num_contacts(const LockSpec& lock) {
  return std::visit(Overload{[](const HingeLockSpec&) { return 2; },
                             [](const PinGrooveSpec& g) { return g.profile.num_facets(); }},
                    lock);
}

std::vector<WallState> contact_states(const LockSpec& lock, const LockState& state, double theta, double rate) {
  if (const auto* w = std::get_if<HingeLockSpec>(&lock)) {
    std::vector<WallState> out(2);
    wall_states(*w, std::get<LockHistory>(state), theta, rate, &out[kStop], &out[kLatch]);
    return out;
  }
  return facet_states(std::get<PinGrooveSpec>(lock), std::get<PinGrooveHistory>(state), theta, rate);
}

double contact_lever(const LockSpec& lock, const LockState& state, int i, double theta) {
  if (const auto* w = std::get_if<HingeLockSpec>(&lock)) return i == kStop ? w->pin_radius : -w->pin_radius;
  return facet_lever(std::get<PinGrooveSpec>(lock), std::get<PinGrooveHistory>(state), i, theta);
}

double contact_v0(const LockState& state, int i) {
  if (const auto* h = std::get_if<LockHistory>(&state)) return i == kStop ? h->stop_v0 : h->latch_v0;
  return std::get<PinGrooveHistory>(state).facets[static_cast<std::size_t>(i)].v0;
}

void set_contact_scale(LockState& state, int i, double T, double resolution) {
  if (auto* h = std::get_if<LockHistory>(&state)) {
    (i == kStop ? h->stop_T : h->latch_T) = T;
    (i == kStop ? h->stop_resolution : h->latch_resolution) = resolution;
    return;
  }
  FacetContact& f = std::get<PinGrooveHistory>(state).facets[static_cast<std::size_t>(i)];
  f.T = T, f.resolution = resolution;
}

ImpactTracker& contact_tracker(LockState& state, int i) {
  if (auto* h = std::get_if<LockHistory>(&state)) return i == kStop ? h->stop_track : h->latch_track;
  return std::get<PinGrooveHistory>(state).facets[static_cast<std::size_t>(i)].track;
}

const contact::ContactLaw& law(const LockSpec& lock) {
  return std::visit([](const auto& l) -> const contact::ContactLaw& { return l.law; }, lock);
}

ContactResolution resolution(const LockSpec& lock, const LockState& state, double theta) {
  if (const auto* w = std::get_if<HingeLockSpec>(&lock)) {
    ContactResolution r = contact_resolution(std::get<LockHistory>(state));
    r.error /= w->pin_radius;  // m of the pin's path to rad
    return r;
  }
  return contact_resolution(std::get<PinGrooveSpec>(lock), std::get<PinGrooveHistory>(state), theta);
}

double friction_step_limit(const LockSpec& lock, const LockState& state, double theta, double rate,
                           double rate_change) {
  if (const auto* w = std::get_if<HingeLockSpec>(&lock))
    return friction_step_limit(*w, std::get<LockHistory>(state), rate, rate_change);
  return friction_step_limit(std::get<PinGrooveSpec>(lock), std::get<PinGrooveHistory>(state), theta, rate,
                             rate_change);
}

bool latched(const LockSpec& lock, const LockState& state) {
  if (std::holds_alternative<HingeLockSpec>(lock)) return std::get<LockHistory>(state).latched;
  // A groove holds the pin once it has reached every face (each facet armed: the pin has been on
  // its free side within its range), e.g. past the latch flank into the notch.
  const auto& facets = std::get<PinGrooveHistory>(state).facets;
  return std::all_of(facets.begin(), facets.end(), [](const FacetContact& f) { return f.armed; });
}

}  // namespace deployfx::joint
