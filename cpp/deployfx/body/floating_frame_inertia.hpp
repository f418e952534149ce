#pragma once
// Inertia shape integrals of a flexible body described in a floating frame E (the frame the
// body's elastic displacements are measured in): You et al. (2016) Eq. 9 and 28 (m_A, L_A, P_A,
// J_A, H_A, L_c and kin), in the invariant form of Shabana, "Dynamics of Multibody Systems",
// 4th ed., 2013, Sec. 5.4. Computed once per model from the shell model's own kinematics, so
// they are exact integrals of the finite-element mass distribution.
//
// A material point at reference position P (in E) moves to P + u, u = N(P) d for the element
// dofs d (in E axes). With E's origin velocity V and angular velocity w (both in E axes),
//   T = 1/2 m V.V + V.(w x s(d)) + V.(S1 dd) + 1/2 w.J(d) w + w.(H(d) dd) + 1/2 dd^T M dd,
// where s(d) = S0 + S1 d, J(d) = tr(E) I - E with E = int rho (P + u)(P + u)^T, and
// H(d) = int rho (P + u)~ N. The drilling inertia of the shell element (a numerical device,
// see ShellElement::mass) belongs to M only: drilling rotations move no material.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <vector>

#include "deployfx/fem/shell_model.hpp"

namespace deployfx::body {

class FloatingFrameInertia {
 public:
  using SparseMatrix = Eigen::SparseMatrix<double>;
  // Row-major: their rows are the integrals (int rho N_i, ...), each a contiguous vector over the
  // dofs, so that products with d are three (nine) long dot products and their rows are formed by
  // vector operations (column-major, a product with d was a chain of 3-long columns, latency-bound).
  using Matrix3X = Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>;
  using Matrix9X = Eigen::Matrix<double, 9, Eigen::Dynamic, Eigen::RowMajor>;

  /// The integrals over all dofs of `model`, whose world frame is taken as E.
  explicit FloatingFrameInertia(const fem::ShellModel& model);
  /// The same integrals in Ritz coordinates, d = Phi eta ((ndof x r) basis): exact, since every
  /// integral is linear or quadratic in d (S1 Phi, C Phi, Phi^T M_ij Phi, Phi^T M Phi).
  FloatingFrameInertia projected(const Eigen::MatrixXd& Phi) const;

  int num_dofs() const { return static_cast<int>(S1_.cols()); }
  double mass() const { return m_; }                        ///< m_A, kg
  const Eigen::Vector3d& S0() const { return S0_; }         ///< int rho P, kg m (m_A x centroid)
  const Eigen::Matrix3d& E0() const { return E0_; }         ///< int rho P P^T, kg m^2
  Eigen::Matrix3d J0() const;                               ///< J_A about E's origin, kg m^2
  const Matrix3X& S1() const { return S1_; }                ///< P_A = int rho N, (3 x ndof)
  /// int rho P_i N_j, (9 x ndof), row 3 i + j.
  const Matrix9X& C() const { return C_; }
  /// int rho N_i^T N_j for components i, j of the displacement, (ndof x ndof).
  SparseMatrix Mij(int i, int j) const;
  const SparseMatrix& M() const { return M_; }              ///< L_c: the element mass matrix
  /// L_c z: on a dense copy in a Ritz basis (projected(): every entry is nonzero there, and a
  /// sparse product's scatter over a full pattern costs several times a dense one's sums); on a
  /// mesh by rows, Eigen's sums (math/sparse_rows.hpp).
  Eigen::VectorXd mass_product(const Eigen::VectorXd& z) const;

  /// The products M_ij z (index k = 3 i + j) that every d-dependent integral below is built
  /// from: the cost of those integrals. Immutable and shared: the nine stacked in one vector
  /// (9 ndof), never written while anything but a memo holds it (products() reuses it then).
  class Products {
   public:
    Products() = default;
    Eigen::VectorXd::ConstSegmentReturnType operator[](int k) const {
      return static_cast<const Eigen::VectorXd&>(*p_).segment(k * n_, n_);
    }

