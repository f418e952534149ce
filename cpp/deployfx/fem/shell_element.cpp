#include "deployfx/fem/shell_element.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace deployfx::fem {
namespace {

using namespace node_dof;  // U, V, W, TX, TY, TZ: a node's six dofs
constexpr double kXi[4] = {-1, 1, 1, -1};
constexpr double kEta[4] = {-1, -1, 1, 1};

struct Shape {
  Eigen::Vector4d N, dN_dxi, dN_deta;
};

Shape shape(double xi, double eta) {
  Shape s;
  for (int i = 0; i < 4; ++i) {
    s.N(i) = 0.25 * (1 + kXi[i] * xi) * (1 + kEta[i] * eta);
    s.dN_dxi(i) = 0.25 * kXi[i] * (1 + kEta[i] * eta);
    s.dN_deta(i) = 0.25 * kEta[i] * (1 + kXi[i] * xi);
  }
  return s;
}

// Jacobian J = [x,xi y,xi; x,eta y,eta] from local node coordinates xy (4 x 2).
Eigen::Matrix2d jacobian(const Shape& s, const Eigen::Matrix<double, 4, 2>& xy) {
  Eigen::Matrix2d J;
  J.row(0) = s.dN_dxi.transpose() * xy;
  J.row(1) = s.dN_deta.transpose() * xy;
  return J;
}

// Covariant transverse shear e_az = w,a + beta_x x,a + beta_y y,a for a = xi or eta, as a
// row operator on the element dofs at (xi, eta) (Bathe & Dvorkin 1985, Eq. 8).
RowOp covariant_shear(double xi, double eta, bool along_xi, const Eigen::Matrix<double, 4, 2>& xy) {
  const Shape s = shape(xi, eta);
  const Eigen::Vector4d& dN = along_xi ? s.dN_dxi : s.dN_deta;
  const Eigen::Vector2d g = dN.transpose() * xy;  // (x,a  y,a)
  RowOp e = RowOp::Zero();
  for (int i = 0; i < 4; ++i) {
    e(6 * i + W) = dN(i);
    e(6 * i + TY) = s.N(i) * g(0);   // beta_x = theta_y
    e(6 * i + TX) = -s.N(i) * g(1);  // beta_y = -theta_x
  }
  return e;
}

// Bm, Bb, G (Eq. 20) and the MITC4 assumed shear Bs at (xi, eta), on E's dofs, from the shape
// functions there, the inverse Jacobian and the covariant shear at the tying points B, D, A, C.
void fill_strain_operators(const Shape& s, const Eigen::Matrix2d& Jinv, double xi, double eta,
                           const std::array<RowOp, 4>& tying, ShellElement::StrainOperators* op) {
  op->Bm.setZero();
  op->Bb.setZero();
  op->G.setZero();
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d dN = Jinv * Eigen::Vector2d(s.dN_dxi(i), s.dN_deta(i));  // (N,x N,y)
    const int o = 6 * i;
    op->Bm(0, o + U) = dN(0);
    op->Bm(1, o + V) = dN(1);
    op->Bm(2, o + U) = dN(1);
    op->Bm(2, o + V) = dN(0);
    // kappa_x = beta_x,x; kappa_y = beta_y,y; kappa_xy = beta_x,y + beta_y,x
    op->Bb(0, o + TY) = dN(0);
    op->Bb(1, o + TX) = -dN(1);
    op->Bb(2, o + TY) = dN(1);
    op->Bb(2, o + TX) = -dN(0);
    for (int a = 0; a < 3; ++a) {
      op->G(a, o + a) = dN(0);
      op->G(3 + a, o + a) = dN(1);
    }
  }
  // Assumed covariant shear (Bathe & Dvorkin 1985, Eq. 11), then Cartesian: e = J gamma.
  Eigen::Matrix<double, 2, kElementDofs> e;
  e.row(0) = 0.5 * (1 - eta) * tying[0] + 0.5 * (1 + eta) * tying[1];
  e.row(1) = 0.5 * (1 - xi) * tying[2] + 0.5 * (1 + xi) * tying[3];
  op->Bs = Jinv * e;
}

