#pragma once
// Four-node flat laminated shell element, 6 dof per node (u, v, w, theta_x, theta_y, theta_z in
// world axes), first-order shear deformation theory:
// - membrane and bending: bilinear Q4 with full 2x2 Gauss integration, A/B/D coupling;
// - transverse shear: MITC4 assumed covariant strains tied at the edge mid-points, free of shear
//   locking (Bathe & Dvorkin, Int. J. Numer. Meth. Eng. 21, 1985, 367-383; Eq. 8-11 there);
// - drilling rotation: Hughes-Brezzi penalty on theta_z - (v,x - u,y)/2 with modulus
//   kDrillingPenalty * A66 (Hughes & Brezzi, CMAME 72, 1989), so the element can sit in 3D;
// - geometric nonlinearity: Green membrane strain with the in-plane and transverse gradients of
//   You et al. (2016) Eq. 14, whose tangent is K_L + K_L* + K_s (Eq. 19-23).
//
// Notation: W world frame, E element frame (origin at the node centroid, x along the projected
// material reference axis, z along the normal). R_WE has E's axes as columns in W.
// Through the thickness: u(z) = u0 + z beta_x, v(z) = v0 + z beta_y with beta_x = theta_y,
// beta_y = -theta_x (rotation-vector components about E's axes).
#include <Eigen/Core>
#include <array>

#include "deployfx/material/laminate.hpp"

namespace deployfx::fem {

constexpr int kNodeDofs = 6;
constexpr int kElementDofs = 4 * kNodeDofs;
/// A node's dof types, in the order of its six dofs.
namespace node_dof {
constexpr int U = 0, V = 1, W = 2, TX = 3, TY = 4, TZ = 5;
}  // namespace node_dof
using ElemVec = Eigen::Matrix<double, kElementDofs, 1>;
using ElemMat = Eigen::Matrix<double, kElementDofs, kElementDofs>;
using RowOp = Eigen::Matrix<double, 1, kElementDofs>;

class ShellElement {
 public:
  /// Accepted element diagonal / laminate thickness (std::invalid_argument outside).
  static constexpr double kMinSlenderness = 1e-3, kMaxSlenderness = 1e6;
  /// Fraction of A66 used as the drilling penalty modulus (Hughes-Brezzi gamma).
  static constexpr double kDrillingPenalty = 1e-3;

  /// X_W: node positions (4 x 3, m), counter-clockwise about the intended normal.
  /// ref_axis_W: the laminate's 0-degree direction, projected onto the element plane.
  /// Throws std::invalid_argument for a degenerate, warped or non-convex quadrilateral, or a
  /// reference axis normal to the element.
  ShellElement(const Eigen::Matrix<double, 4, 3>& X_W, const Eigen::Vector3d& ref_axis_W,
               const material::Laminate& laminate);

  const Eigen::Matrix3d& R_WE() const { return R_WE_; }
  double area() const { return area_; }
  /// Mass moments per area about the mid-plane (kg/m^2, kg/m, kg).
  double I0() const { return I0_; }
  double I1() const { return I1_; }
  double I2() const { return I2_; }

  /// The shell kinematics at one of the four Gauss points, in world axes: the material point at
  /// height z above the mid-surface sits at X_W + z n_W and moves by (N0 + z N1) d_W.
  struct Kinematics {
    Eigen::Vector3d X_W;                         // mid-surface point, m
    Eigen::Vector3d n_W;                         // unit normal
    Eigen::Matrix<double, 3, kElementDofs> N0;   // mid-surface displacement operator
    Eigen::Matrix<double, 3, kElementDofs> N1;   // fibre rotation operator (beta_x, beta_y, 0)
    double weight;                               // area weight, m^2
  };
  Kinematics kinematics(int gauss_point) const;

