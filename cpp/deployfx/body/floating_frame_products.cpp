// FloatingFrameInertia's nine products M_ij z, from which every d-dependent integral is built:
// dense in a Ritz basis, by the mesh's nodes where its kinematics split so (the header's
// NodeMass), else by the sparse M_ij.
//
// By nodes: where every element's kinematics is, at each Gauss point, N0 = N_a [I3 0] and
// N1 = N_a [0 J] on node a's dofs (u, v, w, theta), with J theta = (theta_y, -theta_x, 0), the
// fibre rotation of a mid-surface in the x-y plane (ShellElement::kinematics), the integrand of
// M_ij = int rho N_i^T N_j (N_i row i of N0 + z N1) is through the thickness I0 N0_i^T N0_j +
// I1 (N0_i^T N1_j + N1_i^T N0_j) + I2 N1_i^T N1_j, so M_ij is three scalar matrices on the node
// graph, m_k(a, b) = sum I_k w N_a N_b (k = 0, 1, 2), with fixed dofs. With z's translations t and fibre rotations r = J theta at each
// node, (M_ij z) at node a is
//   at its translation i:                    (m_0 t_j + m_1 r_j)(a),
//   at theta_y (i = x), at theta_x (i = y):   +-(m_1 t_j + m_2 r_j)(a) (J's signs),
// and zero at every other dof: all nine from one pass over the node graph, about 10 multiply-adds
// per neighbour against the nine sparse products' 25 (the paper's 15 x 10 panel: 1056 dofs).
#include <algorithm>
#include <array>
#include <vector>

#include "deployfx/body/floating_frame_inertia.hpp"
#include "deployfx/math/sparse_rows.hpp"

namespace deployfx::body {

using fem::kNodeDofs;

namespace {

// y_v = A z_v (A column-major: scattered by row) and yt_v = A^T z_v (gathered by column) for V
// vectors in one pass over A: each sum in the order of Eigen's sparse product (column by column,
// from zero); the gathered sums hide the scatter's latency (by rows: two passes, no faster).
template <int V>
void sparse_pass(const Eigen::SparseMatrix<double>& A, const std::array<const double*, V>& z,
                 const std::array<double*, V>& y, const std::array<double*, V>& yt) {
  const Eigen::Index n = A.cols();
  const int* outer = A.outerIndexPtr();
  const int* row = A.innerIndexPtr();
  const double* val = A.valuePtr();
  for (int v = 0; v < V; ++v) std::fill(y[v], y[v] + A.rows(), 0.0);
  for (Eigen::Index c = 0; c < n; ++c) {
    std::array<double, V> zc, sum;
    for (int v = 0; v < V; ++v) zc[v] = z[v][c], sum[v] = 0;
    for (int k = outer[c]; k < outer[c + 1]; ++k)
      for (int v = 0; v < V; ++v) {
        y[v][row[k]] += val[k] * zc[v];
        sum[v] += val[k] * z[v][row[k]];
      }
    for (int v = 0; v < V; ++v) yt[v][c] = sum[v];
  }
}

#if defined(__GNUC__)
#define DEPLOYFX_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define DEPLOYFX_ALWAYS_INLINE inline
#endif

// Node a's sums over its neighbours b on the node graph (m_0, m_1, m_2: the header's NodeMass, one
// pattern) for V vectors z (t, r: z's translations and fibre rotations r = (theta_y, -theta_x, 0)
// at b): s(0..2) = (m_0 t + m_1 r)(a), and with kMoments s(3..5) = (m_1 t + m_2 r)(a). Inlined
// into its loops (a call per node cost the products 4 us on the paper's mesh).
template <bool kMoments, int V>
DEPLOYFX_ALWAYS_INLINE void node_sums(const Eigen::SparseMatrix<double, Eigen::RowMajor>* m, Eigen::Index a,
                                      const std::array<const double*, V>& z,
                                      std::array<Eigen::Matrix<double, 6, 1>, V>& s) {
  const int* outer = m[0].outerIndexPtr();
  const int* inner = m[0].innerIndexPtr();
  const double *m0 = m[0].valuePtr(), *m1 = m[1].valuePtr(), *m2 = m[2].valuePtr();
  for (int v = 0; v < V; ++v) s[v].setZero();
  for (int p = outer[a]; p < outer[a + 1]; ++p) {
    const Eigen::Index b = inner[p];
    for (int v = 0; v < V; ++v) {
      const double* zb = z[v] + kNodeDofs * b;
      const double rx = zb[4], ry = -zb[3];
      s[v](0) += m0[p] * zb[0] + m1[p] * rx;
      s[v](1) += m0[p] * zb[1] + m1[p] * ry;
      s[v](2) += m0[p] * zb[2];
      if constexpr (kMoments) {
        s[v](3) += m1[p] * zb[0] + m2[p] * rx;
        s[v](4) += m1[p] * zb[1] + m2[p] * ry;
        s[v](5) += m1[p] * zb[2];
      }
    }
  }
}

}  // namespace

template <int V>
void FloatingFrameInertia::compute_products(const std::array<const Eigen::VectorXd*, V>& z,
                                            const std::array<Eigen::VectorXd*, V>& out) const {
  const Eigen::Index n = z[0]->size();
  for (int v = 0; v < V; ++v) out[v]->resize(9 * n);
  if (dense_) {
    for (int v = 0; v < V; ++v) out[v]->noalias() = Mij_stacked_ * *z[v];
    return;
  }
  if (!node_mass_.empty()) return node_products<V>(z, out);
  // With M_ji = M_ij^T, the M_ij with i <= j give all nine: one pass over M_ij (column-major)
  // gives both y = M_ij z (scattered by row) and y' = M_ji z (gathered by column), and M_ii z is
  // gathered by rows (math/sparse_rows.hpp: 8 % of inertial_forces() on the paper's 15 x 10
  // mesh); the V vectors share each pass (their sums' chains interleave).
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      std::array<const double*, V> zv;
      std::array<double*, V> y, yt;
      for (int v = 0; v < V; ++v) {
        zv[v] = z[v]->data();
        y[v] = out[v]->data() + (3 * i + j) * n;
        yt[v] = out[v]->data() + (3 * j + i) * n;
      }
      if (i == j) rows_product<V, false>(Mii_rows_[i], zv, y);
      else sparse_pass<V>(Mij_[3 * i + j], zv, y, yt);
    }
}