   private:
    friend class FloatingFrameInertia;
    std::shared_ptr<Eigen::VectorXd> p_;
    Eigen::Index n_ = 0;
  };
  /// A run's memo of products(): the last few (z, M_ij z) it formed, handed out again for the
  /// same z, so the integrals at one d share one set (a Newton iteration asks for them at one d in
  /// its residual, momentum, matrix and momentum Jacobian). Per-run data (multibody::Data), never
  /// shared between runs: the model stays immutable and runs on it independent. A slot's storage
  /// is reused for the next z once nothing else holds it: a run allocates only its first few sets.
  class ProductsMemo {
   private:
    friend class FloatingFrameInertia;
    static constexpr int kSlots = 4;
    std::array<Eigen::VectorXd, kSlots> z;
    std::array<Products, kSlots> products;
    int next = 0;
  };
  /// M_ij z; from `memo` if it holds z (and recorded there otherwise); memo may be null.
  Products products(const Eigen::VectorXd& z, ProductsMemo* memo = nullptr) const;
  /// products(z1, memo), then products(z2, memo), into P1 and P2: two that the memo holds neither
  /// of are formed in one pass over the M_ij (the same sums; a residual's d and dd').
  void products(const Eigen::VectorXd& z1, const Eigen::VectorXd& z2, ProductsMemo* memo, Products& P1,
                Products& P2) const;

  /// s(d) = S0 + S1 d, the first moment of the deformed body, kg m.
  Eigen::Vector3d first_moment(const Eigen::VectorXd& d) const;
  /// J(d) about E's origin, kg m^2.
  Eigen::Matrix3d inertia_tensor(const Eigen::VectorXd& d, ProductsMemo* memo = nullptr) const;
  /// H(d) = int rho (P + u)~ N, the rotation-elastic coupling (H_A and kin), (3 x ndof).
  Matrix3X rotation_coupling(const Eigen::VectorXd& d, ProductsMemo* memo = nullptr) const;
  /// Kinetic energy for frame velocity V, angular velocity w (E axes), d and its rate dd, J.
  double kinetic_energy(const Eigen::Vector3d& V, const Eigen::Vector3d& w, const Eigen::VectorXd& d,
                        const Eigen::VectorXd& dd, ProductsMemo* memo = nullptr) const;
  /// dJ/dt for the rate dd, kg m^2/s.
  Eigen::Matrix3d inertia_tensor_rate(const Eigen::VectorXd& d, const Eigen::VectorXd& dd,
                                      ProductsMemo* memo = nullptr) const;
  /// Centrifugal load on d of the undeformed body, int rho N^T (w x (w x P)), N.
  Eigen::VectorXd centrifugal_load(const Eigen::Vector3d& w) const;
  /// Its elastic part: int rho N^T (w x (w x u)) = G_w d; G_w = sum w_i w_j M_ij - |w|^2 sum M_ii
  /// (the softening -Omega^2 M of Kane, Ryan & Banerjee 1987), N/m.
  SparseMatrix centrifugal_stiffness(const Eigen::Vector3d& w) const;
  /// Gyroscopic matrix: int rho N^T (w x u') = G_y dd, skew-symmetric, kg/s.
  SparseMatrix gyroscopic(const Eigen::Vector3d& w) const;

  /// d(J(d) x)/dd for a fixed vector x, (3 x ndof). Also J'(d, dd) x = this(d, x) dd.
  Matrix3X inertia_tensor_jacobian(const Eigen::VectorXd& d, const Eigen::Vector3d& x,
                                   ProductsMemo* memo = nullptr) const;
  /// d(J'(d, dd) x)/dd for fixed dd and x, (3 x ndof).
  Matrix3X inertia_rate_jacobian(const Eigen::VectorXd& dd, const Eigen::Vector3d& x,
                                 ProductsMemo* memo = nullptr) const;
  /// d(H(d) y)/dd for a fixed y (independent of d), (3 x ndof).
  Matrix3X rotation_coupling_jacobian(const Eigen::VectorXd& y, ProductsMemo* memo = nullptr) const;

  /// The inertial forces of the body, int rho A dV, int rho r x A dV about E's origin and
  /// int rho N^T A dV, for the point acceleration A = a + al x r + w x (w x r) + 2 w x u' + u''
  /// (frame origin acceleration a, angular velocity w and acceleration al, all in E axes).
  struct InertialForces {
    Eigen::Vector3d F;   ///< N
    Eigen::Vector3d M;   ///< N m, about E's origin
    Eigen::VectorXd Q;   ///< on the dofs d
  };
  /// With `damping` (alpha_M, 1/s), Q also holds the mass-proportional (Rayleigh) damping force
  /// alpha_M L_c dd', formed with the inertial term in one product L_c (dd'' + alpha_M dd').
  InertialForces inertial_forces(const Eigen::Vector3d& a, const Eigen::Vector3d& al,
                                 const Eigen::Vector3d& w, const Eigen::VectorXd& d,
                                 const Eigen::VectorXd& dd, const Eigen::VectorXd& ddd,
                                 ProductsMemo* memo = nullptr, double damping = 0.0) const;

