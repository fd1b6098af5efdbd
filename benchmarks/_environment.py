"""Environment of every benchmark: BLAS pinned to one thread, the machine/version report, a progress bar.

Importing this module sets ``OPENBLAS_NUM_THREADS``, ``OMP_NUM_THREADS`` and ``MKL_NUM_THREADS`` to 1 (unless already
set) before numpy is imported, so it is the first import of every script; :func:`one_thread` adds
``threadpoolctl``'s limit for libraries loaded later.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import contextlib  # noqa: E402
import platform  # noqa: E402
from importlib import metadata  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import scipy  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

import sqp  # noqa: E402

#: How ``guidewire.solve`` picks its QP backend when none is named (``qp_solver=None``), in words.
AUTO_QP_SOLVER = ("auto (sqp's structural choice: PIQP for programs above 300 variables whose rows are all sparse, "
                  "DAQP otherwise)")


def one_thread() -> Any:
    """Context manager limiting every BLAS/OpenMP pool to one thread (``threadpoolctl``)."""
    return threadpool_limits(limits=1)


def version(dist: str) -> str:
    """The installed version of distribution ``dist``, or ``"not installed"``."""
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


def ipopt_available() -> bool:
    """Whether ``cyipopt.minimize_ipopt`` imports."""
    try:
        from cyipopt import minimize_ipopt  # noqa: F401
    except ImportError:
        return False
    return True


def cpu_name() -> str:
    """The CPU model (``/proc/cpuinfo``), else what :mod:`platform` knows."""
    cpu = platform.processor() or platform.machine()
    with contextlib.suppress(OSError):
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return cpu


def environment(*, guidewire: bool = True) -> list[str]:
    """Machine and versions, one item per line (printed, and written at the top of every Markdown file).

    ``guidewire``: add how ``ours`` (:func:`guidewire.solve` with its defaults) is configured.
    """
    backends = ", ".join(f"{b} {version(b if b != 'proxqp' else 'proxsuite')}" for b in sqp.installed_solvers())
    qp_line = f"QP backends: {backends}"
    if guidewire:
        qp_line += f"; ours = guidewire.solve defaults: qp_solver {AUTO_QP_SOLVER}, hessian 'exact'"
    return [
        f"machine: {cpu_name()}, {os.cpu_count()} logical cores, {platform.system()} {platform.release()}",
        f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
        f"qpsolvers {version('qpsolvers')}, cyipopt {version('cyipopt-wheels') if ipopt_available() else 'missing'}",
        qp_line,
        "BLAS pinned to one thread (OPENBLAS/OMP/MKL_NUM_THREADS=1 and threadpoolctl)",
    ]


def progress(iterable: Any, **kwargs: Any) -> Any:
    """``tqdm`` progress bar when installed, the iterable itself otherwise."""
    try:
        from tqdm import tqdm
    except ImportError:
        return iterable
    return tqdm(iterable, **kwargs)
