"""The speed-accuracy table (deployfx.tradeoff, issue 6): its mechanics on tiny runs of the paper's
scene (2 x 1 mesh, 2.6 s, just past the first lock at ~2.47 s), not the trade's numbers (those
are measured by bench/tradeoff.py). A run identical to the reference has zero errors exactly (the
engine is deterministic); a coarser step has positive ones."""
import csv
import math

import numpy as np
import pytest

import deployfx as dfx
from deployfx.integrators import HHT
from deployfx.tradeoff import COLUMNS, ERRORS, Case, history_error
from deployfx.tradeoff_report import plot_work_precision, to_dataframe, to_markdown, write_csv

T_END = 2.6
REF = Case("nonlinear", nx=2, ny=1, dt=0.005)
COARSE = Case("nonlinear", nx=2, ny=1, dt=0.01)
RIGID = {"model": "rigid", "nx": 2, "ny": 1, "dt": 0.01}  # a mapping works as well as a Case


@pytest.fixture(scope="module")
def run():
    """(rows, the reference's Result, results of the cases by label)."""
    seen = {}
    rows = dfx.tradeoff([REF, COARSE, RIGID], REF, T_END,
                        callback=lambda row, r: seen.update({row["label"]: r}))
    return rows, seen["reference: " + REF.name], seen


def test_rows_have_every_column_and_describe_the_case(run):
    rows, _, _ = run
    assert len(rows) == 4  # the reference first, then the three cases in order
    for row in rows:
        assert list(row) == list(COLUMNS)
    ref, same, coarse, rigid = rows
    assert ref["is_reference"] and not any(r["is_reference"] for r in rows[1:])
    assert [r["model"] for r in rows] == ["nonlinear", "nonlinear", "nonlinear", "rigid"]
    assert coarse["mesh"] == "2x1" and coarse["dt_s"] == 0.01 and coarse["integrator"] == "GA(0.8)"
    assert coarse["coordinates"] == 6 * 3 * 2 - 6 * 2 and rigid["coordinates"] == 0  # free dofs
    assert coarse["basis_size"] is None and coarse["modes"] is None
    for r in rows:
        assert r["wall_time_s"] > 0 and r["steps"] > 0 and r["newton_iterations"] > 0
        assert r["failure"] is None and r["t_reached_s"] == pytest.approx(T_END)
        assert r["ms_per_step"] == pytest.approx(1e3 * r["wall_time_s"] / r["substeps"])
    assert coarse["steps"] < same["steps"]  # half the steps
    # The reference's values are those of its own summary (the paper: first lock at ~2.46 s).
    summary = run[1].summary(hinge=0)
    for r in rows:
        assert r["ref_lock_time_s"] == summary["first_lock_time_s"]
        assert r["ref_peak_lock_force_N"] == summary["peak_lock_force_N"]
        assert r["ref_max_node_E_deflection_m"] == summary["max_node_E_deflection_m"]
    assert abs(summary["first_lock_time_s"] - 2.46) < 0.03


def test_a_run_identical_to_the_reference_has_zero_errors(run):
    rows, _, _ = run
    for r in rows[:2]:
        for err in ERRORS:
            assert r[err] == 0.0, (r["label"], err)
        assert r["lock_time_s"] == r["ref_lock_time_s"]
        assert r["peak_lock_force_N"] == r["ref_peak_lock_force_N"]


def test_a_coarser_step_and_a_rigid_appendage_have_positive_errors(run):
    rows, ref_result, results = run
    _, _, coarse, rigid = rows
    for r in (coarse, rigid):
        for err in ERRORS:
            assert math.isfinite(r[err]) and r[err] > 0, (r["label"], err)
    # The errors are what their definitions say, recomputed here from the two results.
    c, ref = results[COARSE.name].summary(hinge=0), ref_result.summary(hinge=0)
    assert coarse["lock_time_error_s"] == pytest.approx(
        abs(c["first_lock_time_s"] - ref["first_lock_time_s"]), rel=1e-12)
    assert coarse["peak_lock_force_rel_error"] == pytest.approx(
        abs(c["peak_lock_force_N"] / ref["peak_lock_force_N"] - 1), rel=1e-9)
    # A rigid appendage does not deflect: its history error is the reference's RMS over its max,
    # far larger than the coarse flexible run's.
    t = results["rigid dt=0.01 GA(0.8)"].t
    e2 = np.interp(t, ref_result.t, ref_result.node_E_deflection) ** 2
    rms = math.sqrt(np.sum(0.5 * (e2[1:] + e2[:-1]) * np.diff(t)) / (t[-1] - t[0]))
    scale = np.abs(ref_result.node_E_deflection).max()
    assert rigid["node_E_rms_rel_error"] == pytest.approx(rms / scale, rel=1e-9)
    assert rigid["node_E_rms_rel_error"] > 3 * coarse["node_E_rms_rel_error"]


def test_a_given_reference_result_gives_the_same_errors(run):
    rows, ref_result, _ = run
    again = dfx.tradeoff([COARSE], ref_result, T_END)
    assert again[0]["is_reference"] and again[0]["label"] == "reference (given result)"
    for err in ERRORS:
        assert again[1][err] == rows[2][err]


