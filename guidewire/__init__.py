"""The bar-chain guidewire model of Li et al. (Appl. Sci. 2019, 9, 280) on top of :mod:`sqp`.

>>> import guidewire
>>> sol = guidewire.solve(guidewire.paper_scenes()["table1_pi_4"])
>>> sol.success, round(sol.energy, 2)
(True, 4.55)

Modules: :mod:`~guidewire.scene` (values), :mod:`~guidewire.scene_file` (TOML), :mod:`~guidewire.chain`
(kinematics), :mod:`~guidewire.energy` (the two schemes), :mod:`~guidewire.blocks` (one type per constraint kind),
:mod:`~guidewire.formulation` (the NLP in either layout; :mod:`~guidewire.full_space` the full-space one),
:mod:`~guidewire.initial_shape` (the start), :mod:`~guidewire.solve`, :mod:`~guidewire.sequence` and
:mod:`~guidewire.result`, :mod:`~guidewire.reference` (the exact continuum elastica), :mod:`~guidewire.paper` (the
paper's scenes), :mod:`~guidewire.vessel` (vessel lumens), :mod:`~guidewire.plot` (figures, needs matplotlib),
:mod:`~guidewire.cli` (``python -m guidewire``).
"""

from .batch import SceneError, solve_many
from .batch_insert import insert_many
from .formulation import Formulation, formulate
from .insertion import Insertion, insert
from .paper import paper_groups, paper_scenes
from .result import Reaction, Solution
from .scene import Base, Contact, Scene, Section, Wall, Wire
from .scene_file import load_scene, scene_to_toml
from .sequence import SequenceResult, solve_sequence
from .solve import solve
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
