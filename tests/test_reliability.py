"""Regression tests of issue 29's reliability findings outside the multibody engine: each input
that crashed the interpreter, hung, returned inf/NaN silently, wrapped an index or took a wrong
type now gives a clear error naming the parameter, or a valid result checked against an
independent reference. Inputs that crashed run in a child interpreter (tests/isolated.py)."""
import json
import math
import signal
import time

import numpy as np
import pytest
import scipy.linalg

import deployfx as dfx
from deployfx import contact, paper2016, scenes
from isolated import assert_ok, run_python


# ------------------------------------------------------------------------------------------------
# The modal solver near the dense-solver threshold (n = ndof - 12 and just below)

def _dense_frequencies(plate, boundary):
    """Reference: all frequencies (Hz) of the restricted K, M by LAPACK's dense generalised
    symmetric solver (scipy.linalg.eigh), independent of deployfx's solvers; equilibrated by
    diag(M)^-1/2 (rotary inertia is ~1e-6 of the translational mass). Each eigenvalue is then the
    Rayleigh quotient x^T K x / x^T M x of its eigenvector, whose error is quadratic in the vector's:
    LAPACK's own eigenvalues carry ~eps lambda_max / lambda ~ 1e-5 relative here, and which 1e-5
    depends on the machine's BLAS kernels (1.2e-5 on an AMD EPYC, below 1e-5 on earlier machines)."""
    fixed = set(plate.fixed_dofs(boundary).tolist())
    keep = [d for d in range(plate.model.num_dofs) if d not in fixed]
    K = plate.model.stiffness_matrix().toarray()[np.ix_(keep, keep)]
    M = plate.model.mass_matrix().toarray()[np.ix_(keep, keep)]
    s = 1.0 / np.sqrt(np.diag(M))
    Ks, Ms = s[:, None] * K * s, s[:, None] * M * s
    _, X = scipy.linalg.eigh(Ks, Ms)
    lam = np.einsum("ij,ij->j", X, Ks @ X) / np.einsum("ij,ij->j", X, Ms @ X)
    return np.sqrt(np.clip(lam, 0, None)) / (2 * np.pi)


# (boundary, n, rigid-body modes)
CASES = [("FFFF", 58, 6), ("FFFF", 59, 6), ("FFFF", 60, 6), ("CFFF", 40, 0), ("CFFF", 41, 0),
         ("CFFF", 42, 0)]


def test_lowest_modes_just_below_the_dense_threshold_match_lapack():
    """Plate(2.0, 1.3, lam, 3, 2).natural_frequencies(58, "FFFF") and CFFF n = 40..42 crashed
    (SIGSEGV: the Lanczos basis could not grow, the eigenvalues still wanted lying beyond 1e12
    times the shift, and an empty block reached the eigensolver). In a child: every case
    returns; the elastic frequencies match LAPACK to 1e-4 relative (a dense solver's round-off is
    ~eps lambda_max / lambda = 1e-16 x 1.3e13 / 134 ~ 1e-5 here: two LAPACK runs, scaled and
    not, differ by 7e-6), the rigid-body ones are below 1e-2 Hz (the first elastic: 1.84 Hz)."""
    out = assert_ok(run_python(f"""
        import json
        from deployfx import paper2016
        plate = paper2016.appendage_plate(2, 3, 2)
        print(json.dumps({{f"{{b}} {{n}}": plate.natural_frequencies(n, b).tolist()
                          for b, n, _ in {CASES!r}}}))
    """, timeout=300)).json()
    plate = paper2016.appendage_plate(2, 3, 2)
    for boundary, n, rigid in CASES:
        f = np.array(out[f"{boundary} {n}"])
        ref = _dense_frequencies(plate, boundary)[:n]
        assert f.shape == (n,)
        assert np.all(f[:rigid] < 1e-2) and np.all(ref[:rigid] < 1e-2), (boundary, n)
        np.testing.assert_allclose(f[rigid:], ref[rigid:], rtol=1e-4, err_msg=f"{boundary} {n}")