FloatingFrameInertia::NodeMass FloatingFrameInertia::node_mass(const fem::ShellModel& model) {
  const int nodes = model.num_dofs() / kNodeDofs;
  std::array<std::vector<Eigen::Triplet<double>>, 3> t;
  for (int e = 0; e < model.num_elements(); ++e) {
    const fem::ShellElement& el = model.elements()[e];
    const double I[3] = {el.I0(), el.I1(), el.I2()};
    for (int q = 0; q < 4; ++q) {
      const fem::ShellElement::Kinematics g = el.kinematics(q);
      for (int a = 0; a < 4; ++a) {
        // The shape function of node a, and the operators' exact pattern on its dofs.
        const double N = g.N0(0, kNodeDofs * a);
        for (int i = 0; i < 3; ++i)
          for (int c = 0; c < kNodeDofs; ++c) {
            const double n0 = i == c ? N : 0.0;
            const double n1 = (i == 0 && c == 4) ? N : (i == 1 && c == 3) ? -N : 0.0;
            if (g.N0(i, kNodeDofs * a + c) != n0 || g.N1(i, kNodeDofs * a + c) != n1) return {};
          }
        for (int b = 0; b < 4; ++b)
          for (int k = 0; k < 3; ++k)
            t[k].emplace_back(model.quads()(e, a), model.quads()(e, b), g.weight * I[k] * N * g.N0(0, kNodeDofs * b));
      }
    }
  }
  NodeMass out;
  for (int k = 0; k < 3; ++k) {  // one pattern: the same triplets' positions, zeros kept
    out.m[k].resize(nodes, nodes);
    out.m[k].setFromTriplets(t[k].begin(), t[k].end());
  }
  return out;
}

template <int V>
void FloatingFrameInertia::node_products(const std::array<const Eigen::VectorXd*, V>& z,
                                         const std::array<Eigen::VectorXd*, V>& out) const {
  const Eigen::Index n = num_dofs();
  std::array<const double*, V> zv;
  for (int v = 0; v < V; ++v) out[v]->setZero(), zv[v] = z[v]->data();
  std::array<Eigen::Matrix<double, 6, 1>, V> s;
  for (Eigen::Index a = 0; a < node_mass_.m[0].rows(); ++a) {
    node_sums<true, V>(node_mass_.m.data(), a, zv, s);
    for (int v = 0; v < V; ++v) {
      double* P = out[v]->data();
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) P[(3 * i + j) * n + kNodeDofs * a + i] = s[v](j);
      for (int j = 0; j < 3; ++j) {
        P[(3 * 0 + j) * n + kNodeDofs * a + 4] = s[v](3 + j);   // theta_y: +r_x
        P[(3 * 1 + j) * n + kNodeDofs * a + 3] = -s[v](3 + j);  // theta_x: -r_y
      }
    }
  }
}

void FloatingFrameInertia::node_row_products(const RowSelection& rows, const Eigen::VectorXd& d,
                                             const Eigen::VectorXd& dd, Eigen::VectorXd& P,
                                             Eigen::VectorXd& R) const {
  // The rows are in-plane dofs (select_rows()): at u (v) of node a, M_(c j) z is s_j(a) for c = x
  // (y) and zero for the other components; at theta_z every M_k z is zero (node_products()).
  const Eigen::Index m = static_cast<Eigen::Index>(rows.dofs_.size());
  P.setZero(9 * m);
  R.setZero(9 * m);
  std::array<Eigen::Matrix<double, 6, 1>, 2> s;
  int last = -1;  // the node whose sums s holds (a node's rows are adjacent in the selection)
  for (Eigen::Index i = 0; i < m; ++i) {
    const int a = rows.dofs_[i] / kNodeDofs, c = rows.dofs_[i] % kNodeDofs;
    if (c > 1) continue;  // theta_z
    if (a != last) node_sums<false, 2>(node_mass_.m.data(), a, {d.data(), dd.data()}, s), last = a;
    for (int j = 0; j < 3; ++j) {
      P((3 * c + j) * m + i) = s[0](j);
      R((3 * c + j) * m + i) = s[1](j);
    }
  }
}

template void FloatingFrameInertia::compute_products<1>(const std::array<const Eigen::VectorXd*, 1>&,
                                                       const std::array<Eigen::VectorXd*, 1>&) const;
template void FloatingFrameInertia::compute_products<2>(const std::array<const Eigen::VectorXd*, 2>&,
                                                       const std::array<Eigen::VectorXd*, 2>&) const;

}  // namespace deployfx::body
