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
  figures, exports);
- the 3D model: :mod:`~guidewire.rod` (framed rod energy with twist), :mod:`~guidewire.vessel3d` (tubes, shipped
  shapes, VMTK files), :mod:`~guidewire.solve3d` (scenes, the sparse program, solve, insertion and rotation, 3D
  scene files; :func:`load_scene` reads planar and 3D files alike).
"""

from .batch import SceneError, insert_many, solve_many
from .march import Insertion, SequenceResult, insert, solve_sequence
from .program import Formulation, formulate
from .scene import Base, Contact, Scene, Section, Wall, Wire, paper_groups, paper_scenes, scene_to_toml
from .solve import Reaction, Solution, solve
from .solve3d import Base3D, Contact3D, Scene3D, Solution3D, solve3d
from .solve3d.file import load_scene
from .solve3d.insert import Insertion3D, insert3d
from .status import Status
from .vessel import Branch, Clearance, Vessel

__all__ = [
    "Base",
    "Base3D",
    "Contact3D",
    "Insertion3D",
    "Scene3D",
    "Solution3D",
    "insert3d",
    "solve3d",
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
