"""deployfx: deployment and locking dynamics of flexible laminated-composite appendages.

- Structures: laminated materials (:class:`Isotropic`, :class:`Orthotropic`, :class:`Ply`,
  :class:`Laminate`) and the MITC4 laminated shell on a :class:`Plate` or any :class:`ShellModel`.
- Scenes: :class:`Scene` builds a base and a tree of hinges (a yoke and panels, two wings, or one
  hinge), each body with rigid parts, a panel of any :class:`Fidelity` and a lock, into one
  immutable :class:`Model`; :mod:`deployfx.scenes` holds the paper's scene (``scenes.paper2016``)
  and the spin-up beam.
- Results: :class:`Result` (series, units, ``summary()``, ``save``/:func:`load`), :mod:`plot`.
- Scene files: :func:`save_scene` / :func:`load_scene` (JSON or TOML, :mod:`deployfx.scene_file`).
- Ply stresses: :class:`Strengths`, :mod:`stress` (ply stresses, failure indices, a run's
  envelope), :mod:`stress_plot`.
- Checkpoint and resume: ``Model.simulate(..., checkpoint_at=[...])``, :class:`Checkpoint`,
  :func:`load_checkpoint`, ``Model.resume`` (:mod:`checkpoint`; bit-identical).
- Modes about a state: ``Model.modes`` returns :class:`Modes` (:mod:`modal_analysis`).
SI units throughout.
"""
from .materials import Isotropic, Laminate, Orthotropic, Ply
from .plate import Plate, ShellModel
from .strengths import Strengths
from . import (checkpoint, contact, export, integrators, metrics, modal_analysis, paper2016, plot, scenes, specs,
               stress, stress_plot)
from .checkpoint import Checkpoint, load_checkpoint
from .modal_analysis import Modes
from .model import Model
from .results import Result, load
from .scene import Scene
from .specs import Fidelity
from .scene_file import load_scene, save_scene
from .tradeoff import tradeoff

__all__ = ["Isotropic", "Orthotropic", "Ply", "Laminate", "Plate", "ShellModel", "Scene", "Model", "Fidelity",
           "Strengths", "Result", "load", "Checkpoint", "load_checkpoint", "save_scene", "load_scene", "checkpoint",
           "contact", "export", "integrators", "metrics", "Modes", "modal_analysis", "paper2016", "plot", "scenes", "specs", "stress", "stress_plot", "tradeoff"]
__version__ = "0.1.0"
