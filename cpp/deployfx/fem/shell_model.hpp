#pragma once
// A mesh of laminated shell elements with assembled sparse operators (world dofs, six per node:
// u_x, u_y, u_z, theta_x, theta_y, theta_z; dof 6 i + k belongs to node i).
// Immutable after construction: the linear stiffness and mass are assembled once.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "deployfx/fem/shell_element.hpp"
#include "deployfx/fem/shell_batch.hpp"
#include "deployfx/material/laminate.hpp"

namespace deployfx::fem {

using SparseMatrix = Eigen::SparseMatrix<double>;
using NodeMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;  // (nodes x 3), m
using QuadMatrix = Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>;     // (elements x 4)

class ShellModel {
 public:
  /// Throws std::invalid_argument for out-of-range node indices, unused nodes or a bad element.
  ShellModel(NodeMatrix nodes, QuadMatrix quads, const material::Laminate& laminate,
             const Eigen::Vector3d& ref_axis = Eigen::Vector3d::UnitX());

  int num_nodes() const { return static_cast<int>(nodes_.rows()); }
  int num_dofs() const { return kNodeDofs * num_nodes(); }
  int num_elements() const { return static_cast<int>(quads_.rows()); }
  const NodeMatrix& nodes() const { return nodes_; }
  const QuadMatrix& quads() const { return quads_; }
  const std::vector<ShellElement>& elements() const { return elements_; }
  /// Whether internal_force()'s force alone, its tangent alone (and add_tangent() without a
  /// force) and in_plane_force() run four elements at a time (fem/shell_batch.hpp: every element
  /// in world axes).
  bool batched_force() const { return !batch_.empty(); }

  const SparseMatrix& stiffness() const { return K_; }  ///< K_L, N/m and N m/rad
  const SparseMatrix& mass() const { return M_; }       ///< consistent mass, kg and kg m^2
  /// Total translational mass (kg): r^T M r for a unit rigid translation r.
  double total_mass() const;
  /// Nodal forces of a uniform pressure (Pa) along each element's normal.
  Eigen::VectorXd pressure_load(double pressure) const;
  /// K_s for uniform membrane resultants N = (N_x, N_y, N_xy) in N/m (element axes).
  SparseMatrix geometric_stiffness(const Eigen::Vector3d& N) const;
  /// K_s with the resultants of the linear strains of the displacement u.
  SparseMatrix geometric_stiffness_from(const Eigen::VectorXd& u) const;
  /// Strain energy of the nonlinear strain field (You et al. 2016 Eq. 14), J, from the elements'
  /// 24-column strain operators: the tests' reference.
  double strain_energy(const Eigen::VectorXd& u) const;
  /// Internal force and tangent stiffness K_L + K_L* + K_s at displacement u (either may be null);
  /// with `energy`, the strain energy from the force's own strains (J, what the engine reports:
  /// a sixth of strain_energy()'s multiply-adds, equal to round-off).
  void internal_force(const Eigen::VectorXd& u, Eigen::VectorXd* f, SparseMatrix* K_T,
                      double* energy = nullptr) const;
  /// internal_force()'s force at the in-plane dofs (u, v, theta_z of each node) into f
  /// (num_dofs()): exact there (ShellElement::in_plane_force); the other rows unspecified (zero,
  /// exact, or partial where elements of other orientations share a node).
  void in_plane_force(const Eigen::VectorXd& u, Eigen::VectorXd* f) const;
  /// For each element e, where its 24 x 24 entries (column-major, k = 0..575) land in the values
  /// of stiffness()'s pattern: element_slots()[576 e + k].
  const std::vector<int>& element_slots() const { return slots_; }
  /// Where add_tangent() puts the elements' entries: `slots` (576 per element, element_slots()'s
  /// layout, < 0 for none) and, formed from them once, their runs: for the column dof q of an
  /// element's node b and its row node a, the six entries (a, u .. theta_z) land in consecutive
  /// values on a node-block pattern (ShellBatch::runs).
  struct TangentSlots {
    std::vector<int> slots, runs;
  };
  /// `slots` with their runs; std::invalid_argument unless they have 576 entries per element.
  TangentSlots tangent_slots(std::vector<int> slots) const;
  /// The tangent K_T(u) added as values[slots[576 e + k]] += coef (K_e)_k, skipping slots < 0:
  /// assembly straight into any array whose entries the caller has mapped the elements' entries
  /// to (a free-dof block's, fem/free_block.hpp), with no sparse matrix in between. With `f`
  /// (num_dofs()), the internal force is added to it too.
  void add_tangent(const Eigen::VectorXd& u, const TangentSlots& slots, double coef, double* values,
                   Eigen::VectorXd* f = nullptr) const;

 private:
  void check_size(const Eigen::VectorXd& u, const char* name) const;
  ElemVec gather(const Eigen::VectorXd& u, int e) const;
  void scatter(const ElemVec& fe, int e, Eigen::VectorXd* f) const;
  // The mesh's node-block pattern and, for each element, where its 24 x 24 entries land in the
  // pattern's values (column-major within the element), so assembly is a scatter with no sort.
  void build_pattern();
  template <class ElementMatrix>
  SparseMatrix assemble(ElementMatrix&& element_matrix) const;

  NodeMatrix nodes_;
  QuadMatrix quads_;
  std::vector<ShellElement> elements_;
  ShellBatch batch_;  // force and tangent four elements at a time (a mesh in world axes), else empty
  SparseMatrix pattern_;               // compressed, zero values
  std::vector<int> slots_;             // (elements x 576): element entry -> pattern_ value index
  TangentSlots pattern_slots_;         // slots_ with their runs (internal_force()'s K_T)
  SparseMatrix K_, M_;
};

}  // namespace deployfx::fem
