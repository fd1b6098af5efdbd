"""``augmented_rungs``: the augmented-Lagrangian ladder cut short, with an identity shift on top of the term beyond.

On a compressed chain (the guidewire's reduced program in miniature, ``W`` indefinite near the answer) every ladder
length reaches the same KKT point: the term and the shift change the model, not the problem.
"""

from __future__ import annotations

import numpy as np
import pytest

import sqp
from tests.sqp.test_indefinite_first import chain


@pytest.mark.parametrize("n", [20, 60, 150])
@pytest.mark.parametrize("rungs", [0, 1, 3, 5])
def test_a_short_ladder_reaches_the_same_answer(n, rungs):
    """For chains of 20-150 links and ladders of 0-5 rungs: success, the same energy to 1e-9 and links to 1e-5 rad
    as the engine's ladder (the answer is determined to ``sqrt(tol)`` in the links by a KKT residual of ``tol``)."""
    fun, jac, hess, con, x0 = chain(n)
    ref = sqp.minimize(fun, x0, jac=jac, hess=hess, constraints=[con], tol=1e-10)
    short = sqp.minimize(fun, x0, jac=jac, hess=hess, constraints=[con], tol=1e-10, augmented_rungs=rungs)
    assert ref.success and short.success, short.message
    assert short.fun == pytest.approx(ref.fun, rel=1e-9)
    assert np.max(np.abs(short.x - ref.x)) < 1e-5


@pytest.mark.parametrize("bad", [-1, 2.5, True, "5"])
def test_a_bad_ladder_length_is_refused_by_name(bad):
    with pytest.raises(ValueError, match="augmented_rungs"):
        sqp.Options(augmented_rungs=bad)
