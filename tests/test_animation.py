"""Animation of a deployment (issue 5): the world-coordinate transform against closed forms and a
forward kinematics composed by hand from the scene's hinges, and a GIF written frame by frame."""
import numpy as np
import pytest
from PIL import Image
from scipy.spatial.transform import Rotation

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
            .set_appendage(strip.model, strip.fixed_dofs("CFFF"), fidelity="linear"))


def _elastic(model, node: int, w: float) -> np.ndarray:
    """The free elastic coordinates of a transverse displacement w (m, E's z) of one node: a full
    panel's are its free mesh dofs, selected by its displacement map."""
    full = np.zeros(model.shells[0].num_dofs)
    full[6 * node + 2] = w
    D = model.core.displacement_map(0)
    assert set(np.unique(D)) == {0.0, 1.0} and np.all(D.sum(axis=0) == 1)  # a selection
    return D.T @ full


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
    P = world_points(model, result)
    x, y = model.shells[0].nodes[node, :2]
    assert (x, y) == (10.0, 0.0)
    np.testing.assert_allclose(P[0, node], [HINGE[0] - w, y, x], atol=1e-12)  # R_BE0 (x, y, w)
    np.testing.assert_allclose(P[1, node], [HINGE[0] + x, y, w], atol=1e-12)  # R_BE = I at 90 deg
    np.testing.assert_allclose(P[2, node], [1 - y, 2 + HINGE[0] + x, 3 + w], atol=1e-12)
    # Every node of the undeformed panel at 90 deg: the hinge point plus its E coordinates.
    others = np.arange(model.shells[0].nodes.shape[0]) != node
    np.testing.assert_allclose(P[1, others], HINGE + model.shells[0].nodes[others], atol=1e-12)
    # Undeformed (scale 0); the hinge given by its index.
    P0 = world_points(model, result, hinge=0, scale=0.0)
    np.testing.assert_allclose(P0[1], HINGE + model.shells[0].nodes, atol=1e-12)


def test_world_points_fixed_base_and_theta_from_q():
    scene = _scene(free=False)
    model = scene.compile()
    q = np.array([np.r_[np.pi / 2, np.zeros(model.layout(0)["num_elastic"])]])
    assert q.shape[1] == model.num_positions            # a fixed base has no coordinates
    result = dfx.Result({"t": [0.0], "q": q})          # no "deployment_angle" series: read from q
    np.testing.assert_allclose(world_points(model, result)[0], HINGE + model.shells[0].nodes, atol=1e-12)


def test_world_points_of_a_run_keep_the_root_on_the_hinge():
    paper = scenes.paper2016(2, "linear", nx=4, ny=2)
    r = paper.model.simulate(0.3, 0.01)
    P = world_points(paper, r)                           # the scene's only panel
    r_W, R_WB = animation.base_poses(paper, r)
    # The clamped root nodes move only with the base and the hinge: their distance to the
    # hinge axis (b_h = 0.03 m) is kept.
    root = np.flatnonzero(np.isclose(paper.model.shells[0].nodes[:, 0], 0.03))
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
    path = dfx.plot.animate(paper.model, r, tmp_path / "deploy.gif", fps=10, frames=4, dpi=40,
                            figsize=(4, 3.5))
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
    # A ready scene stands for its model, and the paper's own series keep q.
    np.testing.assert_array_equal(world_points(paper.model, r), world_points(paper, r))
    short = paper.simulate(0.02, 0.01)
    np.testing.assert_array_equal(world_points(paper, short), world_points(paper.model, short))
    with pytest.raises(ValueError, match="'q'"):
        world_points(paper, dfx.Result({"t": r.t}, units={"t": "s"}))
    with pytest.raises(TypeError, match="model"):
        world_points("model", r)


