"""deployfx against Exudyn on one equal model: the paper's reduced panel (You et al. 2016, lay-up 2).

Issue 27's side-by-side. One run builds the same model in both codes, runs it with the lock and
without it, and prints both codes' results and CPU times (``time.process_time``, one core: both
codes step on one thread) with their ratios.

The model, built once by deployfx (``scenes.paper2016(2, "reduced-linear", modes=10)``) and handed
to Exudyn as numbers, so both integrate the same equations:

- the panel (15 x 10 shell mesh by default, ``--mesh``) reduced to deployfx's Ritz basis, exported
  (``Model.basis``): 10 clamped (Craig-Bampton fixed-interface) modes plus the static corrections
  for the root's acceleration loads, 15 vectors, M-orthonormal. Exudyn's
  ``ObjectFFRFreducedOrder`` gets that basis's translation rows as its mode basis, the reduced mass
  and stiffness ``Psi^T M Psi`` (= I) and ``Psi^T K Psi`` of the full shell matrices, and the
  floating-frame inertia terms from the translation block of the consistent mass matrix (its
  ``FEMinterface`` / ``ObjectFFRFreducedOrderInterface``, the nodal-based FFRF of Zwoelfer &
  Gerstmayr); mass-proportional damping alpha_M = 0.7 1/s on the modal coordinates in both;
  linear strain, no geometric stiffness in both (deployfx's ``reduced-linear`` fidelity);
- a free-floating base (3000 kg, 500 kg m^2) with the 2 kg yoke merged into it (one rigid body
  in Exudyn; a rigid part on the base in deployfx), the hinge a revolute joint on the base at
  (0.83, 0, 0) about its y axis, the panel's floating frame on the hinge axis, the hinge fitting
  (0.02 kg m^2, isotropic) added to the panel frame's inertia in Exudyn;
- the spring tau = tau0 - k_theta theta (7.2 N m, 4.58 N m/rad) and the stop-and-latch lock of
  the paper scene's default (pin at r = 0.03 m, 0.2 mm clearance, normal force
  K delta^1.5 + D delta' with K = 3.16e10 N/m^1.5, D = 1e6 N s/m, Coulomb friction mu = 0.25
  regularised by tanh(v / 1e-4 m/s) along the pin's path), in Exudyn as a symbolic user function
  of a ``ObjectConnectorTorsionalSpringDamper`` (the latch wall armed once the hinge has passed it,
  from a pre-step function);
- generalized-alpha rho_inf = 0.8, output step dt = 0.01 s, Newton on the full Jacobian.

What differs (by design of each code, not of the model):

- the contact: deployfx locates each wall's contact onset and release as events and steps through
  the impact on the contact's own time scale (an active set: docs/engine-design.md); Exudyn steps
  at dt with the same force law clamped at zero (``max(0, ...)``) and, when Newton fails, its
  automatic step reduction. Its lock time is the first output step in contact, so it is
  quantised to dt, and its impact is not resolved: the results after the lock differ, and that
  difference is the cost of the events deployfx pays for (without the lock both agree);
- coordinates: deployfx a quaternion base, the hinge angle and the 15 modal coordinates (22
  velocities, the momentum rows solved in integrated form); Exudyn Euler parameters for the base and
  the panel frame and a revolute joint's five Lagrange multipliers (two bodies of 7 + 22 ODE2
  coordinates with two Euler-parameter constraints);
- rotary inertia through the thickness: deployfx's shape integrals include it (1e-6 of the
  panel's inertia), the nodal FFRF only the mid-surface's translations (the reduced mass matrix
  includes it in both);
- Newton, each code's defaults: deployfx full Newton (a fresh or kept matrix by its contraction
  test), converged to 1e-10 of the accelerations; Exudyn modified Newton (its Jacobian kept while
  the iterations contract), relative tolerance 1e-8, and its "discontinuous iteration" after each
  step (its check of switching conditions: one a step here).

Without the lock the two runs agree to 1e-3 mm in node E and 1e-3 deg in the hinge angle over
3 s (``max|dE|``, ``max|dangle|``: Exudyn's largest difference from deployfx), so they integrate
the same equations; with it they differ by the contact's treatment above.

CPU times exclude building either model (deployfx's compile: the mesh and the basis; Exudyn's
``Assemble``); each is the best of ``--repeat`` runs of the whole solve call (deployfx:
``simulate``, its series included; Exudyn: ``SolveDynamic`` with sensors storing the hinge angle
and the modal coordinates in memory). No assertions: speed is measured here, not tested.

    python bench/vs_exudyn.py [--mesh 15x10] [--modes 10] [--t-end 3] [--repeat 5]
"""
from __future__ import annotations

