#include "deployfx/integrate/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "deployfx/math/check.hpp"

namespace deployfx::integrate {
namespace {

constexpr int kMaxHalvings = 10;
constexpr int kMaxLocateIterations = 60;
constexpr double kLocateTolerance = 1e-9;  // of the step, on the bracket's width
// The shortest step an event search takes, s. Below it a step's velocity update h gamma a nears
// the round-off of v, and the momentum rows (Pi_n+1 - Pi_n) / (h gamma c) turn that round-off
// into residual noise of order eps |v| / h that Newton cannot remove (at 1e-11 s: 1e-5 of the
// accelerations, the Newton floor). An event is located to this width at best.
constexpr double kMinEventStep = 1e-8;
constexpr double kEventTolerance = 1e-9;   // on G, the events normalised by their start values

// Advances s by h, halving on Newton failure; returns the Newton iterations spent. On failure
// s is unchanged and StepFailure propagates. `guess`: Newton's start for the whole step.
// A stop asked for by the caller's Poll: ends the run with the states recorded so far.
struct Stopped {
  std::string why;
};

int advance(GeneralizedAlpha& integrator, AlphaState& s, double h, int depth, long* substeps, const Poll& poll,
            const Eigen::VectorXd* guess = nullptr) {
  try {
    const int it = integrator.step(s, h, guess);
    ++*substeps;
    if (poll) {
      std::string why = poll(s.t);
      if (!why.empty()) throw Stopped{std::move(why)};
    }
    return it;
  } catch (const StepFailure&) {
    if (depth >= kMaxHalvings) throw;
  }
  AlphaState trial = s;
  const int it = advance(integrator, trial, 0.5 * h, depth + 1, substeps, poll) +
                 advance(integrator, trial, 0.5 * h, depth + 1, substeps, poll);
  s = std::move(trial);
  return it;
}

// The earliest switch among the events holding at the step's start is the first root of
// G = min_i g_i / g0_i over those events (each normalised by its start value, so events in
// different units compare; G = 1 at the start).
double first_switch(const Eigen::VectorXd& g0, const Eigen::VectorXd& g) {
  double G = 1.0;
  for (Eigen::Index i = 0; i < g0.size(); ++i)
    if (g0(i) > 0 && std::isfinite(g0(i))) G = std::min(G, g(i) / g0(i));
  return G;
}

// A bracket [lo, hi] of the first root of G over a trial step's size (G(lo) > 0 >= G(hi)) and
// the next trial step's size. While G behaves, the trial goes to the root of the inverse
// quadratic through the ends and the end the last trial replaced (Brent's interpolation: G curves
// within a step), else of the secant with the Illinois modification; once that root lies within
// the width of an end, a probe one width inside the end closes the bracket; three trials in a row
// on one side bisect it. A probe that lands on its end's own side shows G misbehaving there (near
// the latch's drop the trial steps' G is noisy to 1e-3 and flat past the root, where a step
// ending within about 1e-7 s past the drop has no solution: NewtonOptions::diverging_steps):
// the search then keeps its trials 5 % of the bracket inside its ends (the Illinois secant,
// bisecting after two clipped trials in a row), still probing until such a probe too lands on
// its own side. Paper scene, 15 x 10, 30 s: 5.2 trials an event against 6.3 for the guarded
// search alone (reduced-manifold); the swinging pin of tests/test_lock_accuracy.py 3-6 for its
// two events against 6-20.
struct EventBracket {
  double lo = 0, hi, G_lo = 1.0, G_hi;
  double w_lo = 1.0, w_hi;  // Illinois: the ends' values as the secant weighs them
  double t_old = std::numeric_limits<double>::quiet_NaN(), G_old = 0;  // the end the last trial replaced
  int side = 0;             // the side of the last trial: -1 (G > 0, lo) or 1 (hi)
  int same_side = 0;        // trials in a row on that side
  int clipped = 0;          // guarded trials in a row clipped to the guard
  int probe = 0;            // the last trial probed one width inside lo (-1) or hi (1)
  bool interpolating = true, probing = true;

  EventBracket(double h, double G_h) : hi(h), G_hi(G_h), w_hi(G_h) {}

