"""What a batch leaves for a user to load: its JSON lines (:func:`read_records`), the shapes as one NumPy ``.npz``
(:func:`save_shapes`, :func:`load_shapes`) and the wire as a B-spline
(:func:`~guidewire.chain.spline.wire_spline`), the form SplineFormer-style models are trained on.

The ``.npz`` holds every scene that has a shape (a solution, converged or not; a scene without one has no row), as
flat arrays cut by offsets (scenes may have different numbers of bars): scene ``i``'s nodes are
``nodes[node_offsets[i]:node_offsets[i + 1]]``, and likewise ``s`` (by ``node_offsets``), ``bar_angles`` (by
``bar_offsets``), ``knots`` (by ``knot_offsets``) and ``coefficients`` (by ``coefficient_offsets``); per scene
``names``, ``files``, ``success``, ``energy`` and ``degree``. Plain arrays only: ``numpy.load`` needs no pickle.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..chain.spline import DEGREE, WireSpline, wire_spline

FloatArray = NDArray[np.float64]


def read_records(path: str | Path, *, latest: bool = True) -> list[dict[str, Any]]:
    """The records of a batch's JSON-lines file, in file order (blank lines skipped).

    With ``latest`` (default), a scene file recorded more than once (a resumed run retries a file that could not be
    read or run) counts by its last record, in that record's place.

    Raises
    ------
    ValueError
        A line that is not a JSON object (its number in the message).
    """
    records = []
    with Path(path).open(encoding="utf-8") as handle:
        for number, line in enumerate(handle, 1):
            if not line.strip():
                continue
            try:
                item = json.loads(line)
            except json.JSONDecodeError as exc:
                raise ValueError(f"{path}: line {number} is not JSON ({exc.msg}).") from None
            if not isinstance(item, dict):
                raise ValueError(f"{path}: line {number} is {type(item).__name__}; expected a JSON object.")
            records.append(item)
    if latest:
        last = {item["file"]: i for i, item in enumerate(records) if isinstance(item.get("file"), str)}
        records = [item for i, item in enumerate(records) if last.get(item.get("file"), i) == i]
    return records


def _as_record(item: Any) -> Mapping[str, Any]:
    """A record (mapping) as it is, or a :class:`~guidewire.Solution`'s fields the ``.npz`` needs."""
    if isinstance(item, Mapping):
        return item
    if hasattr(item, "nodes") and hasattr(item, "scene"):
        return {"name": item.scene.name, "file": None, "success": item.success, "energy": item.energy,
                "nodes": item.nodes, "s": item.s, "bar_angles": item.bar_angles}
    return {}  # a SceneError: no shape


def save_shapes(results: Iterable[Any], path: str | Path, *, degree: int = DEGREE) -> int:
    """Write the shapes of ``results`` to the ``.npz`` file ``path`` (layout in the module docstring).

    Parameters
    ----------
    results : iterable of dict, Solution or SceneError
        Batch records (:func:`read_records`) or :func:`guidewire.solve_many` results; those without a shape are
        left out.
    path : str or Path
    degree : int
        Of the B-splines (:func:`wire_spline`).

    Returns
    -------
    int
        Number of scenes written.
    """
    names, files, success, energy, degrees = [], [], [], [], []
    nodes, s, angles, knots, coefficients = [], [], [], [], []
    for item in map(_as_record, results):
        if item.get("nodes") is None:
            continue
        p, arc = np.asarray(item["nodes"], dtype=float), np.asarray(item["s"], dtype=float)
        spline = wire_spline(p, arc, degree)
        names.append(str(item.get("name") or ""))
        files.append(str(item.get("file") or ""))
        success.append(bool(item.get("success")))
        energy.append(float(item.get("energy", np.nan)))
        degrees.append(spline.degree)
        nodes.append(p)
        s.append(arc)
        angles.append(np.asarray(item["bar_angles"], dtype=float))
        knots.append(spline.knots)
        coefficients.append(spline.coefficients)

    def offsets(parts: list[FloatArray]) -> NDArray[np.int64]:
        return np.concatenate(([0], np.cumsum([len(x) for x in parts], dtype=np.int64))).astype(np.int64)

    def flat(parts: list[FloatArray], width: int = 0) -> FloatArray:
        return np.concatenate(parts) if parts else np.zeros((0, width) if width else 0)

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("wb") as handle:  # a file object: numpy adds no ".npz" to a name without it
        np.savez_compressed(
            handle, names=np.array(names, dtype=str), files=np.array(files, dtype=str),
            success=np.array(success, dtype=bool), energy=np.array(energy, dtype=float),
            degree=np.array(degrees, dtype=np.int64),
            nodes=flat(nodes, 2), s=flat(s), node_offsets=offsets(nodes),
            bar_angles=flat(angles), bar_offsets=offsets(angles),
            knots=flat(knots), knot_offsets=offsets(knots),
            coefficients=flat(coefficients, 2), coefficient_offsets=offsets(coefficients),
        )
    return len(names)


def load_shapes(path: str | Path) -> list[dict[str, Any]]:
    """The scenes of a :func:`save_shapes` file, one dict each: ``name``, ``file``, ``success``, ``energy``,
    ``nodes``, ``s``, ``bar_angles`` and ``spline`` (a :class:`WireSpline`)."""
    with np.load(Path(path), allow_pickle=False) as data:
        d = {key: data[key] for key in data.files}
    out = []
    for i, name in enumerate(d["names"]):
        a, b = d["node_offsets"][i], d["node_offsets"][i + 1]
        out.append({
            "name": str(name), "file": str(d["files"][i]), "success": bool(d["success"][i]),
            "energy": float(d["energy"][i]), "nodes": d["nodes"][a:b], "s": d["s"][a:b],
            "bar_angles": d["bar_angles"][d["bar_offsets"][i]:d["bar_offsets"][i + 1]],
            "spline": WireSpline(d["knots"][d["knot_offsets"][i]:d["knot_offsets"][i + 1]],
                                 d["coefficients"][d["coefficient_offsets"][i]:d["coefficient_offsets"][i + 1]],
                                 int(d["degree"][i])),
        })
    return out
