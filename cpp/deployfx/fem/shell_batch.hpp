#pragma once
// A mesh of shell elements whose axes are the world's (a flat mesh in the x-y plane along x: no
// rotation between element and world dofs), four elements at a time: the force of
// ShellElement::internal_force (You et al. 2016 Eq. 14 membrane strain, A/B/D resultants, MITC4
// shear, drilling penalty) and its type-major tangent (ShellElement::tangent_type_major: K_L +
// K_L* + K_s, Eq. 19-23), with each scalar of that element's formulas a four-lane value, one
// lane an element. One element's force is a few hundred multiply-adds on 3- and 4-vectors, its
// tangent a few thousand on 3 x 12 operators, which vectorize poorly; across elements every
// operation fills the register. The per-element formulas are the same (ShellElement::evaluate),
// in lanes; the sums run in their own order (round-off apart from the element's). With
// `in_plane_rows`, the force's in-plane rows alone (u, v, theta_z: the membrane and drilling
// terms), as ShellElement::in_plane_force.
#include <Eigen/Core>
#include <vector>

#include "deployfx/fem/shell_element.hpp"

namespace deployfx::fem {

class ShellBatch {
 public:
  using Lane = Eigen::Array4d;  // one value per element of a batch
  static constexpr int kLanes = 4;

  ShellBatch() = default;
  /// The batches of `elements` (node indices in `quads`, (elements x 4)); empty if any element's
  /// axes are not the world's.
  ShellBatch(const std::vector<ShellElement>& elements,
                  const Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>& quads);
  bool empty() const { return batches_.empty(); }
  /// f += the elements' internal force at the displacement u (world dofs; f sized); with
  /// `in_plane_rows`, only f's in-plane rows (u, v, theta_z of each node) gain anything.
  void add_force(const Eigen::VectorXd& u, Eigen::VectorXd& f, bool in_plane_rows) const;
  /// The elements' strain energy at u (J), from the force's strains (ShellElement::evaluate's
  /// `energy`, round-off apart).
  double strain_energy(const Eigen::VectorXd& u) const;
  /// The runs of `slots` (576 per element, ShellModel::add_tangent's): for element e, the column
  /// dof q of its node b and its row node a, runs[kRuns e + 24 b + 4 q + a] is the slot of entry
  /// (a, u) when the six entries (a, u .. theta_z) land in consecutive slots, -1 when none lands,
  /// -2 otherwise (entry by entry).
  static constexpr int kRuns = 4 * kNodeDofs * 4;
  static std::vector<int> runs(const std::vector<int>& slots);
  /// values[slots[576 e + k]] += coef (K_e)_k for the tangent K_e of element e at u, entry k of
  /// its node-major 24 x 24 (column-major), slots < 0 skipped (ShellModel::add_tangent's contract),
  /// six consecutive values at a time where `runs` (runs(slots)) has them.
  void add_tangent(const Eigen::VectorXd& u, const std::vector<int>& slots, const std::vector<int>& runs,
                   double coef, double* values) const;

 private:
  struct GaussPoint {
    Lane N[4], dNx[4], dNy[4];  // node a's shape function and gradients
    Lane Bs[2][12];             // MITC4 shear on (w, theta_x, theta_y) of the nodes
    Lane weight;                // m^2; zero in a batch's unused lanes
    Lane wA[3][3], wBBb[3][8], wAsBs[2][12];  // the tangent's (ShellElement::TangentOperators)
  };
  struct Batch {
    int first;             // the first element's index (lane l: first + l)
    int nodes[4][kLanes];  // node a of lane l's element (a used lane's in unused lanes)
    int lanes;             // elements in the batch
    GaussPoint gp[4];
    Lane A[3][3], B[3][3], D[3][3], As[2][2], drill;  // section constants, drilling modulus
    // The tangent's constant blocks ([c][r]): bending and shear on (theta_x, theta_y), and the
    // drilling penalty's corners (u, v) x theta_z, theta_z x (u, v), theta_z x theta_z
    // (ShellElement::rotation_tangent, drilling_tangent).
    Lane K_rot[8][8], drill_uv_tz[4][8], drill_tz_uv[8][4], drill_tz_tz[4][4];
  };
  void gather(const Batch& b, const Eigen::VectorXd& u, Lane (&X)[6][4]) const;
  template <bool kInPlane>
  void add_batch(const Batch& b, const Eigen::VectorXd& u, Eigen::VectorXd& f) const;
  // Lane l's type-major tangent, column-major (entry r + 24 c), into Kt.
  void batch_tangent(const Batch& b, const Eigen::VectorXd& u, Lane* Kt) const;
  std::vector<Batch> batches_;
};

}  // namespace deployfx::fem
