"""Classical lamination theory written independently of deployfx, for the ply-stress tests.

Plane-stress lamina stiffness from the compliance (Jones, *Mechanics of Composite Materials*,
1999, Sec. 2.5), rotation of strain and stress as second-order tensors (Jones Sec. 2.6), A, B, D
by summing the rotated stiffness over the plies (Jones Sec. 4.2; Reddy, *Mechanics of Laminated
Composite Plates and Shells*, 2004, Sec. 3.3), and the transverse shear stresses of Rolfes &
Rohwer (Int. J. Numer. Meth. Eng. 40, 1997, 51-60) by numerical integration of the equilibrium
equations on a fine grid. Nothing here calls deployfx.
"""
from __future__ import annotations

import numpy as np


def lamina_Q(E1, E2, G12, nu12):
    """(sigma_1, sigma_2, tau_12) = Q (eps_1, eps_2, gamma_12): the inverse of the compliance."""
    S = np.array([[1 / E1, -nu12 / E1, 0], [-nu12 / E1, 1 / E2, 0], [0, 0, 1 / G12]])
    return np.linalg.inv(S)


def _rotation(theta_deg):
    t = np.deg2rad(theta_deg)
    return np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])  # columns: fibre, transverse


def strain_to_ply(eps_xy, theta_deg):
    """(eps_x, eps_y, gamma_xy) in laminate axes to (eps_1, eps_2, gamma_12) of a ply at theta."""
    ex, ey, gxy = eps_xy
    E = np.array([[ex, gxy / 2], [gxy / 2, ey]])
    R = _rotation(theta_deg)
    M = R.T @ E @ R
    return np.array([M[0, 0], M[1, 1], 2 * M[0, 1]])


def stress_to_laminate(sig_12, theta_deg):
    """(sigma_1, sigma_2, tau_12) of a ply at theta to (sigma_x, sigma_y, tau_xy)."""
    s1, s2, t12 = sig_12
    S = np.array([[s1, t12], [t12, s2]])
    R = _rotation(theta_deg)
    M = R @ S @ R.T
    return np.array([M[0, 0], M[1, 1], M[0, 1]])


def shear_to_ply(tau_xz_yz, theta_deg):
    """(tau_xz, tau_yz) to (tau_13, tau_23): a vector rotated into the ply axes."""
    return _rotation(theta_deg).T @ np.asarray(tau_xz_yz)


def Q_bar(Q, theta_deg):
    """Laminate-axis stiffness of a rotated ply, column by column from unit strains."""
    return np.column_stack([stress_to_laminate(Q @ strain_to_ply(e, theta_deg), theta_deg)
                            for e in np.eye(3)])


def ply_stress(Q, theta_deg, eps0, kappa, z):
    """Ply-axis (sigma_1, sigma_2, tau_12) at z for mid-plane strain eps0 and curvature kappa."""
    return Q @ strain_to_ply(np.asarray(eps0) + z * np.asarray(kappa), theta_deg)


def abd(Q, angles_deg, t):
    """The 6x6 [A B; B D] of plies of stiffness Q and thickness t, bottom first."""
    h = t * len(angles_deg)
    A, B, D = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3))
    for k, a in enumerate(angles_deg):
        z0, z1 = -h / 2 + k * t, -h / 2 + (k + 1) * t
        Qb = Q_bar(Q, a)
        A += Qb * (z1 - z0)
        B += Qb * (z1**2 - z0**2) / 2
        D += Qb * (z1**3 - z0**3) / 3
    return np.block([[A, B], [B, D]])


def equilibrium_shear_numeric(Q, angles_deg, t, z_out, per_ply=4000):
    """H(z) (len(z_out), 2, 2): (tau_xz, tau_yz) = H (Q_x, Q_y) from integrating
    tau_xz,z = -(sigma_x,x + tau_xy,y), tau_yz,z = -(tau_xy,x + sigma_y,y) upward from the bottom
    face with the trapezoid rule, for the gradients M_x,x = Q_x, M_y,y = Q_y, N and M_xy constant
    (Rolfes & Rohwer 1997)."""
    h = t * len(angles_deg)
    F = np.linalg.inv(abd(Q, angles_deg, t))
    gx, gy = F[:, 3], F[:, 4]
    zs, dsig = [], []
    for k, a in enumerate(angles_deg):
        z = np.linspace(-h / 2 + k * t, -h / 2 + (k + 1) * t, per_ply + 1)
        Qb = Q_bar(Q, a)
        sx = Qb @ (gx[:3, None] + z[None, :] * gx[3:, None])  # (3, m): stress gradients ,x / Q_x
        sy = Qb @ (gy[:3, None] + z[None, :] * gy[3:, None])
        rate = np.stack([np.stack([-sx[0], -sy[2]]), np.stack([-sx[2], -sy[1]])])  # (2, 2, m)
        zs.append(z)
        dsig.append(rate)
    z = np.concatenate(zs)
    rate = np.concatenate(dsig, axis=2)
    dz = np.diff(z)
    H = np.concatenate([np.zeros((2, 2, 1)),
                        np.cumsum(0.5 * (rate[:, :, 1:] + rate[:, :, :-1]) * dz, axis=2)], axis=2)
    return np.stack([np.stack([np.interp(z_out, z, H[i, j]) for j in range(2)]) for i in range(2)]
                    ).transpose(2, 0, 1)