// N_s of Eq. 21: [N_x I3, N_xy I3; N_xy I3, N_y I3] acting on Psi = (u,x v,x w,x u,y v,y w,y).
Eigen::Matrix<double, 6, 6> resultant_matrix(const Eigen::Vector3d& N) {
  Eigen::Matrix<double, 6, 6> Ns = Eigen::Matrix<double, 6, 6>::Zero();
  Ns.topLeftCorner<3, 3>().diagonal().setConstant(N(0));
  Ns.bottomRightCorner<3, 3>().diagonal().setConstant(N(1));
  Ns.topRightCorner<3, 3>().diagonal().setConstant(N(2));
  Ns.bottomLeftCorner<3, 3>().diagonal().setConstant(N(2));
  return Ns;
}

}  // namespace

ShellElement::ShellElement(const Eigen::Matrix<double, 4, 3>& X_W, const Eigen::Vector3d& ref_axis_W,
                           const material::Laminate& laminate)
    : A_(laminate.A()), B_(laminate.B()), D_(laminate.D()), As_(laminate.As()),
      I0_(laminate.I0()), I1_(laminate.I1()), I2_(laminate.I2()) {
  if (!X_W.allFinite()) throw std::invalid_argument("ShellElement: node coordinates are not finite");
  const Eigen::Vector3d c = X_W.colwise().mean().transpose();
  const Eigen::Vector3d d13 = (X_W.row(2) - X_W.row(0)).transpose();
  const Eigen::Vector3d d24 = (X_W.row(3) - X_W.row(1)).transpose();
  const double size = std::max(d13.norm(), d24.norm());
  // Slenderness: beyond these size / thickness ratios the membrane and bending stiffnesses
  // (~ A and D / size^2, D / A = h^2 / 12) differ by more than ~1e13 and the element matrices
  // carry no digit of the weaker one (the paper's elements: size / h = 400).
  const double h = laminate.thickness();
  if (!(size >= kMinSlenderness * h && size <= kMaxSlenderness * h)) {
    std::ostringstream e;
    e << "ShellElement: the element's diagonal " << size << " m is out of range: must be in ["
      << kMinSlenderness << ", " << kMaxSlenderness << "] x the laminate thickness h = " << h
      << " m";
    throw std::invalid_argument(e.str());
  }
  Eigen::Vector3d n = d13.cross(d24);
  if (!(n.norm() > 1e-12 * size * size))
    throw std::invalid_argument("ShellElement: degenerate quadrilateral (zero area)");
  n.normalize();
  // Flatness: every node within 1e-6 of the element size of the mean plane.
  for (int i = 0; i < 4; ++i) {
    if (std::abs((X_W.row(i).transpose() - c).dot(n)) > 1e-6 * size)
      throw std::invalid_argument("ShellElement: warped quadrilateral; nodes must be coplanar");
  }
  Eigen::Vector3d e1 = ref_axis_W - ref_axis_W.dot(n) * n;
  if (!(e1.norm() > 1e-6 * ref_axis_W.norm()))
    throw std::invalid_argument("ShellElement: ref_axis is normal to the element; choose another");
  e1.normalize();
  R_WE_.col(0) = e1;
  R_WE_.col(1) = n.cross(e1);
  R_WE_.col(2) = n;
  world_axes_ = R_WE_ == Eigen::Matrix3d::Identity();

  X_W_ = X_W;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d p = R_WE_.transpose() * (X_W.row(i).transpose() - c);
    xy_.row(i) << p(0), p(1);
  }
  drill_modulus_ = kDrillingPenalty * A_(2, 2);

  // MITC4 tying points: e_xi,z at B(0,-1) and D(0,1); e_eta,z at A(-1,0) and C(1,0).
  tying_ = {covariant_shear(0, -1, true, xy_), covariant_shear(0, 1, true, xy_),
            covariant_shear(-1, 0, false, xy_), covariant_shear(1, 0, false, xy_)};

  const double g = 1.0 / std::sqrt(3.0);
  const double gx[4] = {-g, g, g, -g}, gy[4] = {-g, -g, g, g};
  area_ = 0;
  for (int q = 0; q < 4; ++q) {
    const Shape s = shape(gx[q], gy[q]);
    const Eigen::Matrix2d J = jacobian(s, xy_);
    const double detJ = J.determinant();
    if (!(detJ > 0))
      throw std::invalid_argument(
          "ShellElement: non-positive Jacobian; the quadrilateral must be convex");
    const Eigen::Matrix2d Jinv = J.inverse();
    GaussPoint& p = gp_[q];
    p.weight = detJ;  // Gauss weights are 1 for the 2x2 rule
    p.X_W = X_W.transpose() * s.N;  // bilinear geometry
    area_ += detJ;
    StrainOperators op;
    fill_strain_operators(s, Jinv, gx[q], gy[q], tying_, &op);
    p.Bm = op.Bm;
    p.Bb = op.Bb;
    p.Bs = op.Bs;
    p.G = op.G;
    p.Bd.setZero();
    p.Nu.setZero();
    p.Nr.setZero();
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector2d dN = Jinv * Eigen::Vector2d(s.dN_dxi(i), s.dN_deta(i));  // (N,x N,y)
      const int o = 6 * i;
      p.Bd(o + TZ) = s.N(i);
      p.Bd(o + V) = -0.5 * dN(0);
      p.Bd(o + U) = 0.5 * dN(1);
      for (int a = 0; a < 3; ++a) p.Nu(a, o + a) = s.N(i);
      p.Nr(0, o + TY) = s.N(i);
      p.Nr(1, o + TX) = -s.N(i);
      p.Nr(2, o + TZ) = s.N(i);
      p.N(i) = s.N(i);
      p.dNx(i) = dN(0);
      p.dNy(i) = dN(1);
    }
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k) p.Bs_wr.col(4 * k + i) = p.Bs.col(6 * i + W + k);  // W, TX, TY
    p.Bs_wrT = p.Bs_wr.transpose();
  }
  constant_tangent();
}

