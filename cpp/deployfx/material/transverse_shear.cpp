#include "deployfx/material/transverse_shear.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

#include "deployfx/math/check.hpp"

namespace deployfx::material {

std::vector<Eigen::Matrix2d> equilibrium_shear(const Laminate& laminate, const std::vector<double>& z) {
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  Eigen::Matrix<double, 6, 6> ABD;
  ABD << laminate.A(), laminate.B(), laminate.B(), laminate.D();
  const Eigen::PartialPivLU<Eigen::Matrix<double, 6, 6>> lu(ABD);
  // Strain gradients (eps0, kappa),x per unit Q_x (M_x,x = Q_x) and (eps0, kappa),y per unit Q_y.
  const Vector6d gx = lu.solve(Vector6d::Unit(3)), gy = lu.solve(Vector6d::Unit(4));
  const std::vector<double>& zk = laminate.z();
  const double h = laminate.thickness();

  // H gained across [z0, z1] inside ply k: minus the integral of the stress gradients,
  // int Q_bar (a + z b) dz = Q_bar (a (z1 - z0) + b (z1^2 - z0^2) / 2).
  auto increment = [&](std::size_t k, double z0, double z1) {
    const Ply& ply = laminate.plies()[k];
    const Eigen::Matrix3d Qb = ply.material.Q_bar(ply.angle_deg * M_PI / 180.0);
    const double d1 = z1 - z0, d2 = 0.5 * (z1 * z1 - z0 * z0);
    const Eigen::Vector3d sx = Qb * (gx.head<3>() * d1 + gx.tail<3>() * d2);  // (s_x, s_y, t_xy),x
    const Eigen::Vector3d sy = Qb * (gy.head<3>() * d1 + gy.tail<3>() * d2);  // the same, ,y
    Eigen::Matrix2d dH;
    dH << -sx(0), -sy(2),  // tau_xz,z = -(sigma_x,x + tau_xy,y)
        -sx(2), -sy(1);    // tau_yz,z = -(tau_xy,x + sigma_y,y)
    return dH;
  };

  std::vector<Eigen::Matrix2d> H;
  H.reserve(z.size());
  for (std::size_t q = 0; q < z.size(); ++q) {
    const double zq = z[q];
    if (!(std::abs(zq) <= 0.5 * h * (1 + 1e-12)))
      throw_out_of_range("equilibrium_shear.z[" + std::to_string(q) + "]", zq,
                         "in [-h/2, h/2] = [" + std::to_string(-0.5 * h) + ", " +
                             std::to_string(0.5 * h) + "] (m)");
    Eigen::Matrix2d Hq = Eigen::Matrix2d::Zero();
    for (std::size_t k = 0; k + 1 < zk.size() && zk[k] < zq; ++k)
      Hq += increment(k, zk[k], std::min(zk[k + 1], zq));
    H.push_back(Hq);
  }
  return H;
}

}  // namespace deployfx::material
