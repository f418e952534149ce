#pragma once
// A flexible appendage described in its floating frame E (root edge clamped to E), compiled once:
// the shape integrals (FloatingFrameInertia, You et al. 2016 Eq. 9 and 28), for the reduced
// fidelities the Ritz basis (fem/ritz_basis.hpp) with the integrals projected on it and the
// exact modal internal force (fem/modal_internal_force.hpp), the stiffness and mass on the
// elastic coordinates, and Rayleigh damping. Part of the immutable multibody::Model; what a run
// remembers of it (the memos of its last evaluations) is a Workspace in the run's Data.
//
// Elastic coordinates q: the free mesh dofs d (full fidelities) or the Ritz coordinates eta,
// d = Phi eta (reduced); for reduced-manifold the bending Ritz coordinates alone, the in-plane
// ones slaved, eta = g(q) (fem/quadratic_manifold.hpp). inertia() works on "its dofs": all mesh
// dofs for a full model (stage() scatters the free ones into them), the Ritz coordinates for a
// reduced one (the identity, or g). The elastic force on them is (docs/engine-design.md,
// "Fidelity", "Damping")
//   f_int(d) + alpha_M L_c d' + beta_K K(d) d',
// f_int = K_L d (linear strain) or Green strain's force (Eq. 14; reduced: the exact cubic;
// manifold: the quartic g condenses exactly), K(d) = K_L or the tangent K_T(d) (damping the strain
// rate, so rigid motion is undamped). alpha_M L_c d' is formed with the inertial force's L_c d''
// (one product, multibody::inertial_wrench) and projected with it; on the manifold it acts on
// eta: G^T (Q + alpha_M L_c eta').
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deployfx/body/floating_frame_inertia.hpp"
#include "deployfx/body/node_mass_blocks.hpp"
#include "deployfx/fem/free_block.hpp"
#include "deployfx/fem/modal_internal_force.hpp"
#include "deployfx/fem/quadratic_manifold.hpp"
#include "deployfx/fem/ritz_basis.hpp"
#include "deployfx/fem/shell_model.hpp"

namespace deployfx::body {

/// The appendage's model: one rigid body; finite elements with linear or Green strain (Eq. 14);
/// the same two reduced to a Ritz basis (fem/ritz_basis.hpp) of a few modes; or reduced Green
/// strain with the in-plane coordinates slaved to the bending ones (fem/quadratic_manifold.hpp).
enum class Fidelity { kRigid, kLinear, kNonlinear, kReducedLinear, kReducedNonlinear, kReducedManifold };

/// The fidelity named "rigid", "linear", "nonlinear", "reduced-linear", "reduced-nonlinear" or
/// "reduced-manifold"; std::invalid_argument naming `name` and the allowed values otherwise.
Fidelity fidelity_from_name(const std::string& value, const std::string& name = "fidelity");

/// A panel's elastic state staged for one evaluation (multibody::Data keeps one per panel).
struct ElasticState {
  Eigen::VectorXd q, v, a;     ///< its elastic coordinates, rates, accelerations (n_el)
  Eigen::VectorXd d, dd, ddd;  ///< the same on its inertia's dofs (FlexibleBody::stage)
  Eigen::MatrixXd G;           ///< manifold: dd/dq (inertia dofs x n_el); empty otherwise
};

struct AppendageSpec {
  std::shared_ptr<const fem::ShellModel> model;  ///< nodes in E (m)
  std::vector<int> fixed_dofs;                   ///< clamped to E (the root edge)
  Fidelity fidelity = Fidelity::kNonlinear;
  /// Structural (Rayleigh) damping of the elastic dofs, C = alpha_M L_c + beta_K K (1/s and s):
  /// a modal damping ratio (alpha_M / omega + beta_K omega) / 2. K is K_L for linear strain and
  /// the tangent K_T(d) for Green strain (damping the strain rate, so rigid motion is undamped).
  double alpha_M = 0, beta_K = 0;
  /// Reduced fidelities: the clamped vibration modes kept; the basis adds the static corrections
  /// and, for Green strain, the modal derivatives of every pair among the first
  /// `derivative_modes` modes (-1: min(modes, 3); fewer lets the bending stretch the mid-surface,
  /// a spurious stiffening: docs/engine-design.md), and of each of the first
  /// `derivative_partners` modes with every mode and static correction (-1: automatic, 1;
  /// fem/ritz_basis.hpp).
  int modes = 10;
  int derivative_modes = -1;
  int derivative_partners = -1;
};

class FlexibleBody {
 public:
  /// What one run keeps of this body's evaluations: the memos of the floating-frame products and
  /// of the reduced Green-strain polynomial (multibody::Data holds one per panel). Optional
  /// everywhere (null: compute afresh).
  struct Workspace {
    FloatingFrameInertia::ProductsMemo products;
    fem::ModalInternalForce::Memo modal;
    Eigen::VectorXd mesh_force;  // in_plane_force()'s element forces (kept sized)
  };