import one_thread  # noqa: F401  (first: one BLAS thread for CPU times)

import argparse
import sys
import time

import numpy as np
import scipy.sparse as sp

import deployfx as dfx

try:
    import exudyn as exu
    import exudyn.itemInterface as eii
    from exudyn.advancedUtilities import CreateSymbolicUserFunction
    from exudyn.FEM import FEMinterface, ObjectFFRFreducedOrderInterface
except ImportError:  # the bench extra: pip install "deployfx[bench]"
    exu = None

RHO = 0.8


def scene(nx: int, ny: int, modes: int, lock: bool):
    # The stop-and-latch walls: the lock Exudyn's user function models (the scene's default groove
    # has a riding latch pin that a torsional stop cannot express).
    return dfx.scenes.paper2016(2, "reduced-linear", nx=nx, ny=ny, modes=modes, lock=lock,
                                lock_geometry="stop-latch")


def hinge_angle_at(t: np.ndarray, angle_deg: np.ndarray, when: float) -> float:
    return float(np.interp(when, t, angle_deg))


# ----------------------------------------------------------------------------------- deployfx
def run_deployfx(sc, t_end: float, dt: float, repeat: int) -> dict:
    best, r = (np.inf, None), None
    for _ in range(repeat):
        t0 = time.process_time()
        r = sc.simulate(t_end, dt, scheme=dfx.integrators.GeneralizedAlpha(RHO))
        best = min(best, (time.process_time() - t0, r.metadata["wall_time_s"]))
    s = r.summary()
    return {"cpu": best[0], "engine": best[1], "t": r.t,
            "angle": r.deployment_angle[:, 0], "node_E": r.node_E_deflection,
            "first_lock": s["first_lock_time_s"][0] if sc.parameters.lock else None,
            "steps": r.metadata["substeps"], "newton": int(np.sum(r.metadata["newton_iterations"]))}


