"""Pinholes and specks (docs/capture.md §10, "Pinholes"): holes of one or two pixels are filled by sc.trace's
default, ink specks of one or two pixels dropped where a larger outline is left, and the other boundaries
stay exactly what tracing the cleaned bitmap gives."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import splinecraft as sc
from splinecraft.capture._binarize import PINHOLE_AREA, drop_specks, fill_pinholes


def random_masks(test):
    """The property tests' inputs: small random bitmaps under every connectivity rule."""
    test = given(mask=arrays(bool, st.tuples(st.integers(3, 12), st.integers(3, 12)), elements=st.booleans()),
                 connectivity=st.sampled_from([4, 8, "minority"]))(test)
    return pytest.mark.filterwarnings("ignore:the mask.s True pixels:UserWarning")(
        settings(max_examples=100, deadline=None)(test))


@random_masks
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
        outer = [b.area for b in result.boundaries if not b.is_hole]
        assert all(area >= PINHOLE_AREA for area in outer) or all(area < PINHOLE_AREA for area in outer)
        # ink is lost only where it was a speck of the pinhole-free bitmap
        lost = mask & ~result.mask
        if lost.any():
            cleared = fill_pinholes(mask, boundaries)[0]
            for _ in range(8):  # (the same rounds as sc.trace: until no pinhole is left)
                again = fill_pinholes(cleared, sc.trace_boundaries(cleared, connectivity=connectivity))[0]
                if again is cleared:
                    break
                cleared = again
            specks = [b for b in sc.trace_boundaries(cleared, connectivity=connectivity)
                      if not b.is_hole and b.area < PINHOLE_AREA]
            assert int(lost.sum()) == sum(b.area for b in specks)
            for b in specks:
                columns, rows = np.floor(np.asarray(b.pixels)).astype(int).T  # (pixel centres, x then y)
                assert not result.mask[rows, columns].any()


@random_masks
def test_only_speck_pixels_turn_into_paper(mask, connectivity):
    boundaries = sc.trace_boundaries(mask, connectivity=connectivity)
    dropped, count = drop_specks(mask, boundaries)
    outer = [b for b in boundaries if not b.is_hole]
    specks = [b for b in outer if b.area < PINHOLE_AREA]
    expected = specks if len(specks) < len(outer) else []  # a bitmap of nothing but specks keeps them
    assert count == len(expected)
    assert int(mask.sum()) - int(dropped.sum()) == sum(b.area for b in expected)
    assert not np.any(dropped & ~mask)  # only ink turns into paper
    assert (dropped is mask) == (count == 0)
    if count:
        after = sc.trace_boundaries(dropped, connectivity=connectivity)
        assert len([b for b in after if not b.is_hole]) == len(outer) - count
        assert not any(not b.is_hole and b.area < PINHOLE_AREA for b in after)


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


def test_trace_drops_specks_by_default_and_keeps_them_on_request():
    mask = _ring_with_holes()
    mask[0, 0] = True  # a speck of one pixel
    mask[38, 10:12] = True  # of two
    mask[1, 57] = mask[2, 58] = True  # of two diagonal pixels
    mask[37:39, 40:42] = True  # a speck of four pixels stays
    mask[20, 40] = True  # a one-pixel speck inside the real hole
    default = sc.trace(mask)
    assert sorted(b.area for b in default.boundaries) == [-288, -3, 4, 50 * 30]  # the hole whole again
    assert default.mask.sum() == mask.sum() + 3 - 6
    assert not default.mask[0, 0] and not default.mask[38, 10:12].any() and not default.mask[20, 40]
    assert any("2 pinholes and dropped 4 specks" in note for note in default.notes)
    kept = sc.trace(mask, min_speck_area=0)
    assert len(kept.boundaries) == 10
    np.testing.assert_array_equal(kept.mask, mask)


def test_a_bitmap_of_specks_only_keeps_them():
    mask = np.zeros((12, 12), bool)
    mask[2, 2] = mask[8, 5:7] = True
    result = sc.trace(mask)
    assert sorted(b.area for b in result.boundaries) == [1, 2]
    np.testing.assert_array_equal(result.mask, mask)


@pytest.mark.parametrize("area", [-1, 4, 2.5, True, "3"])
def test_pinhole_area_is_checked(area):
    mask = _ring_with_holes()
    with pytest.raises(ValueError, match="area"):
        fill_pinholes(mask, sc.trace_boundaries(mask), area)
    with pytest.raises(ValueError, match="area"):
        drop_specks(mask, sc.trace_boundaries(mask), area)
