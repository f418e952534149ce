"""Studies on Dask (issue 26): a study's samples are the scene run alone, bit for bit; a resumed
store equals one run through and recomputes nothing; the pipeline (Saltelli sampling, Dask, zarr,
SALib) recovers the Ishigami function's Sobol' indices (Ishigami & Homma 1990); two worker
processes; failing samples recorded.

Clusters: the tests run in-process threads (``processes=False``), which start at once, except
the two-process test; the engine integrates with the GIL released, so both modes run samples in
parallel.
"""
import math

import numpy as np
import pytest

pytest.importorskip("distributed")
pytest.importorskip("xarray")
pytest.importorskip("zarr")
pytest.importorskip("SALib")

import zarr  # noqa: E402

import deployfx as dfx  # noqa: E402
from deployfx import study  # noqa: E402
from deployfx.scene_file import scene_from_dict, scene_to_dict  # noqa: E402
from deployfx.integrators import GeneralizedAlpha  # noqa: E402

import study_scenes  # noqa: E402  (tests/, importable by the workers)

RIGID = {"layup": 2, "model": "rigid", "nx": 4, "ny": 2}
T_END, DT = 3.0, 0.01     # s: past the first lock (about 2.45 s)
SUMMARY = ["first_lock_time_s", "impacts", "peak_lock_force_N", "body_attitude_change_deg"]


def _paper_study(**kw):
    args = dict(fixed=RIGID, vary={"tau0": study.Uniform(6.84, 7.56),
                                   "k_theta": study.Uniform(4.35, 4.81),
                                   "clearance": study.Uniform(1e-4, 3e-4),
                                   "friction.mu": study.Uniform(0.15, 0.35)},
                samples=3, sampler="lhs", outputs=SUMMARY + ["max(deployment_angle)"],
                series=["lock_force"], t_end=T_END, dt=DT, seed=1)
    args.update(kw)
    return study.Study(dfx.scenes.paper2016, **args)


def _alone(values):
    """The paper's scene with the sample's values, built and run without deployfx.study."""
    scene = dfx.scenes.paper2016(2, "rigid", nx=4, ny=2, tau0=values["tau0"],
                                 k_theta=values["k_theta"], clearance=values["clearance"],
                                 friction=dfx.contact.Friction(values["friction.mu"]))
    return scene.simulate(T_END, DT)


def _check_against_alone(ds, st):
    """Reference: each sample run alone; tolerance: none (bit for bit; the series on the grid
    are the alone run's interpolated the same way, np.interp)."""
    assert (ds["status"].values == 1).all()
    for i in range(st.size):
        values = {k: ds[k].values[i].item() for k in st.parameters}
        assert values == st.values(i)
        r = _alone(values)
        s = r.summary()
        for key in SUMMARY:
            assert ds[key].values[i] == s[key], (i, key)
        assert ds["max(deployment_angle)"].values[i] == r.deployment_angle.max()
        assert np.array_equal(ds["lock_force"].values[i], np.interp(st.time, r.t, r.lock_force[:, 0]))


def test_a_sample_equals_the_scene_run_alone(tmp_path):
    st = _paper_study()
    ds = st.run(tmp_path / "s.zarr", workers=2, processes=False).load()
    _check_against_alone(ds, st)


def test_two_worker_processes(tmp_path):
    """A LocalCluster of two worker processes: both build samples (their process ids in the
    log), and the results are those of the scene run alone, bit for bit."""
    log = tmp_path / "pids.txt"
    # a factory without defaults: the object whose field varies is fixed (sent to the workers)
    st = study.Study(study_scenes.logged_paper2016,
                     fixed={**RIGID, "log": str(log), "friction": dfx.contact.Friction(0.25)},
                     vary={"tau0": study.Uniform(6.84, 7.56), "k_theta": study.Uniform(4.35, 4.81),
                           "clearance": study.Uniform(1e-4, 3e-4),
                           "friction.mu": study.Uniform(0.15, 0.35)},
                     samples=6, sampler="lhs", outputs=SUMMARY + ["max(deployment_angle)"],
                     series=["lock_force"], t_end=T_END, dt=DT, seed=1)
    ds = st.run(tmp_path / "s.zarr", workers=2).load()
    _check_against_alone(ds, st)
    pids = log.read_text().split()
    assert len(pids) == 6 and len(set(pids)) == 2


