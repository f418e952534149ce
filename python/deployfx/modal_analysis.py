"""Modes about a state: the equations of motion linearised about (q, v, t), their eigenvalues as
frequencies (Hz) and damping ratios, and the mode shapes (``Model.modes``; docs/modes.md).

The engine's residual r(q, v, a, t) = 0 is linearised about a state on the coordinates that are
unknowns of the model (``Model.layout``: a free base's six, the undriven hinge angles, the elastic
coordinates; a prescribed hinge has no coordinate, so its angle is held at theta(t)):

    M dv' + C dv + K dq = 0,   dq' = dv + G dq,
    M = dr/da, C = dr/dv, K = dr/dq (along the base's retraction R_WB exp(dpsi)),

with G = -[w_B]x on a free base's attitude block (the retraction's kinematics, dpsi' = dw -
w x dpsi; zero elsewhere). In state space, [[G, I], [-K, -C]] z = lambda [[I, 0], [0, M]] z,
solved through the shifted inverse (``SHIFT``), which gives the low modes to round-off however
stiff the highest: dense, or on large models Arnoldi for the eigenvalues nearest the shift. A mode is an eigenvalue lambda with Im >= 0 (its conjugate is the
same mode): natural frequency |lambda| / 2 pi, damping ratio -Re lambda / |lambda|, damped
frequency |Im lambda| / 2 pi; the shape is the dq part of z, in the velocity coordinates.

Rigid-body modes. A free base at rest (its rows and columns of C and K vanish: no velocity, no
acceleration) is condensed exactly: zero total momentum, dv_b = -M_bb^-1 M_br dv_r, leaving the
free-floating mass M_rr - M_rb M_bb^-1 M_br on the hinge and elastic coordinates; its six
rigid-body modes (three translations, three rotations) never enter, and every shape carries the
base's counter-motion. A free base in motion is solved whole, and its six rigid-body modes are
the twelve state eigenvalues nearest zero, left out. Any other mode with |lambda| / 2 pi below
``zero_hz`` (a hinge that nothing holds) is left out too; ``num_rigid`` counts them all.

The lock is linearised as it stands, with the history a run has there (a run's sample: its
latch states, its impact records' contacts in progress, a groove's latch pin followed through
the samples; a given state: the walls the pin penetrates; an equilibrium: an active set of the
walls penetrated by more than ``TOUCH``): each wall in contact contributes its law's tangent,
r_pin^2 dF/ddelta to the hinge stiffness and r_pin^2 dF/ddelta' to its damping (friction: the
regularised law's slope at the slip rate, steep at rest); an open wall nothing. A latched pin
that floats in its clearance leaves the hinge its spring (k_theta) only, or nothing: a zero mode.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np

from ._checks import as_float, as_int, finite_vector
from ._modal_locks import TOUCH, _Locks, _locks, _set_locks, _walls

__all__ = ["Modes", "modes", "relative_equilibrium", "SHIFT", "TOUCH"]


@dataclass(frozen=True, eq=False)
class Modes:
    """The lowest modes of a model linearised about one state (:meth:`deployfx.Model.modes`).

    Arrays are per mode, in ascending natural frequency; ``shapes`` is (num_velocities, n), complex,
    in the model's velocity coordinates (``Model.layout``), each scaled so that its largest entry
    is 1 (real)."""

    eigenvalues: np.ndarray = field(repr=False)      #: lambda (rad/s), Im >= 0
    frequencies_hz: np.ndarray                       #: natural frequency |lambda| / 2 pi (Hz)
    damping_ratios: np.ndarray                       #: -Re lambda / |lambda| (1: a real, decaying root; < 0 unstable)
    shapes: np.ndarray = field(repr=False)           #: (num_velocities, n) complex
    q: np.ndarray = field(repr=False)                #: the state linearised about: positions,
    v: np.ndarray = field(repr=False)                #: velocities,
    t: float                                         #: and time (s)
    equilibrium: bool             #: whether q (and v) were moved to the relative equilibrium
    num_rigid: int                #: rigid-body (zero) modes left out (6 for a free base, plus zero hinges)
    model: Any = field(repr=False, default=None)

    @property
    def damped_frequencies_hz(self) -> np.ndarray:
        """|Im lambda| / 2 pi (Hz): the frequency the mode rings at."""
        return np.abs(self.eigenvalues.imag) / (2 * np.pi)

    def __len__(self) -> int:
        return len(self.eigenvalues)

    def mesh_shapes(self, hinge: Optional[int] = None) -> np.ndarray:
        """Hinge ``hinge``'s panel: each mode's elastic mesh displacements (n, 6 nodes), real part
        (m and rad per unit shape, the panel frame C_k's axes; zeros for a rigid panel), ready for
        drawing or export (e.g. as point data of its ShellModel's quads). A shape s of the
        elastic coordinates moves the mesh by D G s: D the displacement map, G the
        :meth:`~deployfx.Model.panel_tangent` at the state linearised about (the identity unless
        the panel is on the quadratic manifold)."""
        m = self.model
        k = m._hinge(hinge, panel=True)
        lay = m.core.layout(k)
        n_el = lay["num_elastic"]
        if n_el == 0:
            return np.zeros((len(self), m.shells[k].num_dofs))
        s = self.shapes[lay["iv_elastic"]:lay["iv_elastic"] + n_el].real
        if m.fidelities[k].slaved:
            s = m.panel_tangent(self.q, k) @ s
        return (m.core.displacement_map(k) @ s).T

    def world_shapes(self, hinge: Optional[int] = None) -> np.ndarray:
        """Hinge ``hinge``'s panel nodes' motion in W per unit shape, (n, nodes, 3), real part: the
        bodies' motion (base, hinges) and the elastic one together, the linearisation of the
        engine's kinematics (``Model.world_points``) along each shape by central differences
        (step 1e-6 of the shape's largest entry: exact to 1e-12 of it)."""
        m = self.model
        k = m._hinge(hinge, panel=True)
        eps = 1e-6
        out = np.zeros((len(self), m.shells[k].num_dofs // 6, 3))
        for j in range(len(self)):
            dq = eps * self.shapes[:, j].real
            ends = np.stack([m.core.retract(self.q, dq), m.core.retract(self.q, -dq)])
            X = m.world_points(ends, k, t=np.full(2, self.t))
            out[j] = (X[0] - X[1]) / (2 * eps)
        return out

    def hinge_shapes(self) -> np.ndarray:
        """Each mode's undriven hinge angles (n, H), real part (rad per unit shape; 0 for a
        prescribed hinge)."""
        out = np.zeros((len(self), self.model.num_hinges))
        for k in range(self.model.num_hinges):
            i = self.model.core.layout(k)["iv_theta"]
            if i >= 0:
                out[:, k] = self.shapes[i].real
        return out


# ------------------------------------------------------------------------------------- state

def _given_state(model, q, v) -> tuple[np.ndarray, np.ndarray]:
    """A given state's (q, v) as float arrays of the model's sizes (v None: at rest), or
    ValueError naming q or v."""
    q = finite_vector("q", q, model.num_positions)
    v = np.zeros(model.num_velocities) if v is None else finite_vector("v", v, model.num_velocities)
    return q, v

def _state_from(model, result, time, q, v, t):
    """(q, v, t, sample index or None) from a result at ``time`` or from the given q, v, t."""
    if result is not None:
        from .results import Result

        if not isinstance(result, Result):
            raise TypeError(f"result must be a deployfx.Result (a run of this model), got {type(result).__name__}")
        if q is not None or v is not None or t is not None:
            raise ValueError("give either result= and time=, or q= (v=, t=), not both")
        if time is None:
            raise ValueError("time is required with result= (s, within the run)")
        time = as_float("time", time)
        ts = np.asarray(result.t, dtype=float)
        if "q" not in result or "v" not in result:
            raise ValueError("result has no q, v series: it was not recorded by Model.simulate")
        if not len(ts) or not (ts[0] <= time <= ts[-1]):
            span = f"[{ts[0]:g}, {ts[-1]:g}]" if len(ts) else "(empty)"
            raise ValueError(f"time = {time!r} is out of range: must be within the result's {span} s")
        i = int(np.argmin(np.abs(ts - time)))  # the nearest recorded sample
        Q, V = np.asarray(result["q"], dtype=float), np.asarray(result["v"], dtype=float)
        if Q.ndim != 2 or Q.shape[1] != model.num_positions or V.shape[1:] != (model.num_velocities,):
            raise ValueError(f"result's q, v have shapes {Q.shape}, {V.shape}: not a run of this model "
                             f"({model.num_positions} positions, {model.num_velocities} velocities)")
        return Q[i].copy(), V[i].copy(), float(ts[i]), i
    if time is not None:
        raise ValueError("time is given without result=: pass result= (a run of this model), or t=")
    if q is None:
        raise ValueError("give result= and time=, or the state q= (v=, t=)")
    q, v = _given_state(model, q, v)
    t = 0.0 if t is None else as_float("t", t)
    if not np.isfinite(t):
        raise ValueError(f"t = {t!r} is out of range: must be finite (s)")
    return q.copy(), v.copy(), t, None


# ------------------------------------------------------------------------------- equilibrium
def _relative(model) -> np.ndarray:
    """The velocity indices of the hinge angles and elastic coordinates (not the base's)."""
    return np.arange(6 if model.base_free else 0, model.num_velocities)


def relative_equilibrium(model, q, t: float = 0.0, *, v=None, tol: float = 1e-12,
                         max_iter: int = 50) -> tuple[np.ndarray, np.ndarray]:
    """The relative equilibrium (q, v) near the state (``q``, ``v`` default 0) at time ``t`` (s),
    as ``Model.modes(..., equilibrium=True)`` finds it: every undriven hinge and elastic velocity
    and acceleration zero, the driven hinges moving as prescribed at t (a steady spin once their
    ramp is over), a free base's pose held and its velocity the rigid motion that carries the
    state's momentum [P; H] (zero momentum: at rest; a spinning spacecraft keeps its spin);
    Newton on r(q, v, 0, t) = 0 over the hinge angles and elastic coordinates until the step is
    below ``tol`` of the coordinates. The locks' walls form an active set: Newton with the walls
    in contact at the start, then again with those the pin penetrates by more than ``TOUCH`` at
    its root, until the set holds. A free base must then be unloaded (its rows of r vanish at zero
    acceleration: at rest, or spinning steadily about a principal axis), else ValueError."""
    q, v = _given_state(model, q, v)
    t = as_float("t", t)
    return _relative_equilibrium(model, q, v, t, model.make_data(), _locks(model, q, None, 0, t), tol, max_iter)


def _relative_equilibrium(model, q, v, t, data, locks: _Locks, tol, max_iter):
    zero = np.zeros(model.num_velocities)
    momentum = None
    if model.base_free:
        momentum = model.momentum(q, v, t=t, data=data)
        # A run from rest conserves zero momentum to round-off: zero it, so that the base rests.
        carried = np.abs(model.momentum_jacobian(q, v, 1.0, 0.0, data=data)) @ np.abs(v)
        if np.all(np.abs(momentum) <= 1e-9 * carried.max()):
            momentum = np.zeros(6)
    by_penetration = dataclasses.replace(locks, result=None)
    walls = _walls(model, q, zero, locks)
    seen = []
    while True:
        _set_locks(model, data, q, zero, walls, locks)
        q, v, force = _newton(model, q, t, data, momentum, tol, max_iter)
        settled = _walls(model, q, zero, by_penetration, TOUCH)
        if settled == walls:
            break
        if settled in seen:
            raise ValueError(f"no equilibrium found near the state at t = {t:g} s: the lock's walls cycle "
                             f"between {walls} and {settled} (hinge: (latched, stop, latch) or a groove's "
                             f"(support, closed facets))")
        seen.append(walls)
        walls = settled
    if model.base_free:
        r = model.residual(q, v, zero, t, data=data)
        scale = max(force, 1.0, float(np.abs(momentum[3:]).max() * np.abs(v[3:6]).max()))
        if np.abs(r[:6]).max() > 1e-8 * scale:
            raise ValueError(f"no relative equilibrium at t = {t:g} s: the free base is loaded (|r_base| = "
                             f"{np.abs(r[:6]).max():.3g}): a prescribed hinge spinning or accelerating on a free "
                             f"base, or the whole tumbling (spinning about no principal axis)")
    return q, v


def _carry(model, q, t, data, momentum) -> np.ndarray:
    """v with the hinge and elastic rates zero and a free base's (v_W, w_B) the rigid motion that
    carries ``momentum`` ([P; H] about W's origin; the driven hinges' share from t): Pi is linear
    in v, Pi(q, v) = Pi(q, 0) + dPi/dv v."""
    v = np.zeros(model.num_velocities)
    if momentum is None:
        return v
    J = model.momentum_jacobian(q, v, 1.0, 0.0, data=data)[:, :6]
    v[:6] = np.linalg.solve(J, momentum - model.momentum(q, v, t=t, data=data))
    return v


def _newton(model, q, t, data, momentum, tol, max_iter):
    """Newton on the relative rows of r(q, v, 0, t) under data's lock histories, v carrying the
    free base's ``momentum`` at each iterate: (q, v, the largest residual entry at the start)."""
    rel = _relative(model)
    nv = model.num_velocities
    zero = np.zeros(nv)
    q = q.copy()
    force = None
    for _ in range(max_iter):
        v = _carry(model, q, t, data, momentum)
        r = model.residual(q, v, zero, t, data=data)
        force = np.abs(r).max() if force is None else force
        if len(rel) == 0:
            return q, v, force
        Krr = model.newton_matrix(q, v, zero, t, 0.0, 0.0, 1.0, data=data)[np.ix_(rel, rel)]
        try:
            dq_rel = np.linalg.solve(Krr, -r[rel])
            ok = np.all(np.isfinite(dq_rel)) and np.abs(Krr @ dq_rel + r[rel]).max() <= 1e-8 * np.abs(r[rel]).max()
        except np.linalg.LinAlgError:
            ok = False
        if not ok:  # a coordinate nothing holds (a pin floating in its play): the least-squares step
            dq_rel = np.linalg.lstsq(Krr, -r[rel], rcond=1e-14)[0]
        dq = np.zeros(nv)
        dq[rel] = dq_rel
        q = model.core.retract(q, dq)
        if np.abs(dq_rel).max() <= tol * max(1.0, np.abs(q).max()):
            return q, _carry(model, q, t, data, momentum), force
    raise ValueError(f"no equilibrium found near the state at t = {t:g} s: Newton did not converge in "
                     f"{max_iter} iterations (|r| = {np.abs(r[rel]).max():.3g})")


# ---------------------------------------------------------------------------------- modes
def modes(model, n: int, *, result=None, time: Optional[float] = None, q=None, v=None,
          t: Optional[float] = None, equilibrium: bool = False, data=None, zero_hz: float = 1e-3) -> Modes:
    """The implementation of :meth:`deployfx.Model.modes` (see there and the module docstring)."""
    n = as_int("n", n)
    if n < 1:
        raise ValueError(f"n = {n} is out of range: must be >= 1 (the number of modes)")
    zero_hz = as_float("zero_hz", zero_hz)
    if not (np.isfinite(zero_hz) and zero_hz >= 0):
        raise ValueError(f"zero_hz = {zero_hz!r} is out of range: must be finite and >= 0 (Hz)")
    if not isinstance(equilibrium, (bool, np.bool_)):
        raise TypeError(f"equilibrium must be True or False, got {equilibrium!r}")
    q, v, t, i = _state_from(model, result, time, q, v, t)
    own = data is None
    data = model.make_data() if own else data
    nv = model.num_velocities
    locks = _locks(model, q, result, i, t) if own else None
    if equilibrium:
        if not own:
            raise ValueError("equilibrium=True switches the locks' walls itself: leave data=None")
        q, v = _relative_equilibrium(model, q, v, t, data, locks, 1e-12, 50)
        a = np.zeros(nv)
    else:
        if own:
            _set_locks(model, data, q, v, _walls(model, q, v, locks), locks)
        # The accelerations the equations of motion give at the state: r is affine in a.
        M = model.newton_matrix(q, v, np.zeros(nv), t, 1.0, 0.0, 0.0, data=data)
        a = np.linalg.solve(M, -model.residual(q, v, np.zeros(nv), t, data=data))
    M, C, K = (model.newton_matrix(q, v, a, t, *c, data=data) for c in ((1, 0, 0), (0, 1, 0), (0, 0, 1)))
    want = 2 * n + 16  # state roots near the shift (a large model: Arnoldi), doubled until n modes are sure
    while True:
        lam, X, rigid, radius = _solve(model, M, C, K, v, want)
        zero = np.abs(lam) < 2 * np.pi * zero_hz
        rigid += (int(np.count_nonzero(zero)) + 1) // 2  # a zero mode is a (Jordan) pair of state roots
        lam, X = _upper(lam[~zero], X[:, ~zero])
        inside = np.abs(lam) < radius  # every mode below the radius was found
        if np.count_nonzero(inside) >= n or radius == np.inf:
            lam, X = lam[inside], X[:, inside]
            break
        want *= 2  # at most until the whole spectrum (then radius = inf)
    if n > len(lam):
        raise ValueError(f"n = {n} is out of range: the linearised model has {len(lam)} modes besides its "
                         f"{rigid} rigid-body ones")
    order = np.argsort(np.abs(lam), kind="stable")[:n]
    lam, X = lam[order], X[:, order]
    big = np.argmax(np.abs(X), axis=0)
    X = X / X[big, np.arange(X.shape[1])]
    w = np.abs(lam)
    arrays = {"eigenvalues": lam, "frequencies_hz": w / (2 * np.pi), "damping_ratios": -lam.real / w + 0.0, "shapes": X,
              "q": q, "v": v}
    for a in arrays.values():
        a.setflags(write=False)  # a frozen result: its arrays too
    return Modes(**arrays, t=t, equilibrium=bool(equilibrium), num_rigid=rigid, model=model)



def _solve(model, M, C, K, v, want):
    """State eigenvalues (both of each conjugate pair), their dq shapes (nv, m), the number of
    rigid-body modes left out here, and the radius within which every eigenvalue is among them
    (inf: all were computed). ``want``: how many state eigenvalues near the shift (None: all)."""
    nv = len(M)
    if not model.base_free:
        lam, X, radius = _state_space(M, C, K, np.zeros((nv, nv)), want)
        return lam, X, 0, radius
    b, r = np.arange(6), _relative(model)
    norm = max(np.abs(K).max(), np.abs(C).max(), 1e-300)
    couple = max(np.abs(K[b]).max(), np.abs(K[:, b]).max(), np.abs(C[b]).max(), np.abs(C[:, b]).max())
    if couple <= 1e-10 * norm and not np.any(v[b]):
        # At rest: zero total momentum, dv_b = -M_bb^-1 M_br dv_r (exact; six rigid modes out).
        Mbb_Mbr = np.linalg.solve(M[np.ix_(b, b)], M[np.ix_(b, r)])
        Mr = M[np.ix_(r, r)] - M[np.ix_(r, b)] @ Mbb_Mbr
        lam, Xr, radius = _state_space(Mr, C[np.ix_(r, r)], K[np.ix_(r, r)], np.zeros((len(r), len(r))), want)
        X = np.zeros((nv, Xr.shape[1]), dtype=complex)
        X[b], X[r] = -Mbb_Mbr @ Xr, Xr
        return lam, X, 6, radius
    # In motion: the six rigid-body modes are the twelve state eigenvalues nearest zero (exact
    # zeros of translation and of the conserved momenta, the rest of the order of the base's rate).
    G = np.zeros((nv, nv))
    G[3:6, 3:6] = -_skew(v[3:6])  # dpsi' = dw - w x dpsi
    lam, X, radius = _state_space(M, C, K, G, None if want is None else want + 12)
    keep = np.argsort(np.abs(lam), kind="stable")[12:]
    return lam[keep], X[:, keep], 6, radius


#: The shift (rad/s) of the inverse iteration: the eigenvalues nearest it come out to round-off
#: relative to themselves, not to the stiffest mode's (a shell's drilling and membrane modes lie
#: six orders of magnitude above its first bending mode); real and negative, so no undamped or
#: lightly damped mode sits on it, and zero modes stay finite (mu = -1/sigma).
SHIFT = -1.0
#: State sizes (2 num_velocities) above which only the eigenvalues nearest the shift are computed,
#: by Arnoldi (ARPACK) on the same shifted inverse, factored once (dense LU); all of them below.
_ARNOLDI_ABOVE = 800


def _state_space(M, C, K, G, want=None):
    """Eigenvalues of A z = lambda B z, A = [[G, I], [-K, -C]], B = diag(I, M), the dq parts of z,
    and the radius within which every eigenvalue is among those returned: from the shifted
    inverse (A - sigma B)^-1 B z = mu z, lambda = sigma + 1/mu; all 2 n (radius inf), or for a
    large problem the ``want`` nearest sigma (a disc |lambda - sigma| <= rho holds every
    eigenvalue with |lambda| <= rho - |sigma|)."""
    n = len(M)
    I, Z = np.eye(n), np.zeros((n, n))
    A = np.block([[G - SHIFT * I, I], [-K, -C - SHIFT * M]])
    B = np.block([[I, Z], [Z, M]])
    if want is None or 2 * n <= _ARNOLDI_ABOVE or want >= 2 * n - 2:
        mu, V = np.linalg.eig(np.linalg.solve(A, B))
        return SHIFT + 1.0 / mu, V[:n], np.inf
    import scipy.linalg
    import scipy.sparse.linalg

    lu = scipy.linalg.lu_factor(A, check_finite=False)
    op = scipy.sparse.linalg.LinearOperator((2 * n, 2 * n), dtype=float,
                                            matvec=lambda x: scipy.linalg.lu_solve(lu, B @ x, check_finite=False))
    try:
        mu, V = scipy.sparse.linalg.eigs(op, k=want, which="LM", ncv=min(2 * n, 3 * want + 20))
    except scipy.sparse.linalg.ArpackNoConvergence:  # rare: the dense solve instead
        return _state_space(M, C, K, G, None)
    lam = SHIFT + 1.0 / mu
    return lam, V[:n], float(np.abs(lam - SHIFT).max() - abs(SHIFT))


def _upper(lam, X):
    """One of each conjugate pair (Im >= 0), real roots as real."""
    tiny = 1e-9 * np.maximum(np.abs(lam), 1.0)
    ok = lam.imag >= -tiny
    lam, X = lam[ok], X[:, ok]
    return np.where(np.abs(lam.imag) <= tiny[ok], lam.real + 0j, lam), X


def _skew(w) -> np.ndarray:
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])
