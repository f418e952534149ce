#include "deployfx/contact/impact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "deployfx/math/check.hpp"

namespace deployfx::contact {
namespace {

struct State {
  double x, v;  // delta (m), delta_dot (m/s)
};

class Impact {
 public:
  Impact(const ContactLaw& law, double mass, double v0) : law_(law), m_(mass), v0_(v0) {}

  // At onset (x = 0, v > 0) the force is its limit from inside the contact, D v0 for
  // Kelvin-Voigt: the law itself gives 0 at delta = 0, which would cost RK4 an O(dt) error.
  double force(const State& s) const {
    const double x = s.x == 0.0 && s.v > 0.0 ? std::numeric_limits<double>::denorm_min() : s.x;
    return law_.evaluate(x, s.v, v0_).F;
  }

  // One classical Runge-Kutta step of x' = v, v' = -F(x, v) / m.
  State rk4(const State& s, double h) const {
    const auto a = [&](double x, double v) { return -force({x, v}) / m_; };
    const double k1x = s.v, k1v = a(s.x, s.v);
    const double k2x = s.v + 0.5 * h * k1v, k2v = a(s.x + 0.5 * h * k1x, k2x);
    const double k3x = s.v + 0.5 * h * k2v, k3v = a(s.x + 0.5 * h * k2x, k3x);
    const double k4x = s.v + h * k3v, k4v = a(s.x + h * k3x, k4x);
    return {s.x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
            s.v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)};
  }

  // The largest substep tau in (0, h] after which `holds` is still true, by bisection to
  // round-off; `holds` is true just after s and false after the full step h.
  template <class Pred>
  double locate(const State& s, double h, Pred holds) const {
    double lo = 0.0, hi = h;
    for (;;) {
      const double mid = 0.5 * (lo + hi);
      if (!(mid > lo && mid < hi)) return lo;
      (holds(rk4(s, mid)) ? lo : hi) = mid;
    }
  }

 private:
  const ContactLaw& law_;
  double m_, v0_;
};

}  // namespace

double impact_time_scale(const ContactLaw& law, double mass, double v0) {
  require_positive("impact.mass", mass, "(kg)");
  require_positive("impact.v0", v0, "(m/s)");
  // The Hunt-Crossley family's exact maximum penetration (energy balance over compression,
  // docs/research/engine-references.md Sec. 4): K delta^(n+1) / (n+1) = m v0^2 q(c),
  // q(c) = (c - ln(1 + c)) / c^2 -> 1/2 as c -> 0 (undamped Hertz).
  const double c = law.hysteresis_factor();
  const double q = c < 1e-3 ? 0.5 - c / 3.0 + c * c / 4.0 : (c - std::log1p(c)) / (c * c);
  // In logarithms: m v0^2 / K alone can leave the doubles when T itself does not.
  const double n1 = law.n() + 1.0;
  double T = std::exp((std::log(n1 * q) + std::log(mass) + 2.0 * std::log(v0) - std::log(law.K())) / n1 -
                      std::log(v0));
  if (law.D() > 0.0) T = std::min(T, mass / law.D());
  // A step of T / 1e4 must still be a normal double.
  if (!(std::isfinite(T) && T / 1e4 >= std::numeric_limits<double>::min())) {
    std::ostringstream m;
    m.precision(6);
    m << "impact: the contact time scale T = " << T << " s is outside the doubles' range for "
      << "impact.mass = " << mass << " kg, impact.v0 = " << v0 << " m/s, contact.K = " << law.K()
      << ", contact.n = " << law.n() << ", contact.D = " << law.D();
    throw std::invalid_argument(m.str());
  }
  return T;
}

double rebound_time_scale(const ContactLaw& law, double mass, double v0) {
  const double T = impact_time_scale(law, mass, v0);
  if (!(law.D() > 0.0)) return T;
  const ContactLaw hertz(ContactLaw::Kind::kKelvinVoigtHertz, law.K(), law.n(), 0.0);
  return mass / law.D() < 0.1 * impact_time_scale(hertz, mass, v0) ? 0.0 : T;
}

