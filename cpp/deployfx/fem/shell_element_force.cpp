// The shell element's Green-strain internal force and tangent (You et al. 2016 Eq. 14-23): the
// kernel ShellElement::evaluate and what is formed from it (internal_force, tangent_type_major,
// in_plane_force); the element's operators and linear matrices are in shell_element.cpp.
#include <array>

#include "deployfx/fem/shell_element.hpp"

// The element kernel is one large function, and the compiler left its small fixed-size Eigen
// products and assignments out of line (calls, a 3-vector through memory): flattened, they are
// inlined (15 x 10, 150 element forces 55 -> 30 us, tangents 170 -> 147 us). Only in optimized,
// uninstrumented builds: under ASan and UBSan (tools/sanitize.sh, -O1 -g) the flattened kernel
// took GCC 12 more than 19 min and 1.9 GB to compile, against about a minute without.
#if defined(__GNUC__) && defined(__OPTIMIZE__) && !defined(DEPLOYFX_SANITIZED)
#define DEPLOYFX_FLATTEN __attribute__((flatten))
#else
#define DEPLOYFX_FLATTEN
#endif

namespace deployfx::fem {

using namespace node_dof;  // U, V, W, TX, TY, TZ: a node's six dofs

void ShellElement::internal_force(const ElemVec& d_W, ElemVec* f_W, ElemMat* K_W, double* energy) const {
  ElemMat Kt;
  evaluate(d_W, f_W, K_W ? &Kt : nullptr, energy);
  if (!K_W) return;
  ElemMat K;  // node-major
  for (int b = 0; b < 4; ++b)
    for (int r = 0; r < kNodeDofs; ++r)
      for (int a = 0; a < 4; ++a)
        for (int s = 0; s < kNodeDofs; ++s)
          K(kNodeDofs * a + s, kNodeDofs * b + r) = Kt(4 * s + a, 4 * r + b);
  *K_W = to_world(K);
}

const std::array<int, kElementDofs * kElementDofs>& ShellElement::type_major_index() {
  static const std::array<int, kElementDofs * kElementDofs> index = [] {
    std::array<int, kElementDofs * kElementDofs> out{};
    for (int r = 0; r < kElementDofs; ++r)
      for (int c = 0; c < kElementDofs; ++c)
        out[kElementDofs * c + r] = kElementDofs * (4 * (c % kNodeDofs) + c / kNodeDofs) + 4 * (r % kNodeDofs) + r / kNodeDofs;
    return out;
  }();
  return index;
}

bool ShellElement::tangent_type_major(const ElemVec& d_W, ElemMat* K_t) const {
  if (!world_axes_) return false;
  evaluate(d_W, nullptr, K_t, nullptr);
  return true;
}

void ShellElement::in_plane_force(const ElemVec& d_W, ElemVec* f_W) const {
  evaluate(d_W, f_W, nullptr, nullptr, world_axes_);
}

DEPLOYFX_FLATTEN void ShellElement::evaluate(const ElemVec& d_W, ElemVec* f_W, ElemMat* K_t, double* energy,
                                             bool in_plane_rows) const {
  // Each strain operator touches few of the 24 dofs, through the nodes' shape functions: Bm and
  // G the (u, v, w), Bb the (theta_x, theta_y), Bs the (w, theta_x, theta_y), Bd the (u, v,
  // theta_z). The force and tangent are formed from those, with the tangent in the dof-type-major
  // order 4 type + node (u1..u4, v1..v4, w1..w4, theta_x1..4, theta_y1..4, theta_z1..4), where
  // each operator's dofs are contiguous: a sixth of the multiply-adds of the 24-column products.
  // strain_energy() keeps the 24-column operators (the tests' independent reference); `energy` here
  // is the engine's, from the same strains and resultants as the force. Only what is asked for is
  // formed (a Newton matrix asks for the tangent alone, an output for the energy alone, a sweep on
  // the in-plane rows for those rows: the membrane and drilling terms, no moments or shear).
  const ElemVec d = to_element(d_W);
  // Column a: node a's dofs.
  const Eigen::Map<const Eigen::Matrix<double, kNodeDofs, 4>> X(d.data());
  Eigen::Matrix<double, kNodeDofs, 4> F = Eigen::Matrix<double, kNodeDofs, 4>::Zero();
  const bool K_W = K_t != nullptr;
  ElemMat Kt;  // type-major
  if (K_W) Kt.setZero();
  if (energy) *energy = 0;
  Eigen::Matrix<double, 12, 1> wr;  // (w, theta_x, theta_y) of the nodes
  wr << X.row(W).transpose(), X.row(TX).transpose(), X.row(TY).transpose();
  for (const GaussPoint& p : gp_) {
    const Eigen::Vector3d px = X.topRows<3>() * p.dNx;  // Psi (Eq. 20): (u,x v,x w,x)
    const Eigen::Vector3d py = X.topRows<3>() * p.dNy;  // (u,y v,y w,y)
    // Eq. 14: eps = (u,x + |px|^2 / 2, v,y + |py|^2 / 2, u,y + v,x + px.py); its variation is
    // (gx.dpx, gy.dpy, gx.dpy + gy.dpx) with gx = e_x + px, gy = e_y + py (Eq. 20: Bm + H G).
    const Eigen::Vector3d gx = px + Eigen::Vector3d::UnitX(), gy = py + Eigen::Vector3d::UnitY();
    const Eigen::Vector3d eps(px(0) + 0.5 * px.squaredNorm(), py(1) + 0.5 * py.squaredNorm(),
                              py(0) + px(1) + px.dot(py));
    // kappa = (beta_x,x, beta_y,y, beta_x,y + beta_y,x), beta_x = theta_y, beta_y = -theta_x.
    auto field = [&](int type, const Eigen::Vector4d& shape) {
      return shape.dot(X.row(type).transpose());
    };
    const double ty_x = field(TY, p.dNx), ty_y = field(TY, p.dNy);
    const double tx_x = field(TX, p.dNx), tx_y = field(TX, p.dNy);
    const Eigen::Vector3d kap(ty_x, -tx_y, ty_y - tx_x);
    const Eigen::Vector3d N = A_ * eps + B_ * kap;
    const double drill_strain = field(TZ, p.N) - 0.5 * (field(V, p.dNx) - field(U, p.dNy));
    const double w = p.weight;
    const double drill = w * drill_modulus_ * drill_strain;
    if (f_W) {
      // f = int (Bm_bar^T N + Bb^T M + Bs^T Q + Bd^T drill) dA, by node; the in-plane rows (u, v,
      // theta_z) hold Bm_bar's and the drilling's terms alone.
      const Eigen::Vector3d nx = w * (N(0) * gx + N(2) * gy), ny = w * (N(1) * gy + N(2) * gx);
      if (in_plane_rows)
        F.topRows<2>().noalias() += nx.head<2>() * p.dNx.transpose() + ny.head<2>() * p.dNy.transpose();
      else
        F.topRows<3>().noalias() += nx * p.dNx.transpose() + ny * p.dNy.transpose();
      F.row(TZ) += drill * p.N.transpose();
      F.row(U) += 0.5 * drill * p.dNy.transpose();
      F.row(V) -= 0.5 * drill * p.dNx.transpose();
    }
    if (!energy && !K_W && in_plane_rows) continue;  // the in-plane rows alone: done
    const Eigen::Vector3d M = B_ * eps + D_ * kap;
    const Eigen::Vector2d Q = As_ * (p.Bs_wr * wr);
    if (energy) {
      const Eigen::Vector2d gam = p.Bs_wr * wr;  // the shear strains
      *energy += 0.5 * (w * (eps.dot(N) + kap.dot(M) + gam.dot(Q)) + drill * drill_strain);
    }
    if (f_W && !in_plane_rows) {
      const Eigen::Matrix<double, 12, 1> fs = p.Bs_wr.transpose() * (w * Q);
      F.row(W) += fs.segment<4>(0).transpose();
      F.row(TX) += fs.segment<4>(4).transpose() - w * (M(1) * p.dNy + M(2) * p.dNx).transpose();
      F.row(TY) += fs.segment<4>(8).transpose() + w * (M(0) * p.dNx + M(2) * p.dNy).transpose();
    }
    if (!K_W) continue;
    // K_L + K_L* (Eq. 19, 23) on the compact operators: Bm_bar on (u, v, w), Bb on (theta_x,
    // theta_y). Only the terms with Bm_bar (it holds d's gradients) and the shear and drilling
    // blocks that share its rows are formed here; the rest is d-free (constant_tangent()).
    Eigen::Matrix<double, 3, 12> Bm;
    for (int t = 0; t < 3; ++t) {
      Bm.block<1, 4>(0, 4 * t) = gx(t) * p.dNx.transpose();
      Bm.block<1, 4>(1, 4 * t) = gy(t) * p.dNy.transpose();
      Bm.block<1, 4>(2, 4 * t) = gx(t) * p.dNy.transpose() + gy(t) * p.dNx.transpose();
    }
    const Eigen::Matrix<double, 3, 12> wABm = p.wA * Bm;
    // Eigen sends a fixed 12 x 3 x 12 product to its general GEMM (packing, blocking): 30 % of the
    // tangent. lazyProduct with a column-major left factor is the same sums in the same order
    // (over the depth, each a product then fused multiply-adds, added to Kt), in registers.
    const Eigen::Matrix<double, 12, 3> BmT = Bm.transpose();
    Kt.topLeftCorner<12, 12>().noalias() += BmT.lazyProduct(wABm);
    Kt.block<12, 8>(0, 12).noalias() += BmT.lazyProduct(p.wBBb);
    // The shear's rows of w; its rows of (theta_x, theta_y) are in K_rot_ or below the diagonal.
    Kt.block<4, 12>(8, 8).noalias() += p.Bs_wrT.topRows<4>().lazyProduct(p.wAsBs);
    Eigen::Matrix<double, 8, 1> bd;  // Bd on (u, v); its theta_z part is in Kd_
    bd << 0.5 * p.dNy, -0.5 * p.dNx;
    const Eigen::Matrix<double, 8, 8> Kd = (w * drill_modulus_) * bd * bd.transpose();
    Kt.topLeftCorner<8, 8>() += Kd;
    // K_s (Eq. 22): G^T N_s G = S (x) I3 on (u, v, w), S = the resultants on the gradients.
    if (N.squaredNorm() > 0) {
      const Eigen::Matrix4d S =
          w * (N(0) * p.dNx * p.dNx.transpose() + N(1) * p.dNy * p.dNy.transpose() +
               N(2) * (p.dNx * p.dNy.transpose() + p.dNy * p.dNx.transpose()));
      for (int t = 0; t < 3; ++t) Kt.block<4, 4>(4 * t, 4 * t) += S;
    }
  }
  if (f_W) *f_W = to_world(ElemVec(Eigen::Map<const ElemVec>(F.data())));
  if (!K_W) return;
  // The blocks no d reaches (constant_tangent()), and the symmetric one.
  Kt.block<8, 8>(12, 12) = K_rot_;
  Kt.block<8, 4>(0, 20) = Kd_.topRightCorner<8, 4>();
  Kt.block<4, 8>(20, 0) = Kd_.bottomLeftCorner<4, 8>();
  Kt.bottomRightCorner<4, 4>() = Kd_.bottomRightCorner<4, 4>();
  Kt.block<8, 12>(12, 0) = Kt.block<12, 8>(0, 12).transpose();
  *K_t = Kt;
}

}  // namespace deployfx::fem
