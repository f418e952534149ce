#include "deployfx/material/orthotropic.hpp"

#include <cmath>
#include <string>

#include "deployfx/math/check.hpp"

namespace deployfx::material {

Orthotropic::Orthotropic(double E1, double E2, double G12, double G13, double G23, double nu12,
                         double rho)
    : E1_(E1), E2_(E2), G12_(G12), G13_(G13), G23_(G23), nu12_(nu12), rho_(rho) {
  validate("Orthotropic");
}

Orthotropic Orthotropic::isotropic(double E, double nu, double rho) {
  require_positive("Isotropic.E", E, "(Pa)");
  require_open_interval("Isotropic.nu", nu, -1.0, 0.5);
  require_positive("Isotropic.rho", rho, "(kg/m^3)");
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
  require_positive(w + ".E1", E1_, "(Pa)");
  require_positive(w + ".E2", E2_, "(Pa)");
  require_positive(w + ".G12", G12_, "(Pa)");
  require_positive(w + ".G13", G13_, "(Pa)");
  require_positive(w + ".G23", G23_, "(Pa)");
  require_positive(w + ".rho", rho_, "(kg/m^3)");
  // Positive-definite plane-stress compliance: 1 - nu12 nu21 > 0, i.e. |nu12| < sqrt(E1/E2)
  // (Jones, "Mechanics of Composite Materials", 1999, Sec. 2.4.1).
  const double bound = std::sqrt(E1_ / E2_);
  require_open_interval(w + ".nu12", nu12_, -bound, bound,
                        "(= +-sqrt(E1/E2), for a positive-definite compliance)");
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
