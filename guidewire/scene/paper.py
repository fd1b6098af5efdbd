"""The paper's scenes (Li et al. 2019, Tables 1, 2, 4, 5 and Fig. 6) as Python values; the same ship as TOML files in
``guidewire/scenes/`` (see :func:`scene_path`).

Material, all scenes (§2.1, Table 3): E = 3.56 GPa = 3560 MPa, d = 0.78 mm, I = 1.816e-14 m⁴ = 0.01816 mm⁴, so
EI = 64.65 N·mm². Lengths in mm, angles in rad.

- Table 1 (Fig. 4): clamp A (0, 0) along +x, contact B (60, 40) at s = L = 100 with angle θ_B ∈ {−π/2, −π/4, 0,
  π/4, π/2}; n = 100.
- Table 2 (Fig. 5): A as above, C (30, 20) at s = 50 with angle θ_C (same five values), B (60, 40) at s = 100 with
  angle 0; n = 100.
- Fig. 6a: clamp at the origin along +x, L = 100, n = 100, free end, wall y ≥ 1.5x − 30 (normal (1.5, −1),
  offset 30; Eq. 23). Fig. 6b: the same with the wall x ≤ 45 (Eq. 24).
- Table 4 (Fig. 13a, position I): O (0, 0) at 1.187 rad, P1 (9.5, 14.5) at s = 18 with 0.820, P2 (59, 28.3) at
  s = 71 with 0.061; inserted length l_in = 87 (a 16 mm free end); n = 87 (n/L = 1, the paper's choice, Fig. 10).
- Table 5 (Fig. 13b, position II) as printed: O (0, 0) at 1.518, P3 (80, 28.5) at s = 91.5 with 0.244, P4 (98, 42.5)
  at s = 112.5 with 0.644; l_in = 112.5, n = 112. **Infeasible**: P3 and P4 are 22.80 mm apart with only 21.0 mm of
  wire between them; :meth:`Scene.check_feasible` says so before any solve.
"""

from __future__ import annotations

import math
from importlib import resources
from pathlib import Path

from .scene import Base, Contact, Scene, Wall, Wire

YOUNGS_MODULUS = 3560.0  # MPa; §2.1: 3.56 GPa
DIAMETER = 0.78  # mm; §2.1
MOMENT_OF_INERTIA = 0.01816  # mm⁴; §2.1: 1.816e-14 m⁴

ANGLES = {
    "minus_pi_2": -math.pi / 2,
    "minus_pi_4": -math.pi / 4,
    "zero": 0.0,
    "pi_4": math.pi / 4,
    "pi_2": math.pi / 2,
}
"""The five angles of Tables 1 and 2 (θ_B, θ_C), keyed as they appear in scene names."""


def paper_wire(length: float = 100.0, bars: int = 100) -> Wire:
    """The paper's guidewire (EI = 64.65 N·mm²) with the default (second-order) scheme."""
    return Wire(length, bars, YOUNGS_MODULUS, DIAMETER, moment_of_inertia=MOMENT_OF_INERTIA)


def table1(theta_b: float, *, name: str = "") -> Scene:
    """Table 1 / Fig. 4: two-point contact, clamp A (0, 0) at 0 and B (60, 40) at s = 100 with angle ``theta_b``."""
    return Scene(
        paper_wire(),
        Base((0.0, 0.0), 0.0, name="A"),
        (Contact(100.0, (60.0, 40.0), theta_b, name="B"),),
        name=name or "table1",
        notes=f"Li et al. 2019, Table 1 / Fig. 4: two-point contact, theta_B = {theta_b:.10g} rad",
    )


def table2(theta_c: float, *, name: str = "") -> Scene:
    """Table 2 / Fig. 5: three-point contact, A (0, 0) at 0, C (30, 20) at s = 50 with ``theta_c``, B (60, 40) at 0."""
    contacts = (Contact(50.0, (30.0, 20.0), theta_c, name="C"), Contact(100.0, (60.0, 40.0), 0.0, name="B"))
    notes = f"Li et al. 2019, Table 2 / Fig. 5: three-point contact, theta_C = {theta_c:.10g} rad"
    return Scene(paper_wire(), Base((0.0, 0.0), 0.0, name="A"), contacts, name=name or "table2", notes=notes)


def fig6a() -> Scene:
    """Fig. 6a: clamp at the origin along +x, free end, oblique wall y ≥ 1.5x − 30 (Eq. 23)."""
    return Scene(
        paper_wire(),
        Base((0.0, 0.0), 0.0, name="O"),
        walls=(Wall((1.5, -1.0), 30.0),),
        name="fig6a",
        notes="Li et al. 2019, Fig. 6a: clamp along +x, free end, oblique wall y >= 1.5x - 30 (Eq. 23)",
    )


def fig6b() -> Scene:
    """Fig. 6b: clamp at the origin along +x, free end, vertical wall x ≤ 45 (Eq. 24)."""
    return Scene(
        paper_wire(),
        Base((0.0, 0.0), 0.0, name="O"),
        walls=(Wall((1.0, 0.0), 45.0),),
        name="fig6b",
        notes="Li et al. 2019, Fig. 6b: clamp along +x, free end, vertical wall x <= 45 (Eq. 24)",
    )


def table4() -> Scene:
    """Table 4 / Fig. 13a: position I of the experiment, l_in = 87 mm, n = 87."""
    contacts = (Contact(18.0, (9.5, 14.5), 0.820, name="P1"), Contact(71.0, (59.0, 28.3), 0.061, name="P2"))
    return Scene(
        paper_wire(87.0, 87),
        Base((0.0, 0.0), 1.187, name="O"),
        contacts,
        name="table4",
        notes="Li et al. 2019, Table 4 / Fig. 13a: experiment, position I, l_in = 87 mm",
    )


def table5() -> Scene:
    """Table 5 / Fig. 13b: position II as printed, l_in = 112.5 mm, n = 112 — infeasible (see the module doc)."""
    contacts = (Contact(91.5, (80.0, 28.5), 0.244, name="P3"), Contact(112.5, (98.0, 42.5), 0.644, name="P4"))
    return Scene(
        paper_wire(112.5, 112),
        Base((0.0, 0.0), 1.518, name="O"),
        contacts,
        name="table5",
        notes="Li et al. 2019, Table 5 / Fig. 13b: position II as printed -- infeasible (P3-P4)",
    )


def paper_groups() -> dict[str, tuple[Scene, ...]]:
    """The paper's scenes by figure: ``fig4`` (Table 1), ``fig5`` (Table 2), ``fig6`` and ``fig13`` (Tables 4–5)."""
    return {
        "fig4": tuple(table1(a, name=f"table1_{key}") for key, a in ANGLES.items()),
        "fig5": tuple(table2(a, name=f"table2_{key}") for key, a in ANGLES.items()),
        "fig6": (fig6a(), fig6b()),
        "fig13": (table4(), table5()),
    }


def paper_scenes() -> dict[str, Scene]:
    """Every paper scene by name (``table1_pi_4``, ``fig6b``, ``table5``, ...), in the paper's order."""
    return {scene.name: scene for group in paper_groups().values() for scene in group}


def scene_path(name: str) -> Path:
    """The shipped TOML file of the paper scene ``name``."""
    path = Path(str(resources.files("guidewire") / "scenes" / f"{name}.toml"))
    if not path.is_file():
        raise ValueError(f"no shipped scene {name!r}; choose one of {', '.join(paper_scenes())}.")
    return path
