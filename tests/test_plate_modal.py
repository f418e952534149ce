"""Natural frequencies of plates against published tables and closed forms."""
import numpy as np
import pytest
import scipy.linalg

import deployfx as dfx
from closed_forms import (
    cantilever_beam_frequency,
    cross_ply_clpt_omega,
    cross_ply_fsdt_navier_omega,
    flexural_rigidity,
    ss_plate_frequency_kirchhoff,
)

STEEL = dict(E=200e9, nu=0.3, rho=8000.0)


def isotropic_plate(a, b, h, nx, ny, E=200e9, nu=0.3, rho=8000.0):
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E, nu, rho), h, 0.0)])
    return dfx.Plate(a, b, lam, nx, ny)


def test_cantilever_square_plate_leissa():
    # Leissa (1969) NASA SP-160, Table 4.60 (Barton 1951), nu = 0.3, CFFF square:
    # lambda = omega a^2 sqrt(rho h / D) = 3.492, 8.525, 21.43, 27.33, 31.11. These sit ~0.6 %
    # above the converged thin-plate values, so a converged element lies slightly below:
    # tolerance -2.0 % .. +0.5 % on a 16 x 16 mesh at a/h = 1000.
    a, h = 1.0, 1e-3
    plate = isotropic_plate(a, a, h, 16, 16)
    D = flexural_rigidity(200e9, 0.3, h)
    lam = 2 * np.pi * plate.natural_frequencies(5, "CFFF") * a**2 * np.sqrt(8000 * h / D)
    ref = np.array([3.492, 8.525, 21.43, 27.33, 31.11])
    rel = lam / ref - 1
    assert np.all(rel < 0.005) and np.all(rel > -0.02), rel


def test_nafems_fv12_free_square_plate():
    # NAFEMS FV12 (NAFEMS R0015, "Selected benchmarks for natural frequency analysis", 1990):
    # free 10 x 10 x 0.05 m plate, E = 200 GPa, nu = 0.3, rho = 8000 kg/m^3. Six rigid-body modes,
    # then 1.622, 2.360, 2.922, 4.190, 4.190 Hz. Tolerance 1.5 % on a 16 x 16 mesh.
    plate = isotropic_plate(10.0, 10.0, 0.05, 16, 16)
    f = plate.natural_frequencies(11, "FFFF")
    assert np.all(np.abs(f[:6]) < 1e-3), f[:6]
    np.testing.assert_allclose(f[6:], [1.622, 2.360, 2.922, 4.190, 4.190], rtol=0.015)


def test_nafems_fv16_cantilever_square_plate():
    # NAFEMS FV16: the FV12 plate clamped along one edge: 0.421, 1.029, 2.582, 3.306, 3.753 Hz.
    # Tolerance 1.5 % on a 16 x 16 mesh.
    plate = isotropic_plate(10.0, 10.0, 0.05, 16, 16)
    f = plate.natural_frequencies(5, "CFFF")
    np.testing.assert_allclose(f, [0.421, 1.029, 2.582, 3.306, 3.753], rtol=0.015)


def cross_ply(a_over_h, a=1.0):
    E2 = 1e9
    m = dfx.Orthotropic(E1=40 * E2, E2=E2, G12=0.6 * E2, G13=0.6 * E2, G23=0.5 * E2, nu12=0.25,
                        rho=1.0)
    h = a / a_over_h
    return dfx.Laminate.from_angles(m, h / 4, [0, 90, 90, 0]), E2, h


def test_cross_ply_fsdt_reddy():
    # Reddy (2004) Table 7.3.3 (Khdeir & Reddy): SS-1 [0/90/90/0], E1/E2 = 40, G12 = G13 = 0.6 E2,
    # G23 = 0.5 E2, nu12 = 0.25, k = 5/6, a/h = 10: omega_bar = omega a^2/h sqrt(rho/E2) = 15.1426.
    # Check our Navier reference reproduces the table (1e-4), then the element (16 x 16) within 1 %.
    lam, E2, h = cross_ply(10)
    a = 1.0
    nav = cross_ply_fsdt_navier_omega(lam.As[0, 0], lam.As[1, 1], lam.D, lam.mass_per_area,
                                      lam.rotary_inertia_per_area, a, a)
    scale = a**2 / h * np.sqrt(1.0 / E2)
    assert nav * scale == pytest.approx(15.1426, rel=1e-4)
    f = dfx.Plate(a, a, lam, 16, 16).natural_frequencies(1, "SSSS")[0]
    assert 2 * np.pi * f * scale == pytest.approx(15.1426, rel=0.01)


def test_cross_ply_thin_limit_tends_to_clpt():
    # Same lay-up at a/h = 100: FSDT approaches CLPT, omega_bar = 18.89 at the thin limit
    # (Reddy 2004 Table 7.3.3). Element within 1 % of the Navier FSDT value, and within 2 % of CLPT.
    lam, E2, h = cross_ply(100)
    a = 1.0
    scale = a**2 / h * np.sqrt(1.0 / E2)
    clpt = cross_ply_clpt_omega(lam.D, lam.mass_per_area, a, a) * scale
    assert clpt == pytest.approx(18.89, rel=2e-3)
    nav = cross_ply_fsdt_navier_omega(lam.As[0, 0], lam.As[1, 1], lam.D, lam.mass_per_area,
                                      lam.rotary_inertia_per_area, a, a) * scale
    fe = 2 * np.pi * dfx.Plate(a, a, lam, 16, 16).natural_frequencies(1, "SSSS")[0] * scale
    assert fe == pytest.approx(nav, rel=0.01)
    assert fe == pytest.approx(clpt, rel=0.02)