def test_mp4_has_the_frames_asked_for(run, tmp_path):
    # MP4 through ffmpeg (the system's or the imageio-ffmpeg wheel of the test extras): the movie
    # ffmpeg itself reads back has the frames written and lasts frames / fps.
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    paper, r = run
    path = animate(paper, r, tmp_path / "deploy.mp4", frames=4, fps=8.0, dpi=40, figsize=(4, 3.5))
    frames, seconds = imageio_ffmpeg.count_frames_and_secs(str(path))
    assert frames == 4
    assert seconds == pytest.approx(4 / 8.0, abs=1 / 8.0)


def test_mp4_without_ffmpeg_says_how_to_get_it(run, tmp_path, monkeypatch):
    # No ffmpeg on PATH and no imageio-ffmpeg: a RuntimeError naming both remedies, no file.
    import builtins

    import matplotlib

    real_import = builtins.__import__

    def no_imageio_ffmpeg(name, *args, **kwargs):
        if name == "imageio_ffmpeg":
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    monkeypatch.setitem(matplotlib.rcParams, "animation.ffmpeg_path", "no-such-ffmpeg-deployfx")
    monkeypatch.setattr(builtins, "__import__", no_imageio_ffmpeg)
    paper, r = run
    with pytest.raises(RuntimeError, match=r"ffmpeg.*deployfx\[video\].*apt-get install ffmpeg"):
        animate(paper, r, tmp_path / "deploy.mp4", frames=3)
    assert not (tmp_path / "deploy.mp4").exists()


# ------------------------------------------------------------------------------------------------
# Chains of hinges: a yoke and two rigid panels, placed in world coordinates.

L_PANEL, W_PANEL = 1.0, 0.4  # m


def Ry(a):
    """Rotation by ``a`` (rad) about y."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def Rx(a):
    """Rotation by ``a`` (rad) about x."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _panel():
    """A 1 m x 0.4 m aluminium panel, nodes (x, y, 0) in E, x in [0, 1], y in [-0.2, 0.2]: its
    root edge x = 0 lies on E's y axis."""
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=70e9, nu=0.33, rho=2700.0), 2e-3)])
    plate = dfx.Plate(L_PANEL, W_PANEL, lam, nx=3, ny=2)
    nodes = plate.model.nodes.copy()
    nodes[:, 1] -= W_PANEL / 2
    return dfx.ShellModel(nodes, plate.model.quads, lam), plate.fixed_dofs("CFFF")


def _chain(free: bool):
    """Yoke on hinge 0 (about B's y), panel A on hinge 1 (about E0's z, R_PE0 = Rx(90 deg), which
    does not commute with the hinge rotation; A's root edge, E1's y, lies on that axis: Rx(90)^T z
    = y), panel B on hinge 2 at A's far edge (about E1's y, folded back: Ry(180 deg))."""
    shell, root = _panel()
    scene = (Scene().set_base(200.0, 30.0, free=free)
             .add_hinge("base", point=(0.5, 0, 0), axis=(0, 1, 0), R_PE0=Ry(-np.pi / 2), tau0=1.0,
                        fitting_inertia=0.01)
             .add_rigid_part(2.0, np.diag([0.01, 0.1, 0.1]), (0.3, 0, 0), body=0)
             .add_hinge(0, point=(0.6, 0, 0), axis=(0, 0, 1), R_PE0=Rx(np.pi / 2), tau0=0.5,
                        fitting_inertia=0.01)
             .set_appendage(shell, root, fidelity="rigid")
             .add_hinge(1, point=(L_PANEL, 0, 0), axis=(0, 1, 0), R_PE0=Ry(np.pi), tau0=0.5,
                        fitting_inertia=0.01)
             .set_appendage(shell, root, fidelity="rigid"))
    return scene.compile(), shell


THETAS = np.array([[0.0, 0.0, 0.0], [0.3, -0.7, 1.1], [1.2, 0.4, -2.0], [np.pi / 2, np.pi / 3, 3.0]])


def _chain_result(model, thetas=THETAS, base=None):
    """A Result with prescribed q: the hinge angles (rad) and, for a free base, ``base`` = the
    7 base coordinates [r_W, quaternion (w, x, y, z)] (identity pose by default)."""
    q = np.asarray(thetas, dtype=float)
    if model.base_free:
        b = np.r_[0, 0, 0, 1.0, 0, 0, 0] if base is None else np.asarray(base, dtype=float)
        q = np.hstack([np.tile(b, (len(q), 1)), q])
    return dfx.Result({"t": np.arange(len(q), dtype=float), "q": q})


