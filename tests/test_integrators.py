"""Accuracy and stability of the generalized-alpha family on linear oscillators, against the
closed forms of Hughes, "The Finite Element Method" (1987), Ch. 9, and Chung & Hulbert (1993)."""
import numpy as np
import pytest

from deployfx.integrators import HHT, GeneralizedAlpha, Newmark, SimulationError, simulate_linear


def measured_period(t, x):
    # Period from the zero up-crossings of x(t), linearly interpolated.
    s = np.where((x[:-1] < 0) & (x[1:] >= 0))[0]
    tc = t[s] - x[s] * (t[s + 1] - t[s]) / (x[s + 1] - x[s])
    return np.mean(np.diff(tc))


@pytest.mark.parametrize("Omega", [0.1, 0.3, 0.6])
def test_newmark_average_acceleration_period_error(Omega):
    # Trapezoidal rule: omega_bar h = 2 atan(Omega/2), Omega = omega h, so the period grows by
    # Omega / (2 atan(Omega/2)) - 1 (Hughes 1987 Sec. 9.3.2). Measured over many cycles to 1e-5.
    omega = 2 * np.pi
    h = Omega / omega
    tr = simulate_linear([[1.0]], [[0.0]], [[omega**2]], [1.0], [0.0], 200.0, h, Newmark())
    T_bar = measured_period(tr.t, tr.q[:, 0])
    expected = Omega / (2 * np.arctan(Omega / 2)) - 1
    assert T_bar / 1.0 - 1 == pytest.approx(expected, rel=1e-3, abs=1e-6)


def test_undamped_energy_conserved_without_dissipation():
    # Average acceleration and generalized-alpha with rho_inf = 1 conserve the energy of a linear
    # undamped system exactly (Hughes 1987 Sec. 9.3.3); 1e-10 relative over 1000 steps, 3 dofs.
    rng = np.random.default_rng(0)
    L = rng.normal(size=(3, 3))
    M = L @ L.T + 3 * np.eye(3)
    R = rng.normal(size=(3, 3))
    K = R @ R.T + np.eye(3)
    for scheme in (Newmark(), GeneralizedAlpha(1.0)):
        tr = simulate_linear(M, np.zeros((3, 3)), K, [1.0, -0.5, 0.2], [0.0, 1.0, 0.0], 50.0, 0.05, scheme)
        E = 0.5 * np.einsum("ni,ij,nj->n", tr.v, M, tr.v) + 0.5 * np.einsum("ni,ij,nj->n", tr.q, K, tr.q)
        assert np.abs(E / E[0] - 1).max() < 1e-10


@pytest.mark.parametrize("scheme", [Newmark(), HHT(-0.1), GeneralizedAlpha(0.8), GeneralizedAlpha(0.0)])
def test_second_order_convergence(scheme):
    # Global error at t = 1 s of x'' + x = 0 against cos t: order 2 for all these schemes
    # (Chung & Hulbert 1993 Sec. 3). Observed order from h = 0.02 / 0.01 / 0.005 in [1.9, 2.1].
    errs = []
    for h in (0.02, 0.01, 0.005):
        tr = simulate_linear([[1.0]], [[0.0]], [[1.0]], [1.0], [0.0], 1.0, h, scheme)
        assert tr.t[-1] == pytest.approx(1.0, abs=1e-12)
        errs.append(abs(tr.q[-1, 0] - np.cos(1.0)))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all((orders > 1.9) & (orders < 2.1)), orders


@pytest.mark.parametrize("rho_inf", [0.0, 0.5, 0.8])
def test_spectral_radius_at_infinite_frequency(rho_inf):
    # Chung & Hulbert (1993) Eq. 25: the principal roots at infinite frequency are a double
    # -rho_inf, so a stiff oscillator (omega h = 1e4) decays as (c0 + c1 k) rho_inf^k. Over steps
    # 100..500 the polynomial factor biases the per-step rate by (5)^(1/400) - 1 < 0.5 %:
    # tolerance 1 %. rho_inf = 0 annihilates the response (below 1e-6 of the start in 20 steps).
    omega = 1e4
    tr = simulate_linear([[1.0]], [[0.0]], [[omega**2]], [1.0], [0.0], 500.0, 1.0, GeneralizedAlpha(rho_inf))
    amp = np.abs(tr.q[:, 0]) + np.abs(tr.v[:, 0]) / omega
    if rho_inf == 0.0:
        assert amp[20] < 1e-6 * amp[0]
    else:
        rate = (amp[500] / amp[100]) ** (1 / 400)
        assert rate == pytest.approx(rho_inf, rel=0.01)


def test_parameters_follow_chung_hulbert_and_hht():
    from deployfx import _core

    p = _core.AlphaParameters.generalized_alpha(0.5)
    assert (p.alpha_m, p.alpha_f) == pytest.approx((0.0, 1 / 3))
    assert p.gamma == pytest.approx(0.5 - p.alpha_m + p.alpha_f)
    assert p.beta == pytest.approx(0.25 * (1 - p.alpha_m + p.alpha_f) ** 2)
    h = _core.AlphaParameters.hht(-0.2)
    assert (h.alpha_m, h.alpha_f, h.gamma, h.beta) == pytest.approx((0.0, 0.2, 0.7, 0.36))


