"""The aortic-arch family of stEVE (Karstensen et al.): arch types I, II, IV, V (a and b), VI and VII as
:class:`~guidewire.vessel3d.vessel.Vessel3D` trees, entered from the descending aorta.

Source: github.com/lkarstensen/stEVE, ``eve/intervention/vesseltree/aorticarch.py`` (which branches leave where) with
the artery generators in ``eve/intervention/vesseltree/aorticarcharteries/*.py`` and the curve construction in
``eve/intervention/vesseltree/util/cubichermitesplines.py`` (read at commit f909e71; this is our own code). stEVE
draws every value from a normal distribution; we take the MEANS (no sigma), in stEVE's units (mm) and axes
(``x`` patient left, ``y`` anterior-posterior, ``z`` head-wards).

Construction (as stEVE's ``chs_to_cl_points``)
-----------------------------------------------
Each artery is a cubic Hermite spline through control points ``(x, y, z, d)`` in the parameter "chord length between
control points"; the slope at a control point is the unit ``direction`` times ``magnitude`` (and ``dd`` for the
fourth component). NOTE: stEVE's fourth component (``radius_mean_and_sigma``) is a DIAMETER — ``chs_to_cl_points``
halves it — so the aorta is 17 mm wide at the descending end, not 34. The curve is sampled every 0.1 in its parameter
and resampled by arc length every ``resolution`` mm (2 mm for the aorta, 1 mm for the branches). Mean control points
(``point``; direction; magnitude; diameter; d diameter), ``s`` the branch start on its parent::

    aorta  (0, 0, 0); (0, 0, 1); 1.0; 17; 0.02 → (30, 0, 90); (1, 0, 2); 1.2; 20; 0.02
           → (20, −40, 160); (−4, −6, −0.5); 1.4; 24; 0.07 → (−5, −60, 100); (3, 4, −8); 1.6; 29; 0
    brachiocephalic (bct)   s; (0, −0.3, 1); 2.0; 17; 0 → s + (−20, 5, 45); (−0.3, 0.3, 0.7); 0.8; 10; −0.1
    common origin (co_VI)   s; (0, 0.6, 1); 1.0; 22; 0 → s + (5, 5, 25); (−0.3, 0.3, 0.7); 0.8; 12; −0.1
    left common carotid     s; (0.3, 0, 1); 1.5; 10; 0 → (s_x + 2, s_y + 8, 230); (0, 0, 1); 1.5; 9.5; 0
      … _II                 s; (0.6, 0, 1); 1.5; 10; 0 → (s_x + 25, s_y + 8, 230); (0, 0, 1); 1.5; 9.5; 0
    left subclavian         s; (0.1, 0.1, 2); 2.0; 10; 0 → (59, s_y + 5, s_z + 50); (1, 0.3, 0); 1.7; 9; −0.1
      … _IV                 as above with s_z + 40;   … _VI: (59, s_y + 15, s_z + 20); (1, 0.3, −0.1)
    right common carotid    s; (0.2, 0, 1); 1.5; 10; 0 → (s_x, s_y, 230); (0, 0, 1); 1.5; 9; 0
      … _V                  starts along the parent's end slope (magnitude 1.5), otherwise as above
      … _VII                s; (0.2, 0, 1) … → (s_x − 10, s_y, 230); (−0.2, 0, 1); 1.5; 9; 0
    right subclavian        s along the parent's end slope; 1.5; parent's end d and dd
                            → (−57, s_y + 35, s_z + 25); (−1.2, 0, 0); 1.5; same d; 0
      … _IV                 s; (0.1, −0.1, 2); 3.0; 10; 0 → (−57, s_y + 2, s_z + 50); (−1.2, 0, 0); 1.5; 10; 0
      … _V                  s; (0.1, 0.1, 2); 2.0; 10; 0 → (−57, s_y + 2, s_z + 42); (−1.2, −2.5, 0); 1.5; 10; 0
      … _VI                 s along the parent's end slope → (−57, s_y + 15, s_z + 20); (−0.6, 0, −0.1); 1.5

Branch layout (stEVE's ``_create_*``; "aorta at D" is the aorta sample ``round(D / 2)`` samples from its ascending
end, the distances accumulating from one branch to the next, mean values)::

    I    bct at 36 (right subclavian + right common carotid from its end); left common carotid at +16;
         left subclavian at +28
    II   bct at 36 (right subclavian + right common carotid from its end); left common carotid (_II) from the bct
         at 2/3 of its length (bovine arch); left subclavian at +41
    IV   right subclavian (_IV) at 42; common origin at +20 (right common carotid + left common carotid _II from its
         end: a bicarotid trunk); left subclavian (_IV) at +38
    Va   bct at 36 (right common carotid _V + left common carotid _II from its end); left subclavian at +41;
         right subclavian (_V, aberrant) at +20
    Vb   right common carotid (_VII) at 50; left common carotid at +22; left subclavian at +26; right subclavian
         (_V, aberrant) at +20
    VI   bct at 36 (right common carotid _V + left common carotid _II from its end); common origin at +50
         (right subclavian _VI + left subclavian _VI from its end: a bisubclavian trunk)
    VII  right subclavian (_IV) at 38; right common carotid (_VII) at +20; left common carotid at +20;
         left subclavian at +27

stEVE draws type V as Va or Vb with probability 1/2; ``"V"`` here is ``"Va"``. Its scalings (``AorticArchRandom``:
width scales ``x`` and ``y``, height ``z``, diameter the radii, about the origin, the descending aorta's start) are
``scale_width``, ``scale_height``, ``scale_diameter``.

Insertion: stEVE inserts the device at the aorta's second sample, along the first two samples — at the descending end
(diameter 17 mm, heading up ``+z``). Our wire enters at the main centreline's first point, so the main centreline is
a straight ``lead_in`` along ``+z`` (the aorta's entrance tangent, kept by the scalings) followed by the aorta.

Bends (:class:`Vessel3D` refuses a tube whose curvature × radius reaches 1): at the mean values the aorta reaches
0.42 and the other arteries at most 0.48, except stEVE's common-origin trunk (``common_origin_VI``: diameter 22 mm,
in types IV and VI), whose Hermite curve bends at radius 10.4 mm at its origin, where its radius is 11 mm (1.06),
and at 6.3 mm at its end, radius 6.07 mm (0.96; more when scaled). Sampling finer does not help (it is stEVE's curve,
not a sampling artefact), and we do not reshape stEVE's curves; instead every radius is clipped to
:data:`BEND_SAFETY` (0.95) × the bend radius of the spline next to that sample (:func:`_clip_to_bends`). At the mean
values this touches only the trunk: its first two samples 11.0 → 9.8 mm (its origin, inside the aorta's 12 mm
lumen, so the tree's lumen barely changes) and its last two 6.1 → 5.9 mm. All scalings in stEVE's range (0.7 to 1.3
each) then build. :func:`arch_bend_margins` reports the unclipped margins.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicHermiteSpline

from .tube import Tube
from .vessel import Branch3D, Vessel3D

FloatArray = NDArray[np.float64]

ARCH_TYPES = ("I", "II", "IV", "V", "Va", "Vb", "VI", "VII")
"""The arch types :func:`aortic_arch` builds (``"V"`` is ``"Va"``)."""

AORTA_RESOLUTION = 2.0
"""Sample spacing of the aorta (mm), stEVE's ``aorta_resolution``."""

