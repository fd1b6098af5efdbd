"""What is solved, as values: the :class:`Scene` (:mod:`.scene`; its :class:`Wire` from :mod:`guidewire.wire`),
scene files in TOML (:mod:`.file`), the paper's scenes (:mod:`.paper`) and random scenes generated from a bar chain
(:mod:`.generated`)."""

from .file import load_scene, scene_to_toml
from .paper import paper_groups, paper_scenes
from .scene import SCHEMES, Base, Contact, Scene, Section, Wall, Wire

__all__ = ["SCHEMES", "Base", "Contact", "Scene", "Section", "Wall", "Wire", "load_scene", "paper_groups",
           "paper_scenes", "scene_to_toml"]
