#include "deployfx/multibody/model.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "deployfx/math/check.hpp"
#include "deployfx/math/so3.hpp"
#include "deployfx/math/sparse_slot.hpp"

namespace deployfx::multibody {

void SpinUpDriver::evaluate(double t, double* theta, double* rate, double* accel) const {
  const double w = 2 * M_PI / t_s;
  if (t <= t_s) {
    *theta = omega_s / t_s * (0.5 * t * t + (std::cos(w * t) - 1) / (w * w));
    *rate = omega_s / t_s * (t - std::sin(w * t) / w);
    *accel = omega_s / t_s * (1 - std::cos(w * t));
  } else {
    *theta = omega_s / t_s * (0.5 * t_s * t_s) + omega_s * (t - t_s);
    *rate = omega_s;
    *accel = 0;
  }
}

void check_rigid_inertia(const std::string& name, const RigidInertia& body, bool definite) {
  // At most kMaxMagnitude (1e50 kg, kg m^2): with hinge arms within 1e4 m the mass matrix and its
  // factorization then stay within the doubles' range (a fuzz case's fitting inertia of 1.8e308
  // overflowed it: "the mass matrix is singular").
  if (definite) {
    require_positive(name + ".mass", body.mass, "(kg)");
    if (!(body.mass <= kMaxMagnitude)) throw_out_of_range(name + ".mass", body.mass, "<= 1e50 (kg)");
  } else if (!(std::isfinite(body.mass) && body.mass >= 0 && body.mass <= kMaxMagnitude)) {
    throw_out_of_range(name + ".mass", body.mass, "finite, >= 0 and <= 1e50 (kg)");
  }
  if (!body.com.allFinite()) throw std::invalid_argument(name + ".com must be 3 finite numbers (m)");
  const Eigen::Matrix3d& J = body.inertia_com;
  const bool symmetric = J.allFinite() && (J - J.transpose()).norm() <= 1e-12 * std::max(1.0, J.norm());
  const double low = symmetric ? Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(J).eigenvalues().minCoeff() : -1.0;
  if (!symmetric || !(definite ? low > 0 : low >= -1e-12 * J.norm()))
    throw std::invalid_argument(name + ".inertia must be symmetric positive " +
                                (definite ? "definite" : "semidefinite") + " (kg m^2)");
  if (!(J.cwiseAbs().maxCoeff() <= kMaxMagnitude))
    throw std::invalid_argument(name + ".inertia must have entries within 1e50 (kg m^2)");
}

namespace {

void check_hinge(const std::string& name, const HingeSpec& h, int k) {
  if (!(h.parent >= -1 && h.parent < k))
    throw std::invalid_argument(name + ".parent = " + std::to_string(h.parent) + " is out of range: must be -1 (the base)" +
                                (k > 0 ? " or an earlier hinge's index in [0, " + std::to_string(k - 1) + "]" : ""));
  // Within 10 km of the parent's origin: a spacecraft's hinges lie within tens of metres, and a
  // point far beyond makes m r^2 swamp every other inertia (a fuzz case at 5e108 m left the mass
  // matrix singular to working precision).
  constexpr double kMaxHingeDistance = 1e4;  // m
  if (!h.point.allFinite() || !(h.point.cwiseAbs().maxCoeff() <= kMaxHingeDistance))
    throw std::invalid_argument(name + ".point must be 3 finite numbers within 1e4 m of the parent's origin (m)");
  if (!(std::abs(h.axis.norm() - 1.0) < 1e-9))
    throw_out_of_range(name + ".axis (its norm)", h.axis.norm(), "1 (a unit vector)");
  const Eigen::Matrix3d& R = h.R_PC0;
  if (!R.allFinite() || (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-9 || R.determinant() < 0)
    throw std::invalid_argument(name + ".R_PC0 must be a rotation matrix");
  // At most kMaxMagnitude in size, as the rigid parts (check_rigid_inertia): a preload of
  // -1.8e308 N m (a fuzz case) overflowed the first residual ("the mass matrix is singular").
  if (!(std::abs(h.tau0) <= kMaxMagnitude))
    throw_out_of_range(name + ".tau0", h.tau0, "finite and within [-1e50, 1e50] (N m)");
  if (!(h.k_theta >= 0 && h.k_theta <= kMaxMagnitude))
    throw_out_of_range(name + ".k_theta", h.k_theta, "finite and >= 0, at most 1e50 (N m/rad)");
  if (!(h.c_theta >= 0 && h.c_theta <= kMaxMagnitude))
    throw_out_of_range(name + ".c_theta", h.c_theta, "finite and >= 0, at most 1e50 (N m s/rad)");
  if (h.driver) {
    require_positive(name + ".spin_up.t_s", h.driver->t_s, "(s)");
    require_finite(name + ".spin_up.omega_s", h.driver->omega_s, "(rad/s)");
    if (h.lock) throw std::invalid_argument(name + ": a hinge with a prescribed angle (spin_up) cannot have a lock");
  }
  if (h.lock) {
    try {
      joint::validate(*h.lock);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(name + "." + e.what());
    }
  }
  check_rigid_inertia(name + ".body", h.body, false);
}

// Two rigid bodies in one frame as one (parallel axes).
RigidInertia merged(const RigidInertia& a, double m, const Eigen::Vector3d& s, const Eigen::Matrix3d& J_O) {
  const double mass = a.mass + m;
  const Eigen::Vector3d first = a.first_moment() + s;
  const Eigen::Matrix3d J = a.inertia_origin() + J_O;
  const Eigen::Vector3d c = mass > 0 ? Eigen::Vector3d(first / mass) : Eigen::Vector3d::Zero();
  return {mass, c, J - mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose())};
}

}  // namespace

Model::Model(TreeSpec spec) : spec_(std::move(spec)) {
  const int N = static_cast<int>(spec_.hinges.size());
  if (N == 0) throw std::invalid_argument("hinges must hold at least one hinge, got 0");
  if (spec_.base.free) check_rigid_inertia("base", spec_.base.inertia, true);
  for (int k = 0; k < N; ++k) check_hinge("hinges[" + std::to_string(k) + "]", spec_.hinges[k], k);
  bodies_.resize(N);
  for (int k = 0; k < N; ++k) {
    const int p = spec_.hinges[k].parent;
    bodies_[k].parent = p;
    if (p >= 0) bodies_[p].children.push_back(k);
    if (p >= 0) {
      bodies_[k].ancestors = bodies_[p].ancestors;
      bodies_[k].ancestors.push_back(p);
    }
  }
  for (int k = N - 1; k >= 0; --k) {  // children have larger indices: their subtrees are complete
    Body& b = bodies_[k];
    b.subtree = {k};
    for (int c : b.children) b.subtree.insert(b.subtree.end(), bodies_[c].subtree.begin(), bodies_[c].subtree.end());
    std::sort(b.subtree.begin(), b.subtree.end());
  }

  // The panels: shape integrals and bases. A reduced panel carrying hinges adds to its basis the
  // static responses to unit loads at each attachment node (the hinges' reactions).
  for (int k = 0; k < N; ++k) {
    const HingeSpec& h = spec_.hinges[k];
    Body& b = bodies_[k];
    b.rigid = h.body;
    b.axis_skew = skew(h.axis);
    b.axis_skew2 = b.axis_skew * b.axis_skew;
    if (!h.panel) continue;
    const std::string name = "hinges[" + std::to_string(k) + "].panel";
    const AppendageSpec& a = *h.panel;
    if (!a.model) throw std::invalid_argument(name + ".model is missing");
    Eigen::MatrixXd loads;
    if (a.fidelity == Fidelity::kReducedLinear || a.fidelity == Fidelity::kReducedNonlinear ||
        a.fidelity == Fidelity::kReducedManifold)
      for (int c : b.children) {
        const Eigen::MatrixXd f = node_unit_loads(*a.model, nearest_node(*a.model, spec_.hinges[c].point));
        loads.conservativeResize(f.rows(), loads.cols() + f.cols());
        loads.rightCols(f.cols()) = f;
      }
    auto panel = std::make_shared<const body::FlexibleBody>(a, name, loads);
    if (panel->flexible()) {
      b.panel = std::move(panel);
    } else {  // the undeformed panel as a rigid body in C, merged with the rigid parts
      const body::FloatingFrameInertia& ffi = panel->inertia();
      b.rigid = merged(b.rigid, ffi.mass(), ffi.S0(), ffi.J0());
    }
  }
  for (int k = 0; k < N; ++k) {  // a hinge turning nothing has no equation of motion
    const Body& b = bodies_[k];
    if (!b.panel && b.children.empty() && b.rigid.mass == 0 && b.rigid.inertia_com.isZero(0.0))
      throw std::invalid_argument("hinges[" + std::to_string(k) + "].body carries no inertia: give the hinge a "
                                  "fitting, a rigid part or a panel (a massless body has no equation of motion)");
  }
  for (int k = 0; k < N; ++k) {
    const int p = bodies_[k].parent;
    if (p >= 0 && bodies_[p].panel) {
      const body::FlexibleBody& parent = *bodies_[p].panel;
      const Eigen::Vector3d& point = spec_.hinges[k].point;
      bodies_[k].attachment = make_attachment(parent, nearest_node(*parent.spec().model, point), point);
    }
  }

  // Coordinates: base, hinge angles, panels.
  nq_ = nv_ = 0;
  if (base_free()) nq_ += kBasePositions, nv_ += kBaseVelocities;
  for (int k = 0; k < N; ++k) {
    if (spec_.hinges[k].driver) {
      driven_ = true;
      continue;
    }
    bodies_[k].iq_theta = nq_++;
    bodies_[k].iv_theta = nv_++;
  }
  nb_ = nv_;
  for (int k = 0; k < N; ++k) {
    Body& b = bodies_[k];
    if (spec_.hinges[k].lock) locks_.push_back(k);
    if (!b.panel) continue;
    panels_.push_back(k);
    b.n_el = b.panel->num_elastic();
    b.iq_el = nq_, b.iv_el = nv_, b.ie = nv_ - nb_;
    nq_ += b.n_el;
    nv_ += b.n_el;
  }
  build_pattern();
  if (base_free())
    for (int i = 0; i < kBaseVelocities; ++i) seeds_.push_back({Seed::kBase, i, 0});
  for (int k = 0; k < N; ++k)
    if (bodies_[k].iv_theta >= 0) seeds_.push_back({Seed::kHinge, k, 0});
  attachment_seed_.assign(static_cast<std::size_t>(N), -1);
  for (int k = 0; k < N; ++k) {
    if (!bodies_[k].attachment) continue;
    attachment_seed_[k] = static_cast<int>(seeds_.size());
    for (int c = 0; c < 6; ++c) seeds_.push_back({Seed::kAttachment, k, c});
  }
}

void Model::build_pattern() {
  const int ne = elastic();
  ElasticPattern& P = pattern_;
  P.body_slots.assign(bodies_.size(), {});
  P.couplings.assign(bodies_.size(), std::nullopt);
  if (ne == 0) {
    P.matrix.resize(0, 0);
    return;
  }
  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> entries;
  for (int k : panels_) {
    const Eigen::SparseMatrix<double>& B = bodies_[k].panel->block().matrix();
    const int o = bodies_[k].ie;
    for (int c = 0; c < B.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(B, c); it; ++it)
        entries.emplace_back(o + static_cast<int>(it.row()), o + c, 0.0);
  }
  bool coupled = false;
  for (std::size_t k = 0; k < bodies_.size(); ++k) {
    const Body& b = bodies_[k];
    if (!b.attachment) continue;
    coupled = true;
    ElasticPattern::Coupling C;
    for (int j : b.subtree)
      for (int i = 0; i < bodies_[j].n_el; ++i) C.rows.push_back(bodies_[j].ie + i);
    const Body& p = bodies_[b.parent];
    for (int c : b.attachment->parent_cols) C.cols.push_back(p.ie + c);
    // The parent's attachment rows take the attachment's own generalized force (A x A).
    std::vector<int> rows = C.rows;
    rows.insert(rows.end(), C.cols.begin(), C.cols.end());
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    C.rows = rows;
    for (int r : C.rows)
      for (int c : C.cols) entries.emplace_back(r, c, 0.0), entries.emplace_back(c, r, 0.0);
    P.couplings[k] = std::move(C);
  }
  P.matrix.resize(ne, ne);
  P.matrix.setFromTriplets(entries.begin(), entries.end());
  P.matrix.makeCompressed();
  std::fill(P.matrix.valuePtr(), P.matrix.valuePtr() + P.matrix.nonZeros(), 0.0);
  P.identity = panels_.size() == 1 && !coupled;
  for (int k : panels_) {
    const Eigen::SparseMatrix<double>& B = bodies_[k].panel->block().matrix();
    const int o = bodies_[k].ie;
    std::vector<int>& slots = P.body_slots[k];
    slots.reserve(static_cast<std::size_t>(B.nonZeros()));
    for (int c = 0; c < B.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(B, c); it; ++it)
        slots.push_back(static_cast<int>(sparse_slot(P.matrix, o + static_cast<int>(it.row()), o + c)));
  }
  for (auto& C : P.couplings) {
    if (!C) continue;
    const Eigen::Index nr = static_cast<Eigen::Index>(C->rows.size()), na = static_cast<Eigen::Index>(C->cols.size());
    C->slots_RA.resize(nr, na);
    C->slots_AR.resize(na, nr);
    for (Eigen::Index i = 0; i < nr; ++i)
      for (Eigen::Index j = 0; j < na; ++j) {
        C->slots_RA(i, j) = static_cast<int>(sparse_slot(P.matrix, C->rows[i], C->cols[j]));
        C->slots_AR(j, i) = static_cast<int>(sparse_slot(P.matrix, C->cols[j], C->rows[i]));
      }
  }
}

Eigen::VectorXd Model::initial_positions() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(nq_);
  if (base_free()) q(3) = 1.0;  // identity quaternion (w, x, y, z)
  return q;
}

