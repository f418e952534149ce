#include "deployfx/body/flexible_body.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "deployfx/fem/constrained_solve.hpp"
#include "deployfx/fem/parity.hpp"
#include "deployfx/math/check.hpp"
#include "deployfx/math/sparse_rows.hpp"

namespace deployfx::body {

Fidelity fidelity_from_name(const std::string& value, const std::string& name) {
  if (value == "rigid") return Fidelity::kRigid;
  if (value == "linear") return Fidelity::kLinear;
  if (value == "nonlinear") return Fidelity::kNonlinear;
  if (value == "reduced-linear") return Fidelity::kReducedLinear;
  if (value == "reduced-nonlinear") return Fidelity::kReducedNonlinear;
  if (value == "reduced-manifold") return Fidelity::kReducedManifold;
  throw std::invalid_argument(name + " = '" + value +
                              "' is invalid: must be 'rigid', 'linear', 'nonlinear', 'reduced-linear', "
                              "'reduced-nonlinear' or 'reduced-manifold'");
}

namespace {

// Bending-in-plane entries of K and M below this (relative, fem::parity_decoupled) are round-off,
// as in fem/ritz_basis.cpp: the paper's symmetric lay-ups leave B at 5e-17 of sqrt(|A| |D|).
constexpr double kParityTolerance = 1e-12;

// A deforming panel's clamped dofs must hold it to its frame: its stiffness on the free dofs
// must be definite (the shell's drilling penalty makes it so for any proper support). A panel
// left free to move rigidly against its frame has no elastic equilibrium.
void check_clamped(const fem::ShellModel& model, const std::vector<int>& fixed, const std::string& name) {
  const std::vector<int> free = fem::free_dofs(model.num_dofs(), fixed);
  if (free.empty())
    throw std::invalid_argument(name + ".fixed_dofs clamps every dof of the mesh: a flexible panel needs free "
                                "dofs (use the fidelity 'rigid' for a panel that does not deform)");
  const Eigen::SparseMatrix<double> K = fem::restrict(model.stiffness(), free);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(K);
  const double scale = K.diagonal().cwiseAbs().maxCoeff();
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * scale))
    throw std::invalid_argument(name + ".fixed_dofs leave the panel free to move as a rigid body against its frame "
                                "(its stiffness on the free dofs is singular): clamp its root to the frame, e.g. "
                                "every dof of the root edge's nodes");
}

// The coefficients c of the nine M_ij in the derivatives of the generalized inertial force Q
// (FloatingFrameInertia, Eq. 9) along the panel's own coordinates: c_v dQ/dd' + c_q dQ/dd =
// c_v 2 G_y(w) + c_q (G_y(al) + G_w(w)), G_y(x) = sum_i x_j M_ik - x_k M_ij (i, j, k cyclic),
// G_w(w) = sum w_i w_l M_il - |w|^2 M_ii.
Eigen::Matrix3d mass_coefficients(const Eigen::Vector3d& w, const Eigen::Vector3d& al, double c_v, double c_q) {
  const Eigen::Vector3d x = 2 * c_v * w + c_q * al;
  Eigen::Matrix3d cm = c_q * (w * w.transpose() - w.squaredNorm() * Eigen::Matrix3d::Identity());
  for (int i = 0; i < 3; ++i) {
    const int jn = (i + 1) % 3, l = (i + 2) % 3;
    cm(i, l) += x(jn);
    cm(i, jn) -= x(l);
  }
  return cm;
}

}  // namespace