  /// Checks the spec (std::invalid_argument naming `<name>.model`, `<name>.alpha_M`,
  /// `<name>.beta_K`, `<name>.modes`, `<name>.derivative_modes`, `<name>.derivative_partners`) and
  /// compiles it.
  /// `extra_loads` (mesh dofs x m, may have no columns): further load shapes whose static
  /// responses K^-1 f join a reduced basis, beside those of E's own acceleration (S1^T, H(0)^T,
  /// Eq. 28): e.g. unit loads where a child body is attached (system/chain_attachment.hpp).
  FlexibleBody(AppendageSpec spec, const std::string& name,
               const Eigen::MatrixXd& extra_loads = Eigen::MatrixXd());

  const AppendageSpec& spec() const { return spec_; }
  Fidelity fidelity() const { return spec_.fidelity; }
  bool flexible() const { return spec_.fidelity != Fidelity::kRigid; }
  bool green() const { return green_; }  ///< Green strain (full or reduced)
  bool reduced() const { return modal_.has_value(); }
  bool manifold() const { return manifold_.has_value(); }
  /// The elastic coordinates (0 for a rigid appendage).
  int num_elastic() const { return static_cast<int>(free_.size()); }
  /// The shape integrals on its dofs (projected on the basis for a reduced model).
  const FloatingFrameInertia& inertia() const { return ffi_; }
  /// Reduced: mesh displacements d = basis().Phi eta (empty for a full model).
  const fem::RitzBasis& basis() const { return basis_; }
  /// The elastic coordinates among inertia()'s dofs (manifold: the bending Ritz coordinates).
  const std::vector<int>& free_dofs() const { return free_; }
  /// inertia()'s dofs from the elastic coordinates: zero on the clamped ones; g(q) on the manifold.
  Eigen::VectorXd full(const Eigen::VectorXd& q_el) const;
  /// The same into `d` (a run's staged state: its storage is reused).
  void full(const Eigen::VectorXd& q_el, Eigen::VectorXd& d) const;
  /// Stages s.d, s.dd, s.ddd (and s.G) from s.q, s.v, s.a: d = full(q), dd = G v,
  /// ddd = G a + C(v, v) (the manifold's curvature; 0 otherwise).
  void stage(ElasticState& s) const;
  /// The coordinates mesh_rows() multiplies: the Ritz coordinates of a reduced panel (g(q) on
  /// the manifold), the elastic coordinates of a full one.
  int num_coordinates() const { return manifold_ ? manifold_->num_dofs() : num_elastic(); }
  /// The displacement of the given mesh dofs per coordinate (num_coordinates()), (rows.size() x
  /// num_coordinates()): rows of the basis (reduced) or a selection (full; zero rows for clamped dofs).
  Eigen::MatrixXd mesh_rows(const std::vector<int>& mesh_dofs) const;
  /// Those coordinates at q_el, and their derivative in q_el (num_coordinates() x num_elastic()):
  /// g(q) and G(q) on the manifold, q_el and the identity otherwise.
  Eigen::VectorXd coordinates(const Eigen::VectorXd& q_el) const;
  Eigen::MatrixXd coordinates_jacobian(const Eigen::VectorXd& q_el) const;

