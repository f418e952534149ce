#pragma once
// Forward-mode dual numbers with K directions: x + sum_j x'_j eps_j (eps_i eps_j = 0).
// Evaluating a function on Duals gives its value and its directional derivatives along K seeded
// tangents at once, exactly (to round-off), with no step to choose (Griewank & Walther,
// "Evaluating Derivatives", 2nd ed., SIAM 2008, Ch. 3, the vector forward mode). The multibody
// engine writes its kinematics once, templated on the scalar, and differentiates them by running
// them on Duals (multibody/newton_matrix.cpp): K columns of the Newton matrix per pass, the value
// computed once.
#include <Eigen/Core>
#include <cmath>

namespace deployfx {

/// The number of directions a Dual carries: one pass gives this many Newton-matrix columns (the
/// paper's free base and hinge: 7).
constexpr int kDualDirections = 8;

struct Dual {
  static constexpr int K = kDualDirections;
  double v = 0;      ///< value
  double d[K] = {};  ///< directional derivatives
  Dual() = default;
  Dual(double value) : v(value) {}  // NOLINT: constants promote implicitly, as in Eigen's AutoDiff

  Dual& operator+=(const Dual& b) {
    v += b.v;
    for (int j = 0; j < K; ++j) d[j] += b.d[j];
    return *this;
  }
  Dual& operator-=(const Dual& b) {
    v -= b.v;
    for (int j = 0; j < K; ++j) d[j] -= b.d[j];
    return *this;
  }
  Dual& operator*=(const Dual& b) {
    for (int j = 0; j < K; ++j) d[j] = d[j] * b.v + v * b.d[j];
    v *= b.v;
    return *this;
  }
  Dual& operator/=(const Dual& b) {
    const double inv = 1.0 / b.v;
    for (int j = 0; j < K; ++j) d[j] = (d[j] - v * inv * b.d[j]) * inv;
    v *= inv;
    return *this;
  }
};

inline Dual operator+(Dual a, const Dual& b) { return a += b; }
inline Dual operator-(Dual a, const Dual& b) { return a -= b; }
inline Dual operator*(Dual a, const Dual& b) { return a *= b; }
inline Dual operator/(Dual a, const Dual& b) { return a /= b; }
inline Dual operator-(const Dual& a) {
  Dual r;
  r.v = -a.v;
  for (int j = 0; j < Dual::K; ++j) r.d[j] = -a.d[j];
  return r;
}
inline Dual operator+(const Dual& a) { return a; }
// With a constant (a double): no derivative of its own to carry.
inline Dual operator*(Dual a, double b) {
  a.v *= b;
  for (int j = 0; j < Dual::K; ++j) a.d[j] *= b;
  return a;
}
inline Dual operator*(double b, Dual a) { return a * b; }
inline Dual operator/(Dual a, double b) { return a * (1.0 / b); }
inline Dual operator+(Dual a, double b) {
  a.v += b;
  return a;
}
inline Dual operator+(double b, Dual a) { return a + b; }
inline Dual operator-(Dual a, double b) {
  a.v -= b;
  return a;
}
inline Dual operator-(double b, const Dual& a) { return -a + b; }
inline bool operator<(const Dual& a, const Dual& b) { return a.v < b.v; }
inline bool operator>(const Dual& a, const Dual& b) { return a.v > b.v; }
inline bool operator<=(const Dual& a, const Dual& b) { return a.v <= b.v; }
inline bool operator>=(const Dual& a, const Dual& b) { return a.v >= b.v; }

namespace dual_detail {
// f(a) with f(a.v) = value and f'(a.v) = slope: the chain rule on every direction.
inline Dual chain(const Dual& a, double value, double slope) {
  Dual r;
  r.v = value;
  for (int j = 0; j < Dual::K; ++j) r.d[j] = slope * a.d[j];
  return r;
}
}  // namespace dual_detail

inline Dual sin(const Dual& a) { return dual_detail::chain(a, std::sin(a.v), std::cos(a.v)); }
inline Dual cos(const Dual& a) { return dual_detail::chain(a, std::cos(a.v), -std::sin(a.v)); }
/// sqrt at a > 0 (its derivative is unbounded at 0: callers keep away from it).
inline Dual sqrt(const Dual& a) {
  const double s = std::sqrt(a.v);
  return dual_detail::chain(a, s, 0.5 / s);
}

/// The value of a scalar (double or Dual), for branches that depend on it.
inline double value(double x) { return x; }
inline double value(const Dual& x) { return x.v; }

}  // namespace deployfx

namespace Eigen {

template <>
struct NumTraits<deployfx::Dual> : NumTraits<double> {
  using Real = deployfx::Dual;
  using NonInteger = deployfx::Dual;
  using Nested = deployfx::Dual;
  using Literal = deployfx::Dual;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1 + deployfx::kDualDirections,
    AddCost = 1 + deployfx::kDualDirections,
    MulCost = 1 + 2 * deployfx::kDualDirections
  };
};

// A double matrix times a Dual one (the model's constants against the state) yields Duals.
template <typename BinaryOp>
struct ScalarBinaryOpTraits<deployfx::Dual, double, BinaryOp> {
  using ReturnType = deployfx::Dual;
};
template <typename BinaryOp>
struct ScalarBinaryOpTraits<double, deployfx::Dual, BinaryOp> {
  using ReturnType = deployfx::Dual;
};

}  // namespace Eigen
