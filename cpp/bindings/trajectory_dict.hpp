#pragma once
// Trajectory -> dict of numpy arrays: t (n,), q (n, nq), v (n, nv), newton_iterations, substeps,
// failure. Shared by every simulate_* binding; callers add their own outputs to the dict.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "deployfx/integrate/trajectory.hpp"

inline pybind11::dict trajectory_dict(const deployfx::integrate::Trajectory& tr) {
  const Eigen::Index n = static_cast<Eigen::Index>(tr.t.size());
  const Eigen::Index nq = n ? tr.q[0].size() : 0, nv = n ? tr.v[0].size() : 0;
  Eigen::MatrixXd Q(n, nq), V(n, nv);
  for (Eigen::Index k = 0; k < n; ++k) {
    Q.row(k) = tr.q[k].transpose();
    V.row(k) = tr.v[k].transpose();
  }
  pybind11::dict d;
  d["t"] = Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(tr.t.data(), n));
  d["q"] = Q;
  d["v"] = V;
  d["newton_iterations"] = tr.newton_iterations;
  d["substeps"] = tr.substeps;
  d["steps"] = tr.steps;
  d["rejected"] = tr.rejected;
  d["events"] = tr.events;
  d["failure"] = tr.failure;
  return d;
}
