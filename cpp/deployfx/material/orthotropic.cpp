#include "deployfx/material/orthotropic.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "deployfx/math/check.hpp"

namespace deployfx::material {

Orthotropic::Orthotropic(double E1, double E2, double G12, double G13, double G23, double nu12,
                         double rho)
    : E1_(E1), E2_(E2), G12_(G12), G13_(G13), G23_(G23), nu12_(nu12), rho_(rho) {
  validate("Orthotropic");
}

Orthotropic Orthotropic::isotropic(double E, double nu, double rho) {
  require_magnitude("Isotropic.E", E, "(Pa)");
  // nu -> -1 would make G = E / (2 (1 + nu)) exceed E by more than kMaxAnisotropy.
  require_open_interval("Isotropic.nu", nu, -1.0 + 1.0 / kMaxAnisotropy, 0.5);
  require_magnitude("Isotropic.rho", rho, "(kg/m^3)");
  const double G = E / (2.0 * (1.0 + nu));
  Orthotropic m;
  m.E1_ = m.E2_ = E;
  m.G12_ = m.G13_ = m.G23_ = G;
  m.nu12_ = nu;
  m.rho_ = rho;
  m.validate("Isotropic");
  return m;
}

void Orthotropic::validate(const char* who) const {
  const std::string w(who);
  require_magnitude(w + ".E1", E1_, "(Pa)");
  require_magnitude(w + ".E2", E2_, "(Pa)");
  require_magnitude(w + ".G12", G12_, "(Pa)");
  require_magnitude(w + ".G13", G13_, "(Pa)");
  require_magnitude(w + ".G23", G23_, "(Pa)");
  require_magnitude(w + ".rho", rho_, "(kg/m^3)");
  // The stiffness of one element mixes the five moduli: beyond a ratio of kMaxAnisotropy its
  // factorisation loses every digit of the weakest (G12 = 1e308 against E2 = 1e10 crashed the
  // modal solver). Real laminae stay below ~300 (pitch-carbon E1 / G23).
  const double moduli[] = {E1_, E2_, G12_, G13_, G23_};
  const char* names[] = {"E1", "E2", "G12", "G13", "G23"};
  int lo = 0, hi = 0;
  for (int i = 1; i < 5; ++i) {
    if (moduli[i] < moduli[lo]) lo = i;
    if (moduli[i] > moduli[hi]) hi = i;
  }
  if (moduli[hi] > kMaxAnisotropy * moduli[lo]) {
    std::ostringstream r;
    r << "<= " << kMaxAnisotropy << " " << w << "." << names[lo] << " = "
      << kMaxAnisotropy * moduli[lo] << " (Pa): the moduli must lie within a factor "
      << kMaxAnisotropy << " of each other";
    throw_out_of_range(w + "." + names[hi], moduli[hi], r.str());
  }
  // Positive-definite plane-stress compliance: 1 - nu12 nu21 > 0, i.e. |nu12| < sqrt(E1/E2)
  // (Jones, "Mechanics of Composite Materials", 1999, Sec. 2.4.1); kept >= 1 / kMaxAnisotropy, as
  // Q = E / (1 - nu12 nu21) would otherwise outgrow the moduli by more than kMaxAnisotropy.
  const double bound = std::sqrt((1.0 - 1.0 / kMaxAnisotropy) * E1_ / E2_);
  require_open_interval(w + ".nu12", nu12_, -bound, bound,
                        "(~ +-sqrt(E1/E2): 1 - nu12 nu21 >= 1e-6, a positive-definite compliance)");
}

Eigen::Matrix3d Orthotropic::Q() const {
  const double d = 1.0 - nu12_ * nu21();
  Eigen::Matrix3d q = Eigen::Matrix3d::Zero();
  q(0, 0) = E1_ / d;
  q(1, 1) = E2_ / d;
  q(0, 1) = q(1, 0) = nu12_ * E2_ / d;
  q(2, 2) = G12_;
  return q;
}

Eigen::Matrix3d Orthotropic::strain_rotation(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix3d T;
  T << c * c, s * s, c * s,  //
      s * s, c * c, -c * s,  //
      -2 * c * s, 2 * c * s, c * c - s * s;
  return T;
}

Eigen::Matrix3d Orthotropic::Q_bar(double theta) const {
  // Engineering-strain transformation: eps_material = T_eps eps_laminate; energy invariance gives
  // Q_bar = T_eps^T Q T_eps (equivalent to Reddy Eq. 2.3.17).
  const Eigen::Matrix3d T = strain_rotation(theta);
  return T.transpose() * Q() * T;
}

Eigen::Matrix2d Orthotropic::Qs_bar(double theta) const {
  // (gamma_13, gamma_23) = R (gamma_xz, gamma_yz) with R the in-plane rotation.
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix2d R;
  R << c, s, -s, c;
  Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
  q(0, 0) = G13_;
  q(1, 1) = G23_;
  return R.transpose() * q * R;
}

}  // namespace deployfx::material