def test_history_error_closed_forms():
    t_ref = np.linspace(0.0, 2.0, 2001)
    x_ref = np.sin(np.pi * t_ref)  # max |x_ref| = 1
    t = np.linspace(0.0, 2.0, 11)
    # A constant offset c: RMS c, whatever the sampling.
    assert history_error(t, np.sin(np.pi * t) + 0.1, t_ref, x_ref) == pytest.approx(0.1, rel=1e-12)
    # Uneven samples weigh by the time they stand for: an offset only on [1, 2], sampled densely
    # there, still has RMS 0.1 sqrt(1/2) (to the trapezoid's error on the one straddling interval).
    t2 = np.r_[np.linspace(0.0, 1.0, 3), np.linspace(1.001, 2.0, 200)]
    x2 = np.sin(np.pi * t2) + np.where(t2 > 1.0, 0.1, 0.0)
    assert history_error(t2, x2, t_ref, x_ref) == pytest.approx(0.1 * math.sqrt(0.5), rel=0.01)
    assert history_error(t, np.sin(np.pi * t), t, np.sin(np.pi * t)) == 0.0
    with pytest.raises(ValueError, match="outside"):
        history_error(np.linspace(0, 3, 4), np.zeros(4), t_ref, x_ref)


def test_table_exports(run, tmp_path):
    rows, _, _ = run
    df = to_dataframe(rows)
    assert list(df.columns) == list(COLUMNS) and len(df) == 4
    path = write_csv(rows, tmp_path / "t.csv")
    with open(path, newline="") as fh:
        table = list(csv.reader(fh))
    assert table[0] == list(COLUMNS) and len(table) == 5
    assert float(table[3][COLUMNS.index("dt_s")]) == 0.01
    md = to_markdown(rows).splitlines()
    assert len(md) == 2 + 4 and md[0].startswith("| label |")


def test_work_precision_plot(run):
    rows, _, _ = run
    fig = plot_work_precision(rows)
    axes = fig.axes
    assert len(axes) == len(ERRORS)
    for ax, (err, label) in zip(axes, ERRORS.items()):
        assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
        assert ax.get_xlabel() == "wall time (s)" and ax.get_ylabel() == label
        # One point per row with a positive error: the coarse (nonlinear) and the rigid rows;
        # the reference and its zero-error rerun have none.
        points = {line.get_label(): (line.get_xdata(), line.get_ydata()) for line in ax.lines
                  if line.get_linestyle() == "None"}
        assert set(points) == {"nonlinear", "rigid"}
        np.testing.assert_array_equal(points["nonlinear"][0], [rows[2]["wall_time_s"]])
        np.testing.assert_array_equal(points["nonlinear"][1], [rows[2][err]])
    with pytest.raises(ValueError, match="errors"):
        plot_work_precision(rows, errors=["wall_time_s"])


def test_cases_are_checked():
    with pytest.raises(ValueError, match="modes"):
        Case("nonlinear", modes=10)
    with pytest.raises(ValueError, match="model"):
        Case("elastic")
    with pytest.raises(ValueError, match="dt"):
        Case(dt=0.0)
    with pytest.raises(TypeError, match="unknown fields"):
        dfx.tradeoff([{"model": "rigid", "mesh": "2x1"}], REF, T_END)
    assert Case("reduced-nonlinear", 4, 3, 0.01, HHT(-0.05), modes=5).name == \
        "reduced-nonlinear(5) 4x3 dt=0.01 HHT(-0.05)"
    assert Case("rigid", dt=0.02).name == "rigid dt=0.02 GA(0.8)"
    with pytest.raises(ValueError, match="derivative_modes"):
        Case("reduced-linear", modes=5, derivative_modes=2)
    with pytest.raises(ValueError, match="derivative_modes"):
        Case("reduced-nonlinear", modes=5, derivative_modes=-1)
    assert Case("reduced-nonlinear", 4, 3, modes=10, derivative_modes=3).name == \
        "reduced-nonlinear(10, md=3) 4x3 dt=0.01 GA(0.8)"
    with pytest.raises(ValueError, match="derivative_partners"):
        Case("nonlinear", derivative_partners=1)
    with pytest.raises(ValueError, match="derivative_partners = -1 is out of range"):
        Case("reduced-nonlinear", derivative_partners=-1)
    assert Case("reduced-nonlinear", 4, 3, modes=10, derivative_modes=3, derivative_partners=0).name == \
        "reduced-nonlinear(10, md=3, dp=0) 4x3 dt=0.01 GA(0.8)"


def test_derivative_modes_set_the_reduced_basis(run):
    # The modal derivatives of every pair among the first k modes: k (k + 1) / 2 proposed
    # (fem/ritz_basis.hpp), and the first mode's partners (the default derivative_partners = 1):
    # its pairs with the modes beyond k and with the static corrections' bending directions
    # beyond the modes (one on this strip); the default k is min(modes, 3). Too many for the
    # basis: a failure row.
    _, ref, _ = run
    cases = [Case("reduced-nonlinear", 2, 1, 0.01, modes=3, derivative_modes=k) for k in (1, 3, 4)]
    rows = dfx.tradeoff(cases + [Case("reduced-nonlinear", 2, 1, 0.01, modes=3)], ref, T_END)
    one, three, four, default = rows[1:]
    assert (one["modal_derivatives"], three["modal_derivatives"]) == (1 + 2 + 1, 6 + 0 + 1)
    assert one["basis_size"] < three["basis_size"] == default["basis_size"]
    assert default["modal_derivatives"] == 7 and one["failure"] is None
    assert four["failure"].startswith("scene:") and "derivative_modes" in four["failure"]
    # Without the partners: the pairs among the first k only (today's md=3 basis of session 17).
    (no_partners,) = dfx.tradeoff([Case("reduced-nonlinear", 2, 1, 0.01, modes=3, derivative_modes=3,
                                        derivative_partners=0)], ref, T_END)[1:]
    assert no_partners["modal_derivatives"] == 6 and no_partners["basis_size"] <= default["basis_size"]
