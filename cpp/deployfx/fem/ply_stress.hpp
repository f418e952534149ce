#pragma once
// Ply stresses and strains of a laminated MITC4 shell mesh, recovered from the mesh dofs (six per
// node, world axes, ShellModel's numbering) with the element's own interpolation
// (ShellElement::strain_operators), at each element's centroid or at its 2x2 Gauss points.
//
// At a sampling point, in the element frame E (x along the projected laminate reference axis):
// - membrane strain eps0 = Bm d, plus for StrainMeasure::Green the quadratic terms of the
//   paper's Eq. 14, 1/2 (|Psi_x|^2, |Psi_y|^2, 2 Psi_x.Psi_y), for StrainMeasure::VonKarman those
//   of the normal displacement w alone, 1/2 (w_x^2, w_y^2, 2 w_x w_y) (von Karman's plate strain:
//   the strain whose energy the reduced-manifold fidelity condenses, Green strain without the
//   in-plane displacements' own quadratic terms; docs/research/quadratic-manifold.md, section 3);
//   curvature kappa = Bb d; the shear resultants Q = As Bs d from the MITC4 assumed shear strains
//   (Bathe & Dvorkin 1985);
// - in ply k at height z: (eps_1, eps_2, gamma_12) = T_k (eps0 + z kappa), (sigma_1, sigma_2,
//   tau_12) = Q_k T_k (eps0 + z kappa) (classical lamination theory; Jones 1999, Sec. 4.2; Reddy
//   2004, Sec. 3.3); with Green strains these are second Piola-Kirchhoff stresses;
// - (tau_13, tau_23) = R_k H(z) Q with H the equilibrium distribution of
//   material/transverse_shear.hpp (Rolfes & Rohwer 1997) and R_k the in-plane rotation to the ply
//   axes; gamma_13 = tau_13 / G13, gamma_23 = tau_23 / G23.
// Each ply is sampled at three stations, its bottom, middle and top (z_k, (z_k + z_k+1) / 2,
// z_k+1): the in-plane fields are linear and the shear stresses quadratic in z within a ply, so
// the extremes of the in-plane stresses lie on the stations and Simpson's rule over them
// integrates the ply's stress resultants exactly.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "deployfx/fem/shell_model.hpp"
#include "deployfx/material/failure_criteria.hpp"
#include "deployfx/material/laminate.hpp"

namespace deployfx::fem {

enum class StrainMeasure { Linear, Green, VonKarman };
/// The measure named "linear", "green" or "von-karman"; std::invalid_argument naming `strain` and
/// the allowed values otherwise.
StrainMeasure strain_measure_from_name(const std::string& value);
/// Centroid: one point per element, (xi, eta) = (0, 0). Gauss: the stiffness's 2x2 points, in the
/// element's order (-g, -g), (g, -g), (g, g), (-g, g), g = 1/sqrt(3).
enum class Sampling { Centroid, Gauss };

constexpr int kPlyStations = 3;  // bottom, middle, top of each ply
constexpr int kPlyComponents = 5;  // (sigma_1, sigma_2, tau_12, tau_13, tau_23) or the strains
/// The section state at a sampling point: eps0 (3), kappa (3, 1/m), Q (2, N/m), E's axes.
using SectionState = Eigen::Matrix<double, 8, 1>;

/// Everything the recovery needs, precomputed from a mesh and its laminate (immutable).
struct PlyRecovery {
  Sampling sampling = Sampling::Centroid;
  int num_elements = 0, points_per_element = 0, num_plies = 0, num_dofs = 0;
  /// Per (element, point), index e * points_per_element + p: the rows Bm (3), Bb (3), As Bs (2)
  /// and G (6) on the element's 24 world dofs.
  std::vector<Eigen::Matrix<double, 14, kElementDofs>> op;
  std::vector<std::array<int, 4>> element_nodes;
  /// The sampling points on the mid-surface, world axes, m: (elements * points, 3).
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> points_W;
  struct PlyData {
    Eigen::Matrix3d T;   // laminate-axis strains to ply-axis strains
    Eigen::Matrix3d QT;  // laminate-axis strains to ply-axis stresses, Q_k T_k (Pa)
    std::array<double, kPlyStations> z;  // station heights, m
    std::array<Eigen::Matrix2d, kPlyStations> H;  // (tau_13, tau_23) = H Q at each station, 1/m
    double G13 = 0, G23 = 0;  // Pa
  };
  std::vector<PlyData> plies;
};

/// Throws std::invalid_argument when `laminate` is not the section `model` was built with.
PlyRecovery make_ply_recovery(const ShellModel& model, const material::Laminate& laminate,
                              Sampling sampling);

/// The section state of sampling point p of element e for the mesh dofs u (num_dofs values).
SectionState section_state(const PlyRecovery& r, const double* u, int e, int p, StrainMeasure measure);

/// The ply-axis stress (Pa) and, if strain is not null, strain of ply k at station j.
void ply_state(const PlyRecovery& r, const SectionState& s, int k, int j, material::PlyStress* stress,
               material::PlyStress* strain);

/// Every element's ply fields for u (num_dofs values): stress and strain (either may be null)
/// receive (elements, points, plies, stations, 5) row-major values. Throws for a wrong size or
/// non-finite u.
void ply_fields(const PlyRecovery& r, const Eigen::VectorXd& u, StrainMeasure measure, double* stress,
                double* strain);

}  // namespace deployfx::fem