Eigen::VectorXd Model::retract(const Eigen::VectorXd& q, const Eigen::VectorXd& dq) const {
  Eigen::VectorXd out = q;
  if (!base_free()) return out += dq;
  out.head<3>() += dq.head<3>();
  const Eigen::Quaterniond Q(q(3), q(4), q(5), q(6));
  const Eigen::Quaterniond Q1 = (Q * quaternion_exp(dq.segment<3>(3))).normalized();  // R_WB exp(dpsi)
  out.segment<4>(3) << Q1.w(), Q1.x(), Q1.y(), Q1.z();
  const Eigen::Index rest = q.size() - kBasePositions;
  out.tail(rest) += dq.tail(rest);
  return out;
}

void Model::check_state(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd* a) const {
  if (q.size() != nq_ || v.size() != nv_ || (a && a->size() != nv_))
    throw std::invalid_argument("q, v, a must have sizes " + std::to_string(nq_) + ", " + std::to_string(nv_) + ", " +
                                std::to_string(nv_) + "; got " + std::to_string(q.size()) + ", " +
                                std::to_string(v.size()) + (a ? ", " + std::to_string(a->size()) : std::string()));
  if (!q.allFinite() || !v.allFinite() || (a && !a->allFinite()))
    throw std::invalid_argument("q, v and a must be finite");
  if (base_free() && !(std::abs(q.segment<4>(3).norm() - 1.0) < 1e-6))
    throw_out_of_range("q[3:7] (the base's quaternion, its norm)", q.segment<4>(3).norm(), "1 (a unit quaternion)");
}

}  // namespace deployfx::multibody
