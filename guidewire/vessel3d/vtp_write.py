"""Writing VMTK centreline files (``.vtp``): :func:`write_centerlines`, re-exported by :mod:`guidewire.vessel3d.vtp`,
whose module docstring describes the layout written ("Writing") and how :func:`~guidewire.vessel3d.vtp.read_centerlines`
reads it back."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .vessel import Vessel3D
from .vtp import CENTERLINE_IDS, RADIUS_ARRAY, TUBE_IDS, TUBE_NAMES, _vtk


def _tube_paths(vessel: Vessel3D) -> list[tuple[list[int], list[int]]]:
    """Per tube: (tube index, sample index) pairs from the entrance to its last sample (vtp docstring, "Writing")."""
    lines = [np.array(vessel.centreline)] + [np.array(b.centreline) for b in vessel.branches]
    paths: list[list[tuple[int, int]]] = [[(0, i) for i in range(len(lines[0]))]]
    for k in range(1, len(lines)):
        start = lines[k][:1]
        g = [float(t.rows(start, np.zeros(1))[0][0]) for t in vessel.tubes[:k]]
        parent = int(np.argmax(g))
        j = int(np.argmin(np.linalg.norm(lines[parent] - start, axis=1)))
        head = [pair for pair in paths[parent] if pair[0] != parent or pair[1] <= j]
        if np.array_equal(lines[parent][j], start[0]):
            head = head[:-1]
        paths.append(head + [(k, i) for i in range(len(lines[k]))])
    return [([t for t, _ in p], [i for _, i in p]) for p in paths]


def write_centerlines(vessel: Vessel3D, path: str | os.PathLike[str]) -> Path:
    """Save ``vessel`` as a VMTK centreline file (``.vtp``, see the module docstring); returns the path."""
    vtk = _vtk()
    if not isinstance(vessel, Vessel3D):
        raise TypeError(f"vessel is {type(vessel).__name__}; expected a guidewire.vessel3d.Vessel3D.")
    lines = [np.array(vessel.centreline)] + [np.array(b.centreline) for b in vessel.branches]
    radii = [np.broadcast_to(np.asarray(vessel.radius, dtype=float), (len(lines[0]),))]
    radii += [np.broadcast_to(np.asarray(b.radius, dtype=float), (len(b.centreline),)) for b in vessel.branches]
    pts = vtk.core.vtkPoints()
    pts.SetDataTypeToDouble()
    rad = vtk.core.vtkDoubleArray()
    rad.SetName(RADIUS_ARRAY)
    tube = vtk.core.vtkIntArray()
    tube.SetName(TUBE_IDS)
    cid = vtk.core.vtkIntArray()
    cid.SetName(CENTERLINE_IDS)
    cells = vtk.data.vtkCellArray()
    for c, (tubes, samples) in enumerate(_tube_paths(vessel)):
        cells.InsertNextCell(len(tubes))
        for t, i in zip(tubes, samples, strict=True):
            cells.InsertCellPoint(pts.InsertNextPoint(*lines[t][i]))
            rad.InsertNextValue(float(radii[t][i]))
            tube.InsertNextValue(t)
        cid.InsertNextValue(c)
    names = vtk.core.vtkStringArray()
    names.SetName(TUBE_NAMES)
    for label in ["", *(b.name for b in vessel.branches), vessel.name]:
        names.InsertNextValue(label)
    poly = vtk.data.vtkPolyData()
    poly.SetPoints(pts)
    poly.SetLines(cells)
    poly.GetPointData().AddArray(rad)
    poly.GetPointData().AddArray(tube)
    poly.GetCellData().AddArray(cid)
    poly.GetFieldData().AddArray(names)
    writer = vtk.io.vtkXMLPolyDataWriter()
    out = Path(path)
    writer.SetFileName(str(out))
    writer.SetInputData(poly)
    writer.SetDataModeToBinary()
    if not writer.Write():
        raise OSError(f"{out}: vtk could not write the file.")
    return out


__all__ = ["write_centerlines"]