# ------------------------------------------------------------------------------------- Exudyn
def _Ry(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _Rx(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def exudyn_model(sc, lock: bool):
    """The scene ``sc`` (a compiled paper2016 reduced-linear scene) as an Exudyn system: the
    MainSystem and what the runs read from it."""
    p = sc.parameters
    model = sc.model
    shell = model.shells[0]
    n_nodes = shell.num_dofs // 6
    trans = (6 * np.arange(n_nodes)[:, None] + np.arange(3)[None]).ravel()  # translation dofs
    Psi = model.basis(0)                          # (6 nodes x r), M-orthonormal
    M = shell.mass_matrix().tocsr()
    K = shell.stiffness_matrix().tocsr()

    # The panel in Exudyn's FEM interface: its nodes (in the panel frame C), the translation
    # block of the consistent mass matrix and the basis's translation rows (nodal FFRF).
    fem = FEMinterface()
    fem.nodes = {"Position": np.asarray(shell.nodes, dtype=float)}
    fem.massMatrix = sp.csr_matrix(M[trans][:, trans])
    fem.stiffnessMatrix = sp.csr_matrix(K[trans][:, trans])
    fem.modeBasis = {"matrix": np.ascontiguousarray(Psi[trans]), "type": "deployfx Ritz basis"}
    cms = ObjectFFRFreducedOrderInterface(fem)
    # deployfx's reduced matrices on all six dofs a node (rotary inertia and bending included).
    cms.massMatrixReduced = Psi.T @ (M @ Psi)
    cms.stiffnessMatrixReduced = Psi.T @ (K @ Psi)
    cms.massMatrixFFRFreduced[cms.nODE2rigid:, cms.nODE2rigid:] = cms.massMatrixReduced
    cms.inertiaLocal = cms.inertiaLocal + p.fitting_inertia * np.eye(3)  # the hinge fitting

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    # The base and the yoke as one rigid body (inertia about the base centroid, the node).
    m_b, m_y = p.body_mass, p.yoke_mass
    c_y = np.array([p.yoke_com_x, 0.0, 0.0])
    J = p.body_inertia * np.eye(3) + np.diag(p.yoke_inertia) + m_y * (c_y @ c_y * np.eye(3) - np.outer(c_y, c_y))
    com = m_y * c_y / (m_b + m_y)
    nBase = mbs.AddNode(eii.NodeRigidBodyEP(referenceCoordinates=[0, 0, 0, 1, 0, 0, 0]))
    oBase = mbs.AddObject(eii.ObjectRigidBody(mass=m_b + m_y, nodeNumber=nBase, centerOfMass=list(com),
                                              inertia=[J[0, 0], J[1, 1], J[2, 2], J[1, 2], J[0, 2], J[0, 1]]))
    # The panel: floating frame C at the hinge point, axes R_BC0 = Ry(-90 deg) stowed.
    hinge = np.array([p.hinge_x, 0.0, 0.0])
    R_BC0 = _Ry(-np.pi / 2)
    ffrf = cms.AddObjectFFRFreducedOrder(mbs, positionRef=list(hinge), rotationMatrixRef=R_BC0,
                                         massProportionalDamping=p.damping[0],
                                         stiffnessProportionalDamping=p.damping[1])
    # The hinge: joint z along the base's y axis, the same axis in C (R_BC0 keeps y).
    A0 = _Rx(-np.pi / 2)
    A1 = R_BC0.T @ A0
    mBase = mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=oBase, localHT=exu.HT(rotation=A0, translation=hinge)))
    mPanel = mbs.AddMarker(eii.MarkerNodeRigid(nodeNumber=ffrf["nRigidBody"], localHT=exu.HT(rotation=A1)))
    mbs.AddObject(eii.ObjectJointRevoluteZ(markerNumbers=[mBase, mPanel]))

    # Spring and lock: Exudyn's torque UF is the restoring torque (it acts as -UF on the angle).
    esym = exu.symbolic
    latched = esym.Real("latched", 0.0)
    L = p.contact
    r_pin, theta_lock = p.pin_radius, np.pi / 2
    theta_latch = theta_lock - p.clearance / r_pin
    mu, v_reg = p.friction.mu, p.friction.v_reg
    tau0, k_theta = p.tau0, p.k_theta

    def wall(delta, delta_dot):
        """A wall's normal force (N): the law while the pin is in (delta > 0), never pulling."""
        F = L.K * esym.pow(esym.max(delta, 0.0), L.n) + L.D * delta_dot
        return esym.IfThenElse(delta > 0.0, esym.max(F, esym.Real(0.0)), esym.Real(0.0))

    def torque(mbs, t, itemNumber, rotation, angularVelocity, stiffness, damping, offset):
        drive = tau0 - k_theta * rotation
        if lock:
            F_stop = wall(r_pin * (rotation - theta_lock), r_pin * angularVelocity)
            F_latch = latched * wall(r_pin * (theta_latch - rotation), -r_pin * angularVelocity)
            Fn = F_stop + F_latch
            friction = -mu * Fn * esym.tanh(r_pin * angularVelocity / v_reg)
            drive = drive - r_pin * F_stop + r_pin * F_latch + r_pin * friction
        return -drive

    oSpring = mbs.AddObject(eii.ObjectConnectorTorsionalSpringDamper(markerNumbers=[mBase, mPanel]))
    uf = CreateSymbolicUserFunction(mbs, torque, "springTorqueUserFunction", oSpring)
    mbs.SetObjectParameter(oSpring, "springTorqueUserFunction", uf)

    out = exu.OutputVariableType
    sAngle = mbs.AddSensor(eii.SensorObject(objectNumber=oSpring, outputVariableType=out.Rotation,
                                            storeInternal=True, writeToFile=False))
    sModal = mbs.AddSensor(eii.SensorNode(nodeNumber=ffrf["nGenericODE2"], outputVariableType=out.Coordinates,
                                          storeInternal=True, writeToFile=False))
    state = {"latched": False}

    def pre_step(mbs, t):
        # Arm the latch wall once the hinge has passed it (deployfx's latch history).
        if not state["latched"] and mbs.GetSensorValues(sAngle) >= theta_latch:
            state["latched"] = True
            latched.SetValue(1.0)
        return True

    if lock:
        mbs.SetPreStepUserFunction(pre_step)
    mbs.Assemble()
    node_E_row = Psi[6 * sc.node_E + 2]
    return {"SC": SC, "mbs": mbs, "sensors": (sAngle, sModal), "keep": (uf, latched, cms), "state": state,
            "node_E_row": node_E_row, "reset": lambda: (state.update(latched=False), latched.SetValue(0.0))}


