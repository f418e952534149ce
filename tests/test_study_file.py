"""Study files and the ``deployfx study`` command (issue 26): a study file loads to the study it
describes and saves back to the same dict (nothing lost); a bad file raises ValueError naming the
key; ``deployfx study run`` then ``report`` on a small Saltelli study of the paper's scene."""
import copy
import json

import numpy as np
import pytest

pytest.importorskip("distributed")
pytest.importorskip("xarray")
pytest.importorskip("zarr")
pytest.importorskip("SALib")

import deployfx as dfx  # noqa: E402
from deployfx import study  # noqa: E402
from deployfx._study_file import study_from_dict  # noqa: E402
from deployfx.cli import main  # noqa: E402

STUDY = {
    "schema": "deployfx.study", "version": 1,
    "base": {"scene": "paper2016"},
    "fixed": {"layup": 2, "model": "rigid", "nx": 4, "ny": 2, "damping": [0.7, 0.0]},
    "vary": {"tau0": {"distribution": "uniform", "low": 6.84, "high": 7.56},
             "friction.mu": {"distribution": "uniform", "low": 0.15, "high": 0.35},
             "clearance": {"distribution": "normal", "mean": 2e-4, "std": 3e-5, "low": 1e-4,
                           "high": 3e-4}},
    "sampling": {"sampler": "saltelli", "samples": 2, "seed": 0},
    "run": {"t_end_s": 3.0, "dt_s": 0.01, "scheme": {"type": "generalized-alpha", "rho_inf": 0.8}},
    "outputs": {"metrics": ["first_lock_time_s", "peak_lock_force_N"],
                "series": ["deployment_angle"], "time_step_s": 0.1},
}


def test_a_study_file_round_trips(tmp_path):
    st = study_from_dict(STUDY)
    assert st.size == 2 * (3 + 2) and st.parameters == ["tau0", "friction.mu", "clearance"]
    assert st.fixed["damping"] == (0.7, 0.0)           # a factory's sequences are tuples
    assert st.time[1] == 0.1 and st.time[-1] == 3.0
    assert st.to_dict() == STUDY
    for suffix in ("toml", "json"):
        path = st.save(tmp_path / f"s.{suffix}")
        assert study.load_study(path).to_dict() == STUDY
    # the design is the parameters' distributions: the truncated normal stays in its band
    c = st.design["clearance"]
    assert (c >= 1e-4).all() and (c <= 3e-4).all()


def _bad(change):
    d = copy.deepcopy(STUDY)
    change(d)
    return d


BAD = [
    (lambda d: d.pop("run"), r"study file is missing key\(s\) run"),
    (lambda d: d.update(extra=1), r"study file has unknown key\(s\) extra"),
    (lambda d: d.update(schema="deployfx.scene"), r"schema = 'deployfx.scene' is not a deployfx study"),
    (lambda d: d.update(version=2), r"version = 2 is an unknown study-file version"),
    (lambda d: d["base"].update(file="x.toml"), r"base must give exactly one of scene, factory, "
                                                r"file, inline; got \['scene', 'file'\]"),
    (lambda d: d["base"].update(scene="paper2017"), r"base.scene = 'paper2017' is invalid"),
    (lambda d: d["vary"]["tau0"].pop("high"), r"vary.tau0 is missing key\(s\) vary.tau0.high"),
    (lambda d: d["vary"]["tau0"].update(low=8.0), r"vary.tau0: Uniform\(low=8.0, high=7.56\) is "
                                                  r"invalid: must have low < high"),
    (lambda d: d["vary"]["tau0"].update(distribution="beta"), r"vary.tau0.distribution = 'beta' "
                                                              r"is invalid"),
    (lambda d: d["vary"].update(tau1=d["vary"].pop("tau0")), r"vary key = 'tau1': paper2016\(\) has "
                                                             r"no parameter 'tau1'"),
    (lambda d: d["vary"].update({"friction.nu": d["vary"].pop("friction.mu")}),
     r"parameter 'friction.nu': Friction has no field 'nu'; fields: mu, v_reg"),
    (lambda d: d["sampling"].update(samples=3), r"samples = 3 is invalid for sampler 'saltelli': "
                                                r"must be a power of 2"),
    (lambda d: d["sampling"].update(sampler="grid"), r"sampler 'grid' needs levels"),
    (lambda d: d["run"].update(dt_s="0.01"), r"run.dt_s = '0.01' is invalid: must be a number"),
    (lambda d: d["run"].update(scheme={"type": "rk4"}), r"run.scheme.type must be"),
    (lambda d: d["outputs"].update(metrics=["peak_force"]), r"output 'peak_force' is invalid"),
    (lambda d: d["outputs"].update(metrics=["median(lock_force)"]), r"unknown reduction 'median'"),
    (lambda d: d["fixed"].update(friction={"mu": 0.3}), r"fixed.friction is a table"),
]


