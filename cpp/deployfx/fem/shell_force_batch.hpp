#pragma once
// The internal force of a mesh of shell elements whose axes are the world's (a flat mesh in the
// x-y plane along x: no rotation between element and world dofs), four elements at a time: the
// force of ShellElement::internal_force (You et al. 2016 Eq. 14 membrane strain, A/B/D resultants,
// MITC4 shear, drilling penalty) with each scalar of that element's formulas a four-lane value,
// one lane an element. One element's force is a few hundred multiply-adds on 3- and 4-vectors,
// which vectorize poorly; across elements every operation fills the register. The per-element
// formulas are the same (ShellElement::evaluate), in lanes; the sums run in their own order
// (round-off apart from the element's). With `in_plane_rows`, the in-plane rows alone (u, v,
// theta_z: the membrane and drilling terms), as ShellElement::in_plane_force.
#include <Eigen/Core>
#include <vector>

#include "deployfx/fem/shell_element.hpp"

namespace deployfx::fem {

class ShellForceBatch {
 public:
  using Lane = Eigen::Array4d;  // one value per element of a batch
  static constexpr int kLanes = 4;

  ShellForceBatch() = default;
  /// The batches of `elements` (node indices in `quads`, (elements x 4)); empty if any element's
  /// axes are not the world's.
  ShellForceBatch(const std::vector<ShellElement>& elements,
                  const Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>& quads);
  bool empty() const { return batches_.empty(); }
  /// f += the elements' internal force at the displacement u (world dofs; f sized); with
  /// `in_plane_rows`, only f's in-plane rows (u, v, theta_z of each node) gain anything.
  void add_force(const Eigen::VectorXd& u, Eigen::VectorXd& f, bool in_plane_rows) const;

 private:
  struct GaussPoint {
    Lane N[4], dNx[4], dNy[4];  // node a's shape function and gradients
    Lane Bs[2][12];             // MITC4 shear on (w, theta_x, theta_y) of the nodes
    Lane weight;                // m^2; zero in a batch's unused lanes
  };
  struct Batch {
    int nodes[4][kLanes];  // node a of lane l's element (a used lane's in unused lanes)
    int lanes;             // elements in the batch
    GaussPoint gp[4];
    Lane A[3][3], B[3][3], D[3][3], As[2][2], drill;  // section constants, drilling modulus
  };
  template <bool kInPlane>
  void add_batch(const Batch& b, const Eigen::VectorXd& u, Eigen::VectorXd& f) const;
  std::vector<Batch> batches_;
};

}  // namespace deployfx::fem
