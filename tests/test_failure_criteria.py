"""Failure indices at known ply stress states against hand values of each criterion.

References: maximum stress and Tsai-Wu in plane stress (Jones, *Mechanics of Composite
Materials*, 1999, Sec. 2.9); Tsai & Wu, J. Compos. Mater. 5 (1971) 58-80, with
F12 = F12* sqrt(F11 F22) (Tsai & Hahn 1980); Hashin, J. Appl. Mech. 47 (1980) 329-334, with
sigma_3 = 0. deployfx reports every index as the inverse strength ratio FI = 1/R, R the factor that
brings the stress state onto the failure surface, so each hand check solves F(R s) = 1 for R
independently (numpy's polynomial roots) and compares 1/R.

The strengths are round numbers chosen for hand arithmetic, not a material's allowables.
"""
import numpy as np
import pytest

import deployfx as dfx
from deployfx import stress

MPa = 1e6
ST = dfx.Strengths(Xt=1500 * MPa, Xc=1200 * MPa, Yt=50 * MPa, Yc=200 * MPa, S12=70 * MPa,
                   S13=80 * MPa, S23=60 * MPa)
IN_PLANE = dfx.Strengths(Xt=1500 * MPa, Xc=1200 * MPa, Yt=50 * MPa, Yc=200 * MPa, S12=70 * MPa)


def fi(s, strengths=ST, criterion="tsai_wu"):
    return float(stress.failure_index(np.array(s, dtype=float), strengths, criterion))


def inverse_ratio(quadratic, linear):
    """1/R for the smallest positive root of quadratic R^2 + linear R - 1 = 0 (hand solution)."""
    roots = np.roots([quadratic, linear, -1.0]) if quadratic else np.array([1.0 / linear])
    R = min(r.real for r in np.atleast_1d(roots) if abs(r.imag) < 1e-12 and r.real > 0)
    return 1.0 / R


@pytest.mark.parametrize("s, expected", [
    ((750 * MPa, 0, 0, 0, 0), 0.5),                       # sigma_1 / Xt
    ((-600 * MPa, 0, 0, 0, 0), 0.5),                      # |sigma_1| / Xc
    ((0, 25 * MPa, 49 * MPa, 0, 0), 0.7),                 # tau_12 / S12 governs
    ((0, -150 * MPa, 0, 0, 0), 0.75),                     # |sigma_2| / Yc
    ((100 * MPa, 10 * MPa, 0, 60 * MPa, 0), 0.75),        # tau_13 / S13 (S13 given)
    ((100 * MPa, 10 * MPa, 0, 0, -54 * MPa), 0.9),        # |tau_23| / S23 (S23 given)
])
def test_maximum_stress_is_the_largest_stress_to_strength_ratio(s, expected):
    # Jones 1999, Sec. 2.9.1; exact arithmetic.
    assert fi(s, criterion="max_stress") == pytest.approx(expected, rel=1e-14)


def test_maximum_stress_ignores_interlaminar_shear_without_its_allowable():
    assert fi((100 * MPa, 0, 0, 60 * MPa, 54 * MPa), IN_PLANE, "max_stress") == pytest.approx(
        100 / 1500, rel=1e-14)


@pytest.mark.parametrize("s", [(1500 * MPa, 0, 0, 0, 0), (-1200 * MPa, 0, 0, 0, 0),
                               (0, 50 * MPa, 0, 0, 0), (0, -200 * MPa, 0, 0, 0),
                               (0, 0, 70 * MPa, 0, 0), (0, 0, -70 * MPa, 0, 0)])
def test_tsai_wu_is_one_at_each_uniaxial_strength(s):
    # Tsai & Wu 1971: F1 = 1/Xt - 1/Xc, F11 = 1/(Xt Xc), ... put the uniaxial strengths on the
    # surface.
    assert fi(s, IN_PLANE) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("F12_star", [-0.5, 0.0, 0.3])
