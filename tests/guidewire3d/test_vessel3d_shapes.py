"""Shipped 3-D vessels: stEVE's aortic-arch family (guidewire.vessel3d.arch)."""

import numpy as np
import pytest

from guidewire.vessel3d import ARCH_TYPES, BRANCH_NAMES, Vessel3D, aortic_arch
from guidewire.vessel3d.arch import BRANCH_PARENTS, arch_arteries, arch_bend_margins

EXPECTED = {
    "I": {"brachiocephalic", "right_common_carotid", "right_subclavian", "left_common_carotid", "left_subclavian"},
    "II": {"brachiocephalic", "right_common_carotid", "right_subclavian", "left_common_carotid", "left_subclavian"},
    "IV": {"right_subclavian", "bicarotid_trunk", "right_common_carotid", "left_common_carotid", "left_subclavian"},
    "Va": {"brachiocephalic", "right_common_carotid", "left_common_carotid", "left_subclavian", "right_subclavian"},
    "Vb": {"right_common_carotid", "left_common_carotid", "left_subclavian", "right_subclavian"},
    "VI": {"brachiocephalic", "right_common_carotid", "left_common_carotid", "bisubclavian_trunk", "right_subclavian",
           "left_subclavian"},
    "VII": {"right_subclavian", "right_common_carotid", "left_common_carotid", "left_subclavian"},
}
EXPECTED["V"] = EXPECTED["Va"]