FlexibleBody::FlexibleBody(AppendageSpec spec, const std::string& name, const Eigen::MatrixXd& extra_loads)
    : spec_(std::move(spec)),
      ffi_(spec_.model ? *spec_.model : throw std::invalid_argument(name + ".model is missing")) {
  if (!(spec_.alpha_M >= 0 && std::isfinite(spec_.alpha_M)))
    throw_out_of_range(name + ".alpha_M", spec_.alpha_M, "finite and >= 0 (1/s)");
  if (!(spec_.beta_K >= 0 && std::isfinite(spec_.beta_K)))
    throw_out_of_range(name + ".beta_K", spec_.beta_K, "finite and >= 0 (s)");
  green_ = spec_.fidelity == Fidelity::kNonlinear || spec_.fidelity == Fidelity::kReducedNonlinear ||
           spec_.fidelity == Fidelity::kReducedManifold;
  const fem::ShellModel& model = *spec_.model;
  if (flexible()) check_clamped(model, spec_.fixed_dofs, name);
  if (spec_.fidelity == Fidelity::kReducedLinear || spec_.fidelity == Fidelity::kReducedNonlinear ||
      spec_.fidelity == Fidelity::kReducedManifold) {
    const int nfree = static_cast<int>(fem::free_dofs(model.num_dofs(), spec_.fixed_dofs).size());
    if (!(spec_.modes >= 1 && spec_.modes <= nfree))
      throw_out_of_range(name + ".modes", spec_.modes, "in [1, " + std::to_string(nfree) + "] (the free dofs)");
    if (extra_loads.cols() > 0 && extra_loads.rows() != ffi_.num_dofs())
      throw std::invalid_argument(name + ": extra_loads must have one row per mesh dof (" +
                                  std::to_string(ffi_.num_dofs()) + "), got " + std::to_string(extra_loads.rows()));
    // The loads E's acceleration puts on the appendage, int rho N^T a and int rho N^T (al x P):
    // S1^T and H(0)^T (Eq. 28); then the caller's.
    Eigen::MatrixXd loads(ffi_.num_dofs(), 6 + extra_loads.cols());
    loads.leftCols<6>() << ffi_.S1().transpose(),
        ffi_.rotation_coupling(Eigen::VectorXd::Zero(ffi_.num_dofs())).transpose();
    if (extra_loads.cols() > 0) loads.rightCols(extra_loads.cols()) = extra_loads;
    if (!(spec_.derivative_modes >= -1 && spec_.derivative_modes <= spec_.modes))
      throw_out_of_range(name + ".derivative_modes", spec_.derivative_modes, "in [0, modes] or -1 (automatic)");
    if (!(spec_.derivative_partners >= -1 && spec_.derivative_partners <= spec_.modes))
      throw_out_of_range(name + ".derivative_partners", spec_.derivative_partners, "in [0, modes] or -1 (automatic)");
    // Automatic: the pairs among the first 3 modes and the first mode's partners (30 vectors on
    // the paper's panel; docs/research/undamped-stability.md: with the first 6 modes' pairs and no
    // partners, modes 7-10 stiffened with the first mode's amplitude and the undamped reduced
    // model was chaotic).
    const int derivatives = spec_.derivative_modes >= 0 ? spec_.derivative_modes : std::min(spec_.modes, 3);
    const int partners = spec_.derivative_partners >= 0 ? spec_.derivative_partners : std::min(spec_.modes, 1);
    basis_ = fem::ritz_basis(model, spec_.fixed_dofs,
                             {spec_.modes, true, green_ ? derivatives : 0, green_ ? partners : 0}, loads);
    modal_.emplace(model, basis_.Phi, green_);
    ffi_ = ffi_.projected(basis_.Phi);
    if (spec_.fidelity == Fidelity::kReducedManifold) {
      std::vector<fem::Parity> parity(static_cast<std::size_t>(basis_.Phi.cols()));
      for (Eigen::Index i = 0; i < basis_.Phi.cols(); ++i) parity[i] = fem::vector_parity(basis_.Phi.col(i));
      manifold_.emplace(*modal_, parity, name);
      modal_.emplace(manifold_->condensed_force(*modal_));
      L_eta_ = Eigen::MatrixXd(ffi_.M());
      for (int im = 0; im < 9; ++im) Mij_eta_[im] = Eigen::MatrixXd(ffi_.Mij(im / 3, im % 3));
      const int n = manifold_->num_coordinates();
      free_ = manifold_->bending();
      K_free_ = modal_->linear_stiffness().sparseView(0.0, 0.0);
      M_free_ = fem::restrict(ffi_.M(), free_);
      std::vector<int> all(static_cast<std::size_t>(n));
      std::iota(all.begin(), all.end(), 0);
      block_.emplace(Eigen::SparseMatrix<double>(Eigen::MatrixXd::Ones(n, n).sparseView()), all);
      return;  // no in-plane coordinates left to relax (in_plane_coordinates())
    }
    const int r = modal_->size();
    free_.resize(r);
    for (int i = 0; i < r; ++i) free_[i] = i;
    K_free_ = modal_->linear_stiffness().sparseView(0.0, 0.0);
    M_free_ = ffi_.M();
    // A dense r x r elastic block: its pattern stores every entry, column-major.
    block_.emplace(Eigen::SparseMatrix<double>(Eigen::MatrixXd::Ones(r, r).sparseView()), free_);
    M_vals_ = block_->aligned(ffi_.M());
    K_vals_ = block_->aligned(K_free_);
    align_Mij();
    // A basis split by parity (fem/ritz_basis.hpp) has every vector exactly in-plane or bending.
    std::vector<int> in_plane;
    bool split = green_;
    for (int i = 0; split && i < r; ++i) {
      const fem::Parity p = fem::vector_parity(basis_.Phi.col(i));
      split = p != fem::Parity::kMixed;
      if (p == fem::Parity::kInPlane) in_plane.push_back(i);
    }
    if (split) in_plane_ = std::move(in_plane);
  } else if (flexible()) {
    free_ = fem::free_dofs(model.num_dofs(), spec_.fixed_dofs);
    for (int k = 0; k < static_cast<int>(free_.size()); ++k)  // full()'s runs of consecutive free dofs
      if (k == 0 || free_[k] != free_[k - 1] + 1) free_runs_.push_back({k, 1});
      else ++free_runs_.back()[1];
    // Their nonzeros alone (the mesh pattern stores zeros: 31 % of K_L's entries, 72 % of the
    // mass's): the product once per residual (K_L q) forms the same sums.
    K_free_ = fem::restrict(model.stiffness(), free_);
    K_free_.prune([](Eigen::Index, Eigen::Index, double value) { return value != 0.0; });
    M_free_ = fem::restrict(ffi_.M(), free_);  // pruned in FloatingFrameInertia
    K_rows_ = K_free_;
    // K_L, L_c, the M_ij and the tangent stiffness all live on K_L's node-block pattern.
    block_.emplace(model.stiffness(), free_);
    M_vals_ = block_->aligned(ffi_.M());
    K_vals_ = block_->aligned(model.stiffness());
    if (green_) tangent_slots_ = model.tangent_slots(block_->block_slots(model.element_slots()));
    align_Mij();
    if (green_ && fem::parity_decoupled(K_free_, free_, kParityTolerance) &&
        fem::parity_decoupled(M_free_, free_, kParityTolerance))
      for (int k = 0; k < static_cast<int>(free_.size()); ++k)
        if (fem::dof_parity(free_[k]) == fem::Parity::kInPlane) in_plane_.push_back(k);
    if (!in_plane_.empty()) {
      std::vector<int> dofs;
      for (const int k : in_plane_) dofs.push_back(free_[k]);
      in_plane_rows_ = ffi_.select_rows(dofs);
    }
  }
}

