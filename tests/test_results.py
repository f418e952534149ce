"""The results layer: metric definitions on analytic signals with closed-form answers, the Result
container (read-only arrays, validation, lossless save/load, DataFrame layout, summary) and the
paper's figures. Synthetic series only: no engine run."""
import math
import sys

import numpy as np
import pytest

from deployfx import metrics, plot, results
from deployfx.results import Result


def grid(t_end, dt):
    """Samples 0, dt, ..., t_end (s)."""
    return np.linspace(0.0, t_end, int(round(t_end / dt)) + 1)


def half_sines(t, starts, width, peaks):
    """Sum of half-sine pulses p sin(pi (t - a) / width) on [a, a + width] (N)."""
    f = np.zeros_like(t)
    for a, p in zip(starts, peaks):
        inside = (t > a) & (t < a + width)
        f[inside] += p * np.sin(np.pi * (t[inside] - a) / width)
    return f


# Paper-like record: four impacts ~4.9 s apart (a harmonic rebound's half period), peaks halving.
DT = 0.01
T = grid(30.0, DT)
STARTS = (2.463, 7.361, 12.259, 17.157)
WIDTH = 0.2
PEAKS = (4000.0, 2000.0, 1000.0, 500.0)


# ---------------------------------------------------------------- impacts and the first lock


def test_separated_half_sine_pulses_are_counted_with_their_peaks():
    f = half_sines(T, STARTS, WIDTH, PEAKS)
    assert metrics.impact_count(T, f) == 4
    # The sample nearest each crest is within dt/2 of it: p cos(pi dt / (2 width)) <= peak <= p.
    peaks = metrics.impact_peaks(T, f)
    assert np.all(peaks <= PEAKS)
    assert np.all(peaks >= np.array(PEAKS) * np.cos(np.pi * DT / (2 * WIDTH)))
    assert metrics.peak_lock_force(f) == peaks[0] == f.max()
    # Each interval runs from the first to the last sample strictly inside its pulse.
    spans = metrics.contact_intervals(T, f)
    assert spans.shape == (4, 2)
    assert np.all((spans[:, 0] > STARTS) & (spans[:, 0] <= np.array(STARTS) + DT + 1e-12))
    assert np.all((spans[:, 1] < np.array(STARTS) + WIDTH) &
                  (spans[:, 1] >= np.array(STARTS) + WIDTH - DT - 1e-12))


def test_chatter_within_one_contact_is_one_impact_and_a_real_opening_is_two():
    f = half_sines(T, STARTS[:1], WIDTH, PEAKS[:1])
    on = np.flatnonzero(f > 0)
    chatter = f.copy()
    chatter[on[3]] = 0.0             # one sample open: 0.02 s between in-contact samples
    chatter[on[8]:on[10]] = 0.0      # two samples: 0.03 s
    chatter[on[14]:on[19]] = 0.0     # five samples: 0.06 s, not < min_gap: separate contacts
    assert metrics.impact_count(T[: on[14]], chatter[: on[14]]) == 1
    assert metrics.impact_count(T, chatter) == 2
    # Without the hysteresis every run counts: the rule, not luck, merges the chatter.
    assert metrics.impact_count(T, chatter, min_gap=0.0) == 4
    assert metrics.impact_count(T, chatter, min_gap=0.07) == 1


def test_round_off_contacts_below_the_peak_fraction_are_not_impacts():
    f = half_sines(T, STARTS[:2] + (25.0,), WIDTH, PEAKS[:2] + (PEAKS[0] * 1e-6,))
    assert metrics.impact_count(T, f) == 2
    assert metrics.impact_count(T, f, min_peak_fraction=0.0) == 3
    assert metrics.impact_count(T, f, min_peak_fraction=0.6) == 1


def test_no_contact():
    zero = np.zeros_like(T)
    assert metrics.impact_count(T, zero) == 0
    assert metrics.contact_intervals(T, zero).shape == (0, 2)
    assert metrics.impact_peaks(T, zero).shape == (0,)
    assert metrics.peak_lock_force(zero) == 0.0
    assert metrics.first_contact_time(T, zero) is None
    angle = np.full_like(T, 181.0)  # the force decides when given: no contact, no lock
    assert metrics.first_lock_time(T, lock_force=zero, deployment_angle=angle) is None


def test_first_lock_time_from_the_lock_force_is_the_first_positive_sample():
    f = half_sines(T, STARTS, WIDTH, PEAKS)
    # sin vanishes at the pulse start 2.463 s; the first sample after it is 2.47 s.
    assert metrics.first_lock_time(T, lock_force=f) == pytest.approx(2.47, abs=1e-12)
    angle = np.full_like(T, 180.0)  # the force takes precedence over the angle
    both = metrics.first_lock_time(T, lock_force=f, deployment_angle=angle)
    assert both == pytest.approx(2.47, abs=1e-12)


