#pragma once
// The inertial part of a Newton matrix's elastic block, c_a L_c + sum_ij c(i, j) M_ij (the
// floating frame's mass matrices, body/floating_frame_inertia.hpp), formed by the mesh's 6 x 6
// node blocks. On a mesh in the x-y plane (FloatingFrameInertia's NodeMass) every M_ij is three
// scalar node-graph matrices m_k (k = 0, 1, 2: the thickness moments I_k) on fixed dofs, and L_c
// = sum_i M_ii plus the drilling inertia on theta_z. With each dof p of a node's (u, v, w,
// theta_x, theta_y, theta_z) its displacement component comp(p) = (x, y, z, y, x, -), order
// ord(p) = (0, 0, 0, 1, 1, -) (translation or fibre rotation r = (theta_y, -theta_x, 0)) and sign
// s(p) = (+, +, +, -, +, +), the block of nodes (a, b) is
//   (c_a I + c)(comp p, comp q) s(p) s(q) m_{ord p + ord q}(a, b),   p, q not theta_z,
//   c_a drill(a, b)                                                    at (theta_z, theta_z),
// zero elsewhere: each entry four multiply-adds from four scalars, written block by block, where
// the sum over the nine M_ij's nonzeros scattered each through memory (2.4 % of the paper's
// nonlinear run).
#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

#include "deployfx/fem/free_block.hpp"

namespace deployfx::body {

class NodeMassBlocks {
 public:
  /// From L_c's and the nine M_ij's values aligned with `block` (fem::FreeBlock::aligned; index
  /// 3 i + j), `free` the block's dofs (mesh dofs, six a node): the node form, if every value of
  /// `block` lies in a 6 x 6 block of two nodes with all their dofs free and every value equals
  /// the formula above to round-off (1e-13 of the largest); nothing otherwise.
  static std::optional<NodeMassBlocks> build(const fem::FreeBlock& block, const std::vector<int>& free,
                                             const Eigen::VectorXd& M, const std::array<Eigen::VectorXd, 9>& Mij);
  /// vals (every value of the block) = c_a L_c + sum_ij c(i, j) M_ij.
  void combine(double c_a, const Eigen::Matrix3d& c, double* vals) const;

 private:
  NodeMassBlocks() = default;
  // The six 6 x 6 coefficient tables of m_0, m_1, m_2 and drill for (c_a, c): T[k][q][p].
  using Tables = std::array<std::array<std::array<double, 6>, 6>, 4>;
  static Tables tables(double c_a, const Eigen::Matrix3d& c);
  struct Block {
    std::array<int, 6> slot;       // column q's first value (row p = 0); rows p = 1..5 follow
    std::array<double, 4> scalar;  // m_0, m_1, m_2, drill of the two nodes
  };
  std::vector<Block> blocks_;
};

}  // namespace deployfx::body