@pytest.mark.parametrize("change, message", BAD)
def test_a_bad_study_file_names_the_key(change, message):
    with pytest.raises(ValueError, match=message):
        study_from_dict(_bad(change))


def test_a_scene_file_base_checks_its_paths(tmp_path):
    dfx.save_scene(dfx.scenes.paper2016(2, "rigid", nx=4, ny=2), tmp_path / "paper.toml")
    d = _bad(lambda d: d.update(base={"file": "paper.toml"}, fixed={}))
    d["vary"] = {"hinges.0.tau0": {"distribution": "uniform", "low": 6.8, "high": 7.6}}
    (tmp_path / "s.json").write_text(json.dumps(d))
    with pytest.raises(ValueError, match=r"vary key = 'hinges.0.tau0': hinges.0 has no key 'tau0'; "
                                         r"keys: parent, point_m, axis, R_PC0, tau0_N_m"):
        study.load_study(tmp_path / "s.json")
    d["vary"] = {"hinges.0.groove": {"distribution": "uniform", "low": 6.8, "high": 7.6}}
    (tmp_path / "s.json").write_text(json.dumps(d))
    with pytest.raises(ValueError, match=r"'hinges.0.groove' is a table; address one number inside"):
        study.load_study(tmp_path / "s.json")


def test_cli_run_and_report(tmp_path, capsys):
    path = study_from_dict(STUDY).save(tmp_path / "study.toml")
    store = tmp_path / "study.zarr"
    assert main(["study", "run", str(path), "--out", str(store), "--workers", "2", "--threads",
                 "--no-progress", "--limit", "4"]) == 0
    assert "4 samples computed, 0 failed, 6 pending" in capsys.readouterr().out
    assert main(["study", "run", str(path), "--out", str(store), "--threads", "--no-progress"]) == 0
    assert "10 samples computed, 0 failed, 0 pending" in capsys.readouterr().out
    assert main(["study", "report", str(store), "--out", str(tmp_path / "report")]) == 0
    out = capsys.readouterr().out
    ds = study.open(store)
    lock = ds["first_lock_time_s"].values
    assert f"{lock.mean():.6g}" in out and f"{lock.max():.6g}" in out   # the statistics table
    assert "Sobol' indices" in out and "friction.mu" in out
    for name in ("scatter_matrix.png", "histograms.png", "sobol_indices.png"):
        assert (tmp_path / "report" / name).stat().st_size > 1000
    # the store's study is the file's
    assert study.load_study(store).to_dict(strict=False) == study.load_study(path).to_dict(strict=False)
    # a bad file: exit status 2, the key named on stderr
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(_bad(lambda d: d["vary"]["tau0"].pop("low"))))
    assert main(["study", "run", str(bad), "--out", str(tmp_path / "b.zarr")]) == 2
    assert "vary.tau0 is missing key(s) vary.tau0.low" in capsys.readouterr().err
    assert not (tmp_path / "b.zarr").exists()


def test_the_paper_study_is_deterministic_in_the_store(tmp_path):
    """The design written in the store is the study's, value for value."""
    st = study_from_dict(STUDY)
    ds = st.run(tmp_path / "d.zarr", workers=1, processes=False, limit=0)
    for k in st.parameters:
        assert np.array_equal(ds[k].values, st.design[k])
    assert (ds["status"].values == 0).all()