  /// Adds to r (size num_elastic()) the generalized force on the elastic coordinates of a force Q
  /// on inertia()'s dofs: its free entries, or G^T Q on the manifold.
  void add_projected(const ElasticState& s, const Eigen::VectorXd& Q, Eigen::Ref<Eigen::VectorXd> r) const;
  /// The same for each column of X (inertia dofs x m): (num_elastic() x m).
  Eigen::MatrixXd projected(const ElasticState& s, const Eigen::MatrixXd& X) const;
  /// The derivative along the elastic coordinates of a quantity y(d, dd, ddd) given its
  /// derivatives X_d, X_dd, X_ddd (m x inertia dofs; X_ddd may have no columns: y does not depend
  /// on ddd), combined as c_a d/da + c_v d/dv + c_q d/dq through the staging (stage()):
  /// (c_a X_ddd + c_v X_dd + c_q X_d) G + (c_q X_dd + 2 c_v X_ddd) C(v, .) + c_q X_ddd C(a, .) on the
  /// manifold, the free columns of the first term otherwise. (m x num_elastic())
  Eigen::MatrixXd chain(const ElasticState& s, double c_a, const Eigen::MatrixXd& X_ddd, double c_v,
                        const Eigen::MatrixXd& X_dd, double c_q, const Eigen::MatrixXd& X_d) const;
  /// The same from the combination X = c_a X_ddd + c_v X_dd + c_q X_d as the caller formed it
  /// (its rounding kept) and, read on the manifold only, W_v = c_q X_dd + 2 c_v X_ddd and
  /// W_a = c_q X_ddd (no columns: zero).
  Eigen::MatrixXd chain(const ElasticState& s, const Eigen::MatrixXd& X, const Eigen::MatrixXd& W_v,
                        const Eigen::MatrixXd& W_a) const;

  /// Adds the elastic force (header) at the staged s to r (size num_elastic()), but its
  /// mass-proportional damping alpha_M L_c d', which the generalized inertial force Q carries
  /// (multibody::inertial_wrench: FloatingFrameInertia::inertial_forces' `damping`, one product
  /// L_c (d'' + alpha_M d') for both).
  void add_elastic_force(const ElasticState& s, Eigen::Ref<Eigen::VectorXd> r, Workspace* ws = nullptr) const;
  /// The panel's own block of a Newton matrix (c_a d/da + c_v d/dv + c_q d/dq of its elastic rows
  /// in its elastic coordinates) into values aligned with block(): its generalized inertial force's
  /// (Q: its value at s; w, al: the frame's angular velocity and acceleration, in its axes) and the
  /// elastic force's (the d-derivative of the damping beta_K K_T(d) d' dropped).
  void elastic_block(const ElasticState& s, const Eigen::VectorXd& Q, const Eigen::Vector3d& w,
                     const Eigen::Vector3d& al, double c_a, double c_v, double c_q, Eigen::Ref<Eigen::VectorXd> vals,
                     Workspace* ws = nullptr) const;
  /// Green strain on a basis or mesh that splits by parity (fem/parity.hpp: a flat laminate
  /// without membrane-bending coupling): the elastic coordinates that move the mid-surface in its
  /// plane (in-plane Ritz vectors, or the u, v, theta_z dofs); empty otherwise. They are stiff
  /// (the paper's panel: omega dt = 14-670 for its in-plane Ritz vectors at dt = 10 ms) and
  /// follow the bending quadratically: integrate::SecondOrderSystem::slaved_velocities.
  const std::vector<int>& in_plane_coordinates() const { return in_plane_; }
  /// add_projected(Q) + add_elastic_force() at the in-plane coordinates alone (in their order),
  /// into out, from the frame's motion at s (a, al, w in its axes, as inertial_forces() takes
  /// them), for a mesh panel with Green strain: the inertial force's rows
  /// (FloatingFrameInertia::inertial_force_rows) and the elements' membrane and drilling terms
  /// (fem::ShellModel::in_plane_force), about half a residual's work. False (out untouched) for
  /// any other panel, whose caller takes the whole residual.
  bool in_plane_rows() const { return in_plane_rows_.has_value(); }  ///< in_plane_force() forms them
  bool in_plane_force(const ElasticState& s, const Eigen::Vector3d& a, const Eigen::Vector3d& al,
                      const Eigen::Vector3d& w, Eigen::Ref<Eigen::VectorXd> out, Workspace* ws = nullptr) const;
  /// Strain energy at the staged s, J.
  double strain_energy(const ElasticState& s, const Workspace* ws = nullptr) const;

  /// The elastic block of a Newton matrix on the mesh's node-block pattern (a dense pattern for a
  /// reduced model), with L_c, K_L and the nine M_ij aligned to it: a combination of them is a
  /// sum of value arrays (fem/free_block.hpp). Absent for a rigid appendage.
  const fem::FreeBlock& block() const { return *block_; }
  const Eigen::SparseMatrix<double>& stiffness() const { return K_free_; }  ///< K_L, free
  const Eigen::SparseMatrix<double>& mass() const { return M_free_; }       ///< L_c, free