  double next(double width) {
    const double secant = hi - w_hi * (hi - lo) / (w_hi - w_lo);
    probe = 0;
    if (interpolating) {
      double t = secant;
      if (std::isfinite(t_old) && G_old != G_lo && G_old != G_hi) {
        const double a = lo, fa = G_lo, b = hi, fb = G_hi, c = t_old, fc = G_old;
        const double iqi = a * fb * fc / ((fa - fb) * (fa - fc)) + b * fa * fc / ((fb - fa) * (fb - fc)) +
                           c * fa * fb / ((fc - fa) * (fc - fb));
        if (iqi > lo && iqi < hi) t = iqi;
      }
      if (same_side >= 3) {
        same_side = 0;
        return 0.5 * (lo + hi);
      }
      probe = hi - t < width ? 1 : t - lo < width ? -1 : 0;
      return probe == 0 ? t : probe_at(width);
    }
    // Guarded: the unweighted secant's root decides a probe, the weighted one the trial.
    const double root = hi - G_hi * (hi - lo) / (G_hi - G_lo);
    if (probing) probe = hi - root <= 0.5 * width ? 1 : root - lo <= 0.5 * width ? -1 : 0;
    if (probe != 0) return probe_at(width);
    const double guard = 0.05 * (hi - lo);
    clipped = secant > lo + guard && secant < hi - guard ? 0 : clipped + 1;
    if (clipped >= 2) {
      clipped = 0;
      return 0.5 * (lo + hi);
    }
    return std::min(std::max(secant, lo + guard), hi - guard);
  }

  // One width inside the end `probe` names.
  double probe_at(double width) const { return probe == 1 ? hi - 0.99 * width : lo + 0.99 * width; }

