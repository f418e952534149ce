#include "deployfx/body/flexible_body.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "deployfx/fem/constrained_solve.hpp"
#include "deployfx/fem/parity.hpp"
#include "deployfx/math/check.hpp"

namespace deployfx::body {

Fidelity fidelity_from_name(const std::string& value, const std::string& name) {
  if (value == "rigid") return Fidelity::kRigid;
  if (value == "linear") return Fidelity::kLinear;
  if (value == "nonlinear") return Fidelity::kNonlinear;
  if (value == "reduced-linear") return Fidelity::kReducedLinear;
  if (value == "reduced-nonlinear") return Fidelity::kReducedNonlinear;
  throw std::invalid_argument(name + " = '" + value +
                              "' is invalid: must be 'rigid', 'linear', 'nonlinear', 'reduced-linear' or "
                              "'reduced-nonlinear'");
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

}  // namespace

FlexibleBody::FlexibleBody(AppendageSpec spec, const std::string& name, const Eigen::MatrixXd& extra_loads)
    : spec_(std::move(spec)),
      ffi_(spec_.model ? *spec_.model : throw std::invalid_argument(name + ".model is missing")) {
  if (!(spec_.alpha_M >= 0 && std::isfinite(spec_.alpha_M)))
    throw_out_of_range(name + ".alpha_M", spec_.alpha_M, "finite and >= 0 (1/s)");
  if (!(spec_.beta_K >= 0 && std::isfinite(spec_.beta_K)))
    throw_out_of_range(name + ".beta_K", spec_.beta_K, "finite and >= 0 (s)");
  green_ = spec_.fidelity == Fidelity::kNonlinear || spec_.fidelity == Fidelity::kReducedNonlinear;
  const fem::ShellModel& model = *spec_.model;
  if (flexible()) check_clamped(model, spec_.fixed_dofs, name);
  if (spec_.fidelity == Fidelity::kReducedLinear || spec_.fidelity == Fidelity::kReducedNonlinear) {
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
    // Their nonzeros alone (the mesh pattern stores zeros: 31 % of K_L's entries, 72 % of the
    // mass's): the products once per residual (K_L q, the damping's L_c q') form the same sums.
    K_free_ = fem::restrict(model.stiffness(), free_);
    K_free_.prune([](Eigen::Index, Eigen::Index, double value) { return value != 0.0; });
    M_free_ = fem::restrict(ffi_.M(), free_);  // pruned in FloatingFrameInertia
    // K_L, L_c, the M_ij and the tangent stiffness all live on K_L's node-block pattern.
    block_.emplace(model.stiffness(), free_);
    M_vals_ = block_->aligned(ffi_.M());
    K_vals_ = block_->aligned(model.stiffness());
    if (green_) tangent_slots_ = block_->block_slots(model.element_slots());
    align_Mij();
    if (green_ && fem::parity_decoupled(K_free_, free_, kParityTolerance) &&
        fem::parity_decoupled(M_free_, free_, kParityTolerance))
      for (int k = 0; k < static_cast<int>(free_.size()); ++k)
        if (fem::dof_parity(free_[k]) == fem::Parity::kInPlane) in_plane_.push_back(k);
  }
}

void FlexibleBody::align_Mij() {
  for (int im = 0; im < 9; ++im) {
    const Eigen::VectorXd vals = block_->aligned(ffi_.Mij(im / 3, im % 3));
    AlignedNonzeros& nz = Mij_nonzeros_[im];
    for (Eigen::Index n = 0; n < vals.size(); ++n)
      if (vals[n] != 0.0) nz.index.push_back(static_cast<int>(n)), nz.value.push_back(vals[n]);
  }
}

void FlexibleBody::mass_combination(double c_a, const Eigen::Matrix3d& c, Eigen::Ref<Eigen::VectorXd> vals) const {
  vals = c_a * M_vals_;
  for (int im = 0; im < 9; ++im) {
    const double cim = c(im / 3, im % 3);
    if (cim == 0.0) continue;
    const AlignedNonzeros& nz = Mij_nonzeros_[im];
    const int* index = nz.index.data();
    const double* value = nz.value.data();
    for (std::size_t k = 0; k < nz.index.size(); ++k) vals[index[k]] += cim * value[k];
  }
}

Eigen::VectorXd FlexibleBody::full(const Eigen::VectorXd& d_free) const {
  Eigen::VectorXd d;
  full(d_free, d);
  return d;
}

void FlexibleBody::full(const Eigen::VectorXd& d_free, Eigen::VectorXd& d) const {
  d.setZero(ffi_.num_dofs());  // no allocation when d has the size already
  for (int k = 0; k < num_elastic(); ++k) d(free_[k]) = d_free(k);
}

Eigen::MatrixXd FlexibleBody::mesh_rows(const std::vector<int>& mesh_dofs) const {
  const int n = static_cast<int>(mesh_dofs.size());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, num_elastic());
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

void FlexibleBody::add_elastic_force(const Eigen::VectorXd& q_el, const Eigen::VectorXd& v_el,
                                     const Eigen::VectorXd& d, const Eigen::VectorXd& dd,
                                     Eigen::Ref<Eigen::VectorXd> r, Workspace* ws) const {
  const int n = num_elastic();
  if (n == 0) return;
  if (modal_ && green_) {
    // Reduced Green strain: the polynomial force and, for damping, its exact tangent.
    Eigen::VectorXd f;
    Eigen::MatrixXd T;
    modal_->evaluate(q_el, &f, spec_.beta_K > 0 ? &T : nullptr, ws ? &ws->modal : nullptr);
    r += f + spec_.alpha_M * (M_free_ * v_el);
    if (spec_.beta_K > 0) r += spec_.beta_K * (T * v_el);
    return;
  }
  if (spec_.fidelity == Fidelity::kNonlinear) {
    Eigen::VectorXd f_int;
    spec_.model->internal_force(d, &f_int, nullptr);  // Eq. 14 (Green strain)
    for (int i = 0; i < n; ++i) r(i) += f_int(free_[i]);
  } else {
    r += K_free_ * q_el;
  }
  // Rayleigh damping. The stiffness-proportional part acts on the strain rate: beta_K K_L d'
  // for linear strain, beta_K K_T(d) d' = beta_K d/dt f_int(d) for Green strain (K_L d' would
  // damp the in-plane motion that large, inextensional bending needs, and stiffen the plate).
  if (spec_.alpha_M > 0) r += spec_.alpha_M * (M_free_ * v_el);
  if (spec_.fidelity == Fidelity::kNonlinear) {
    const double speed = dd.lpNorm<Eigen::Infinity>();
    if (spec_.beta_K > 0 && speed > 0) {  // K_T(d) d' by a central difference of f_int along d'
      const double eps = 1e-6 / speed;
      Eigen::VectorXd fp, fm;
      spec_.model->internal_force(d + eps * dd, &fp, nullptr);
      spec_.model->internal_force(d - eps * dd, &fm, nullptr);
      for (int i = 0; i < n; ++i) r(i) += spec_.beta_K * (fp(free_[i]) - fm(free_[i])) / (2 * eps);
    }
  } else if (spec_.beta_K > 0) {
    r += spec_.beta_K * (K_free_ * v_el);
  }
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
  vals += c_v * spec_.alpha_M * M_vals_;  // Rayleigh damping
}

Eigen::MatrixXd FlexibleBody::elastic_tangent(const Eigen::VectorXd& q_el, double c_v, double c_q) const {
  Eigen::VectorXd vals = Eigen::VectorXd::Zero(block_->nonzeros());
  add_elastic_block(full(q_el), c_v, c_q, vals);
  return Eigen::MatrixXd(block_->with_values(vals));
}

double FlexibleBody::strain_energy(const Eigen::VectorXd& q_el, const Eigen::VectorXd& d, const Workspace* ws) const {
  if (num_elastic() == 0) return 0.0;
  if (modal_ && green_) return modal_->strain_energy(q_el, ws ? &ws->modal : nullptr);
  if (!green_) return 0.5 * q_el.dot(K_free_ * q_el);
  double U = 0;
  spec_.model->internal_force(d, nullptr, nullptr, &U);
  return U;
}

}  // namespace deployfx::body
