#pragma once
// The inertia of a rigid body seen from a frame F it is fixed in (Newton-Euler about F's origin,
// Shabana, "Dynamics of Multibody Systems", 4th ed., Sec. 3.7): mass m, centre of mass c and
// inertia I_c about it, all in F axes. With F's origin acceleration a, angular velocity w and
// angular acceleration al (F axes), the inertial force and moment about F's origin are
//   F = m (a + al x c + w x (w x c)),   M = m c x a + J_O al + w x (J_O w),
// J_O = I_c + m (|c|^2 I - c c^T) (parallel axes).
#include <Eigen/Core>

#include "deployfx/math/so3.hpp"

namespace deployfx::body {

struct RigidInertia {
  double mass = 0;                                           ///< kg
  Eigen::Vector3d com = Eigen::Vector3d::Zero();             ///< m, in F
  Eigen::Matrix3d inertia_com = Eigen::Matrix3d::Zero();     ///< kg m^2, about com, F axes

  Eigen::Vector3d first_moment() const { return mass * com; }  ///< kg m
  /// J_O about F's origin, kg m^2.
  Eigen::Matrix3d inertia_origin() const {
    return inertia_com + mass * (com.squaredNorm() * Eigen::Matrix3d::Identity() - com * com.transpose());
  }
  /// The 6 x 6 spatial inertia about F's origin acting on (a, al).
  Eigen::Matrix<double, 6, 6> spatial() const {
    Eigen::Matrix<double, 6, 6> M;
    const Eigen::Matrix3d S = skew(first_moment());
    M << mass * Eigen::Matrix3d::Identity(), -S, S, inertia_origin();
    return M;
  }
  /// (F, M) stacked, see the header.
  Eigen::Matrix<double, 6, 1> inertial_forces(const Eigen::Vector3d& a, const Eigen::Vector3d& al,
                                              const Eigen::Vector3d& w) const {
    const Eigen::Vector3d s = first_moment();
    const Eigen::Matrix3d J = inertia_origin();
    Eigen::Matrix<double, 6, 1> f;
    f.head<3>() = mass * a + al.cross(s) + w.cross(w.cross(s));
    f.tail<3>() = s.cross(a) + J * al + w.cross(J * w);
    return f;
  }
  /// Linear momentum and angular momentum about F's origin (F axes) for origin velocity V, rate w.
  Eigen::Matrix<double, 6, 1> momentum(const Eigen::Vector3d& V, const Eigen::Vector3d& w) const {
    Eigen::Matrix<double, 6, 1> p;
    p.head<3>() = mass * V + w.cross(first_moment());
    p.tail<3>() = first_moment().cross(V) + inertia_origin() * w;
    return p;
  }
  double kinetic_energy(const Eigen::Vector3d& V, const Eigen::Vector3d& w) const {
    return 0.5 * mass * V.squaredNorm() + V.dot(w.cross(first_moment())) + 0.5 * w.dot(inertia_origin() * w);
  }
};

}  // namespace deployfx::body
