#include "deployfx/fem/shell_model.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include "deployfx/math/sparse_slot.hpp"

namespace deployfx::fem {

ShellModel::ShellModel(NodeMatrix nodes, QuadMatrix quads, const material::Laminate& laminate,
                       const Eigen::Vector3d& ref_axis)
    : nodes_(std::move(nodes)), quads_(std::move(quads)) {
  if (nodes_.rows() == 0) throw std::invalid_argument("ShellModel.nodes is empty");
  if (quads_.rows() == 0) throw std::invalid_argument("ShellModel.quads is empty");
  if (!nodes_.allFinite()) throw std::invalid_argument("ShellModel.nodes has non-finite entries");
  std::vector<char> used(nodes_.rows(), 0);
  elements_.reserve(quads_.rows());
  for (int e = 0; e < quads_.rows(); ++e) {
    Eigen::Matrix<double, 4, 3> X;
    for (int a = 0; a < 4; ++a) {
      const int n = quads_(e, a);
      if (n < 0 || n >= nodes_.rows())
        throw std::invalid_argument("ShellModel.quads[" + std::to_string(e) + "] = node " +
                                    std::to_string(n) + " is out of range: must be in [0, " +
                                    std::to_string(nodes_.rows() - 1) + "]");
      used[n] = 1;
      X.row(a) = nodes_.row(n);
    }
    try {
      elements_.emplace_back(X, ref_axis, laminate);
    } catch (const std::invalid_argument& err) {
      throw std::invalid_argument("ShellModel.quads[" + std::to_string(e) + "]: " + err.what());
    }
  }
  for (int n = 0; n < nodes_.rows(); ++n)
    if (!used[n])
      throw std::invalid_argument("ShellModel.nodes[" + std::to_string(n) +
                                  "] belongs to no element (its dofs would be singular)");
  build_pattern();
  batch_ = ShellBatch(elements_, quads_);
  K_ = assemble([](const ShellElement& el, int) { return el.stiffness(); });
  M_ = assemble([](const ShellElement& el, int) { return el.mass(); });
}

void ShellModel::build_pattern() {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(num_elements()) * kElementDofs * kElementDofs);
  for (int e = 0; e < num_elements(); ++e)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        for (int i = 0; i < kNodeDofs; ++i)
          for (int j = 0; j < kNodeDofs; ++j)
            t.emplace_back(kNodeDofs * quads_(e, a) + i, kNodeDofs * quads_(e, b) + j, 0.0);
  pattern_.resize(num_dofs(), num_dofs());
  pattern_.setFromTriplets(t.begin(), t.end());
  pattern_.makeCompressed();
  slots_.resize(static_cast<std::size_t>(num_elements()) * kElementDofs * kElementDofs);
  std::size_t k = 0;
  for (int e = 0; e < num_elements(); ++e)
    for (int c = 0; c < kElementDofs; ++c)
      for (int r = 0; r < kElementDofs; ++r) {
        const int row = kNodeDofs * quads_(e, r / kNodeDofs) + r % kNodeDofs;
        const int col = kNodeDofs * quads_(e, c / kNodeDofs) + c % kNodeDofs;
        slots_[k++] = static_cast<int>(sparse_slot(pattern_, row, col));
      }
  pattern_slots_ = tangent_slots(slots_);
}

ShellModel::TangentSlots ShellModel::tangent_slots(std::vector<int> slots) const {
  if (slots.size() != static_cast<std::size_t>(num_elements()) * kElementDofs * kElementDofs)
    throw std::invalid_argument("slots must have 576 entries per element (" +
                                std::to_string(num_elements() * kElementDofs * kElementDofs) + "), got " +
                                std::to_string(slots.size()));
  TangentSlots out;
  out.runs = ShellBatch::runs(slots);
  out.slots = std::move(slots);
  return out;
}

template <class ElementMatrix>
SparseMatrix ShellModel::assemble(ElementMatrix&& element_matrix) const {
  SparseMatrix A = pattern_;
  double* values = A.valuePtr();
  constexpr int kEntries = kElementDofs * kElementDofs;
  for (int e = 0; e < num_elements(); ++e) {
    const ElemMat Ke = element_matrix(elements_[e], e);
    const int* slot = slots_.data() + static_cast<std::size_t>(e) * kEntries;
    for (int k = 0; k < kEntries; ++k) values[slot[k]] += Ke.data()[k];
  }
  return A;
}

void ShellModel::check_size(const Eigen::VectorXd& u, const char* name) const {
  if (u.size() != num_dofs())
    throw std::invalid_argument(std::string(name) + " has wrong size: expected " +
                                std::to_string(num_dofs()) + " (6 per node), got " +
                                std::to_string(u.size()));
  if (!u.allFinite()) throw std::invalid_argument(std::string(name) + " has non-finite entries");
}

