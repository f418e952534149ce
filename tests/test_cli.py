"""The README's main job through the CLI: it prints the computed mass and frequencies and writes
its files; bad input ends with a clear message and exit status 2."""
import csv
import datetime
import json

import numpy as np
import pytest

import deployfx as dfx
from deployfx import resolution, scenes
from deployfx.cli import main
from deployfx.results import Result


def test_appendage_command_writes_results(tmp_path, capsys):
    assert main(["appendage", "--layup", "2", "--modes", "6", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "mass: 8.3200 kg" in out  # 1600 x 2.0 x 1.3 x 0.002 (You et al. 2016)
    with open(tmp_path / "appendage_frequencies.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    f = np.array([float(r["frequency_Hz"]) for r in rows])
    expected = dfx.paper2016.appendage_plate(2).natural_frequencies(6, "CFFF")
    np.testing.assert_allclose(f, expected, rtol=1e-7)
    assert (tmp_path / "appendage_modes.png").stat().st_size > 10_000


def test_bad_input_is_reported(capsys):
    assert main(["appendage", "--nx", "0"]) == 2
    assert "Plate.nx" in capsys.readouterr().err


# ---------------------------------------------------------------- deployfx run (issue 25)

SMALL = ["--nx", "2", "--ny", "1"]


def test_version_and_run_help_show_the_version_and_defaults(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--version"])
    assert e.value.code == 0 and capsys.readouterr().out.strip() == f"deployfx {dfx.__version__}"
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for default in ("(default: 30.0)", "(default: nonlinear)", "(default: 15)", "default 0.01"):
        assert default in text
    assert "Contacts resolved at the default step" in text  # lock contacts need no step of their own


@pytest.mark.parametrize("args, option", [
    (["--t-end", "0"], "--t-end = 0 is out of range"),
    (["--t-end", "-1"], "--t-end = -1 is out of range"),
    (["--dt", "0"], "--dt = 0 is out of range"),
    (["--dt", "nan"], "--dt = nan is out of range"),
])
def test_a_run_that_cannot_give_results_is_refused_before_it_starts(tmp_path, capsys, args, option):
    out = tmp_path / "out"
    assert main(["run", "paper2016", "--model", "rigid", *SMALL, "--out", str(out), *args]) == 2
    assert option in capsys.readouterr().err
    assert not out.exists()  # refused before anything was run or written


def test_an_output_directory_that_cannot_be_written_is_refused(tmp_path, capsys):
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    assert main(["run", "paper2016", "--model", "rigid", *SMALL, "--out", str(blocker / "out")]) == 2
    assert "--out" in capsys.readouterr().err


def test_unknown_scenes_and_ready_scene_options_on_a_scene_file_are_refused(tmp_path, capsys):
    assert main(["run", "paper2017"]) == 2
    assert "scene = 'paper2017' is invalid" in capsys.readouterr().err
    assert main(["run", str(tmp_path / "missing.toml")]) == 2
    assert "no such scene file" in capsys.readouterr().err
    path = dfx.save_scene(scenes.paper2016(2, "rigid", nx=2, ny=1).scene, tmp_path / "s.toml")
    assert main(["run", str(path), "--layup", "1"]) == 2
    assert "--layup shapes a ready scene" in capsys.readouterr().err


def test_a_scene_file_runs_like_the_scene_it_holds(tmp_path, capsys):
    # A saved scene compiles to a model giving bit-identical results (deployfx.scene_file), so the
    # file's run has the ready scene's lock metrics exactly.
    path = dfx.save_scene(scenes.paper2016(2, "rigid", nx=2, ny=1).scene, tmp_path / "rigid.toml")
    assert main(["run", str(path), "--t-end", "3", "--json", "--out", str(tmp_path / "out")]) == 0
    summary = json.loads(capsys.readouterr().out)
    ref = scenes.paper2016(2, "rigid", nx=2, ny=1).simulate(3.0, 0.01).summary()
    for key in ("first_lock_time_s", "impacts", "peak_lock_force_N"):
        assert summary[key] == ref[key]
    assert summary["settings"]["scene"] == str(path)
    assert summary["settings"]["parameters"]["sha256"] == __import__("hashlib").sha256(path.read_bytes()).hexdigest()
    names = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert names == ["body_angular_momentum.png", "body_attitude.png", "deployment_angle.png", "lock_force.png",
                     "summary.json", "timeseries.csv"]  # a rigid panel: no tip deflection figure


def test_summary_json_carries_the_run_settings(tmp_path, capsys):
    before = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0)
    args = ["run", "paper2016", "--model", "both", *SMALL, "--t-end", "0.1", "--damping", "0.7", "0",
            "--out", str(tmp_path)]
    assert main(args) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert list(summary) == ["linear", "nonlinear"]
    for model, s in summary.items():
        settings = s["settings"]
        assert list(settings) == ["scene", "parameters", "mesh", "fidelity", "dt", "t_end", "scheme", "tolerance",
                                  "newton_tolerance", "deployfx_version", "run_started_utc", "command"]
        assert settings["scene"] == "paper2016" and settings["fidelity"] == [model]
        assert settings["mesh"] == [{"nodes": 6, "quads": 2}]  # 2 x 1 quads, 3 x 2 nodes
        p = settings["parameters"]
        assert (p["layup"], p["nx"], p["ny"], p["model"], p["damping"]) == (2, 2, 1, model, [0.7, 0.0])
        assert p["contact"]["n"] == 1.5 and p["friction"]["mu"] == 0.25
        assert (settings["dt"], settings["t_end"], settings["tolerance"]) == (0.01, 0.1, None)
        assert settings["newton_tolerance"] == 1e-10  # the engine's default
        assert settings["scheme"] == "GeneralizedAlpha(rho_inf=0.8)"
        assert settings["deployfx_version"] == dfx.__version__
        started = datetime.datetime.fromisoformat(settings["run_started_utc"])
        assert before <= started <= datetime.datetime.now(datetime.timezone.utc)
        assert settings["command"] == ["deployfx"] + args
    assert "settings: scene paper2016" in capsys.readouterr().out


def test_saved_results_carry_the_same_settings(tmp_path):
    r = scenes.spin_up_beam(4.0, nx=4).simulate(0.1, 0.01)
    settings = dfx.load(r.save(tmp_path / "r.npz")).settings()
    assert settings == r.settings()
    assert settings["parameters"]["omega_s_rad_per_s"] == 4.0 and settings["mesh"] == [{"nodes": 10, "quads": 4}]
    assert Result({"t": [0.0]}).settings()["dt"] is None  # a result made by hand has none


def test_a_step_that_does_not_resolve_the_scene_warns_with_the_step_that_does(capsys):
    # The 2 x 1 mesh's tenth clamped mode is far above what dt = 0.01 s follows (resolution).
    scene = scenes.paper2016(2, "linear", nx=2, ny=1)
    T = resolution.shortest_period(scene)["period_s"]
    assert T < 4 * 0.01
    assert main(["run", "paper2016", "--model", "linear", *SMALL, "--t-end", "0.02", "--json"]) == 0
    err = capsys.readouterr().err
    assert "deployfx: warning: dt = 0.01 s does not resolve the scene" in err
    assert f"period of {T:.4g} s" in err and f"use dt <= {resolution.suggested_dt(T):g} s" in err
    # A rigid panel's only period is its 9.9 s swing: dt = 0.01 s resolves it, no warning.
    assert main(["run", "paper2016", "--model", "rigid", *SMALL, "--t-end", "0.02", "--json"]) == 0
    assert "warning" not in capsys.readouterr().err


def test_spin_up_beam_summary_reports_its_tip_and_no_lock(capsys):
    # Kane, Ryan & Banerjee (1987), tests/test_spin_up_beam.py: peak -0.4003 m at 6.95 s, |tip| ~
    # 0.004 m after spin-up (omega_s = 4 rad/s, t_s = 15 s); 2 % and 0.1 s, 1 cm. The default step
    # (0.002 s) resolves the beam's kept modes: no warning.
    assert main(["run", "spin-up-beam", "--t-end", "20", "--json"]) == 0
    captured = capsys.readouterr()
    assert "warning" not in captured.err
    s = json.loads(captured.out)
    assert s["max_tip_deflection_m"] == [pytest.approx(0.4003, rel=0.02)]
    assert s["max_tip_deflection_time_s"] == [pytest.approx(6.95, abs=0.1)]
    assert 0 < s["tip_deflection_after_spin_up_m"][0] < 0.01
    assert not any(k.startswith(("first_lock", "impacts", "peak_lock", "settling")) for k in s)
    assert None not in [v for value in s.values() if isinstance(value, list) for v in value]
    assert s["settings"]["dt"] == 0.002


def test_scene_parameters_with_strengths_are_json():
    # Strengths keep a core object; the settings hold their fields (Pa), as a scene file does.
    s = dfx.Strengths(Xt=1.5e9, Xc=1.2e9, Yt=5e7, Yc=2e8, S12=7e7)
    p = scenes.paper2016(2, "rigid", nx=2, ny=1, strengths=s).model.description["parameters"]
    assert p["strengths"] == {"Xt": 1.5e9, "Xc": 1.2e9, "Yt": 5e7, "Yc": 2e8, "S12": 7e7, "S13": None,
                              "S23": None, "F12_star": -0.5}
    json.dumps(p)


def test_the_paper_lock_geometry_is_an_option(capsys):
    # The groove (default) and the stop-and-latch walls: the rigid panel reaches the stop at
    # 2.4538 s riding the groove (its ride friction, docs/research/pin-groove.md) and at 2.4510 s
    # on the walls (the energy quadrature, tests/test_paper2016.py); the settings say which.
    locks = {}
    for geometry in ("groove", "stop-latch"):
        assert main(["run", "paper2016", "--model", "rigid", *SMALL, "--t-end", "2.6", "--json",
                     "--lock-geometry", geometry]) == 0
        summary = json.loads(capsys.readouterr().out)
        assert summary["settings"]["parameters"]["lock_geometry"] == geometry
        locks[geometry] = summary["first_lock_time_s"][0]
    assert locks["groove"] == pytest.approx(2.4538, abs=5e-4)
    assert locks["stop-latch"] == pytest.approx(2.4510, abs=5e-4)