def test_tsai_wu_biaxial_state_against_the_hand_strength_ratio(F12_star):
    Xt, Xc, Yt, Yc, S = 1500 * MPa, 1200 * MPa, 50 * MPa, 200 * MPa, 70 * MPa
    st = dfx.Strengths(Xt=Xt, Xc=Xc, Yt=Yt, Yc=Yc, S12=S, F12_star=F12_star)
    s1, s2, t12 = 500 * MPa, 20 * MPa, 30 * MPa
    F1, F2 = 1 / Xt - 1 / Xc, 1 / Yt - 1 / Yc
    F11, F22, F66 = 1 / (Xt * Xc), 1 / (Yt * Yc), 1 / S**2
    F12 = F12_star * np.sqrt(F11 * F22)
    quad = F11 * s1**2 + F22 * s2**2 + F66 * t12**2 + 2 * F12 * s1 * s2
    lin = F1 * s1 + F2 * s2
    got = fi((s1, s2, t12, 0, 0), st)
    assert got == pytest.approx(inverse_ratio(quad, lin), rel=1e-12)
    # The defining property: the state scaled by R = 1/FI lies on the Tsai-Wu surface.
    R = 1 / got
    assert quad * R**2 + lin * R == pytest.approx(1.0, rel=1e-12)


def test_tsai_wu_includes_interlaminar_shear_when_given():
    # Tsai & Wu 1971's F44 tau_23^2 + F55 tau_13^2 with F44 = 1/S23^2, F55 = 1/S13^2.
    assert fi((0, 0, 0, 80 * MPa, 0)) == pytest.approx(1.0, rel=1e-12)
    assert fi((0, 0, 0, 0, 60 * MPa)) == pytest.approx(1.0, rel=1e-12)
    assert fi((0, 0, 0, 80 * MPa, 60 * MPa), IN_PLANE) == 0.0


def test_hashin_fibre_modes():
    # Tension: (s1/Xt)^2 + (t12^2 + t13^2)/S12^2 = 1; compression: |s1| = Xc.
    assert fi((0.6 * 1500 * MPa, 0, 0.8 * 70 * MPa, 0, 0), criterion="hashin_fibre") == \
        pytest.approx(1.0, rel=1e-12)
    assert fi((0.6 * 1500 * MPa, 0, 0, 0.8 * 70 * MPa, 0), criterion="hashin_fibre") == \
        pytest.approx(1.0, rel=1e-12)
    s = (900 * MPa, 40 * MPa, 20 * MPa, 10 * MPa, 30 * MPa)
    assert fi(s, criterion="hashin_fibre") == pytest.approx(
        np.sqrt((900 / 1500) ** 2 + (20**2 + 10**2) / 70**2), rel=1e-12)
    assert fi((-600 * MPa, 0, 50 * MPa, 0, 0), criterion="hashin_fibre") == \
        pytest.approx(0.5, rel=1e-14)


def test_hashin_matrix_modes():
    Yt, Yc, S12, S23 = 50 * MPa, 200 * MPa, 70 * MPa, 60 * MPa
    # Tension: (s2/Yt)^2 + t23^2/S23^2 + (t12^2 + t13^2)/S12^2 = 1.
    assert fi((0, 0.6 * Yt, 0, 0, 0.8 * S23), criterion="hashin_matrix") == \
        pytest.approx(1.0, rel=1e-12)
    s = (300 * MPa, 30 * MPa, 20 * MPa, 15 * MPa, 25 * MPa)
    assert fi(s, criterion="hashin_matrix") == pytest.approx(
        np.sqrt((30 / 50) ** 2 + (25 / 60) ** 2 + (20**2 + 15**2) / 70**2), rel=1e-12)
    # Compression: (s2/2S23)^2 + [(Yc/2S23)^2 - 1] s2/Yc + t23^2/S23^2 + (t12^2+t13^2)/S12^2 = 1,
    # exactly 1 at s2 = -Yc.
    assert fi((0, -Yc, 0, 0, 0), criterion="hashin_matrix") == pytest.approx(1.0, rel=1e-12)
    s2, t12, t23 = -100 * MPa, 35 * MPa, 20 * MPa
    quad = (s2 / (2 * S23)) ** 2 + t23**2 / S23**2 + t12**2 / S12**2
    lin = ((Yc / (2 * S23)) ** 2 - 1) * s2 / Yc
    assert fi((0, s2, t12, 0, t23), criterion="hashin_matrix") == pytest.approx(
        inverse_ratio(quad, lin), rel=1e-12)