def test_first_lock_time_from_the_angle_interpolates_the_crossing():
    # Rigid quarter period: 180 - 90 cos(pi t / (2 T_lock)) reaches 180 deg at T_lock, at the
    # sine's inflection, where the secant's error is O(omega^2 dt^3) ~ 1e-7 s: tolerance 1e-6 s.
    t_lock = 2.4567
    angle = 180.0 - 90.0 * np.cos(np.pi * T / (2 * t_lock))
    assert metrics.first_lock_time(T, deployment_angle=angle) == pytest.approx(t_lock, abs=1e-6)
    assert metrics.crossing_time(T, angle, 135.0) == pytest.approx(2 * t_lock / 3, abs=1e-4)
    assert metrics.first_lock_time(T, deployment_angle=np.full_like(T, 180.0)) == 0.0
    assert metrics.first_lock_time(T, deployment_angle=np.full_like(T, 179.9)) is None
    with pytest.raises(ValueError, match="lock_force or deployment_angle"):
        metrics.first_lock_time(T)


# ---------------------------------------------------------------- settling


def test_settling_of_an_exponential_approach_matches_the_closed_form():
    # |x - x(t_end)| = A (e^(-t/tau) - e^(-t_end/tau)) = tol at
    # t_s = -tau ln(tol/A + e^(-t_end/tau)). The secant's error on the convex exponential is below
    # dt^2 / (8 tau) ~ 6e-6 s: tolerance 1e-5 s.
    A, tau, tol = 90.0, 2.0, 0.1
    x = 180.0 - A * np.exp(-T / tau)
    expected = -tau * math.log(tol / A + math.exp(-T[-1] / tau))
    assert metrics.settling_time(T, x, tol) == pytest.approx(expected, abs=1e-5)
    assert metrics.lock_settling_time(T, x) == pytest.approx(expected, abs=1e-5)


def test_settling_of_a_decaying_oscillation_lies_within_its_envelope_bounds():
    # x = 180 - A e^(-t/tau) cos(omega t): after the envelope falls below the band, at
    # t_env = tau ln(A / tol), x stays inside; within the half period before t_env there is a crest
    # of |cos| at which the envelope still exceeds tol, so t_env - pi/omega < t_s <= t_env
    # (the band is about x[-1], delta = |x[-1] - 180| ~ 2e-7 deg away; both bounds allow for it).
    A, tau, omega, tol = 90.0, 3.0, 2 * np.pi * 2.0, 0.1
    t = grid(60.0, 1e-3)
    x = 180.0 - A * np.exp(-t / tau) * np.cos(omega * t)
    delta = abs(x[-1] - 180.0)
    ts = metrics.settling_time(t, x, tol)
    lower = tau * math.log(A / (tol + delta)) - np.pi / omega
    assert lower < ts <= tau * math.log(A / (tol - delta))


def test_a_record_that_ends_before_the_band_is_held_has_no_settling_time():
    x = 180.0 + np.sin(2 * np.pi * T)  # undamped: the last exit is within a period of the end
    assert metrics.settling_time(T, x, 0.1) is None
    assert metrics.lock_settling_time(T, x) is None
    assert T[-1] - 1.0 < metrics.settling_time(T, x, 0.1, min_hold=0.0) < T[-1]
    assert metrics.settling_time(T, np.full_like(T, 180.0), 0.1) == 0.0


def test_a_late_impact_above_one_percent_of_the_peak_delays_settling():
    # Angle settled at t_a (closed form above); a pulse of peak p at 20 s leaves the band of 1 % of
    # the peak P when p sin(pi (t - a) / w) = 0.01 P on its falling side:
    # t = a + w - (w / pi) asin(0.01 P / p). Secant error < 1e-5 s at dt = 1e-3 s.
    t = grid(30.0, 1e-3)
    A, tau = 90.0, 2.0
    angle = 180.0 - A * np.exp(-t / tau)
    t_angle = -tau * math.log(0.1 / A + math.exp(-t[-1] / tau))
    P, p, a, w = 4000.0, 200.0, 20.0, 0.2
    f = half_sines(t, (2.5, a), w, (P, p))
    expected = a + w - (w / np.pi) * math.asin(0.01 * P / p)
    assert metrics.lock_settling_time(t, angle, f) == pytest.approx(expected, abs=1e-5)
    small = half_sines(t, (2.5, a), w, (P, 0.5 * 0.01 * P))  # inside the band: no delay
    assert metrics.lock_settling_time(t, angle, small) == pytest.approx(t_angle, abs=1e-5)


def test_a_pin_resting_anywhere_in_its_play_is_settled():
    # A latched pin drifting unloaded from the stop (180 deg) to the latch (180 deg - play) is at
    # rest in its groove: Result.summary's angle band is the lock's play (metadata lock_play_deg)
    # when wider than 0.1 deg. Closed forms: the drift 180 - (play / 2)(1 - cos(pi t / T)) enters
    # the 0.1 deg band of its end value at t = (T / pi) acos(0.2 / play - 1); the impact at 5 s
    # falls below 1 % of its peak at a + w - (w / pi) asin(0.01), as above.
    T = 30.0
    t = grid(T, 1e-3)
    play = np.degrees(0.2e-3 / 0.03)  # the paper scene's 0.2 mm at a 30 mm pin radius
    angle = 180.0 - 0.5 * play * (1.0 - np.cos(np.pi * t / T))
    a, w = 5.0, 0.5
    f = half_sines(t, (a,), w, (3e4,))
    expected = a + w - (w / np.pi) * math.asin(0.01)
    series = {"t": t, "deployment_angle": angle, "lock_force": f}
    drift = T / np.pi * math.acos(0.2 / play - 1.0)
    assert Result(series).summary()["settling_time_s"] == pytest.approx(drift, abs=1e-4)
    settled = Result(series, metadata={"hinges": [{"lock_play_deg": play}]}).summary()["settling_time_s"]
    assert settled == pytest.approx(expected, abs=1e-5)
    # several hinges ((n, H) series): one play per hinge (metadata hinges[k]), None for no play
    chain = {"t": t, "deployment_angle": np.c_[angle, angle], "lock_force": np.c_[f, f]}
    two = Result(chain, metadata={"hinges": [{"lock_play_deg": play}, {"lock_play_deg": None}]})
    assert two.summary()["settling_time_s"] == [pytest.approx(expected, abs=1e-5), pytest.approx(drift, abs=1e-4)]
    assert two.summary(hinge=1)["settling_time_s"] == pytest.approx(drift, abs=1e-4)
    assert two.hinge(0).summary()["settling_time_s"] == pytest.approx(expected, abs=1e-5)


