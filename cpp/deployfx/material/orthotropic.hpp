#pragma once
// A transversely isotropic / orthotropic lamina in plane stress with transverse shear
// (Reddy, "Mechanics of Laminated Composite Plates and Shells", 2nd ed., 2004, Sec. 2.4, 3.3).
// Units: moduli in Pa, density in kg/m^3. Axis 1 is the fibre direction.
#include <Eigen/Core>

namespace deployfx::material {

class Orthotropic {
 public:
  /// The largest ratio between two of the five moduli (E1, E2, G12, G13, G23).
  static constexpr double kMaxAnisotropy = 1e6;

  /// Throws std::invalid_argument for moduli or density outside [1e-50, 1e50] (check.hpp), moduli
  /// more than kMaxAnisotropy apart, or a compliance that is not positive definite
  /// (|nu12| >= sqrt(E1/E2)).
  Orthotropic(double E1, double E2, double G12, double G13, double G23, double nu12, double rho);
  /// The isotropic special case, G = E / (2 (1 + nu)); requires -1 < nu < 0.5.
  static Orthotropic isotropic(double E, double nu, double rho);

  double E1() const { return E1_; }
  double E2() const { return E2_; }
  double G12() const { return G12_; }
  double G13() const { return G13_; }
  double G23() const { return G23_; }
  double nu12() const { return nu12_; }
  double nu21() const { return nu12_ * E2_ / E1_; }
  double rho() const { return rho_; }

  /// Plane-stress reduced stiffness in material axes, (sigma1, sigma2, tau12) = Q (eps1, eps2, gamma12).
  Eigen::Matrix3d Q() const;
  /// Engineering-strain rotation (eps_1, eps_2, gamma_12) = T (eps_x, eps_y, gamma_xy) into the
  /// axes of a ply whose fibre lies at theta (rad) from the laminate x axis (Jones 1999,
  /// Sec. 2.6; Reddy 2004, Sec. 2.3).
  static Eigen::Matrix3d strain_rotation(double theta);
  /// In-plane stiffness of a ply rotated by theta (rad, fibre axis from the laminate x axis,
  /// counter-clockwise): Q_bar = T^-1 Q T^-T (Reddy Eq. 2.3.17).
  Eigen::Matrix3d Q_bar(double theta) const;
  /// Transverse shear stiffness of the rotated ply, (tau_xz, tau_yz) = Qs_bar (gamma_xz, gamma_yz)
  /// (Reddy Eq. 2.3.18).
  Eigen::Matrix2d Qs_bar(double theta) const;

 private:
  Orthotropic() = default;
  void validate(const char* who) const;
  double E1_ = 0, E2_ = 0, G12_ = 0, G13_ = 0, G23_ = 0, nu12_ = 0, rho_ = 0;
};

}  // namespace deployfx::material