void ShellElement::constant_tangent() {
  // internal_force()'s tangent terms that no displacement enters, summed over the Gauss points as
  // it summed them (type-major, the same expressions in the same order: bit for bit its sums).
  ElemMat Kt = ElemMat::Zero();
  for (GaussPoint& p : gp_) {
    const double w = p.weight;
    Eigen::Matrix<double, 3, 8> Bb;  // on (theta_x, theta_y)
    Bb << Eigen::RowVector4d::Zero(), p.dNx.transpose(),  //
        -p.dNy.transpose(), Eigen::RowVector4d::Zero(),   //
        -p.dNx.transpose(), p.dNy.transpose();
    p.wA = w * A_;
    p.wBBb = (w * B_) * Bb;
    const Eigen::Matrix<double, 3, 8> wDBb = (w * D_) * Bb;
    p.wAsBs = (w * As_) * p.Bs_wr;
    Kt.block<8, 8>(12, 12).noalias() += Bb.transpose().lazyProduct(wDBb);
    Kt.block<12, 12>(8, 8).noalias() += p.Bs_wrT.lazyProduct(p.wAsBs);
    Eigen::Matrix<double, 12, 1> bd;  // Bd on (u, v, theta_z)
    bd << 0.5 * p.dNy, -0.5 * p.dNx, p.N;
    const Eigen::Matrix<double, 12, 12> Kd = (w * drill_modulus_) * bd * bd.transpose();
    Kt.block<8, 4>(0, 20) += Kd.topRightCorner<8, 4>();
    Kt.block<4, 8>(20, 0) += Kd.bottomLeftCorner<4, 8>();
    Kt.bottomRightCorner<4, 4>() += Kd.bottomRightCorner<4, 4>();
  }
  K_rot_ = Kt.block<8, 8>(12, 12);
  Kd_.setZero();
  Kd_.topRightCorner<8, 4>() = Kt.block<8, 4>(0, 20);
  Kd_.bottomLeftCorner<4, 8>() = Kt.block<4, 8>(20, 0);
  Kd_.bottomRightCorner<4, 4>() = Kt.bottomRightCorner<4, 4>();
}

