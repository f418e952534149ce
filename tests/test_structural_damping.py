"""Structural (Rayleigh) damping of the appendage: C = alpha_M M + beta_K K gives each mode the
damping ratio zeta = (alpha_M / omega + beta_K omega) / 2 (Clough & Penzien, Dynamics of
Structures, 1993, Sec. 12-4). The spin-up beam's strip (first bending frequency 3.80 rad/s) is
jerked by a short hub spin-up to 0.05 rad/s and then rings freely; the logarithmic decrement of
its tip deflection over four cycles gives zeta, within 5 % of the prediction.
"""
import numpy as np
import pytest

import deployfx as dfx
from deployfx import scenes

OMEGA_1 = 3.7977  # rad/s, 1.87510^2 sqrt(EI / (rho A L^4)) for the spin-up beam


def ringing(damping, fidelity="linear"):
    strip = scenes.spin_up_strip(20)
    model = (dfx.Scene().set_base(1.0, 1.0, free=False)
             .set_hinge(point=(0, 0, 0), axis=(0, 1, 0), spin_up=(0.05, 0.5))
             .set_appendage(strip.model, strip.fixed_dofs("CFFF"), fidelity=fidelity, damping=damping)
             .compile())
    r = model.simulate(12.0, 0.005, scheme=dfx.integrators.Newmark(), nodes={0: [20, 41]})
    tip = r.node_displacements_0[:, :, 2].mean(axis=1)
    t = r.t
    after = t > 1.0
    w, tt = tip[after], t[after]
    w = w - w[-400:].mean()  # about the quasi-static offset of the steady rotation (tiny)
    peaks = [k for k in range(1, len(w) - 1) if w[k] > w[k - 1] and w[k] >= w[k + 1] and w[k] > 0]
    return tt[peaks], w[peaks]


@pytest.mark.parametrize("damping,fidelity", [((0.0, 0.01), "linear"), ((0.2, 0.0), "linear"),
                                              ((0.0, 0.01), "nonlinear")])
def test_rayleigh_damping_ratio_from_the_logarithmic_decrement(damping, fidelity):
    # For Green strain the stiffness-proportional part is beta_K K_T(d) d' (the strain rate);
    # at this small amplitude K_T = K_L and the ratio is the same.
    alpha_M, beta_K = damping
    zeta = 0.5 * (alpha_M / OMEGA_1 + beta_K * OMEGA_1)
    tp, wp = ringing(damping, fidelity)
    assert len(wp) >= 5
    n = 4
    delta = np.log(wp[0] / wp[n]) / n
    measured = delta / np.sqrt(4 * np.pi**2 + delta**2)
    assert measured == pytest.approx(zeta, rel=0.05)
    assert np.mean(np.diff(tp[: n + 1])) == pytest.approx(2 * np.pi / (OMEGA_1 * np.sqrt(1 - zeta**2)), rel=0.02)


def test_negative_damping_is_rejected():
    strip = scenes.spin_up_strip(4)
    scene = (dfx.Scene().set_base(1.0, 1.0, free=False)
             .set_hinge(point=(0, 0, 0), axis=(0, 1, 0), spin_up=(0.05, 0.5)))
    with pytest.raises(ValueError, match="beta_K"):  # checked where it is set
        scene.set_appendage(strip.model, strip.fixed_dofs("CFFF"), fidelity="linear", damping=(0.0, -1e-3))
    with pytest.raises(ValueError, match="alpha_M"):
        scene.set_appendage(strip.model, strip.fixed_dofs("CFFF"), fidelity="linear", damping=(-0.1, 0.0))


@pytest.mark.parametrize("rate", [5e-324, 1e-300, 1e-3])
def test_green_strain_damping_is_continuous_down_to_denormal_rates(rate):
    """beta_K K_T(d) d' of Green strain is a central difference of the internal force along d'
    (body/flexible_body.cpp). Its step was once 1e-6 / |d'|, infinite for a denormal rate (a fuzz
    case: 'u has non-finite entries' from inside a run). Reference: linearity in d' at a bent
    state, the residual's damping part r(d') - r(0) = beta_K K_T d', against the rate's
    1e-3 m/s value scaled down: within 1e-6 relative for 1e-300, and the denormal rate's within
    its own round-off (the force is 0 there, as for d' = 0)."""
    strip = scenes.spin_up_strip(4)
    model = (dfx.Scene().set_base(1.0, 1.0, free=False)
             .set_hinge(point=(0, 0, 0), axis=(0, 1, 0), k_theta=1.0, fitting_inertia=0.1)
             .set_appendage(strip.model, strip.fixed_dofs("CFFF"), fidelity="nonlinear", damping=(0.0, 1e-3))
             .compile())
    core = model.core
    n, nq = core.num_velocities, core.num_positions
    rng = np.random.default_rng(0)
    q = core.initial_positions()
    q[nq - (n - 1):] = 1e-2 * rng.normal(size=n - 1)  # bent (elastic dofs after theta)
    direction = np.zeros(n)
    direction[1:] = rng.normal(size=n - 1)
    a = np.zeros(n)
    r0 = core.residual(q, np.zeros(n), a, 0.0)
    unit = (core.residual(q, 1e-3 * direction, a, 0.0) - r0) / 1e-3  # beta_K K_T along the direction
    got = core.residual(q, rate * direction, a, 0.0) - r0
    assert np.all(np.isfinite(got))
    np.testing.assert_allclose(got, rate * unit, rtol=0, atol=1e-6 * rate * np.abs(unit).max() + 1e-12 * np.abs(r0).max())