def test_chain_keeps_its_panels_shells():
    model, shell = _chain(free=False)
    assert isinstance(model, dfx.Model)
    assert model.shells[0] is None and model.shells[1] is shell and model.shells[2] is shell
    assert len(model.shells) == model.num_hinges == 3


def test_chain_stowed_geometry_by_hand():
    model, shell = _chain(free=False)
    r = _chain_result(model, np.zeros((1, 3)))
    x, y = shell.nodes[:, 0], shell.nodes[:, 1]
    # E0 = (0.5, 0, 0), Ry(-90); E1 = E0 + Ry(-90) (0.6, 0, 0) = (0.5, 0, 0.6), axes Ry(-90) Rx(90)
    # = [[0,-1,0],[0,0,-1],[1,0,0]]; E2 = E1 + (0, 0, L), axes E1's Ry(180).
    A = np.column_stack([0.5 - y, 0 * x, 0.6 + x])
    B = np.column_stack([0.5 - y, 0 * x, 0.6 + L_PANEL - x])
    np.testing.assert_allclose(world_points(model, r, hinge=1)[0], A, atol=1e-12)
    np.testing.assert_allclose(world_points(model, r, hinge=2)[0], B, atol=1e-12)


def _frames_by_hand(model, q):
    """Every body frame composed from the scene's hinges (docs/notation.md): C_k's origin
    o_P + R_WP point_k and axes R_WP Rot(axis_k, theta_k) R_PC0_k, P its parent (the base at r_W,
    R_WB, or body k - 1 here); theta_k = q's hinge angles after the base's 7 coordinates."""
    r_W, R_WB = np.zeros(3), np.eye(3)
    if model.base_free:
        r_W, R_WB = q[:3], Rotation.from_quat(q[[4, 5, 6, 3]]).as_matrix()
    thetas = q[7:] if model.base_free else q
    R, o = [], []
    for k, link in enumerate(model.links):
        h = link.hinge
        R_P, o_P = (R_WB, r_W) if h.parent == "base" else (R[h.parent], o[h.parent])
        o.append(o_P + R_P @ h.point)
        R.append(R_P @ Rotation.from_rotvec(thetas[k] * h.axis).as_matrix() @ h.R_PC0)
    return np.array(R), np.array(o)


def test_chain_frames_match_a_forward_kinematics_by_hand():
    """body_frames (the engine's forward pass, Model.frames) against the frames composed above."""
    c = np.cos(np.pi / 6)
    for free in (False, True):
        model, _ = _chain(free)
        base = np.array([0.3, -1.0, 2.0, c, 0.2, -0.3, np.sin(np.pi / 6)])
        base[3:7] /= np.linalg.norm(base[3:7])  # the engine takes unit quaternions
        r = _chain_result(model, base=base)
        R_WE, o_W = animation.body_frames(model, r)
        assert R_WE.shape == (len(THETAS), 3, 3, 3) and o_W.shape == (len(THETAS), 3, 3)
        for i, q in enumerate(r["q"]):
            R, o = _frames_by_hand(model, q)
            np.testing.assert_allclose(o_W[i], o, atol=1e-12)
            np.testing.assert_allclose(R_WE[i], R, atol=1e-12)
        if free:  # the base's pose moves the frames (the check can fail)
            assert np.abs(o_W[0] - _frames_by_hand(_chain(False)[0], THETAS[0])[1]).max() > 0.1


