#include "deployfx/integrate/trajectory.hpp"

#include <cmath>

#include "deployfx/math/check.hpp"

namespace deployfx::integrate {
namespace {

constexpr int kMaxHalvings = 10;
constexpr int kMaxLocateIterations = 40;
constexpr double kLocateTolerance = 1e-9;  // of the step, on the bracket's width

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

// The first gap that is open at g0 and closed at g1 (-1: none).
int closing(const Eigen::VectorXd& g0, const Eigen::VectorXd& g1) {
  for (Eigen::Index i = 0; i < g0.size(); ++i)
    if (g0(i) > 0 && g1(i) <= 0) return static_cast<int>(i);
  return -1;
}

}  // namespace

Trajectory run_fixed_step(const GeneralizedAlpha& integrator, AlphaState s, double t_end, double h,
                          const Observer& observe) {
  require_positive("dt", h, "(s)");
  require_finite("t_end", t_end, "(s)");
  if (t_end < s.t) throw_out_of_range("t_end", t_end, ">= the start time");
  const SecondOrderSystem& sys = integrator.system();
  Trajectory tr;
  const long steps = std::lround(std::ceil((t_end - s.t) / h - 1e-9));
  tr.t.reserve(steps + 1);
  auto record = [&] {
    tr.t.push_back(s.t);
    tr.q.push_back(s.q);
    tr.v.push_back(s.v);
    if (observe) observe(s);
  };
  sys.accept(s.q, s.v, s.t);
  record();
  const double t0 = s.t;
  for (long k = 1; k <= steps; ++k) {
    const double target = k == steps ? t_end : t0 + k * h;  // no round-off drift in output times
    int iterations = 0;
    try {
      while (target - s.t > 1e-12 * std::max(1.0, std::abs(target))) {
        const double h_k = target - s.t;
        AlphaState trial = s;
        iterations += advance(integrator, trial, h_k, 0, &tr.substeps);
        const Eigen::VectorXd g0 = sys.gaps(s.q, s.v, s.t);
        Eigen::VectorXd g1 = sys.gaps(trial.q, trial.v, trial.t);
        const int i = closing(g0, g1);
        if (i < 0) {
          s = std::move(trial);
          s.t = std::abs(s.t - target) < 1e-12 * std::max(1.0, std::abs(target)) ? target : s.t;
          sys.accept(s.q, s.v, s.t);
          continue;
        }
        // Locate the closing of gap i in (0, h_k]: Illinois-safeguarded secant on g_i(step size).
        double lo = 0, hi = h_k, g_lo = g0(i), g_hi = g1(i);
        AlphaState best = std::move(trial);
        int side = 0;
        // Until the event function is within 1e-9 of its scale or the bracket is 1e-9 of the step.
        const double tol = 1e-9 * std::max(std::abs(g_lo), std::abs(g_hi));
        for (int n = 0; n < kMaxLocateIterations && g_hi < -tol && hi - lo > kLocateTolerance * h; ++n) {
          double mid = hi - g_hi * (hi - lo) / (g_hi - g_lo);
          const double guard = 0.05 * (hi - lo);
          mid = std::min(std::max(mid, lo + guard), hi - guard);
          AlphaState m = s;
          iterations += advance(integrator, m, mid, 0, &tr.substeps);
          const double g = sys.gaps(m.q, m.v, m.t)(i);
          if (g > 0) {
            lo = mid, g_lo = g;
            if (side == -1) g_hi *= 0.5;  // Illinois: keep the stale end from stalling
            side = -1;
          } else {
            hi = mid, g_hi = g, best = std::move(m);
            if (side == 1) g_lo *= 0.5;
            side = 1;
          }
        }
        s = std::move(best);
        sys.accept(s.q, s.v, s.t);
        ++tr.events;
        if (target - s.t > 1e-12 * std::max(1.0, std::abs(target))) {
          tr.newton_iterations.push_back(iterations);
          iterations = 0;
          record();
        }
      }
    } catch (const StepFailure& e) {
      tr.failure = e.what();
      return tr;
    }
    s.t = target;
    tr.newton_iterations.push_back(iterations);
    record();
  }
  return tr;
}

}  // namespace deployfx::integrate