BRANCH_RESOLUTION = 1.0
"""Sample spacing of the branches (mm), stEVE's ``resolution=1`` / ``bct_resolution``."""

CAROTID_TOP = 230.0
"""Height ``z`` (mm) where stEVE ends both common carotids."""


@dataclass(frozen=True)
class _Knot:
    """A control point: position (mm), slope direction (any length), slope magnitude, diameter (mm), d diameter."""

    point: tuple[float, float, float]
    direction: tuple[float, float, float]
    magnitude: float
    diameter: float
    d_diameter: float

    @property
    def value(self) -> FloatArray:
        return np.array([*self.point, self.diameter], dtype=float)

    @property
    def slope(self) -> FloatArray:
        d = np.asarray(self.direction, dtype=float)
        return np.append(d / np.linalg.norm(d) * self.magnitude, self.d_diameter)


@dataclass(frozen=True)
class _Artery:
    """A sampled artery: points (m, 3), radii (m,) and its last control point (for children that continue it)."""

    points: FloatArray
    radii: FloatArray
    end: _Knot

    @property
    def length(self) -> float:
        return float(np.sum(np.linalg.norm(np.diff(self.points, axis=0), axis=1)))


def _sample(knots: Sequence[_Knot], resolution: float) -> _Artery:
    """stEVE's ``chs_to_cl_points``: the Hermite spline in chord-length parameter, sampled every 0.1 and resampled
    every ``resolution`` mm of arc length from the start (radius = diameter / 2)."""
    values = np.array([k.value for k in knots])
    x = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(values[:, :3], axis=0), axis=1))))
    curve = CubicHermiteSpline(x, values, np.array([k.slope for k in knots]))
    fine = curve(np.arange(0.0, x[-1], 0.1))
    arc = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(fine[:, :3], axis=0), axis=1))))
    s = np.arange(0.0, arc[-1] + 1e-9, resolution)
    out = np.column_stack([np.interp(s, arc, fine[:, k]) for k in range(4)])
    return _Artery(out[:, :3], out[:, 3] / 2.0, knots[-1])


