"""The notebooks in notebooks/ run from top to bottom without error (issue 5: executed in the test
suite so they never rot), as scikit-fem's tests/test_examples.py runs its examples.

Each notebook is executed with nbclient on a fresh ``python3`` kernel in a temporary directory,
with a short simulated time (``DEPLOYFX_NOTEBOOK_T_END``, still past the first lock of both
scenes). The checks are that every cell ran, that the figures and the printed results the
notebook is about exist, and that nothing was written to stderr (so no warnings either). The
notebooks are kept in the repository without outputs.
"""
import os
from pathlib import Path

# Some jupyter_core 5 releases (5.3, say) warn at import (DeprecationWarning: "Jupyter is
# migrating its paths to use standard platformdirs") unless this is set; it selects the paths
# jupyter_core 6 will use. It must be set before nbclient is imported.
os.environ.setdefault("JUPYTER_PLATFORM_DIRS", "1")

import nbclient
import nbformat
import pytest

import deployfx

NOTEBOOKS = Path(__file__).resolve().parent.parent / "notebooks"
T_END_S = "3.0"  # s: past the first lock (about 2.5 s and 2.1 s), short enough for the suite
STUDY_SAMPLES = "4"  # notebook 3: Saltelli's base sample count N (7 N = 28 deployments)

# notebook: (minimum number of figures, texts that must be printed, output types that must exist)
EXPECTED = {
    "01_paper2016_deployment.ipynb": (
        4, ["first_lock_time_s", "peak_lock_force_N", "linear: first lock at",
            "nonlinear: first lock at", "15 x 10", "nonlinear, mesh 15 x 10: first lock at"], []),
    "02_build_your_own_scene.ipynb": (
        4, ["ValueError: hinge.axis", "rigid: first lock", "nonlinear: first lock",
            "identical: True", "array: panel 2 (hinge 2) first locks at",
            "nonlinear panels in a chain:", "reduced-linear panels in a chain:",
            "two wings: wing -x (hinges 3-5) first locks at", "two wings: spacecraft attitude change"],
        ["text/html"]),
    "03_monte_carlo_study.ipynb": (
        4, ["28 deployments computed, 0 failed", "lock load over 28 deployments: mean",
            "Sobol' indices (S1, ST", "damping.alpha_M"], ["text/html"]),
}


def test_every_notebook_is_tested():
    assert sorted(p.name for p in NOTEBOOKS.glob("*.ipynb")) == sorted(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_notebook_is_stored_without_outputs(name):
    nb = nbformat.read(NOTEBOOKS / name, as_version=4)
    nbformat.validate(nb)
    for k, cell in enumerate(nb.cells):
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, f"cell {k} has outputs"


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_notebook_runs(name, tmp_path, monkeypatch):
    if name.startswith("03"):  # the study extra (Python >= 3.11)
        for module in ("distributed", "xarray", "zarr", "SALib"):
            pytest.importorskip(module)
    monkeypatch.setenv("DEPLOYFX_NOTEBOOK_T_END", T_END_S)
    monkeypatch.setenv("DEPLOYFX_STUDY_SAMPLES", STUDY_SAMPLES)
    # The kernel imports the deployfx this test imported (installed or from a source tree).
    package_root = str(Path(deployfx.__file__).resolve().parent.parent)
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, [package_root,
                                                                   os.environ.get("PYTHONPATH")])))
    nb = nbformat.read(NOTEBOOKS / name, as_version=4)
    client = nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute()  # raises CellExecutionError, with the cell and its traceback, on any error

    outputs = [o for cell in nb.cells if cell.cell_type == "code" for o in cell.outputs]
    code_cells = [cell for cell in nb.cells if cell.cell_type == "code"]
    assert all(cell.execution_count is not None for cell in code_cells)
    stderr = "".join(o.text for o in outputs if o.output_type == "stream" and o.name == "stderr")
    assert stderr == ""
    stdout = "".join(o.text for o in outputs if o.output_type == "stream" and o.name == "stdout")
    data = [o.data for o in outputs if o.output_type in ("execute_result", "display_data")]
    n_figures, texts, mime_types = EXPECTED[name]
    assert sum("image/png" in d for d in data) >= n_figures
    for text in texts:
        assert text in stdout
    for mime in mime_types:
        assert any(mime in d for d in data)
