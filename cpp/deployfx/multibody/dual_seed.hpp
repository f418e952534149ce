#pragma once
// Dual-valued Eigen objects (math/dual.hpp) for the engine's derivative passes: made from a
// value, seeded along one of the Dual's directions, and read back direction by direction.
#include <Eigen/Core>

#include "deployfx/math/dual.hpp"

namespace deployfx::multibody {

/// `value` on Duals with no tangent.
template <int R, int C>
Eigen::Matrix<Dual, R, C> dual(const Eigen::Matrix<double, R, C>& value) {
  return value.template cast<Dual>();
}

/// Sets direction j of x's tangent to `tangent`.
template <int R, int C>
void seed(Eigen::Matrix<Dual, R, C>& x, int j, const Eigen::Matrix<double, R, C>& tangent) {
  for (int r = 0; r < R; ++r)
    for (int c = 0; c < C; ++c) x(r, c).d[j] = tangent(r, c);
}

/// Direction j of x's tangent.
template <int R, int C>
Eigen::Matrix<double, R, C> tangent(const Eigen::Matrix<Dual, R, C>& x, int j) {
  Eigen::Matrix<double, R, C> t;
  for (int r = 0; r < R; ++r)
    for (int c = 0; c < C; ++c) t(r, c) = x(r, c).d[j];
  return t;
}

}  // namespace deployfx::multibody