def test_a_huge_shear_modulus_is_refused_where_it_enters():
    """G12 = 1e308 passed the checks and crashed the modal solver."""
    with pytest.raises(ValueError, match=r"Orthotropic\.G12 = 1e\+308"):
        dfx.Orthotropic(E1=177e9, E2=10.8e9, G12=1e308, G13=7.6e9, G23=8.5e9, nu12=0.27, rho=1600)
    # Within the doubles but 1e7 times E2: the stiffness would carry no digit of E2.
    with pytest.raises(ValueError, match=r"Orthotropic\.G12 .* within a factor 1e\+06"):
        dfx.Orthotropic(E1=177e9, E2=10.8e9, G12=1e17, G13=7.6e9, G23=8.5e9, nu12=0.27, rho=1600)


@pytest.mark.parametrize("name, kwargs", [("Isotropic.E", dict(E=1e-300, nu=0.3, rho=1.0)),
                                          ("Isotropic.rho", dict(E=1.0, nu=0.3, rho=1e-300)),
                                          ("Isotropic.nu", dict(E=70e9, nu=-1 + 1e-9, rho=2700.0))])
def test_materials_outside_the_representable_range_are_refused(name, kwargs):
    """E = rho = 1e-300 crashed compile() of a reduced appendage; nu -> -1 makes G = E/(2(1+nu))
    unbounded."""
    with pytest.raises(ValueError, match=name.replace(".", r"\.")):
        dfx.Isotropic(**kwargs)


def test_the_weakest_lightest_material_accepted_keeps_its_frequencies():
    """Nearly the smallest moduli and density the checks take (E = rho = 1e-48, G = 3.8e-49;
    E = rho = 1e-300 crashed): in a child, the clamped plate's lowest frequencies are those of
    E = rho = 1 (they depend on E / rho only) to 1e-9 relative, and LAPACK's to 1e-5 (a dense
    solver's round-off here, see above)."""
    out = assert_ok(run_python("""
        import json
        import deployfx as dfx
        for scale in (1e-48, 1.0):
            lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(scale, 0.3, scale), 0.002)])
            f = dfx.Plate(1.0, 0.5, lam, 4, 2).natural_frequencies(3, "CFFF")
            print(json.dumps(f.tolist()))
    """)).stdout.splitlines()
    tiny, unit = np.array(json.loads(out[0])), np.array(json.loads(out[1]))
    np.testing.assert_allclose(tiny, unit, rtol=1e-9)
    plate = dfx.Plate(1.0, 0.5, dfx.Laminate([dfx.Ply(dfx.Isotropic(1e-48, 0.3, 1e-48), 0.002)]),
                      4, 2)
    np.testing.assert_allclose(tiny, _dense_frequencies(plate, "CFFF")[:3], rtol=1e-5)


# ------------------------------------------------------------------------------------------------
# contact.impact: bounded, interruptible, finite

def test_an_impact_that_never_separates_is_a_clear_error_not_a_hang():
    """K = 1e-300 with D = 1e3: the dashpot stops the mass, the spring would need ~1e300 s to push
    it out; impact() never returned. In a child (120 s limit): a ValueError naming contact.K."""
    out = run_python("""
        from deployfx import contact
        law = contact.ContactLaw("kelvin-voigt-hertz", K=1e-300, n=1.5, D=1e3)
        try:
            contact.impact(law, 1.0, 1.0)
        except ValueError as e:
            print("ValueError:", e)
    """, timeout=120)
    assert_ok(out)
    assert "ValueError:" in out.stdout and "contact.K = 1e-300" in out.stdout, out.describe()
    assert "1000 T" in out.stdout


def test_ctrl_c_interrupts_a_long_impact():
    """A long impact (the case above runs ~4e6 steps) is interrupted by SIGINT: the child ends
    with KeyboardInterrupt, not with the ValueError it reaches when left to run."""
    import subprocess
    import sys
    import textwrap

    code = textwrap.dedent("""
        import sys
        from deployfx import contact
        law = contact.ContactLaw("kelvin-voigt-hertz", K=1e-300, n=1.5, D=1e3)
        print("started", flush=True)
        contact.impact(law, 1.0, 1.0)
        print("finished")
    """)
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == "started"
        time.sleep(0.5)
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=120)
    finally:
        p.kill()
        p.communicate()
    assert "KeyboardInterrupt" in err and "finished" not in out, err[-2000:]