void FlexibleBody::align_Mij() {
  std::array<Eigen::VectorXd, 9> aligned;
  for (int im = 0; im < 9; ++im) {
    const Eigen::VectorXd& vals = aligned[im] = block_->aligned(ffi_.Mij(im / 3, im % 3));
    AlignedNonzeros& nz = Mij_nonzeros_[im];
    if (modal_) {  // a dense block: every value
      nz.value.assign(vals.data(), vals.data() + vals.size());
      continue;
    }
    for (Eigen::Index n = 0; n < vals.size(); ++n)
      if (vals[n] != 0.0) nz.index.push_back(static_cast<int>(n)), nz.value.push_back(vals[n]);
  }
  if (!modal_) node_mass_blocks_ = NodeMassBlocks::build(*block_, free_, M_vals_, aligned);
}

void FlexibleBody::mass_combination(double c_a, const Eigen::Matrix3d& c, Eigen::Ref<Eigen::VectorXd> vals) const {
  if (node_mass_blocks_) return node_mass_blocks_->combine(c_a, c, vals.data());
  vals = c_a * M_vals_;
  for (int im = 0; im < 9; ++im) {
    const double cim = c(im / 3, im % 3);
    if (cim == 0.0) continue;
    const AlignedNonzeros& nz = Mij_nonzeros_[im];
    if (nz.index.empty() && static_cast<Eigen::Index>(nz.value.size()) == vals.size()) {  // every value (align_Mij)
      vals += cim * Eigen::Map<const Eigen::VectorXd>(nz.value.data(), static_cast<Eigen::Index>(nz.value.size()));
      continue;
    }
    const int* index = nz.index.data();
    const double* value = nz.value.data();
    for (std::size_t k = 0; k < nz.index.size(); ++k) vals[index[k]] += cim * value[k];
  }
}

