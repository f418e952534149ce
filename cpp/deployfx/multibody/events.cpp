#include "deployfx/multibody/events.hpp"

#include <algorithm>

namespace deployfx::multibody {

Eigen::VectorXd lock_events(const Model& m, const Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  Eigen::VectorXd g(2 * static_cast<Eigen::Index>(m.locks().size()));
  Eigen::Index i = 0;
  for (int k : m.locks()) {
    const Body& b = m.body(k);
    joint::lock_events(*m.hinge(k).lock, d.locks[k], q(b.iq_theta), v(b.iv_theta), &g(i), &g(i + 1));
    i += 2;
  }
  return g;
}

void accept(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
            const Eigen::VectorXd& margin) {
  Eigen::Index i = 0;
  for (int k : m.locks()) {
    const Body& b = m.body(k);
    const double stop = margin.size() ? margin(i) : 0.0, latch = margin.size() ? margin(i + 1) : 0.0;
    joint::update_lock_history(*m.hinge(k).lock, d.locks[k], q(b.iq_theta), v(b.iv_theta), stop, latch);
    i += 2;
  }
}

double friction_step_limit(const Model& m, const Data& d, const Eigen::VectorXd& v, const Eigen::VectorXd& dv) {
  double limit = 1.0;
  for (int k : m.locks()) {
    const int i = m.body(k).iv_theta;
    limit = std::min(limit, joint::friction_step_limit(*m.hinge(k).lock, d.locks[k], v(i), dv(i)));
  }
  return limit;
}

}  // namespace deployfx::multibody
