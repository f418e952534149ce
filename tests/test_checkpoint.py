"""Checkpoint and resume (issue 29): a run resumed from a checkpoint is bit-identical to the run
that took it, for every fidelity and a two-wing tree, with fixed and error-controlled steps, before
the lock and while a lock contact is in progress; through a file too. Runs are deterministic in
any thread."""
import threading

import numpy as np
import pytest

import deployfx as dfx
from deployfx import scenes

import chain_scenes  # tests/: scenes shared by tests

T_END = 2.75  # s: the paper's scene locks at about 2.46 s and rattles in its play after
DT = 0.01
BEFORE = 1.0  # s: deploying, no contact yet
# Checkpoints at every output instant of the rattle: the test picks those with a contact open.
RATTLE = [round(2.40 + DT * k, 10) for k in range(int(round((T_END - 2.40) / DT)) + 1)]


def scene(model, **kw):
    kw.setdefault("nx", 2)
    kw.setdefault("ny", 1)
    if model.startswith("reduced"):
        kw.setdefault("modes", 4)
    return scenes.paper2016(2, model, **kw)


def assert_same_from(full, resumed, t):
    """``resumed`` equals ``full`` from time t on, bit for bit."""
    i = int(np.flatnonzero(full.t == t)[0])
    assert resumed.t[0] == t
    for name in ("t", "q", "v", "deployment_angle", "lock_force", "kinetic_energy"):
        a, b = full[name][i:], resumed[name]
        assert a.shape == b.shape and np.array_equal(a, b), name
    for k, h in enumerate(full.metadata["hinges"]):
        assert resumed.metadata["hinges"][k].get("impacts") == h.get("impacts"), k


def in_contact(checkpoint):
    """Whether a lock contact is in progress at the checkpoint (an open impact record)."""
    imp = checkpoint.impacts
    return bool(len(imp["t_separation"]) and np.isnan(imp["t_separation"][-1]))


def check_resumes(sc, tolerance=None, t_end=T_END):
    full = sc.simulate(t_end, DT, tolerance=tolerance, checkpoint_at=[BEFORE] + RATTLE, progress=False)
    plain = sc.simulate(t_end, DT, tolerance=tolerance, progress=False)  # taking checkpoints changes nothing
    assert np.array_equal(plain.q, full.q) and np.array_equal(plain.v, full.v) and np.array_equal(plain.t, full.t)
    cks = {round(c.t, 10): c for c in full.checkpoints}
    assert sorted(cks) == sorted([BEFORE] + RATTLE)
    during = [c for t, c in sorted(cks.items()) if t > 2.4 and in_contact(c)]
    assert during, "no output instant inside a lock contact"
    after_lock = [c for t, c in sorted(cks.items()) if len(c.impacts["t_onset"]) and not in_contact(c)]
    for c in [cks[BEFORE], during[0], during[-1], *after_lock[:1]]:
        resumed = sc.simulate(t_end, DT, tolerance=tolerance, resume=c, progress=False)
        assert_same_from(full, resumed, c.t)
    return full, cks, during


@pytest.mark.parametrize("model", ["rigid", "linear", "nonlinear", "reduced-linear", "reduced-nonlinear"])
def test_resume_is_bit_identical_for_every_fidelity(model):
    check_resumes(scene(model))


def test_resume_anywhere_in_a_reduced_green_strain_panels_full_newton():
    """A reduced Green-strain panel's Newton runs full steps while it deploys, alternating whole
    matrices with ones whose elastic block alone was refreshed (NewtonOptions::elastic_refreshes):
    a checkpoint carries where in that alternation its step ended. Resumed from every 0.05 s of
    the first second (without that counter, 6 of the 19 resumes took other iterates)."""
    sc = scene("reduced-nonlinear")
    at = [round(0.05 * k, 10) for k in range(1, 20)]
    full = sc.simulate(1.0, DT, checkpoint_at=at, progress=False)
    assert len(full.checkpoints) == len(at)
    for c in full.checkpoints:
        resumed = sc.simulate(1.0, DT, resume=c, progress=False)
        i = int(np.flatnonzero(full.t == c.t)[0])
        assert np.array_equal(full.q[i:], resumed.q) and np.array_equal(full.v[i:], resumed.v), c.t