def test_hashin_is_the_larger_mode():
    s = np.array([[900 * MPa, 10 * MPa, 20 * MPa, 10 * MPa, 30 * MPa],
                  [100 * MPa, 45 * MPa, 20 * MPa, 10 * MPa, 30 * MPa]])
    both = stress.failure_index(s, ST, "hashin")
    expected = np.maximum(stress.failure_index(s, ST, "hashin_fibre"),
                          stress.failure_index(s, ST, "hashin_matrix"))
    np.testing.assert_array_equal(both, expected)
    assert both[0] == stress.failure_index(s, ST, "hashin_fibre")[0]
    assert both[1] == stress.failure_index(s, ST, "hashin_matrix")[1]


def test_every_index_is_the_inverse_strength_ratio():
    # FI(s / FI(s)) = 1 for every criterion: the state scaled by R = 1/FI lies on the surface.
    # Maximum stress and Hashin's fibre modes are homogeneous: FI(2.5 s) = 2.5 FI(s).
    rng = np.random.default_rng(3)
    s = rng.normal(size=(20, 5)) * np.array([600, 40, 40, 30, 30]) * MPa
    for criterion in stress.CRITERIA:
        a = stress.failure_index(s, ST, criterion)
        b = stress.failure_index(2.5 * s, ST, criterion)
        on_surface = stress.failure_index(s / a[:, None], ST, criterion)
        np.testing.assert_allclose(on_surface, 1.0, rtol=1e-10)
        if criterion in ("max_stress", "hashin_fibre"):
            np.testing.assert_allclose(b, 2.5 * a, rtol=1e-12)


def test_margin_of_safety():
    np.testing.assert_allclose(stress.margin_of_safety([0.5, 1.0, 2.0]), [1.0, 0.0, -0.5],
                               rtol=1e-15)
    assert stress.margin_of_safety(0.0) == np.inf
    with pytest.raises(ValueError, match="index"):
        stress.margin_of_safety([-0.1])


def test_strengths_are_checked():
    with pytest.raises(ValueError,
                       match=r"Strengths\.Xc = -1200000000 is out of range: must be > 0"):
        dfx.Strengths(Xt=1500 * MPa, Xc=-1200 * MPa, Yt=50 * MPa, Yc=200 * MPa, S12=70 * MPa)
    with pytest.raises(ValueError, match=r"Strengths\.S23"):
        dfx.Strengths(Xt=1.0, Xc=1.0, Yt=1.0, Yc=1.0, S12=1.0, S23=0.0)
    with pytest.raises(ValueError, match=r"Strengths\.F12_star = 1 is out of range"):
        dfx.Strengths(Xt=1.0, Xc=1.0, Yt=1.0, Yc=1.0, S12=1.0, F12_star=1.0)
    with pytest.raises(TypeError, match=r"Strengths\.Xt must be a real number"):
        dfx.Strengths(Xt="1.5e9", Xc=1.0, Yt=1.0, Yc=1.0, S12=1.0)
    with pytest.raises(ValueError, match="S23 is required by Hashin's matrix modes"):
        stress.failure_index(np.zeros(5), IN_PLANE, "hashin_matrix")
    with pytest.raises(ValueError, match="criterion = 'puck' is invalid"):
        stress.failure_index(np.zeros(5), IN_PLANE, "puck")
    with pytest.raises(ValueError, match="5 components"):
        stress.failure_index(np.zeros(4), IN_PLANE)
    with pytest.raises(ValueError, match="non-finite"):
        stress.failure_index(np.full(5, np.nan), IN_PLANE)
