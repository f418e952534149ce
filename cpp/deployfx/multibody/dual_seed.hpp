#pragma once
// Building Dual-valued Eigen objects from a value and a tangent, and reading the tangent back
// (math/dual.hpp): the seeds and results of the engine's derivative passes.
#include <Eigen/Core>

#include "deployfx/math/dual.hpp"

namespace deployfx::multibody {

template <int R, int C>
Eigen::Matrix<Dual, R, C> dual(const Eigen::Matrix<double, R, C>& value, const Eigen::Matrix<double, R, C>& tangent) {
  Eigen::Matrix<Dual, R, C> x;
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j) x(i, j) = Dual(value(i, j), tangent(i, j));
  return x;
}

template <int R, int C>
Eigen::Matrix<Dual, R, C> dual(const Eigen::Matrix<double, R, C>& value) {
  return value.template cast<Dual>();
}

template <int R, int C>
Eigen::Matrix<double, R, C> tangent(const Eigen::Matrix<Dual, R, C>& x) {
  Eigen::Matrix<double, R, C> t;
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j) t(i, j) = x(i, j).d;
  return t;
}

template <int R, int C>
Eigen::Matrix<double, R, C> values(const Eigen::Matrix<Dual, R, C>& x) {
  Eigen::Matrix<double, R, C> t;
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j) t(i, j) = x(i, j).v;
  return t;
}

}  // namespace deployfx::multibody
