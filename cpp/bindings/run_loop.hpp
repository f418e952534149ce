#pragma once
// A run for the bindings: multibody::simulate with the GIL released, recording every output
// instant into flat buffers that become numpy arrays without a copy. Every 0.2 s of wall time the
// GIL is taken to answer Ctrl-C (the main thread's signals), call progress(t, t_end) and ask
// should_stop(); any of them stops the run, keeping what was computed (`failure` says why and
// when). The poll runs after every integrator step, so a run whose steps shrink still answers.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <chrono>
#include <string>
#include <vector>

#include "deployfx/multibody/outputs.hpp"
#include "deployfx/multibody/simulate.hpp"

namespace run_detail {

// A growing (n, ...) series of doubles, handed to numpy without a copy.
struct Series {
  std::vector<double> values;
  std::vector<pybind11::ssize_t> shape;  // per sample
  template <class V>
  void append(const V& x) {
    values.insert(values.end(), x.data(), x.data() + x.size());
  }
  void append(double x) { values.push_back(x); }
  pybind11::array_t<double> to_numpy(pybind11::ssize_t n) {
    std::vector<pybind11::ssize_t> full{n};
    full.insert(full.end(), shape.begin(), shape.end());
    auto* heap = new std::vector<double>(std::move(values));
    pybind11::capsule owner(heap, [](void* p) { delete static_cast<std::vector<double>*>(p); });
    return pybind11::array_t<double>(full, heap->data(), owner);
  }
};

}  // namespace run_detail

/// A run's impact records (joint/impact_record.hpp) as a dict of equal-length numpy arrays.
inline pybind11::dict impact_table(const std::vector<deployfx::joint::Impact>& records) {
  namespace py = pybind11;
  const auto n = static_cast<py::ssize_t>(records.size());
  py::array_t<long> hinge(n), wall(n), steps(n);
  py::array_t<double> t_on(n), t_sep(n), v_in(n), v_out(n), peak(n), t_peak(n), impulse(n), pen(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    const auto& r = records[static_cast<std::size_t>(i)];
    hinge.mutable_at(i) = r.hinge, wall.mutable_at(i) = r.wall, steps.mutable_at(i) = r.steps;
    t_on.mutable_at(i) = r.t_onset, t_sep.mutable_at(i) = r.t_separation;
    v_in.mutable_at(i) = r.v_approach, v_out.mutable_at(i) = r.v_rebound;
    peak.mutable_at(i) = r.peak_force, t_peak.mutable_at(i) = r.t_peak;
    impulse.mutable_at(i) = r.impulse, pen.mutable_at(i) = r.max_penetration;
  }
  py::dict d;
  d["hinge"] = hinge, d["wall"] = wall, d["t_onset"] = t_on, d["t_separation"] = t_sep;
  d["v_approach"] = v_in, d["v_rebound"] = v_out, d["peak_force"] = peak, d["t_peak"] = t_peak;
  d["impulse"] = impulse, d["max_penetration"] = pen, d["steps"] = steps;
  return d;
}

