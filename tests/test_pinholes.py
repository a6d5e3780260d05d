"""Pinholes (docs/capture.md §10, "Pinholes"): holes of one or two pixels are filled by sc.trace's default,
and the other boundaries stay exactly what tracing the filled bitmap gives."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import splinecraft as sc
from splinecraft.capture._binarize import PINHOLE_AREA, fill_pinholes


@pytest.mark.filterwarnings("ignore:the mask.s True pixels:UserWarning")
@settings(max_examples=100, deadline=None)
@given(mask=arrays(bool, st.tuples(st.integers(3, 12), st.integers(3, 12)), elements=st.booleans()),
       connectivity=st.sampled_from([4, 8, "minority"]))
def test_only_pinhole_pixels_turn_into_ink_and_none_is_left(mask, connectivity):
    boundaries = sc.trace_boundaries(mask, connectivity=connectivity)
    filled, count = fill_pinholes(mask, boundaries)
    pinholes = [b for b in boundaries if b.is_hole and -b.area < PINHOLE_AREA]
    assert count == len(pinholes)
    assert int(filled.sum()) - int(mask.sum()) == sum(-b.area for b in pinholes)
    assert np.all(filled[mask])  # only paper turns into ink
    assert (filled is mask) == (count == 0)
    result = sc.trace(mask, connectivity=connectivity, keep_snapshots=False) if mask.any() else None
    if result is not None:
        retraced = sc.trace_boundaries(result.mask, connectivity=connectivity)
        assert [b.area for b in retraced] == [b.area for b in result.boundaries]
        assert not any(b.is_hole and -b.area < PINHOLE_AREA for b in result.boundaries)
        assert np.all(result.mask[mask])


def _ring_with_holes():
    mask = np.zeros((40, 60), bool)
    mask[5:35, 5:55] = True
    mask[12:28, 30:48] = False  # a real hole of 16 x 18 px
    mask[10, 10] = False  # pinhole of one pixel
    mask[20, 12:14] = False  # pinhole of two pixels
    mask[30, 20:23] = False  # a hole of three pixels stays
    return mask


def test_trace_fills_pinholes_by_default_and_keeps_them_on_request():
    mask = _ring_with_holes()
    default = sc.trace(mask)
    assert sorted(b.area for b in default.boundaries) == [-288, -3, 50 * 30]
    assert default.mask.sum() == mask.sum() + 3 and not mask[10, 10] and default.mask[10, 10]
    assert any("2 pinholes" in note for note in default.notes)
    kept = sc.trace(mask, min_speck_area=0)
    assert sorted(b.area for b in kept.boundaries) == [-288, -3, -2, -1, 50 * 30]
    np.testing.assert_array_equal(kept.mask, mask)
    assert not any("pinhole" in note for note in kept.notes)


@pytest.mark.parametrize("area", [-1, 4, 2.5, True, "3"])
def test_pinhole_area_is_checked(area):
    mask = _ring_with_holes()
    with pytest.raises(ValueError, match="area"):
        fill_pinholes(mask, sc.trace_boundaries(mask), area)