def test_no_shear_locking_at_a_over_h_1e4():
    # Kirchhoff SS square plate, omega = 2 pi^2/a^2 sqrt(D/(rho h)) (Leissa 1969 Eq. 4.19).
    # A locking element would be far too stiff at a/h = 1e4; required: within 1 % on 16 x 16.
    a, h = 1.0, 1e-4
    f = isotropic_plate(a, a, h, 16, 16).natural_frequencies(1, "SSSS")[0]
    ref = ss_plate_frequency_kirchhoff(flexural_rigidity(200e9, 0.3, h), 8000 * h, a, a)
    assert 2 * np.pi * f == pytest.approx(ref, rel=0.01)


def test_convergence_rate_is_second_order():
    # Bilinear elements: frequency error O(h_e^2) on refinement (Bathe, "Finite Element
    # Procedures", 2014, Sec. 4.3). Observed order from meshes 4, 8, 16 must lie in [1.7, 2.3].
    a, h = 1.0, 1e-3
    ref = ss_plate_frequency_kirchhoff(flexural_rigidity(200e9, 0.3, h), 8000 * h, a, a)
    err = [abs(2 * np.pi * isotropic_plate(a, a, h, n, n).natural_frequencies(1, "SSSS")[0] - ref)
           for n in (4, 8, 16)]
    orders = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all((orders > 1.7) & (orders < 2.3)), orders


def test_free_plate_has_exactly_six_rigid_modes():
    plate = isotropic_plate(2.0, 1.0, 0.01, 8, 4)
    f = plate.natural_frequencies(8, "FFFF")
    assert np.all(f[:6] < 1e-3 * f[6]), f  # omega^2 below 1e-6 of the first elastic one
    assert f[6] > 1.0


def test_paper_appendage_mass_and_frequency_convergence():
    # You et al. (2016): 2.0 x 1.3 x 0.002 m, rho = 1600 kg/m^3: 8.32 kg (exact up to round-off).
    # Cantilever frequencies converge under refinement: successive differences shrink, and the
    # paper's 15 x 10 mesh is within 2 % of the 60 x 40 mesh for the first five modes.
    for layup in (1, 2):
        plates = [dfx.paper2016.appendage_plate(layup, 15 * k, 10 * k) for k in (1, 2, 4)]
        assert plates[0].mass == pytest.approx(8.32, rel=1e-12)
        f = np.array([p.natural_frequencies(5, "CFFF") for p in plates])
        d1, d2 = np.abs(f[1] - f[0]), np.abs(f[2] - f[1])
        assert np.all(d2 < d1), (d1, d2)
        np.testing.assert_allclose(f[0], f[2], rtol=0.02)


@pytest.mark.parametrize("layup", [1, 2])
def test_paper_appendage_first_bending_mode_matches_beam_theory(layup):
    # Wide cantilever strip, first bending mode: Euler-Bernoulli with the bending stiffness per
    # width between D11 - D12^2/D22 (free anticlastic curvature) and D11 (Blevins 1979 Table 8-1).
    # For these lay-ups the two bounds differ by < 0.1 %; shear deformation at L/h = 1000 is
    # negligible. Tolerance 1 % on the 30 x 20 mesh.
    lam = dfx.paper2016.appendage_laminate(layup)
    D = lam.D
    plate = dfx.paper2016.appendage_plate(layup, 30, 20)
    f1 = plate.natural_frequencies(1, "CFFF")[0]
    lo = cantilever_beam_frequency(D[0, 0] - D[0, 1] ** 2 / D[1, 1], lam.mass_per_area, 2.0)
    hi = cantilever_beam_frequency(D[0, 0], lam.mass_per_area, 2.0)
    assert lo / (2 * np.pi) * 0.99 < f1 < hi / (2 * np.pi) * 1.01


def test_modes_are_mass_normalised_shapes():
    plate = dfx.paper2016.appendage_plate(2)
    f, w = plate.modes(3, "CFFF")
    assert w.shape == (3, 11, 16)
    assert np.all(w[:, :, 0] == 0)  # the clamped root edge x = 0


@pytest.mark.parametrize("n", [18, 20, 24])
def test_every_mode_of_a_small_model(n):
    # Up to all 24 free dofs of a 2 x 1 cantilever (a complete modal basis, as a reduced model
    # with every mode asks for): the eigenvalues of the dense generalised problem (LAPACK, via
    # scipy.linalg.eigh) within 1e-9 relative plus that solver's own backward error, ~eps
    # lambda_max (Golub & Van Loan, Matrix Computations, 4th ed., Sec. 8.7: the in-plane and
    # drilling modes reach 1e13 (rad/s)^2, so the 0.8 Hz mode is only good to ~5e-5 there);
    # M-orthonormal shapes (1e-9).
    plate = dfx.paper2016.appendage_plate(2, 2, 1)
    fixed = plate.fixed_dofs("CFFF")
    free = np.setdiff1d(np.arange(plate.model.num_dofs), fixed)
    K = plate.model.stiffness_matrix().toarray()[np.ix_(free, free)]
    M = plate.model.mass_matrix().toarray()[np.ix_(free, free)]
    ref = scipy.linalg.eigh(K, M, eigvals_only=True)
    f, X = plate.model.modes(n, fixed)
    np.testing.assert_allclose((2 * np.pi * f) ** 2, ref[:n], rtol=1e-9, atol=1e-13 * ref.max())
    Xf = X[free]
    np.testing.assert_allclose(Xf.T @ M @ Xf, np.eye(n), atol=1e-9)