def test_bad_scheme_parameters_name_the_parameter():
    with pytest.raises(ValueError, match="rho_inf"):
        simulate_linear([[1.0]], [[0.0]], [[1.0]], [1.0], [0.0], 1.0, 0.1, GeneralizedAlpha(1.5))
    with pytest.raises(ValueError, match="alpha"):
        simulate_linear([[1.0]], [[0.0]], [[1.0]], [1.0], [0.0], 1.0, 0.1, HHT(0.2))
    with pytest.raises(ValueError, match="dt"):
        simulate_linear([[1.0]], [[0.0]], [[1.0]], [1.0], [0.0], 1.0, -0.1)


def test_failure_keeps_the_computed_steps():
    # A system whose residual turns non-finite (K = inf is rejected up front, so use an overflow:
    # a negative stiffness of astronomic size makes the solution overflow after some steps).
    with pytest.raises(SimulationError) as e:
        simulate_linear([[1.0]], [[0.0]], [[-1e300]], [1.0], [0.0], 10.0, 0.1)
    assert "t = " in str(e.value)
    tr = e.value.result
    assert len(tr.t) >= 1 and np.all(np.isfinite(tr.q))


def _cantilever():
    """A 3 x 2 aluminium cantilever's scipy.sparse K and M, its clamped root dofs and a bent
    start (m) that is zero there."""
    import scipy.sparse

    import deployfx as dfx

    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=70e9, nu=0.33, rho=2700.0), 2e-3)])
    plate = dfx.Plate(1.0, 0.6, lam, nx=3, ny=2)
    K, M = plate.model.stiffness_matrix(), plate.model.mass_matrix()
    assert scipy.sparse.issparse(K) and scipy.sparse.issparse(M)
    fixed = plate.fixed_dofs("CFFF")
    q0 = np.zeros(plate.model.num_dofs)
    q0[2::6] = 1e-3 * plate.model.nodes[:, 0] ** 2
    return K, M, fixed, q0


def test_sparse_matrices_with_fixed_dofs_give_the_dense_reduced_run():
    # Issue 25: simulate_linear takes the scipy.sparse matrices a ShellModel gives and the fixed
    # dofs; the reference is the same run on dense matrices reduced to the free dofs by hand.
    # Same arithmetic on the same numbers: bit-identical; the fixed dofs stay exactly 0.
    import scipy.sparse

    K, M, fixed, q0 = _cantilever()
    C = 1e-3 * K
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    ix = np.ix_(free, free)
    dense = simulate_linear(M.toarray()[ix], C.toarray()[ix], K.toarray()[ix], q0[free], np.zeros(free.size),
                            0.05, 1e-3, GeneralizedAlpha(0.9))
    for fmt in (scipy.sparse.csc_matrix, scipy.sparse.csr_array):
        tr = simulate_linear(fmt(M), fmt(C), fmt(K), q0, np.zeros_like(q0), 0.05, 1e-3, GeneralizedAlpha(0.9),
                             fixed_dofs=fixed)
        assert tr.q.shape == (len(dense.t), K.shape[0])
        np.testing.assert_array_equal(tr.q[:, free], dense.q)
        np.testing.assert_array_equal(tr.v[:, free], dense.v)
        assert not tr.q[:, fixed].any() and not tr.v[:, fixed].any()
    assert np.abs(dense.q).max() > 1e-4  # it moved


def test_simulate_linear_names_a_bad_argument():
    K, M, fixed, q0 = _cantilever()
    n = K.shape[0]
    v0 = np.zeros(n)
    with pytest.raises(ValueError, match=r"K must be \(%d x %d\)" % (n, n)):
        simulate_linear(M, K, K[:-1, :-1], q0, v0, 0.01, 1e-3)
    with pytest.raises(ValueError, match="q0 must be %d finite numbers" % n):
        simulate_linear(M, K, K, q0[1:], v0, 0.01, 1e-3)
    with pytest.raises(ValueError, match=r"fixed_dofs = %d is out of range: must be in \[0, %d\]" % (n, n - 1)):
        simulate_linear(M, K, K, q0, v0, 0.01, 1e-3, fixed_dofs=[0, n])
    q_bad = q0.copy()
    q_bad[fixed[3]] = 1e-3
    with pytest.raises(ValueError, match=r"q0\[%d\] = 0.001: a fixed dof must start at 0" % fixed[3]):
        simulate_linear(M, K, K, q_bad, v0, 0.01, 1e-3, fixed_dofs=fixed)
    with pytest.raises(TypeError, match=r"fixed_dofs\[0\] must be an integer"):
        simulate_linear(M, K, K, q0, v0, 0.01, 1e-3, fixed_dofs=[0.5])