def test_frame_labels_read_the_angles_from_q_without_a_deployment_angle_series():
    # A result of q alone: each hinge's angle is its travel in q (Model.layout), in degrees; a
    # prescribed hinge's is Kane, Ryan & Banerjee's theta(t) = (omega_s / t_s) [t^2 / 2
    # + (t_s / 2 pi)^2 (cos(2 pi t / t_s) - 1)] during the spin-up.
    model, _ = _chain(free=True)
    r = _chain_result(model)
    np.testing.assert_allclose(animation._angles_deg(model, r.q, r.t), np.degrees(THETAS), rtol=1e-14)
    assert animation._picture(model, r, 1.0)["label"](1) == "deployment angle 17.2, -40.1, 63.0 deg"
    # The frame's words are the plots' axis labels' (deployfx.plot), with their units.
    text = animation._frame_text(0.25, animation._picture(model, r, 1.0)["label"](1))
    assert text == "time   0.250 s   deployment angle 17.2, -40.1, 63.0 deg"
    (ax,) = dfx.plot.deployment_angle(dfx.Result({"t": [0.0, 1.0], "deployment_angle": [90.0, 180.0]})).axes
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("time (s)", "deployment angle (deg)")
    omega_s, t_s = 2.0, 5.0
    beam = scenes.spin_up_beam(omega_s, t_s=t_s, nx=2).model
    t = np.array([0.0, 1.0, 2.5, 5.0])
    q = np.zeros((len(t), beam.num_positions))
    exact = omega_s / t_s * (t**2 / 2 + (t_s / (2 * np.pi)) ** 2 * (np.cos(2 * np.pi * t / t_s) - 1))
    np.testing.assert_allclose(animation._angles_deg(beam, q, t)[:, 0], np.degrees(exact), rtol=1e-12, atol=1e-12)


def test_chain_root_edges_lie_on_their_hinge_axes():
    model, shell = _chain(free=False)
    r = _chain_result(model)
    root = np.flatnonzero(np.isclose(shell.nodes[:, 0], 0.0))
    assert root.size == 3
    axes = [np.array(h) for h in ((0, 1, 0), (0, 0, 1), (0, 1, 0))]
    R_all, o_all = model.frames(r["q"])
    for i in range(len(r["q"])):
        R, o = R_all[i], o_all[i]
        for k in (1, 2):
            # Hinge k's axis in W: through E_k's origin, along the parent E_{k-1}'s axis_k.
            d = R[k - 1] @ axes[k]
            rel = world_points(model, r, hinge=k)[i, root] - o[k]
            np.testing.assert_allclose(np.linalg.norm(np.cross(rel, d), axis=1), 0.0, atol=1e-12)
            # ... and the far nodes are not on it (the check can fail).
            far = world_points(model, r, hinge=k)[i] - o[k]
            assert np.linalg.norm(np.cross(far, d), axis=1).max() > 0.9 * L_PANEL


def test_chain_free_base_pose_moves_everything_rigidly():
    fixed, _ = _chain(free=False)
    free, _ = _chain(free=True)
    c = np.cos(np.pi / 4)
    r_W, R_WB = np.array([1.0, 2.0, 3.0]), np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    rf = _chain_result(fixed)
    rm = _chain_result(free, base=np.r_[r_W, c, 0, 0, c])   # 90 deg about z
    np.testing.assert_allclose(animation.base_poses(free, rm)[1][0], R_WB, atol=1e-12)
    for k in (1, 2):
        expected = r_W + world_points(fixed, rf, hinge=k) @ R_WB.T
        np.testing.assert_allclose(world_points(free, rm, hinge=k), expected, atol=1e-12)


@pytest.fixture(scope="module")
def chain_run():
    model, _ = _chain(free=True)
    return model, model.simulate(0.3, 0.01)


def test_chain_run_moves_panels_rigidly(chain_run):
    model, r = chain_run
    assert np.ptp(r.deployment_angle, axis=0).min() > np.degrees(1e-3)  # every hinge moved
    for k in (1, 2):
        P = world_points(model, r, hinge=k)
        X = model.shells[k].nodes
        d0 = np.linalg.norm(X[:, None] - X[None], axis=2)
        d = np.linalg.norm(P[:, :, None] - P[:, None], axis=3)
        np.testing.assert_allclose(d, np.broadcast_to(d0, d.shape), atol=1e-12)
        assert np.abs(P[-1] - P[0]).max() > 1e-3               # and it moved in W


