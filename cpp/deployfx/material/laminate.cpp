#include "deployfx/material/laminate.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "deployfx/math/check.hpp"

namespace deployfx::material {

Laminate::Laminate(std::vector<Ply> plies) : plies_(std::move(plies)) {
  if (plies_.empty())
    throw std::invalid_argument("Laminate.plies is empty: a laminate needs at least one ply");
  for (std::size_t k = 0; k < plies_.size(); ++k) {
    const std::string p = "Laminate.plies[" + std::to_string(k) + "]";
    require_magnitude(p + ".thickness", plies_[k].thickness, "(m)");
    require_finite(p + ".angle_deg", plies_[k].angle_deg, "(degrees)");
    h_ += plies_[k].thickness;
  }
  A_.setZero();
  B_.setZero();
  D_.setZero();
  As_.setZero();
  z_.assign(1, -0.5 * h_);
  for (const Ply& ply : plies_) {
    const double z0 = z_.back(), z1 = z0 + ply.thickness;
    z_.push_back(z1);
    // Reduced to one turn first (fmod is exact): angle_deg * pi overflows beyond 5.7e307 deg.
    const double theta = std::fmod(ply.angle_deg, 360.0) * M_PI / 180.0;
    const Eigen::Matrix3d Qb = ply.material.Q_bar(theta);
    const double d1 = z1 - z0, d2 = (z1 * z1 - z0 * z0) / 2, d3 = (z1 * z1 * z1 - z0 * z0 * z0) / 3;
    // Reddy 2004 Eq. 3.3.17 and 3.4.29.
    A_ += Qb * d1;
    B_ += Qb * d2;
    D_ += Qb * d3;
    As_ += kShearCorrection * ply.material.Qs_bar(theta) * d1;
    const double rho = ply.material.rho();
    I0_ += rho * d1;
    I1_ += rho * d2;
    I2_ += rho * d3;
  }
}

}  // namespace deployfx::material
