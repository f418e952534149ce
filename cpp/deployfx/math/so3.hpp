#pragma once
// Rotations: the skew operator and the exponential map (Rodrigues), used to update attitudes by
// body-frame rotation-vector increments (Bruls & Cardona, J. Comput. Nonlinear Dyn. 5, 2010).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace deployfx {

/// skew(a) b = a x b.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d S;
  S << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return S;
}

/// The unit quaternion of the rotation vector psi (angle |psi| about psi / |psi|).
inline Eigen::Quaterniond quaternion_exp(const Eigen::Vector3d& psi) {
  const double angle = psi.norm();
  if (angle < 1e-12) return Eigen::Quaterniond(1.0, 0.5 * psi.x(), 0.5 * psi.y(), 0.5 * psi.z()).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, psi / angle));
}

}  // namespace deployfx
