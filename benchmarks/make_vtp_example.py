"""Write the shipped VMTK centreline example ``guidewire/scenes/vessels3d/arch_type_I.vtp``: stEVE's type I aortic arch
(:func:`guidewire.vessel3d.aortic_arch`, mean values, 20 mm lead-in) saved by
:func:`guidewire.vessel3d.write_centerlines` (one polyline per tube end, ``CenterlineIds``,
``MaximumInscribedSphereRadius`` in mm, doubles). Needs ``vtk`` (``pip install "guidewire-sqp[vtk]"``).

Usage: ``python benchmarks/make_vtp_example.py [OUT]`` (default: the shipped file).
"""

from __future__ import annotations

import sys
from pathlib import Path

from guidewire.vessel3d import aortic_arch, read_centerlines, write_centerlines
from guidewire.vessel3d.vtp import EXAMPLE_VTP


def main(out: Path = EXAMPLE_VTP) -> Path:
    vessel = aortic_arch("I")
    out.parent.mkdir(parents=True, exist_ok=True)
    write_centerlines(vessel, out)
    back = read_centerlines(out)
    assert back == vessel, "the written file does not read back to the same vessel"
    print(f"{out}: {len(vessel.branches)} branches ({', '.join(b.name for b in vessel.branches)}), "
          f"{out.stat().st_size} bytes")
    return out


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else EXAMPLE_VTP)
