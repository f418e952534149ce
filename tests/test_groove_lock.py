"""The lock as a pin sliding in a groove, run by the engine (issue 24; joint/pin_groove.hpp through
joint/lock.hpp; the geometry's own tests are tests/test_pin_groove.py).

References:
- a normal impact on a stop wall is unchanged by friction along the groove (the pin slides along
  the wall only by r (1 - cos D), docs/research/pin-groove.md): Hunt-Crossley restitution from
  the exact relation x - ln(1 + x) = -e x - ln(1 - e x) (Carvalho & Martins 2019), 1 %;
- a cam-driven deployment with friction: a rigid body (J about the axis) on a spring
  tau0 - k theta, its latch pin pressed by its spring (force N, constant on the circular track)
  onto a track about the hinge axis at radius s: work-energy, KE = tau0 theta - k theta^2 / 2 -
  mu N s theta, 1e-6 of the peak kinetic energy (measured 3e-8);
- the paper's scene with the groove: its first lock at the paper's 2.46 s (Fig. 7), 0.03 s;
- a scene file holds a groove: the same run, bit for bit.
"""
import numpy as np
import pytest
import scipy.optimize

import deployfx as dfx
from deployfx import scenes
from deployfx.contact import ContactLaw, Friction
from deployfx.groove import PinGroove
from deployfx.specs import Lock

R_PIN, J, W0, THETA_LOCK = 0.03, 12.0, 1.0, 0.05  # m, kg m^2, rad/s, rad (as test_lock_accuracy)


def body_on_hinge(lock=None, groove=None, tau0=0.0, k_theta=0.0):
    s = dfx.Scene().set_base(1.0, 1.0, free=False)
    s.set_hinge(point=(0.0, 0, 0), axis=(0, 1, 0), tau0=tau0, k_theta=k_theta)
    s.add_rigid_part(10.0, np.diag([J / 2, J, J / 2]), (0.0, 0, 0), body=0)
    if lock is not None:
        s.set_lock(lock.theta_lock, lock.pin_radius, lock.clearance, lock.law, friction=lock.friction)
    if groove is not None:
        s.set_groove(groove)
    return s.compile()


def swing(model):
    lay = model.layout(0)
    q0, v0 = model.initial_positions(), np.zeros(model.num_velocities)
    q0[lay["iq_theta"]], v0[lay["iv_theta"]] = THETA_LOCK - 0.01, W0
    return model.simulate(0.1, 0.01, q0=q0, v0=v0, progress=False)


def test_friction_along_the_groove_leaves_a_normal_impact_alone():
    x = 1.5 * (1 - 0.8)
    e = scipy.optimize.brentq(lambda r: x - np.log1p(x) + r * x + np.log1p(-r * x), 0.5, 1.0)
    law = ContactLaw("hunt-crossley", K=3e10, e=0.8)
    rebound = {}
    for mu in (0.0, 0.25):
        lock = Lock(THETA_LOCK, R_PIN, 0.9 * np.pi * R_PIN, law, Friction(mu))
        r = swing(body_on_hinge(groove=PinGroove.stop_latch(lock, rho=0.005)))
        first = r.impacts[0]
        assert first.wall == "facet 0" and first.t_separation_s is not None  # the stop
        rebound[mu] = first.restitution
        assert rebound[mu] == pytest.approx(e, rel=0.01)
    assert abs(rebound[0.25] - rebound[0.0]) < 1e-3 * rebound[0.0]
    # Today's walls in the hinge angle put the friction along the pin's path, i.e. the normal:
    # it damps the impact (the defect the groove removes).
    lock = Lock(THETA_LOCK, R_PIN, 0.9 * np.pi * R_PIN, law, Friction(0.25))
    assert swing(body_on_hinge(lock=lock)).impacts[0].restitution < 0.9 * e


def test_cam_driven_deployment_balances_spring_work_kinetic_energy_and_friction():
    tau0, k = 7.2, 1.0  # N m, N m/rad
    for mu in (0.0, 0.25):
        groove = PinGroove.paper(ContactLaw("paper", K=3.162e10, n=1.5, D=1e6), Friction(mu))
        r = body_on_hinge(groove=groove, tau0=tau0, k_theta=k).simulate(3.0, 0.01, progress=False).hinge(0)
        on_track = groove.position(0.5, groove.start_history(0.0))
        assert on_track["found"] and not on_track["bottomed"]
        N = groove.latch.preload + groove.latch.stiffness * on_track["w"]  # N, the pin's radial balance
        theta = np.radians(r.deployment_angle)
        ride = r.t < r.impacts[0].t_onset_s - 0.3  # on the track, before the notch
        assert theta[ride][-1] > 1.0
        energy = tau0 * theta - k * theta**2 / 2 - mu * N * on_track["s"] * theta
        assert np.abs(r.kinetic_energy[ride] - energy[ride]).max() < 1e-6 * r.kinetic_energy.max()


