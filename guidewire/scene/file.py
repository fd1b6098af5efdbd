"""Scene files: TOML in, TOML out (units mm, rad, MPa).

The format::

    name = "table1_pi_4"         # optional; default the file name
    [wire]
    length = 100.0               # inserted length L (mm)
    bars = 100                   # n rigid bars
    youngs_modulus = 3560.0      # E (MPa); optional
    diameter = 0.78              # d (mm); optional
    moment_of_inertia = 0.01816  # I (mm⁴); optional, default π d⁴/64
    max_relative_angle = 0.2     # b₂ (rad); optional, omitted = no bounds
    scheme = "paper"             # optional, default "second_order"
    density = "curvature"        # optional: bars graded by a coarse solve's curvature; default uniform
    bar_lengths = [1.0, ...]     # optional: `bars` explicit bar lengths (mm) summing to L, a node at every contact

    [[wire.section]]             # zero or more, listed FROM THE TIP; the wire's own values hold base-side of them
    length = 19.0                # mm along the wire
    youngs_modulus = 17000.0     # optional, default the wire's
    diameter = 0.7               # optional, default the wire's
    moment_of_inertia = 0.0118   # optional, default π d⁴/64 (the wire's I when the section sets no diameter)
    rest_curvature = 0.0826      # optional (1/mm), signed like the tangent's turn from base to tip; default 0
    refinement = 3.0             # optional: bars per mm relative to the wire's own stretch; default 1

    [base]                       # s = 0
    point = [0.0, 0.0]
    angle = 0.0                  # optional; omitted = free to rotate
    name = "A"                   # optional

    [[contact]]                  # zero or more, by increasing s
    s = 100.0
    point = [60.0, 40.0]         # optional
    angle = 0.785398             # optional
    name = "B"                   # optional

    [[wall]]                     # zero or more: normal · p ≤ offset at every node
    normal = [1.0, 0.0]
    offset = 45.0

    [vessel]                     # optional: a lumen every node stays inside (see guidewire.vessel)
    centreline = [[0.0, 0.0], [50.0, 0.0], [90.0, 30.0]]   # mm, entrance first
    radius = 2.0                 # mm: one number, or one per centreline point
    # walls = [[[0.0, 2.0], [100.0, 2.0]], [[0.0, -2.0], [100.0, -2.0]]]  # instead of centreline and radius

    [[vessel.branch]]            # zero or more side branches, each starting inside the main lumen
    centreline = [[50.0, 0.0], [50.0, 30.0]]
    radius = 1.5

With a ``[vessel]`` and no ``[base]``, the base is the vessel's entrance (its first centreline point, the tangent
there pointing in; see :meth:`guidewire.Scene.in_vessel`).
"""

from __future__ import annotations

import difflib
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..vessel.vessel import Branch, Vessel
from .scene import Base, Contact, Scene, Section, Wall, Wire

_TOP_KEYS = {"name", "notes", "wire", "base", "contact", "wall", "vessel"}
_WIRE_KEYS = {"length", "bars", "youngs_modulus", "diameter", "moment_of_inertia", "max_relative_angle", "scheme",
              "section", "density", "bar_lengths"}
_SECTION_KEYS = {"length", "youngs_modulus", "diameter", "moment_of_inertia", "rest_curvature", "refinement"}
_BASE_KEYS = {"point", "angle", "name"}
_CONTACT_KEYS = {"s", "point", "angle", "name"}
_WALL_KEYS = {"normal", "offset"}
_VESSEL_KEYS = {"centreline", "radius", "branch", "walls"}
_BRANCH_KEYS = {"centreline", "radius"}


_EXAMPLES = {
    "wire": "length = 100.0 (mm)",
    "bars": "bars = 100",
    "length": "length = 100.0 (mm)",
    "base": "[base] with point = [0.0, 0.0]",
    "point": "point = [0.0, 0.0] (mm)",
    "s": "s = 100.0 (mm, arc length from the base)",
    "normal": "normal = [1.0, 0.0]",
    "offset": "offset = 45.0 (mm)",
    "centreline": "centreline = [[0.0, 0.0], [50.0, 0.0]] (mm, entrance first)",
    "radius": "radius = 2.0 (mm, or one per centreline point)",
}