_AORTA_ENTRANCE_DIRECTION = np.array([0.0, 0.0, 1.0])


def _aorta() -> _Artery:
    return _sample((_Knot((0.0, 0.0, 0.0), tuple(_AORTA_ENTRANCE_DIRECTION), 1.0, 17.0, 0.02),
                    _Knot((30.0, 0.0, 90.0), (1.0, 0.0, 2.0), 1.2, 20.0, 0.02),
                    _Knot((20.0, -40.0, 160.0), (-4.0, -6.0, -0.5), 1.4, 24.0, 0.07),
                    _Knot((-5.0, -60.0, 100.0), (3.0, 4.0, -8.0), 1.6, 29.0, 0.0)), AORTA_RESOLUTION)


def _two(start: FloatArray, direction: Sequence[float], magnitude: float, diameter: float, d_diameter: float,
         end: Sequence[float], end_direction: Sequence[float], end_magnitude: float, end_diameter: float,
         end_d_diameter: float, resolution: float = BRANCH_RESOLUTION) -> _Artery:
    s = tuple(float(v) for v in start)
    return _sample((_Knot(s, tuple(direction), magnitude, diameter, d_diameter),
                    _Knot(tuple(float(v) for v in end), tuple(end_direction), end_magnitude, end_diameter,
                          end_d_diameter)), resolution)


def _bct(s: FloatArray, _: _Artery | None = None) -> _Artery:
    return _two(s, (0, -0.3, 1), 2.0, 17.0, 0.0, s + (-20, 5, 45), (-0.3, 0.3, 0.7), 0.8, 10.0, -0.1)


def _common_origin(s: FloatArray, _: _Artery | None = None) -> _Artery:
    return _two(s, (0, 0.6, 1), 1.0, 22.0, 0.0, s + (5, 5, 25), (-0.3, 0.3, 0.7), 0.8, 12.0, -0.1)


def _lcca(s: FloatArray, _: _Artery | None = None) -> _Artery:
    return _two(s, (0.3, 0, 1), 1.5, 10.0, 0.0, (s[0] + 2, s[1] + 8, CAROTID_TOP), (0, 0, 1), 1.5, 9.5, 0.0)


def _lcca_ii(s: FloatArray, _: _Artery | None = None) -> _Artery:
    return _two(s, (0.6, 0, 1), 1.5, 10.0, 0.0, (s[0] + 25, s[1] + 8, CAROTID_TOP), (0, 0, 1), 1.5, 9.5, 0.0)


def _lsa(s: FloatArray, _: _Artery | None = None, dz: float = 50.0, dy: float = 5.0,
         end_direction: Sequence[float] = (1, 0.3, 0)) -> _Artery:
    return _two(s, (0.1, 0.1, 2), 2.0, 10.0, 0.0, (59.0, s[1] + dy, s[2] + dz), end_direction, 1.7, 9.0, -0.1)


def _lsa_iv(s: FloatArray, _: _Artery | None = None) -> _Artery:
    return _lsa(s, dz=40.0)


def _lsa_vi(s: FloatArray, _: _Artery | None = None) -> _Artery:
    return _lsa(s, dz=20.0, dy=15.0, end_direction=(1, 0.3, -0.1))