ShellElement::StrainOperators ShellElement::strain_operators(double xi, double eta) const {
  if (!(std::abs(xi) <= 1 && std::abs(eta) <= 1))
    throw std::invalid_argument("ShellElement.strain_operators: (xi, eta) = (" + std::to_string(xi) +
                                ", " + std::to_string(eta) + ") is out of range: must be in [-1, 1]^2");
  const Shape s = shape(xi, eta);
  StrainOperators op;
  fill_strain_operators(s, jacobian(s, xy_).inverse(), xi, eta, tying_, &op);
  return op;
}

Eigen::Vector3d ShellElement::position(double xi, double eta) const {
  return X_W_.transpose() * shape(xi, eta).N;  // bilinear geometry, as the Gauss points'
}

ShellElement::Kinematics ShellElement::kinematics(int q) const {
  const GaussPoint& p = gp_.at(q);
  Kinematics k;
  k.X_W = p.X_W;
  k.n_W = R_WE_.col(2);
  k.weight = p.weight;
  Eigen::Matrix<double, 3, kElementDofs> beta = Eigen::Matrix<double, 3, kElementDofs>::Zero();
  beta.topRows<2>() = p.Nr.topRows<2>();
  // d_E = T d_W with T = blockdiag(R_WE^T); displacement in world = R_WE (operator_E) T d_W.
  for (int b = 0; b < 8; ++b) {
    k.N0.middleCols<3>(3 * b) = R_WE_ * p.Nu.middleCols<3>(3 * b) * R_WE_.transpose();
    k.N1.middleCols<3>(3 * b) = R_WE_ * beta.middleCols<3>(3 * b) * R_WE_.transpose();
  }
  return k;
}

ElemVec ShellElement::to_element(const ElemVec& d_W) const {
  if (world_axes_) return d_W;
  ElemVec d_E;
  for (int b = 0; b < 8; ++b) d_E.segment<3>(3 * b) = R_WE_.transpose() * d_W.segment<3>(3 * b);
  return d_E;
}

ElemVec ShellElement::to_world(const ElemVec& f_E) const {
  if (world_axes_) return f_E;
  ElemVec f_W;
  for (int b = 0; b < 8; ++b) f_W.segment<3>(3 * b) = R_WE_ * f_E.segment<3>(3 * b);
  return f_W;
}

ElemMat ShellElement::to_world(const ElemMat& K_E) const {
  if (world_axes_) return K_E;
  ElemMat K_W;
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b)
      K_W.block<3, 3>(3 * a, 3 * b) = R_WE_ * K_E.block<3, 3>(3 * a, 3 * b) * R_WE_.transpose();
  return K_W;
}

ElemMat ShellElement::stiffness() const {
  ElemMat K;
  internal_force(ElemVec::Zero(), nullptr, &K);
  return K;
}