def _unknown_key(key: str, where: str, allowed: set[str]) -> str:
    close = difflib.get_close_matches(key, sorted(allowed), n=1, cutoff=0.6)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return f"[{where}] has unknown key {key!r}; {hint}allowed keys: {', '.join(sorted(allowed))}."


def checked_table(data: Any, where: str, allowed: set[str], required: tuple[str, ...]) -> Mapping[str, Any]:
    """Check one TOML table: a mapping with only ``allowed`` keys and all ``required`` ones."""
    if not isinstance(data, Mapping):
        raise ValueError(f"[{where}] is {type(data).__name__}; expected a table.")
    unknown = sorted(set(data) - allowed)
    if unknown:
        raise ValueError(_unknown_key(unknown[0], where, allowed))
    missing = [key for key in required if key not in data]
    if missing:
        key = missing[0]
        example = _EXAMPLES.get(key, f"{key} = ...")
        table = "the top level" if where == "scene file" else f"[{where}]"
        raise ValueError(f"{table} is missing the required key {key!r}; add it, e.g. {example}.")
    for key in ("name", "notes"):
        if key in data and not isinstance(data[key], str):
            raise ValueError(f"[{where}] {key} is {data[key]!r}; expected a string in quotes.")
    return data


def scene_from_dict(data: Mapping[str, Any], *, name: str = "") -> Scene:
    """Build a :class:`Scene` from the parsed TOML mapping (see the module docstring for the keys)."""
    top = checked_table(data, "scene file", _TOP_KEYS, ("wire",) if "vessel" in data else ("wire", "base"))
    wire = wire_from_dict(top["wire"])
    vessel = _vessel(top["vessel"]) if "vessel" in top else None
    if "base" in top:
        base = Base(**checked_table(top["base"], "base", _BASE_KEYS, ("point",)))
    else:
        assert vessel is not None  # checked_table required [base] otherwise
        base = Scene.in_vessel(wire, vessel).base
    contact_list = top.get("contact", [])
    wall_list = top.get("wall", [])
    if not isinstance(contact_list, list):
        raise ValueError("contact must be an array of tables: write [[contact]] (double brackets).")
    if not isinstance(wall_list, list):
        raise ValueError("wall must be an array of tables: write [[wall]] (double brackets).")
    contacts = tuple(_item(Contact, c, f"contact {i + 1}", _CONTACT_KEYS, ("s",)) for i, c in enumerate(contact_list))
    walls = tuple(_item(Wall, w, f"wall {i + 1}", _WALL_KEYS, ("normal", "offset")) for i, w in enumerate(wall_list))
    return Scene(
        wire=wire, base=base, contacts=contacts, walls=walls, name=str(top.get("name", name)),
        notes=str(top.get("notes", "")), vessel=vessel,
    )


def wire_from_dict(data: Any, extra_keys: frozenset[str] = frozenset()) -> Wire:
    """The ``[wire]`` table (with its ``[[wire.section]]`` list) as a :class:`Wire`; keys in ``extra_keys`` are
    allowed and left out (the 3-D scene's twist material)."""
    wire_table = dict(checked_table(data, "wire", _WIRE_KEYS | extra_keys, ("length", "bars")))
    for key in extra_keys:
        wire_table.pop(key, None)
    section_list = wire_table.pop("section", [])
    if not isinstance(section_list, list):
        raise ValueError("wire.section must be an array of tables: write [[wire.section]] (double brackets).")
    sections = tuple(_item(Section, c, f"wire.section {i + 1}", _SECTION_KEYS, ("length",))
                     for i, c in enumerate(section_list))
    return Wire(**wire_table, sections=sections)