def _rcca(s: FloatArray, _: _Artery | None = None) -> _Artery:
    return _two(s, (0.2, 0, 1), 1.5, 10.0, 0.0, (s[0], s[1], CAROTID_TOP), (0, 0, 1), 1.5, 9.0, 0.0)


def _rcca_v(s: FloatArray, parent: _Artery | None = None) -> _Artery:
    assert parent is not None
    return _two(s, parent.end.slope[:3], 1.5, 10.0, 0.0, (s[0], s[1], CAROTID_TOP), (0, 0, 1), 1.5, 9.0, 0.0)


def _rcca_vii(s: FloatArray, _: _Artery | None = None) -> _Artery:
    return _two(s, (0.2, 0, 1), 1.5, 10.0, 0.0, (s[0] - 10, s[1], CAROTID_TOP), (-0.2, 0, 1), 1.5, 9.0, 0.0)


def _rsa(s: FloatArray, parent: _Artery | None = None, dy: float = 35.0, dz: float = 25.0,
         end_direction: Sequence[float] = (-1.2, 0, 0)) -> _Artery:
    assert parent is not None
    e = parent.end
    return _two(s, e.slope[:3], 1.5, e.diameter, e.d_diameter, (-57.0, s[1] + dy, s[2] + dz), end_direction, 1.5,
                e.diameter, 0.0)


def _rsa_iv(s: FloatArray, _: _Artery | None = None) -> _Artery:
    return _two(s, (0.1, -0.1, 2), 3.0, 10.0, 0.0, (-57.0, s[1] + 2, s[2] + 50), (-1.2, 0, 0), 1.5, 10.0, 0.0)


def _rsa_v(s: FloatArray, _: _Artery | None = None) -> _Artery:
    return _two(s, (0.1, 0.1, 2), 2.0, 10.0, 0.0, (-57.0, s[1] + 2, s[2] + 42), (-1.2, -2.5, 0), 1.5, 10.0, 0.0)


def _rsa_vi(s: FloatArray, parent: _Artery | None = None) -> _Artery:
    return _rsa(s, parent, dy=15.0, dz=20.0, end_direction=(-0.6, 0, -0.1))


Maker = Callable[..., _Artery]

# Per type: (name, generator, parent name, where). ``where`` on the aorta is the cumulative mean distance (mm) from
# the aorta's ascending end, stEVE's ``idx += round(distance / aorta_resolution)``; on a branch, "end" (its last
# sample) or a fraction of its length (sample index round(fraction × length / resolution)).
_LAYOUT: dict[str, tuple[tuple[str, Maker, str, object], ...]] = {
    "I": (("brachiocephalic", _bct, "aorta", (36.0,)),
          ("right_common_carotid", _rcca, "brachiocephalic", "end"),
          ("right_subclavian", _rsa, "brachiocephalic", "end"),
          ("left_common_carotid", _lcca, "aorta", (36.0, 16.0)),
          ("left_subclavian", _lsa, "aorta", (36.0, 16.0, 28.0))),
    "II": (("brachiocephalic", _bct, "aorta", (36.0,)),
           ("right_common_carotid", _rcca, "brachiocephalic", "end"),
           ("right_subclavian", _rsa, "brachiocephalic", "end"),
           ("left_common_carotid", _lcca_ii, "brachiocephalic", 2.0 / 3.0),
           ("left_subclavian", _lsa, "aorta", (36.0, 41.0))),
    "IV": (("right_subclavian", _rsa_iv, "aorta", (42.0,)),
           ("bicarotid_trunk", _common_origin, "aorta", (42.0, 20.0)),
           ("right_common_carotid", _rcca, "bicarotid_trunk", "end"),
           ("left_common_carotid", _lcca_ii, "bicarotid_trunk", "end"),
           ("left_subclavian", _lsa_iv, "aorta", (42.0, 20.0, 38.0))),
    "Va": (("brachiocephalic", _bct, "aorta", (36.0,)),
           ("right_common_carotid", _rcca_v, "brachiocephalic", "end"),
           ("left_common_carotid", _lcca_ii, "brachiocephalic", "end"),
           ("left_subclavian", _lsa, "aorta", (36.0, 41.0)),
           ("right_subclavian", _rsa_v, "aorta", (36.0, 41.0, 20.0))),
    "Vb": (("right_common_carotid", _rcca_vii, "aorta", (50.0,)),
           ("left_common_carotid", _lcca, "aorta", (50.0, 22.0)),
           ("left_subclavian", _lsa, "aorta", (50.0, 22.0, 26.0)),
           ("right_subclavian", _rsa_v, "aorta", (50.0, 22.0, 26.0, 20.0))),
    "VI": (("brachiocephalic", _bct, "aorta", (36.0,)),
           ("right_common_carotid", _rcca_v, "brachiocephalic", "end"),
           ("left_common_carotid", _lcca_ii, "brachiocephalic", "end"),
           ("bisubclavian_trunk", _common_origin, "aorta", (36.0, 50.0)),
           ("right_subclavian", _rsa_vi, "bisubclavian_trunk", "end"),
           ("left_subclavian", _lsa_vi, "bisubclavian_trunk", "end")),
    "VII": (("right_subclavian", _rsa_iv, "aorta", (38.0,)),
            ("right_common_carotid", _rcca_vii, "aorta", (38.0, 20.0)),
            ("left_common_carotid", _lcca, "aorta", (38.0, 20.0, 20.0)),
            ("left_subclavian", _lsa, "aorta", (38.0, 20.0, 20.0, 27.0))),
}
_LAYOUT["V"] = _LAYOUT["Va"]

