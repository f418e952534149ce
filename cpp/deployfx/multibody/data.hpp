#pragma once
// What one run changes, kept apart from the immutable Model (MuJoCo's mjData, Pinocchio's Data):
// the contacts' history, the memos of the panels' evaluations and the stages' outputs at the last
// state evaluated. Every engine function takes (const Model&, Data&); one model backs any number
// of Data, so runs on one model are independent (threads included) and bit-identical to serial
// runs. Fields are grouped by the stage that writes them.
#include <Eigen/Core>
#include <vector>

#include "deployfx/body/flexible_body.hpp"
#include "deployfx/integrate/bordered_solver.hpp"
#include "deployfx/joint/lock.hpp"
#include "deployfx/multibody/kinematics.hpp"
#include "deployfx/multibody/model.hpp"

namespace deployfx::multibody {

/// A panel's elastic state at the last evaluation (FlexibleBody::stage).
using PanelState = body::ElasticState;

class Data {
 public:
  explicit Data(const Model& m);

  // History (written by accept() only, on accepted steps): per hinge (unused without a lock).
  std::vector<joint::LockState> locks;
  /// Every contact of every lock wall so far, in order of onset (joint/impact_record.hpp).
  std::vector<joint::Impact> impacts;
  /// The configuration of the last accepted step (what step_bounds resolves at).
  Eigen::VectorXd accepted_q;
  // Memos of the panels' evaluations (per hinge; used for the panels only).
  std::vector<body::FlexibleBody::Workspace> panels;
  /// The mass matrix's solver at a contact's onset (hinge_inverse_inertia, events.cpp): its
  /// elastic block's pattern analysed once a run, not at every onset.
  integrate::BorderedSolver mass_solver;

  // Stage: state (set_state): the joints' and panels' coordinates.
  double t = 0;
  std::vector<JointState<double>> joints;  ///< per hinge
  std::vector<PanelState> elastic;         ///< per hinge (empty vectors without a panel)
  // Stage: forward kinematics.
  TreeMotion<double> motion;
  /// The state the stages above were computed at (a Newton iteration asks for its residual, its
  /// momentum and, for a fresh matrix, its Jacobians at one state: staged once). `staged_a`:
  /// with accelerations (else they were 0).
  Eigen::VectorXd staged_q, staged_v, staged_accel;
  bool staged_a = false;

  // Scratch of the residual and outputs (sizes kept between calls).
  std::vector<Vector6<double>> wrench;  ///< per hinge: its body's inertial wrench
  std::vector<Eigen::VectorXd> Q;       ///< per hinge: its panel's generalized inertial force
  Wrenches<double> wrenches;
  /// Scratch of the derivative passes (seeds.hpp): the seeded state, its motion, the bodies'
  /// wrenches and the backward pass's, on Duals.
  struct Pass {
    BaseMotion<Dual> base;
    std::vector<JointState<Dual>> joints;
    TreeMotion<Dual> motion;
    std::vector<Vector6<Dual>> wrench;
    Wrenches<Dual> wrenches;
  } pass;

  /// Forgets the history: a new run from the configuration q (the locks' start states depend on
  /// their hinge angles: a groove arms the faces the pin is in front of).
  void reset_history(const Model& m, const Eigen::VectorXd& q);
  /// Whether this Data was made for a model of m's shape.
  bool fits(const Model& m) const;

 private:
  int hinges_ = 0, nq_ = 0, nv_ = 0;
};

/// Throws std::invalid_argument unless `d` was made for `m`.
void check_data(const Model& m, const Data& d);

/// Stages `state` and kinematics: the joints' and panels' coordinates from (q, v, a, t) (a may be
/// null: zero accelerations) and the bodies' motion, into d.
void forward_kinematics(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                        const Eigen::VectorXd* a, double t);

}  // namespace deployfx::multibody
