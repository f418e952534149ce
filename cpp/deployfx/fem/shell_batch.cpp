#include "deployfx/fem/shell_batch.hpp"

#include <algorithm>
#include <array>

namespace deployfx::fem {

using namespace node_dof;  // U, V, W, TX, TY, TZ: a node's six dofs

ShellBatch::ShellBatch(const std::vector<ShellElement>& elements,
                       const Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>& quads) {
  for (const ShellElement& el : elements)
    if (!el.world_axes()) return;
  const int n = static_cast<int>(elements.size());
  for (int first = 0; first < n; first += kLanes) {
    Batch b;
    b.first = first;
    b.lanes = std::min(kLanes, n - first);
    for (int l = 0; l < kLanes; ++l) {
      const int e = first + std::min(l, b.lanes - 1);  // an unused lane repeats the last element
      const ShellElement& el = elements[e];
      for (int a = 0; a < 4; ++a) b.nodes[a][l] = quads(e, a);
      for (int q = 0; q < 4; ++q) {
        const ShellElement::ForceOperators o = el.force_operators(q);
        GaussPoint& g = b.gp[q];
        for (int a = 0; a < 4; ++a) g.N[a][l] = o.N(a), g.dNx[a][l] = o.dNx(a), g.dNy[a][l] = o.dNy(a);
        for (int r = 0; r < 2; ++r)
          for (int k = 0; k < 12; ++k) g.Bs[r][k][l] = o.Bs_wr(r, k);
        g.weight[l] = l < b.lanes ? o.weight : 0.0;  // an unused lane's force is zero (and never scattered)
        const ShellElement::TangentOperators t = el.tangent_operators(q);
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) g.wA[i][j][l] = t.wA(i, j);
          for (int j = 0; j < 8; ++j) g.wBBb[i][j][l] = t.wBBb(i, j);
        }
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 12; ++j) g.wAsBs[i][j][l] = t.wAsBs(i, j);
      }
      for (int c = 0; c < 8; ++c)
        for (int r = 0; r < 8; ++r) b.K_rot[c][r][l] = el.rotation_tangent()(r, c);
      const Eigen::Matrix<double, 12, 12>& Kd = el.drilling_tangent();
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 8; ++r) b.drill_uv_tz[c][r][l] = Kd(r, 8 + c), b.drill_tz_uv[r][c][l] = Kd(8 + c, r);
        for (int r = 0; r < 4; ++r) b.drill_tz_tz[c][r][l] = Kd(8 + r, 8 + c);
      }
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) b.A[i][j][l] = el.A()(i, j), b.B[i][j][l] = el.B()(i, j), b.D[i][j][l] = el.D()(i, j);
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) b.As[i][j][l] = el.As()(i, j);
      b.drill[l] = el.drill_modulus();
    }
    batches_.push_back(b);
  }
}

void ShellBatch::add_force(const Eigen::VectorXd& u, Eigen::VectorXd& f, bool in_plane_rows) const {
  for (const Batch& b : batches_) {
    if (in_plane_rows) add_batch<true>(b, u, f);
    else add_batch<false>(b, u, f);
  }
}

void ShellBatch::gather(const Batch& b, const Eigen::VectorXd& u, Lane (&X)[6][4]) const {
  for (int a = 0; a < 4; ++a)
    for (int l = 0; l < kLanes; ++l) {
      const double* x = u.data() + kNodeDofs * b.nodes[a][l];
      for (int t = 0; t < 6; ++t) X[t][a][l] = x[t];
    }
}

namespace {
using Lane = ShellBatch::Lane;

Lane dot(const Lane* x, const Lane* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2] + x[3] * y[3]; }

