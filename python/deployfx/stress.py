"""Ply stresses, strains and failure indices of a laminated shell mesh, and their envelope over
the samples of a run (docs/ply-stresses.md has the formulas and references).

Inputs are mesh-dof displacements in the :class:`~deployfx.ShellModel`'s axes and numbering (six
per node, ``(u_x, u_y, u_z, theta_x, theta_y, theta_z)``, dof ``6 i + k`` of node ``i``): one
vector ``u`` (ndof,) or a series ``u_series`` (n, ndof).

- Strains are recovered with the element's own interpolation, including its MITC4 transverse
  shear: linear, or with the Green membrane strain of You et al. (2016) Eq. 14
  (``strain="green"``, for the nonlinear fidelities), or von Karman's (``strain="von-karman"``:
  the quadratic terms of the normal displacement alone, for "reduced-manifold"), at each
  element's centroid (``where="centroid"``, one point) or at its 2x2 Gauss points
  (``where="gauss"``, four points in the element's order (-g, -g), (g, -g), (g, g), (-g, g),
  g = 1/sqrt(3)).
- Each ply is sampled at three stations through its thickness: bottom, middle, top.
- Components, in each ply's material axes (1 along the fibres): ``sigma_1, sigma_2, tau_12,
  tau_13, tau_23`` (Pa) and strains ``eps_1, eps_2, gamma_12, gamma_13, gamma_23``. The in-plane
  ones follow classical lamination theory; ``tau_13, tau_23`` follow the equilibrium
  distribution of the shear resultants (Rolfes & Rohwer 1997, :func:`shear_distribution`).
- Failure indices (:data:`CRITERIA`) are inverse strength ratios, ``FI = 1/R``: ``FI = 1`` on
  the failure surface, linear in the load; the margin of safety is ``MS = R - 1 = 1/FI - 1``.
- Plies count from the bottom (z = -h/2), 0-based; elements index the shell's quads.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional, Sequence, Union

import numpy as np

from . import _core
from .materials import Laminate
from .plate import Plate, ShellModel
from .strengths import Strengths

__all__ = ["COMPONENTS", "STRAIN_COMPONENTS", "CRITERIA", "PlyStresses", "StressEnvelope",
           "ply_stresses", "failure_index", "margin_of_safety", "envelope", "fields_at",
           "cell_data", "shear_distribution", "strain_measure"]

#: Stress components on the last axis of :attr:`PlyStresses.stress` (Pa, ply material axes).
COMPONENTS = ("sigma_1", "sigma_2", "tau_12", "tau_13", "tau_23")
#: Strain components on the last axis of :attr:`PlyStresses.strain` (ply material axes).
STRAIN_COMPONENTS = ("eps_1", "eps_2", "gamma_12", "gamma_13", "gamma_23")
#: The failure criteria: maximum stress, Tsai-Wu, Hashin's fibre and matrix modes ("hashin"
#: names both).
CRITERIA = ("max_stress", "tsai_wu", "hashin_fibre", "hashin_matrix")
_STRAINS = ("linear", "green", "von-karman")
_WHERE = ("centroid", "gauss")
_STATIONS = ("bottom", "middle", "top")

StrengthsArg = Union[Strengths, Sequence[Strengths]]


@dataclass(frozen=True)
class PlyStresses:
    """The ply fields of one displacement vector.

    Attributes
    ----------
    stress : (elements, points, plies, 3, 5) ply stresses, Pa, material axes, components
        :data:`COMPONENTS`; axis 3 the stations bottom, middle, top of each ply.
    strain : the same shape, strains :data:`STRAIN_COMPONENTS` (dimensionless).
    z : (plies, 3) height of each station above the laminate mid-plane, m.
    points : (elements, points, 3) the sampling points on the undeformed mid-surface, m (the
        shell's axes).
    angles_deg : (plies,) each ply's fibre angle, degrees, bottom first.
    where : "centroid" or "gauss".
    strain_measure : "linear", "green" or "von-karman".
    time_s : the sample's time, s (None for a lone displacement vector).
    """

    stress: np.ndarray
    strain: np.ndarray
    z: np.ndarray
    points: np.ndarray
    angles_deg: np.ndarray
    where: str
    strain_measure: str
    time_s: Optional[float] = None

    @property
    def num_plies(self) -> int:
        """Number of plies."""
        return self.stress.shape[2]


@dataclass(frozen=True)
class StressEnvelope:
    """The failure envelope of a run: each element's and ply's maximum failure index over the
    samples, and where the panel is closest to failure.

    Attributes
    ----------
    t : (n,) sample times, s.
    criteria : the criteria, in the order of the first axis below.
    index : (criteria, elements, plies) maximum failure index over the samples, the element's
        sampling points and the ply's stations (dimensionless).
    time_s : (criteria, elements, plies) the time of that maximum, s (the earliest on ties).
    sample, point, station : (criteria, elements, plies) its sample, sampling point and ply
        station (0 bottom, 1 middle, 2 top) indices.
    peak_index : (n, criteria) the largest index over the mesh at each sample.
    critical_criterion, critical_element, critical_ply : the governing criterion (the largest
        index over all of them), the element (an index into the shell's quads) and the ply
        (0-based from the bottom) where it occurs.
    critical_sample, critical_time_s, critical_point, critical_station : when (sample, s) and
        where (sampling point, ply station) it occurs.
    max_failure_index : the largest index, at that place and time.
    min_failure_margin : the margin of safety there, ``1 / max_failure_index - 1`` (+inf for an
        unloaded panel).
    critical_history : (n,) the critical element's index in the critical ply (governing criterion)
        at each sample.
    critical_field : (elements,) every element's index in the critical ply (governing criterion)
        at the critical sample.
    impact_times : (m,) times to mark on plots (e.g. the lock's impacts), s.
    where, strain_measure : as :func:`ply_stresses`.
    """

    t: np.ndarray
    criteria: tuple
    index: np.ndarray
    time_s: np.ndarray
    sample: np.ndarray
    point: np.ndarray
    station: np.ndarray
    peak_index: np.ndarray
    critical_criterion: str
    critical_element: int
    critical_ply: int
    critical_sample: int
    critical_time_s: float
    critical_point: int
    critical_station: int
    max_failure_index: float
    min_failure_margin: float
    critical_history: np.ndarray
    critical_field: np.ndarray
    impact_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    where: str = "centroid"
    strain_measure: str = "linear"

    def summary(self) -> dict:
        """The numbers a structures engineer signs off: ``min_failure_margin``,
        ``max_failure_index``, ``critical_criterion``, ``critical_ply`` (from the bottom, 0-based),
        ``critical_element`` (a quad index), ``critical_time_s`` (s); plain Python types."""
        return {"min_failure_margin": float(self.min_failure_margin),
                "max_failure_index": float(self.max_failure_index),
                "critical_criterion": self.critical_criterion,
                "critical_ply": int(self.critical_ply),
                "critical_element": int(self.critical_element),
                "critical_time_s": float(self.critical_time_s)}

    def margin(self) -> np.ndarray:
        """(criteria, elements, plies) margins of safety of :attr:`index` (see
        :func:`margin_of_safety`)."""
        return margin_of_safety(self.index)

    def cell_data(self) -> dict:
        """The envelope as meshio cell data for the shell's quads: ``ply<k>_<criterion>_max``
        (the maximum index over the run) for each ply and criterion,
        ``{name: [array (elements,)]}``."""
        return {f"ply{k}_{c}_max": [np.array(self.index[i, :, k])]
                for k in range(self.index.shape[2]) for i, c in enumerate(self.criteria)}


def ply_stresses(shell: ShellModel, u: object, *, strain: str = "linear",
                 where: str = "centroid") -> PlyStresses:
    """Stresses and strains of every ply of every element for the mesh displacements ``u``
    (ndof,), in each ply's material axes. ``strain``: "linear", "green" (the Green membrane
    strain of You et al. 2016 Eq. 14, for the nonlinear fidelities; the stresses are then second
    Piola-Kirchhoff) or "von-karman" (its quadratic terms of the normal displacement w alone,
    1/2 (w_x^2, w_y^2, 2 w_x w_y) in the element's axes: the strain whose energy the
    reduced-manifold fidelity condenses). ``where``: "centroid" or "gauss" (see the module
    docstring)."""
    shell = _shell(shell)
    rec = _recovery(shell, where)
    u = _float_array("u", u, (shell.num_dofs,))
    stress, strain_arr = rec.fields(u, _strain(strain))
    return _ply_stresses(shell, rec, stress, strain_arr, where, strain, None)


def failure_index(stresses: Union[PlyStresses, np.ndarray], strengths: StrengthsArg,
                  criterion: str = "tsai_wu") -> np.ndarray:
    """Failure index ``FI = 1/R`` of ply stress states (R: the strength ratio).

    ``stresses``: a :class:`PlyStresses` or an array (..., 5) of :data:`COMPONENTS` (Pa).
    ``strengths``: one :class:`~deployfx.Strengths`, or one per ply (then ``stresses`` has the
    ply axis third from the end, (..., plies, 3, 5), as :attr:`PlyStresses.stress`).
    ``criterion``: one of :data:`CRITERIA`, or "hashin" (the larger of its fibre and matrix
    modes). Returns ``stresses.shape[:-1]``.
    """
    s = stresses.stress if isinstance(stresses, PlyStresses) else _float_array(
        "stresses", stresses, None)
    if s.ndim < 1 or s.shape[-1] != 5:
        raise ValueError(f"stresses must have the 5 components {COMPONENTS} on the last axis, "
                         f"got shape {s.shape}")
    names = _criteria(criterion)
    if isinstance(strengths, Strengths):
        per_ply = None
    elif s.ndim < 3:
        raise ValueError(f"strengths per ply need stresses of shape (..., plies, 3, 5), "
                         f"got {s.shape}")
    else:
        per_ply = _strengths_list(strengths, s.shape[-3])
    out = np.zeros(s.shape[:-1])
    for name in names:
        crit = getattr(_core.FailureCriterion, name)
        if per_ply is None:
            fi = _core.failure_indices(s.reshape(-1, 5), strengths._impl, crit)
            fi = fi.reshape(s.shape[:-1])
        else:
            fi = np.empty(s.shape[:-1])
            for k, st in enumerate(per_ply):
                part = s[..., k, :, :]
                fi[..., k, :] = _core.failure_indices(part.reshape(-1, 5), st._impl,
                                                      crit).reshape(part.shape[:-1])
        out = np.maximum(out, fi)
    return out


def margin_of_safety(index: object) -> np.ndarray:
    """Margin of safety ``MS = R - 1 = 1/FI - 1`` of failure indices (R the strength ratio);
    +inf where the index is 0 (an unloaded ply). Negative: failed."""
    fi = np.asarray(index, dtype=float)
    if np.any(~np.isfinite(fi)) or np.any(fi < 0):
        raise ValueError("index must hold finite failure indices >= 0")
    with np.errstate(divide="ignore"):
        return np.where(fi > 0, 1.0 / np.where(fi > 0, fi, 1.0) - 1.0, np.inf)


def envelope(shell: ShellModel, strengths: StrengthsArg, t: object, u_series: object, *,
             criteria: Optional[Sequence[str]] = None, strain: str = "linear",
             where: str = "centroid", impact_times: Optional[object] = None) -> StressEnvelope:
    """The failure envelope of a run: ``t`` (n,) sample times (s), ``u_series`` (n, ndof) the
    mesh displacements at those times.

    ``strengths``: one :class:`~deployfx.Strengths` for every ply, or one per ply (bottom first).
    ``criteria``: names from :data:`CRITERIA` (or "hashin" for both modes); default every
    criterion the strengths support (maximum stress, Tsai-Wu, Hashin fibre, and Hashin matrix
    when every ply has ``S23``). ``strain``, ``where``: as :func:`ply_stresses`.
    ``impact_times`` (s): stored for :func:`deployfx.stress_plot.critical_history` to mark.
    Runs in the compiled core over all samples (Ctrl-C stops it), storing no stress field.
    """
    shell = _shell(shell)
    rec = _recovery(shell, where)
    measure = _strain(strain)
    t = _float_array("t", t, (None,))
    U = _float_array("u_series", u_series, (t.shape[0], shell.num_dofs))
    per_ply = _strengths_list(strengths, rec.num_plies)
    if criteria is None:
        names = ["max_stress", "tsai_wu", "hashin_fibre"]
        if all(s.S23 is not None for s in per_ply):
            names.append("hashin_matrix")
    else:
        if isinstance(criteria, str):
            criteria = [criteria]
        names = [n for c in criteria for n in _criteria(c)]
        names = list(dict.fromkeys(names))
    crits = [getattr(_core.FailureCriterion, n) for n in names]
    impls = [s._impl for s in per_ply]
    env = rec.envelope(U, impls, crits, measure)
    index = env["index"]
    c, e, k = np.unravel_index(int(np.argmax(index)), index.shape)
    sample = env["sample"]
    k_star = int(sample[c, e, k])
    history = rec.index_series(U, impls, [crits[c]], measure, [int(e)])[:, 0, 0, k]
    field_ = rec.index_series(U[k_star:k_star + 1], impls, [crits[c]], measure,
                              list(range(rec.num_elements)))[0, 0, :, k]
    fi = float(index[c, e, k])
    impacts = np.zeros(0) if impact_times is None else _float_array(
        "impact_times", np.atleast_1d(impact_times), (None,), allow_empty=True)
    return StressEnvelope(
        t=t, criteria=tuple(names), index=index, time_s=t[sample], sample=sample,
        point=env["point"], station=env["station"], peak_index=env["peak"],
        critical_criterion=names[c], critical_element=int(e), critical_ply=int(k),
        critical_sample=k_star, critical_time_s=float(t[k_star]),
        critical_point=int(env["point"][c, e, k]), critical_station=int(env["station"][c, e, k]),
        max_failure_index=fi, min_failure_margin=float(margin_of_safety(fi)),
        critical_history=history, critical_field=field_, impact_times=impacts, where=where,
        strain_measure=strain)


def fields_at(shell: ShellModel, t: object, u_series: object, times: object, *,
              strain: str = "linear", where: str = "centroid") -> list[PlyStresses]:
    """The full ply fields at chosen ``times`` (s): one :class:`PlyStresses` per time, at the
    sample nearest to it (its ``time_s`` says which). Times must lie within ``t``."""
    shell = _shell(shell)
    t = _float_array("t", t, (None,))
    U = _float_array("u_series", u_series, (t.shape[0], shell.num_dofs))
    times = _float_array("times", np.atleast_1d(times), (None,))
    bad = times[(times < t.min()) | (times > t.max())]
    if bad.size:
        raise ValueError(f"times = {bad.tolist()} is out of range: must be within the samples' "
                         f"[{t.min():g}, {t.max():g}] s")
    rec = _recovery(shell, where)
    measure = _strain(strain)
    out = []
    for time in times:
        i = int(np.argmin(np.abs(t - time)))
        stress, strain_arr = rec.fields(U[i], measure)
        out.append(_ply_stresses(shell, rec, stress, strain_arr, where, strain, float(t[i])))
    return out


def cell_data(stresses: PlyStresses, strengths: Optional[StrengthsArg] = None,
              criteria: Optional[Sequence[str]] = None) -> dict:
    """Per-cell ply fields for VTK export (meshio ``cell_data`` of the shell's quads,
    ``{name: [array (elements,)]}``).

    ``ply<k>_<component>`` (Pa, :data:`COMPONENTS`): the stress at the ply's middle station,
    averaged over the element's sampling points. With ``strengths``: ``ply<k>_<criterion>``, the
    failure index (maximum over the element's points and the ply's stations), and
    ``<criterion>_max`` over the plies; ``criteria`` default: maximum stress and Tsai-Wu.
    """
    if not isinstance(stresses, PlyStresses):
        raise TypeError(f"stresses must be a deployfx.stress.PlyStresses, got "
                        f"{type(stresses).__name__}")
    out = {}
    mid = stresses.stress[:, :, :, 1, :].mean(axis=1)  # (elements, plies, 5)
    for k in range(stresses.num_plies):
        for j, comp in enumerate(COMPONENTS):
            out[f"ply{k}_{comp}"] = [np.array(mid[:, k, j])]
    if strengths is not None:
        names = ["max_stress", "tsai_wu"] if criteria is None else list(criteria)
        for name in names:
            fi = failure_index(stresses, strengths, name).max(axis=(1, 3))  # (elements, plies)
            for k in range(stresses.num_plies):
                out[f"ply{k}_{name}"] = [np.array(fi[:, k])]
            out[f"{name}_max"] = [fi.max(axis=1)]
    return out


def shear_distribution(laminate: Laminate, z: object) -> np.ndarray:
    """The equilibrium transverse shear distribution (Rolfes & Rohwer, Int. J. Numer. Meth. Eng.
    40, 1997, 51-60): ``H`` (len(z), 2, 2) in 1/m with ``(tau_xz, tau_yz)(z) = H(z) (Q_x, Q_y)``
    in the laminate's axes, ``z`` (m) from the mid-plane within [-h/2, h/2]. It vanishes at both
    faces and integrates to the identity over the thickness; for a homogeneous section it is
    ``3 / (2 h) (1 - 4 z^2 / h^2)``."""
    if not isinstance(laminate, Laminate):
        raise TypeError(f"laminate must be a deployfx.Laminate, got {type(laminate).__name__}")
    z = _float_array("z", np.atleast_1d(z), (None,))
    return _core.equilibrium_shear(laminate._impl, z.tolist())


def strain_measure(fidelity: str) -> str:
    """The strain a fidelity's internal force uses: "green" for "nonlinear" and
    "reduced-nonlinear" (You et al. 2016 Eq. 14), "linear" for "linear" and "reduced-linear",
    "von-karman" for "reduced-manifold". A rigid appendage has no stresses (ValueError).

    The manifold's energy is Green strain without the in-plane displacements' own quadratic
    terms (docs/research/quadratic-manifold.md, "poly"): on its flat panel, whose bending vectors
    move w alone and in-plane vectors u, v alone, that is von Karman's strain. Green strain of its
    mesh displacements would add those terms back, about the foreshortening's (w_x^2/2)^2/2, as
    tension: on the paper scene (6 x 4, node E at 0.41 m) 196 MPa of peak fibre stress where the
    reduced-nonlinear run of the same motion has 52 MPa."""
    measures = {"nonlinear": "green", "reduced-nonlinear": "green", "linear": "linear",
                "reduced-linear": "linear", "reduced-manifold": "von-karman"}
    if fidelity not in measures:
        raise ValueError(f"fidelity = {fidelity!r} has no ply stresses: must be one of "
                         f"{', '.join(measures)}")
    return measures[fidelity]


# -- helpers ------------------------------------------------------------------------------------

def _shell(shell: object) -> ShellModel:
    if isinstance(shell, Plate):
        return shell.model
    if not isinstance(shell, ShellModel):
        raise TypeError(f"shell must be a deployfx.ShellModel (or a Plate), "
                        f"got {type(shell).__name__}")
    return shell


def _recovery(shell: ShellModel, where: str) -> "_core.PlyRecovery":
    if where not in _WHERE:
        raise ValueError(f"where = {where!r} is invalid: must be one of {', '.join(_WHERE)}")
    return _core.PlyRecovery(shell._impl, shell.laminate._impl, where == "gauss")


def _strain(strain: str) -> str:
    if strain not in _STRAINS:
        raise ValueError(f"strain = {strain!r} is invalid: must be one of {', '.join(_STRAINS)}")
    return strain


def _criteria(name: object) -> tuple:
    if name == "hashin":
        return ("hashin_fibre", "hashin_matrix")
    if name not in CRITERIA:
        raise ValueError(f"criterion = {name!r} is invalid: must be one of "
                         f"{', '.join(CRITERIA)}, or hashin")
    return (name,)


def _strengths_list(strengths: object, plies: int) -> list:
    if isinstance(strengths, Strengths):
        return [strengths] * plies
    if isinstance(strengths, (str, bytes)) or not isinstance(strengths, Sequence):
        raise TypeError(f"strengths must be a deployfx.Strengths or one per ply, got "
                        f"{type(strengths).__name__}")
    for i, s in enumerate(strengths):
        if not isinstance(s, Strengths):
            raise TypeError(f"strengths[{i}] must be a deployfx.Strengths, got {type(s).__name__}")
    if len(strengths) != plies:
        raise ValueError(f"strengths must give one Strengths per ply ({plies}), "
                         f"got {len(strengths)}")
    return list(strengths)


def _ply_stresses(shell, rec, stress, strain_arr, where, strain, time_s) -> PlyStresses:
    E, P = rec.num_elements, rec.points_per_element
    angles = np.array([p.angle_deg for p in shell.laminate.plies], dtype=float)
    return PlyStresses(stress=stress, strain=strain_arr, z=np.array(rec.z),
                       points=np.array(rec.points).reshape(E, P, 3), angles_deg=angles, where=where,
                       strain_measure=strain, time_s=time_s)


def _float_array(name: str, value: object, shape, allow_empty: bool = False) -> np.ndarray:
    a = np.asarray(value)
    if a.dtype.kind not in "iuf":
        raise TypeError(f"{name} must be a real array, got dtype {a.dtype}")
    if shape is not None:
        ok = a.ndim == len(shape) and all(s is None or s == g for s, g in zip(shape, a.shape))
        if not ok:
            dims = ", ".join("n" if s is None else str(s) for s in shape)
            raise ValueError(f"{name} must have shape ({dims}{',' if len(shape) == 1 else ''}), "
                             f"got {a.shape}")
        if not allow_empty and a.size == 0:
            raise ValueError(f"{name} is empty: give at least one value")
    a = np.ascontiguousarray(a, dtype=float)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} has non-finite entries (NaN or inf)")
    return a