  /// Linear stiffness K_L (world dofs), Eq. 19.
  ElemMat stiffness() const;
  /// Consistent mass with rotary inertia (world dofs).
  ElemMat mass() const;
  /// Nodal forces of a uniform pressure p (Pa) along the element normal (world dofs).
  ElemVec pressure_load(double p) const;
  /// Geometric stiffness K_s of Eq. 22 for given membrane resultants (N_x, N_y, N_xy) in N/m,
  /// uniform over the element, in E's axes.
  ElemMat geometric_stiffness(const Eigen::Vector3d& N_E) const;
  /// Geometric stiffness with resultants N = A eps_L + B kappa from the linear strains of d_W.
  ElemMat geometric_stiffness_from(const ElemVec& d_W) const;
  /// Strain energy of the nonlinear (Eq. 14) strain field for displacements d_W (J).
  double strain_energy(const ElemVec& d_W) const;
  /// Internal force f = dU/dd and tangent K_T = K_L + K_L*(d) + K_s(N(d)) (world dofs), and the
  /// strain energy U from the same strains (J; strain_energy() is the independent reference).
  void internal_force(const ElemVec& d_W, ElemVec* f_W, ElemMat* K_W, double* energy = nullptr) const;
  /// For an element whose axes are the world's (a mesh in the x-y plane along x), the tangent of
  /// internal_force() in the dof-type-major order it is formed in, row and column 4 t + a for dof
  /// type t (u, v, w, theta_x, theta_y, theta_z) of node a: assembly without reordering it. False
  /// (K_t untouched) for any other element.
  bool tangent_type_major(const ElemVec& d_W, ElemMat* K_t) const;
  /// Entry k of the node-major tangent (column-major, the order internal_force() gives) is entry
  /// type_major_index()[k] of tangent_type_major()'s.
  static const std::array<int, kElementDofs * kElementDofs>& type_major_index();
  /// internal_force()'s force at the in-plane dofs (u, v, theta_z of each node) alone, the other
  /// rows zero, for an element whose axes are the world's (a mesh in the x-y plane: the membrane
  /// and drilling terms, without the bending and shear resultants' rows); any other element's
  /// whole force. A Newton sweep on a flat panel's in-plane rows (multibody::slaved_rows) needs no
  /// other.
  void in_plane_force(const ElemVec& d_W, ElemVec* f_W) const;

  /// The ingredients of the Green membrane strain at Gauss point g, on world dofs, for its exact
  /// projection on a Ritz basis (fem/modal_internal_force): the gradients psi = G d (Eq. 20), so
  /// eps = Bm d + 1/2 (psi_x.psi_x, psi_y.psi_y, 2 psi_x.psi_y) (Eq. 14); the resultant of the
  /// linear strains, N_L = L d = (A Bm + B Bb) d (N/m); the membrane stiffness A (N/m) and the
  /// area weight (m^2). Bending, shear and drilling strains are linear in d (in K_L only).
  struct GreenOperators {
    Eigen::Matrix<double, 6, kElementDofs> G;
    Eigen::Matrix<double, 3, kElementDofs> L;
    Eigen::Matrix3d A;
    double weight;
  };
  GreenOperators green_operators(int gauss_point) const;

  /// The generalized-strain operators at natural coordinates (xi, eta) in [-1, 1]^2, on E's dofs
  /// (d_E = blockdiag(R_WE^T) d_W), exactly those the stiffness integrates (it uses them at the
  /// 2x2 Gauss points xi, eta = +-1/sqrt(3)): membrane strain Bm, curvature Bb, the MITC4 assumed
  /// transverse shear Bs (Bathe & Dvorkin 1985, Eq. 11, from the tying points) and the gradients
  /// G of Eq. 20 for the Green strain of Eq. 14 (fem/ply_stress recovers stresses from them).
  struct StrainOperators {
    Eigen::Matrix<double, 3, kElementDofs> Bm;  // (eps_x, eps_y, gamma_xy), linear part
    Eigen::Matrix<double, 3, kElementDofs> Bb;  // (kappa_x, kappa_y, kappa_xy), 1/m
    Eigen::Matrix<double, 2, kElementDofs> Bs;  // (gamma_xz, gamma_yz)
    Eigen::Matrix<double, 6, kElementDofs> G;   // Psi = (u,x v,x w,x u,y v,y w,y)
  };
  StrainOperators strain_operators(double xi, double eta) const;
  /// The bilinear map of the natural coordinates to the mid-surface, world axes (m).
  Eigen::Vector3d position(double xi, double eta) const;
  /// What the force of internal_force() reads at Gauss point q besides the section constants
  /// (fem/shell_batch.hpp): the shape functions N_a, their gradients in E's axes, the MITC4
  /// shear operator on (w, theta_x, theta_y) of the four nodes (column 4 k + node) and the area
  /// weight (m^2).
  struct ForceOperators {
    Eigen::Vector4d N, dNx, dNy;
    Eigen::Matrix<double, 2, 12> Bs_wr;
    double weight;
  };
  ForceOperators force_operators(int q) const {
    const GaussPoint& p = gp_.at(q);
    return {p.N, p.dNx, p.dNy, p.Bs_wr, p.weight};
  }
  /// What the tangent of tangent_type_major() reads at Gauss point q besides force_operators():
  /// w A, w B Bb (the curvature operator on (theta_x, theta_y) of the nodes) and w As Bs_wr.
  struct TangentOperators {
    Eigen::Matrix3d wA;
    Eigen::Matrix<double, 3, 8> wBBb;
    Eigen::Matrix<double, 2, 12> wAsBs;
  };
  TangentOperators tangent_operators(int q) const {
    const GaussPoint& p = gp_.at(q);
    return {p.wA, p.wBBb, p.wAsBs};
  }
  /// The tangent's blocks that no displacement enters (type-major): bending and shear on
  /// (theta_x, theta_y) (rows and columns 12-19), and the drilling penalty's on (u, v, theta_z), a
  /// 12 x 12 whose corners (u, v) x theta_z, theta_z x (u, v) and theta_z x theta_z are the
  /// tangent's (rows and columns 0-7 and 20-23; the rest unused).
  const Eigen::Matrix<double, 8, 8>& rotation_tangent() const { return K_rot_; }
  const Eigen::Matrix<double, 12, 12>& drilling_tangent() const { return Kd_; }
  /// Whether the element's axes are exactly the world's (its dofs then need no rotation).
  bool world_axes() const { return world_axes_; }
  /// The drilling penalty's modulus kDrillingPenalty A66, N/m.
  double drill_modulus() const { return drill_modulus_; }
  /// The section constants the element was built with (laminate A, B, D, As).
  const Eigen::Matrix3d& A() const { return A_; }
  const Eigen::Matrix3d& B() const { return B_; }
  const Eigen::Matrix3d& D() const { return D_; }
  const Eigen::Matrix2d& As() const { return As_; }

