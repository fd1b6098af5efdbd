"""VMTK centreline files (guidewire.vessel3d.vtp): round trips, the VMTK rules, the shipped example, bad files."""

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

from guidewire.vessel3d import BRANCH_NAMES, Vessel3D, aortic_arch, read_centerlines, write_centerlines
from guidewire.vessel3d.vtp import EXAMPLE_VTP, RADIUS_ARRAY

needs_vtk = pytest.mark.skipif(importlib.util.find_spec("vtk") is None,
                               reason='vtk is not installed (pip install "guidewire-sqp[vtk]", part of [dev])')


def _write_poly(path: Path, lines: list[tuple[np.ndarray, np.ndarray]], cell_arrays: dict[str, list[int]],
                radius: bool = True) -> Path:
    """A hand-made VMTK-like file: polylines with radii and integer cell arrays."""
    from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    pts, cells, rad = vtkPoints(), vtkCellArray(), vtkDoubleArray()
    pts.SetDataTypeToDouble()
    rad.SetName(RADIUS_ARRAY)
    for p, r in lines:
        cells.InsertNextCell(len(p))
        for x, ri in zip(p, r, strict=True):
            cells.InsertCellPoint(pts.InsertNextPoint(*x))
            rad.InsertNextValue(float(ri))
    poly = vtkPolyData()
    poly.SetPoints(pts)
    if lines:
        poly.SetLines(cells)
    if radius:
        poly.GetPointData().AddArray(rad)
    for name, values in cell_arrays.items():
        arr = vtkIntArray()
        arr.SetName(name)
        for v in values:
            arr.InsertNextValue(v)
        poly.GetCellData().AddArray(arr)
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(poly)
    assert writer.Write()
    return path


def _y_tree() -> list[tuple[np.ndarray, np.ndarray]]:
    """Two VMTK centrelines from a common inlet: a straight trunk (z, radius 3 mm) and one bending off at z = 40."""
    z = np.arange(0.0, 101.0, 1.0)
    main = np.column_stack((0 * z, 0 * z, z))
    t = np.arange(0.0, 60.0, 1.0)
    side = np.column_stack((20.0 * (1 - np.cos(t / 40.0)), 0 * t, 40.0 + 20.0 * np.sin(t / 40.0) * 2.0))
    other = np.vstack((main[:40], side))
    return [(main, np.full(len(main), 3.0)), (other, np.concatenate((np.full(40, 3.0), np.full(len(side), 2.0))))]


@needs_vtk
@pytest.mark.parametrize("arch_type", ["I", "IV", "VI", "VII"])
def test_round_trip_is_exact(tmp_path: Path, arch_type: str) -> None:
    v = aortic_arch(arch_type)
    out = write_centerlines(v, tmp_path / "arch.vtp")
    assert 'type="Float64" Name="MaximumInscribedSphereRadius"' in out.read_text(errors="replace")
    back = read_centerlines(out)
    assert back == v  # centrelines, radii and names to the last bit (doubles)
    assert [b.name for b in back.branches] == list(BRANCH_NAMES[arch_type])


@needs_vtk
@pytest.mark.parametrize("arch_type", ["I", "IV", "VII"])
def test_vmtk_rules_rebuild_the_tree(tmp_path: Path, arch_type: str) -> None:
    """Without our tube ids, by VMTK's rules alone (main = centreline 0, the aorta)."""
    v = aortic_arch(arch_type)
    back = read_centerlines(write_centerlines(v, tmp_path / "arch.vtp"), use_tube_ids=False, main=0)
    assert back.centreline == v.centreline and back.radius == v.radius
    assert len(back.branches) == len(v.branches)
    for b, orig in zip(back.branches, v.branches, strict=True):
        p, q = np.array(b.centreline), np.array(orig.centreline)
        k = len(q) - len(p)
        assert 0 <= k < len(q) // 2 + 1 and np.array_equal(p, q[k:])  # the original from where it leaves the tree
        r, r0 = np.array(b.radius), np.array(orig.radius)[k:]
        assert np.all(r <= r0) and np.mean(r == r0) > 0.9
    # the longest centreline (aorta → right subclavian) turns into a branch at an angle: refused, with advice
    if arch_type == "I":
        with pytest.raises(ValueError, match="the longest.*main="):
            read_centerlines(tmp_path / "arch.vtp", use_tube_ids=False)


@needs_vtk
def test_shipped_example_is_the_type_I_arch() -> None:
    assert EXAMPLE_VTP.is_file()
    v, arch = read_centerlines(EXAMPLE_VTP), aortic_arch("I")
    assert v == arch
    p, t = v.entrance
    p0, t0 = arch.entrance
    assert np.array_equal(p, p0) and np.allclose(t, t0, atol=1e-12)
    assert [b.name for b in v.branches] == list(BRANCH_NAMES["I"]) and v.name == "aortic_arch_I"