def test_a_huge_mass_gives_a_finite_peak_force_matching_hertz():
    """impact(law, 1e300, 1.0).peak_force was inf (the parabolic refinement overflowed). The
    undamped Hertz impact has the closed form (Johnson, Contact Mechanics, 1985, Sec. 11.4):
    delta_max = ((n + 1) m v0^2 / (2 K))^(1/(n+1)), F_max = K delta_max^n, restitution 1."""
    K, n, m, v0 = 1e7, 1.5, 1e300, 1.0
    r = contact.impact(contact.ContactLaw("kelvin-voigt-hertz", K=K, n=n), m, v0)
    delta = ((n + 1) * m * v0 ** 2 / (2 * K)) ** (1 / (n + 1))
    assert math.isfinite(r.peak_force) and math.isfinite(r.energy_lost)
    assert r.max_penetration == pytest.approx(delta, rel=1e-9)
    assert r.peak_force == pytest.approx(K * delta ** n, rel=1e-9)
    assert r.restitution == pytest.approx(1.0, abs=1e-9)


def test_an_impact_step_below_round_off_is_refused():
    """Found by the fuzzer: dt_s = 1e-9 s on a 1e-2 s contact ran 1e7 recorded steps (bounded,
    but minutes); below T / 1e5 a smaller step only adds round-off."""
    law = contact.ContactLaw("flores", K=1e4, n=2.37, e=0.99999)
    T = contact.impact_time_scale(law, 0.005, 0.0017)
    with pytest.raises(ValueError, match=r"impact\.dt = .* in \[T/1e5, T/10\]"):
        contact.impact(law, 0.005, 0.0017, dt_s=T * 1e-7)


def test_an_impact_beyond_the_doubles_is_a_clear_error():
    law = contact.ContactLaw("kelvin-voigt-hertz", K=1e7, n=1.5)
    with pytest.raises(ValueError, match="impact.mass"):
        contact.impact(law, 1e300, 1e200)  # m v0^2 / 2 = 5e699 J


# ------------------------------------------------------------------------------------------------
# Silent inf/NaN

IM6 = paper2016.IM6_SC1081


@pytest.mark.parametrize("plies, name", [
    ([dfx.Ply(IM6, 1e200, 0.0)], r"plies\[0\]\.thickness = 1e\+200"),
    ([dfx.Ply(IM6, 1e-3, 0.0), dfx.Ply(IM6, 1e-300, 0.0)], r"plies\[1\]\.thickness = 1e-300"),
])
def test_laminates_of_extreme_thickness_are_refused(plies, name):
    """A ply of 1e200 m gave inf D (h^3), one of 1e-300 m a zero stiffness contribution."""
    with pytest.raises(ValueError, match=name):
        dfx.Laminate(plies)


def test_an_extreme_ply_angle_is_reduced_to_one_turn():
    """angle_deg = 1.7e308 gave NaN A, B, D (angle * pi overflowed to inf, cos(inf) = NaN). The
    stiffness is 360-degree periodic, so it equals that of math.fmod(angle, 360) (exact)."""
    angle = 1.7e308
    a = dfx.Laminate([dfx.Ply(IM6, 1e-3, angle)])
    b = dfx.Laminate([dfx.Ply(IM6, 1e-3, math.fmod(angle, 360.0))])
    for name in ("A", "B", "D", "As"):
        assert np.all(np.isfinite(getattr(a, name)))
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


@pytest.fixture(scope="module")
def plate():
    return paper2016.appendage_plate(2, 3, 2)