# stEVE's aorta (aorticarcharteries/aorta.py), mean values: point, direction, slope magnitude (mm)
AORTA = [((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 1.0), ((30.0, 0.0, 90.0), (1.0, 0.0, 2.0), 1.2),
         ((20.0, -40.0, 160.0), (-4.0, -6.0, -0.5), 1.4), ((-5.0, -60.0, 100.0), (3.0, 4.0, -8.0), 1.6)]


def _hermite_box() -> tuple[np.ndarray, np.ndarray]:
    """Bounds of stEVE's aorta from its construction: on a cubic Hermite segment of chord h (its parameter) between
    p0 and p1 with slopes m0, m1, each coordinate stays within [min(p0, p1), max(p0, p1)] widened by
    (4/27) h (|m0| + |m1|) (the Hermite basis: H00 + H01 = 1, |H10|, |H11| <= 4/27)."""
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for (p0, d0, a0), (p1, d1, a1) in zip(AORTA[:-1], AORTA[1:], strict=True):
        p0, p1 = np.array(p0), np.array(p1)
        m0 = np.array(d0) / np.linalg.norm(d0) * a0
        m1 = np.array(d1) / np.linalg.norm(d1) * a1
        widen = 4.0 / 27.0 * np.linalg.norm(p1 - p0) * (np.abs(m0) + np.abs(m1))
        lo = np.minimum(lo, np.minimum(p0, p1) - widen)
        hi = np.maximum(hi, np.maximum(p0, p1) + widen)
    return lo, hi


@pytest.mark.parametrize("arch_type", ARCH_TYPES)
def test_every_type_builds_with_its_named_branches(arch_type: str) -> None:
    v = aortic_arch(arch_type)
    assert isinstance(v, Vessel3D)
    names = [b.name for b in v.branches]
    assert len(names) == len(EXPECTED[arch_type]) and set(names) == EXPECTED[arch_type]
    assert tuple(names) == BRANCH_NAMES[arch_type]
    assert v.name == f"aortic_arch_{arch_type}"


@pytest.mark.parametrize("arch_type", ARCH_TYPES)
def test_each_branch_starts_inside_its_parents_lumen(arch_type: str) -> None:
    v = aortic_arch(arch_type)
    tubes = {"aorta": v.tubes[0]} | {b.name: t for b, t in zip(v.branches, v.tubes[1:], strict=True)}
    for b in v.branches:
        parent = tubes[BRANCH_PARENTS[arch_type][b.name]]
        start = np.array(b.centreline[:1])
        e = parent.closest(start, np.zeros(1))
        assert np.linalg.norm(start - e.centre) < e.radius[0], b.name
        if BRANCH_PARENTS[arch_type][b.name] == "aorta":  # the arch itself, not the lead-in or a trunk
            assert e.u[0] > 20.0 + 100.0 and start[0, 2] > 100.0, b.name


@pytest.mark.parametrize("arch_type", ["I", "IV", "VI", "VII"])
def test_entrance_is_the_descending_aorta_after_a_straight_lead_in(arch_type: str) -> None:
    v = aortic_arch(arch_type, lead_in=20.0)
    p, t = v.entrance
    assert np.allclose(p, (0.0, 0.0, -20.0), atol=1e-12) and np.allclose(t, (0.0, 0.0, 1.0), atol=1e-6)
    line = np.array(v.centreline)
    lead = line[line[:, 2] <= 0.0]
    assert len(lead) == 11 and np.all(lead[:, :2] == 0.0)
    assert np.isclose(v.tubes[0].radius0, 8.5)  # stEVE's diameter 17 mm at the descending end
    assert np.isclose(aortic_arch(arch_type, lead_in=0.0).entrance[0][2], 0.0)


@pytest.mark.parametrize("arch_type", ["I", "Vb", "VI"])
def test_aorta_has_stEVEs_mean_dimensions(arch_type: str) -> None:
    line = aortic_arch(arch_type, lead_in=0.0).centrelines(spacing=0.05)[0]
    lo, hi = _hermite_box()
    # the control points' box, widened by the Hermite bound (x: -5..30, y: -60..0, z: 0..160 mm)
    assert np.all(line.min(axis=0) >= lo - 1e-6) and np.all(line.max(axis=0) <= hi + 1e-6)
    assert line[:, 2].max() >= 160.0 and line[:, 1].min() <= -60.0 + 2.0 and line[:, 0].max() >= 30.0
    # it passes through stEVE's control points (the last one within one 2 mm sample of the root)
    for point, _, _ in AORTA[:3]:
        assert np.min(np.linalg.norm(line - point, axis=1)) < 0.05
    assert np.linalg.norm(line[-1] - AORTA[3][0]) < 2.0


@pytest.mark.parametrize("arch_type", ["I", "II", "IV", "Vb", "VI", "VII"])
def test_scale_width_scales_x_and_y_only(arch_type: str) -> None:
    base, wide = aortic_arch(arch_type), aortic_arch(arch_type, scale_width=1.2)
    a, b = np.array(base.centreline), np.array(wide.centreline)
    span = np.ptp
    assert np.allclose(span(b[:, :2], axis=0), 1.2 * span(a[:, :2], axis=0), rtol=1e-12)
    assert np.isclose(span(b[:, 2]), span(a[:, 2]), rtol=1e-12)
    for x, y in zip(base.branches, wide.branches, strict=True):
        assert np.allclose(np.array(y.centreline[-1]), np.array(x.centreline[-1]) * (1.2, 1.2, 1.0), rtol=1e-12)
        if not x.name.endswith("trunk"):  # the trunks' radii are clipped to their bends, which the scale changes
            assert np.allclose(y.radius, x.radius, rtol=1e-12)
    tall = aortic_arch(arch_type, scale_height=0.8, scale_diameter=0.9, lead_in=0.0)
    c = np.array(tall.centreline)
    assert np.isclose(c[:, 2].max(), 0.8 * a[:, 2].max(), rtol=1e-12)
    assert np.isclose(tall.tubes[0].radius0, 0.9 * 8.5)


def test_bad_type_raises_listing_the_valid_ones() -> None:
    with pytest.raises(ValueError, match="III") as info:
        aortic_arch("III")
    assert ", ".join(ARCH_TYPES) in str(info.value)  # every valid type, listed
    assert ARCH_TYPES == ("I", "II", "IV", "V", "Va", "Vb", "VI", "VII")
    with pytest.raises(ValueError, match="expected one of"):
        aortic_arch("i")
    with pytest.raises(ValueError, match="scale_width"):
        aortic_arch("I", scale_width=0.0)


@pytest.mark.parametrize("arch_type", ["IV", "VI"])
def test_only_the_common_origin_trunk_is_clipped_to_its_bends(arch_type: str) -> None:
    margins = arch_bend_margins(arch_type)
    trunk = BRANCH_NAMES[arch_type][1 if arch_type == "IV" else 3]
    assert margins[trunk] > 1.0  # stEVE's trunk bends tighter than its radius: Vessel3D would refuse it
    assert max(m for name, m in margins.items() if name != trunk) < 0.5
    v = aortic_arch(arch_type)
    stEVE = arch_arteries(arch_type)
    for b in v.branches:
        r, r0 = np.array(b.radius), stEVE[b.name][1]
        if b.name == trunk:
            clipped = np.flatnonzero(r < r0)
            assert list(clipped) == [0, 1, len(r) - 2, len(r) - 1] and np.all(r >= 0.85 * r0)
        else:
            assert np.array_equal(r, r0)
    for w in (0.7, 1.3):
        for d in (0.7, 1.3):
            aortic_arch(arch_type, scale_width=w, scale_height=2.0 - w, scale_diameter=d)  # stEVE's range builds