@needs_vtk
def test_centreline_ids_tracts_units_and_entrance(tmp_path: Path) -> None:
    (main, rm), (other, ro) = _y_tree()
    plain = read_centerlines(_write_poly(tmp_path / "y.vtp", _y_tree(), {"CenterlineIds": [0, 1]}))
    assert plain.centreline == tuple(map(tuple, main)) and len(plain.branches) == 1
    b = np.array(plain.branches[0].centreline)
    d = np.hypot(b[:, 0], b[:, 1])
    assert d[0] < 3.0 and np.array_equal(b[-1], other[-1])  # starts in the trunk's lumen, ends at the outlet
    assert plain.branches[0].name == "centerline_1" and plain.name == "y"
    # vmtkbranchextractor: tracts of each centreline, out of order in the file, with TractIds
    tracts = [(main[50:], rm[50:]), (other[:30], ro[:30]), (main[:51], rm[:51]), (other[29:], ro[29:])]
    split = read_centerlines(_write_poly(tmp_path / "t.vtp", tracts, {"CenterlineIds": [0, 1, 0, 1],
                                                                       "TractIds": [1, 0, 0, 1]}), name="split")
    assert split.centreline == plain.centreline and split.branches == plain.branches and split.name == "split"
    # a file in cm
    cm = read_centerlines(_write_poly(tmp_path / "cm.vtp", [(p / 10, r / 10) for p, r in _y_tree()],
                                      {"CenterlineIds": [0, 1]}), units_scale=10.0)
    assert np.allclose(cm.centreline, plain.centreline, atol=1e-12) and np.allclose(cm.radius, 3.0)
    # entering from the far end of the main centreline
    rev = read_centerlines(tmp_path / "y.vtp", entrance=(0.0, 0.0, 100.0))
    assert np.allclose(rev.entrance[0], (0.0, 0.0, 100.0)) and np.allclose(rev.entrance[1], (0.0, 0.0, -1.0))
    assert len(rev.branches) == 1
    # choosing the main centreline
    assert np.array_equal(read_centerlines(tmp_path / "y.vtp", main=1).centreline, tuple(map(tuple, other)))


@needs_vtk
def test_branch_id_segments_are_chained(tmp_path: Path) -> None:
    (main, rm), (other, ro) = _y_tree()
    segments = [(main[:40], rm[:40]), (main[39:], rm[39:]), (other[39:], ro[39:])]
    v = read_centerlines(_write_poly(tmp_path / "b.vtp", segments, {"BranchId": [0, 1, 2]}))
    plain = read_centerlines(_write_poly(tmp_path / "y.vtp", _y_tree(), {"CenterlineIds": [0, 1]}))
    assert v.centreline == plain.centreline and len(v.branches) == 1
    assert v.branches[0].centreline == plain.branches[0].centreline
    assert isinstance(v, Vessel3D)


@needs_vtk
def test_bad_files_name_what_is_missing(tmp_path: Path) -> None:
    no_radius = _write_poly(tmp_path / "r.vtp", _y_tree(), {"CenterlineIds": [0, 1]}, radius=False)
    with pytest.raises(ValueError, match=f"{RADIUS_ARRAY}") as info:
        read_centerlines(no_radius)
    assert str(no_radius) in str(info.value)
    no_ids = _write_poly(tmp_path / "i.vtp", _y_tree(), {})
    with pytest.raises(ValueError, match="CenterlineIds") as info:
        read_centerlines(no_ids)
    assert str(no_ids) in str(info.value)
    empty = _write_poly(tmp_path / "e.vtp", [], {})
    with pytest.raises(ValueError, match="no polylines"):
        read_centerlines(empty)
    with pytest.raises(FileNotFoundError, match="nothing.vtp"):
        read_centerlines(tmp_path / "nothing.vtp")
    good = _write_poly(tmp_path / "y.vtp", _y_tree(), {"CenterlineIds": [0, 1]})
    with pytest.raises(ValueError, match="main=7"):
        read_centerlines(good, main=7)


def test_without_vtk_the_error_says_how_to_install(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    for key in [k for k in sys.modules if k == "vtk" or k.startswith(("vtk.", "vtkmodules"))]:
        monkeypatch.setitem(sys.modules, key, None)
    for key in ("vtk", "vtkmodules", "vtkmodules.vtkCommonCore", "vtkmodules.vtkCommonDataModel",
                "vtkmodules.vtkIOXML"):
        monkeypatch.setitem(sys.modules, key, None)
    with pytest.raises(ImportError, match=r'pip install "guidewire-sqp\[vtk\]"'):
        read_centerlines(tmp_path / "any.vtp")
    with pytest.raises(ImportError, match=r"\[vtk\]"):
        write_centerlines(aortic_arch("VII"), tmp_path / "any.vtp")