Eigen::VectorXd FlexibleBody::full(const Eigen::VectorXd& q_el) const {
  Eigen::VectorXd d;
  full(q_el, d);
  return d;
}

void FlexibleBody::full(const Eigen::VectorXd& q_el, Eigen::VectorXd& d) const {
  if (manifold_) return manifold_->map(q_el, d);
  if (free_runs_.empty()) {  // a Ritz basis: every coordinate
    d.setZero(ffi_.num_dofs());  // no allocation when d has the size already
    for (int k = 0; k < num_elastic(); ++k) d(free_[k]) = q_el(k);
    return;
  }
  // A mesh: its runs of free dofs copied, the held ones between them zero.
  const Eigen::Index n = ffi_.num_dofs();
  d.resize(n);
  Eigen::Index next = 0;  // the first dof not yet written
  for (const auto& [k, length] : free_runs_) {
    const Eigen::Index first = free_[k];
    d.segment(next, first - next).setZero();
    d.segment(first, length) = q_el.segment(k, length);
    next = first + length;
  }
  d.tail(n - next).setZero();
}

void FlexibleBody::stage(ElasticState& s) const {
  if (!manifold_) {
    full(s.q, s.d);
    full(s.v, s.dd);
    full(s.a, s.ddd);
    return;
  }
  manifold_->jacobian(s.q, s.G);
  manifold_->map(s.q, s.G, s.d);
  s.dd.noalias() = s.G * s.v;
  s.ddd.noalias() = s.G * s.a;
  manifold_->add_curvature(s.v, s.v, s.ddd);  // d'' = G q'' + C(q', q')
}

Eigen::VectorXd FlexibleBody::coordinates(const Eigen::VectorXd& q_el) const {
  return manifold_ ? full(q_el) : q_el;
}

Eigen::MatrixXd FlexibleBody::coordinates_jacobian(const Eigen::VectorXd& q_el) const {
  if (!manifold_) return Eigen::MatrixXd::Identity(num_elastic(), num_elastic());
  Eigen::MatrixXd G;
  manifold_->jacobian(q_el, G);
  return G;
}

void FlexibleBody::add_projected(const ElasticState& s, const Eigen::VectorXd& Q, Eigen::Ref<Eigen::VectorXd> r) const {
  if (manifold_) {
    r.noalias() += s.G.transpose() * Q;
    return;
  }
  for (int i = 0; i < num_elastic(); ++i) r(i) += Q(free_[i]);
}

Eigen::MatrixXd FlexibleBody::projected(const ElasticState& s, const Eigen::MatrixXd& X) const {
  if (manifold_) return s.G.transpose() * X;
  Eigen::MatrixXd out(num_elastic(), X.cols());
  for (int i = 0; i < num_elastic(); ++i) out.row(i) = X.row(free_[i]);
  return out;
}