  /// The inertial forces with their first derivatives, analytic (docs/engine-design.md,
  /// "Body-level equations"), from one set of the 27 products M_ij d, M_ij dd, M_ij dd'' (M_ij^T
  /// = M_ji). The d-, dd- and dd''-derivatives of Q are the sparse combinations L_c (dd''),
  /// 2 G_y(w) (dd) and G_y(al) + G_w(w) (d), which the caller forms on its own pattern.
  struct ForceJacobians {
    InertialForces f;
    Eigen::Vector3d s;    ///< s(d), kg m
    Eigen::Matrix3d J;    ///< J(d) about E's origin, kg m^2
    /// d(F, M)/d(a, al, w), (6 x 9), and dQ/d(a, al, w), (ndof x 9): columns a, al, w.
    Eigen::Matrix<double, 6, 9> FM_k;
    Eigen::Matrix<double, Eigen::Dynamic, 9> Q_k;
    /// d(F, M)/d dd'' = (S1; H(d)), d(F, M)/d dd' and d(F, M)/dd, (6 x ndof each).
    Eigen::Matrix<double, 6, Eigen::Dynamic> FM_ddd, FM_dd, FM_d;
  };
  ForceJacobians inertial_force_jacobians(const Eigen::Vector3d& a, const Eigen::Vector3d& al,
                                          const Eigen::Vector3d& w, const Eigen::VectorXd& d,
                                          const Eigen::VectorXd& dd, const Eigen::VectorXd& ddd,
                                          ProductsMemo* memo = nullptr) const;

  /// The generalized inertial force Q of inertial_forces() at a few of its dofs alone (a Newton
  /// sweep on a flat panel's in-plane rows needs no other: multibody::slaved_rows): each product
  /// with M_ij and L_c restricted to those rows, by rows (math/sparse_rows.hpp), the M_ij's from
  /// the node graph's sums where the mesh and the rows allow (by_nodes_). Immutable, formed once
  /// per model by select_rows() on a mesh.
  class RowSelection {
   public:
    const std::vector<int>& dofs() const { return dofs_; }

   private:
    friend class FloatingFrameInertia;
    std::vector<int> dofs_;
    // On a mesh with the node-graph form (NodeMass) and rows at in-plane dofs (u, v, theta_z: a
    // flat panel's slaved rows), the row products come from the nodes' sums (node_row_products())
    // and Mij_ is empty.
    bool by_nodes_ = false;
    Eigen::SparseMatrix<double, Eigen::RowMajor> Mij_;  // rows dofs_ of M_0 .. M_8, stacked (9 m x ndof)
    Eigen::SparseMatrix<double, Eigen::RowMajor> M_;    // rows dofs_ of L_c (m x ndof)
    Matrix3X S1_;                                       // columns dofs_ of S1
    Matrix9X C_;                                        // and of C
  };
  /// The selection of the given dofs (each in [0, num_dofs())); std::invalid_argument otherwise,
  /// or in a Ritz basis (projected(): its Q is a few dozen entries, formed whole).
  RowSelection select_rows(const std::vector<int>& dofs) const;
  /// Q's entries at rows.dofs() (in that order), as inertial_forces() forms them (to round-off;
  /// `damping` as there).
  Eigen::VectorXd inertial_force_rows(const RowSelection& rows, const Eigen::Vector3d& a, const Eigen::Vector3d& al,
                                      const Eigen::Vector3d& w, const Eigen::VectorXd& d, const Eigen::VectorXd& dd,
                                      const Eigen::VectorXd& ddd, double damping = 0.0) const;

