#include "deployfx/integrate/trajectory.hpp"

#include <cmath>

#include "deployfx/math/check.hpp"

namespace deployfx::integrate {
namespace {

constexpr int kMaxHalvings = 10;

// Advances s by h, halving on Newton failure; returns the Newton iterations spent. On failure
// s is unchanged and StepFailure propagates.
int advance(const GeneralizedAlpha& integrator, AlphaState& s, double h, int depth, long* substeps) {
  try {
    const int it = integrator.step(s, h);
    ++*substeps;
    return it;
  } catch (const StepFailure&) {
    if (depth >= kMaxHalvings) throw;
  }
  AlphaState trial = s;
  const int it = advance(integrator, trial, 0.5 * h, depth + 1, substeps) +
                 advance(integrator, trial, 0.5 * h, depth + 1, substeps);
  s = std::move(trial);
  return it;
}

}  // namespace

Trajectory run_fixed_step(const GeneralizedAlpha& integrator, AlphaState s, double t_end, double h) {
  require_positive("dt", h, "(s)");
  require_finite("t_end", t_end, "(s)");
  if (t_end < s.t) throw_out_of_range("t_end", t_end, ">= the start time");
  Trajectory tr;
  const long steps = std::lround(std::ceil((t_end - s.t) / h - 1e-9));
  tr.t.reserve(steps + 1);
  auto record = [&] {
    tr.t.push_back(s.t);
    tr.q.push_back(s.q);
    tr.v.push_back(s.v);
  };
  record();
  const double t0 = s.t;
  for (long k = 1; k <= steps; ++k) {
    const double h_k = std::min(h, t_end - s.t);  // land on t_end
    try {
      tr.newton_iterations.push_back(advance(integrator, s, h_k, 0, &tr.substeps));
    } catch (const StepFailure& e) {
      tr.failure = e.what();
      return tr;
    }
    s.t = k == steps ? t_end : t0 + k * h;  // no round-off drift in the recorded times
    record();
  }
  return tr;
}

}  // namespace deployfx::integrate