# ---------------------------------------------------------------- deflection, attitude, momentum


def test_max_abs_attitude_change_and_momentum_drift():
    deflection = 0.02 * np.sin(T) - 0.01  # extreme -0.03 m at t = 3 pi / 2, sampled within 1e-6
    assert metrics.max_abs(deflection, "node_E_deflection") == pytest.approx(0.03, abs=1e-6)
    att = np.zeros((T.size, 3))
    att[:, 0] = 1.0 + 3.0 * T / T[-1] + np.sin(T)  # the path does not matter, only the ends
    att[:, 1] = 2.0 + 4.0 * T / T[-1]
    att[:, 2] = 3.0
    expected = np.hypot(3.0 + np.sin(30.0), 4.0)
    assert metrics.attitude_change(att) == pytest.approx(expected, rel=1e-12)
    assert metrics.attitude_change(att[:, 1]) == pytest.approx(4.0, rel=1e-12)
    # Body exchanges 2 N m s about y; the total drifts by 3e-9 N m s: drift 1.5e-9, whatever the
    # (conserved) initial momenta.
    body = np.zeros((T.size, 3))
    body[:, 1] = 2.0 * np.sin(np.pi * T / 5.0)
    total = np.zeros((T.size, 3))
    total[:, 2] = 3e-9 * T / T[-1]
    assert metrics.momentum_drift(total, body) == pytest.approx(1.5e-9, rel=1e-9)
    offset = metrics.momentum_drift(total + [5.0, 0, 1.0], body + [0, 7.0, 0])
    assert offset == pytest.approx(1.5e-9, rel=1e-6)
    assert metrics.momentum_drift(total, np.ones_like(body)) is None


