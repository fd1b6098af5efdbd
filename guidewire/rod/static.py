"""Static equilibrium of a clamped 3D rod through :func:`sqp.minimize` (node positions, bar-length equality rows)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

import sqp
from guidewire.rod.energy import FloatArray, RodEnergy


def solve_clamped(
    rod: RodEnergy,
    x0: FloatArray,
    tip: FloatArray | None = None,
    tip_force: FloatArray | None = None,
    **options: object,
) -> sqp.Result:
    """Minimise the bending energy of ``rod`` over the free nodes ``x0[1:]`` with node 0 held.

    Rows: ``|x_{k+1} − x_k|² = l_k²`` per bar (inextensible) and, when ``tip`` is given, the last node at ``tip``.
    A ``tip_force`` (N) adds the potential ``−F · x_tip``.
    The result's ``x`` is the flattened free nodes ``(n, 3)``; a failed solve is reported by its status.
    """
    x0 = np.asarray(x0, dtype=float)
    n = rod.lengths.size
    if x0.shape != (n + 1, 3):
        raise ValueError(f"x0 has shape {x0.shape}; expected ({n + 1}, 3).")
    base = x0[0].copy()
    force = np.zeros(3) if tip_force is None else np.asarray(tip_force, dtype=float)
    if force.shape != (3,):
        raise ValueError(f"tip_force has shape {force.shape}; expected (3,).")

    def nodes(z: FloatArray) -> FloatArray:
        return np.vstack([base, z.reshape(n, 3)])

    def length_rows(z: FloatArray) -> FloatArray:
        e = np.diff(nodes(z), axis=0)
        return np.einsum("ij,ij->i", e, e) - rod.lengths**2

    def length_jac(z: FloatArray) -> sp.csr_matrix:
        e = 2.0 * np.diff(nodes(z), axis=0)
        rows = np.repeat(np.arange(n), 6)
        cols = np.concatenate([np.arange(3 * k - 3, 3 * k + 3) for k in range(n)])  # node k-1, node k
        vals = np.hstack([-e, e])
        keep = cols >= 0
        return sp.csr_matrix((vals.ravel()[keep], (rows[keep], cols[keep])), shape=(n, 3 * n))

    constraints: list[dict[str, object]] = [{"type": "eq", "fun": length_rows, "jac": length_jac}]
    if tip is not None:
        select = sp.csr_matrix((np.ones(3), (np.arange(3), np.arange(3 * n - 3, 3 * n))), shape=(3, 3 * n))
        target = np.asarray(tip, dtype=float)
        constraints.append({"type": "eq", "fun": lambda z: z[-3:] - target, "jac": lambda z: select})
    return sqp.minimize(
        lambda z: rod.bending(nodes(z)) - force @ z[-3:],
        x0[1:].ravel(),
        jac=lambda z: rod.bending_gradient(nodes(z))[1:].ravel() - np.concatenate([np.zeros(3 * n - 3), force]),
        constraints=constraints,
        **options,
    )