// The strains at a Gauss point g of batch b for the nodes' dofs X (type t of node a) and their
// membrane resultants: the gradients Psi (Eq. 20), the Green membrane strain (Eq. 14), the
// curvature (beta_x = theta_y, beta_y = -theta_x) and N = A eps + B kap.
struct Strains {
  Lane px[3], py[3], eps[3], kap[3], N[3];
};
template <class GaussPoint, class Batch>
Strains strains(const GaussPoint& g, const Batch& b, const Lane (&X)[6][4]) {
  Strains s;
  Lane *px = s.px, *py = s.py;
  for (int t = 0; t < 3; ++t) px[t] = dot(X[t], g.dNx), py[t] = dot(X[t], g.dNy);
  s.eps[0] = px[0] + 0.5 * (px[0] * px[0] + px[1] * px[1] + px[2] * px[2]);
  s.eps[1] = py[1] + 0.5 * (py[0] * py[0] + py[1] * py[1] + py[2] * py[2]);
  s.eps[2] = py[0] + px[1] + (px[0] * py[0] + px[1] * py[1] + px[2] * py[2]);
  const Lane ty_x = dot(X[TY], g.dNx), ty_y = dot(X[TY], g.dNy);
  const Lane tx_x = dot(X[TX], g.dNx), tx_y = dot(X[TX], g.dNy);
  s.kap[0] = ty_x, s.kap[1] = -tx_y, s.kap[2] = ty_y - tx_x;
  for (int i = 0; i < 3; ++i)
    s.N[i] = b.A[i][0] * s.eps[0] + b.A[i][1] * s.eps[1] + b.A[i][2] * s.eps[2] + b.B[i][0] * s.kap[0] +
             b.B[i][1] * s.kap[1] + b.B[i][2] * s.kap[2];
  return s;
}

// The drilling strain theta_z - (v,x - u,y) / 2 at g.
template <class GaussPoint>
Lane drill_strain(const GaussPoint& g, const Lane (&X)[6][4]) {
  return dot(X[TZ], g.N) - 0.5 * (dot(X[V], g.dNx) - dot(X[U], g.dNy));
}

// The bending moments M = B eps + D kap and the MITC4 shear strains gam (from w, theta_x, theta_y
// of the nodes) at g.
struct Bending {
  Lane M[3], gam[2];
};
template <class GaussPoint, class Batch>
Bending bending(const GaussPoint& g, const Batch& b, const Strains& st, const Lane (&X)[6][4]) {
  Bending out;
  const Lane *eps = st.eps, *kap = st.kap;
  for (int i = 0; i < 3; ++i)
    out.M[i] = b.B[i][0] * eps[0] + b.B[i][1] * eps[1] + b.B[i][2] * eps[2] + b.D[i][0] * kap[0] +
               b.D[i][1] * kap[1] + b.D[i][2] * kap[2];
  for (int r = 0; r < 2; ++r)
    out.gam[r] = dot(g.Bs[r], X[W]) + dot(g.Bs[r] + 4, X[TX]) + dot(g.Bs[r] + 8, X[TY]);
  return out;
}
}  // namespace

template <bool kInPlane>
void ShellBatch::add_batch(const Batch& b, const Eigen::VectorXd& u, Eigen::VectorXd& f) const {
  // ShellElement::evaluate's force, lane by lane (its comments give the equations).
  Lane X[6][4];  // dof type t of node a
  gather(b, u, X);
  Lane F[6][4];
  for (int t = 0; t < 6; ++t)
    for (int a = 0; a < 4; ++a) F[t][a].setZero();
  for (const GaussPoint& g : b.gp) {
    const Strains st = strains(g, b, X);
    const Lane *px = st.px, *py = st.py, *N = st.N;
    const Lane& w = g.weight;
    const Lane drill = w * b.drill * drill_strain(g, X);
    const Lane gx[3] = {px[0] + 1.0, px[1], px[2]}, gy[3] = {py[0], py[1] + 1.0, py[2]};
    for (int t = 0; t < (kInPlane ? 2 : 3); ++t) {
      const Lane nx = w * (N[0] * gx[t] + N[2] * gy[t]), ny = w * (N[1] * gy[t] + N[2] * gx[t]);
      for (int a = 0; a < 4; ++a) F[t][a] += nx * g.dNx[a] + ny * g.dNy[a];
    }
    for (int a = 0; a < 4; ++a) {
      F[TZ][a] += drill * g.N[a];
      F[U][a] += 0.5 * drill * g.dNy[a];
      F[V][a] -= 0.5 * drill * g.dNx[a];
    }
    if constexpr (kInPlane) continue;
    const Bending bs = bending(g, b, st, X);
    const Lane *M = bs.M, *gam = bs.gam;
    const Lane wQ0 = w * (b.As[0][0] * gam[0] + b.As[0][1] * gam[1]), wQ1 = w * (b.As[1][0] * gam[0] + b.As[1][1] * gam[1]);
    for (int a = 0; a < 4; ++a) {
      F[W][a] += g.Bs[0][a] * wQ0 + g.Bs[1][a] * wQ1;
      F[TX][a] += g.Bs[0][4 + a] * wQ0 + g.Bs[1][4 + a] * wQ1 - w * (M[1] * g.dNy[a] + M[2] * g.dNx[a]);
      F[TY][a] += g.Bs[0][8 + a] * wQ0 + g.Bs[1][8 + a] * wQ1 + w * (M[0] * g.dNx[a] + M[2] * g.dNy[a]);
    }
  }
  // Into f lane by lane (the elements of a batch may share nodes).
  constexpr int kRows[] = {U, V, TZ, W, TX, TY};
  for (int l = 0; l < b.lanes; ++l)
    for (int a = 0; a < 4; ++a) {
      double* y = f.data() + kNodeDofs * b.nodes[a][l];
      for (int k = 0; k < (kInPlane ? 3 : 6); ++k) y[kRows[k]] += F[kRows[k]][a][l];
    }
}

