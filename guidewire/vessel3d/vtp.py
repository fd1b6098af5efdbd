"""VMTK centreline files (``.vtp`` PolyData) to and from :class:`~guidewire.vessel3d.vessel.Vessel3D`; needs the
optional ``vtk`` package (``pip install "guidewire-sqp[vtk]"``, the distribution that ships :mod:`guidewire`).

The layout (``vmtkcenterlines``): polylines, one per centreline, each running from the common inlet to one outlet, so
they overlap along shared trunks; the point array ``MaximumInscribedSphereRadius`` (the radius of the largest sphere
inside the lumen centred there); the cell array ``CenterlineIds``. After ``vmtkbranchextractor`` each centreline is
split into tracts (one cell each) with the cell arrays ``CenterlineIds``, ``TractIds`` (order along the centreline)
and ``GroupIds``; a file may instead carry ``BranchId``/``BranchIds`` with one cell per branch segment.

Reading (:func:`read_centerlines`)
----------------------------------
1. Centrelines: cells grouped by ``CenterlineIds`` (cell or point array), their tracts joined in ``TractIds`` order
   (else in file order), consecutive repeated points dropped. Without ``CenterlineIds``, a ``BranchId(s)`` file's
   segments are chained (a segment continues the one whose last point is nearest its first, when that is within its
   first radius) and every root-to-leaf chain becomes a centreline. One cell needs neither array.
2. The main vessel is the longest centreline (arc length) or the one the caller picks (``main``, a ``CenterlineIds``
   value or a chain's index); ``entrance`` (a point) turns it around when its last point is the nearer end.
3. Every other centreline, in ``CenterlineIds`` order, becomes a :class:`Branch3D` from where it leaves the tree built
   so far: its first point farther than the local radius (of the tube it is in, linear in the polyline) from every
   centreline kept so far, stepping back at least one point and until the point is within 3/4 of that radius, so
   it starts inside the parent's lumen (:class:`Vessel3D` checks the spline tube). A centreline that never leaves
   the tree adds nothing and is dropped.
4. Radii are ``MaximumInscribedSphereRadius``. It overestimates near junctions (the inscribed sphere there touches
   the walls of both vessels), so a branch's first radii are those of the junction; where that (or noise in the
   centreline) makes a tube bend tighter than its radius, which :class:`Vessel3D` refuses, the radius is clipped to
   0.95 × the local bend radius of the spline (:func:`guidewire.vessel3d.arch._clip_to_bends`; the clip only narrows
   the lumen), but never below half the file's value (:data:`CLIP_FLOOR`): a sharper corner is a kink in the data
   (e.g. the longest centreline turning into a side branch at an angle) and the ``ValueError`` names the point and
   the main centreline, so that another can be chosen with ``main``. Nothing is smoothed.
5. ``units_scale`` multiplies coordinates and radii (VMTK keeps the image's units, usually mm; 10 for cm).

Writing (:func:`write_centerlines`, in :mod:`~guidewire.vessel3d.vtp_write`)
----------------------------------------------------------------------------
One polyline per tube end, in tube order (main first): the path from the entrance through the parent tubes (each cut
at its sample nearest the child's first point) to the tube's last point, with ``CenterlineIds`` (cell),
``MaximumInscribedSphereRadius`` (point, the vessel's radii) — VMTK's layout, read back by the VMTK rules above. A
trunk that ends where its children start (stEVE's brachiocephalic) gets its own polyline, which VMTK would not have;
read back it is still one branch. Points and radii are doubles. Two extra arrays make the round trip exact: the point
array ``GuidewireTubeIds`` (which tube a point comes from) and the field array ``GuidewireTubeNames`` (with the
vessel's name last); :func:`read_centerlines` uses them when present (``use_tube_ids=True``), giving back the same
centrelines, radii and names.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .arch import _clip_to_bends
from .vessel import Branch3D, Vessel3D

FloatArray = NDArray[np.float64]

RADIUS_ARRAY = "MaximumInscribedSphereRadius"
CENTERLINE_IDS = "CenterlineIds"
TRACT_IDS = "TractIds"
BRANCH_IDS = ("BranchId", "BranchIds")
TUBE_IDS = "GuidewireTubeIds"
TUBE_NAMES = "GuidewireTubeNames"

CLIP_FLOOR = 0.5
"""Radii are clipped to the bends (module docstring, 4) down to this fraction of the file's values, no further."""

