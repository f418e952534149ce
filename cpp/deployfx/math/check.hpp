#pragma once
// Argument checks that throw (never abort), with messages naming the parameter, the value
// received and the allowed range: "Ply.thickness = -0.001 is out of range: must be > 0 (m)".
// std::invalid_argument becomes Python's ValueError in the bindings.
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace deployfx {

[[noreturn]] inline void throw_out_of_range(const std::string& name, double value,
                                            const std::string& allowed) {
  std::ostringstream s;
  s.precision(10);
  s << name << " = " << value << " is out of range: must be " << allowed;
  throw std::invalid_argument(s.str());
}

/// value must be finite and > 0.
inline void require_positive(const std::string& name, double value, const std::string& unit) {
  if (!(std::isfinite(value) && value > 0.0)) throw_out_of_range(name, value, "> 0 " + unit);
}

/// value must be finite and in the open interval (lo, hi).
inline void require_open_interval(const std::string& name, double value, double lo, double hi,
                                  const std::string& unit = "") {
  if (!(std::isfinite(value) && value > lo && value < hi)) {
    std::ostringstream r;
    r << "in (" << lo << ", " << hi << ")" << (unit.empty() ? "" : " ") << unit;
    throw_out_of_range(name, value, r.str());
  }
}

/// The magnitudes of material and section inputs (SI units) that the shell matrices and their
/// factorisations carry without leaving the doubles: products of a few of them and their squares
/// stay within ~1e+-300 (docs/reliability.md).
constexpr double kMinMagnitude = 1e-50, kMaxMagnitude = 1e50;

/// value must be finite and in [kMinMagnitude, kMaxMagnitude].
inline void require_magnitude(const std::string& name, double value, const std::string& unit) {
  if (!(std::isfinite(value) && value >= kMinMagnitude && value <= kMaxMagnitude)) {
    std::ostringstream r;
    r << "in [" << kMinMagnitude << ", " << kMaxMagnitude << "] " << unit
      << " (beyond, the shell matrices leave the doubles' range)";
    throw_out_of_range(name, value, r.str());
  }
}

/// value must be finite.
inline void require_finite(const std::string& name, double value, const std::string& unit = "") {
  if (!std::isfinite(value)) throw_out_of_range(name, value, "finite " + unit);
}

}  // namespace deployfx
