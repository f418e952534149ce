"""The compiled scene: one :class:`Model` for every scene (one hinge, a chain, a tree of two
wings), immutable and shareable between runs and threads; ``simulate`` runs it and returns a
:class:`~deployfx.results.Result` with one series vocabulary (documented in
:mod:`deployfx.results`).

A run's mutable state lives in a data object (``Model.make_data()``, the engine's
``multibody::Data``: lock histories, memos, the staged kinematics), one per run: several threads
may simulate one Model at once and get the same bits as serial runs.

Coordinates (``q``, ``v``): a free base's position r_W (m) and unit quaternion (w, x, y, z) of
R_WB (velocities v_W in W axes, w_B in B axes), the undriven hinges' angles (rad: the travel from
stowed) in hinge order, then each deforming panel's elastic coordinates in hinge order (its free
mesh dofs, m and rad, or its Ritz coordinates, kg^0.5 m; on the quadratic manifold its bending
Ritz coordinates, ``Model.panel_coordinates`` giving all of them): ``Model.layout(k)`` says where.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from time import gmtime, strftime
from typing import Callable, Mapping, Optional, Sequence, Union

import numpy as np

from . import _core, _node_rows, _run_record, impacts
from . import checkpoint as _checkpoint
from ._checks import finite_vector
from ._node_rows import node_translations
from ._run import _run_arguments, _run_result, _timed_run, newton_tolerance_arg
from .integrators import GeneralizedAlpha
from .results import Result

__all__ = ["Model", "SERIES_UNITS"]

#: Units of the series every run records (see :mod:`deployfx.results` for their meaning); H is
#: the number of hinges.
SERIES_UNITS = {
    "t": "s",
    "deployment_angle": "deg", "deployment_rate": "deg/s", "spring_torque": "N m", "lock_force": "N",
    "lock_torque": "N m", "latched": "1", "hinge_force": "N", "hinge_moment": "N m", "strain_energy": "J",
    "tip_displacement": "m", "tip_deflection": "m",
    "body_attitude": "deg", "total_angular_momentum": "N m s", "body_angular_momentum": "N m s",
    "total_linear_momentum": "N s", "body_linear_momentum": "N s", "kinetic_energy": "J", "potential_energy": "J",
    "q": "m, rad, kg^0.5 m (base position and quaternion, hinge angles, elastic coordinates: Model.layout)",
    "v": "m/s, rad/s (base velocity in W, angular velocity in B, hinge rates, elastic rates)",
}


@functools.cache  # imported at the first run (deployfx imports this module first), then kept
def _version() -> str:
    from . import __version__

    return __version__


@dataclass(frozen=True, eq=False)
class Model:
    """A compiled scene (``Scene.compile()``): immutable, reusable for many runs, shareable
    between threads. ``links`` are the scene's hinges as compiled (:class:`~deployfx.specs.Link`)."""

    core: _core.Model = field(repr=False)
    base_free: bool
    links: tuple = field(repr=False)
    description: dict = field(default_factory=dict)
    #: Per hinge: the tip node of its panel (the node farthest from the hinge axis; among equals the
    #: one nearest the axis' foot, the free edge's middle), -1 without a panel.
    tip_nodes: tuple = ()
    #: Per hinge: the unit direction (C_k axes) in which the hinge's rotation moves the tip node;
    #: the tip deflection is the tip's elastic displacement along it (negative: lagging).
    tip_directions: tuple = field(default=(), repr=False)

    # ---------------------------------------------------------------------------- the scene
    @property
    def num_hinges(self) -> int:
        """The scene's hinges (H: the width of a run's per-hinge series)."""
        return len(self.links)

    @property
    def shells(self) -> tuple:
        """Per hinge: its panel's :class:`~deployfx.ShellModel` (nodes in C_k, m), or None."""
        return tuple(None if L.appendage is None else L.appendage.shell for L in self.links)

    @property
    def fidelities(self) -> tuple:
        """Per hinge: its panel's :class:`~deployfx.specs.Fidelity`, or None without a panel."""
        return tuple(None if L.appendage is None else L.appendage.fidelity for L in self.links)

    @property
    def deforming(self) -> tuple:
        """Per hinge: True if its body is a deforming panel (has elastic coordinates)."""
        return tuple(self.layout(k)["num_elastic"] > 0 for k in range(self.num_hinges))

    @property
    def locks(self) -> tuple:
        """Per hinge: True if it has a lock."""
        return tuple(L.lock is not None for L in self.links)

    @property
    def lock_play_deg(self) -> tuple:
        """Per hinge: its lock's free play once latched (deg), None without a lock."""
        return tuple(None if L.lock is None else L.lock.play_deg for L in self.links)

    @property
    def conservative(self) -> bool:
        """No prescribed hinge angle: nothing can add energy, so energy growth is a numerical
        failure and ``simulate`` reports it."""
        return all(L.hinge.spin_up is None for L in self.links)

    @property
    def num_positions(self) -> int:
        """The length of ``q`` (see the module docstring and :meth:`layout`)."""
        return self.core.num_positions

    @property
    def num_velocities(self) -> int:
        """The length of ``v`` (a free base's 6, the undriven hinges' rates, the elastic rates)."""
        return self.core.num_velocities

    def _hinge(self, hinge, panel: bool = False) -> int:
        if hinge is None:
            candidates = [k for k in range(self.num_hinges) if not panel or self.shells[k] is not None]
            if len(candidates) != 1:
                what = "panels" if panel else "hinges"
                raise ValueError(f"hinge is required: the model has {len(candidates)} {what} "
                                 f"({candidates if panel else self.num_hinges})")
            return candidates[0]
        if isinstance(hinge, bool) or not isinstance(hinge, (int, np.integer)):
            raise TypeError(f"hinge must be a hinge index (int), got {type(hinge).__name__}")
        if not 0 <= hinge < self.num_hinges:
            raise ValueError(f"hinge = {hinge} is out of range: must be in [0, {self.num_hinges - 1}]")
        if panel and self.shells[hinge] is None:
            raise ValueError(f"hinge = {hinge} carries no panel (Scene.set_appendage(..., hinge={hinge}))")
        return int(hinge)

    def layout(self, hinge: int) -> dict:
        """Hinge k's coordinates: ``parent`` (-1: the base), ``iq_theta``/``iv_theta`` (its angle in
        q and v; -1 when prescribed), ``num_elastic``, ``iq_elastic``/``iv_elastic`` (its panel's
        elastic coordinates), ``attachment_node`` (the parent panel's node it rides on, or -1)."""
        return self.core.layout(self._hinge(hinge))

    def basis(self, hinge: Optional[int] = None) -> Optional[np.ndarray]:
        """A reduced panel's Ritz basis, mesh dofs = ``basis @ eta`` ((6 nodes x r), M-orthonormal:
        eta in kg^0.5 m), eta its panel coordinates (:meth:`panel_coordinates`: its elastic
        coordinates, or on the quadratic manifold the r Ritz coordinates g(q) its bending ones
        give); None for any other body."""
        k = self._hinge(hinge, panel=True)
        return self.core.displacement_map(k) if self.fidelities[k].reduced else None

    def basis_info(self, hinge: Optional[int] = None) -> Optional[dict]:
        """A reduced panel's basis: ``modes``, ``static_corrections`` and ``modal_derivatives``
        proposed, the ``size`` kept and its Ritz values ``omega2`` ((rad/s)^2); None otherwise."""
        return self.core.basis_info(self._hinge(hinge, panel=True))

    # ------------------------------------------------------------------- post-processing q
    def _q(self, q) -> np.ndarray:
        q = np.atleast_2d(np.asarray(q, dtype=float))
        if q.ndim != 2 or q.shape[1] != self.num_positions:
            raise ValueError(f"q has shape {q.shape}: this model has {self.num_positions} coordinates per sample "
                             f"(was it recorded by another model?)")
        return q

    def _elastic(self, q: np.ndarray, k: int) -> np.ndarray:
        """Hinge k's elastic coordinates: columns of the checked (n, num_positions) ``q``."""
        lay = self.core.layout(k)
        return q[:, lay["iq_elastic"]:lay["iq_elastic"] + lay["num_elastic"]]

    def _lift(self, k: int, q_el: np.ndarray) -> np.ndarray:
        """Hinge k's panel coordinates from its elastic ones ``q_el`` (n, num_elastic): the one
        place they are turned into each other (:meth:`panel_coordinates`, the node series of
        _node_rows). The elastic coordinates themselves unless the fidelity slaves some
        (``Fidelity.slaved``: the engine's eta = g(q))."""
        if not self.fidelities[k].slaved:
            return q_el
        if not len(q_el):
            return np.zeros((0, self.core.displacement_map(k).shape[1]))
        return self.core.panel_coordinates(k, np.ascontiguousarray(q_el))

    def panel_coordinates(self, q, hinge: Optional[int] = None) -> np.ndarray:
        """Hinge ``hinge``'s panel coordinates at each recorded ``q``, (n, r): those its mesh moves
        by, mesh dofs = ``panel_coordinates(q) @ D.T`` with D its displacement map (a reduced
        panel's :meth:`basis`, the selection of a full panel's free dofs;
        :meth:`mesh_displacements`). They are its elastic coordinates, except on the quadratic
        manifold (``reduced-manifold``): there the basis's r Ritz coordinates eta = g(q_b) of its
        bending coordinates q_b (:class:`~deployfx.specs.Fidelity`); (n, 0) for a rigid panel."""
        k = self._hinge(hinge, panel=True)
        return self._lift(k, self._elastic(self._q(q), k))

    def panel_tangent(self, q, hinge: Optional[int] = None) -> np.ndarray:
        """The derivative of :meth:`panel_coordinates` by the elastic coordinates at one ``q``
        (num_positions,): G = d eta / d q_el, (r x num_elastic), the identity unless the panel is
        on the quadratic manifold. An elastic velocity or mode shape s moves the mesh by
        ``D @ G @ s``."""
        k = self._hinge(hinge, panel=True)
        q_el = self._elastic(self._q(q), k)
        if len(q_el) != 1:
            raise ValueError(f"q must be one sample ({self.num_positions} coordinates), got {len(q_el)}")
        if not self.fidelities[k].slaved:
            return np.eye(q_el.shape[1])
        return np.asarray(self.core.panel_tangent(k, np.ascontiguousarray(q_el[0])))

    def mesh_displacements(self, q, hinge: Optional[int] = None) -> np.ndarray:
        """Hinge ``hinge``'s panel: every mesh dof's displacement (m, rad; 6 per node, C_k axes)
        at each recorded ``q``, shape (n, 6 nodes): its :meth:`panel_coordinates` through its
        displacement map; zeros for a rigid panel."""
        k = self._hinge(hinge, panel=True)
        q = self._q(q)
        if self.core.layout(k)["num_elastic"] == 0:
            return np.zeros((len(q), self.shells[k].num_dofs))
        return self._lift(k, self._elastic(q, k)) @ self.core.displacement_map(k).T

    def node_displacements(self, q, hinge: Optional[int] = None, nodes: Optional[Sequence[int]] = None) -> np.ndarray:
        """Node translations (m, C_k axes) of hinge ``hinge``'s panel at each recorded ``q``,
        shape (n, len(nodes), 3) (``nodes`` None: all of them)."""
        k = self._hinge(hinge, panel=True)
        q = self._q(q)
        return node_translations(self, k, nodes)(q)

    def frames(self, q, t=None) -> tuple[np.ndarray, np.ndarray]:
        """Every body frame C_k in W at each recorded ``q`` (and time ``t``, for prescribed
        hinges): axes ``R_WC`` (n, H, 3, 3) (column j = C_k's axis j in W) and origins ``o_W``
        (n, H, 3), m, from the engine's kinematics (a hinge on a panel rides on its deformed mesh)."""
        q = self._q(q)
        t = np.zeros(len(q)) if t is None else np.broadcast_to(np.asarray(t, dtype=float), (len(q),))
        return self.core.frames(q, np.ascontiguousarray(t))

    def base_poses(self, q) -> tuple[np.ndarray, np.ndarray]:
        """The base's position ``r_W`` (m, (n, 3)) and attitude ``R_WB`` ((n, 3, 3)) at each ``q``;
        zero and identity for a fixed base."""
        q = self._q(q)
        if not self.base_free:
            return np.zeros((len(q), 3)), np.broadcast_to(np.eye(3), (len(q), 3, 3)).copy()
        from scipy.spatial.transform import Rotation

        return q[:, :3].copy(), Rotation.from_quat(q[:, [4, 5, 6, 3]]).as_matrix()

    def world_points(self, q, hinge: Optional[int] = None, t=None, scale: float = 1.0) -> np.ndarray:
        """Hinge ``hinge``'s panel nodes in W (m), (n, nodes, 3): the mesh plus ``scale`` times its
        elastic displacement (1: the true shape; 0: undeformed), placed by :meth:`frames`."""
        k = self._hinge(hinge, panel=True)
        scale = float(scale)
        if not np.isfinite(scale):
            raise ValueError(f"scale = {scale} must be finite")
        R, o = self.frames(q, t)
        X = np.asarray(self.shells[k].nodes, dtype=float)[None] + scale * self.node_displacements(q, k)
        return o[:, k, None, :] + np.einsum("kij,knj->kni", R[:, k], X)

    # --------------------------------------------------------------------- the engine's stages
    def make_data(self):
        """A run's data for this model (lock histories, memos): pass it to the stage functions to
        evaluate with a given contact history (``data.set_lock(k, history)``)."""
        return self.core.make_data()

    def initial_positions(self) -> np.ndarray:
        """The stowed configuration: base at rest at W's origin, every angle 0, panels undeformed."""
        return self.core.initial_positions()

    def residual(self, q, v, a, t: float = 0.0, *, data=None) -> np.ndarray:
        """r(q, v, a, t): the residual of the equations of motion, one entry per velocity (zero
        on a trajectory): the inertia, elastic, spring, damper and lock forces of every body."""
        # Engine: cpp/deployfx/multibody/residual.hpp.
        return self.core.residual(q, v, a, t, data=data)

    def newton_matrix(self, q, v, a, t: float, c_a: float, c_v: float, c_q: float, *, data=None) -> np.ndarray:
        """c_a dr/da + c_v dr/dv + c_q dr/dq (dr/dq along the base's retraction), dense."""
        return self.core.newton_matrix(q, v, a, t, c_a, c_v, c_q, data=data)

    def momentum(self, q, v, *, t: float = 0.0, data=None) -> np.ndarray:
        """[P_W; H_W]: total linear (N s) and angular momentum about W's origin (N m s)."""
        return self.core.momentum(q, v, t=t, data=data)

    def momentum_jacobian(self, q, v, c_v: float, c_q: float, *, data=None) -> np.ndarray:
        """c_v dPi/dv + c_q dPi/dq, (6 x nv)."""
        return self.core.momentum_jacobian(q, v, c_v, c_q, data=data)

    def outputs(self, q, v, a, t: float = 0.0, *, data=None) -> dict:
        """What a run records at (q, v, a, t): the engine's raw per-hinge and system outputs."""
        return self.core.outputs(q, v, a, t, data=data)

    # ---------------------------------------------------------------------------------- modes
    def modes(self, n: int, *, result: Optional[Result] = None, time: Optional[float] = None, q=None, v=None,
              t: Optional[float] = None, equilibrium: bool = False, data=None, zero_hz: float = 1e-3):
        """The lowest ``n`` (>= 1) modes of this model linearised about a state
        (:class:`deployfx.modal_analysis.Modes`: ``frequencies_hz``, ``damping_ratios``,
        ``shapes`` in the velocity coordinates, ``mesh_shapes(k)``).

        The state: ``result`` (a run of this model) at the recorded sample nearest ``time`` (s,
        within the run), or ``q`` (``v`` default 0, ``t`` default 0 s). The locks' histories are
        the run's at that sample (latched as recorded, the contacts its impact records have in
        progress, a groove's latch pin followed through the samples); for a given q, latched
        once past the latch and in contact where the pin penetrates a wall; at an equilibrium,
        where it penetrates by more than 1 nm. ``data`` (a :meth:`make_data` with its lock
        histories set, e.g. the run's own at its end) overrides that.
        ``equilibrium=True`` first moves to the relative equilibrium near the state: every
        undriven hinge and elastic velocity and acceleration zero, the prescribed hinges moving
        as at ``t`` (a steady spin once their ramp is over), a free base carrying the state's
        momentum as a rigid motion (at rest, or spinning), Newton on the residual over the hinge
        angles and elastic coordinates (a latched panel at rest, a spinning beam's centrifugal
        stretch, a spinning spacecraft).

        M = dr/da, C = dr/dv, K = dr/dq of the residual (prescribed hinges are no unknowns: held);
        eigenvalues of the state-space form, natural frequency |lambda|/2 pi, damping ratio
        -Re lambda/|lambda|. A free base at rest is condensed at zero momentum (its six rigid-body
        modes left out); any other mode below ``zero_hz`` (Hz) counts as rigid and is left out
        (``num_rigid``). Dense up to 400 velocities, Arnoldi on the shifted inverse above (the
        paper's full 15 x 10 panel: 2 s). Equations: docs/modes.md."""
        from . import modal_analysis

        return modal_analysis.modes(self, n, result=result, time=time, q=q, v=v, t=t, equilibrium=equilibrium,
                                    data=data, zero_hz=zero_hz)

    # ----------------------------------------------------------------------------------- runs
    def simulate(self, t_end: float, dt: float, *, scheme=GeneralizedAlpha(0.8), tolerance: Optional[float] = None,
                 newton_tolerance: Optional[float] = None, progress: Optional[bool] = None, q0=None, v0=None,
                 nodes: Union[None, str, Mapping[int, Sequence[int]]] = None,
                 series: Optional[Callable[["Model", dict], dict]] = None, units: Optional[dict] = None,
                 metadata: Optional[dict] = None, stop: Optional[Callable[[], bool]] = None, data=None,
                 stresses: bool = False, checkpoint_at: Optional[Sequence[float]] = None,
                 resume: Optional["Checkpoint"] = None) -> Result:
        """Run to ``t_end`` (s) with output step ``dt`` (s), from rest at the stowed configuration
        unless ``q0``/``v0`` are given (see the module docstring for their layout).

        ``scheme``: :class:`~deployfx.integrators.GeneralizedAlpha` (default rho_inf = 0.8), HHT or
        Newmark. ``tolerance`` (m or rad, absolute): error-controlled steps of at most ``dt``,
        keeping the local displacement error estimate h^2 |beta - 1/6| |a_n+1 - a_n| below it;
        None: fixed steps of ``dt``. Contact switches are located in time either way.
        ``newton_tolerance``: Newton's convergence test, the estimated error of each step's
        accelerations relative to their size (at least 1), in [1e-14, 1e-4]; None: the engine's
        1e-10. A trade knob: a looser test saves iterations and moves the outputs (README,
        "Newton's tolerance"; ``bench/newton_tolerance.py``).
        ``progress``: a tqdm bar (True), none (False), or by default one only when standard error
        is a terminal. Ctrl-C (main thread) or ``stop()`` returning True (any thread: e.g. a
        ``threading.Event``'s ``is_set``) stops the run within 0.2 s with a SimulationError holding
        the results so far.

        The result's series are those of :mod:`deployfx.results` (per hinge (n, H), system (n, 3)
        or (n,), the raw ``q`` and ``v``), plus for ``nodes`` (``{hinge: [node, ...]}``, or
        ``"all"`` for every node of every panel) ``node_displacements_<k>`` ((n, nodes, 3), m, C_k
        axes). ``series(model, raw)`` (optional) adds a scene's own series (``units`` theirs) from
        the engine's raw dict. ``stresses=True``: the ply failure envelope of every deforming
        panel that has strengths (``Scene.set_appendage(..., strengths=...)``;
        :meth:`stress_envelope`): series ``max_failure_index`` ((n, H), the panel's largest index
        at each sample) and the summary's ``min_failure_margin``, ``critical_ply``,
        ``critical_element``, ``critical_time_s`` per hinge (metadata ``hinges[k]["stress"]``). Raises :class:`~deployfx.integrators.SimulationError` with
        ``.result`` (the series up to the failure) if a step cannot be completed, or if an undriven
        run's total energy grew by more than ``ENERGY_GROWTH_LIMIT`` of its peak kinetic energy
        (numerical divergence: the message gives the time).

        ``checkpoint_at``: output times (s, multiples of ``dt`` or ``t_end``, in (0, t_end]) at
        which to take a :class:`~deployfx.checkpoint.Checkpoint` (``result.checkpoints``).
        ``resume``: a checkpoint to go on from (see :meth:`resume`): the result runs from its time
        to ``t_end``, bit-identical to the run that took it; dt, scheme, tolerance and
        newton_tolerance must be that run's, and q0, v0 are not taken.
        """
        t_end, dt, tol, scheme = _run_arguments(t_end, dt, scheme, tolerance)
        newton_tol = newton_tolerance_arg(newton_tolerance)
        if resume is not None:
            _checkpoint.check_resume(self, resume, dt=dt, scheme=scheme, tolerance=tol,
                                     newton_tolerance=newton_tol, t_end=t_end, q0=q0, v0=v0)
        steps = _checkpoint._steps(checkpoint_at, t_end, dt, resume)
        stressed = self._stressed_panels() if stresses else []
        if resume is not None:
            q0, v0 = resume.q, resume.v
        q0 = self._rest[0] if q0 is None else finite_vector("q0", q0, self.num_positions)
        v0 = self._rest[1] if v0 is None else finite_vector("v0", v0, self.num_velocities)
        node_sets = _node_rows.node_sets(self, nodes)
        should_stop = None if stop is None else (lambda: bool(stop()))
        raw, wall = _timed_run(lambda progress: _core.simulate(
            self.core, q0, v0, t_end=t_end, dt=dt, scheme=scheme._params(), tolerance=tol,
            newton_tolerance=newton_tol, progress=progress,
            should_stop=should_stop, data=data, checkpoint_steps=steps,
            resume=None if resume is None else resume._core), t_end, progress)
        baseline = None if resume is None else (resume.energy0, resume.kinetic_peak)
        checkpoints = _checkpoint.from_run(self, raw, dt=dt, scheme=scheme, tolerance=tol,
                                           newton_tolerance=newton_tol, baseline=baseline)
        out = self._series(raw)
        for k, idx in node_sets.items():
            out[f"node_displacements_{k}"] = self.node_displacements(raw["q"], k, idx)
        all_units = dict(SERIES_UNITS, **{f"node_displacements_{k}": "m" for k in node_sets})
        if series is not None:
            extra = series(self, raw)
            out.update(extra)
            all_units.update(units or {})
        if stresses:
            peak = np.zeros((len(raw["t"]), self.num_hinges))
            hinge_info = self._hinge_metadata()
            for k in stressed:
                env = self._envelope(raw["t"], raw["q"], k, raw["lock_force"][:, k])
                peak[:, k] = env.peak_index.max(axis=1)
                hinge_info[k]["stress"] = dict(env.summary(), criteria=list(env.criteria), where=env.where,
                                               strain=env.strain_measure)
            out["max_failure_index"] = peak
            all_units["max_failure_index"] = "1"
        meta = {"deployfx_version": _version(),
                "run_started_utc": strftime("%Y-%m-%dT%H:%M:%S+00:00", gmtime())}  # isoformat's, cheaper
        meta.update(self.description)
        meta.update(metadata or {})
        hinge_info = hinge_info if stresses else self._hinge_metadata()
        for k, records in enumerate(impacts.per_hinge(raw["impacts"], self._contact_names)):
            if self.links[k].lock is not None:
                hinge_info[k]["impacts"] = records
        meta.update(base_free=self.base_free, hinges=hinge_info,
                    nodes={str(k): [int(i) for i in v] for k, v in node_sets.items()})
        if len(raw["t"]):  # the momentum the bodies carry: the scale of its conservation error
            scale = {"P_N_s": float(raw["momentum_scale_P"].max()), "H_N_m_s": float(raw["momentum_scale_H"].max())}
            if all(map(math.isfinite, scale.values())):  # not when a divergent run overflowed it
                meta["momentum_scale"] = scale
        if resume is not None:
            meta["resumed_from_s"] = float(resume.t)
        return _run_result(raw, out, all_units, meta, scheme, dt, t_end, tolerance, newton_tol, wall, self.conservative,
                           energy_baseline=baseline, checkpoints=checkpoints)

    def resume(self, checkpoint: "Checkpoint", t_end: float, **options) -> Result:
        """The run that took ``checkpoint`` (:meth:`simulate` with ``checkpoint_at``), continued
        from the checkpoint's time to ``t_end`` (s) with that run's dt, scheme and tolerances;
        bit-identical to the uninterrupted run from there on. ``options``: those of
        :meth:`simulate` (``checkpoint_at``, ``nodes``, ``series``, ``stop``, ...). ValueError if
        the checkpoint was taken on another model."""
        if not isinstance(checkpoint, _checkpoint.Checkpoint):
            raise TypeError(f"checkpoint must be a deployfx Checkpoint, got {type(checkpoint).__name__}")
        for name in ("dt", "scheme", "tolerance", "newton_tolerance", "resume"):
            if name in options:
                raise TypeError(f"resume() takes no {name!r}: the checkpoint's run sets it")
        return self.simulate(t_end, checkpoint.dt, scheme=checkpoint.scheme,
                             tolerance=checkpoint.tolerance or None,
                             newton_tolerance=checkpoint.newton_tolerance, resume=checkpoint, **options)

    @functools.cached_property
    def fingerprint(self) -> str:
        """SHA-256 identifying the compiled model (deployfx.checkpoint.model_fingerprint)."""
        return _checkpoint.model_fingerprint(self)

    def _stressed_panels(self) -> list:
        """The hinges whose deforming panel has strengths; ValueError if there is none."""
        from . import stress

        out = [k for k, L in enumerate(self.links) if self.deforming[k] and L.appendage.strengths is not None]
        if not out:
            raise ValueError("stresses=True needs a deforming panel with strengths: Scene.set_appendage(..., "
                             "strengths=deployfx.Strengths(...)) (deployfx ships no allowables)")
        for k in out:  # a fidelity without a strain measure is refused before the run, not after it
            stress.strain_measure(self.links[k].appendage.fidelity.value)
        return out

    def _envelope(self, t, q, k: int, lock_force, **options):
        from . import metrics, stress

        a = self.links[k].appendage
        force = np.asarray(lock_force, dtype=float)
        impacts = metrics.contact_intervals(t, force)[:, 0] if force.any() else None
        strengths = a.strengths[0] if len(a.strengths) == 1 else list(a.strengths)
        return stress.envelope(a.shell, strengths, t, self.mesh_displacements(q, k),
                               strain=stress.strain_measure(a.fidelity.value), impact_times=impacts, **options)

    def stress_envelope(self, result: Result, hinge: Optional[int] = None, **options):
        """The ply failure envelope (:class:`deployfx.stress.StressEnvelope`) of hinge ``hinge``'s
        panel over ``result`` (a run of this model): its mesh displacements from the recorded
        ``q``, the panel's strengths, Green strain for the nonlinear fidelities, the impacts of
        its hinge's lock marked. ``options``: ``criteria``, ``where`` of
        :func:`deployfx.stress.envelope`."""
        k = self._hinge(hinge, panel=True)
        a = self.links[k].appendage
        if not self.deforming[k] or a.strengths is None:
            raise ValueError(f"hinge {k}'s panel needs to deform and have strengths (Scene.set_appendage(..., "
                             f"fidelity=..., strengths=...)) for a ply envelope")
        force = result["lock_force"][:, k] if "lock_force" in result else np.zeros(len(result.t))
        return self._envelope(np.asarray(result.t), self._q(result["q"]), k, force, **options)

    def _hinge_metadata(self) -> list:
        """A run's metadata ``hinges``: a fresh dict a hinge, for the run's own keys (impacts, stress)."""
        return [dict(info) for info in self._hinges_described]

    @functools.cached_property
    def _hinges_described(self) -> tuple:
        """What a run's metadata says of each hinge before the run's own keys: the model's, taken once."""
        return _run_record.describe_hinges(self)

    @functools.cached_property
    def _rest(self) -> tuple:
        """(q, v, the hinges' stowed angles (deg)) at rest stowed, read-only: a run's defaults."""
        rest = (self.initial_positions(), np.zeros(self.num_velocities),
                np.array([L.hinge.stowed_angle_deg for L in self.links]))
        for a in rest:
            a.flags.writeable = False
        return rest

    @functools.cached_property
    def _contact_names(self) -> tuple:
        """Per hinge: its lock's contacts by the engine's index (impacts.contact_names)."""
        return tuple(impacts.contact_names(L.lock) for L in self.links)

    @functools.cached_property
    def _tips(self) -> tuple:
        """Per hinge: its deforming panel's tip node's translations (_node_rows.NodeTranslations), else None."""
        return tuple(node_translations(self, k, [node]) if deforming else None
                     for k, (node, deforming) in enumerate(zip(self.tip_nodes, self.deforming)))

    def _series(self, raw: dict) -> dict:
        """A run's series from the engine's arrays (deployfx.results names them)."""
        return _run_record.series(self, raw)
