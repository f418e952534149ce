#pragma once
// A forward-mode dual number x + x' eps (eps^2 = 0): evaluating a function on Duals gives its
// value and its directional derivative along the seeded tangent, exactly (to round-off), with no
// step to choose (Griewank & Walther, "Evaluating Derivatives", 2nd ed., SIAM 2008, Ch. 3).
// The multibody engine writes its kinematics once, templated on the scalar, and differentiates
// them by running them on Duals (multibody/newton_matrix.cpp).
#include <Eigen/Core>
#include <cmath>

namespace deployfx {

struct Dual {
  double v = 0;  ///< value
  double d = 0;  ///< directional derivative
  Dual() = default;
  Dual(double value) : v(value) {}  // NOLINT: constants promote implicitly, as in Eigen's AutoDiff
  Dual(double value, double derivative) : v(value), d(derivative) {}

  Dual& operator+=(const Dual& b) { v += b.v, d += b.d; return *this; }
  Dual& operator-=(const Dual& b) { v -= b.v, d -= b.d; return *this; }
  Dual& operator*=(const Dual& b) { d = d * b.v + v * b.d, v *= b.v; return *this; }
  Dual& operator/=(const Dual& b) { d = (d * b.v - v * b.d) / (b.v * b.v), v /= b.v; return *this; }
};

inline Dual operator+(Dual a, const Dual& b) { return a += b; }
inline Dual operator-(Dual a, const Dual& b) { return a -= b; }
inline Dual operator*(Dual a, const Dual& b) { return a *= b; }
inline Dual operator/(Dual a, const Dual& b) { return a /= b; }
inline Dual operator-(const Dual& a) { return {-a.v, -a.d}; }
inline Dual operator+(const Dual& a) { return a; }
inline bool operator<(const Dual& a, const Dual& b) { return a.v < b.v; }
inline bool operator>(const Dual& a, const Dual& b) { return a.v > b.v; }
inline bool operator<=(const Dual& a, const Dual& b) { return a.v <= b.v; }
inline bool operator>=(const Dual& a, const Dual& b) { return a.v >= b.v; }
inline bool operator==(const Dual& a, const Dual& b) { return a.v == b.v && a.d == b.d; }
inline bool operator!=(const Dual& a, const Dual& b) { return !(a == b); }

inline Dual sin(const Dual& a) { return {std::sin(a.v), std::cos(a.v) * a.d}; }
inline Dual cos(const Dual& a) { return {std::cos(a.v), -std::sin(a.v) * a.d}; }
/// sqrt at a > 0 (its derivative is unbounded at 0: callers keep away from it).
inline Dual sqrt(const Dual& a) {
  const double s = std::sqrt(a.v);
  return {s, 0.5 * a.d / s};
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
  enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 1, ReadCost = 2, AddCost = 2, MulCost = 3 };
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
