"""Independent closed-form references used by the validation tests.

Each function cites its source; none calls deployfx.
"""
from __future__ import annotations

import numpy as np


def flexural_rigidity(E: float, nu: float, h: float) -> float:
    """Isotropic plate bending stiffness D = E h^3 / (12 (1 - nu^2)), N m."""
    return E * h**3 / (12.0 * (1.0 - nu**2))


def ss_plate_center_deflection_coefficient(terms: int = 200) -> float:
    """Navier series for the centre deflection of a simply supported square Kirchhoff plate under
    uniform load, w_c = alpha q a^4 / D (Timoshenko & Woinowsky-Krieger 1959, Sec. 30, Eq. 139):
    alpha = 16/pi^6 sum_{m,n odd} (-1)^((m+n)/2 - 1) / (m n (m^2 + n^2)^2) = 0.00406235."""
    s = 0.0
    for m in range(1, terms, 2):
        for n in range(1, terms, 2):
            s += (-1) ** ((m + n) // 2 - 1) / (m * n * (m * m + n * n) ** 2)
    return 16.0 / np.pi**6 * s


def ss_plate_frequency_kirchhoff(D: float, rho_h: float, a: float, b: float, m: int = 1, n: int = 1) -> float:
    """omega_mn = pi^2 ((m/a)^2 + (n/b)^2) sqrt(D / (rho h)), rad/s (Leissa 1969, NASA SP-160,
    Eq. 4.19)."""
    return np.pi**2 * ((m / a) ** 2 + (n / b) ** 2) * np.sqrt(D / rho_h)


def cross_ply_fsdt_navier_omega(A55: float, A44: float, D: np.ndarray, I0: float, I2: float,
                                a: float, b: float, m: int = 1, n: int = 1) -> float:
    """Lowest omega (rad/s) of mode (m, n) of a simply supported (SS-1) symmetric cross-ply plate
    in first-order shear deformation theory by the Navier solution (Reddy 2004, Sec. 7.3.3):
    w = W sin(ax) sin(by), phi_x = X cos(ax) sin(by), phi_y = Y sin(ax) cos(by). A44, A55 include
    the shear correction factor."""
    al, be = m * np.pi / a, n * np.pi / b
    S = np.array([
        [A55 * al**2 + A44 * be**2, A55 * al, A44 * be],
        [A55 * al, D[0, 0] * al**2 + D[2, 2] * be**2 + A55, (D[0, 1] + D[2, 2]) * al * be],
        [A44 * be, (D[0, 1] + D[2, 2]) * al * be, D[2, 2] * al**2 + D[1, 1] * be**2 + A44],
    ])
    Mm = np.diag([I0, I2, I2])
    lam = np.linalg.eigvals(np.linalg.solve(Mm, S)).real
    return float(np.sqrt(lam.min()))


def cross_ply_clpt_omega(D: np.ndarray, I0: float, a: float, b: float, m: int = 1, n: int = 1) -> float:
    """Classical (Kirchhoff) laminated plate theory, simply supported symmetric cross-ply, rotary
    inertia neglected (Reddy 2004, Eq. 6.3.31): omega^2 = pi^4/(I0) [D11 (m/a)^4
    + 2 (D12 + 2 D66) (m/a)^2 (n/b)^2 + D22 (n/b)^4]."""
    p, q = m / a, n / b
    return float(np.pi**2 * np.sqrt((D[0, 0] * p**4 + 2 * (D[0, 1] + 2 * D[2, 2]) * p**2 * q**2
                                     + D[1, 1] * q**4) / I0))


def cantilever_beam_frequency(EI_per_width: float, mass_per_area: float, L: float, mode: int = 1) -> float:
    """Euler-Bernoulli cantilever, omega_k = (beta_k L)^2 sqrt(EI / (m L^4)), rad/s, with
    beta_k L = 1.87510, 4.69409 (Blevins 1979, Table 8-1); per unit width."""
    beta_L = (1.8751040687, 4.6940911330)[mode - 1]
    return beta_L**2 * np.sqrt(EI_per_width / (mass_per_area * L**4))


def uniaxial_buckling_resultant_ss_square(D: float, b: float) -> float:
    """Critical compressive resultant of a simply supported square plate, N_cr = 4 pi^2 D / b^2,
    N/m (Timoshenko & Gere 1961, Sec. 9.2, k = 4)."""
    return 4.0 * np.pi**2 * D / b**2
