#pragma once
// A run's checkpoint: everything the run loop (simulate.hpp) carries from one output instant to
// the next, its check against a model, and its versioned binary image.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "deployfx/integrate/trajectory.hpp"
#include "deployfx/joint/impact_record.hpp"
#include "deployfx/joint/lock.hpp"
#include "deployfx/multibody/model.hpp"

namespace deployfx::multibody {

/// Everything a run carries from one output instant to the next: the driver's state (the
/// integrator's state and predictor history, the step control's sizes, the output count) and the
/// run's history in Data (lock histories with their impact trackers, the impact records, the last
/// accepted configuration). A run resumed from it is bit-identical to the one that wrote it.
struct Checkpoint {
  integrate::DriverState driver;
  std::vector<joint::LockState> locks;
  std::vector<joint::Impact> impacts;
  Eigen::VectorXd accepted_q;
  /// A versioned binary image; from_bytes throws std::invalid_argument for a malformed one.
  std::string to_bytes() const;
  static Checkpoint from_bytes(const std::string& bytes);
};

/// Throws std::invalid_argument unless `c` fits m (state sizes, the locks' kinds).
void check_checkpoint(const Model& m, const Checkpoint& c);

}  // namespace deployfx::multibody
