"""VTK export (deployfx.export.write_vtk_series) read back as ParaView would: the .pvd collection's
times and files, each file through meshio (an independent VTU reader). References: the run's own
time samples (exact), the animation's world points (deployfx.animation.world_points, checked
against closed forms in test_animation.py; exact, the same arithmetic) and the panel's elastic
displacement, whose length a rotation to world axes keeps (1e-12)."""
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from deployfx import scenes
from deployfx.animation import world_points
from deployfx.export import write_vtk_series

meshio = pytest.importorskip("meshio")  # in the test extras


@pytest.fixture(scope="module")
def run():
    paper = scenes.paper2016(2, "linear", nx=4, ny=2)
    return paper, paper.simulate(0.5, 0.01)


def collection(path):
    """(times, files) of a .pvd collection."""
    sets = ET.parse(path).getroot().find("Collection").findall("DataSet")
    return [float(d.get("timestep")) for d in sets], [d.get("file") for d in sets]


@pytest.mark.parametrize("options, samples", [
    ({"times": [0.1, 0.234, 0.5]}, [10, 23, 50]),   # the samples nearest the times asked for
    ({"every": 25}, [0, 25, 50]),                     # a stride
])
def test_the_collection_reads_back_with_the_runs_times(run, tmp_path, options, samples):
    paper, r = run
    paths = write_vtk_series(paper, r, tmp_path, name="wing", **options)
    times, files = collection(tmp_path / "wing.pvd")
    assert times == [float(r.t[k]) for k in samples]
    assert files == [p.name for p in paths]
    u = paper.model.node_displacements(r.q, 0)
    for path, k in zip(paths, samples):
        back = meshio.read(path)
        np.testing.assert_array_equal(back.points, world_points(paper, r)[k])
        np.testing.assert_allclose(np.linalg.norm(back.point_data["displacement"], axis=1),
                                   np.linalg.norm(u[k], axis=1), rtol=1e-12, atol=1e-15)
    csv = np.loadtxt(tmp_path / "wing_times.csv", delimiter=",", skiprows=1, ndmin=2)
    np.testing.assert_array_equal(csv[:, 0], samples)


def test_bad_stride_and_times_are_named(run, tmp_path):
    paper, r = run
    with pytest.raises(ValueError, match="every = 0 is out of range"):
        write_vtk_series(paper, r, tmp_path, every=0)
    with pytest.raises(ValueError, match="times must be finite and within the run's"):
        write_vtk_series(paper, r, tmp_path, times=[0.6])
