#pragma once
// Each contact of a lock wall as a record, onset to separation: what a mechanism engineer sizing a
// latch reads (the peak normal force and when, the impulse, the approach and rebound speeds).
// Written from the accepted steps of a run only; the peaks are located, not sampled: the largest
// sample and its two neighbours define a parabola whose vertex is the peak (the steps inside a
// contact resolve it, integrate/trajectory.hpp, so the vertex is within O(h^3) of the true one).
#include <limits>
#include <vector>

namespace deployfx::joint {

struct Impact {
  static constexpr double kOpen = std::numeric_limits<double>::quiet_NaN();
  int hinge = -1;
  int wall = 0;                     ///< 0 the stop, 1 the latch
  double t_onset = 0;               ///< s
  double t_separation = kOpen;      ///< s; NaN while the pin is still on the wall (run's end)
  double v_approach = 0;            ///< m/s, the pin's normal speed into the wall at onset
  double v_rebound = kOpen;         ///< m/s, its normal speed away from the wall at separation
  double peak_force = 0;            ///< N, the largest normal force, located
  double t_peak = 0;                ///< s
  double impulse = 0;               ///< N s, the integral of the normal force (trapezoidal rule)
  double max_penetration = 0;       ///< m, located like the peak
  long steps = 0;                   ///< accepted steps in contact
};

/// Follows one wall through the accepted steps of a run and keeps its Impact records.
class ImpactTracker {
 public:
  /// The wall at an accepted step's end: whether it is in contact (its mode after the step's
  /// switches), its normal force F (N), penetration delta (m) and its rate (m/s) at time t (s).
  /// A contact that starts opens a record in `records`, one that ends closes it.
  void observe(int hinge, int wall, bool in_contact, double t, double F, double delta, double delta_dot,
               std::vector<Impact>& records);

  /// Everything the tracker carries between steps (for a checkpoint).
  struct Snapshot {
    bool open = false;
    std::size_t index = 0;
    double t[3] = {0, 0, 0}, F[3] = {0, 0, 0}, x[3] = {0, 0, 0};
    int n = 0;
  };
  Snapshot snapshot() const {
    Snapshot s;
    s.open = open_, s.index = index_, s.n = n_;
    for (int i = 0; i < 3; ++i) s.t[i] = t_[i], s.F[i] = F_[i], s.x[i] = x_[i];
    return s;
  }
  void restore(const Snapshot& s) {
    open_ = s.open, index_ = s.index, n_ = s.n;
    for (int i = 0; i < 3; ++i) t_[i] = s.t[i], F_[i] = s.F[i], x_[i] = s.x[i];
  }

 private:
  bool open_ = false;
  std::size_t index_ = 0;  // of the open record
  // The last three samples of the open contact (oldest first): t, F, delta.
  double t_[3] = {0, 0, 0}, F_[3] = {0, 0, 0}, x_[3] = {0, 0, 0};
  int n_ = 0;
};

/// The vertex (t, y) of the parabola through three samples (t0 < t1 < t2) whose middle one is
/// the largest; the middle sample itself if the parabola does not open downward.
void parabola_peak(const double t[3], const double y[3], double* t_peak, double* y_peak);

}  // namespace deployfx::joint