INSTALL_HINT = 'pip install "guidewire-sqp[vtk]"'
_VTK_MODULES = ("vtkmodules.vtkCommonCore", "vtkmodules.vtkCommonDataModel", "vtkmodules.vtkIOXML")

EXAMPLE_VTP = Path(__file__).resolve().parent.parent / "scenes" / "vessels3d" / "arch_type_I.vtp"
"""The shipped example: :func:`~guidewire.vessel3d.arch.aortic_arch` type I written by :func:`write_centerlines`
(``benchmarks/make_vtp_example.py``)."""


def _vtk() -> Any:
    """The vtk modules used here, or an ImportError saying how to install them."""
    try:
        from vtkmodules import vtkCommonCore, vtkCommonDataModel, vtkIOXML
    except ImportError as error:
        raise ImportError(f"reading and writing VMTK centreline files (.vtp) needs the vtk package: {INSTALL_HINT} "
                          f"(or pip install vtk); {error}") from None

    class _Modules:
        core, data, io = vtkCommonCore, vtkCommonDataModel, vtkIOXML

    return _Modules


# -- reading -----------------------------------------------------------------------------------------------------
def _array(data: Any, name: str) -> NDArray[Any] | None:
    arr = data.GetArray(name)
    if arr is None:
        return None
    from vtkmodules.util.numpy_support import vtk_to_numpy

    return np.array(vtk_to_numpy(arr), dtype=float)


def _dedup(ids: NDArray[np.int64], points: FloatArray) -> NDArray[np.int64]:
    """Drop consecutive repeated points (by id and by position)."""
    if len(ids) < 2:
        return ids
    keep = np.ones(len(ids), dtype=bool)
    keep[1:] = np.any(points[ids[1:]] != points[ids[:-1]], axis=1)
    return ids[keep]


def _length(p: FloatArray) -> float:
    return float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1)))


def _distance_to(points: FloatArray, line: FloatArray, radii: FloatArray,
                 chunk: int = 256) -> tuple[FloatArray, FloatArray]:
    """Per point: the distance to the polyline ``line`` and its radius (linear along the segment) there; in chunks
    of points, so memory stays ``chunk × len(line)``."""
    a, b = line[:-1], line[1:]
    ab = b - a
    ll = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    dist, rad = np.empty(len(points)), np.empty(len(points))
    for lo in range(0, len(points), chunk):
        p = points[lo:lo + chunk]
        t = np.clip(np.einsum("pij,ij->pi", p[:, None, :] - a[None], ab) / ll, 0.0, 1.0)
        d = np.linalg.norm(p[:, None, :] - (a[None] + t[..., None] * ab[None]), axis=2)
        j = np.argmin(d, axis=1)
        rows = np.arange(len(p))
        dist[lo:lo + chunk] = d[rows, j]
        rad[lo:lo + chunk] = radii[:-1][j] + t[rows, j] * (radii[1:][j] - radii[:-1][j])
    return dist, rad


def _chains(cells: list[NDArray[np.int64]], points: FloatArray, radius: FloatArray) -> list[NDArray[np.int64]]:
    """Root-to-leaf chains of branch segments: a segment continues the one whose last point is nearest its first,
    when that is within its first radius."""
    parent: dict[int, int | None] = {}
    ends = np.array([points[c[-1]] for c in cells])
    for i, c in enumerate(cells):
        d = np.linalg.norm(ends - points[c[0]], axis=1)
        d[i] = np.inf
        j = int(np.argmin(d))
        parent[i] = j if d[j] <= radius[c[0]] else None
    children = {i: [k for k, p in parent.items() if p == i] for i in parent}
    out = []
    for leaf in (i for i in parent if not children[i]):
        chain, node, seen = [], leaf, set()
        while node is not None and node not in seen:
            seen.add(node)
            chain.append(cells[node])
            node = parent[node]
        out.append(np.concatenate(chain[::-1]))
    return out