@pytest.mark.parametrize("call, name", [
    (lambda: metrics.impact_count(T, np.zeros(T.size - 1)), "lock_force"),
    (lambda: metrics.first_contact_time(np.r_[T[:-1], np.nan], np.zeros_like(T)), "t"),
    (lambda: metrics.peak_lock_force(np.r_[1.0, np.inf]), "lock_force"),
    (lambda: metrics.settling_time(T[::-1], T, 0.1), "t must be strictly increasing"),
    (lambda: metrics.settling_time(T, T, 0.0), "tol"),
    (lambda: metrics.settling_time(T, T, 0.1, min_hold=-1.0), "min_hold"),
    (lambda: metrics.lock_settling_time(T, T, angle_tol=-0.1), "angle_tol"),
    (lambda: metrics.lock_settling_time(T, T, force_tol_fraction=2.0), "force_tol_fraction"),
    (lambda: metrics.contact_intervals(T, T, min_gap=-1.0), "min_gap"),
    (lambda: metrics.impact_peaks(T, T, min_peak_fraction=np.nan), "min_peak_fraction"),
    (lambda: metrics.first_lock_time(T, deployment_angle=T[:5]), "deployment_angle"),
    (lambda: metrics.max_abs(np.zeros((3, 2)), "node_E_deflection"), "node_E_deflection"),
    (lambda: metrics.attitude_change(np.full((4, 3), np.nan)), "body_attitude"),
    (lambda: metrics.momentum_drift(np.zeros((4, 2)), np.zeros((4, 3))), "total_angular_momentum"),
    (lambda: metrics.momentum_drift(np.zeros((4, 3)), np.zeros((5, 3))), "body_angular_momentum"),
])
def test_metric_validation_names_the_parameter(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_metric_options_must_be_real_numbers():
    with pytest.raises(TypeError, match="tol must be a real number"):
        metrics.settling_time(T, T, "0.1")
    with pytest.raises(TypeError, match="min_gap must be a real number"):
        metrics.impact_count(T, T, min_gap=True)


# ---------------------------------------------------------------- the Result container


def paper_like_result(model="nonlinear", dt=DT):
    """A synthetic record with the paper scene's series and closed-form metrics."""
    t = grid(30.0, dt)
    n = t.size
    body = np.zeros((n, 3))
    body[:, 1] = 2.0 * np.sin(np.pi * t / 5.0)
    total = np.zeros((n, 3))
    total[:, 1] = 1e-12 * np.cos(t)
    attitude = np.zeros((n, 3))
    attitude[:, 1] = -0.04 * (1.0 - np.exp(-t))
    series = {"t": t, "deployment_angle": 180.0 - 90.0 * np.exp(-t / 2.0),
              "spring_torque": 7.2 * np.exp(-t / 2.0),
              "lock_force": half_sines(t, STARTS, WIDTH, PEAKS),
              "node_E_deflection": 0.05 * np.exp(-t / 4.0) * np.sin(2 * np.pi * 0.8 * t),
              "body_attitude": attitude, "body_angular_momentum": body,
              "total_angular_momentum": total}
    units = {"deployment_angle": "deg", "spring_torque": "N m", "lock_force": "N",
             "node_E_deflection": "m", "body_attitude": "deg",
             "body_angular_momentum": "N m s", "total_angular_momentum": "N m s"}
    meta = {"model": model, "dt": dt, "integrator": {"name": "newmark", "beta": 0.25},
            "scene": {"layup": 2, "tau0_Nm": 7.2}, "steps": n - 1, "wall_time_s": 1.25}
    return Result(series, units, meta)


def test_series_are_attributes_read_only_copies():
    source = {"t": np.array([0.0, 0.5, 1.0]), "tip_deflection": np.array([0.0, 1e-3, -2e-3])}
    r = Result(source, {"tip_deflection": "m"}, {"model": "linear"})
    assert r.series == ("t", "tip_deflection")
    assert r.units == {"t": "s", "tip_deflection": "m"}
    np.testing.assert_array_equal(r.tip_deflection, [0.0, 1e-3, -2e-3])
    assert r["tip_deflection"] is r.tip_deflection and "tip_deflection" in r
    with pytest.raises(ValueError, match="read-only"):
        r.tip_deflection[0] = 1.0
    source["tip_deflection"][1] = 99.0  # the caller's array is not the result's
    assert r.tip_deflection[1] == 1e-3
    with pytest.raises(AttributeError, match="no series 'lock_force'.*tip_deflection"):
        _ = r.lock_force
    r.metadata["model"] = "changed"  # metadata is handed out as a copy
    assert r.metadata["model"] == "linear"
    assert "tip_deflection" in dir(r)


def test_repr_names_size_span_series_model_and_failure():
    r = paper_like_result()
    text = repr(r)
    assert text.startswith("Result(3001 samples, t = 0 .. 30 s;")
    assert "body_attitude[3] (deg)" in text and "model='nonlinear'" in text
    assert r.failure is None
    stopped = Result({"t": [0.0, 0.01]}, metadata={"failure": "Newton failed at t = 0.02 s"})
    assert "stopped early: Newton failed at t = 0.02 s" in repr(stopped)
    assert stopped.failure == "Newton failed at t = 0.02 s"


TWO = [0.0, 1.0]


@pytest.mark.parametrize("series, units, metadata, error, match", [
    ({"x": [1.0]}, None, None, ValueError, "must contain 't'"),
    ({"t": TWO, "lock_force": [0.0]}, None, None, ValueError,
     "'lock_force' must have leading dimension"),
    ({"t": TWO, "lock_force": [0.0, np.nan]}, None, None, ValueError,
     "'lock_force' must be finite"),
    ({"t": TWO, "summary": TWO}, None, None, ValueError, "'summary' is reserved"),
    ({"t": TWO, "_x": TWO}, None, None, ValueError, "'_x' is reserved"),
    ({"t": TWO, "tip deflection": TWO}, None, None, ValueError, "identifiers"),
    ({"t": TWO, "label": ["a", "b"]}, None, None, ValueError, "'label' must hold real numbers"),
    ({"t": [1.0, 0.0]}, None, None, ValueError, "t must be strictly increasing"),
    ({"t": TWO}, {"lock_force": "N"}, None, ValueError, "units names 'lock_force'"),
    ({"t": TWO}, {"t": 1}, None, TypeError, r"units\['t'\] must be a string"),
    ({"t": TWO}, None, {"dt": float("nan")}, ValueError, r"metadata\['dt'\] must be finite"),
    ({"t": TWO}, None, {"scene": {1: 2}}, TypeError, r"metadata\['scene'\] keys"),
    ({"t": TWO}, None, {"scene": object()}, TypeError, r"metadata\['scene'\] must be JSON"),
    ([0.0, 1.0], None, None, TypeError, "series must be a mapping"),
])
def test_result_validation_names_the_offender(series, units, metadata, error, match):
    with pytest.raises(error, match=match):
        Result(series, units, metadata)


def test_save_load_round_trip_is_bitwise_lossless(tmp_path):
    rng = np.random.default_rng(7)
    n = 50
    t = np.cumsum(rng.uniform(1e-3, 2e-2, n))
    raw = rng.integers(0, 2**63, size=(n, 3), dtype=np.int64).view(np.float64)  # arbitrary bits
    raw[~np.isfinite(raw)] = -0.0
    raw[0, 0] = 5e-324  # a subnormal
    series = {"t": t, "bits": raw, "count": np.arange(n, dtype=np.int32),
              "in_contact": rng.random(n) > 0.5,
              "field": rng.normal(size=(n, 4, 2)).astype(np.float32)}
    meta = {"model": "nonlinear", "dt": 0.1 + 0.2, "steps": np.int64(49),
            "wall_time_s": np.float64(1 / 3),
            "scene": {"layup": 2, "K_c": 3.1622776601683795e10, "pin": (0.03, 0.0), "latch": True,
                      "note": None}, "failure": "Newton failed at t = 0.49 s"}
    r = Result(series, {"bits": "N m s", "field": "m"}, meta)
    path = r.save(tmp_path / "run.result")
    assert path == tmp_path / "run.result" and path.stat().st_size > 0  # exactly the given path
    back = results.load(path)
    assert back.series == r.series and back.units == r.units and back.metadata == r.metadata
    for name in r.series:
        a, b = r[name], back[name]
        assert a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
        assert not b.flags.writeable
    assert back.metadata["scene"]["pin"] == [0.03, 0.0] and type(back.metadata["steps"]) is int


def test_load_refuses_foreign_and_pickled_archives(tmp_path):
    np.savez(tmp_path / "plain.npz", t=np.arange(3.0))
    with pytest.raises(ValueError, match="not a deployfx result file"):
        results.load(tmp_path / "plain.npz")
    np.savez(tmp_path / "pickled.npz", deployfx_header=np.array([{"format": "x"}], dtype=object))
    with pytest.raises(ValueError, match="allow_pickle"):
        results.load(tmp_path / "pickled.npz")


def test_to_dataframe_columns_index_and_units():
    import pandas as pd

    t = grid(1.0, 0.25)
    r = Result({"t": t, "lock_force": 2 * t, "body_attitude": np.c_[t, 2 * t, 3 * t],
                "pair": np.c_[t, -t], "field": np.arange(t.size * 4.0).reshape(-1, 2, 2)},
               {"lock_force": "N", "body_attitude": "deg"})
    df = r.to_dataframe()
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == ["lock_force", "body_attitude_x", "body_attitude_y",
                                "body_attitude_z", "pair[0]", "pair[1]", "field[0,0]",
                                "field[0,1]", "field[1,0]", "field[1,1]"]
    assert df.index.name == "t"
    np.testing.assert_array_equal(df.index.to_numpy(), t)
    np.testing.assert_array_equal(df["body_attitude_z"].to_numpy(), 3 * t)
    np.testing.assert_array_equal(df["field[1,0]"].to_numpy(), r.field[:, 1, 0])
    assert df.attrs["units"] == {"lock_force": "N", "body_attitude_x": "deg",
                                 "body_attitude_y": "deg", "body_attitude_z": "deg"}
    df.iloc[0, 0] = -1.0  # the frame is the caller's to modify; the result is not touched
    assert r.lock_force[0] == 0.0


def test_to_dataframe_names_per_hinge_columns_by_hinge():
    # Three hinges: (n, 3) per-hinge series are one column per hinge, not x, y, z components;
    # a hinge view's (n, 3) hinge force is a vector.
    t = grid(1.0, 0.5)
    force = np.arange(t.size * 9.0).reshape(-1, 3, 3)
    r = Result({"t": t, "deployment_angle": np.c_[t, 2 * t, 3 * t], "hinge_force": force,
                "body_attitude": np.c_[t, t, t]})
    df = r.to_dataframe()
    assert list(df.columns)[:4] == ["deployment_angle[0]", "deployment_angle[1]", "deployment_angle[2]",
                                    "hinge_force[0]_x"]
    assert list(df.columns)[-3:] == ["body_attitude_x", "body_attitude_y", "body_attitude_z"]
    np.testing.assert_array_equal(df["hinge_force[2]_y"].to_numpy(), force[:, 2, 1])
    one = r.hinge(2).to_dataframe()
    assert list(one.columns)[:4] == ["deployment_angle", "hinge_force_x", "hinge_force_y", "hinge_force_z"]
    np.testing.assert_array_equal(one["deployment_angle"].to_numpy(), 3 * t)


def test_to_dataframe_without_pandas_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas"):
        Result({"t": [0.0]}).to_dataframe()


def test_summary_is_computed_from_the_series():
    r = paper_like_result()
    s = r.summary()
    # the keys in SUMMARY_KEYS' order, those of series the record lacks (tip deflection, hinge
    # force and moment) left out
    # the impact records' impulse (a result built from series alone has no records) and the ply
    # failure envelope (a run with stresses=True)
    absent = ("max_tip_deflection_m", "max_tip_deflection_time_s", "tip_deflection_after_spin_up_m",
              "peak_hinge_force_N", "peak_hinge_moment_Nm", "peak_impact_impulse_N_s", "min_failure_margin",
              "critical_ply", "critical_element", "critical_time_s")
    assert tuple(s) == tuple(k for k in results.SUMMARY_KEYS if k not in absent)
    assert s["first_lock_time_s"] == pytest.approx(2.47, abs=1e-12)
    assert s["impacts"] == 4 and isinstance(s["impacts"], int)
    sampling = 1 - np.cos(np.pi * DT / (2 * WIDTH))  # crest sampled within dt / 2
    assert s["peak_lock_force_N"] == pytest.approx(PEAKS[0], rel=sampling)
    # The last pulse (500 N, 12.5 % of the peak) leaves the 40 N band at
    # 17.157 + 0.2 (1 - asin(0.08) / pi), between the last sample in the pulse and the first after
    # its end: the secant cannot see that kink, so the bound is one sample interval.
    expected = STARTS[3] + WIDTH * (1 - math.asin(0.08) / np.pi)
    assert s["settling_time_s"] == pytest.approx(expected, abs=DT)
    assert s["max_node_E_deflection_m"] == metrics.max_abs(r.node_E_deflection)
    assert s["body_attitude_change_deg"] == pytest.approx(0.04 * (1 - math.exp(-30.0)), rel=1e-12)
    assert s["momentum_drift"] == pytest.approx(1e-12 * (1 - math.cos(30.0)) / 2.0, rel=1e-3)
    # steps and wall time are passed through from the metadata this test wrote (no timing here)
    assert (s["steps"], s["wall_time_s"]) == (3000, 1.25)


def test_summary_of_other_scenes_leaves_out_what_they_do_not_measure():
    t = grid(2.0, 0.01)
    # A tip deflection of no stated panel (metadata hinges[k].fidelity) measures nothing.
    assert Result({"t": t, "tip_deflection": 1e-3 * np.sin(t)}).summary() == {}
    tip = Result({"t": t, "tip_deflection": 1e-3 * np.sin(np.pi * t) - 0.5e-3},
                 metadata={"hinges": [{"fidelity": "linear"}]})
    assert tip.summary() == {"max_tip_deflection_m": pytest.approx(1.5e-3, abs=1e-12),  # at t = 1.5 s, sampled
                             "max_tip_deflection_time_s": pytest.approx(1.5, abs=1e-12)}
    # A prescribed spin-up (metadata hinges[k].spin_up) adds the largest |tip| from its end t_s on:
    # from t_s = 1.6 s, past the -1.5e-3 trough at 1.5 s: |1e-3 sin(1.6 pi) - 0.5e-3| (within one
    # sample's change, 2e-5).
    spun = Result({"t": t, "tip_deflection": 1e-3 * np.sin(np.pi * t) - 0.5e-3},
                  metadata={"hinges": [{"fidelity": "linear", "spin_up": {"omega_s_rad_per_s": 1.0, "t_s_s": 1.6}}]})
    expected = 0.5e-3 - 1e-3 * np.sin(1.6 * np.pi)
    assert spun.summary()["tip_deflection_after_spin_up_m"] == pytest.approx(expected, abs=2e-5)
    late = Result({"t": t, "tip_deflection": t},
                  metadata={"hinges": [{"fidelity": "linear", "spin_up": {"t_s_s": 5.0}}]})
    assert late.summary()["tip_deflection_after_spin_up_m"] is None  # the run ends before t_s
    # Without a lock force no lock metric (the angle crossing 180 deg is metrics.first_lock_time's).
    angle = 180.0 - 90.0 * np.cos(np.pi * t / (2 * 1.2345))
    s = Result({"t": t, "deployment_angle": angle}, metadata={"steps": 200}).summary()
    assert s == {"steps": 200}
    # A hinge without a lock (metadata hinges[k].lock False) has None where its neighbour has a value.
    f = half_sines(t, (0.5,), 0.2, (100.0,))
    two = Result({"t": t, "deployment_angle": np.c_[angle, angle], "lock_force": np.c_[f, np.zeros_like(f)]},
                 metadata={"hinges": [{"lock": True}, {"lock": False}]})
    assert two.summary()["impacts"] == [1, None]
    # A fixed base (metadata base_free False) has no attitude or momentum to report.
    att = np.zeros((t.size, 3))
    fixed = Result({"t": t, "body_attitude": att, "body_angular_momentum": att, "total_angular_momentum": att},
                   metadata={"base_free": False})
    assert fixed.summary() == {}


# ---------------------------------------------------------------- figures


def short_pair():
    return [paper_like_result("linear", dt=0.1), paper_like_result("nonlinear", dt=0.1)]


def legend_texts(ax):
    return [text.get_text() for text in ax.get_legend().get_texts()]


def test_scalar_figures_overlay_runs_with_labels_and_units():
    pair = short_pair()
    for draw, ylabel in [(plot.deployment_angle, "deployment angle (deg)"),
                         (plot.spring_torque, "spring torque (N m)"),
                         (plot.lock_force, "lock force (N)"),
                         (plot.node_deflection, "deflection of node E (m)")]:
        fig = draw(pair)
        (ax,) = fig.axes
        assert len(ax.lines) == 2 and legend_texts(ax) == ["linear", "nonlinear"]
        assert ax.get_ylabel() == ylabel and ax.get_xlabel() == "time (s)"
    fig = plot.deployment_angle(pair[0], labels=["present model"])
    assert legend_texts(fig.axes[0]) == ["present model"]
    single = Result({"t": [0.0, 1.0], "deployment_angle": [90.0, 180.0]})
    fig = plot.deployment_angle(single)
    assert len(fig.axes[0].lines) == 1 and fig.axes[0].get_legend() is None


def test_vector_figures_draw_three_components_per_run():
    # The paper-like records turn about y only: the components identically zero in every run
    # (x, z) are left out, one line per run remains.
    pair = short_pair()
    (ax,) = plot.body_attitude(pair).axes
    assert len(ax.lines) == 2 and legend_texts(ax) == ["linear, y", "nonlinear, y"]
    assert ax.get_ylabel() == "body attitude (deg)"
    top, bottom = plot.angular_momentum(pair).axes
    assert len(top.lines) == len(bottom.lines) == 2
    assert top.get_ylabel() == "body angular momentum (N m s)"
    # the conserved total: its drift relative to the body's peak (no momentum_scale here), 2 N m s
    assert bottom.get_ylabel() == "total angular momentum drift\n|H - H(0)| / H_ref"
    H = pair[1].total_angular_momentum[:, 1]
    np.testing.assert_allclose(bottom.lines[1].get_ydata(), np.abs(H - H[0]) / 2.0, rtol=1e-12, atol=1e-30)
    # Three components that move: three lines per run.
    t = grid(1.0, 0.1)
    tumbling = [Result({"t": t, "body_attitude": np.c_[t, -t, 2 * t]}, metadata={"model": m})
                for m in ("linear", "nonlinear")]
    (ax,) = plot.body_attitude(tumbling).axes
    assert len(ax.lines) == 6 and legend_texts(ax)[:3] == ["linear, x", "linear, y", "linear, z"]
    np.testing.assert_array_equal(ax.lines[5].get_ydata(), 2 * t)


def test_coinciding_overlays_stay_visible():
    # Two identical runs: the first a wide solid line underneath, the second narrower, dashed,
    # with markers and drawn over it, so both show where the curves coincide.
    same = [paper_like_result("linear", dt=0.1), paper_like_result("nonlinear", dt=0.1)]
    for fig in (plot.deployment_angle(same), plot.body_attitude(same)):
        first, second = fig.axes[0].lines
        np.testing.assert_array_equal(first.get_ydata(), second.get_ydata())
        assert first.get_linewidth() > second.get_linewidth() and first.get_zorder() < second.get_zorder()
        assert first.get_marker() in ("None", None, "") and second.get_marker() not in ("None", None, "")
    first, second = plot.deployment_angle(same).axes[0].lines
    assert (first.get_linestyle(), second.get_linestyle()) == ("-", "--")


def test_legends_leave_out_round_off_components():
    # Attitude about y with x and z at round-off (1e-17 deg): only y is drawn and listed.
    t = grid(1.0, 0.1)
    att = np.c_[1e-17 * np.sin(t), t, -1e-17 * t]
    (ax,) = plot.body_attitude(Result({"t": t, "body_attitude": att}, metadata={"model": "m"})).axes
    assert legend_texts(ax) == ["m, y"] and len(ax.lines) == 1
    # Above 1e-9 of the largest component a component is shown.
    att[:, 0] = 1e-6 * t
    (ax,) = plot.body_attitude(Result({"t": t, "body_attitude": att}, metadata={"model": "m"})).axes
    assert legend_texts(ax) == ["m, x", "m, y"]


def test_momentum_drift_is_relative_to_the_runs_momentum_scale():
    t = grid(1.0, 0.1)
    H = np.zeros((t.size, 3))
    H[:, 2] = 5.0 + 3e-6 * t  # a drift of 1e-6 of H_ref a second
    r = Result({"t": t, "body_angular_momentum": np.c_[0 * t, 2.0 * t, 0 * t], "total_angular_momentum": H},
               metadata={"momentum_scale": {"P_N_s": 1.0, "H_N_m_s": 3.0}})
    top, bottom = plot.angular_momentum(r).axes
    np.testing.assert_allclose(bottom.lines[0].get_ydata(), 1e-6 * t, rtol=1e-8, atol=1e-25)  # round-off of 5 + ...
    assert bottom.get_legend() is None and [line.get_label() for line in top.lines] == ["y"]


def test_figures_carry_the_run_settings_as_a_caption():
    from deployfx import scenes

    r = scenes.paper2016(2, "rigid", nx=2, ny=1).simulate(0.05, 0.01)
    text = plot.caption(r)
    for part in ("scene paper2016", "mesh 2 quads", "dt 0.01 s", "GeneralizedAlpha(rho_inf=0.8)", "fixed steps",
                 f"deployfx {r.settings()['deployfx_version']}",
                 f"run {r.settings()['run_started_utc'][:16].replace('T', ' ')} UTC"):
        assert part in text
    assert max(len(line) for line in text.splitlines()) <= 90  # fits the figure's width
    for fig in (plot.deployment_angle(r), plot.angular_momentum(r), plot.body_attitude(r)):
        assert fig.get_supxlabel() == text
    # runs that differ list each value; results made by hand have no caption
    r2 = scenes.paper2016(2, "rigid", nx=2, ny=1).simulate(0.05, 0.005)
    assert "dt 0.01 s / dt 0.005 s" in plot.caption([r, r2]).replace("\n", " ")
    assert plot.caption(Result({"t": [0.0, 1.0]})) == ""
    assert plot.deployment_angle(Result({"t": [0.0, 1.0], "deployment_angle": [90.0, 180.0]})).get_supxlabel() == ""


def test_figures_draw_into_given_axes_and_use_the_results_units():
    from matplotlib.figure import Figure

    fig = Figure()
    ax1, ax2 = fig.subplots(1, 2)
    t = grid(1.0, 0.1)
    kn = Result({"t": t, "lock_force": t}, {"lock_force": "kN"})
    assert plot.lock_force(kn, ax=ax2) is fig
    assert len(ax2.lines) == 1 and not ax1.lines and ax2.get_ylabel() == "lock force (kN)"
    with pytest.raises(ValueError, match="different units"):
        plot.lock_force([kn, Result({"t": t, "lock_force": t}, {"lock_force": "N"})])


@pytest.mark.parametrize("call, match", [
    (lambda r: plot.spring_torque([r[0], Result({"t": [0.0, 1.0]}, metadata={"model": "rigid"})]),
     r"result 1 \(rigid\) has no series 'spring_torque'"),
    (lambda r: plot.body_attitude(Result({"t": [0.0, 1.0], "body_attitude": [1.0, 2.0]})),
     r"'body_attitude' must have shape \(n, 3\)"),
    (lambda r: plot.deployment_angle(r, labels=["one"]), "one label per result"),
    (lambda r: plot.deployment_angle([]), "at least one Result"),
])
def test_figure_errors_are_clear(call, match):
    with pytest.raises(ValueError, match=match):
        call(short_pair())


def test_paper_figures_writes_six_pngs(tmp_path):
    paths = plot.paper_figures(short_pair(), tmp_path / "figs", dpi=40)
    assert [p.name for p in paths] == ["deployment_angle.png", "spring_torque.png",
                                       "lock_force.png", "node_E_deflection.png",
                                       "body_angular_momentum.png", "body_attitude.png"]
    for p in paths:
        assert p.parent == tmp_path / "figs" and p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert p.stat().st_size > 1000
    unnamed = Result({name: paper_like_result(dt=0.5)[name] for name in paper_like_result().series})
    single = plot.paper_figures(unnamed, tmp_path / "one", dpi=40)  # no model: no legend
    assert len(single) == 6 and all(p.stat().st_size > 1000 for p in single)
    bare = Result({"t": [0.0, 1.0], "deployment_angle": [90.0, 180.0]})
    with pytest.raises(ValueError, match="no series 'spring_torque'"):
        plot.paper_figures(bare, tmp_path / "none")
    assert not (tmp_path / "none").exists()  # checked before anything is written


def plate_mesh(nx, ny, length, width):
    x, y = np.meshgrid(np.linspace(0, length, nx + 1), np.linspace(0, width, ny + 1))
    node = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1)
    corners = [node[:-1, :-1], node[:-1, 1:], node[1:, 1:], node[1:, :-1]]  # counterclockwise
    quads = np.stack(corners, axis=-1).reshape(-1, 4)
    return np.c_[x.ravel(), y.ravel()], quads


