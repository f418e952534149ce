#pragma once
// A Ritz basis for a reduced appendage, d = Phi eta: the clamped appendage's lowest vibration
// modes (Craig-Bampton with a fully clamped interface: the fixed-interface normal modes, and no
// constraint modes since the interface does not move relative to E), enriched where it pays:
// - static corrections: K^-1 of the loads that E's own acceleration puts on the appendage
//   (int rho N^T a and int rho N^T (al x P): the mode-acceleration correction for the loads
//   that actually drive it; Dickens, Nakagawa & Wittbrodt, Comput. Struct. 62, 1997);
// - modal derivatives for Green strain: -K^-1 (dK_T/d phi_j) phi_i (Idelsohn & Cardona, CMAME
//   49, 1985), the in-plane motion that large bending drags along, without which a bending-only
//   basis stretches the mid-surface and stiffens spuriously. Which pairs: every pair among the
//   first `derivative_modes` modes, and each of the first `derivative_partners` modes with every
//   other direction of the bending span (every mode, and the static corrections' parts beyond the
//   modes): a mode j bent together with mode i stretches the mid-surface by q(phi_i, phi_j), which
//   only the derivative of the pair relaxes; without it mode j stiffens with mode i's amplitude
//   (docs/research/undamped-stability.md: the first mode's partners keep every condensed bending
//   frequency at the first mode's amplitude that of the full in-plane motion).
// The span is orthonormalised in M and rotated to Ritz vectors (Phi^T M Phi = I,
// Phi^T K Phi = diag(omega2)), so the reduced linear model is diagonal. Where K and M decouple
// bending from in-plane motion (a flat symmetric laminate, parity.hpp), this is done in each
// parity's part of the span: every vector is exactly one or the other, not mixed by round-off.
#include <Eigen/Core>
#include <vector>

#include "deployfx/fem/shell_model.hpp"

namespace deployfx::fem {

struct RitzBasisOptions {
  int modes = 10;            ///< clamped vibration modes, >= 1
  bool static_correction = true;
  int derivative_modes = 0;  ///< modal derivatives of every pair among the first this many modes
  /// and of each of the first this many modes with every mode and with the static corrections'
  /// directions beyond the modes (their bending parts where the span splits by parity)
  int derivative_partners = 0;
};

struct RitzBasis {
  Eigen::MatrixXd Phi;     ///< (ndof x r), zero on the fixed dofs
  Eigen::VectorXd omega2;  ///< Ritz values, (rad/s)^2, ascending (the first `modes` are the modes')
  /// Vectors proposed of each kind; Phi has fewer columns if some repeated others (dropped).
  int modes = 0, static_corrections = 0, modal_derivatives = 0;
};

/// `inertial_loads`: (ndof x m) load shapes for the static correction (ignored without it).
/// Throws std::invalid_argument for modes out of [1, free dofs], derivative_modes or
/// derivative_partners out of [0, modes], or fixed dofs that leave the clamped stiffness singular.
RitzBasis ritz_basis(const ShellModel& model, const std::vector<int>& fixed,
                     const RitzBasisOptions& options, const Eigen::MatrixXd& inertial_loads);

}  // namespace deployfx::fem