@pytest.mark.parametrize("model", ["rigid", "reduced-linear"])
def test_the_papers_scene_with_the_groove_locks_at_the_papers_time(model):
    r = scenes.paper2016(2, model, nx=4, ny=2, lock_geometry="groove").simulate(4.0, 0.01).hinge(0)
    s = r.summary()
    assert s["first_lock_time_s"] == pytest.approx(2.46, abs=0.03)
    assert r.latched[-1] == 1.0 and r.latched[0] == 0.0
    assert all(i.wall.startswith("facet ") for i in r.impacts)


def test_a_scene_file_holds_a_groove(tmp_path):
    sc = scenes.paper2016(2, "rigid", nx=2, ny=1, lock_geometry="groove")
    path = dfx.save_scene(sc.scene, tmp_path / "groove.toml")
    back = dfx.load_scene(path)
    assert dfx.scene_file.scene_to_dict(back) == dfx.scene_file.scene_to_dict(sc.scene)
    a, b = sc.model.simulate(3.0, 0.01), back.compile().simulate(3.0, 0.01)
    assert np.array_equal(a.q, b.q) and a.impacts == b.impacts
    # The play (0.2 mm at the 30 mm seat: 0.382 deg) is kept, and with it the settling band.
    assert back.compile().lock_play_deg == sc.model.lock_play_deg == pytest.approx((np.degrees(0.2e-3 / 0.03),))
    same = [{k: v for k, v in r.summary().items() if k != "wall_time_s"} for r in (a, b)]
    assert same[0] == same[1]


def test_the_groove_play_is_checked():
    profile = PinGroove.paper(ContactLaw("hunt-crossley", K=1e9, e=0.8), Friction(0.0)).profile
    with pytest.raises(ValueError, match=r"play_deg = -1.0 is out of range: must be in \[0, 360\]"):
        PinGroove(profile, 0.03, 0.0, 2e-3, ContactLaw("hunt-crossley", K=1e9, e=0.8), play_deg=-1.0)


def test_bad_groove_input_is_named():
    scene = dfx.Scene().set_base(1.0, 1.0).set_hinge(point=(0, 0, 0), axis=(0, 1, 0))
    with pytest.raises(TypeError, match="groove must be a deployfx.groove.PinGroove"):
        scene.set_groove(Lock(1.0, 0.03, 1e-4, ContactLaw("hunt-crossley", K=1e9, e=0.8)))
    with pytest.raises(ValueError, match="lock_geometry = 'slot' is invalid"):
        scenes.paper2016(2, "rigid", nx=2, ny=1, lock_geometry="slot")


@pytest.mark.parametrize("pin_radius", [1e-3, 0.1])
@pytest.mark.parametrize("mu", [0.0, 1.0])
@pytest.mark.parametrize("K", [1e3, 1e12])
def test_extremes_of_stiffness_friction_and_pin_radius(K, mu, pin_radius):
    # Issue 24's ranges at the default step, on the stop-latch groove. Every run completes with
    # finite values and never gains energy (the spring-free body only loses kinetic energy to the
    # law's hysteresis, 1e-9 of it for round-off). Where the impact's penetration scale v0 T
    # (contact.impact's time scale T of the pin's effective mass J / r^2) is well inside the
    # walls (a quarter of their reach, rho + r / 4), it rebounds as the closed form says
    # (Hunt-Crossley e = 0.8, 1 %); a softer law lets the pin through the walls' ends, a stop
    # that is not one, and is only required to stay finite.
    from deployfx import _core

    x = 1.5 * (1 - 0.8)
    e = scipy.optimize.brentq(lambda r: x - np.log1p(x) + r * x + np.log1p(-r * x), 0.5, 1.0)
    law = ContactLaw("hunt-crossley", K=K, e=0.8)
    lock = Lock(THETA_LOCK, pin_radius, 0.9 * np.pi * pin_radius, law, Friction(mu))
    rho = 0.1 * pin_radius
    model = body_on_hinge(groove=PinGroove.stop_latch(lock, rho=rho))
    lay = model.layout(0)
    q0, v0 = model.initial_positions(), np.zeros(model.num_velocities)
    q0[lay["iq_theta"]], v0[lay["iv_theta"]] = THETA_LOCK - 0.01, W0
    speed = W0 * pin_radius
    T = _core.impact_time_scale(law._impl, J / pin_radius**2, speed)
    r = model.simulate(max(0.2, 0.01 + 10 * T), 0.01, q0=q0, v0=v0, progress=False)
    assert np.all(np.isfinite(r.q)) and np.all(np.isfinite(r.lock_force))
    assert r.kinetic_energy.max() <= r.kinetic_energy[0] * (1 + 1e-9)
    if speed * T < (rho + pin_radius / 4) / 4:
        first = r.impacts[0]
        assert first.t_separation_s is not None
        assert first.restitution == pytest.approx(e, rel=0.01)
