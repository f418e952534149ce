#pragma once
// Classical lamination theory with first-order transverse shear (Reddy 2004, Sec. 3.3-3.4):
//   (N, M) = [A B; B D] (eps0, kappa),  Q = As gamma,
// with z measured from the laminate mid-plane, plies stacked from z = -h/2 (ply 0, bottom) up.
#include <Eigen/Core>
#include <vector>

#include "deployfx/material/orthotropic.hpp"

namespace deployfx::material {

struct Ply {
  Orthotropic material;
  double thickness;  ///< m, > 0
  double angle_deg;  ///< fibre axis from the laminate x axis, counter-clockwise, degrees
};

class Laminate {
 public:
  /// Transverse shear correction factor k applied to As = k sum(Qs_bar t): 5/6, the
  /// energy-equivalent value for a homogeneous section (Reissner 1945; Reddy 2004 Eq. 3.4.29).
  static constexpr double kShearCorrection = 5.0 / 6.0;

  /// Throws std::invalid_argument for an empty lay-up, a thickness outside [1e-50, 1e50] m
  /// (check.hpp; with the materials' range, A, B, D then stay finite and non-zero) or a
  /// non-finite angle.
  explicit Laminate(std::vector<Ply> plies);

  const std::vector<Ply>& plies() const { return plies_; }
  double thickness() const { return h_; }             ///< m
  const Eigen::Matrix3d& A() const { return A_; }     ///< N/m
  const Eigen::Matrix3d& B() const { return B_; }     ///< N
  const Eigen::Matrix3d& D() const { return D_; }     ///< N m
  const Eigen::Matrix2d& As() const { return As_; }   ///< N/m, (Q_xz, Q_yz) = As (gamma_xz, gamma_yz)
  double I0() const { return I0_; }  ///< mass per area, kg/m^2
  double I1() const { return I1_; }  ///< first mass moment per area about the mid-plane, kg/m
  double I2() const { return I2_; }  ///< rotary inertia per area about the mid-plane, kg
  /// Upper edge z of each ply (size plies+1, from -h/2 to h/2), m.
  const std::vector<double>& z() const { return z_; }

 private:
  std::vector<Ply> plies_;
  std::vector<double> z_;
  double h_ = 0, I0_ = 0, I1_ = 0, I2_ = 0;
  Eigen::Matrix3d A_, B_, D_;
  Eigen::Matrix2d As_;
};

}  // namespace deployfx::material