 private:
  struct GaussPoint {
    Eigen::Matrix<double, 3, kElementDofs> Bm;  // membrane strain (eps_x, eps_y, gamma_xy)
    Eigen::Matrix<double, 3, kElementDofs> Bb;  // curvature (kappa_x, kappa_y, kappa_xy)
    Eigen::Matrix<double, 2, kElementDofs> Bs;  // MITC4 transverse shear (gamma_xz, gamma_yz)
    RowOp Bd;                                   // drilling: theta_z - (v,x - u,y) / 2
    Eigen::Matrix<double, 6, kElementDofs> G;   // Psi = (u,x v,x w,x u,y v,y w,y), Eq. 20
    Eigen::Matrix<double, 3, kElementDofs> Nu;  // mid-surface displacement (u, v, w)
    Eigen::Matrix<double, 3, kElementDofs> Nr;  // (beta_x, beta_y, theta_z)
    double weight;                              // Gauss weight x det J (m^2)
    Eigen::Vector3d X_W;                        // mid-surface position (m)
    // The same operators by node (internal_force): shape functions and their gradients, and Bs
    // on the dofs it touches, (w, theta_x, theta_y) of the four nodes, column 4 k + node.
    Eigen::Vector4d N, dNx, dNy;
    Eigen::Matrix<double, 2, 12> Bs_wr;
    Eigen::Matrix<double, 12, 2> Bs_wrT;  // its transpose, column-major (the tangent's products)
    // The tangent's factors that no displacement enters: w A, w B Bb, w As Bs_wr.
    Eigen::Matrix3d wA;
    Eigen::Matrix<double, 3, 8> wBBb;
    Eigen::Matrix<double, 2, 12> wAsBs;
  };
  /// internal_force()'s force (world axes) and type-major tangent (E axes), each if asked for;
  /// with `in_plane_rows` (an element in world axes), the force's in-plane rows alone.
  void evaluate(const ElemVec& d_W, ElemVec* f_W, ElemMat* K_t, double* energy, bool in_plane_rows = false) const;
  /// The tangent's blocks that no displacement enters, into K_rot_ and Kd_ (constructor).
  void constant_tangent();
  /// d_E = T d_W, T = blockdiag(R_WE^T); returns T^T K T. (The identity, copying, for an element
  /// whose axes are the world's: a mesh in the x-y plane along x.)
  ElemMat to_world(const ElemMat& K_E) const;
  ElemVec to_element(const ElemVec& d_W) const;
  ElemVec to_world(const ElemVec& f_E) const;

  // Section constants copied from the laminate (the element owns no reference to it).
  Eigen::Matrix3d A_, B_, D_;
  Eigen::Matrix2d As_;
  double I0_ = 0, I1_ = 0, I2_ = 0;
  Eigen::Matrix3d R_WE_;
  bool world_axes_ = false;  // R_WE_ is exactly the identity
  double area_ = 0;
  double drill_modulus_ = 0;  // N/m
  Eigen::Matrix<double, 4, 2> xy_;  // node coordinates in E (origin at the node centroid), m
  Eigen::Matrix<double, 4, 3> X_W_;  // node positions, world, m
  std::array<RowOp, 4> tying_;      // MITC4 covariant shear at the tying points B, D, A, C
  std::array<GaussPoint, 4> gp_;
  // Their sums over the Gauss points (type-major): bending and shear on (theta_x, theta_y), and
  // the drilling penalty's blocks with theta_z (the (u, v) x theta_z, theta_z x (u, v) and
  // theta_z x theta_z corners of a 12 x 12 on (u, v, theta_z); the rest unused).
  Eigen::Matrix<double, 8, 8> K_rot_;
  Eigen::Matrix<double, 12, 12> Kd_;
};

}  // namespace deployfx::fem