 private:
  FloatingFrameInertia() = default;
  void check(const Eigen::VectorXd& d, const char* name) const;
  // The integrals above from the products Pd = products(d) (Py = products(y)).
  Eigen::Matrix3d inertia_tensor(const Eigen::VectorXd& d, const Products& Pd) const;
  Matrix3X rotation_coupling(const Products& Pd) const;
  void fill_rotation_coupling(const Products& Pd, Matrix3X& H) const;  // H(d) into H (3 x ndof)
  static Matrix3X rotation_coupling_jacobian(const Products& Py);
  // Rows g_ij = dE_ij/dd = [C_(ij) + C_(ji)] + (M_ij z + M_ji z)^T (z = d; without C: the rate
  // part, z = dd), from the products P = M_k z, contracted with x as tr(g) x - g x.
  Matrix3X contract_inertia(const Products& P, bool with_C, const Eigen::Vector3d& x) const;
  // The integrals at (d, dd') that the inertial forces need, from the products Pd = M_k d and
  // Pdd = M_k dd' (formulas of inertia_tensor(), rotation_coupling(), inertia_tensor_rate(),
  // centrifugal_stiffness() and gyroscopic()), and the forces they give.
  struct StateIntegrals {
    Eigen::Vector3d s;           // s(d)
    Eigen::Matrix3d J, Jdot;     // J(d), its rate
    Matrix3X H;                  // H(d)
    Eigen::VectorXd Gd, Gdd;     // G_w(w) d, G_y(w) dd'
  };
  StateIntegrals state_integrals(const Eigen::Vector3d& w, const Eigen::VectorXd& d,
                                 const Eigen::VectorXd& dd, const Products& Pd, const Products& Pdd) const;
  InertialForces forces(const StateIntegrals& g, const Eigen::Vector3d& a, const Eigen::Vector3d& al,
                        const Eigen::Vector3d& w, const Eigen::VectorXd& dd,
                        const Eigen::VectorXd& ddd, double damping = 0.0) const;
  double m_ = 0;
  Eigen::Vector3d S0_;
  Eigen::Matrix3d E0_;
  Matrix3X S1_;
  Matrix9X C_;
  // The nine int rho N_i^T N_j (index k = 3 i + j): sparse on the mesh's pattern, or, in a Ritz
  // basis (projected(); every entry is then nonzero), dense and stacked, rows k r .. k r + r - 1
  // of a (9 r x r) matrix, so that the nine products are one. Sparse, M_ji = M_ij^T, and
  // products() reads only the M_ij with i <= j (one pass gives M_ij z and M_ji z).
  std::array<SparseMatrix, 9> Mij_;
  std::array<Eigen::SparseMatrix<double, Eigen::RowMajor>, 3> Mii_rows_;  // M_ii by rows (products())
  Eigen::MatrixXd Mij_stacked_;
  bool dense_ = false;
  SparseMatrix M_;
  // M_ by rows (a mesh's; empty in a Ritz basis), for mass_product() and mass_product_add().
  Eigen::SparseMatrix<double, Eigen::RowMajor> M_rows_;
  Eigen::MatrixXd M_dense_;  // M_ in a Ritz basis (mass_product())
  // y += M_ z: on M_dense_ in a Ritz basis; for a mesh by rows (math/sparse_rows.hpp), the same
  // sums in the same order as Eigen's column-major product, whose scatter's latency took half of
  // forces()' time on the paper's 15 x 10 mesh; y and z distinct.
  void mass_product_add(const Eigen::VectorXd& z, Eigen::VectorXd& y) const;
  // The M_ij as three scalar matrices on the node graph (floating_frame_products.cpp), m[k](a, b) =
  // sum I_k w N_a N_b, one pattern, by rows; empty where the mesh's kinematics do not split so (a
  // mesh off the x-y plane, or an element in it whose normal is -z) and in a Ritz basis:
  // products() then runs on the M_ij.
  struct NodeMass {
    std::array<Eigen::SparseMatrix<double, Eigen::RowMajor>, 3> m;
    bool empty() const { return m[0].rows() == 0; }
  };
  NodeMass node_mass_;
  static NodeMass node_mass(const fem::ShellModel& model);
  // compute_products() by node_mass_ (floating_frame_products.cpp).
  template <int V>
  void node_products(const std::array<const Eigen::VectorXd*, V>& z, const std::array<Eigen::VectorXd*, V>& out) const;
  // The row products (M_k d, M_k dd') at rows.dofs_ (in-plane dofs: RowSelection::by_nodes_) into
  // P and R (9 m each, k-major), by node_mass_.
  void node_row_products(const RowSelection& rows, const Eigen::VectorXd& d, const Eigen::VectorXd& dd,
                         Eigen::VectorXd& P, Eigen::VectorXd& R) const;
  // c with centrifugal_load(w) = C^T c.
  static Eigen::Matrix<double, 9, 1> centrifugal_weights(const Eigen::Vector3d& w);
  // The nine M_k z[v] into out[v] (resized to 9 ndof), stacked, for V vectors at once.
  template <int V>
  void compute_products(const std::array<const Eigen::VectorXd*, V>& z,
                        const std::array<Eigen::VectorXd*, V>& out) const;
  // products()'s memo: the products of z if it holds them (null otherwise); a new set's storage
  // (the next slot's once nothing else holds it) recorded there for z.
  static const Products* recalled(const Eigen::VectorXd& z, const ProductsMemo* memo);
  static Products recorded(const Eigen::VectorXd& z, ProductsMemo* memo);
};

}  // namespace deployfx::body
