"""The whole-array helpers of the ``"background"`` threshold (``capture/_binarize.py``) against the scipy
filters they stand in for: the same values bit for bit, on random arrays and shapes (BENCHMARKS.md,
"Session 13": they made the default threshold of a 48-Mpx photo 3x faster at half the memory)."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy import ndimage

from splinecraft.capture import _binarize
from splinecraft.capture._binarize import HOLE_RING, _blur_near, _box_max, _ring

shapes = st.tuples(st.integers(1, 40), st.integers(1, 40))


@settings(max_examples=150, deadline=None)
@given(data=st.data(), shape=shapes, size=st.sampled_from([1, 3, 5, 7, 9]),
       dtype=st.sampled_from([np.bool_, np.uint8, np.int32]))
def test_box_max_is_scipys_maximum_filter(data, shape, size, dtype):
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    values = rng.integers(0, 4, shape).astype(dtype)
    expected = ndimage.maximum_filter(values, size, mode="nearest")
    got = _box_max(values, size)
    assert got.dtype == values.dtype
    np.testing.assert_array_equal(got, expected)


@settings(max_examples=150, deadline=None)
@given(data=st.data(), shape=shapes, reach=st.integers(0, 5), share=st.sampled_from([0.0, 0.01, 0.05, 0.3]))
def test_blur_near_is_scipys_gaussian_filter_near_the_pixels(data, shape, reach, share):
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    values = rng.random(shape, dtype=np.float32)
    chosen = rng.random(shape) < share
    rows, cols = np.nonzero(chosen)
    got = _blur_near(values, rows, cols, reach)
    near = ndimage.maximum_filter(chosen, 2 * reach + 1, mode="constant")
    expected = ndimage.gaussian_filter(values, 1.0)
    np.testing.assert_array_equal(got[near], expected[near])   # bit for bit, not approximately
    far = ~near
    assert np.all((got[far] == 0) | (got[far] == expected[far]))  # elsewhere 0, or the filter's value


@pytest.mark.parametrize("band", [2, 5, 512])
def test_ring_is_the_maximum_filter_of_the_labels_at_the_ink(monkeypatch, band):
    monkeypatch.setattr(_binarize, "_BLOCK_ROWS", band)       # several bands, overlapping by the ring
    rng = np.random.default_rng(band)
    paper = rng.random((37, 29)) < 0.4
    labels, count = ndimage.label(paper)
    labels[labels % 3 == 0] = 0                                 # some paper pieces are not holes
    rows, cols = np.nonzero(labels)
    ring_rows, ring_cols, ring_piece = _ring(labels, paper, rows, cols)
    expected = ndimage.maximum_filter(labels, 2 * HOLE_RING + 1, mode="nearest")
    expected[paper] = 0
    want_rows, want_cols = np.nonzero(expected)
    np.testing.assert_array_equal(ring_rows, want_rows)
    np.testing.assert_array_equal(ring_cols, want_cols)
    np.testing.assert_array_equal(ring_piece, expected[want_rows, want_cols])