@pytest.mark.parametrize("model", ["rigid", "linear"])
def test_resume_with_error_controlled_steps(model):
    check_resumes(scene(model), tolerance=1e-4)


@pytest.mark.parametrize("tolerance", [None, 1e-4], ids=["fixed", "error-controlled"])
def test_resume_a_sparse_green_strain_mesh(tolerance):
    """A 4 x 3 nonlinear mesh (its elastic block sparse, unlike 2 x 1's): Newton relaxes the
    membrane after every kept-matrix iteration, reading the in-plane rows formed alone where the
    slaved block for the step size is at hand, keeps that block over the factorizations at its
    step size, and forms a new step size's block from the kept matrix (every step of an
    error-controlled run has its own size): all of it is a function of the state a checkpoint
    restores (the slaved block's source matrix among it)."""
    check_resumes(scene("nonlinear", nx=4, ny=3), tolerance=tolerance)


def test_resume_two_wings_and_through_a_file(tmp_path):
    sc = scene("linear", wings=2)
    full, cks, during = check_resumes(sc)
    c = during[0]
    path = c.save(tmp_path / "run.ckpt")
    back = dfx.load_checkpoint(path)
    assert back.t == c.t and back.dt == DT and back.scheme == c.scheme and back.tolerance == c.tolerance
    assert np.array_equal(back.q, c.q) and np.array_equal(back.v, c.v)
    resumed = sc.model.resume(back, T_END, progress=False)
    np.testing.assert_array_equal(resumed.q, sc.model.resume(c, T_END, progress=False).q)
    i = int(np.flatnonzero(full.t == c.t)[0])
    assert np.array_equal(resumed.q, full.q[i:]) and np.array_equal(resumed.t, full.t[i:])
    assert resumed.metadata["resumed_from_s"] == c.t
    import pickle
    assert np.array_equal(sc.model.resume(pickle.loads(pickle.dumps(c)), T_END, progress=False).q, resumed.q)


def test_resume_to_a_later_end_and_checkpoint_again():
    sc = scene("rigid")
    full = sc.simulate(2.6, DT, checkpoint_at=[1.0, 2.5], progress=False)
    first = sc.simulate(1.5, DT, checkpoint_at=[1.0, 1.5], progress=False)  # a run cut at 1.5 s
    np.testing.assert_array_equal(first.q, full.q[: len(first.t)])  # same checkpoints up to 1.5 s
    second = sc.simulate(2.6, DT, checkpoint_at=[2.5], resume=first.checkpoints[0], progress=False)
    assert_same_from(full, second, 1.0)
    assert second.checkpoints[0].t == 2.5
    np.testing.assert_array_equal(second.checkpoints[0].q, full.checkpoints[1].q)


def test_same_run_in_threads_is_bit_identical():
    sc = scene("linear")
    ref = sc.simulate(2.6, DT, checkpoint_at=[2.0], progress=False)
    ck = ref.checkpoints[0]
    out = {}

    def run(k):
        out[k] = sc.simulate(2.6, DT, checkpoint_at=[2.0], progress=False) if k % 2 else \
            sc.model.resume(ck, 2.6, progress=False)

    threads = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k, r in out.items():
        if k % 2:
            assert np.array_equal(r.q, ref.q) and np.array_equal(r.v, ref.v) and np.array_equal(r.t, ref.t)
        else:
            assert_same_from(ref, r, 2.0)


