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
#include <cmath>
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

// x * y + acc in one rounding where the target has fused multiply-adds, else two: spelled out, so
// that a sum's rounding does not depend on how the compiler contracts and vectorizes the loop it
// is inlined into (node_sums: a run's memo hands out products formed for one vector or for two, and
// a resumed run, whose memo starts empty, must get the same bits).
inline double multiply_add(double x, double y, double acc) {
#ifdef __FMA__
  return std::fma(x, y, acc);
#else
  return x * y + acc;
#endif
}

// Node a's sums over its neighbours b on the node graph (m_0, m_1, m_2: the header's NodeMass, one
// pattern) for V vectors z (t, r: z's translations and fibre rotations r = (theta_y, -theta_x, 0)
// at b): s(0..2) = (m_0 t + m_1 r)(a), and with kMoments s(3..5) = (m_1 t + m_2 r)(a), each term
// added in that order whatever V. Inlined into its loops (a call per node cost the products 4 us
// on the paper's mesh).
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
      s[v](0) = multiply_add(m1[p], rx, multiply_add(m0[p], zb[0], s[v](0)));
      s[v](1) = multiply_add(m1[p], ry, multiply_add(m0[p], zb[1], s[v](1)));
      s[v](2) = multiply_add(m0[p], zb[2], s[v](2));
      if constexpr (kMoments) {
        s[v](3) = multiply_add(m2[p], rx, multiply_add(m1[p], zb[0], s[v](3)));
        s[v](4) = multiply_add(m2[p], ry, multiply_add(m1[p], zb[1], s[v](4)));
        s[v](5) = multiply_add(m1[p], zb[2], s[v](5));
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
  for (int v = 0; v < V; ++v) zv[v] = z[v]->data();
  std::array<Eigen::Matrix<double, 6, 1>, V> s;
  for (Eigen::Index a = 0; a < node_mass_.m[0].rows(); ++a) {
    node_sums<true, V>(node_mass_.m.data(), a, zv, s);
    // Every entry of node a in each M_(ij) z written (no zeroing pass): s_j at translation i,
    // +s_(3+j) at theta_y (i = x: +r_x), -s_(3+j) at theta_x (i = y: -r_y), zero elsewhere.
    for (int v = 0; v < V; ++v)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double* P = out[v]->data() + (3 * i + j) * n + kNodeDofs * a;
          for (int t = 0; t < kNodeDofs; ++t) P[t] = 0.0;
          P[i] = s[v](j);
          if (i == 0) P[4] = s[v](3 + j);
          if (i == 1) P[3] = -s[v](3 + j);
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
