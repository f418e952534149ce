#pragma once
// Through-thickness distribution of the transverse shear stresses of a laminate from its shear
// resultants, by integrating the 3-D equilibrium equations (Rolfes & Rohwer, Int. J. Numer.
// Meth. Eng. 40, 1997, 51-60):
//   tau_xz,z = -(sigma_x,x + tau_xy,y),  tau_yz,z = -(tau_xy,x + sigma_y,y),  tau(-h/2) = 0,
// with their two assumptions: the membrane forces do not vary in the plane (N,x = N,y = 0) and
// the bending is two cylindrical modes, M_x,x = Q_x and M_y,y = Q_y (the derivatives of M_xy and
// the mixed ones neglected). The resultant gradients then give the strain gradients through the
// section compliance [A B; B D]^-1, and sigma(z) = Q_bar(z) (eps0 + z kappa) their stress
// gradients. The result, (tau_xz, tau_yz)(z) = H(z) (Q_x, Q_y), vanishes at both faces and
// integrates exactly to (Q_x, Q_y) for any lay-up; for a homogeneous section it is the parabola
// 3 Q / (2 h) (1 - 4 z^2 / h^2).
#include <Eigen/Core>
#include <vector>

#include "deployfx/material/laminate.hpp"

namespace deployfx::material {

/// H(z) for each z in [-h/2, h/2] (m, from the mid-plane), laminate axes: (tau_xz, tau_yz) =
/// H (Q_x, Q_y), 1/m. Throws std::invalid_argument for z outside the section.
std::vector<Eigen::Matrix2d> equilibrium_shear(const Laminate& laminate, const std::vector<double>& z);

}  // namespace deployfx::material