def test_a_scene_file_sample_equals_the_scene_run_alone(tmp_path):
    """Base: a scene file, parameters by dotted path. Reference: the paper's scene built with
    the same values by keyword and run alone; bit for bit."""
    path = dfx.save_scene(dfx.scenes.paper2016(**RIGID), tmp_path / "paper.toml")
    st = study.Study(path, vary={"hinges.0.tau0_N_m": [6.9, 7.5],
                                 "hinges.0.groove.friction.mu": [0.2]},
                     sampler="grid", outputs=["first_lock_time_s", "max(lock_force)"],
                     t_end=T_END, dt=DT, scheme=GeneralizedAlpha(0.8))
    ds = st.run(tmp_path / "s.zarr", workers=1, processes=False).load()
    for i, tau0 in enumerate([6.9, 7.5]):
        alone = dfx.scenes.paper2016(**RIGID, tau0=tau0, friction=dfx.contact.Friction(0.2))
        r = alone.model.simulate(T_END, DT, scheme=GeneralizedAlpha(0.8))
        assert ds["hinges.0.tau0_N_m"].values[i] == tau0
        assert ds["first_lock_time_s"].values[i] == r.summary(hinge=0)["first_lock_time_s"]
        assert ds["max(lock_force)"].values[i] == r.lock_force.max()


def _ishigami_study(log="", samples=8, sampler="lhs", **fixed):
    u = study.Uniform(-math.pi, math.pi)
    return study.Study(study_scenes.ishigami, fixed={"log": log, **fixed},
                       vary={"x1": u, "x2": u, "x3": u}, samples=samples, sampler=sampler,
                       outputs={"y_final": "final(y)"}, series=["y"], t_end=1.0, dt=1.0, seed=3)


def _stores_equal(a, b):
    ga, gb = zarr.open_group(str(a), mode="r"), zarr.open_group(str(b), mode="r")
    assert dict(ga.attrs) == dict(gb.attrs)
    assert sorted(ga.array_keys()) == sorted(gb.array_keys())
    for k in ga.array_keys():
        x, y = ga[k], gb[k]
        assert x.dtype == y.dtype and x.shape == y.shape and x.chunks == y.chunks, k
        assert dict(x.attrs) == dict(y.attrs), k
        xv, yv = x[...], y[...]
        if xv.dtype.kind == "f":
            assert np.array_equal(xv, yv, equal_nan=True), k
        else:
            assert (xv == yv).all(), k


def test_resume_equals_one_run_and_recomputes_nothing(tmp_path):
    """A study stopped after 5 of 12 samples (``limit``) and run again: the store equals one run
    through (every array, bit for bit, and the attributes), and each sample was computed once
    (the factory's log has one line per run)."""
    log = tmp_path / "runs.txt"
    st = _ishigami_study(str(log), samples=12)
    part = st.run(tmp_path / "resumed.zarr", workers=2, processes=False, limit=5)
    assert (part["status"].values == 1).sum() == 5 and (part["status"].values == 0).sum() == 7
    assert np.isnan(part["y_final"].values[part["status"].values == 0]).all()
    st.run(tmp_path / "resumed.zarr", workers=2, processes=False)
    assert len(log.read_text().splitlines()) == 12
    st.run(tmp_path / "resumed.zarr", workers=2, processes=False)  # nothing left: nothing runs
    runs = log.read_text().splitlines()
    assert len(runs) == 12
    assert sorted(float(line.split()[1]) for line in runs) == sorted(st.design["x1"].tolist())
    whole = _ishigami_study(str(tmp_path / "whole.txt"), samples=12)
    whole.fixed["log"] = str(log)  # the same study (the log path is one of its parameters)
    whole.run(tmp_path / "whole.zarr", workers=1, processes=False)
    _stores_equal(tmp_path / "resumed.zarr", tmp_path / "whole.zarr")
    y = [study_scenes.ishigami_value(*(st.values(i)[k] for k in ("x1", "x2", "x3")))
         for i in range(12)]
    whole_ds = study.open(tmp_path / "whole.zarr")
    assert np.array_equal(whole_ds["y_final"].values, y)
    assert np.array_equal(whole_ds["y"].values, np.column_stack([y, y]))


def test_a_store_of_another_study_is_refused(tmp_path):
    _ishigami_study(samples=4).run(tmp_path / "s.zarr", workers=1, processes=False)
    with pytest.raises(ValueError, match=r"holds a different study \(sampling.samples: the store "
                                         r"has 4, this study 8\)"):
        _ishigami_study(samples=8).run(tmp_path / "s.zarr", workers=1, processes=False)