def test_shell_model_loads_and_displacements_must_be_finite(plate):
    model = plate.model
    with pytest.raises(ValueError, match="pressure = nan"):
        model.pressure_load(float("nan"))
    load = np.zeros(model.num_dofs)
    load[5] = np.nan
    with pytest.raises(ValueError, match=r"load\[5\] = nan"):
        model.static(load, plate.fixed_dofs("CFFF"))
    with pytest.raises(ValueError, match=r"internal force .* displacements u are too large"):
        model.internal_force(np.full(model.num_dofs, 1e300))
    with pytest.raises(ValueError, match="pressure = inf"):
        plate.static(1.8e308, "CFFF")  # (1.8e308 is inf as a double)
    with pytest.raises(ValueError, match="deflection leaves the finite doubles: pressure = 1.7e"):
        plate.static(1.7e308, "CFFF")


def test_contact_and_friction_forces_refuse_nan_inputs():
    law = contact.ContactLaw("paper", K=1e9, n=1.5, D=1e3)
    with pytest.raises(ValueError, match="delta = nan"):
        law.force(float("nan"), 0.0)
    with pytest.raises(ValueError, match="delta_dot = nan"):
        law.force(np.array([1e-4, 2e-4]), np.array([0.0, np.nan]))
    with pytest.raises(ValueError, match="v_t = nan"):
        contact.Friction(0.3).force(float("nan"), 10.0)
    with pytest.raises(ValueError, match="F_n = inf"):
        contact.Friction(0.3).force(0.1, float("inf"))


# ------------------------------------------------------------------------------------------------
# Indices and types

def test_quad_node_indices_beyond_int32_are_refused_not_wrapped(plate):
    """2**32 + 3 became node 3 in the core's int32."""
    quads = np.array(plate.model.quads, dtype=np.int64)
    quads[1, 2] = 2 ** 32 + 3
    with pytest.raises(ValueError, match=r"quads\[1, 2\] = node 4294967299 is out of range"):
        dfx.ShellModel(plate.model.nodes, quads, plate.laminate)


def test_fixed_dofs_must_be_integers(plate):
    """fixed_dofs=[1.5] became dof 1."""
    scene = dfx.Scene().set_base(100.0, 10.0).set_hinge(point=(0.1, 0.0, 0.0), axis=(0.0, 1.0, 0.0))
    with pytest.raises(TypeError, match=r"fixed_dofs\[...\] must be an integer, got float 1.5"):
        scene.set_appendage(plate.model, [1.5], fidelity="linear")
    with pytest.raises(TypeError, match=r"fixed_dofs\[1\] must be an integer"):
        plate.model.modes(3, [0, 2.0])
    with pytest.raises(ValueError, match=r"fixed_dofs\[0\] = 72 is out of range"):
        plate.model.static(np.zeros(72), [72])


@pytest.mark.parametrize("override, name", [(dict(lock="no"), "lock"), (dict(nx=4.5), "nx"),
                                            (dict(body_mass="3000"), "body_mass"),
                                            (dict(damping=(0.7, "x")), r"damping\[1\]"),
                                            (dict(contact=1e9), "contact"),
                                            (dict(derivative_modes=2.0), "derivative_modes")])
def test_paper2016_parameters_are_type_checked(override, name):
    """paper2016(lock='no') turned the lock on (a non-empty string is true)."""
    with pytest.raises(TypeError, match=rf"Paper2016Parameters\.{name}"):
        scenes.paper2016(2, "linear", **override)


def test_a_reduced_appendage_left_free_to_move_is_a_clear_error(plate):
    """Found by the fuzzer: a reduced appendage clamped at one dof only raised RuntimeError
    ('the clamped stiffness is singular') from compile(); it is bad input, named."""
    scene = (dfx.Scene().set_base(100.0, 10.0)
             .set_hinge(point=(0.1, 0.0, 0.0), axis=(0.0, 1.0, 0.0), tau0=1.0))
    scene.set_appendage(plate.model, [15], fidelity="reduced-linear", modes=2)
    with pytest.raises(ValueError, match="fixed_dofs leave the panel free to move as a rigid body"):
        scene.compile()