def read_centerlines(path: str | os.PathLike[str], *, name: str | None = None, entrance: Any = None,
                     main: int | None = None, units_scale: float = 1.0, use_tube_ids: bool = True) -> Vessel3D:
    """A :class:`Vessel3D` from a VMTK centreline file (see the module docstring for the rules).

    Parameters
    ----------
    path : str or os.PathLike
        A ``.vtp`` PolyData of polylines with the point array ``MaximumInscribedSphereRadius`` and ``CenterlineIds``
        (or ``BranchId``) when it has more than one polyline.
    name : str, optional
        The vessel's name; default the file's stem (or the name stored by :func:`write_centerlines`).
    entrance : (3,) array_like, optional
        A point (file units) near the end where the wire enters the main centreline; default its first point (VMTK's
        inlet).
    main : int, optional
        The ``CenterlineIds`` value (or chain index) of the main vessel; default the longest centreline.
    units_scale : float
        Multiplies coordinates and radii into mm (10 for a file in cm).
    use_tube_ids : bool
        Use the ``GuidewireTubeIds`` array written by :func:`write_centerlines` when present (exact round trip).

    Raises
    ------
    ImportError
        ``vtk`` is not installed (the message says ``pip install "guidewire-sqp[vtk]"``).
    FileNotFoundError, ValueError
        No such file; a file without polylines or without a needed array (named, with the path); a centreline that
        starts outside the lumen; or :class:`Vessel3D`'s checks.
    """
    vtk = _vtk()
    path = _checked_arguments(path, units_scale)
    poly, lines = _read_polydata(vtk, path)
    points, radius = _points_and_radii(poly, path, units_scale)
    cells = _polylines(vtk, lines)
    tube_ids = _array(poly.GetPointData(), TUBE_IDS) if use_tube_ids else None
    stored = _strings(poly.GetFieldData(), TUBE_NAMES)
    default_name = _vessel_name(name, stored, path)
    entrance = None if entrance is None else np.asarray(entrance, dtype=float) * units_scale
    if tube_ids is not None:
        return _from_tube_ids(cells, points, radius, tube_ids.astype(int), stored, default_name, entrance)
    keys, paths = _centrelines(path, poly, cells, points, radius)
    paths = [_dedup(p, points) for p in paths]
    lines_xyz = [points[p] for p in paths]
    lines_r = [radius[p] for p in paths]
    first = _main_index(path, lines_xyz, keys, main)
    xyz, r = _oriented(lines_xyz[first], lines_r[first], entrance)
    others = [(keys[k], lines_xyz[k], lines_r[k]) for k in range(len(paths)) if k != first]
    branches = _branches(path, (xyz, r), others)
    try:
        return Vessel3D.from_centreline(xyz, _clip(xyz, r), branches, name=default_name)
    except ValueError as error:
        raise ValueError(f"{path}: {error} (main vessel: centreline {keys[first]}"
                         f"{', the longest' if main is None else ''}; branches: centrelines "
                         f"{[b.name.removeprefix('centerline_') for b in branches]}; choose another main "
                         "centreline with main=...)") from None


def _checked_arguments(path: str | os.PathLike[str], units_scale: float) -> Path:
    """The file's path, checked to exist, and ``units_scale`` checked to be positive, before vtk reads anything."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such VMTK centreline file.")
    if not (np.isfinite(units_scale) and units_scale > 0.0):
        raise ValueError(f"units_scale is {units_scale!r}; expected a positive factor (10 for a file in cm).")
    return path


def _vessel_name(name: str | None, stored: list[str], path: Path) -> str:
    """The caller's name, else the one :func:`write_centerlines` stored (last of its tube names), else the stem."""
    return name if name is not None else (stored[-1] if stored else path.stem)


def _read_polydata(vtk: Any, path: Path) -> tuple[Any, Any]:
    """The file's PolyData and its polylines; a ValueError when it has no points or no polylines."""
    reader = vtk.io.vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    poly = reader.GetOutput()
    lines = poly.GetLines() if poly is not None else None
    if poly is None or poly.GetNumberOfPoints() == 0 or lines is None or lines.GetNumberOfCells() == 0:
        raise ValueError(f"{path}: no polylines (is it a VTK XML PolyData of centrelines, e.g. from vmtkcenterlines?)")
    return poly, lines


