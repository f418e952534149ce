"""Animation of a deployment (issue 5): the world-coordinate transform against closed forms, and a
GIF written frame by frame."""
import numpy as np
import pytest
from PIL import Image

import deployfx as dfx
from deployfx import animation, scenes
from deployfx.animation import animate, world_points
from deployfx.scene import Scene

HINGE = (0.5, 0.0, 0.0)
# Ry(-90 deg): the panel (along E's x) stands along +z when stowed.
R_BE0 = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])


def _scene(free: bool) -> Scene:
    strip = scenes.spin_up_strip(nx=2)  # 10 m x 0.2 m, nodes (x, y, 0) in E
    return (Scene().set_base(10.0, 1.0, free=free)
            .set_hinge(point=HINGE, axis=(0.0, 1.0, 0.0), R_BE0=R_BE0, tau0=1.0)
            .set_appendage(strip.model, strip.fixed_dofs("CFFF"), "linear"))


def _elastic(model, node: int, w: float) -> np.ndarray:
    """The free elastic coordinates of a transverse displacement w (m, E's z) of one node."""
    full = np.zeros(model.shell.num_dofs)
    full[6 * node + 2] = w
    return full[model.free_dofs]


def test_world_points_closed_form_free_base():
    scene = _scene(free=True)
    model = scene.compile()
    node, w = 2, 0.1                      # the free end (x = 10, y = 0), lifted along E's z
    d = _elastic(model, node, w)
    c = np.cos(np.pi / 4)
    q = np.array([
        np.r_[0, 0, 0, 1, 0, 0, 0, 0.0, d],            # stowed, base at the origin
        np.r_[0, 0, 0, 1, 0, 0, 0, np.pi / 2, d],      # deployed by 90 deg about the hinge axis
        np.r_[1, 2, 3, c, 0, 0, c, np.pi / 2, d],      # and the base moved, turned 90 deg about z
    ])
    result = dfx.Result({"t": [0.0, 1.0, 2.0], "q": q})
    P = world_points(model, result, hinge=scene)
    x, y = model.shell.nodes[node, :2]
    assert (x, y) == (10.0, 0.0)
    np.testing.assert_allclose(P[0, node], [HINGE[0] - w, y, x], atol=1e-12)  # R_BE0 (x, y, w)
    np.testing.assert_allclose(P[1, node], [HINGE[0] + x, y, w], atol=1e-12)  # R_BE = I at 90 deg
    np.testing.assert_allclose(P[2, node], [1 - y, 2 + HINGE[0] + x, 3 + w], atol=1e-12)
    # Every node of the undeformed panel at 90 deg: the hinge point plus its E coordinates.
    others = np.arange(model.shell.nodes.shape[0]) != node
    np.testing.assert_allclose(P[1, others], HINGE + model.shell.nodes[others], atol=1e-12)
    # Undeformed (scale 0) and the hinge given as a mapping.
    P0 = world_points(model, result, hinge={"point": HINGE, "axis": (0, 1, 0), "R_BE0": R_BE0},
                      scale=0.0)
    np.testing.assert_allclose(P0[1], HINGE + model.shell.nodes, atol=1e-12)


def test_world_points_fixed_base_and_theta_from_q():
    scene = _scene(free=False)
    model = scene.compile()
    q = np.array([np.r_[np.pi / 2, np.zeros(model.free_dofs.size)]])
    result = dfx.Result({"t": [0.0], "q": q})          # no "theta" series: read from q
    np.testing.assert_allclose(world_points(model, result, hinge=scene)[0],
                               HINGE + model.shell.nodes, atol=1e-12)


def test_world_points_of_a_run_keep_the_root_on_the_hinge():
    paper = scenes.paper2016(2, "linear", nx=4, ny=2)
    r = paper.model.simulate(0.3, 0.01)
    P = world_points(paper, r)                           # hinge from paper.scene
    r_W, R_WB = animation.base_poses(paper, r)
    # The clamped root nodes move only with the base and the hinge: their distance to the
    # hinge axis (b_h = 0.03 m) is kept.
    root = np.flatnonzero(np.isclose(paper.model.shell.nodes[:, 0], 0.03))
    hinge_W = r_W + R_WB @ np.array([0.83, 0.0, 0.0])
    axis_W = R_WB @ np.array([0.0, 1.0, 0.0])
    rel = P[:, root] - hinge_W[:, None]
    dist = np.linalg.norm(np.cross(rel, axis_W[:, None]), axis=2)
    np.testing.assert_allclose(dist, 0.03, atol=1e-9)


@pytest.fixture(scope="module")
def run():
    paper = scenes.paper2016(2, "linear", nx=4, ny=2)
    return paper, paper.model.simulate(0.5, 0.01)


def test_gif_has_the_frames_asked_for(run, tmp_path):
    paper, r = run
    path = dfx.plot.animate(paper.model, r, tmp_path / "deploy.gif", fps=10, frames=4,
                            hinge=paper.scene, dpi=40, figsize=(4, 3.5))
    with Image.open(path) as im:
        assert im.format == "GIF"
        assert im.n_frames == 4
        assert im.info["duration"] == pytest.approx(100, abs=10)  # ms per frame at 10 fps


def test_bad_inputs(run, tmp_path):
    paper, r = run
    with pytest.raises(ValueError, match="path"):
        animate(paper, r, tmp_path / "x.avi")
    with pytest.raises(ValueError, match="frames"):
        animate(paper, r, tmp_path / "x.gif", frames=len(r.t) + 1)
    with pytest.raises(ValueError, match="fps"):
        animate(paper, r, tmp_path / "x.gif", fps=0)
    # A compiled Model carries its hinge, and the paper's own series keep q.
    np.testing.assert_array_equal(world_points(paper.model, r), world_points(paper, r))
    short = paper.simulate(0.02, 0.01)
    np.testing.assert_array_equal(world_points(paper, short), world_points(paper.model, short))
    with pytest.raises(ValueError, match="'q'"):
        world_points(paper, dfx.Result({"t": r.t}, units={"t": "s"}))
    with pytest.raises(TypeError, match="model"):
        world_points("model", r, hinge=paper.scene)


def test_mp4_needs_ffmpeg(run, tmp_path):
    from matplotlib.animation import FFMpegWriter

    paper, r = run
    if FFMpegWriter.isAvailable():
        path = animate(paper, r, tmp_path / "deploy.mp4", frames=3, dpi=40, figsize=(4, 3.5))
        assert path.stat().st_size > 0
    else:
        with pytest.raises(RuntimeError, match="ffmpeg"):
            animate(paper, r, tmp_path / "deploy.mp4", frames=3)