def _vessel(data: Any) -> Vessel:
    """The ``[vessel]`` table: ``centreline`` with ``radius`` (and ``[[vessel.branch]]``), or ``walls``."""
    table = checked_table(data, "vessel", _VESSEL_KEYS, ())
    if "walls" in table:
        extra = sorted(set(table) - {"walls"})
        if extra:
            raise ValueError(f"[vessel] has both walls and {extra[0]!r}; give either walls = [[[x, y], ...], "
                             "[[x, y], ...]] or centreline with radius (and [[vessel.branch]]), not both.")
        walls = table["walls"]
        if not isinstance(walls, list) or len(walls) != 2:
            raise ValueError("[vessel] walls must be two polylines: walls = [[[x, y], ...], [[x, y], ...]] (mm).")
        return Vessel.from_walls(walls[0], walls[1])
    checked_table(table, "vessel", _VESSEL_KEYS, ("centreline", "radius"))
    branches = branch_entries(table, _BRANCH_KEYS, lambda entry: Branch(entry["centreline"], entry["radius"]))
    return Vessel.from_centreline(table["centreline"], table["radius"], branches)


def branch_entries(table: Mapping[str, Any], keys: set[str], make: Any) -> list[Any]:
    """The ``[[vessel.branch]]`` list of a ``[vessel]`` table, each entry checked against ``keys`` and built by
    ``make(entry)``; a bad entry's message says which (``[[vessel.branch]] number 2: …``)."""
    items = table.get("branch", [])
    if not isinstance(items, list):
        raise ValueError("vessel.branch must be an array of tables: write [[vessel.branch]] (double brackets).")
    out = []
    for i, item in enumerate(items):
        entry = checked_table(item, f"vessel.branch {i + 1}", keys, ("centreline", "radius"))
        try:
            out.append(make(entry))
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"[[vessel.branch]] number {i + 1}: {exc}") from None
    return out


def _item(cls: Any, data: Any, where: str, allowed: set[str], required: tuple[str, ...]) -> Any:
    """One ``[[contact]]``/``[[wall]]`` entry; a bad value's message says which entry (``contact 2``)."""
    table = checked_table(data, where, allowed, required)
    try:
        return cls(**table)
    except (TypeError, ValueError) as exc:
        raise type(exc)(f"[[{where.split()[0]}]] number {where.split()[1]}: {exc}") from None


def read_toml(path: Path) -> dict[str, Any]:
    """The parsed TOML file; a ValueError naming the file when it is not TOML (FileNotFoundError when missing)."""
    try:
        with path.open("rb") as handle:
            return tomllib.load(handle)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path} is not valid TOML: {exc}") from None
    except UnicodeDecodeError:
        raise ValueError(f"{path} is not valid TOML: it is not UTF-8 text.") from None


def load_scene(path: str | Path) -> Scene:
    """Read a scene file.

    Parameters
    ----------
    path : str or Path
        A TOML file in the format of this module's docstring.

    Returns
    -------
    Scene
        Named by the file's ``name`` key, else by the file name without extension.

    Raises
    ------
    FileNotFoundError
        When the file does not exist.
    ValueError
        When the file is not valid TOML or a value is out of range (the message names the field).
    """
    path = Path(path)
    data = read_toml(path)
    try:
        return scene_from_dict(data, name=path.stem)
    except TypeError as exc:
        raise ValueError(f"{path}: {exc}") from None
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None


def _toml_value(value: Any) -> str:
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)
    return "[" + ", ".join(_toml_value(v) for v in value) + "]"


def scene_to_dict(scene: Scene) -> dict[str, Any]:
    """The scene as the mapping of a scene file (mm, rad, MPa; only the fields that are set), which
    :func:`scene_from_dict` reads back to an equal :class:`Scene`; JSON-ready."""
    base: dict[str, Any] = {"point": list(scene.base.point)}
    if scene.base.angle is not None:
        base["angle"] = scene.base.angle
    base["name"] = scene.base.name
    contacts = [contact_to_dict(contact) for contact in scene.contacts]
    out: dict[str, Any] = {}
    if scene.name:
        out["name"] = scene.name
    if scene.notes:
        out["notes"] = scene.notes
    out["wire"], out["base"] = wire_to_dict(scene.wire), base
    if contacts:
        out["contact"] = contacts
    if scene.walls:
        out["wall"] = [{"normal": list(wall.normal), "offset": wall.offset} for wall in scene.walls]
    if scene.vessel is not None:
        out["vessel"] = vessel_to_dict(scene.vessel)
        if scene.base == Scene.in_vessel(scene.wire, scene.vessel).base:
            del out["base"]  # the entrance: what a file without [base] means
    return out