ElemMat ShellElement::mass() const {
  // Kinetic energy per area: I0 |u0|^2 + 2 I1 (u0 beta_x + v0 beta_y) + I2 (beta_x^2 + beta_y^2)
  // + J_z theta_z^2. theta_z has no physical inertia; J_z = kDrillingPenalty I0 A_e puts the
  // drilling modes at omega^2 = A66 / (I0 A_e), the element's in-plane shear-wave frequency, above
  // every mode the mesh resolves, whatever the thickness (J_z = I2 would bring a spurious drilling
  // mode down to the bending range of thick plates, omega^2 = 12 kDrillingPenalty A66 / (I0 h^2)).
  const double Jz = kDrillingPenalty * I0_ * area_;
  ElemMat M = ElemMat::Zero();
  for (const GaussPoint& p : gp_) {
    const auto uv = p.Nu.topRows<2>();
    const auto beta = p.Nr.topRows<2>();
    M.noalias() += p.weight * (I0_ * p.Nu.transpose() * p.Nu +
                               I2_ * beta.transpose() * beta +
                               Jz * p.Nr.row(2).transpose() * p.Nr.row(2));
    if (I1_ != 0.0)
      M.noalias() += p.weight * I1_ * (uv.transpose() * beta + beta.transpose() * uv);
  }
  return to_world(M);
}

ElemVec ShellElement::pressure_load(double pressure) const {
  ElemVec f = ElemVec::Zero();
  for (const GaussPoint& p : gp_) f += p.weight * pressure * p.Nu.row(2).transpose();
  return to_world(f);
}

ElemMat ShellElement::geometric_stiffness(const Eigen::Vector3d& N) const {
  // Eq. 21-22: K_s = int G^T N_s G dA, N_s = [N_x I3, N_xy I3; N_xy I3, N_y I3].
  const Eigen::Matrix<double, 6, 6> Ns = resultant_matrix(N);
  ElemMat K = ElemMat::Zero();
  for (const GaussPoint& p : gp_) K.noalias() += p.weight * p.G.transpose() * Ns * p.G;
  return to_world(K);
}

ElemMat ShellElement::geometric_stiffness_from(const ElemVec& d_W) const {
  const ElemVec d = to_element(d_W);
  ElemMat K = ElemMat::Zero();
  for (const GaussPoint& p : gp_) {
    const Eigen::Vector3d N = A_ * (p.Bm * d) + B_ * (p.Bb * d);
    K.noalias() += p.weight * p.G.transpose() * resultant_matrix(N) * p.G;
  }
  return to_world(K);
}

double ShellElement::strain_energy(const ElemVec& d_W) const {
  const ElemVec d = to_element(d_W);
  double U = 0;
  for (const GaussPoint& p : gp_) {
    const Eigen::Matrix<double, 6, 1> psi = p.G * d;
    const Eigen::Vector3d px = psi.head<3>(), py = psi.tail<3>();
    // Eq. 14: Green membrane strain.
    const Eigen::Vector3d eps =
        p.Bm * d + 0.5 * Eigen::Vector3d(px.squaredNorm(), py.squaredNorm(), 2 * px.dot(py));
    const Eigen::Vector3d kap = p.Bb * d;
    const Eigen::Vector2d gam = p.Bs * d;
    const double drill = p.Bd.dot(d.transpose());
    U += 0.5 * p.weight *
         (eps.dot(A_ * eps) + 2 * eps.dot(B_ * kap) + kap.dot(D_ * kap) + gam.dot(As_ * gam) +
          drill_modulus_ * drill * drill);
  }
  return U;
}

ShellElement::GreenOperators ShellElement::green_operators(int gauss_point) const {
  const GaussPoint& p = gp_.at(static_cast<std::size_t>(gauss_point));
  GreenOperators out{p.G, A_ * p.Bm + B_ * p.Bb, A_, p.weight};
  // d_E = T d_W with T = blockdiag(R_WE^T) on the eight 3-blocks: an operator X on E's dofs is
  // X T on W's, column block by column block.
  for (int b = 0; b < kElementDofs / 3; ++b) {
    out.G.middleCols<3>(3 * b) = (p.G.middleCols<3>(3 * b) * R_WE_.transpose()).eval();
    out.L.middleCols<3>(3 * b) = (out.L.middleCols<3>(3 * b) * R_WE_.transpose()).eval();
  }
  return out;
}

}  // namespace deployfx::fem
