#include "deployfx/contact/force_law.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "deployfx/math/check.hpp"

namespace deployfx::contact {
namespace {

constexpr double kMax = std::numeric_limits<double>::max();

// Saturates at +-DBL_MAX. Applied to the inputs and after every operation that can overflow, it
// keeps every intermediate finite, so no inf - inf or 0 * inf can produce a NaN.
double sat(double x) { return std::clamp(x, -kMax, kMax); }

double hysteresis(ContactLaw::Kind kind, double e) {
  switch (kind) {
    case ContactLaw::Kind::kHuntCrossley: return 1.5 * (1.0 - e);
    case ContactLaw::Kind::kLankaraniNikravesh: return 0.75 * (1.0 - e * e);
    case ContactLaw::Kind::kFlores: return 1.6 * (1.0 - e) / e;
    case ContactLaw::Kind::kKelvinVoigtHertz: break;
  }
  return 0.0;
}

}  // namespace

const char* to_string(ContactLaw::Kind kind) {
  switch (kind) {
    case ContactLaw::Kind::kKelvinVoigtHertz: return "kelvin-voigt-hertz";
    case ContactLaw::Kind::kHuntCrossley: return "hunt-crossley";
    case ContactLaw::Kind::kLankaraniNikravesh: return "lankarani-nikravesh";
    case ContactLaw::Kind::kFlores: return "flores";
  }
  return "unknown";
}

ContactLaw::ContactLaw(Kind kind, double K, double n, double D, double e)
    : kind_(kind), K_(K), n_(n), D_(D), e_(e) {
  require_positive("contact.K", K, "(N/m^n)");
  if (!(std::isfinite(n) && n >= 1.0)) throw_out_of_range("contact.n", n, ">= 1");
  const std::string law = to_string(kind);
  if (kind == Kind::kKelvinVoigtHertz) {
    if (!(std::isfinite(D) && D >= 0.0)) throw_out_of_range("contact.D", D, ">= 0 (N s/m)");
    if (e != 1.0) throw_out_of_range("contact.e", e, "1 (unused by " + law + ", set D instead)");
  } else {
    if (!(std::isfinite(e) && e > 0.0 && e <= 1.0)) throw_out_of_range("contact.e", e, "in (0, 1]");
    if (D != 0.0) throw_out_of_range("contact.D", D, "0 (unused by " + law + ", set e instead)");
  }
  c_ = hysteresis(kind, e);
}

ContactForce ContactLaw::evaluate(double delta, double delta_dot, double v0) const {
  if (std::isnan(delta) || std::isnan(delta_dot)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan, nan};
  }
  delta = sat(delta);
  delta_dot = sat(delta_dot);
  if (delta <= 0.0) return {};
  // Elastic part K delta^n and its slope n K delta^(n-1) (n >= 1: bounded as delta -> 0).
  const double p = sat(K_ * std::pow(delta, n_));
  const double dp = sat(n_ * sat(K_ * std::pow(delta, n_ - 1.0)));
  if (kind_ == Kind::kKelvinVoigtHertz) {
    const double F = sat(p + sat(D_ * delta_dot));
    if (!(F > 0.0)) return {};  // the dashpot would pull: released
    return {F, dp, D_};
  }
  require_positive("contact.v0", v0, "(m/s, approach speed at contact onset)");
  const double d = sat(c_ / v0);                  // chi / K (s/m)
  const double g = sat(1.0 + sat(d * delta_dot));  // damping factor 1 + chi delta_dot / K
  if (!(g > 0.0)) return {};
  return {sat(p * g), sat(dp * g), sat(p * d)};
}

}  // namespace deployfx::contact
