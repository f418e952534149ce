#include "deployfx/material/failure_criteria.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "deployfx/math/check.hpp"

namespace deployfx::material {
namespace {

// The root FI = 1/R of a R^2 + b R = 1 (a >= 0): (b + sqrt(b^2 + 4 a)) / 2, written to stay >= 0
// and exact when a = 0 (FI = max(b, 0)).
double inverse_ratio(double a, double b) { return 0.5 * (b + std::sqrt(b * b + 4.0 * a)); }

}  // namespace

void Strengths::validate() const {
  require_positive("Strengths.Xt", Xt, "(Pa)");
  require_positive("Strengths.Xc", Xc, "(Pa, a magnitude)");
  require_positive("Strengths.Yt", Yt, "(Pa)");
  require_positive("Strengths.Yc", Yc, "(Pa, a magnitude)");
  require_positive("Strengths.S12", S12, "(Pa)");
  if (S13) require_positive("Strengths.S13", *S13, "(Pa)");
  if (S23) require_positive("Strengths.S23", *S23, "(Pa)");
  // |F12*| < 1 keeps the Tsai-Wu surface closed (F11 F22 - F12^2 > 0; Tsai & Wu 1971).
  require_open_interval("Strengths.F12_star", F12_star, -1.0, 1.0, "(a closed Tsai-Wu surface)");
}

FailureModel::FailureModel(const Strengths& strengths) : s_(strengths) {
  s_.validate();
  F1_ = 1.0 / s_.Xt - 1.0 / s_.Xc;
  F2_ = 1.0 / s_.Yt - 1.0 / s_.Yc;
  F11_ = 1.0 / (s_.Xt * s_.Xc);
  F22_ = 1.0 / (s_.Yt * s_.Yc);
  F66_ = 1.0 / (s_.S12 * s_.S12);
  F12_ = s_.F12_star * std::sqrt(F11_ * F22_);
  F55_ = s_.S13 ? 1.0 / (*s_.S13 * *s_.S13) : 0.0;
  F44_ = s_.S23 ? 1.0 / (*s_.S23 * *s_.S23) : 0.0;
}

void FailureModel::require(Criterion c) const {
  if (c == Criterion::HashinMatrix && !s_.S23)
    throw std::invalid_argument(
        "Strengths.S23 is required by Hashin's matrix modes (the transverse shear strength S_T of "
        "Hashin 1980): give it, or leave the Hashin criteria out");
}

double FailureModel::index(Criterion c, const PlyStress& s) const {
  switch (c) {
    case Criterion::MaxStress: return max_stress(s);
    case Criterion::TsaiWu: return tsai_wu(s);
    case Criterion::HashinFibre: return hashin_fibre(s);
    case Criterion::HashinMatrix: return hashin_matrix(s);
  }
  throw std::invalid_argument("FailureModel.index: unknown criterion");
}

double FailureModel::max_stress(const PlyStress& s) const {
  double r = std::max(s(0) >= 0 ? s(0) / s_.Xt : -s(0) / s_.Xc,
                      s(1) >= 0 ? s(1) / s_.Yt : -s(1) / s_.Yc);
  r = std::max(r, std::abs(s(2)) / s_.S12);
  if (s_.S13) r = std::max(r, std::abs(s(3)) / *s_.S13);
  if (s_.S23) r = std::max(r, std::abs(s(4)) / *s_.S23);
  return r;
}

double FailureModel::tsai_wu(const PlyStress& s) const {
  const double a = F11_ * s(0) * s(0) + F22_ * s(1) * s(1) + 2.0 * F12_ * s(0) * s(1) +
                   F66_ * s(2) * s(2) + F55_ * s(3) * s(3) + F44_ * s(4) * s(4);
  const double b = F1_ * s(0) + F2_ * s(1);
  return inverse_ratio(a, b);
}

double FailureModel::hashin_fibre(const PlyStress& s) const {
  if (s(0) < 0) return -s(0) / s_.Xc;  // compression: |sigma_1| = Xc
  const double t = s(0) / s_.Xt;
  return std::sqrt(t * t + (s(2) * s(2) + s(3) * s(3)) / (s_.S12 * s_.S12));
}

double FailureModel::hashin_matrix(const PlyStress& s) const {
  require(Criterion::HashinMatrix);
  const double ST = *s_.S23;
  const double shear = s(4) * s(4) / (ST * ST) + (s(2) * s(2) + s(3) * s(3)) / (s_.S12 * s_.S12);
  if (s(1) >= 0) {
    const double t = s(1) / s_.Yt;
    return std::sqrt(t * t + shear);
  }
  // Compression: (s2 / 2 ST)^2 + [(Yc / 2 ST)^2 - 1] s2 / Yc + shear = 1.
  const double q = s(1) / (2.0 * ST);
  const double k = s_.Yc / (2.0 * ST);
  return inverse_ratio(q * q + shear, (k * k - 1.0) * s(1) / s_.Yc);
}

}  // namespace deployfx::material