ElemVec ShellModel::gather(const Eigen::VectorXd& u, int e) const {
  ElemVec d;
  for (int a = 0; a < 4; ++a)
    d.segment<kNodeDofs>(kNodeDofs * a) = u.segment<kNodeDofs>(kNodeDofs * quads_(e, a));
  return d;
}

void ShellModel::scatter(const ElemVec& fe, int e, Eigen::VectorXd* f) const {
  for (int a = 0; a < 4; ++a)
    f->segment<kNodeDofs>(kNodeDofs * quads_(e, a)) += fe.segment<kNodeDofs>(kNodeDofs * a);
}

double ShellModel::total_mass() const {
  Eigen::VectorXd r = Eigen::VectorXd::Zero(num_dofs());
  for (int n = 0; n < num_nodes(); ++n) r(kNodeDofs * n) = 1.0;
  return r.dot(M_ * r);
}

Eigen::VectorXd ShellModel::pressure_load(double pressure) const {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(num_dofs());
  for (int e = 0; e < num_elements(); ++e) {
    const ElemVec fe = elements_[e].pressure_load(pressure);
    scatter(fe, e, &f);
  }
  return f;
}

SparseMatrix ShellModel::geometric_stiffness(const Eigen::Vector3d& N) const {
  return assemble([&](const ShellElement& el, int) { return el.geometric_stiffness(N); });
}

SparseMatrix ShellModel::geometric_stiffness_from(const Eigen::VectorXd& u) const {
  check_size(u, "u");
  return assemble(
      [&](const ShellElement& el, int e) { return el.geometric_stiffness_from(gather(u, e)); });
}

double ShellModel::strain_energy(const Eigen::VectorXd& u) const {
  check_size(u, "u");
  double U = 0;
  for (int e = 0; e < num_elements(); ++e) U += elements_[e].strain_energy(gather(u, e));
  return U;
}

void ShellModel::internal_force(const Eigen::VectorXd& u, Eigen::VectorXd* f, SparseMatrix* K_T,
                                double* energy) const {
  check_size(u, "u");
  if (f) f->setZero(num_dofs());
  if (K_T) {  // and f with it
    *K_T = pattern_;
    add_tangent(u, pattern_slots_, 1.0, K_T->valuePtr(), f);
    f = nullptr;
  }
  if (energy) *energy = 0;
  if (!f && !energy) return;
  if (!batch_.empty() && !energy) return batch_.add_force(u, *f, false);
  if (!batch_.empty() && !f) {  // the energy alone (an output's)
    *energy = batch_.strain_energy(u);
    return;
  }
  for (int e = 0; e < num_elements(); ++e) {
    ElemVec fe;
    double Ue = 0;
    elements_[e].internal_force(gather(u, e), f ? &fe : nullptr, nullptr, energy ? &Ue : nullptr);
    if (f) scatter(fe, e, f);
    if (energy) *energy += Ue;
  }
}

void ShellModel::in_plane_force(const Eigen::VectorXd& u, Eigen::VectorXd* f) const {
  check_size(u, "u");
  f->setZero(num_dofs());
  if (!batch_.empty()) return batch_.add_force(u, *f, true);
  for (int e = 0; e < num_elements(); ++e) {
    ElemVec fe;
    elements_[e].in_plane_force(gather(u, e), &fe);
    scatter(fe, e, f);
  }
}

void ShellModel::add_tangent(const Eigen::VectorXd& u, const TangentSlots& ts, double coef, double* values,
                             Eigen::VectorXd* f) const {
  check_size(u, "u");
  constexpr int kEntries = kElementDofs * kElementDofs;
  const std::vector<int>& slots = ts.slots;
  if (slots.size() != slots_.size() || ts.runs.size() != slots.size() / kEntries * ShellBatch::kRuns)
    throw std::invalid_argument("add_tangent: slots must be tangent_slots() of this model's " +
                                std::to_string(num_elements()) + " elements");
  if (!f && !batch_.empty()) return batch_.add_tangent(u, ts.slots, ts.runs, coef, values);
  // Entry k of the node-major element tangent the slots are given for is entry type_major[k] of
  // the type-major one (ShellElement::tangent_type_major), read in the slots' order: a node's six
  // rows are adjacent in the values.
  const std::array<int, kEntries>& type_major = ShellElement::type_major_index();
  for (int e = 0; e < num_elements(); ++e) {
    ElemVec fe;
    ElemMat Ke;
    const int* slot = slots.data() + static_cast<std::size_t>(e) * kEntries;
    if (!f && elements_[e].tangent_type_major(gather(u, e), &Ke)) {
      for (int k = 0; k < kEntries; ++k)
        if (slot[k] >= 0) values[slot[k]] += coef * Ke.data()[type_major[k]];
      continue;
    }
    elements_[e].internal_force(gather(u, e), f ? &fe : nullptr, &Ke);
    if (f) scatter(fe, e, f);
    for (int k = 0; k < kEntries; ++k)
      if (slot[k] >= 0) values[slot[k]] += coef * Ke.data()[k];
  }
}

}  // namespace deployfx::fem