def _points_and_radii(poly: Any, path: Path, units_scale: float) -> tuple[FloatArray, FloatArray]:
    """The points (n, 3) and their radii (``MaximumInscribedSphereRadius``, required), times ``units_scale``."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    points = np.array(vtk_to_numpy(poly.GetPoints().GetData()), dtype=float).reshape(-1, 3) * units_scale
    radius = _array(poly.GetPointData(), RADIUS_ARRAY)
    if radius is None:
        raise ValueError(f"{path}: no point array {RADIUS_ARRAY!r} (the centreline radii; vmtkcenterlines writes it), "
                         f"point arrays: {_names(poly.GetPointData())}.")
    return points, radius * units_scale


def _polylines(vtk: Any, lines: Any) -> list[NDArray[np.int64]]:
    """The point ids of each polyline, in file order."""
    cells: list[NDArray[np.int64]] = []
    ids = vtk.core.vtkIdList()
    lines.InitTraversal()
    while lines.GetNextCell(ids):
        cells.append(np.array([ids.GetId(k) for k in range(ids.GetNumberOfIds())], dtype=np.int64))
    return cells


def _per_cell(poly: Any, cells: list[NDArray[np.int64]], array_name: str) -> NDArray[Any] | None:
    """One value per polyline: the cell array's, else the point array's at its first point (or None)."""
    v = _array(poly.GetCellData(), array_name)
    if v is not None:
        offset = poly.GetNumberOfVerts()  # cells of vtkPolyData.GetLines() are numbered after the vertices
        return v[offset:offset + len(cells)]
    v = _array(poly.GetPointData(), array_name)
    return None if v is None else np.array([v[c[0]] for c in cells])


def _centrelines(path: Path, poly: Any, cells: list[NDArray[np.int64]], points: FloatArray,
                 radius: FloatArray) -> tuple[list[int], list[NDArray[np.int64]]]:
    """The centrelines' keys and point ids, by ``CenterlineIds`` or ``BranchId(s)`` (module docstring, 1)."""
    centreline_ids = _per_cell(poly, cells, CENTERLINE_IDS)
    if centreline_ids is not None:
        return _grouped(cells, centreline_ids, _per_cell(poly, cells, TRACT_IDS))
    branch_ids = next((v for v in (_per_cell(poly, cells, n) for n in BRANCH_IDS) if v is not None), None)
    if branch_ids is None and len(cells) != 1:
        raise ValueError(f"{path}: {len(cells)} polylines but no cell array {CENTERLINE_IDS!r} (nor "
                         f"{' or '.join(map(repr, BRANCH_IDS))}) to tell which centreline each belongs to; cell "
                         f"arrays: {_names(poly.GetCellData())}.")
    paths = _chains(cells, points, radius) if len(cells) > 1 else cells
    return list(range(len(paths))), paths


def _grouped(cells: list[NDArray[np.int64]], centreline_ids: NDArray[Any],
             tracts: NDArray[Any] | None) -> tuple[list[int], list[NDArray[np.int64]]]:
    """Per ``CenterlineIds`` value (sorted): its cells joined in ``TractIds`` order, else in file order."""
    order = np.arange(len(cells)) if tracts is None else tracts
    keys = sorted({int(v) for v in centreline_ids})
    paths = []
    for key in keys:
        mine = [i for i in range(len(cells)) if int(centreline_ids[i]) == key]
        mine.sort(key=lambda i: (order[i], i))
        paths.append(np.concatenate([cells[i] for i in mine]))
    return keys, paths


def _main_index(path: Path, lines_xyz: list[FloatArray], keys: list[int], main: int | None) -> int:
    """Which centreline is the main vessel: the longest (arc length), or the one whose key is ``main``."""
    if main is None:
        return int(np.argmax([_length(p) for p in lines_xyz]))
    if main in keys:
        return keys.index(main)
    raise ValueError(f"{path}: main={main!r} is not a centreline id; ids: {keys}.")