ImpactResult simulate_impact(const ContactLaw& law, double mass, double v0, double dt,
                             bool record, long max_steps, const std::function<void()>& poll) {
  const double T = impact_time_scale(law, mass, v0);
  require_positive("impact.dt", dt, "(s)");
  if (dt > 0.1 * T || dt < 1e-5 * T) {
    // Below T/1e5, RK4's error (dt/T)^2.5 <= 3e-13 is under the round-off its 1e5+ steps add.
    std::ostringstream r;
    r << "in [T/1e5, T/10] = [" << 1e-5 * T << ", " << 0.1 * T
      << "] s (T = impact time scale: the contact needs many steps, and smaller steps only add "
         "round-off)";
    throw_out_of_range("impact.dt", dt, r.str());
  }
  if (max_steps < 1) throw_out_of_range("impact.max_steps", double(max_steps), ">= 1");

  const Impact impact(law, mass, v0);
  const auto in_contact = [&](const State& s) { return impact.force(s) > 0.0; };
  ImpactResult r;
  State s{0.0, v0};
  double t = 0.0, f = impact.force(s);
  // Step-end force samples f_{k-2}, f_{k-1} for the parabolic refinement of the peak.
  double f2 = 0.0, f1 = f;
  r.peak_force = f;
  const auto push = [&](const State& q, double fq) {
    if (!record) return;
    r.t.push_back(t);
    r.delta.push_back(q.x);
    r.delta_dot.push_back(q.v);
    r.force.push_back(fq);
  };
  push(s, f);
  const double t_max = kMaxContactDurationT * T;
  for (;;) {
    if (r.steps >= max_steps || t > t_max) {
      std::ostringstream m;
      m.precision(6);
      m << "impact: the mass has not separated after " << r.steps << " steps, t = " << t
        << " s = " << t / T << " T (T = " << T << " s, the impact time scale): ";
      if (t > t_max)
        m << "the law's damping (contact.D = " << law.D() << " N s/m, contact.e = " << law.e()
          << ") stops the mass inside the contact and its spring (contact.K = " << law.K()
          << ") is too weak to push it out; contacts longer than " << kMaxContactDurationT
          << " T are not integrated";
      else
        m << "impact.dt = " << dt << " s is too small for max_steps = " << max_steps;
      throw std::invalid_argument(m.str());
    }
    if (poll && (r.steps & 0xFFFF) == 0xFFFF) poll();
    double h = dt;
    State next = impact.rk4(s, h);
    const bool separated = !in_contact(next);
    if (separated) {
      h = impact.locate(s, dt, in_contact);
      next = impact.rk4(s, h);
    }
    if (s.v > 0.0 && next.v <= 0.0) {  // turning point: delta' = 0 at maximum penetration
      const double tm = impact.locate(s, h, [](const State& q) { return q.v > 0.0; });
      r.max_penetration = std::max(r.max_penetration, impact.rk4(s, tm).x);
    }
    r.max_penetration = std::max(r.max_penetration, next.x);
    f = impact.force(next);
    // An interior maximum f1 of three equally spaced samples: the vertex of their parabola.
    // The vertex lies f1 + d^2 / (8 c) with |d| = |f - f2| <= c = 2 f1 - f2 - f: the rise is at
    // most |d| / 8, computed as d (d / 8c) so that it cannot overflow.
    const double curvature = (f1 - f2) + (f1 - f), d = f - f2;
    if (r.steps > 0 && !separated && f1 >= f2 && f1 >= f && curvature > 0.0)
      r.peak_force = std::max(r.peak_force, f1 + d * (d / (8.0 * curvature)));
    r.peak_force = std::max(r.peak_force, f);
    if (!(r.peak_force < std::numeric_limits<double>::max())) {
      std::ostringstream m;
      m << "impact: the contact force reaches the largest double (" << r.peak_force
        << " N): the law (contact.K = " << law.K() << ", contact.n = " << law.n()
        << "), impact.mass = " << mass << " kg and impact.v0 = " << v0
        << " m/s give a force beyond what can be computed";
      throw std::invalid_argument(m.str());
    }
    f2 = f1;
    f1 = f;
    t += h;
    s = next;
    ++r.steps;
    push(s, f);
    if (separated) break;
  }
  r.restitution = -s.v / v0;
  r.contact_duration = t;
  r.energy_lost = 0.5 * mass * ((v0 - s.v) * (v0 + s.v));
  if (!std::isfinite(r.energy_lost)) {
    std::ostringstream m;
    m << "impact: the energy m v0^2 / 2 overflows the doubles (impact.mass = " << mass
      << " kg, impact.v0 = " << v0 << " m/s)";
    throw std::invalid_argument(m.str());
  }
  return r;
}

}  // namespace deployfx::contact
