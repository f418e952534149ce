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

}  // namespace deployfx::contact
