"""Lamina and laminate properties against closed forms of classical lamination theory
(Reddy 2004, Sec. 3.3; Jones 1999, Ch. 2 and 4)."""
import math

import numpy as np
import pytest

import deployfx as dfx

IM6 = dict(E1=177e9, E2=10.8e9, G12=7.6e9, G13=7.6e9, G23=8.504e9, nu12=0.27, rho=1600.0)


def test_isotropic_single_ply_section():
    # Homogeneous plate: A = E h/(1-nu^2) [1 nu 0; nu 1 0; 0 0 (1-nu)/2], B = 0, D = A h^2/12,
    # As = k G h (Reddy 2004 Eq. 3.3.20 for one isotropic layer). Tolerance: round-off, 1e-12.
    E, nu, rho, h = 70e9, 0.33, 2700.0, 0.003
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E, nu, rho), h, 0.0)])
    Q = E / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    np.testing.assert_allclose(lam.A, Q * h, rtol=1e-12)
    np.testing.assert_allclose(lam.B, 0.0, atol=1e-12 * E * h**2)
    np.testing.assert_allclose(lam.D, Q * h**3 / 12, rtol=1e-12)
    G = E / (2 * (1 + nu))
    np.testing.assert_allclose(lam.As, 5 / 6 * G * h * np.eye(2), rtol=1e-12)
    assert lam.shear_correction == pytest.approx(5 / 6)
    assert lam.mass_per_area == pytest.approx(rho * h, rel=1e-12)
    assert lam.rotary_inertia_per_area == pytest.approx(rho * h**3 / 12, rel=1e-12)
    assert lam.first_moment_per_area == pytest.approx(0.0, abs=1e-15)


def test_rotated_ply_stiffness_matches_tensor_rotation():
    # Independent route: rotate the fourth-order plane-stress stiffness as a tensor
    # (C'_ijkl = R_ip R_jq R_kr R_ls C_pqrs) and compare with Q_bar (Reddy Eq. 2.3.17). 1e-10.
    m = dfx.Orthotropic(**IM6)
    d = 1 - m.nu12 * m.nu21
    Q11, Q22, Q12, Q66 = m.E1 / d, m.E2 / d, m.nu12 * m.E2 / d, m.G12
    C = np.zeros((2, 2, 2, 2))
    C[0, 0, 0, 0], C[1, 1, 1, 1] = Q11, Q22
    C[0, 0, 1, 1] = C[1, 1, 0, 0] = Q12
    for i, j in [(0, 1), (1, 0)]:
        for k, l in [(0, 1), (1, 0)]:
            C[i, j, k, l] = Q66
    for angle in (0.0, 30.0, 45.0, 90.0, -60.0):
        t = math.radians(angle)
        R = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])  # material -> laminate
        Cl = np.einsum("ip,jq,kr,ls,pqrs->ijkl", R, R, R, R, C)
        expected = np.array([
            [Cl[0, 0, 0, 0], Cl[0, 0, 1, 1], Cl[0, 0, 0, 1]],
            [Cl[1, 1, 0, 0], Cl[1, 1, 1, 1], Cl[1, 1, 0, 1]],
            [Cl[0, 1, 0, 0], Cl[0, 1, 1, 1], Cl[0, 1, 0, 1]],
        ])
        got = dfx.Ply(m, 1e-3, angle).Q_bar()
        np.testing.assert_allclose(got, expected, rtol=1e-10, atol=1e-10 * Q11)


def test_cross_ply_coupling_closed_form():
    # Antisymmetric [0/90], plies t: B11 = -B22 = (Q11 - Q22) t^2 / 4... exactly
    # B = sum Q_k (z_k+1^2 - z_k^2)/2 = (Q90 - Q0) t^2/2 (Jones 1999 Sec. 4.5.2). 1e-12.
    m = dfx.Orthotropic(**IM6)
    t = 0.5e-3
    lam = dfx.Laminate.from_angles(m, t, [0, 90])
    Q0, Q90 = dfx.Ply(m, t, 0).Q_bar(), dfx.Ply(m, t, 90).Q_bar()
    np.testing.assert_allclose(lam.B, (Q90 - Q0) * t**2 / 2, rtol=1e-12, atol=1e-6)
    assert lam.B[0, 0] < 0 < lam.B[1, 1]


def test_paper_layups_symmetric_and_D_ordering():
    # Both lay-ups of You et al. (2016) Table 2 are symmetric: B = 0. Lay-up 2 moves the 90-degree
    # plies to the core, so D11 drops by the core's share 1/8 of (Q11 - Q22) h^3/12 ... here checked
    # by the exact CLT sum: D11 = (Q11 (h^3 - h_c^3) + Q22 h_c^3)/12, h_c = h/2.
    l1, l2 = dfx.paper2016.appendage_laminate(1), dfx.paper2016.appendage_laminate(2)
    h = 2e-3
    np.testing.assert_allclose(l1.B, 0, atol=1e-9)
    np.testing.assert_allclose(l2.B, 0, atol=1e-9)
    Q = dfx.Ply(dfx.paper2016.IM6_SC1081, 1, 0).Q_bar()
    D11 = (Q[0, 0] * (h**3 - (h / 2) ** 3) + Q[1, 1] * (h / 2) ** 3) / 12
    assert l2.D[0, 0] == pytest.approx(D11, rel=1e-12)
    assert l1.D[0, 0] == pytest.approx(Q[0, 0] * h**3 / 12, rel=1e-12)
    assert l1.thickness == pytest.approx(h) and l2.mass_per_area == pytest.approx(1600 * h)


@pytest.mark.parametrize(
    "make, name",
    [
        (lambda: dfx.Isotropic(-1.0, 0.3, 1.0), "Isotropic.E"),
        (lambda: dfx.Isotropic(1e9, 0.5, 1.0), "Isotropic.nu"),
        (lambda: dfx.Isotropic(1e9, 0.3, float("nan")), "Isotropic.rho"),
        (lambda: dfx.Orthotropic(**{**IM6, "G23": 0.0}), "Orthotropic.G23"),
        (lambda: dfx.Orthotropic(**{**IM6, "nu12": 5.0}), "Orthotropic.nu12"),
        (lambda: dfx.Laminate([]), "Laminate.plies"),
        (lambda: dfx.Laminate([dfx.Ply(dfx.Orthotropic(**IM6), -1e-3, 0)]), "thickness"),
        (lambda: dfx.Laminate([dfx.Ply(dfx.Orthotropic(**IM6), 1e-3, float("inf"))]), "angle_deg"),
    ],
)
def test_invalid_material_input_names_parameter(make, name):
    with pytest.raises(ValueError, match=name):
        make()


def test_error_message_states_value_and_range():
    with pytest.raises(ValueError) as e:
        dfx.Orthotropic(**{**IM6, "nu12": 5.0})
    msg = str(e.value)
    assert "5" in msg and "sqrt(E1/E2)" in msg and "(-4.04" in msg


def test_type_errors_name_parameter():
    with pytest.raises(TypeError, match="Isotropic.E"):
        dfx.Isotropic("steel", 0.3, 7800)
    with pytest.raises(TypeError, match="Ply.material"):
        dfx.Ply("steel", 1e-3, 0)
