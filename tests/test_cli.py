"""The README's main job through the CLI: it prints the computed mass and frequencies and writes
its files; bad input ends with a clear message and exit status 2."""
import csv

import numpy as np

import deployfx as dfx
from deployfx.cli import main


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
