"""Laminated shell finite-element models: a general quadrilateral mesh and a rectangular plate.

The element is a four-node flat shell with MITC4 transverse shear (Bathe & Dvorkin 1985),
membrane-bending coupling, consistent mass with rotary inertia and a drilling penalty; six dofs
per node in world axes, ``(u_x, u_y, u_z, theta_x, theta_y, theta_z)``, dof ``6 i + k`` of node
``i``. Units: m, N, kg, s, Pa; frequencies in Hz.
"""
from __future__ import annotations

from typing import Sequence, Tuple

import numpy as np
import scipy.sparse

from . import _core
from ._checks import as_float, as_int, as_int_sequence
from .materials import Laminate

_EDGE_HELP = "four letters from C, S, F for the edges x=0, y=0, x=length, y=width"


def _frequencies_hz(eigenvalues: np.ndarray) -> np.ndarray:
    # Rigid-body modes come out at round-off, of either sign: they are 0 Hz.
    return np.sqrt(np.clip(eigenvalues, 0.0, None)) / (2.0 * np.pi)


def _count(name: str, value: object) -> int:
    """An int that the core's 32-bit ints hold (the core checks the range it needs)."""
    v = as_int(name, value)
    if not -2**31 <= v < 2**31:
        raise ValueError(f"{name} = {v} is out of range: must be a 32-bit integer")
    return v


def _dofs(name: str, dofs: object, ndof: int) -> list:
    """``dofs`` as a list of ints in [0, ndof), or TypeError/ValueError naming ``name`` (a float
    such as 1.5 is refused, not truncated)."""
    out = as_int_sequence(name, dofs)
    for k, d in enumerate(out):
        if not 0 <= d < ndof:
            raise ValueError(f"{name}[{k}] = {d} is out of range: must be in [0, {ndof - 1}] "
                             f"(6 dofs per node)")
    return out


def _finite(name: str, a: np.ndarray, why: str) -> np.ndarray:
    """``a`` if every entry is finite, else ValueError naming ``name``."""
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} leaves the finite doubles: {why}")
    return a