def test_bad_checkpoint_times_and_resumes(tmp_path):
    sc = scene("rigid")
    m = sc.model
    for bad in ([0.0], [-0.1], [1.01], [0.105], [float("nan")]):
        with pytest.raises(ValueError, match="checkpoint_at"):
            m.simulate(1.0, 0.01, checkpoint_at=bad)
    for bad in ("0.5", 0.5, [True], [None]):
        with pytest.raises(TypeError, match="checkpoint_at"):
            m.simulate(1.0, 0.01, checkpoint_at=bad)
    r = m.simulate(0.2, 0.01, checkpoint_at=[0.1, 0.2])
    assert [c.t for c in r.checkpoints] == [0.1, 0.2]
    ck = r.checkpoints[0]
    with pytest.raises(ValueError, match="dt"):
        m.simulate(0.3, 0.02, resume=ck)
    with pytest.raises(ValueError, match="scheme"):
        m.simulate(0.3, 0.01, scheme=dfx.integrators.GeneralizedAlpha(0.9), resume=ck)
    with pytest.raises(ValueError, match="tolerance"):
        m.simulate(0.3, 0.01, tolerance=1e-3, resume=ck)
    with pytest.raises(ValueError, match="t_end"):
        m.resume(ck, 0.05)
    with pytest.raises(ValueError, match="checkpoint_at"):
        m.resume(ck, 0.3, checkpoint_at=[0.05])
    with pytest.raises(ValueError, match="q0"):
        m.simulate(0.3, 0.01, resume=ck, q0=ck.q)
    with pytest.raises(TypeError, match="resume"):
        m.simulate(0.3, 0.01, resume="ck")
    with pytest.raises(TypeError, match="dt"):
        m.resume(ck, 0.3, dt=0.01)
    other = scene("rigid", k_theta=1.0).model
    with pytest.raises(ValueError, match="another model"):
        other.resume(ck, 0.3)
    linear = scene("linear").model
    with pytest.raises(ValueError, match="another model"):
        linear.resume(ck, 0.3)
    # Files: atomic, checked.
    path = ck.save(tmp_path / "a.ckpt")
    data = path.read_bytes()
    for cut in (len(data) - 1, len(data) // 2, 10):
        (tmp_path / "cut.ckpt").write_bytes(data[:cut])
        with pytest.raises(ValueError, match="cut.ckpt"):
            dfx.load_checkpoint(tmp_path / "cut.ckpt")
    flipped = bytearray(data)
    flipped[len(data) // 2] ^= 1
    (tmp_path / "flip.ckpt").write_bytes(bytes(flipped))
    with pytest.raises(ValueError, match="corrupt"):
        dfx.load_checkpoint(tmp_path / "flip.ckpt")
    r.save(tmp_path / "result.npz")
    with pytest.raises(ValueError, match="not a deployfx checkpoint"):
        dfx.load_checkpoint(tmp_path / "result.npz")
    with pytest.raises(ValueError, match="checkpoint"):
        dfx._core.Checkpoint.from_bytes(ck._core.to_bytes()[:-3])


def locked_chain(fidelity):
    """tests/test_flexible_chain.py's array (chain_scenes.locked_array, 3 x 2 panels): a yoke and
    two panels, hinge 2 riding on panel 1, every hinge locking on stop-and-latch walls."""
    return chain_scenes.locked_array(fidelity, nx=3)


def test_resume_a_locked_chain_through_a_file(tmp_path):
    m = locked_chain("reduced-linear")
    times = [round(0.01 * k, 10) for k in range(1, 191)]
    full = m.simulate(1.9, 0.01, checkpoint_at=times)
    assert np.array_equal(full.q, m.simulate(1.9, 0.01).q)
    during = [c for c in full.checkpoints if in_contact(c)]
    assert during and all(full.summary()["first_lock_time_s"])
    for c in [full.checkpoints[9], during[0], during[len(during) // 2]]:
        back = dfx.load_checkpoint(c.save(tmp_path / "chain.ckpt"))
        assert_same_from(full, m.resume(back, 1.9), c.t)


def test_a_resumed_run_keeps_the_energy_checks_baseline():
    # The divergence check compares the energy with the run's start and its peak kinetic energy:
    # a resumed run judges against the uninterrupted run's, carried in the checkpoint.
    from deployfx._run import _energy_growth

    sc = scene("rigid")
    r = sc.simulate(2.0, DT, checkpoint_at=[1.0, 2.0], progress=False)
    E = r.kinetic_energy + r.potential_energy
    c = r.checkpoints[0]
    assert c.energy0 == E[0] and c.kinetic_peak == r.kinetic_energy[:101].max()
    again = sc.model.resume(c, 2.0, checkpoint_at=[2.0], progress=False).checkpoints[0]
    assert again.energy0 == E[0] and again.kinetic_peak == r.checkpoints[1].kinetic_peak
    raw = {"kinetic_energy": np.array([0.1, 0.1]), "potential_energy": np.array([0.5, 0.5]), "t": np.array([1.0, 1.1])}
    assert _energy_growth(raw) == ""
    assert "diverged" in _energy_growth(raw, (0.0, 1.0)) and _energy_growth(raw, (0.5, 1.0)) == ""