Eigen::MatrixXd FlexibleBody::chain(const ElasticState& s, double c_a, const Eigen::MatrixXd& X_ddd, double c_v,
                                    const Eigen::MatrixXd& X_dd, double c_q, const Eigen::MatrixXd& X_d) const {
  const bool with_a = X_ddd.cols() > 0;
  const Eigen::MatrixXd X = with_a ? Eigen::MatrixXd(c_a * X_ddd + c_v * X_dd + c_q * X_d)
                                   : Eigen::MatrixXd(c_v * X_dd + c_q * X_d);
  if (!manifold_) return chain(s, X, Eigen::MatrixXd(), Eigen::MatrixXd());
  // dd = G(q) q', ddd = G(q) q'' + C(q', q'): d(dd)/dq = C(q', .), d(ddd)/dq = C(q'', .),
  // d(ddd)/dq' = 2 C(q', .).
  const Eigen::MatrixXd W_v = with_a ? Eigen::MatrixXd(c_q * X_dd + 2 * c_v * X_ddd) : Eigen::MatrixXd(c_q * X_dd);
  return chain(s, X, W_v, with_a && c_q != 0.0 ? Eigen::MatrixXd(c_q * X_ddd) : Eigen::MatrixXd());
}

Eigen::MatrixXd FlexibleBody::chain(const ElasticState& s, const Eigen::MatrixXd& X, const Eigen::MatrixXd& W_v,
                                    const Eigen::MatrixXd& W_a) const {
  if (!manifold_) {
    Eigen::MatrixXd out(X.rows(), num_elastic());
    for (int i = 0; i < num_elastic(); ++i) out.col(i) = X.col(free_[i]);
    return out;
  }
  Eigen::MatrixXd out = X * s.G, Cx;
  manifold_->derivative(s.v, Cx);
  if (W_v.cols() > 0) out.noalias() += W_v * Cx;
  if (W_a.cols() > 0) {
    manifold_->derivative(s.a, Cx);
    out.noalias() += W_a * Cx;
  }
  return out;
}

Eigen::MatrixXd FlexibleBody::inertia_combination(double c_L, const Eigen::Matrix3d& cm) const {
  Eigen::MatrixXd X = c_L * L_eta_;
  for (int im = 0; im < 9; ++im)
    if (cm(im / 3, im % 3) != 0.0) X += cm(im / 3, im % 3) * Mij_eta_[im];
  return X;
}

Eigen::MatrixXd FlexibleBody::mesh_rows(const std::vector<int>& mesh_dofs) const {
  const int n = static_cast<int>(mesh_dofs.size());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, num_coordinates());
  for (int i = 0; i < n; ++i) {
    const int dof = mesh_dofs[i];
    if (dof < 0 || dof >= spec_.model->num_dofs()) throw std::out_of_range("mesh_rows: dof out of range");
    if (reduced()) {
      out.row(i) = basis_.Phi.row(dof);
    } else {
      const auto it = std::lower_bound(free_.begin(), free_.end(), dof);
      if (it != free_.end() && *it == dof) out(i, it - free_.begin()) = 1.0;
    }
  }
  return out;
}

void FlexibleBody::add_stiffness_product(double c, const Eigen::VectorXd& x, Eigen::Ref<Eigen::VectorXd> r) const {
  if (modal_) r.noalias() += c * (modal_->linear_stiffness() * x);  // K_free_ is its sparse view
  else add_rows_product(c, K_rows_, x, r);
}

void FlexibleBody::add_rows_product(double c, const RowMajorMatrix& A, const Eigen::VectorXd& x,
                                    Eigen::Ref<Eigen::VectorXd> r) {
  Eigen::VectorXd y(A.rows());
  rows_product<1, false>(A, {x.data()}, {y.data()}, c);  // r += c * (A * x) as Eigen forms it
  r += y;
}