def test_deformed_shape_contours_the_field_on_the_split_quads():
    xy, quads = plate_mesh(15, 10, 2.0, 1.3)
    w = 0.01 * (xy[:, 0] / 2.0) ** 2 * np.cos(np.pi * xy[:, 1] / 1.3)
    fig = plot.deformed_shape(xy, quads, w, title="t = 2.46 s")
    ax, cbar = fig.axes
    (filled,) = ax.collections
    assert cbar.get_ylabel() == "w (m)" and ax.get_title() == "t = 2.46 s"
    assert filled.levels[0] == pytest.approx(-0.01, rel=1e-5)  # symmetric about zero
    assert filled.levels[-1] == pytest.approx(0.01, rel=1e-5)
    assert ax.get_xlabel() == "x (m)" and ax.get_ylabel() == "y (m)"
    # A uniform field (a rigid translation) and a zero field fill the whole 2.0 m x 1.3 m plate:
    # both triangles of every quad are drawn (shoelace area of the filled polygons).
    for uniform in (np.full(len(xy), 0.003), np.zeros(len(xy))):
        (filled,) = plot.deformed_shape(xy, quads, uniform).axes[0].collections
        polygons = [p for path in filled.get_paths() for p in path.to_polygons()]
        area = sum(0.5 * (p[:-1, 0] @ p[1:, 1] - p[1:, 0] @ p[:-1, 1]) for p in polygons)
        assert area == pytest.approx(2.6, rel=1e-9)


