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
from ._checks import as_float, as_int
from .materials import Laminate

_EDGE_HELP = "four letters from C, S, F for the edges x=0, y=0, x=length, y=width"


def _frequencies_hz(eigenvalues: np.ndarray) -> np.ndarray:
    # Rigid-body modes come out at round-off, of either sign: they are 0 Hz.
    return np.sqrt(np.clip(eigenvalues, 0.0, None)) / (2.0 * np.pi)


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
        nodes = np.asarray(nodes, dtype=float)
        quads = np.asarray(quads)
        if nodes.ndim != 2 or nodes.shape[1] != 3:
            raise ValueError(f"nodes must have shape (n, 3), got {nodes.shape}")
        if quads.ndim != 2 or quads.shape[1] != 4 or not np.issubdtype(quads.dtype, np.integer):
            raise ValueError(f"quads must be integers of shape (e, 4), got {quads.dtype} {quads.shape}")
        self.laminate = _laminate(laminate)
        self.ref_axis = np.array(ref_axis, dtype=float)  #: the 0-degree direction given (world axes)
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
        return self._impl.pressure_load(as_float("pressure", pressure))

    def geometric_stiffness(self, N: Sequence[float]) -> scipy.sparse.csc_matrix:
        """K_s (Eq. 22) for uniform membrane resultants ``N = (N_x, N_y, N_xy)`` in N/m."""
        N = np.asarray(N, dtype=float)
        if N.shape != (3,) or not np.all(np.isfinite(N)):
            raise ValueError(f"N must be 3 finite resultants (N_x, N_y, N_xy) in N/m, got {N}")
        return self._impl.geometric_stiffness(N)

    def geometric_stiffness_from(self, u: np.ndarray) -> scipy.sparse.csc_matrix:
        """K_s with the membrane resultants of the linear strains of displacement ``u``."""
        return self._impl.geometric_stiffness_from(np.asarray(u, dtype=float))

    def strain_energy(self, u: np.ndarray) -> float:
        """Strain energy (J) with the Green membrane strain of Eq. 14."""
        return self._impl.strain_energy(np.asarray(u, dtype=float))

    def internal_force(self, u: np.ndarray) -> Tuple[np.ndarray, scipy.sparse.csc_matrix]:
        """Internal force ``dU/du`` (ndof) and tangent ``K_L + K_L* + K_s`` at ``u``."""
        return self._impl.internal_force(np.asarray(u, dtype=float))

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
        r = self._impl.modes(as_int("n", n), [int(d) for d in fixed_dofs])
        return _frequencies_hz(r.eigenvalues), r.modes

    def static(self, load: np.ndarray, fixed_dofs: Sequence[int]) -> np.ndarray:
        """Displacements (ndof) solving ``K u = load`` with ``fixed_dofs`` held at zero."""
        return self._impl.static_solve(np.asarray(load, dtype=float), [int(d) for d in fixed_dofs])


class Plate:
    """A rectangular laminated plate meshed with ``nx`` x ``ny`` shell elements.

    ``length`` (m) runs along x, ``width`` (m) along y; 0-degree plies lie along x. Node
    ``(i, j)`` (i along x) has index ``j (nx + 1) + i``.

    ``boundary`` names the edges x=0, y=0, x=length, y=width, each ``C`` (clamped), ``S``
    (simply supported: w, the in-plane displacement along the edge and the slope along the edge
    held at zero; Reddy's SS-1) or ``F`` (free); e.g. ``"CFFF"`` is a cantilever clamped at x=0.
    """

    def __init__(self, length: float, width: float, laminate: Laminate, nx: int, ny: int):
        self.laminate = _laminate(laminate)
        self._impl = _core.RectangularPlate(as_float("length", length), as_float("width", width),
                                            laminate._impl, as_int("nx", nx), as_int("ny", ny))
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
        r = self._impl.modes(as_int("n", n), self._boundary(boundary))
        w = r.modes[2::6, :].T.reshape(-1, self.ny + 1, self.nx + 1)
        return _frequencies_hz(r.eigenvalues), w

    def static(self, pressure: float, boundary: str) -> np.ndarray:
        """Transverse displacement w (m) at the nodes, shape (ny+1, nx+1), under a uniform
        pressure (Pa) along +z."""
        return self._impl.static_deflection(as_float("pressure", pressure), self._boundary(boundary))

    @staticmethod
    def _boundary(boundary: object) -> str:
        if not isinstance(boundary, str):
            raise TypeError(f"boundary must be a string of {_EDGE_HELP}, got {boundary!r}")
        return boundary.upper()