BRANCH_NAMES: dict[str, tuple[str, ...]] = {t: tuple(row[0] for row in rows) for t, rows in _LAYOUT.items()}
"""The named branches of each arch type, in the order :func:`aortic_arch` adds them."""

BRANCH_PARENTS: dict[str, dict[str, str]] = {t: {row[0]: row[2] for row in rows} for t, rows in _LAYOUT.items()}
"""Per arch type, each branch's parent (``"aorta"`` or the trunk it leaves from)."""


def _check_type(arch_type: str) -> str:
    if not isinstance(arch_type, str) or arch_type not in _LAYOUT:
        raise ValueError(f"arch_type is {arch_type!r}; expected one of {', '.join(ARCH_TYPES)} (stEVE's aortic arch "
                         "types; 'V' is 'Va').")
    return arch_type


def arch_arteries(arch_type: str = "I") -> dict[str, tuple[FloatArray, FloatArray]]:
    """stEVE's sampled arteries of ``arch_type`` at the mean values, unscaled and without a lead-in: ``{"aorta":
    (points (m, 3), radii (m,)), branch name: ..., }`` in mm, the aorta from its descending end."""
    rows = _LAYOUT[_check_type(arch_type)]
    aorta = _aorta()
    built: dict[str, _Artery] = {"aorta": aorta}
    for name, make, parent_name, where in rows:
        parent = built[parent_name]
        if where == "end":
            start = parent.points[-1]
        elif isinstance(where, tuple):
            index = sum(int(np.round(d / AORTA_RESOLUTION)) for d in where)
            start = parent.points[-index]
        else:
            start = parent.points[int(np.round(float(where) * parent.length / BRANCH_RESOLUTION))]
        built[name] = make(np.array(start, dtype=float), parent)
    return {name: (a.points, a.radii) for name, a in built.items()}