double ShellBatch::strain_energy(const Eigen::VectorXd& u) const {
  // ShellElement::evaluate's energy, lane by lane: int (eps.N + kap.M + gam.Q + drill modulus
  // drill strain^2) dA / 2; the unused lanes' weights are zero.
  Lane U = Lane::Zero();
  for (const Batch& b : batches_) {
    Lane X[6][4];
    gather(b, u, X);
    for (const GaussPoint& g : b.gp) {
      const Strains st = strains(g, b, X);
      const Bending bs = bending(g, b, st, X);
      const Lane *eps = st.eps, *kap = st.kap, *N = st.N, *M = bs.M, *gam = bs.gam;
      const Lane Q0 = b.As[0][0] * gam[0] + b.As[0][1] * gam[1], Q1 = b.As[1][0] * gam[0] + b.As[1][1] * gam[1];
      const Lane drill = drill_strain(g, X);
      U += 0.5 * g.weight *
           (eps[0] * N[0] + eps[1] * N[1] + eps[2] * N[2] + kap[0] * M[0] + kap[1] * M[1] + kap[2] * M[2] +
            gam[0] * Q0 + gam[1] * Q1 + b.drill * drill * drill);
    }
  }
  return U.sum();
}

void ShellBatch::batch_tangent(const Batch& b, const Eigen::VectorXd& u, Lane* Kt) const {
  // ShellElement::evaluate's type-major tangent, lane by lane (its comments give the equations):
  // the displacement's blocks summed over the Gauss points, then the constant ones and the
  // symmetric copy.
  Lane X[6][4];
  gather(b, u, X);
  for (int k = 0; k < 576; ++k) Kt[k].setZero();
  auto K = [Kt](int r, int c) -> Lane& { return Kt[r + 24 * c]; };
  for (const GaussPoint& g : b.gp) {
    const Strains st = strains(g, b, X);
    const Lane *px = st.px, *py = st.py, *N = st.N;
    const Lane gx[3] = {px[0] + 1.0, px[1], px[2]}, gy[3] = {py[0], py[1] + 1.0, py[2]};
    // K_L + K_L* (Eq. 19, 23) on Bm_bar (u, v, w; column 4 t + node) and Bb (theta_x, theta_y).
    Lane Bm[3][12], wABm[3][12];
    for (int t = 0; t < 3; ++t)
      for (int a = 0; a < 4; ++a) {
        Bm[0][4 * t + a] = gx[t] * g.dNx[a];
        Bm[1][4 * t + a] = gy[t] * g.dNy[a];
        Bm[2][4 * t + a] = gx[t] * g.dNy[a] + gy[t] * g.dNx[a];
      }
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 12; ++c) wABm[i][c] = g.wA[i][0] * Bm[0][c] + g.wA[i][1] * Bm[1][c] + g.wA[i][2] * Bm[2][c];
    for (int c = 0; c < 12; ++c)
      for (int r = 0; r < 12; ++r) K(r, c) += Bm[0][r] * wABm[0][c] + Bm[1][r] * wABm[1][c] + Bm[2][r] * wABm[2][c];
    for (int c = 0; c < 8; ++c)
      for (int r = 0; r < 12; ++r)
        K(r, 12 + c) += Bm[0][r] * g.wBBb[0][c] + Bm[1][r] * g.wBBb[1][c] + Bm[2][r] * g.wBBb[2][c];
    // The shear's rows of w (Bs_wr's columns 0-3) against (w, theta_x, theta_y).
    for (int c = 0; c < 12; ++c)
      for (int r = 0; r < 4; ++r) K(8 + r, 8 + c) += g.Bs[0][r] * g.wAsBs[0][c] + g.Bs[1][r] * g.wAsBs[1][c];
    // The drilling penalty on (u, v): Bd = (dNy / 2, -dNx / 2).
    const Lane wd = g.weight * b.drill;
    Lane bd[8];
    for (int a = 0; a < 4; ++a) bd[a] = 0.5 * g.dNy[a], bd[4 + a] = -0.5 * g.dNx[a];
    for (int c = 0; c < 8; ++c)
      for (int r = 0; r < 8; ++r) K(r, c) += wd * bd[r] * bd[c];
    // K_s (Eq. 22): S (x) I3 on (u, v, w).
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) {
        const Lane S = g.weight * (N[0] * g.dNx[r] * g.dNx[c] + N[1] * g.dNy[r] * g.dNy[c] +
                                   N[2] * (g.dNx[r] * g.dNy[c] + g.dNy[r] * g.dNx[c]));
        for (int t = 0; t < 3; ++t) K(4 * t + r, 4 * t + c) += S;
      }
  }
  for (int c = 0; c < 8; ++c)
    for (int r = 0; r < 8; ++r) K(12 + r, 12 + c) = b.K_rot[c][r];
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 8; ++r) K(r, 20 + c) = b.drill_uv_tz[c][r], K(20 + c, r) = b.drill_tz_uv[r][c];
    for (int r = 0; r < 4; ++r) K(20 + r, 20 + c) = b.drill_tz_tz[c][r];
  }
  for (int c = 0; c < 12; ++c)
    for (int r = 0; r < 8; ++r) K(12 + r, c) = K(c, 12 + r);
}