def _vector(name: str, u: object, ndof: int) -> np.ndarray:
    """``u`` as a finite float vector of size ndof, or ValueError/TypeError naming ``name``."""
    try:
        u = np.asarray(u, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be an array of {ndof} real numbers: {e}") from None
    if u.shape != (ndof,):
        raise ValueError(f"{name} must have shape ({ndof},) (6 dofs per node), got {u.shape}")
    bad = np.flatnonzero(~np.isfinite(u))
    if bad.size:
        raise ValueError(f"{name}[{bad[0]}] = {float(u[bad[0]])!r} is out of range: must be finite")
    return u


def _laminate(obj: object) -> Laminate:
    if not isinstance(obj, Laminate):
        raise TypeError(f"laminate must be a deployfx.Laminate, got {type(obj).__name__}")
    return obj


class ShellModel:
    """Laminated shell elements on an arbitrary mesh of flat quadrilaterals.

    Parameters
    ----------
    nodes : (n, 3) node coordinates, m.
    quads : (e, 4) node indices per element, counter-clockwise about the element normal.
    laminate : the section of every element.
    ref_axis : the laminate's 0-degree direction (world axes), projected onto each element.
    """

    def __init__(self, nodes, quads, laminate: Laminate, ref_axis: Sequence[float] = (1.0, 0.0, 0.0)):
        try:
            nodes = np.asarray(nodes, dtype=float)
        except (TypeError, ValueError) as e:
            raise TypeError(f"nodes must be an (n, 3) array of coordinates (m): {e}") from None
        quads = np.asarray(quads)
        if nodes.ndim != 2 or nodes.shape[1] != 3:
            raise ValueError(f"nodes must have shape (n, 3), got {nodes.shape}")
        if quads.ndim != 2 or quads.shape[1] != 4 or not np.issubdtype(quads.dtype, np.integer):
            raise ValueError(f"quads must be integers of shape (e, 4), got {quads.dtype} {quads.shape}")
        if quads.size:
            # Checked before the cast to the core's int32, which would wrap 2**32 + 3 to 3.
            bad = np.argwhere((quads < 0) | (quads >= len(nodes)))
            if bad.size:
                e, a = bad[0]
                raise ValueError(f"quads[{e}, {a}] = node {quads[e, a]} is out of range: must be "
                                 f"in [0, {len(nodes) - 1}] (the nodes given)")
        self.laminate = _laminate(laminate)
        try:
            ref = np.array(ref_axis, dtype=float)  #: the 0-degree direction given (world axes)
        except (TypeError, ValueError) as e:
            raise TypeError(f"ref_axis must be 3 real numbers: {e}") from None
        if ref.shape != (3,) or not np.all(np.isfinite(ref)):
            raise ValueError(f"ref_axis must be 3 finite numbers (a direction), got {ref_axis!r}")
        self.ref_axis = ref
        self._impl = _core.ShellModel(nodes, quads.astype(np.int32), laminate._impl, self.ref_axis)

    @classmethod
    def _wrap(cls, impl: _core.ShellModel, laminate: Laminate) -> "ShellModel":
        self = cls.__new__(cls)
        self.laminate, self._impl = laminate, impl
        self.ref_axis = np.array([1.0, 0.0, 0.0])  # a Plate's mesh: 0-degree plies along x
        return self

    @property
    def nodes(self) -> np.ndarray:
        """(n, 3) node coordinates, m."""
        return self._impl.nodes

    @property
    def quads(self) -> np.ndarray:
        """(e, 4) element connectivity."""
        return self._impl.quads

    @property
    def num_dofs(self) -> int:
        """Number of dofs, ndof = 6 n (six per node, world axes)."""
        return self._impl.num_dofs

    @property
    def mass(self) -> float:
        """Total mass from the consistent mass matrix, kg."""
        return self._impl.total_mass()

    def stiffness_matrix(self) -> scipy.sparse.csc_matrix:
        """Linear stiffness K_L (You et al. 2016 Eq. 19), sparse (ndof x ndof)."""
        return self._impl.stiffness()

    def mass_matrix(self) -> scipy.sparse.csc_matrix:
        """Consistent mass with rotary inertia, sparse (ndof x ndof)."""
        return self._impl.mass()

    def pressure_load(self, pressure: float) -> np.ndarray:
        """Nodal forces (ndof) of a uniform pressure (Pa) along each element normal."""
        p = as_float("pressure", pressure)
        if not np.isfinite(p):
            raise ValueError(f"pressure = {p!r} is out of range: must be finite (Pa)")
        return _finite("the pressure load", self._impl.pressure_load(p),
                       f"pressure = {p!r} Pa is too large")

    def geometric_stiffness(self, N: Sequence[float]) -> scipy.sparse.csc_matrix:
        """K_s (Eq. 22) for uniform membrane resultants ``N = (N_x, N_y, N_xy)`` in N/m."""
        N = np.asarray(N, dtype=float)
        if N.shape != (3,) or not np.all(np.isfinite(N)):
            raise ValueError(f"N must be 3 finite resultants (N_x, N_y, N_xy) in N/m, got {N}")
        return self._impl.geometric_stiffness(N)

    def geometric_stiffness_from(self, u: np.ndarray) -> scipy.sparse.csc_matrix:
        """K_s with the membrane resultants of the linear strains of displacement ``u``."""
        K = self._impl.geometric_stiffness_from(_vector("u", u, self.num_dofs))
        _finite("K_s", K.data, "the displacements u are too large")
        return K

    def strain_energy(self, u: np.ndarray) -> float:
        """Strain energy (J) with the Green membrane strain of Eq. 14."""
        U = self._impl.strain_energy(_vector("u", u, self.num_dofs))
        return float(_finite("the strain energy", np.float64(U),
                             "the displacements u are too large"))

    def internal_force(self, u: np.ndarray) -> Tuple[np.ndarray, scipy.sparse.csc_matrix]:
        """Internal force ``dU/du`` (ndof) and tangent ``K_L + K_L* + K_s`` at ``u``."""
        f, K = self._impl.internal_force(_vector("u", u, self.num_dofs))
        _finite("the internal force", f, "the displacements u are too large")
        _finite("the tangent stiffness", K.data, "the displacements u are too large")
        return f, K

    def floating_frame_inertia(self) -> "_core.FloatingFrameInertia":
        """The inertia shape integrals of this mesh as a body in a floating frame (You et al.
        2016 Eq. 9, 28): ``mass``, ``S0``, ``J0``, ``S1`` (P_A), ``C``, ``Mij(i, j)``, ``M``
        (L_c), and ``first_moment(d)``, ``inertia_tensor(d)``, ``rotation_coupling(d)``,
        ``kinetic_energy(V, w, d, dd)`` for the dofs ``d`` in the model's axes (SI units);
        ``products(z)``: the nine ``Mij(i, j) @ z`` (index 3 i + j) they are built from."""
        return _core.FloatingFrameInertia(self._impl)

    def modes(self, n: int, fixed_dofs: Sequence[int] = ()) -> Tuple[np.ndarray, np.ndarray]:
        """Lowest ``n`` modes with ``fixed_dofs`` held at zero.

        Returns frequencies (n,) in Hz, ascending, and mass-normalised shapes (ndof, n).
        """
        r = self._impl.modes(_count("n", n), _dofs("fixed_dofs", fixed_dofs, self.num_dofs))
        return _frequencies_hz(r.eigenvalues), r.modes

    def static(self, load: np.ndarray, fixed_dofs: Sequence[int]) -> np.ndarray:
        """Displacements (ndof) solving ``K u = load`` with ``fixed_dofs`` held at zero."""
        u = self._impl.static_solve(_vector("load", load, self.num_dofs),
                                    _dofs("fixed_dofs", fixed_dofs, self.num_dofs))
        return _finite("the displacements", u, "the load is too large")


class Plate:
    """A rectangular laminated plate meshed with ``nx`` x ``ny`` shell elements.

    ``length`` (m) runs along x, ``width`` (m) along y (each in (0, 1e6]); 0-degree plies lie along x. Node
    ``(i, j)`` (i along x) has index ``j (nx + 1) + i``.

    ``boundary`` names the edges x=0, y=0, x=length, y=width, each ``C`` (clamped), ``S``
    (simply supported: w, the in-plane displacement along the edge and the slope along the edge
    held at zero; Reddy's SS-1) or ``F`` (free); e.g. ``"CFFF"`` is a cantilever clamped at x=0.
    """

    def __init__(self, length: float, width: float, laminate: Laminate, nx: int, ny: int):
        self.laminate = _laminate(laminate)
        self._impl = _core.RectangularPlate(as_float("length", length), as_float("width", width),
                                            laminate._impl, _count("nx", nx), _count("ny", ny))
        self.length, self.width = float(length), float(width)
        self.nx, self.ny = int(nx), int(ny)
        self.model = ShellModel._wrap(self._impl.model, laminate)

    def __repr__(self) -> str:
        return (f"Plate(length={self.length:g}, width={self.width:g}, {self.laminate!r}, "
                f"nx={self.nx}, ny={self.ny})")

    @property
    def mass(self) -> float:
        """Total mass, kg (from the consistent mass matrix)."""
        return self.model.mass

    @property
    def x(self) -> np.ndarray:
        """Node x coordinates on the (ny+1, nx+1) grid, m."""
        return self.model.nodes[:, 0].reshape(self.ny + 1, self.nx + 1)

    @property
    def y(self) -> np.ndarray:
        """Node y coordinates on the (ny+1, nx+1) grid, m."""
        return self.model.nodes[:, 1].reshape(self.ny + 1, self.nx + 1)

    def fixed_dofs(self, boundary: str) -> np.ndarray:
        """The dofs that ``boundary`` holds at zero."""
        return np.unique(self._impl.fixed_dofs(self._boundary(boundary)))

    def natural_frequencies(self, n: int, boundary: str) -> np.ndarray:
        """The lowest ``n`` natural frequencies, Hz, ascending (rigid-body modes at 0)."""
        return self.modes(n, boundary)[0]

    def modes(self, n: int, boundary: str) -> Tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) in Hz and transverse mode shapes w, shape (n, ny+1, nx+1),
        mass-normalised."""
        r = self._impl.modes(_count("n", n), self._boundary(boundary))
        w = r.modes[2::6, :].T.reshape(-1, self.ny + 1, self.nx + 1)
        return _frequencies_hz(r.eigenvalues), w

    def static(self, pressure: float, boundary: str) -> np.ndarray:
        """Transverse displacement w (m) at the nodes, shape (ny+1, nx+1), under a uniform
        pressure (Pa) along +z."""
        w = self._impl.static_deflection(as_float("pressure", pressure), self._boundary(boundary))
        return _finite("the deflection", w, f"pressure = {pressure!r} Pa is too large")

    @staticmethod
    def _boundary(boundary: object) -> str:
        if not isinstance(boundary, str):
            raise TypeError(f"boundary must be a string of {_EDGE_HELP}, got {boundary!r}")
        return boundary.upper()
