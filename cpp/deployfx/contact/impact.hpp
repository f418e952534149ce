#pragma once
// A point mass m hitting a compliant surface at speed v0, from first contact to separation:
//   m delta'' = -F(delta, delta'),  delta(0) = 0, delta'(0) = v0,
// with F a ContactLaw (the Hunt-Crossley family is given its onset speed v0): the reference
// problem for the lock's contact laws, whose restitution and penetration have closed forms for
// Hertz, the linear spring-dashpot and the Hunt-Crossley family.
// Classical RK4 with a fixed step dt; the turning point (delta' = 0) and the separation (F back
// to 0, at delta = 0 or, for Kelvin-Voigt, at delta > 0) are located by bisecting an RK4 substep
// to round-off, so no step straddles the kink of the clamped force. Error: O((dt/T)^4) for
// n = 1, O((dt/T)^2.5) for the Hertz exponent n = 3/2 (delta^n is not smooth at onset), with
// T = impact_time_scale(); at dt = T/4000, restitution, penetration and duration come out to
// ~1e-11 relative (tests/test_contact_laws.py: closed forms and scipy's DOP853).
#include <functional>
#include <vector>

#include "deployfx/contact/force_law.hpp"

namespace deployfx::contact {

struct ImpactResult {
  double restitution = 0;       // exit speed / v0
  double max_penetration = 0;   // m
  double contact_duration = 0;  // s, onset to separation
  double peak_force = 0;        // N; the largest step sample refined by a parabola
  double energy_lost = 0;       // J, m (v0^2 - v_exit^2) / 2: what the mass does not get back
  long steps = 0;               // RK4 steps taken, the located substeps included
  // Every step if recorded (onset and separation included): s, m, m/s, N.
  std::vector<double> t, delta, delta_dot, force;
};

/// T = delta_H / v0, delta_H = ((n + 1) m v0^2 / (2 K))^(1/(n+1)) the penetration of the
/// undamped Hertz impact; for Kelvin-Voigt with D > 0, min(T, m / D) (the dashpot's time).
double impact_time_scale(const ContactLaw& law, double mass, double v0);

/// impact_time_scale for an impact that rebounds; 0 for a plastic one, with nothing to resolve:
/// a Kelvin-Voigt dashpot that stops the mass within a tenth of the Hertz time (m / D <
/// 0.1 delta_H / v0; the restitution is then below 0.6 %: 0.5 % at 0.11, 0.06 % at 0.046).
double rebound_time_scale(const ContactLaw& law, double mass, double v0);

/// A contact longer than this many impact time scales T is not integrated: a law whose damping
/// stops the mass inside the contact and whose spring is too weak to push it out in any useful
/// time (an overdamped Kelvin-Voigt law with a negligible K, a Flores law with e -> 0) would creep
/// for up to ~1e300 s. Well-posed contacts last a few T (undamped Hertz: 2.94 T; an overdamped
/// linear Kelvin-Voigt law of damping ratio zeta: ~4 zeta^2 T, so up to zeta ~ 15).
constexpr double kMaxContactDurationT = 1000.0;

/// mass > 0 (kg), v0 > 0 (m/s), dt in [T/1e5, T/10] (s). Throws std::invalid_argument for bad input, for a
/// contact that lasts beyond kMaxContactDurationT time scales or max_steps steps (the message
/// names the law's parameters, mass and dt), or when the force or the result leaves the finite
/// doubles. `poll` (if set) is called every 2^16 steps; it may throw to interrupt the run.
ImpactResult simulate_impact(const ContactLaw& law, double mass, double v0, double dt,
                             bool record = false, long max_steps = 10'000'000,
                             const std::function<void()>& poll = {});

}  // namespace deployfx::contact