def aortic_arch(arch_type: str = "I", *, scale_width: float = 1.0, scale_height: float = 1.0,
                scale_diameter: float = 1.0, lead_in: float = 20.0) -> Vessel3D:
    """stEVE's aortic arch of ``arch_type`` (``"I"``, ``"II"``, ``"IV"``, ``"V"`` = ``"Va"``, ``"Vb"``, ``"VI"``,
    ``"VII"``) at its mean dimensions, as a :class:`Vessel3D` entered from the descending aorta.

    Parameters
    ----------
    arch_type : str
        Which supra-aortic branches leave the arch and how (see the module docstring and :data:`BRANCH_NAMES`).
    scale_width, scale_height, scale_diameter : float
        stEVE's scalings about the descending aorta's start: ``x`` and ``y`` by ``scale_width``, ``z`` by
        ``scale_height``, every radius by ``scale_diameter`` (stEVE draws each from 0.7 to 1.3).
    lead_in : float
        Length (mm, unscaled) of the straight tube before the aorta along its entrance tangent (``+z``), so that a
        clamp at the entrance meets a straight lumen; 0 for none.

    Returns
    -------
    Vessel3D
        Main centreline: the lead-in and the aorta (2 mm samples, descending end first, ascending root last);
        branches: :class:`Branch3D` named as in :data:`BRANCH_NAMES` (1 mm samples, first point on the parent's
        centreline). Named ``"aortic_arch_<type>"``.

    Raises
    ------
    ValueError
        ``arch_type`` is not one of :data:`ARCH_TYPES` (the message lists them), a scale is not positive, or a
        scaled tube bends tighter than its radius (:class:`Vessel3D`'s check).
    """
    _check_type(arch_type)
    for label, value in (("scale_width", scale_width), ("scale_height", scale_height),
                         ("scale_diameter", scale_diameter)):
        if not (math.isfinite(value) and value > 0.0):
            raise ValueError(f"{label} is {value!r}; expected a positive scale factor (stEVE draws 0.7 to 1.3).")
    if not (math.isfinite(lead_in) and lead_in >= 0.0):
        raise ValueError(f"lead_in is {lead_in!r}; expected a length >= 0 (mm).")
    arteries = arch_arteries(arch_type)
    xyz = np.array([scale_width, scale_width, scale_height])
    scaled = {name: (p * xyz, r * scale_diameter) for name, (p, r) in arteries.items()}
    points, radii = scaled.pop("aorta")
    tangent = _AORTA_ENTRANCE_DIRECTION * xyz  # the Hermite slope at the descending end, scaled
    tangent /= np.linalg.norm(tangent)
    count = int(math.ceil(lead_in / AORTA_RESOLUTION - 1e-9))
    if count:
        lead = points[0] - np.outer(np.linspace(lead_in, lead_in / count, count), tangent)
        points = np.vstack((lead, points))
        radii = np.concatenate((np.full(count, radii[0]), radii))
    branches = [Branch3D(p, _clip_to_bends(p, r), name) for name, (p, r) in scaled.items()]
    return Vessel3D.from_centreline(points, _clip_to_bends(points, radii), branches, name=f"aortic_arch_{arch_type}")


BEND_SAFETY = 0.95
"""Radii are clipped to this fraction of the local bend radius (:func:`_clip_to_bends`)."""


def _bend_ratio(points: FloatArray, radii: FloatArray) -> FloatArray:
    """Per sample: the largest curvature of the tube's spline on the two intervals next to it (1/mm)."""
    tube = Tube(points, np.ones(len(points)))
    u = tube.u[tube.u <= tube.end]
    e = tube.evaluate(u)
    kappa = np.linalg.norm(np.cross(e.d1, e.d2), axis=1) / np.linalg.norm(e.d1, axis=1) ** 3
    interval = np.clip(np.searchsorted(tube.breaks, u, side="right") - 1, 0, len(points) - 2)
    worst = np.zeros(len(points) - 1)
    np.maximum.at(worst, interval, kappa)
    return np.maximum(np.concatenate((worst[:1], worst)), np.concatenate((worst, worst[-1:])))


def _clip_to_bends(points: FloatArray, radii: FloatArray) -> FloatArray:
    """Radii no larger than :data:`BEND_SAFETY` × the bend radius next to each sample, so that the tube (PCHIP radius,
    no overshoot between samples) passes :class:`Vessel3D`'s bend check; stEVE's radii where they already do."""
    return np.minimum(radii, BEND_SAFETY / np.maximum(_bend_ratio(points, radii), 1e-300))


def arch_bend_margins(arch_type: str = "I", **scales: float) -> dict[str, float]:
    """Per artery of ``arch_type`` (``scales``: those of :func:`aortic_arch`): the largest curvature × radius with
    stEVE's radii (≥ 1 would be refused by :class:`Vessel3D`; :func:`aortic_arch` clips those radii)."""
    w, h, d = (scales.get(k, 1.0) for k in ("scale_width", "scale_height", "scale_diameter"))
    out = {}
    for name, (p, r) in arch_arteries(arch_type).items():
        out[name] = float(np.max(_bend_ratio(p * (w, w, h), r) * r * d))
    return out