inline pybind11::dict run_released(const deployfx::multibody::Model& model, deployfx::multibody::Data& data,
                                   const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                                   const deployfx::multibody::RunOptions& opt, const pybind11::object& progress,
                                   const pybind11::object& should_stop,
                                   const std::vector<long>& checkpoint_steps = {},
                                   const deployfx::multibody::Checkpoint* resume = nullptr) {
  namespace py = pybind11;
  namespace mb = deployfx::multibody;
  using run_detail::Series;
  const py::ssize_t H = model.num_hinges();
  Series q{{}, {model.num_positions()}}, v{{}, {model.num_velocities()}};
  Series theta{{}, {H}}, rate{{}, {H}}, spring{{}, {H}}, lock_force{{}, {H}}, lock_torque{{}, {H}},
      latched{{}, {H}}, strain{{}, {H}}, hinge_force{{}, {H, 3}}, hinge_moment{{}, {H, 3}};
  Series P{{}, {3}}, Hw{{}, {3}}, Pb{{}, {3}}, Hb{{}, {3}}, kinetic, potential, P_scale, H_scale;
  std::vector<double> t;
  auto record = [&](const deployfx::integrate::AlphaState& s) {
    const mb::Outputs o = mb::outputs(model, data, s.q, s.v, s.accelerations(), s.t);
    t.push_back(s.t);
    q.append(s.q);
    v.append(s.v);
    theta.append(o.theta);
    rate.append(o.rate);
    spring.append(o.spring_torque);
    lock_force.append(o.lock_force);
    lock_torque.append(o.lock_torque);
    latched.append(o.latched);
    strain.append(o.strain_energy);
    hinge_force.append(o.hinge_force);  // column-major 3 x H: each hinge's 3 components in turn
    hinge_moment.append(o.hinge_moment);
    P.append(o.P_W);
    Hw.append(o.H_W);
    Pb.append(o.P_base_W);
    Hb.append(o.H_base_W);
    kinetic.append(o.kinetic);
    potential.append(o.potential);
    P_scale.append(o.P_scale);
    H_scale.append(o.H_scale);
    return true;
  };
  auto last = std::chrono::steady_clock::now();
  auto poll = [&](double time) -> std::string {
    const auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::milliseconds(200)) return {};
    last = now;
    py::gil_scoped_acquire acquire;
    const std::string at = " at t = " + std::to_string(time) + " s";
    if (PyErr_CheckSignals() != 0) {
      PyErr_Clear();
      return "interrupted (Ctrl-C)" + at;
    }
    try {
      if (!progress.is_none()) progress(time, opt.t_end);
      if (!should_stop.is_none() && should_stop().cast<bool>()) return "stopped by the caller" + at;
    } catch (py::error_already_set& e) {
      return std::string("the progress or stop callback raised: ") + e.what() + at;
    }
    return {};
  };
  mb::RunResult run;
  std::vector<mb::Checkpoint> checkpoints;
  mb::CheckpointOptions cp;
  cp.at = checkpoint_steps;
  cp.resume = resume;
  cp.sink = [&](mb::Checkpoint c) { checkpoints.push_back(std::move(c)); };
  {
    py::gil_scoped_release release;
    run = mb::simulate(model, data, q0, v0, opt, record, poll, &cp);
  }
  const auto& tr = run.trajectory;
  const py::ssize_t n = static_cast<py::ssize_t>(t.size());
  py::dict d;
  d["t"] = py::array_t<double>(n, t.data());
  d["q"] = q.to_numpy(n);
  d["v"] = v.to_numpy(n);
  d["theta"] = theta.to_numpy(n);
  d["theta_rate"] = rate.to_numpy(n);
  d["spring_torque"] = spring.to_numpy(n);
  d["lock_force"] = lock_force.to_numpy(n);
  d["lock_torque"] = lock_torque.to_numpy(n);
  d["latched"] = latched.to_numpy(n);
  d["strain_energy"] = strain.to_numpy(n);
  d["hinge_force"] = hinge_force.to_numpy(n);
  d["hinge_moment"] = hinge_moment.to_numpy(n);
  d["linear_momentum"] = P.to_numpy(n);
  d["angular_momentum"] = Hw.to_numpy(n);
  d["base_linear_momentum"] = Pb.to_numpy(n);
  d["base_angular_momentum"] = Hb.to_numpy(n);
  d["kinetic_energy"] = kinetic.to_numpy(n);
  d["potential_energy"] = potential.to_numpy(n);
  d["momentum_scale_P"] = P_scale.to_numpy(n);
  d["momentum_scale_H"] = H_scale.to_numpy(n);
  d["newton_iterations"] = tr.newton_iterations;
  d["substeps"] = tr.substeps;
  d["steps"] = tr.steps;
  d["rejected"] = tr.rejected;
  d["events"] = tr.events;
  d["contact_steps"] = tr.contact_steps;
  d["impacts"] = impact_table(data.impacts);
  d["factorizations"] = run.factorizations;
  d["failure"] = tr.failure;
  py::list points;
  for (mb::Checkpoint& c : checkpoints) points.append(py::cast(std::move(c)));
  d["checkpoints"] = points;
  return d;
}
