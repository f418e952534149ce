#include "deployfx/fem/ply_envelope.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace deployfx::fem {
namespace {

void require_finite_rows(const double* U, int n, int ndof) {
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < ndof; ++j)
      if (!std::isfinite(U[static_cast<std::ptrdiff_t>(i) * ndof + j]))
        throw std::invalid_argument("u_series[" + std::to_string(i) + "] has non-finite entries");
}

// Element e's indices for one displacement vector: out (criteria, points, plies, stations).
void element_indices(const PlyRecovery& r, const PlyFailureSetup& setup, const double* u, int e,
                     double* out) {
  const int C = static_cast<int>(setup.criteria.size());
  const int per_point = r.num_plies * kPlyStations;
  const int per_criterion = r.points_per_element * per_point;
  material::PlyStress sig;
  for (int p = 0; p < r.points_per_element; ++p) {
    const SectionState s = section_state(r, u, e, p, setup.measure);
    for (int k = 0; k < r.num_plies; ++k)
      for (int j = 0; j < kPlyStations; ++j) {
        ply_state(r, s, k, j, &sig, nullptr);
        for (int c = 0; c < C; ++c)
          out[c * per_criterion + p * per_point + k * kPlyStations + j] =
              setup.ply_models[k].index(setup.criteria[c], sig);
      }
  }
}

}  // namespace

void check_setup(const PlyRecovery& r, const PlyFailureSetup& setup) {
  if (static_cast<int>(setup.ply_models.size()) != r.num_plies)
    throw std::invalid_argument("strengths: expected one per ply (" + std::to_string(r.num_plies) +
                                "), got " + std::to_string(setup.ply_models.size()));
  if (setup.criteria.empty()) throw std::invalid_argument("criteria is empty: give at least one");
  for (const material::FailureModel& m : setup.ply_models)
    for (material::Criterion c : setup.criteria) m.require(c);
}

PlyEnvelope empty_envelope(const PlyRecovery& r, const PlyFailureSetup& setup) {
  check_setup(r, setup);
  PlyEnvelope env;
  env.num_criteria = static_cast<int>(setup.criteria.size());
  env.num_elements = r.num_elements;
  env.num_plies = r.num_plies;
  const std::size_t size = static_cast<std::size_t>(env.num_criteria) * r.num_elements * r.num_plies;
  env.index.assign(size, -1.0);
  env.sample.assign(size, -1);
  env.point.assign(size, -1);
  env.station.assign(size, -1);
  return env;
}

void accumulate_envelope(const PlyRecovery& r, const PlyFailureSetup& setup, const double* U, int n,
                         PlyEnvelope* env) {
  check_setup(r, setup);
  if (env->num_criteria != static_cast<int>(setup.criteria.size()) || env->num_elements != r.num_elements ||
      env->num_plies != r.num_plies)
    throw std::invalid_argument("accumulate_envelope: the envelope was made for another setup");
  require_finite_rows(U, n, r.num_dofs);
  const int C = env->num_criteria, P = r.points_per_element, K = r.num_plies;
  std::vector<double> buf(static_cast<std::size_t>(C) * P * K * kPlyStations);
  for (int i = 0; i < n; ++i) {
    const double* u = U + static_cast<std::ptrdiff_t>(i) * r.num_dofs;
    const int sample = env->samples + i;
    std::vector<double> peak(static_cast<std::size_t>(C), 0.0);
    for (int e = 0; e < r.num_elements; ++e) {
      element_indices(r, setup, u, e, buf.data());
      for (int c = 0; c < C; ++c)
        for (int p = 0; p < P; ++p)
          for (int k = 0; k < K; ++k)
            for (int j = 0; j < kPlyStations; ++j) {
              const double v = buf[((c * P + p) * K + k) * kPlyStations + j];
              const std::size_t slot = (static_cast<std::size_t>(c) * r.num_elements + e) * K + k;
              if (v > env->index[slot]) {
                env->index[slot] = v;
                env->sample[slot] = sample;
                env->point[slot] = p;
                env->station[slot] = j;
              }
              if (v > peak[c]) peak[c] = v;
            }
    }
    env->peak.insert(env->peak.end(), peak.begin(), peak.end());
  }
  env->samples += n;
}

void index_series(const PlyRecovery& r, const PlyFailureSetup& setup, const double* U, int n,
                  const std::vector<int>& elements, double* out) {
  check_setup(r, setup);
  for (std::size_t q = 0; q < elements.size(); ++q)
    if (elements[q] < 0 || elements[q] >= r.num_elements)
      throw std::invalid_argument("elements[" + std::to_string(q) + "] = " + std::to_string(elements[q]) +
                                  " is out of range: must be in [0, " + std::to_string(r.num_elements - 1) +
                                  "]");
  require_finite_rows(U, n, r.num_dofs);
  const int C = static_cast<int>(setup.criteria.size()), P = r.points_per_element, K = r.num_plies;
  const int E = static_cast<int>(elements.size());
  std::vector<double> buf(static_cast<std::size_t>(C) * P * K * kPlyStations);
  for (int i = 0; i < n; ++i) {
    const double* u = U + static_cast<std::ptrdiff_t>(i) * r.num_dofs;
    for (int q = 0; q < E; ++q) {
      element_indices(r, setup, u, elements[q], buf.data());
      for (int c = 0; c < C; ++c)
        for (int k = 0; k < K; ++k) {
          double m = 0;
          for (int p = 0; p < P; ++p)
            for (int j = 0; j < kPlyStations; ++j)
              m = std::max(m, buf[((c * P + p) * K + k) * kPlyStations + j]);
          out[((static_cast<std::ptrdiff_t>(i) * C + c) * E + q) * K + k] = m;
        }
    }
  }
}

}  // namespace deployfx::fem
