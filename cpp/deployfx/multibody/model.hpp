#pragma once
// The compiled scene: immutable after construction, shared by every run on it (threads
// included). What a run changes lives in multibody::Data (data.hpp). One model for any tree:
// a base (free or fixed) and hinges on the base, on rigid bodies or on panels of any fidelity
// (docs/engine-design.md, "One engine for a tree").
//
// Coordinates (minimal, tree-structured: the paper's "Jacobian approach"), in this order, each
// block present only when the scene needs it:
//   q = [r_W (3), unit quaternion of R_WB (w, x, y, z)] [theta_k, undriven hinges] [eta_k, panels]
//   v = [v_W (3, W axes), w_B (3, B axes)]              [theta'_k]                  [eta'_k]
// with eta_k panel k's elastic coordinates (its free mesh dofs, m and rad, or its Ritz
// coordinates, kg^0.5 m), in hinge order. The Newton matrix's border is the base and hinge block
// (nb = 6 [free base] + undriven hinges); its elastic block E (ne = sum of the panels'
// coordinates) is sparse: each panel's own block, coupled only through the hinges that ride on
// panels (ElasticPattern).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deployfx/body/flexible_body.hpp"
#include "deployfx/multibody/attachment.hpp"
#include "deployfx/multibody/spec.hpp"

namespace deployfx::multibody {

constexpr int kBasePositions = 7;   ///< r_W and the quaternion
constexpr int kBaseVelocities = 6;  ///< v_W and w_B

/// Body k of the tree, carried by hinge k (compiled).
struct Body {
  int parent = -1;              ///< -1: the base
  std::vector<int> children;    ///< bodies whose hinges sit on this one
  std::vector<int> subtree;     ///< this body and all its descendants
  std::vector<int> ancestors;   ///< from the root's child down to the parent (empty on the base)
  RigidInertia rigid;           ///< everything rigid in C (a rigid panel merged in)
  std::shared_ptr<const body::FlexibleBody> panel;  ///< a deforming panel in C (null: none or rigid)
  std::optional<Attachment> attachment;             ///< hinge k on a deforming parent panel
  Eigen::Matrix3d axis_skew, axis_skew2;  ///< N = axis~ and N^2 (Rot(axis, theta) = I + sin N + (1 - cos) N^2)
  int iq_theta = -1, iv_theta = -1;  ///< the hinge angle's coordinate (-1: driven)
  int n_el = 0, iq_el = -1, iv_el = -1;  ///< the panel's elastic coordinates (0, -1: none)
  int ie = -1;                       ///< their first row in the Newton matrix's elastic block
};

/// A coordinate the Newton matrix and the momentum Jacobian differentiate by a derivative pass
/// of the kinematics (seeds.hpp): a border coordinate or an attachment's z_m.
struct Seed {
  enum Kind { kBase, kHinge, kAttachment } kind;
  int index;      ///< base coordinate (0-2: v_W, 3-5: w_B) or hinge k
  int component;  ///< attachment coordinate z_m, m in 0..5
};

/// The elastic block's sparsity: each panel's own block (fem/free_block.hpp) on the diagonal, and
/// for every hinge that rides on a panel p, the coupling between p's attachment coordinates A
/// and the elastic coordinates R of the hinge's subtree (rows R x columns A and their transpose;
/// the attachment's generalized force and the subtree's motion: newton_matrix.cpp).
struct ElasticPattern {
  Eigen::SparseMatrix<double> matrix;  ///< compressed, zero values
  /// Per body: its block's values -> slots of matrix (empty: no panel). `identity`: one panel and
  /// no coupling, so E is that panel's block itself.
  std::vector<std::vector<int>> body_slots;
  bool identity = false;
  /// Per body with an attachment on a panel: the rows R (elastic rows, E-relative) and A (the
  /// parent's attachment coordinates, E-relative), and the slots of E(R, A) and E(A, R).
  struct Coupling {
    std::vector<int> rows, cols;
    Eigen::MatrixXi slots_RA, slots_AR;
  };
  std::vector<std::optional<Coupling>> couplings;
};

class Model {
 public:
  /// Checks the spec (std::invalid_argument naming the parameter: `hinges[k].axis`,
  /// `hinges[k].panel.modes`, `base.mass`, ...) and compiles it: shape integrals, reduced bases
  /// (with attachment modes where a hinge rides on a reduced panel), attachments, coordinates.
  explicit Model(TreeSpec spec);

  const TreeSpec& spec() const { return spec_; }
  const HingeSpec& hinge(int k) const { return spec_.hinges[static_cast<std::size_t>(k)]; }
  const Body& body(int k) const { return bodies_[static_cast<std::size_t>(k)]; }
  int num_hinges() const { return static_cast<int>(bodies_.size()); }
  bool base_free() const { return spec_.base.free; }
  /// Bodies with a deforming panel, in hinge order.
  const std::vector<int>& panels() const { return panels_; }
  /// Hinges with a lock, in hinge order.
  const std::vector<int>& locks() const { return locks_; }
  int num_positions() const { return nq_; }
  int num_velocities() const { return nv_; }
  int border() const { return nb_; }   ///< base and hinge coordinates
  int elastic() const { return nv_ - nb_; }
  /// A free base conserves [P_W; H_W] (the paper's Eq. 36-43): no external load acts, and a
  /// prescribed hinge angle acts between the system's own bodies (Pi then depends on t too).
  int num_conserved() const { return base_free() ? 6 : 0; }
  /// Whether a hinge's angle is prescribed (the kinematics then depend on t).
  bool driven() const { return driven_; }
  const ElasticPattern& pattern() const { return pattern_; }
  /// The derivative passes' coordinates: the border's in the velocity ordering (base, then
  /// undriven hinges), then six per hinge on a panel, in hinge order.
  const std::vector<Seed>& seeds() const { return seeds_; }
  /// The first of hinge k's attachment seeds (-1: on the base or a rigid body).
  int attachment_seed(int k) const { return attachment_seed_[static_cast<std::size_t>(k)]; }

  /// The stowed configuration: base at rest at W's origin (identity attitude), every theta = 0,
  /// every panel undeformed.
  Eigen::VectorXd initial_positions() const;
  /// q (+) dq: the base attitude by R_WB exp(dpsi) (body axes), every other coordinate additive.
  Eigen::VectorXd retract(const Eigen::VectorXd& q, const Eigen::VectorXd& dq) const;
  /// Throws std::invalid_argument unless q, v (and a) have this model's sizes and are finite.
  void check_state(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd* a = nullptr) const;

 private:
  TreeSpec spec_;
  std::vector<Body> bodies_;
  std::vector<int> panels_, locks_;
  bool driven_ = false;
  int nq_ = 0, nv_ = 0, nb_ = 0;
  ElasticPattern pattern_;
  std::vector<Seed> seeds_;
  std::vector<int> attachment_seed_;
  void build_pattern();
};

/// Checks a rigid body's inertia: mass finite and >= 0 (> 0 if `definite`), com finite, inertia
/// about the com symmetric positive semidefinite (definite if `definite`). Throws
/// std::invalid_argument naming `<name>.mass`, `<name>.com` or `<name>.inertia`.
void check_rigid_inertia(const std::string& name, const RigidInertia& body, bool definite);

}  // namespace deployfx::multibody