  void update(double t, double G) {
    const int now = G > 0 ? -1 : 1;
    same_side = now == side ? same_side + 1 : 1;
    if (now == -1) {
      if (side == -1) w_hi *= 0.5;  // Illinois: keep the stale end from stalling
      t_old = lo, G_old = G_lo;
      lo = t, G_lo = w_lo = G;
    } else {
      if (side == 1) w_lo *= 0.5;
      t_old = hi, G_old = G_hi;
      hi = t, G_hi = w_hi = G;
    }
    side = now;
    if (probe != 0 && probe == now) {  // a probe that landed on its own end's side
      if (interpolating) interpolating = false;
      else probing = false;
    }
  }
};

}  // namespace

Trajectory run_fixed_step(GeneralizedAlpha& integrator, AlphaState s, double t_end, double h,
                          const Observer& observe) {
  return run(integrator, std::move(s), t_end, h, StepControl{}, observe);
}

Trajectory run(GeneralizedAlpha& integrator, AlphaState s, double t_end, double h,
               const StepControl& control, const Observer& observe, const Poll& poll,
               const Checkpoints* checkpoints) {
  const DriverState* resume = checkpoints ? checkpoints->resume : nullptr;
  if (resume) s = resume->state;
  require_positive("dt", h, "(s)");
  if (!(control.tolerance >= 0 && std::isfinite(control.tolerance)))
    throw_out_of_range("tolerance", control.tolerance, ">= 0 (m or rad; 0: fixed steps)");
  require_finite("t_end", t_end, "(s)");
  if (t_end < s.t) throw_out_of_range("t_end", t_end, ">= the start time");
  SecondOrderSystem& sys = integrator.system();
  Trajectory tr;
  // Output steps are counted in a long and their times kept: beyond 1e9 of them the run cannot be
  // stored (8 GB of times alone), and t_end / dt may overflow the count.
  const double t0 = resume ? resume->t0 : s.t;
  const double outputs = std::ceil((t_end - t0) / h - 1e-9);
  if (!(outputs <= 1e9)) {
    std::ostringstream e;
    e << "t_end = " << t_end << " s and dt = " << h << " s ask for " << outputs
      << " output steps: (t_end - t0) / dt must be <= 1e9";
    throw std::invalid_argument(e.str());
  }
  const long steps = std::lround(outputs);
  tr.t.reserve(static_cast<std::size_t>(std::min(steps + 1, 1L << 20)));
  bool stopped = false;
  auto record = [&] {
    tr.t.push_back(s.t);
    if (observe && !observe(s)) {
      stopped = true;
      tr.failure = "stopped by the caller at t = " + std::to_string(s.t) + " s";
    }
  };
  if (!resume) sys.accept(s.q, s.v, s.t);  // a resumed history holds this instant already
  record();
  if (stopped) return tr;
  const bool adaptive = control.tolerance > 0;
  const auto& p = integrator.parameters();
  const double snap = std::max(std::min(kMinEventStep, 1e-3 * h), 1e-12 * std::max(1.0, std::abs(t_end)));
  double h_try = adaptive ? std::min(h, control.initial_step > 0 ? control.initial_step : 0.1 * h) : h;
  double h_contact = h;  // the next step while a contact is resolved
  // The last contact's bounds, kept after it ends until the steps are back at h: the accelerations
  // the scheme carries out of a contact (a_n) are the contact's, and a full step right after it
  // amplifies them by h^2 (0.5 - beta) (on the undamped 2 x 1 paper scene an 8.7 ms step after a
  // 96 us contact added 1 % of the peak kinetic energy). The error estimate lets the steps grow
  // back (at most 2x a step) once the history has passed.
  SecondOrderSystem::StepBounds contact_bounds;
  if (resume) {
    h_try = resume->h_try, h_contact = resume->h_contact, contact_bounds = resume->contact_bounds;
    integrator.restore(resume->solver);
  }
  for (long k = resume ? resume->k + 1 : 1; k <= steps; ++k) {
    const double target = k == steps ? t_end : t0 + k * h;  // no round-off drift in output times
    int iterations = 0;
    try {
      // An event closer than `snap` to the output time ends the interval: the step left would be
      // shorter than an event search may take (the state is then recorded up to `snap` early).
      while (target - s.t > snap) {
        SecondOrderSystem::StepBounds bounds = sys.step_bounds();
        if (bounds.error.size() > 0) {
          contact_bounds = bounds;
        } else if (h_contact < h && contact_bounds.error.size() > 0) {
          bounds = contact_bounds;
        } else {
          contact_bounds = {};
        }
        const bool resolving = bounds.error.size() > 0;
        const double h_floor = std::max(bounds.min_step, kMinEventStep);
        const double left = target - s.t;
        double h_k = adaptive ? std::min(h_try, left) : left;
        if (resolving && h_contact < h_k) {
          h_k = left / std::ceil(left / h_contact - 1e-9);  // the output step divided evenly
        }
        AlphaState trial = s;
        iterations += advance(integrator, trial, h_k, 0, &tr.substeps, poll);
        // Local error of the Newmark-family displacement update, h^2 (beta - 1/6)(a_n+1 - a_n)
        // (Zienkiewicz & Xie, Earthquake Eng. Struct. Dyn. 20, 1991, 871-887), in the
        // coordinates' own units (m, rad): against the absolute tolerance, and against the
        // contacts' bounds; the next step from the estimate's third-order scaling.
        const Eigen::VectorXd da = trial.a - s.a;
        const double c_err = h_k * h_k * std::abs(p.beta - 1.0 / 6.0);
        if (adaptive) {
          const double err = c_err * da.lpNorm<Eigen::Infinity>() / control.tolerance;
          const double factor = err > 0 ? 0.9 * std::pow(err, -1.0 / 3.0) : 2.0;
          if (err > 1 && h_k > control.min_step) {
            h_try = std::max(std::max(0.2, factor) * h_k, control.min_step);
            ++tr.rejected;
            continue;
          }
          h_try = std::min(std::min(2.0, factor) * h_k, h);
        }
        if (resolving) {
          const double err = c_err * (da.array().abs() / bounds.error.array()).maxCoeff();
          const double factor = err > 0 ? 0.9 * std::pow(err, -1.0 / 3.0) : 2.0;
          if (err > 1 && h_k > h_floor) {
            h_contact = std::max(std::max(0.2, factor) * h_k, h_floor);
            ++tr.rejected;
            continue;
          }
          h_contact = std::min(std::min(2.0, factor) * h_k, h);
          if (h_k < left) ++tr.contact_steps;
        } else {
          h_contact = h;
        }
        const Eigen::VectorXd g0 = sys.gaps(s.q, s.v, s.t), g1 = sys.gaps(trial.q, trial.v, trial.t);
        const double G1 = first_switch(g0, g1);
        if (G1 > 0) {
          s = std::move(trial);
          s.t = std::abs(s.t - target) < 1e-12 * std::max(1.0, std::abs(target)) ? target : s.t;
          sys.accept(s.q, s.v, s.t);
          ++tr.steps;
          continue;
        }
        // Locate the first root of G in (0, h_k] to the width (EventBracket); the stop test uses
        // the true G.
        const double width = std::max(kLocateTolerance * h, kMinEventStep);
        EventBracket bracket(h_k, G1);
        // Each trial starts Newton from vdot_{n+1} interpolated in the step size between the
        // bracket's ends (at size 0 it is vdot_n: the equations of motion hold at t_n), not from
        // the predictor, which knows nothing of the impact.
        Eigen::VectorXd vdot_lo = s.vdot;
        AlphaState best = std::move(trial);
        for (int n = 0; n < kMaxLocateIterations && bracket.G_hi < -kEventTolerance && bracket.hi - bracket.lo > width;
             ++n) {
          const double lo = bracket.lo, hi = bracket.hi, mid = bracket.next(width);
          AlphaState m = s;
          const Eigen::VectorXd guess = vdot_lo + ((mid - lo) / (hi - lo)) * (best.vdot - vdot_lo);
          try {
            iterations += advance(integrator, m, mid, 0, &tr.substeps, poll, &guess);
          } catch (const StepFailure&) {
            break;  // a search step Newton cannot take: the event is at the bracket's end hi
          }
          const double G = first_switch(g0, sys.gaps(m.q, m.v, m.t));
          bracket.update(mid, G);
          if (G > 0) vdot_lo = m.vdot;
          else best = std::move(m);
        }
        // Every event within the location tolerance of its switch switches here too: events
        // simultaneous to round-off (symmetric contacts) must not part by a tiny step. The
        // tolerance is relative to the larger of the event's start value and its change over the
        // step: a separating wall's force at the start of a short contact step can be small.
        Eigen::VectorXd margin = Eigen::VectorXd::Zero(g0.size());
        for (Eigen::Index i = 0; i < g0.size(); ++i)
          if (g0(i) > 0 && std::isfinite(g0(i)))
            margin(i) = kEventTolerance * std::max(g0(i), std::isfinite(g1(i)) ? std::abs(g1(i) - g0(i)) : 0.0);
        if (sys.accept(best.q, best.v, best.t, margin)) {
          // A latch pin dropped: the search's trial steps held it where the drop left it
          // (joint/latch_follower.hpp), so the located state's accelerations are the held pin's.
          // The same step again with the pin dropped (its forces at the step's end) gives the
          // next step the dropped pin's. Measured on the paper scene at dt = 0.01 s against
          // 0.5 ms: the first impact's peak force (D times the approach speed) 0.004-0.05 % off,
          // was 0.12-0.24 %; carrying the held pin's accelerations put the first lock 0.26 ms
          // early. If Newton cannot take the step, the held state stays.
          AlphaState again = s;  // s is still the step's start
          try {
            iterations += advance(integrator, again, bracket.hi, 0, &tr.substeps, poll, &best.vdot);
            best = std::move(again);
          } catch (const StepFailure&) {
          }
        }
        s = std::move(best);
        // A contact to resolve starts here: its first step is the shortest worth taking (a
        // hundredth of the impact's time scale). The law may jump at onset (the paper's, to
        // D delta'), and the acceleration the scheme carries over lacks the jump: a first-order
        // error, which the short first steps keep small (0.7 % of the rebound for the paper's
        // law on the rigid panel). Not absorbed into the accelerations instead: at a hinge that
        // rides on a deforming panel, the jump's acceleration reaches the panel's light rotations,
        // and a chattering pin then fed energy in (notebook 2's nonlinear wing diverged).
        if (const SecondOrderSystem::StepBounds b = sys.step_bounds(); b.error.size() > 0 && b.min_step > 0)
          h_contact = std::min(h, b.min_step);
        ++tr.events;
        ++tr.steps;
        if (target - s.t > snap) {
          tr.newton_iterations.push_back(iterations);
          iterations = 0;
          record();
          if (stopped) return tr;
        }
      }
    } catch (const StepFailure& e) {
      tr.failure = e.what();
      return tr;
    } catch (const Stopped& e) {
      tr.failure = e.why;
      return tr;
    }
    s.t = target;
    tr.newton_iterations.push_back(iterations);
    record();
    if (stopped) return tr;
    if (checkpoints && checkpoints->sink &&
        std::find(checkpoints->at.begin(), checkpoints->at.end(), k) != checkpoints->at.end()) {
      checkpoints->sink(DriverState{s, t0, k, h_try, h_contact, contact_bounds, integrator.solver_state()});
    }
  }
  return tr;
}

}  // namespace deployfx::integrate