@pytest.mark.parametrize("args, match", [
    (lambda xy, q, w: (xy[:, :1], q, w), "nodes_xy"),
    (lambda xy, q, w: (xy, q + 1, w), "quads must index the 176 nodes"),
    (lambda xy, q, w: (xy, q.astype(float), w), "quads must be an integer array"),
    (lambda xy, q, w: (xy, q, w[:-1]), r"w must be a real array of shape \(176,\)"),
    (lambda xy, q, w: (xy, q, np.r_[w[:-1], np.nan]), "w must be finite"),
])
def test_deformed_shape_validates_its_input(args, match):
    xy, quads = plate_mesh(15, 10, 2.0, 1.3)
    with pytest.raises(ValueError, match=match):
        plot.deformed_shape(*args(xy, quads, np.zeros(len(xy))))


def test_base_attitude_is_scipys_rotation_vector():
    # deployfx._run.base_attitude_deg (vectorised) against scipy's Rotation.as_rotvec, an
    # independent implementation of the same map, to round-off (1e-12 deg): small angles (its
    # Taylor branch below 1e-3 rad), large ones up to pi, quaternions with w < 0 (the same
    # rotation) and not quite unit ones (renormalised).
    from scipy.spatial.transform import Rotation

    from deployfx._run import base_attitude_deg

    rng = np.random.default_rng(7)
    for spread in (1e-6, 1e-3, 0.1, 3.0):
        quat = rng.normal(size=(500, 4)) * np.array([1.0, spread, spread, spread])
        quat *= (1 + 1e-10 * rng.normal(size=(500, 1))) / np.linalg.norm(quat, axis=1)[:, None]
        q = np.c_[np.zeros((500, 3)), quat]
        ref = Rotation.from_quat(quat[:, [1, 2, 3, 0]]).as_rotvec(degrees=True)
        assert np.abs(base_attitude_deg(q, True) - ref).max() <= 1e-12
    assert np.array_equal(base_attitude_deg(np.zeros((3, 0)), False), np.zeros((3, 3)))