def _oriented(xyz: FloatArray, r: FloatArray, entrance: FloatArray | None) -> tuple[FloatArray, FloatArray]:
    """The centreline and its radii reversed when its last point is nearer ``entrance`` than its first."""
    if entrance is not None and np.linalg.norm(xyz[-1] - entrance) < np.linalg.norm(xyz[0] - entrance):
        return xyz[::-1], r[::-1]
    return xyz, r


def _branches(path: Path, main: tuple[FloatArray, FloatArray],
              others: list[tuple[int, FloatArray, FloatArray]]) -> list[Branch3D]:
    """The other centrelines as branches from where each leaves the tree built so far (module docstring, 3)."""
    kept = [main]
    branches = []
    for key, p, pr in others:
        start = _branch_start(path, key, p, kept)
        if start is None:
            continue  # inside the tree all along: adds nothing
        bp, br = p[start:], pr[start:]
        kept.append((bp, br))
        branches.append(Branch3D(bp, _clip(bp, br), f"centerline_{key}"))
    return branches


def _branch_start(path: Path, key: int, p: FloatArray, kept: list[tuple[FloatArray, FloatArray]]) -> int | None:
    """Where ``p`` starts as a branch, inside its parent's lumen (module docstring, 3); None if it never leaves."""
    d, local = _distance_to_tree(p, kept)
    outside = np.flatnonzero(d >= local)
    if not outside.size:
        return None
    leave = int(outside[0])
    if leave == 0:
        raise ValueError(f"{path}: centreline {key} starts at {p[0].tolist()}, outside the lumen of the "
                         "centrelines before it; VMTK centrelines share their inlet.")
    start = leave - 1
    while start > 0 and d[start] > 0.75 * local[start]:
        start -= 1
    return start


def _distance_to_tree(p: FloatArray, kept: list[tuple[FloatArray, FloatArray]]) -> tuple[FloatArray, FloatArray]:
    """Per point of ``p``: distance to, and local radius of, the kept centreline it is deepest inside."""
    d = np.full(len(p), np.inf)
    local = np.zeros(len(p))
    for q, qr in kept:
        dq, rq = _distance_to(p, q, qr)
        better = dq - rq < d - local
        d, local = np.where(better, dq, d), np.where(better, rq, local)
    return d, local


def _clip(points: FloatArray, radii: FloatArray) -> FloatArray:
    """:func:`~guidewire.vessel3d.arch._clip_to_bends`, but never below :data:`CLIP_FLOOR` of the file's radius: a
    tighter corner is a kink in the data, left for :class:`Vessel3D` to report."""
    return np.maximum(_clip_to_bends(points, radii), CLIP_FLOOR * radii)


def _from_tube_ids(cells: list[NDArray[np.int64]], points: FloatArray, radius: FloatArray, tube_ids: NDArray[Any],
                   names: list[str], name: str, entrance: Any) -> Vessel3D:
    """The tubes written by :func:`write_centerlines`: tube k is the longest run of points with id k in a cell."""
    best: dict[int, NDArray[np.int64]] = {}
    for c in cells:
        t = tube_ids[c]
        cut = np.flatnonzero(np.diff(t)) + 1
        for run in np.split(c, cut):
            k = int(tube_ids[run[0]])
            if k not in best or len(run) > len(best[k]):
                best[k] = run
    order = sorted(best)
    main = best[order[0]]
    xyz, r = _oriented(points[main], radius[main], entrance)
    branches = [Branch3D(points[best[k]], radius[best[k]], names[k] if k < len(names) - 1 else "") for k in order[1:]]
    return Vessel3D.from_centreline(xyz, r, branches, name=name)


def _names(data: Any) -> list[str]:
    return [data.GetArrayName(i) for i in range(data.GetNumberOfArrays())]


def _strings(data: Any, array_name: str) -> list[str]:
    arr = data.GetAbstractArray(array_name)
    if arr is None:
        return []
    return [arr.GetValue(i) for i in range(arr.GetNumberOfValues())]


from .vtp_write import write_centerlines  # noqa: E402  (the writer imports this module's array names)

__all__ = ["EXAMPLE_VTP", "read_centerlines", "write_centerlines"]
