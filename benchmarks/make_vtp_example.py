"""Write the shipped VMTK centreline example ``guidewire/scenes/vessels3d/arch_type_I.vtp``: stEVE's type I aortic arch
(:func:`guidewire.vessel3d.aortic_arch`, mean values, 20 mm lead-in) saved by
:func:`guidewire.vessel3d.write_centerlines` (one polyline per tube end, ``CenterlineIds``,
``MaximumInscribedSphereRadius`` in mm, doubles). Needs ``vtk`` (``pip install "guidewire-sqp[vtk]"``).

It reads the file back (it must give the same vessel) and writes a table of its tubes, and whether the shipped file
is byte-identical to the new one, to ``--out``/``make_vtp_example.md``.

Usage: ``python benchmarks/make_vtp_example.py [--quick] [--out DIR] [--vtp PATH]``: writes ``PATH`` (default the
shipped file; with ``--quick``, ``DIR/arch_type_I.vtp``, leaving the shipped file alone).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from _arguments import parse, parser
from _tables import markdown_table, output_stem, write_markdown

from guidewire.vessel3d import aortic_arch, read_centerlines, write_centerlines
from guidewire.vessel3d.vtp import EXAMPLE_VTP


def main() -> None:
    ap = parser(__doc__, quick_help="write the file under --out, not over the shipped one", repeats=1)
    ap.add_argument("--vtp", type=Path, default=None, help="where to write the .vtp (default: the shipped file)")
    a = parse(ap)
    out = a.vtp or (a.out / EXAMPLE_VTP.name if a.quick else EXAMPLE_VTP)
    vessel = aortic_arch("I")
    out.parent.mkdir(parents=True, exist_ok=True)
    write_centerlines(vessel, out)
    back = read_centerlines(out)
    assert back == vessel, "the written file does not read back to the same vessel"
    rows = []
    for name, line, radius in [("aorta (main)", vessel.centreline, vessel.radius)] + [
            (b.name, b.centreline, b.radius) for b in vessel.branches]:
        r = np.broadcast_to(np.asarray(radius, dtype=float), (len(line),))
        rows.append([name, len(line), float(r.min()), float(r.max())])
    same = EXAMPLE_VTP.is_file() and EXAMPLE_VTP.read_bytes() == out.read_bytes()
    lines = [f"# VMTK centreline example: {vessel.name}", "", f"File: `{out.name}`, {out.stat().st_size} bytes; reads "
             f"back to the same vessel; the shipped `{EXAMPLE_VTP.name}` is byte-identical: {'yes' if same else 'no'}.",
             "", *markdown_table(["tube", "points", "min radius (mm)", "max radius (mm)"], rows)]
    write_markdown(lines, output_stem(a.out, "make_vtp_example", a.quick).with_suffix(".md"))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