bool FlexibleBody::in_plane_force(const ElasticState& s, const Eigen::Vector3d& a, const Eigen::Vector3d& al,
                                  const Eigen::Vector3d& w, Eigen::Ref<Eigen::VectorXd> out, Workspace* ws) const {
  if (!in_plane_rows_) return false;
  const auto m = static_cast<Eigen::Index>(in_plane_.size());
  if (out.size() != m) throw std::invalid_argument("in_plane_force: out must have one entry per in-plane coordinate");
  // add_projected(Q) and add_elastic_force() at these rows, term by term: Q with the Rayleigh
  // damping's alpha_M L_c d' (as the residual's, multibody::inertial_wrench), f_int (Eq. 14) and
  // beta_K K_T(d) d' (by the same central difference, of the rows alone).
  out = ffi_.inertial_force_rows(*in_plane_rows_, a, al, w, s.d, s.dd, s.ddd, spec_.alpha_M);
  Eigen::VectorXd local;
  Eigen::VectorXd& f = ws ? ws->mesh_force : local;
  spec_.model->in_plane_force(s.d, &f);
  for (Eigen::Index i = 0; i < m; ++i) out(i) += f(free_[in_plane_[i]]);
  add_strain_rate_damping(s.d, s.dd, true, out);
  return true;
}

void FlexibleBody::add_strain_rate_damping(const Eigen::VectorXd& d, const Eigen::VectorXd& dd, bool in_plane,
                                           Eigen::Ref<Eigen::VectorXd> r) const {
  // beta_K K_T(d) d' = beta_K d/dt f_int(d), by a central difference of f_int along d' (for linear
  // strain K_L d' would damp the in-plane motion that large, inextensional bending needs, and
  // stiffen the plate). Along the unit direction d' / |d'|, then scaled: a step 1e-6 / |d'|
  // overflows for a denormal |d'| (a fuzz case: inf * 0 in d).
  const double speed = dd.lpNorm<Eigen::Infinity>();
  if (!(spec_.beta_K > 0 && speed > 0)) return;
  const Eigen::VectorXd step = 1e-6 * (dd / speed);
  Eigen::VectorXd fp, fm;
  if (in_plane) {
    spec_.model->in_plane_force(d + step, &fp);
    spec_.model->in_plane_force(d - step, &fm);
  } else {
    spec_.model->internal_force(d + step, &fp, nullptr);
    spec_.model->internal_force(d - step, &fm, nullptr);
  }
  const double scale = spec_.beta_K * speed / 2e-6;
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    const int dof = free_[in_plane ? in_plane_[i] : i];
    r(i) += scale * (fp(dof) - fm(dof));
  }
}

void FlexibleBody::add_elastic_force(const ElasticState& s, Eigen::Ref<Eigen::VectorXd> r, Workspace* ws) const {
  const int n = num_elastic();
  if (n == 0) return;
  const Eigen::VectorXd &q_el = s.q, &v_el = s.v, &d = s.d, &dd = s.dd;
  if (modal_ && green_) {
    // Reduced Green strain: the polynomial force and, for damping, its exact tangent.
    Eigen::VectorXd f;
    Eigen::MatrixXd T;
    modal_->evaluate(q_el, &f, spec_.beta_K > 0 ? &T : nullptr, ws ? &ws->modal : nullptr);
    r += f;
    if (spec_.beta_K > 0) r += spec_.beta_K * (T * v_el);
    return;
  }
  if (spec_.fidelity == Fidelity::kNonlinear) {
    Eigen::VectorXd f_int;
    spec_.model->internal_force(d, &f_int, nullptr);  // Eq. 14 (Green strain)
    for (int i = 0; i < n; ++i) r(i) += f_int(free_[i]);
  } else {
    add_stiffness_product(1.0, q_el, r);
  }
  // Rayleigh damping's stiffness-proportional part, on the strain rate: beta_K K_L d' for linear
  // strain, beta_K K_T(d) d' for Green strain (add_strain_rate_damping).
  if (spec_.fidelity == Fidelity::kNonlinear) {
    add_strain_rate_damping(d, dd, false, r);
  } else if (spec_.beta_K > 0) {
    add_stiffness_product(spec_.beta_K, v_el, r);
  }
}

