#include "deployfx/body/node_mass_blocks.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "deployfx/fem/shell_element.hpp"

namespace deployfx::body {

using fem::kNodeDofs;

namespace {
// Per dof of a node (u, v, w, theta_x, theta_y, theta_z): the displacement component it moves,
// translation (0) or fibre rotation (1), and its sign in r = (theta_y, -theta_x, 0) (header).
constexpr int kComp[kNodeDofs] = {0, 1, 2, 1, 0, -1};
constexpr int kOrder[kNodeDofs] = {0, 0, 0, 1, 1, -1};
constexpr double kSign[kNodeDofs] = {1, 1, 1, -1, 1, 1};
constexpr int kDrill = 5;
}  // namespace

NodeMassBlocks::Tables NodeMassBlocks::tables(double c_a, const Eigen::Matrix3d& c) {
  const Eigen::Matrix3d K = c_a * Eigen::Matrix3d::Identity() + c;
  Tables T{};
  for (int q = 0; q < kNodeDofs; ++q)
    for (int p = 0; p < kNodeDofs; ++p) {
      if (p == kDrill || q == kDrill) continue;
      T[kOrder[p] + kOrder[q]][q][p] = K(kComp[p], kComp[q]) * kSign[p] * kSign[q];
    }
  T[3][kDrill][kDrill] = c_a;
  return T;
}

std::optional<NodeMassBlocks> NodeMassBlocks::build(const fem::FreeBlock& block, const std::vector<int>& free,
                                                    const Eigen::VectorXd& M,
                                                    const std::array<Eigen::VectorXd, 9>& Mij) {
  const auto& A = block.matrix();
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  NodeMassBlocks out;
  std::unordered_map<long, int> index;  // node pair (a, b) -> its block
  const long nodes = free.empty() ? 0 : *std::max_element(free.begin(), free.end()) / kNodeDofs + 1;
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    const int b = free[j] / kNodeDofs, q = free[j] % kNodeDofs;
    for (int k = outer[j]; k < outer[j + 1]; k += kNodeDofs) {
      // A run of six: rows (a, 0) .. (a, 5), consecutive.
      if (k + kNodeDofs > outer[j + 1]) return std::nullopt;
      const int i = inner[k];
      if (free[i] % kNodeDofs != 0) return std::nullopt;
      for (int t = 1; t < kNodeDofs; ++t)
        if (inner[k + t] != i + t || free[i + t] != free[i] + t) return std::nullopt;
      const long key = static_cast<long>(free[i] / kNodeDofs) * nodes + b;
      auto [it, added] = index.emplace(key, static_cast<int>(out.blocks_.size()));
      if (added) {
        Block blk;
        blk.slot.fill(-1);
        out.blocks_.push_back(blk);
      }
      int& slot = out.blocks_[static_cast<std::size_t>(it->second)].slot[static_cast<std::size_t>(q)];
      if (slot >= 0) return std::nullopt;
      slot = k;
    }
  }
  // Every block whole (its six columns), its scalars read off M_00 and L_c, and every value of the
  // ten matrices the formula's.
  const double scale = std::max(M.lpNorm<Eigen::Infinity>(), 1e-300);
  std::array<Tables, 10> T;
  T[9] = tables(1.0, Eigen::Matrix3d::Zero());
  for (int ij = 0; ij < 9; ++ij) {
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    c(ij / 3, ij % 3) = 1.0;
    T[ij] = tables(0.0, c);
  }
  for (Block& blk : out.blocks_) {
    if (*std::min_element(blk.slot.begin(), blk.slot.end()) < 0) return std::nullopt;
    blk.scalar = {Mij[0][blk.slot[0]], Mij[0][blk.slot[4]], Mij[0][blk.slot[4] + 4], M[blk.slot[kDrill] + kDrill]};
    for (int m = 0; m < 10; ++m) {
      const Eigen::VectorXd& values = m < 9 ? Mij[static_cast<std::size_t>(m)] : M;
      for (int q = 0; q < kNodeDofs; ++q)
        for (int p = 0; p < kNodeDofs; ++p) {
          double formula = 0;
          for (int k = 0; k < 4; ++k) formula += T[m][k][q][p] * blk.scalar[k];
          if (!(std::abs(values[blk.slot[q] + p] - formula) <= 1e-13 * scale)) return std::nullopt;
        }
    }
  }
  return out;
}

void NodeMassBlocks::combine(double c_a, const Eigen::Matrix3d& c, double* vals) const {
  const Tables T = tables(c_a, c);
  for (const Block& blk : blocks_) {
    const double m0 = blk.scalar[0], m1 = blk.scalar[1], m2 = blk.scalar[2], drill = blk.scalar[3];
    for (int q = 0; q < kNodeDofs; ++q) {
      double* v = vals + blk.slot[q];
      for (int p = 0; p < kNodeDofs; ++p)
        v[p] = T[0][q][p] * m0 + T[1][q][p] * m1 + T[2][q][p] * m2 + T[3][q][p] * drill;
    }
  }
}

}  // namespace deployfx::body
