#pragma once
// Ply strength allowables and failure indices of a ply stress state in material axes,
// s = (sigma_1, sigma_2, tau_12, tau_13, tau_23) in Pa, with sigma_3 = 0 (a shell).
//
// Every index is the inverse strength ratio FI = 1/R, R the factor by which the ply's stress
// state, scaled proportionally, reaches the criterion's failure surface: FI = 1 on the surface,
// FI scales linearly with the load, and the margin of safety is MS = R - 1 = 1/FI - 1. For the
// quadratic criteria, F(R s) = a R^2 + b R = 1 gives FI = (b + sqrt(b^2 + 4 a)) / 2.
// - maximum stress (Jones 1999, Sec. 2.9.1): the largest of the stress-to-strength ratios;
// - Tsai-Wu (Tsai & Wu, J. Compos. Mater. 5, 1971, 58-80; plane stress as Jones 1999,
//   Sec. 2.9.5): F1 s1 + F2 s2 + F11 s1^2 + F22 s2^2 + F66 t12^2 + 2 F12 s1 s2, with
//   F12 = F12* sqrt(F11 F22), F12* = -1/2 by default (Tsai & Hahn, Introduction to Composite
//   Materials, 1980);
// - Hashin (J. Appl. Mech. 47, 1980, 329-334), fibre and matrix modes, tension and compression,
//   with sigma_3 = 0, the axial shear strength S12 for tau_12 and tau_13 (transverse isotropy)
//   and the transverse shear strength S23 for tau_23.
// The interlaminar strengths S13, S23 are optional: when given, maximum stress also checks
// |tau_13| / S13 and |tau_23| / S23, and Tsai-Wu adds F55 tau_13^2 + F44 tau_23^2 with
// F55 = 1/S13^2, F44 = 1/S23^2 (Tsai & Wu 1971's quadratic terms); Hashin's matrix modes need S23.
#include <Eigen/Core>
#include <optional>

namespace deployfx::material {

using PlyStress = Eigen::Matrix<double, 5, 1>;  // (sigma_1, sigma_2, tau_12, tau_13, tau_23), Pa

struct Strengths {
  double Xt = 0, Xc = 0;  ///< fibre-direction tensile and compressive strengths (magnitudes), Pa
  double Yt = 0, Yc = 0;  ///< transverse tensile and compressive strengths (magnitudes), Pa
  double S12 = 0;         ///< in-plane (axial) shear strength, Pa
  std::optional<double> S13;  ///< interlaminar shear strength in the 1-3 plane, Pa
  std::optional<double> S23;  ///< transverse shear strength in the 2-3 plane, Pa
  double F12_star = -0.5;     ///< Tsai-Wu normalised interaction F12 / sqrt(F11 F22), in (-1, 1)

  /// Throws std::invalid_argument naming the field, its value and the allowed range.
  void validate() const;
};

enum class Criterion { MaxStress, TsaiWu, HashinFibre, HashinMatrix };

/// The criteria's coefficients for one ply material, computed once.
class FailureModel {
 public:
  explicit FailureModel(const Strengths& strengths);  ///< validates

  const Strengths& strengths() const { return s_; }
  /// Throws std::invalid_argument when the criterion needs a strength that was not given.
  void require(Criterion c) const;
  /// The failure index FI = 1/R (see the file comment), >= 0.
  double index(Criterion c, const PlyStress& s) const;

 private:
  double max_stress(const PlyStress& s) const;
  double tsai_wu(const PlyStress& s) const;
  double hashin_fibre(const PlyStress& s) const;
  double hashin_matrix(const PlyStress& s) const;

  Strengths s_;
  double F1_, F2_, F11_, F22_, F66_, F12_, F44_, F55_;  // Tsai-Wu, 1/Pa and 1/Pa^2
};

}  // namespace deployfx::material