std::vector<int> ShellBatch::runs(const std::vector<int>& slots) {
  constexpr int kEntries = kElementDofs * kElementDofs;
  const std::size_t elements = slots.size() / kEntries;
  std::vector<int> out(elements * kRuns);
  for (std::size_t e = 0; e < elements; ++e)
    for (int b = 0; b < 4; ++b)
      for (int q = 0; q < kNodeDofs; ++q)
        for (int a = 0; a < 4; ++a) {
          // Entry (a, p; b, q) of the node-major tangent: k = 6 a + p + 24 (6 b + q).
          const int* slot = slots.data() + e * kEntries + kNodeDofs * a + kElementDofs * (kNodeDofs * b + q);
          bool none = true, consecutive = slot[0] >= 0;
          for (int p = 0; p < kNodeDofs; ++p) {
            none = none && slot[p] < 0;
            consecutive = consecutive && slot[p] == slot[0] + p;
          }
          out[e * kRuns + 24 * b + 4 * q + a] = consecutive ? slot[0] : none ? -1 : -2;
        }
  return out;
}

void ShellBatch::add_tangent(const Eigen::VectorXd& u, const std::vector<int>& slots, const std::vector<int>& runs,
                             double coef, double* values) const {
  constexpr int kEntries = kElementDofs * kElementDofs;
  std::vector<Lane> Kt(kEntries);
  for (const Batch& b : batches_) {
    batch_tangent(b, u, Kt.data());
    for (int l = 0; l < b.lanes; ++l) {
      const std::size_t e = static_cast<std::size_t>(b.first + l);
      const int* run = runs.data() + e * kRuns;
      for (int nb = 0; nb < 4; ++nb)
        for (int q = 0; q < kNodeDofs; ++q) {
          // Column (nb, q) of the type-major tangent: row (a, p) at 4 p + a.
          const Lane* col = Kt.data() + kElementDofs * (4 * q + nb);
          for (int a = 0; a < 4; ++a) {
            const int s = run[24 * nb + 4 * q + a];
            if (s == -1) continue;
            if (s >= 0) {
              double* v = values + s;
              for (int p = 0; p < kNodeDofs; ++p) v[p] += coef * col[4 * p + a][l];
              continue;
            }
            const int* slot = slots.data() + e * kEntries + kNodeDofs * a + kElementDofs * (kNodeDofs * nb + q);
            for (int p = 0; p < kNodeDofs; ++p)
              if (slot[p] >= 0) values[slot[p]] += coef * col[4 * p + a][l];
          }
        }
    }
  }
}

}  // namespace deployfx::fem