 private:
  AppendageSpec spec_;
  FloatingFrameInertia ffi_;
  bool green_ = false;
  fem::RitzBasis basis_;
  std::optional<fem::ModalInternalForce> modal_;  // reduced fidelities: the force on q
  std::optional<fem::QuadraticManifold> manifold_;
  // Manifold: L_c and the nine M_ij on eta, dense (the block on q is G^T (.) G of them).
  Eigen::MatrixXd L_eta_;
  std::array<Eigen::MatrixXd, 9> Mij_eta_;
  // vals = c_a L_c + sum_ij c(i, j) M_ij, aligned with block(): the inertial part of a Newton
  // matrix's elastic block. Each M_ij is summed over its own nonzeros (on a mesh, 3-11 % of the
  // block's entries each: it couples two translation components). Not for the manifold.
  void mass_combination(double c_a, const Eigen::Matrix3d& c, Eigen::Ref<Eigen::VectorXd> vals) const;
  // Adds c_q d/dq + c_v d/dv of the elastic force to vals, but alpha_M's (mass_combination's,
  // on the manifold the inertial force's).
  void add_elastic_block(const Eigen::VectorXd& d, double c_v, double c_q, Eigen::Ref<Eigen::VectorXd> vals,
                         Workspace* ws) const;
  void manifold_block(const ElasticState& s, const Eigen::VectorXd& Q, const Eigen::Vector3d& w,
                      const Eigen::Vector3d& al, double c_a, double c_v, double c_q, Eigen::Ref<Eigen::VectorXd> vals,
                      Workspace* ws) const;
  // r += c K_L x and r += c L_c x on the elastic coordinates (not on the manifold): dense in a
  // Ritz basis, where every entry is nonzero (a sparse product's scatter over a full pattern
  // costs several times a dense one's sums), over the nonzeros on a mesh.
  void add_stiffness_product(double c, const Eigen::VectorXd& x, Eigen::Ref<Eigen::VectorXd> r) const;
  // r += beta_K K_T(d) d' on the elastic coordinates (a mesh with Green strain), or on the
  // in-plane ones alone (in_plane_force()).
  void add_strain_rate_damping(const Eigen::VectorXd& d, const Eigen::VectorXd& dd, bool in_plane,
                               Eigen::Ref<Eigen::VectorXd> r) const;
  // c_L L_c + sum_ij cm(i, j) M_ij on eta (manifold).
  Eigen::MatrixXd inertia_combination(double c_L, const Eigen::Matrix3d& cm) const;
  std::vector<int> free_;
  std::vector<std::array<int, 2>> free_runs_;  // a mesh's: (first k, length) of consecutive free_
  std::vector<int> in_plane_;  // in_plane_coordinates()
  // A mesh panel's in-plane rows of Q (in_plane_force()).
  std::optional<FloatingFrameInertia::RowSelection> in_plane_rows_;
  Eigen::SparseMatrix<double> K_free_, M_free_;
  // K_L by rows where the residual multiplies it (a mesh's): math/sparse_rows.hpp, Eigen's sums
  // without its scatter's latency.
  using RowMajorMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  RowMajorMatrix K_rows_;
  static void add_rows_product(double c, const RowMajorMatrix& A, const Eigen::VectorXd& x,
                               Eigen::Ref<Eigen::VectorXd> r);
  std::optional<fem::FreeBlock> block_;
  Eigen::VectorXd M_vals_, K_vals_;
  // Full nonlinear fidelity: each element entry's slot in block()'s values (-1: a fixed dof), so
  // the tangent is assembled straight into the iteration matrix's elastic block.
  fem::ShellModel::TangentSlots tangent_slots_;
  // The nonzeros of each M_ij aligned with block(): positions in its values, and the values. In a
  // Ritz basis (a dense block) every value, zeros included, and no positions: a combination is
  // then a vectorised sum over the whole array, not a scatter.
  struct AlignedNonzeros {
    std::vector<int> index;
    std::vector<double> value;
  };
  std::array<AlignedNonzeros, 9> Mij_nonzeros_;
  // mass_combination() by node blocks where the mesh allows (body/node_mass_blocks.hpp).
  std::optional<NodeMassBlocks> node_mass_blocks_;
  void align_Mij();
};

}  // namespace deployfx::body
