"""3-D scene files (TOML, units mm, rad, MPa, N) and the loader that reads either kind.

A scene is 3-D when its vessel's centreline has three columns, its vessel is a shipped shape or a VMTK file, or its
base point has three coordinates; otherwise it is the planar :class:`guidewire.Scene` of :mod:`guidewire.scene.file`
(a 2-column centreline stays a planar vessel)::

    name = "helix_j"
    [wire]                       # the planar format's keys and [[wire.section]] list, plus the twist material:
    length = 40.0
    bars = 80
    youngs_modulus = 80000.0
    diameter = 0.89
    poisson_ratio = 0.33         # optional: G = E / (2 (1 + ν)); default 0.33 (nitinol)
    shear_modulus = 30000.0      # optional instead of poisson_ratio (MPa)
    [[wire.section]]             # a J tip: rest curvature toward the material d1
    length = 15.205
    rest_curvature = 0.0826
    youngs_modulus = 17000.0
    diameter = 0.7
    refinement = 2.9             # optional: the tip's bars per mm relative to the shaft's (stEVE's 22 + 218 beams)

    [base]                       # optional with a vessel (default: its entrance, along its first tangent)
    point = [0.0, 0.0, 0.0]
    tangent = [1.0, 0.0, 0.0]
    normal = [0.0, 1.0, 0.0]     # optional: the material d1 at zero rotation
    rotation = 0.0               # rad about the tangent

    [vessel]                     # one of three forms:
    centreline = [[0.0, 0.0, 0.0], [30.0, 0.0, 5.0], [60.0, 10.0, 0.0]]    # mm, entrance first
    radius = 2.0                 # mm: one, or one per point
    # shape = "helix"            # or a shipped shape, with its keyword arguments in [vessel.parameters]
    # file = "arch.vtp"          # or a VMTK centreline file, relative to this file (needs the [vtk] extra)

    [[vessel.branch]]            # zero or more, with centreline (first point inside the parent) and radius
    centreline = [[30.0, 0.0, 5.0], [35.0, 20.0, 5.0]]
    radius = 1.2
    name = "side"

    tip_force = [0.0, 0.0, -0.01]   # optional top-level key: a load on the tip (N)
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from ..scene.file import branch_entries, checked_table, read_toml, scene_from_dict, wire_from_dict
from ..scene.scene import Scene
from ..vessel3d import Branch3D, Vessel3D
from ..vessel3d import shapes as vessel_shapes
from ..vessel3d.vtp import read_centerlines  # (vtk, an optional extra, is imported only when a file is read)
from .scene import Base3D, Scene3D

TOP_KEYS = {"name", "notes", "wire", "base", "vessel", "tip_force"}
TWIST_KEYS = frozenset({"poisson_ratio", "shear_modulus"})
BASE_KEYS = {"point", "tangent", "normal", "rotation", "name"}
VESSEL_KEYS = {"centreline", "radius", "branch", "shape", "parameters", "file", "name"}
BRANCH_KEYS = {"centreline", "radius", "name"}


def shipped_shapes() -> dict[str, Callable[..., Vessel3D]]:
    """The shapes a ``[vessel] shape = ...`` key may name, by name."""
    return {name: getattr(vessel_shapes, name) for name in vessel_shapes.SHAPES}


def is_3d(data: Mapping[str, Any]) -> bool:
    """Whether a parsed scene file describes a 3-D scene (see the module docstring)."""
    vessel = data.get("vessel")
    if isinstance(vessel, Mapping):
        if "shape" in vessel or "file" in vessel:
            return True
        line = vessel.get("centreline")
        if isinstance(line, list) and line and isinstance(line[0], list) and len(line[0]) == 3:
            return True
    base = data.get("base")
    return isinstance(base, Mapping) and isinstance(base.get("point"), list) and len(base["point"]) == 3


def vessel_from_dict(data: Any, folder: Path) -> Vessel3D:
    """The ``[vessel]`` table of a 3-D scene (``folder``: where a ``file`` is looked up)."""
    table = checked_table(data, "vessel", VESSEL_KEYS, ())
    forms = [key for key in ("centreline", "shape", "file") if key in table]
    if len(forms) != 1:
        raise ValueError("[vessel] needs exactly one of centreline (with radius), shape or file; got "
                         f"{forms or 'none'}.")
    name = str(table.get("name", ""))
    if "shape" in table:
        return _shape(table)
    if "file" in table:
        path = Path(str(table["file"]))
        return read_centerlines(path if path.is_absolute() else folder / path, name=name or None)
    checked_table(table, "vessel", VESSEL_KEYS, ("centreline", "radius"))
    branches = branch_entries(table, BRANCH_KEYS, lambda entry: Branch3D(entry["centreline"], entry["radius"],
                                                                          str(entry.get("name", ""))))
    return Vessel3D.from_centreline(table["centreline"], table["radius"], branches, name=name)


def _shape(table: Mapping[str, Any]) -> Vessel3D:
    shapes = shipped_shapes()
    shape = table["shape"]
    if shape not in shapes:
        raise ValueError(f"[vessel] shape = {shape!r} is not a shipped shape; choose one of {sorted(shapes)}.")
    extra = sorted(set(table) - {"shape", "parameters", "name"})
    if extra:
        raise ValueError(f"[vessel] with shape takes only [vessel.parameters]; remove {extra}.")
    parameters = table.get("parameters", {})
    if not isinstance(parameters, Mapping):
        raise ValueError("[vessel.parameters] must be a table of the shape's keyword arguments.")
    try:
        return shapes[shape](**parameters)
    except TypeError as exc:
        raise ValueError(f"[vessel.parameters] for shape {shape!r}: {exc}") from None


def scene3d_from_dict(data: Mapping[str, Any], *, name: str = "", folder: Path = Path()) -> Scene3D:
    """A :class:`Scene3D` from a parsed scene file (see the module docstring for the keys)."""
    top = checked_table(data, "scene file", TOP_KEYS, ("wire",) if "vessel" in data else ("wire", "base"))
    wire_table = top["wire"]
    wire = wire_from_dict(wire_table, TWIST_KEYS)
    twist = {key: wire_table[key] for key in TWIST_KEYS if isinstance(wire_table, Mapping) and key in wire_table}
    vessel = vessel_from_dict(top["vessel"], folder) if "vessel" in top else None
    load = {"tip_force": top["tip_force"]} if "tip_force" in top else {}
    label = str(top.get("name", name))
    if "base" in top:
        base = Base3D(**checked_table(top["base"], "base", BASE_KEYS, ("point",)))
        return Scene3D(wire=wire, base=base, vessel=vessel, name=label, **twist, **load)
    assert vessel is not None  # (checked_table required [base] otherwise)
    return Scene3D.in_vessel(wire, vessel, name=label, **twist, **load)


def load_scene(path: str | Path) -> Scene | Scene3D:
    """Read a scene file, planar (:class:`guidewire.Scene`) or 3-D (:class:`Scene3D`), whichever it describes.

    Raises
    ------
    FileNotFoundError
        When the file does not exist.
    ValueError
        When the file is not valid TOML or a value is out of range (the message names the file and the field).
    """
    path = Path(path)
    data = read_toml(path)
    try:
        if is_3d(data):
            return scene3d_from_dict(data, name=path.stem, folder=path.parent)
        return scene_from_dict(data, name=path.stem)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{path}: {exc}") from None
