"""The bar-chain guidewire model of Li et al. (Appl. Sci. 2019, 9, 280) on top of :mod:`sqp`.

>>> import guidewire
>>> sol = guidewire.solve(guidewire.paper_scenes()["table1_pi_4"])
>>> sol.success, round(sol.energy, 2)
(True, 4.55)

The package reads from values to answers; each line imports only from the lines above it (and sqp):

- :mod:`~guidewire.fields`, :mod:`~guidewire.wire`, :mod:`~guidewire.energy`, :mod:`~guidewire.status`: checked
  values, the wire, its bending energy and why a solve ended (shared by the planar model and the 3D rod);
- :mod:`~guidewire.vessel` (lumens), :mod:`~guidewire.scene` (what is solved: values, TOML files, the paper's
  scenes), :mod:`~guidewire.chain` (bar layouts, kinematics, density, the wire's spline),
  :mod:`~guidewire.initial_shape` (the default start);
- :mod:`~guidewire.blocks` (one type per constraint kind), :mod:`~guidewire.program` (a scene as a nonlinear
  program, in the reduced or full-space layout);
- :mod:`~guidewire.solve` (one scene: front door, options, pipeline, branches, refinement, the Solution),
  :mod:`~guidewire.march` (warm-started insertion and sequences), :mod:`~guidewire.batch` (many at once);
- :mod:`~guidewire.reference` (the exact continuum elastica), :mod:`~guidewire.app` (``python -m guidewire``,
  figures, exports), :mod:`~guidewire.rod` and :mod:`~guidewire.solve3d` (the 3D model).
"""

from .batch import SceneError, insert_many, solve_many
from .march import Insertion, SequenceResult, insert, solve_sequence
from .program import Formulation, formulate
from .scene import Base, Contact, Scene, Section, Wall, Wire, load_scene, paper_groups, paper_scenes, scene_to_toml
from .solve import Reaction, Solution, solve
from .status import Status
from .vessel import Branch, Clearance, Vessel

__all__ = [
    "Base",
    "Branch",
    "Clearance",
    "Contact",
    "Formulation",
    "Insertion",
    "Reaction",
    "Scene",
    "SceneError",
    "Section",
    "SequenceResult",
    "Solution",
    "Status",
    "Vessel",
    "Wall",
    "Wire",
    "formulate",
    "insert",
    "insert_many",
    "load_scene",
    "paper_groups",
    "paper_scenes",
    "scene_to_toml",
    "solve",
    "solve_many",
    "solve_sequence",
]