def run_exudyn(sc, lock: bool, t_end: float, dt: float, repeat: int) -> dict:
    t0 = time.process_time()
    ex = exudyn_model(sc, lock)
    build = time.process_time() - t0
    mbs = ex["mbs"]
    ss = exu.SimulationSettings()
    ss.timeIntegration.endTime = t_end
    ss.timeIntegration.numberOfSteps = int(round(t_end / dt))
    ss.timeIntegration.generalizedAlpha.spectralRadius = RHO
    ss.timeIntegration.verboseMode = 0
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = dt
    ss.linearSolver.solverType = exu.LinearSolverType.EXUdense  # its default; 29 + 7 unknowns
    best = np.inf
    for _ in range(repeat):
        ex["reset"]()
        mbs.systemData.SetODE2Coordinates(mbs.systemData.GetODE2Coordinates(exu.ConfigurationType.Initial),
                                          exu.ConfigurationType.Current)
        t0 = time.process_time()
        ok = mbs.SolveDynamic(ss, solverType=exu.DynamicSolverType.GeneralizedAlpha)
        best = min(best, time.process_time() - t0)
    sAngle, sModal = ex["sensors"]
    a = mbs.GetSensorStoredData(sAngle)
    q = mbs.GetSensorStoredData(sModal)
    t = a[:, 0]
    angle = 90.0 + np.degrees(a[:, 1])
    node_E = q[:, 1:] @ ex["node_E_row"]
    first = None
    if lock:
        hit = np.nonzero(angle >= 180.0)[0]
        first = float(t[hit[0]]) if hit.size else None
    it = mbs.sys["dynamicSolver"].it
    info = {"steps": it.currentStepIndex, "newton": it.newtonStepsCount, "jacobians": it.newtonJacobiCount,
            "discontinuous": it.discontinuousIterationsCount}
    return {"cpu": best, "build": build, "t": t, "angle": angle, "node_E": node_E, "first_lock": first,
            "ok": ok, "info": info}


# ---------------------------------------------------------------------------------------- main
def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default="15x10", help="NXxNY (the paper's 15x10)")
    ap.add_argument("--modes", type=int, default=10, help="clamped modes of the Ritz basis")
    ap.add_argument("--t-end", type=float, default=3.0, help="simulated time (s): 3 or the paper's 30")
    ap.add_argument("--dt", type=float, default=0.01, help="output step (s)")
    ap.add_argument("--repeat", type=int, default=5, help="runs per code and case; the best CPU time is kept")
    args = ap.parse_args()
    if exu is None:
        print("bench/vs_exudyn.py: Exudyn is not installed; install the bench extra "
              "(pip install 'deployfx[bench]', or pip install exudyn) to run this comparison. Skipped.")
        return
    nx, ny = (int(x) for x in args.mesh.lower().split("x"))
    print(f"paper2016 lay-up 2, reduced-linear, {args.mesh} mesh, {args.modes} clamped modes + static "
          f"corrections; t_end = {args.t_end:g} s, dt = {args.dt:g} s, generalized-alpha rho_inf = {RHO}; "
          f"deployfx {dfx.__version__}, Exudyn {exu.__version__}; CPU s (time.process_time), "
          f"best of {args.repeat}")
    head = (f"{'lock':5s} {'code':8s} {'cpu s':>8s} {'angle 1s':>9s} {'angle 2s':>9s} {'1st lock s':>10s} "
            f"{'E at 2s mm':>10s} {'max|E| mm':>9s} {'dfx/exu':>8s} {'max|dE| mm':>10s} {'max|dangle|':>11s}")
    print(head)
    for lock in (True, False):
        sc = scene(nx, ny, args.modes, lock)
        d = run_deployfx(sc, args.t_end, args.dt, args.repeat)
        e = run_exudyn(sc, lock, args.t_end, args.dt, args.repeat)
        for name, r in (("deployfx", d), ("Exudyn", e)):
            lock_s = f"{r['first_lock']:10.4f}" if r["first_lock"] is not None else f"{'-':>10s}"
            ratio = f"{d['cpu'] / e['cpu']:8.2f}" if name == "deployfx" else f"{'':8s}"
            # Exudyn's row: its largest difference from deployfx over the run, at deployfx's outputs.
            diff = "" if name == "deployfx" else (
                f" {1e3 * np.abs(np.interp(d['t'], r['t'], r['node_E']) - d['node_E']).max():10.4f}"
                f" {np.abs(np.interp(d['t'], r['t'], r['angle']) - d['angle']).max():11.4f}")
            angles = [hinge_angle_at(r["t"], r["angle"], when) for when in (1.0, 2.0)]
            print(f"{('yes' if lock else 'no'):5s} {name:8s} {r['cpu']:8.4f} {angles[0]:9.4f} {angles[1]:9.4f} "
                  f"{lock_s} {1e3 * np.interp(2.0, r['t'], r['node_E']):10.4f} "
                  f"{1e3 * np.abs(r['node_E']).max():9.3f} {ratio}{diff}", flush=True)
        i = e["info"]
        print(f"      deployfx: engine {d['engine']:.4f} s (wall) of it, {d['steps']} steps, {d['newton']} "
              f"Newton iterations ({1e6 * d['cpu'] / d['newton']:.1f} us CPU each); Exudyn: {i['steps']} steps, "
              f"{i['newton']} Newton iterations ({1e6 * e['cpu'] / max(i['newton'], 1):.1f} us each), "
              f"{i['jacobians']} Jacobians, {i['discontinuous']} discontinuous iterations"
              f"{'' if e['ok'] else ', SOLVER FAILED'}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
