"""Static plate deflections against Kirchhoff closed forms, and patch tests."""
import numpy as np
import pytest

import deployfx as dfx
from closed_forms import flexural_rigidity, ss_plate_center_deflection_coefficient


def square(h, n, a=1.0):
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(200e9, 0.3, 8000.0), h, 0.0)])
    return dfx.Plate(a, a, lam, n, n)


def test_navier_coefficient_reference():
    # Timoshenko & Woinowsky-Krieger (1959) Table 8: alpha = 0.00406 (0.00406235 to 6 digits).
    assert ss_plate_center_deflection_coefficient() == pytest.approx(4.06235e-3, rel=1e-5)


def test_simply_supported_square_uniform_load():
    # w_c = 4.06235e-3 q a^4 / D (Timoshenko & Woinowsky-Krieger 1959, Sec. 30). a/h = 1000,
    # 16 x 16 mesh: within 1 %.
    a, h, q = 1.0, 1e-3, 100.0
    w = square(h, 16, a).static(q, "SSSS")
    D = flexural_rigidity(200e9, 0.3, h)
    assert w[8, 8] == pytest.approx(4.06235e-3 * q * a**4 / D, rel=0.01)
    assert w.shape == (17, 17)
    np.testing.assert_allclose(w, w.T, rtol=1e-9, atol=1e-12 * abs(w).max())  # square symmetry


def test_clamped_square_uniform_load():
    # w_c = 0.00126 q a^4 / D (Timoshenko & Woinowsky-Krieger 1959, Sec. 44, Table 35;
    # 0.00126532 by Taylor & Govindjee 2004). 16 x 16 mesh: within 1.5 %.
    a, h, q = 1.0, 1e-3, 100.0
    w = square(h, 16, a).static(q, "CCCC")
    D = flexural_rigidity(200e9, 0.3, h)
    assert w[8, 8] == pytest.approx(0.00126532 * q * a**4 / D, rel=0.015)


def test_singular_boundary_is_reported():
    with pytest.raises(ValueError, match="boundary.*rigid-body"):
        square(1e-3, 4).static(1.0, "FFFF")


# MacNeal & Harder (1985), Finite Elem. Anal. Des. 1, 3-20: the 0.24 x 0.12 patch of five
# distorted elements.
PATCH_NODES = np.array([[0, 0], [0.24, 0], [0.24, 0.12], [0, 0.12],
                        [0.04, 0.02], [0.18, 0.03], [0.16, 0.08], [0.08, 0.08]])
PATCH_QUADS = np.array([[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7], [4, 5, 6, 7]])


def patch_model(h=1e-3):
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(1e6, 0.25, 1.0), h, 0.0)])
    nodes = np.column_stack([PATCH_NODES, np.zeros(8)])
    return dfx.ShellModel(nodes, PATCH_QUADS, lam)


def solve_patch(model, exact):
    # Impose the exact field on the four outer nodes; the four inner nodes must reproduce it.
    u_exact = np.concatenate([exact(x, y) for x, y in PATCH_NODES])
    K = model.stiffness_matrix()
    fixed = np.arange(24)
    free = np.arange(24, 48)
    f = -K[:, fixed] @ u_exact[fixed]
    u = np.zeros(48)
    u[free] = np.linalg.solve(K[free][:, free].toarray(), f[free])
    u[fixed] = u_exact[fixed]
    return u, u_exact


def test_membrane_patch_test():
    # u = 1e-3 (x + y/2), v = 1e-3 (y + x/2): constant strain; drilling rotation
    # (v,x - u,y)/2 = 0. Exact to round-off (1e-10 relative).
    def exact(x, y):
        return np.array([1e-3 * (x + y / 2), 1e-3 * (y + x / 2), 0, 0, 0, 0])

    u, u_exact = solve_patch(patch_model(), exact)
    # Round-off against each field's own scale: translations (m) against max |u|, rotations
    # (rad, the drilling ones here) against the strain 1e-3 that sets them.
    translation = np.arange(48) % 6 < 3
    np.testing.assert_allclose(u[translation], u_exact[translation], atol=1e-10 * np.abs(u_exact).max())
    np.testing.assert_allclose(u[~translation], u_exact[~translation], atol=1e-10 * 1e-3)


def test_bending_patch_test():
    # w = 1e-3 (1 + x + y + x^2 + xy + y^2)/2 with Kirchhoff rotations beta = -grad w
    # (theta_x = w,y, theta_y = -w,x): constant curvature and zero shear, which MITC4 represents
    # exactly (Bathe & Dvorkin 1985). Exact to 1e-8 relative.
    def exact(x, y):
        wx, wy = 1e-3 * (1 + 2 * x + y) / 2, 1e-3 * (1 + x + 2 * y) / 2
        w = 1e-3 * (1 + x + y + x * x + x * y + y * y) / 2
        return np.array([0, 0, w, wy, -wx, 0])

    u, u_exact = solve_patch(patch_model(), exact)
    np.testing.assert_allclose(u, u_exact, atol=1e-8 * np.abs(u_exact).max())