def wire_to_dict(w: Wire) -> dict[str, Any]:
    """The ``[wire]`` table of a scene file (only the fields that are set), JSON-ready."""
    wire: dict[str, Any] = {"length": w.length, "bars": w.bars, "youngs_modulus": w.youngs_modulus,
                            "diameter": w.diameter}
    if w.moment_of_inertia is not None:
        wire["moment_of_inertia"] = w.moment_of_inertia
    if w.max_relative_angle is not None:
        wire["max_relative_angle"] = w.max_relative_angle
    wire["scheme"] = w.scheme
    if w.density is not None:
        wire["density"] = w.density
    if w.bar_lengths is not None:
        wire["bar_lengths"] = list(w.bar_lengths)
    if w.sections:
        wire["section"] = [
            {key: getattr(sec, key) for key in ("length", "youngs_modulus", "diameter", "moment_of_inertia",
                                                "rest_curvature", "refinement")
             if getattr(sec, key) is not None and not (key == "refinement" and sec.refinement == 1.0)}
            for sec in w.sections
        ]
    return wire


def contact_to_dict(contact: Contact) -> dict[str, Any]:
    """One ``[[contact]]`` table of a scene file (only the fields that are set), JSON-ready."""
    item: dict[str, Any] = {"s": contact.s}
    if contact.point is not None:
        item["point"] = list(contact.point)
    if contact.angle is not None:
        item["angle"] = contact.angle
    if contact.name:
        item["name"] = contact.name
    return item


def vessel_to_dict(vessel: Vessel) -> dict[str, Any]:
    """The ``[vessel]`` table of a scene file (mm), JSON-ready."""

    def lists(line: tuple[tuple[float, ...], ...]) -> list[list[float]]:
        return [list(p) for p in line]

    def radius(value: float | tuple[float, ...]) -> float | list[float]:
        return list(value) if isinstance(value, tuple) else value

    if vessel.walls:
        return {"walls": [lists(w) for w in vessel.walls]}
    out: dict[str, Any] = {"centreline": lists(vessel.centreline), "radius": radius(vessel.radius)}
    if vessel.branches:
        out["branch"] = [{"centreline": lists(b.centreline), "radius": radius(b.radius)} for b in vessel.branches]
    return out


def scene_to_toml(scene: Scene) -> str:
    """The scene as TOML text that :func:`load_scene` reads back to an equal :class:`Scene`."""
    data = scene_to_dict(scene)
    lines = [f"{key} = {_toml_value(data[key])}" for key in ("name", "notes") if key in data]
    lines += _toml_table("[wire]", data["wire"], skip="section")
    for item in data["wire"].get("section", []):
        lines += _toml_table("[[wire.section]]", item)
    if "base" in data:
        lines += _toml_table("[base]", data["base"])
    for table in ("contact", "wall"):
        for item in data.get(table, []):
            lines += _toml_table(f"[[{table}]]", item)
    if "vessel" in data:
        lines += _toml_table("[vessel]", data["vessel"], skip="branch")
        for item in data["vessel"].get("branch", []):
            lines += _toml_table("[[vessel.branch]]", item)
    return "\n".join(lines) + "\n"


def _toml_table(header: str, items: dict[str, Any], skip: str = "") -> list[str]:
    """A blank line, the table's ``header`` and its ``key = value`` lines (without the subtable ``skip``)."""
    return ["", header, *(f"{k} = {_toml_value(v)}" for k, v in items.items() if k != skip)]
