"""deployfx.resolution: the periods a step must resolve, and the warning when it does not.

References: the rigid panel swinging on its hinge spring on a fixed base is a compound pendulum
without gravity, T = 2 pi sqrt(I / k_theta), I = m ((L + b)^3 - b^3) / (3 L) + the fitting's
inertia (the paper's panel, You et al. 2016: m = 8.32 kg, L = 2.0 m, root offset b = 0.03 m;
the plate's thickness adds m h^2 / 12, 2.4e-7 of I, left out: tolerance 1e-6). A full panel's
period is its tenth clamped mode's, the same as deployfx.Plate.natural_frequencies (a second
solver path over the same mesh; 1e-9); a reduced panel's its basis' Ritz value.
"""
import math

import numpy as np
import pytest

from deployfx import paper2016, resolution, scenes


def test_rigid_swing_matches_the_compound_pendulum():
    scene = scenes.paper2016(2, "rigid", nx=2, ny=1, base_free=False)
    (p,) = resolution.periods(scene)
    q = scene.parameters
    b, L = q.root_offset, paper2016.LENGTH
    inertia = 8.32 * ((L + b) ** 3 - b ** 3) / (3 * L) + q.fitting_inertia
    assert p["period_s"] == pytest.approx(2 * math.pi * math.sqrt(inertia / q.k_theta), rel=1e-6)
    assert p["hinge"] == 0 and "swing" in p["what"]


def test_panel_periods_are_the_kept_modes():
    f = paper2016.appendage_plate(2).natural_frequencies(10, "CFFF")
    full = resolution.shortest_period(scenes.paper2016(2, "nonlinear"))
    assert full["period_s"] == pytest.approx(1 / f[9], rel=1e-9)
    reduced = resolution.shortest_period(scenes.paper2016(2, "reduced-linear", modes=4))
    assert reduced["period_s"] == pytest.approx(1 / f[3], rel=1e-9)
    # the swing is listed too, longest first
    periods = [p["period_s"] for p in resolution.periods(scenes.paper2016(2, "linear"))]
    assert periods == sorted(periods, reverse=True) and len(periods) == 2


@pytest.mark.parametrize("period, dt", [(0.0548, 0.01), (0.01753, 0.002), (1.0, 0.2), (0.04, 0.01), (4e-5, 1e-5)])
def test_suggested_dt_is_the_largest_round_step_with_four_steps_a_period(period, dt):
    assert resolution.suggested_dt(period) == dt
    assert dt <= period / resolution.STEPS_PER_PERIOD * (1 + 1e-12)


def test_step_warning_at_the_limit():
    scene = scenes.paper2016(2, "nonlinear")
    T = resolution.shortest_period(scene)["period_s"]
    assert resolution.step_warning(scene, T / 4) is None
    message = resolution.step_warning(scene, 0.05)
    assert message.startswith("dt = 0.05 s does not resolve the scene")
    assert f"{T:.4g} s" in message and "use dt <= 0.01 s" in message
    # A scene without a spring or a deforming panel has nothing to resolve.
    assert resolution.step_warning(scenes.paper2016(2, "rigid", nx=2, ny=1, tau0=0.0, k_theta=0.0), 10.0) is None


@pytest.mark.parametrize("call, match", [
    (lambda: resolution.suggested_dt(0.0), "period_s = 0.0 is out of range"),
    (lambda: resolution.suggested_dt(np.inf), "period_s = inf is out of range"),
    (lambda: resolution.suggested_dt(1.0, steps=0), "steps = 0 is out of range"),
    (lambda: resolution.step_warning(scenes.paper2016(2, "rigid", nx=2, ny=1), -1.0), "dt = -1.0 is out of range"),
])
def test_bad_input_is_named(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_a_swing_needs_twenty_steps_a_period():
    # The trapezoidal rule lengthens a period sampled N times by (2 pi / N)^2 / 12: 3.4 % at the
    # paper's 9.88 s swing with dt = 1 s, whose rigid first lock then comes 70 ms late (2.52 s,
    # against 2.45 s at dt = 0.01 s; the lock time within 0.01 s of the energy quadrature's).
    scene = scenes.paper2016(2, "rigid", nx=2, ny=1)
    (swing,) = resolution.periods(scene)
    assert swing["steps"] == resolution.STEPS_PER_SWING == 20
    assert resolution.step_warning(scene, swing["period_s"] / 20) is None
    message = resolution.step_warning(scene, 1.0)
    assert "swing" in message and "about 3.4 % long" in message and "use dt <= 0.2 s" in message
    late = scenes.paper2016(2, "rigid", nx=2, ny=1).simulate(3.0, 1.0).summary()["first_lock_time_s"][0]
    fine = scenes.paper2016(2, "rigid", nx=2, ny=1).simulate(3.0, 0.2).summary()["first_lock_time_s"][0]
    assert late - 2.45 > 0.05 and abs(fine - 2.45) < 0.01
