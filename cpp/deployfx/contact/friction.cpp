#include "deployfx/contact/friction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "deployfx/math/check.hpp"

namespace deployfx::contact {
namespace {

constexpr double kMax = std::numeric_limits<double>::max();
double sat(double x) { return std::clamp(x, -kMax, kMax); }  // see force_law.cpp

}  // namespace

CoulombFriction::CoulombFriction(double mu, double v_reg) : mu_(mu), v_reg_(v_reg) {
  if (!(std::isfinite(mu) && mu >= 0.0)) throw_out_of_range("friction.mu", mu, ">= 0");
  require_positive("friction.v_reg", v_reg, "(m/s)");
}

FrictionForce CoulombFriction::evaluate(double v_t, double F_n) const {
  if (std::isnan(v_t) || std::isnan(F_n)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan, nan};
  }
  if (!(F_n > 0.0)) return {};  // no normal force, no friction
  const double s = std::tanh(sat(v_t) / v_reg_);  // tanh(+-inf) = +-1
  const double ds_dv = sat((1.0 - s * s) / v_reg_);  // 1/s
  const double muN = sat(mu_ * sat(F_n));
  return {-muN * s, -sat(muN * ds_dv), -mu_ * s};
}

}  // namespace deployfx::contact