def test_ishigami_sobol_indices(tmp_path):
    """Ishigami & Homma (1990), a = 7, b = 0.1: S1 = (0.3139, 0.4424, 0), ST = (0.5576, 0.4424,
    0.2437) in closed form (tests/study_scenes.py). Through the whole pipeline (SALib's Saltelli
    design, N = 512, 2560 runs on Dask, the zarr store, SALib's analysis):
    - the indices equal SALib's on the same design evaluated directly (bit for bit);
    - each is within 0.12 of the closed form: the estimator's sampling error at N = 512 (the
      largest over 20 seeds of the design was 0.109, for S1 of x3 and ST of x1), and within
      twice its 95 % bootstrap half-width (the largest ratio over those seeds: 1.36)."""
    from SALib.analyze import sobol as salib_sobol

    st = _ishigami_study(samples=512, sampler="saltelli")
    assert st.size == 512 * 5
    ds = st.run(tmp_path / "ishigami.zarr", workers=2, processes=False).load()
    idx = study.sobol(ds)
    x = np.column_stack([st.design[k] for k in ("x1", "x2", "x3")])
    y = np.array([study_scenes.ishigami_value(*row) for row in x])
    assert np.array_equal(ds["y_final"].values, y)
    direct = salib_sobol.analyze({"num_vars": 3, "names": ["x1", "x2", "x3"],
                                  "bounds": [[0.0, 1.0]] * 3}, y, calc_second_order=False, seed=1)
    for k in ("S1", "S1_conf", "ST", "ST_conf"):
        assert np.array_equal(idx[k].sel(output="y_final").values, direct[k])
    for k, exact in (("S1", study_scenes.ISHIGAMI_S1), ("ST", study_scenes.ISHIGAMI_ST)):
        got = idx[k].sel(output="y_final").values
        err = np.abs(got - np.array(exact))
        assert (err < 0.12).all(), (k, got, exact)
        assert (err < 2 * idx[f"{k}_conf"].sel(output="y_final").values).all(), (k, got, exact)


def test_failing_samples_are_recorded_and_the_study_goes_on(tmp_path):
    """Samples with x1 > 1 raise in their run: recorded (status 2, the error), NaN outputs; every
    other sample computed; Sobol' indices then refuse, naming the failed samples."""
    st = _ishigami_study(samples=8, sampler="saltelli", fail_above=1.0)
    ds = st.run(tmp_path / "f.zarr", workers=2, processes=False).load()
    failed = st.design["x1"] > 1.0
    assert failed.any() and not failed.all()
    assert np.array_equal(ds["status"].values, np.where(failed, 2, 1))
    for i in np.flatnonzero(failed):
        assert ds["error"].values[i] == (f"ValueError: x1 = {st.values(i)['x1']} is out of range: "
                                         "must be <= 1.0")
        assert np.isnan(ds["y_final"].values[i]) and np.isnan(ds["y"].values[i]).all()
    assert (ds["error"].values[~failed] == "").all()
    assert np.isfinite(ds["y_final"].values[~failed]).all()
    with pytest.raises(ValueError, match=r"Sobol' indices need every sample: \d+ of 40"):
        study.sobol(ds)
    stats = study.statistics(ds)
    assert stats.loc["y_final", "failed"] == failed.sum()
    assert stats.loc["y_final", "computed"] == (~failed).sum()
    # a bad value of the scene itself: recorded with the scene's own message
    bad = study.Study(dfx.scenes.paper2016, fixed=RIGID, vary={"clearance": [2e-4, -1e-4]},
                      sampler="grid", outputs=["first_lock_time_s"], t_end=T_END, dt=DT)
    ds = bad.run(tmp_path / "bad.zarr", workers=1, processes=False).load()
    assert ds["status"].values.tolist() == [1, 2]
    assert "clearance" in ds["error"].values[1] and ds["error"].values[1].startswith("ValueError")


def test_a_misnamed_series_stops_the_study(tmp_path):
    st = _ishigami_study(samples=4)
    st.series = ["z"]
    with pytest.raises(ValueError, match="the result has no series 'z'; it has t, y"):
        st.run(tmp_path / "m.zarr", workers=1, processes=False)
