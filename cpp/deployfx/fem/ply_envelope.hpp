#pragma once
// Failure indices of every ply of a shell mesh over the samples of a run: the envelope (the
// maximum over time of each element's and ply's index, where and when it occurred) and, for
// chosen elements, the index history. Streaming: samples are added in batches, nothing of the
// stress field is stored.
//
// An element's index for a ply is the maximum over its sampling points (fem/ply_stress.hpp) and
// the ply's three stations. Ties keep the earliest sample.
#include <vector>

#include "deployfx/fem/ply_stress.hpp"
#include "deployfx/material/failure_criteria.hpp"

namespace deployfx::fem {

struct PlyFailureSetup {
  std::vector<material::FailureModel> ply_models;  ///< one per ply, bottom first
  std::vector<material::Criterion> criteria;
  StrainMeasure measure = StrainMeasure::Linear;
};

/// Throws std::invalid_argument for a count of ply models other than r.num_plies, no criteria,
/// or a criterion whose strengths are missing.
void check_setup(const PlyRecovery& r, const PlyFailureSetup& setup);

struct PlyEnvelope {
  int num_criteria = 0, num_elements = 0, num_plies = 0;
  int samples = 0;  ///< samples accumulated so far
  // (criteria, elements, plies), row-major:
  std::vector<double> index;  ///< maximum failure index (-1 before any sample)
  std::vector<int> sample;    ///< the sample where it occurred
  std::vector<int> point;     ///< the sampling point within the element
  std::vector<int> station;   ///< the ply station (0 bottom, 1 middle, 2 top)
  std::vector<double> peak;   ///< (samples, criteria): the largest index over the mesh per sample
};

PlyEnvelope empty_envelope(const PlyRecovery& r, const PlyFailureSetup& setup);

/// Adds n samples (U: n x num_dofs, row-major, each a mesh-dof displacement vector) to env.
/// Throws for non-finite displacements.
void accumulate_envelope(const PlyRecovery& r, const PlyFailureSetup& setup, const double* U, int n,
                         PlyEnvelope* env);

/// The index history of the given elements: out receives (n, criteria, elements.size(), plies)
/// row-major, each the maximum over the element's points and the ply's stations.
void index_series(const PlyRecovery& r, const PlyFailureSetup& setup, const double* U, int n,
                  const std::vector<int>& elements, double* out);

}  // namespace deployfx::fem