void FlexibleBody::elastic_block(const ElasticState& s, const Eigen::VectorXd& Q, const Eigen::Vector3d& w,
                                 const Eigen::Vector3d& al, double c_a, double c_v, double c_q,
                                 Eigen::Ref<Eigen::VectorXd> vals, Workspace* ws) const {
  if (manifold_) {
    manifold_block(s, Q, w, al, c_a, c_v, c_q, vals, ws);
    return;
  }
  // The Rayleigh damping's alpha_M L_c d' with the inertial L_c: one pass over the values.
  mass_combination(c_a + c_v * spec_.alpha_M, mass_coefficients(w, al, c_v, c_q), vals);
  add_elastic_block(s.d, c_v, c_q, vals, ws);  // K_T (or K_L), beta_K's damping
}

void FlexibleBody::manifold_block(const ElasticState& s, const Eigen::VectorXd& Q, const Eigen::Vector3d& w,
                                  const Eigen::Vector3d& al, double c_a, double c_v, double c_q,
                                  Eigen::Ref<Eigen::VectorXd> vals, Workspace* ws) const {
  // On eta: dQ/d eta'' = L_c, dQ/d eta' = D_v = 2 G_y(w) + alpha_M L_c (the damping), dQ/d eta =
  // D_q = G_y(al) + G_w(w). On q, the staging's chain rule (chain()) with
  // X = c_a L_c + c_v D_v + c_q D_q, W_v = c_q D_v + 2 c_v L_c and W_a = c_q L_c, each one
  // combination of the M_ij; and G^T's own derivative, sum_k (Q + alpha_M L_c eta')_k d^2 g_k / dq^2.
  const double alpha = spec_.alpha_M;
  const Eigen::MatrixXd X = inertia_combination(c_a + c_v * alpha, mass_coefficients(w, al, c_v, c_q));
  const Eigen::MatrixXd W_v = inertia_combination(2 * c_v + c_q * alpha, mass_coefficients(w, al, c_q, 0.0));
  Eigen::MatrixXd E = projected(s, chain(s, X, W_v, c_q != 0.0 ? Eigen::MatrixXd(c_q * L_eta_) : Eigen::MatrixXd()));
  if (c_q != 0.0) E += c_q * manifold_->contract(Q + spec_.alpha_M * (L_eta_ * s.dd));
  vals = Eigen::Map<const Eigen::VectorXd>(E.data(), E.size());  // every value (elastic_block())
  add_elastic_block(s.q, c_v, c_q, vals, ws);  // the quartic's tangent; beta_K's damping
}

void FlexibleBody::add_elastic_block(const Eigen::VectorXd& d, double c_v, double c_q, Eigen::Ref<Eigen::VectorXd> vals,
                                     Workspace* ws) const {
  if (modal_ && green_) {
    Eigen::MatrixXd T;  // dense, column-major: the block's value order
    modal_->evaluate(d, nullptr, &T, ws ? &ws->modal : nullptr);
    vals += (c_q + c_v * spec_.beta_K) * Eigen::Map<const Eigen::VectorXd>(T.data(), T.size());
  } else if (spec_.fidelity == Fidelity::kNonlinear) {
    // K_L + K_L* + K_s (Eq. 19, 22, 23) and the damping beta_K K_T (its d-derivative dropped).
    spec_.model->add_tangent(d, tangent_slots_, c_q + c_v * spec_.beta_K, vals.data());
  } else {
    vals += (c_q + c_v * spec_.beta_K) * K_vals_;
  }
}

double FlexibleBody::strain_energy(const ElasticState& s, const Workspace* ws) const {
  if (num_elastic() == 0) return 0.0;
  if (modal_ && green_) return modal_->strain_energy(s.q, ws ? &ws->modal : nullptr);
  if (!green_) {
    Eigen::VectorXd Kq = Eigen::VectorXd::Zero(s.q.size());
    add_stiffness_product(1.0, s.q, Kq);
    return 0.5 * s.q.dot(Kq);
  }
  double U = 0;
  spec_.model->internal_force(s.d, nullptr, nullptr, &U);
  return U;
}

}  // namespace deployfx::body
