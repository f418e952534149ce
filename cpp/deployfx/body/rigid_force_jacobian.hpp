#pragma once
// The derivatives of a rigid body's inertial forces (rigid_inertia.hpp: Newton-Euler about its
// frame F's origin) with respect to F's motion: with s = m c and J = J_O,
//   F = m a - s~ al + w x (w x s),   M = s~ a + J al + w x (J w),
// d(w x (w x s))/dw = (w.s) I + w s^T - 2 s w^T and d(w x (J w))/dw = w~ J - (J w)~.
#include <Eigen/Core>

#include "deployfx/body/rigid_inertia.hpp"
#include "deployfx/math/so3.hpp"

namespace deployfx::body {

/// d(F, M)/d(a, al, w) for angular velocity w (F axes), (6 x 9): columns a, al, w.
inline Eigen::Matrix<double, 6, 9> rigid_force_jacobian(const RigidInertia& b, const Eigen::Vector3d& w) {
  const Eigen::Vector3d s = b.first_moment();
  const Eigen::Matrix3d J = b.inertia_origin(), I3 = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 6, 9> D;
  D << b.mass * I3, -skew(s), w.dot(s) * I3 + w * s.transpose() - 2.0 * s * w.transpose(),
      skew(s), J, skew(w) * J - skew(J * w);
  return D;
}

}  // namespace deployfx::body
