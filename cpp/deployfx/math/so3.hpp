#pragma once
// Rotations: the skew operator, the rotation about an axis, the exponential map (Rodrigues) and
// its left Jacobian, written once for any scalar (double, or Dual for the derivatives of the
// multibody kinematics: math/dual.hpp). Attitudes are updated by body-frame rotation-vector
// increments (Bruls & Cardona, J. Comput. Nonlinear Dyn. 5, 2010).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "deployfx/math/dual.hpp"

namespace deployfx {

template <class S>
using Vector3 = Eigen::Matrix<S, 3, 1>;
template <class S>
using Matrix3 = Eigen::Matrix<S, 3, 3>;

/// skew(a) b = a x b.
template <class Derived>
Matrix3<typename Derived::Scalar> skew(const Eigen::MatrixBase<Derived>& a) {
  Matrix3<typename Derived::Scalar> S;
  S << 0.0, -a(2), a(1), a(2), 0.0, -a(0), -a(1), a(0), 0.0;
  return S;
}

/// Rot(n, theta) = I + sin(theta) N + (1 - cos(theta)) N^2 for a unit axis n, N = n~ and N2 = N^2
/// given (a hinge's are computed once).
template <class S>
Matrix3<S> rotation_about(const Eigen::Matrix3d& N, const Eigen::Matrix3d& N2, const S& theta) {
  using std::cos;
  using std::sin;
  const S s = sin(theta), c = S(1.0) - cos(theta);
  Matrix3<S> R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = (i == j ? S(1.0) : S(0.0)) + s * N(i, j) + c * N2(i, j);
  return R;
}

/// Rot(n, theta) for a unit axis n.
template <class S>
Matrix3<S> rotation_about(const Eigen::Vector3d& n, const S& theta) {
  const Eigen::Matrix3d N = skew(n);
  return rotation_about<S>(N, N * N, theta);
}

/// A * B for a constant B (the mixed product costs two multiplications an entry on Duals).
template <class S>
Matrix3<S> times_constant(const Matrix3<S>& A, const Eigen::Matrix3d& B) {
  Matrix3<S> C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C(i, j) = A(i, 0) * B(0, j) + A(i, 1) * B(1, j) + A(i, 2) * B(2, j);
  return C;
}

namespace so3_detail {

// exp(psi~) = I + A psi~ + B psi~^2 and its left Jacobian T = I + a psi~ + b psi~^2, with
// (1/f) da/df = a1, (1/f) db/df = b1, f = |psi|. Below f^2 = 0.0025 (f = 0.05) the coefficients
// come from their Taylor series in f^2 (the next term is below 1e-13 of the first; the closed
// forms lose digits to cancellation there), which also keeps sqrt(f^2) and its unbounded
// derivative at 0 out of the Dual evaluation.
template <class S>
struct Coefficients {
  S A, B, a, b, a1, b1;
};

template <class S>
Coefficients<S> coefficients(const S& f2) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  if (value(f2) < 0.0025) {
    const S f4 = f2 * f2, f6 = f4 * f2;
    return {S(1.0) - f2 / 6.0 + f4 / 120.0 - f6 / 5040.0,
            S(0.5) - f2 / 24.0 + f4 / 720.0 - f6 / 40320.0,
            S(0.5) - f2 / 24.0 + f4 / 720.0 - f6 / 40320.0,
            S(1.0 / 6.0) - f2 / 120.0 + f4 / 5040.0 - f6 / 362880.0,
            S(-1.0 / 12.0) + f2 / 180.0 - f4 / 6720.0 + f6 / 453600.0,
            S(-1.0 / 60.0) + f2 / 1260.0 - f4 / 60480.0 + f6 / 4989600.0};
  }
  const S f = sqrt(f2), s = sin(f), c = cos(f), f3 = f2 * f, f4 = f2 * f2;
  const S a = (S(1.0) - c) / f2, b = (f - s) / f3;
  return {s / f, a, a, b, s / f3 - 2.0 * (S(1.0) - c) / f4, (S(1.0) - c) / f4 - 3.0 * (f - s) / (f4 * f)};
}

}  // namespace so3_detail

/// exp(psi~) (Rodrigues).
template <class S>
Matrix3<S> so3_exp(const Vector3<S>& psi) {
  const auto k = so3_detail::coefficients<S>(psi.squaredNorm());
  const Matrix3<S> P = skew(psi);
  return Matrix3<S>::Identity() + k.A * P + k.B * (P * P);
}

/// T(psi), the left Jacobian of SO(3): exp(psi~)' exp(psi~)^T = (T(psi) psi')~ (Bauchau,
/// "Flexible Multibody Dynamics", 2011, Ch. 13, the tangent tensor).
template <class S>
Matrix3<S> so3_left_jacobian(const Vector3<S>& psi) {
  const auto k = so3_detail::coefficients<S>(psi.squaredNorm());
  const Matrix3<S> P = skew(psi);
  return Matrix3<S>::Identity() + k.a * P + k.b * (P * P);
}

/// T'(psi, psi') psi', the rate of T along psi' applied to psi':
/// d/dt (a psi~ + b psi~^2) psi' = a' psi x psi' + b' psi x (psi x psi') + b psi' x (psi x psi'),
/// a' = a1 (psi . psi'), b' = b1 (psi . psi') (psi'~ psi' = 0 drops the other terms).
template <class S>
Vector3<S> so3_left_jacobian_rate(const Vector3<S>& psi, const Vector3<S>& psi_rate) {
  const auto k = so3_detail::coefficients<S>(psi.squaredNorm());
  const S rate = psi.dot(psi_rate);
  const Vector3<S> c = psi.cross(psi_rate);
  return k.a1 * rate * c + k.b1 * rate * psi.cross(c) + k.b * psi_rate.cross(c);
}

/// The unit quaternion of the rotation vector psi (angle |psi| about psi / |psi|).
inline Eigen::Quaterniond quaternion_exp(const Eigen::Vector3d& psi) {
  const double angle = psi.norm();
  if (angle < 1e-12) return Eigen::Quaterniond(1.0, 0.5 * psi.x(), 0.5 * psi.y(), 0.5 * psi.z()).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, psi / angle));
}

}  // namespace deployfx