def test_chain_world_points_inputs(chain_run):
    model, r = chain_run
    with pytest.raises(ValueError, match="hinge is required"):
        world_points(model, r)                                 # two panels: which?
    with pytest.raises(ValueError, match="carries no panel"):
        world_points(model, r, hinge=0)                        # the yoke
    with pytest.raises(ValueError, match="out of range"):
        world_points(model, r, hinge=3)
    with pytest.raises(ValueError, match="another model"):
        animation.body_frames(scenes.paper2016(2, "rigid", nx=2, ny=1).model, r)


def test_chain_gif_has_the_frames_asked_for(chain_run, tmp_path):
    model, r = chain_run
    path = dfx.plot.animate(model, r, tmp_path / "chain.gif", fps=10, frames=3, dpi=40, figsize=(4, 3.5))
    with Image.open(path) as im:
        assert im.format == "GIF"
        assert im.n_frames == 3


def test_chain_vtk_series_round_trips_world_points(chain_run, tmp_path):
    import meshio  # in the test extras

    from deployfx.export import write_vtk_series

    model, r = chain_run
    paths = write_vtk_series(model, r, tmp_path, name="array", every=10)
    assert len(paths) == 4                                     # samples 0, 10, 20, 30
    shell = model.shells[1]
    n = shell.nodes.shape[0]
    for path, k in zip(paths, range(0, len(r.t), 10)):
        back = meshio.read(path)
        expected = np.concatenate([world_points(model, r, hinge=1)[k], world_points(model, r, hinge=2)[k]])
        np.testing.assert_array_equal(back.points, expected)
        quads = back.cells_dict["quad"]
        np.testing.assert_array_equal(quads, np.concatenate([shell.quads, np.asarray(shell.quads) + n]))
        np.testing.assert_array_equal(back.cell_data_dict["hinge"]["quad"], np.repeat([1, 2], len(shell.quads)))
    times = np.loadtxt(tmp_path / "array_times.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(times[:, 1], r.t[::10])
    # The ParaView collection lists the files with their times.
    pvd = (tmp_path / "array.pvd").read_text()
    assert pvd.count("<DataSet ") == 4 and all(f'file="{p.name}"' in pvd for p in paths)
    with pytest.raises(ValueError, match="frame"):
        write_vtk_series(model, r, tmp_path, frame="appendage")
    with pytest.raises(ValueError, match="hinge must be None"):
        write_vtk_series(model, r, tmp_path, hinge=1)
    with pytest.raises(ValueError, match="hinge is required"):
        write_vtk_series(model, r, tmp_path, frame="panel")     # two panels: which?


def test_one_hinge_vtk_series_in_world_coordinates(run, tmp_path):
    import meshio

    from deployfx.export import write_vtk_series

    paper, r = run
    k = 30
    shell = paper.model.shells[0]
    u_E = paper.model.node_displacements(r.q, 0)[k]   # the panel's node translations, E axes
    # In the panel's frame E: the mesh plus its displacement.
    e = write_vtk_series(paper, r, tmp_path / "E", every=k, frame="panel")
    np.testing.assert_array_equal(meshio.read(e[1]).points, shell.nodes + u_E)
    w = write_vtk_series(paper, r, tmp_path / "W", every=k)  # default: world coordinates
    back = meshio.read(w[1])
    np.testing.assert_array_equal(back.points, world_points(paper, r)[k])
    assert np.abs(back.points - meshio.read(e[1]).points).max() > 0.1   # a different frame
    # The displacement in W's axes: rotated, so of the same length as in E, and not all zero.
    np.testing.assert_allclose(np.linalg.norm(back.point_data["displacement"], axis=1),
                               np.linalg.norm(u_E, axis=1), rtol=1e-12, atol=1e-15)
    assert np.abs(u_E).max() > 0
    with pytest.raises(TypeError, match="model"):
        write_vtk_series(shell, r, tmp_path)
    with pytest.raises(ValueError, match="frame"):
        write_vtk_series(paper, r, tmp_path, frame="body")
