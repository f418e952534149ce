#include "deployfx/contact/unclamped_force.hpp"

#include <algorithm>
#include <cmath>

namespace deployfx::contact {

ContactForce unclamped_force(const ContactLaw& law, double delta, double delta_dot, double v0) {
  const double a = std::abs(delta), sgn = delta < 0 ? -1.0 : 1.0;
  const double p = law.K() * std::pow(a, law.n()), dp = law.n() * law.K() * std::pow(a, law.n() - 1);
  ContactForce f;
  if (law.kind() == ContactLaw::Kind::kKelvinVoigtHertz) {
    f.F = sgn * p + law.D() * delta_dot;
    f.dF_ddelta = dp;
    f.dF_ddelta_dot = law.D();
    return f;
  }
  const double c = law.hysteresis_factor() / std::max(v0, 1e-9), m = 1 + c * delta_dot;
  if (delta >= 0) {
    f.F = p * m;
    f.dF_ddelta = dp * m;
    f.dF_ddelta_dot = p * c;
  } else {
    const double sm = m < 0 ? -1.0 : 1.0;
    f.F = -p * std::abs(m);
    f.dF_ddelta = dp * std::abs(m);
    f.dF_ddelta_dot = -p * sm * c;
  }
  return f;
}

double wall_event(const ContactLaw& law, bool closed, bool inside, double v0, double delta, double delta_dot) {
  if (closed) {
    const double F = unclamped_force(law, delta, delta_dot, v0).F;
    if (law.kind() == ContactLaw::Kind::kKelvinVoigtHertz && law.D() > 0) return F;
    return std::copysign(std::pow(std::abs(F) / law.K(), 1.0 / law.n()), F);
  }
  if (!inside || delta <= 0) return -delta;
  return -unclamped_force(law, delta, delta_dot, std::max(v0, std::abs(delta_dot))).F;
}

}  // namespace deployfx::contact
