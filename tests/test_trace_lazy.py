"""Per-boundary results made on access (capture/fitting/results.BoundaryList, fitting/budget.PolygonFits): a
noise image's polygons cost no objects until read, and read the same as when they are made up front."""
from __future__ import annotations

import numpy as np
import pytest

from splinecraft.capture.fitting.budget import polygon_fits
from splinecraft.capture.fitting.results import BoundaryList
from splinecraft.capture.trace import trace


def noise_image(size, seed):
    return np.random.default_rng(seed).random((size, size)) < 0.3


@pytest.fixture(scope="module")
def spent():
    """Every boundary of a noise image left to the polygon (the budget is spent at once), and the same run
    with snapshots (which reads every fit while merging them)."""
    image = noise_image(40, 3)
    return trace(image, time_budget=1e-9, keep_snapshots=False), trace(image, time_budget=1e-9)


def test_polygons_are_made_only_when_read(spent):
    lean, _ = spent
    assert isinstance(lean.fits, BoundaryList) and isinstance(lean.splines, BoundaryList)
    assert lean.fits.made() == 0 and lean.splines.made() == 0
    count = len(lean.boundaries)
    assert len(lean.fits) == len(lean.splines) == count == lean.stats["boundaries"] > 20
    last = lean.fits[-1]
    assert last is lean.fits[count - 1] and lean.fits.made() == 1
    assert last.spline is lean.splines[-1]  # the fit's own spline, made once
    assert lean.splines.made() == 1


def test_stats_of_unread_polygons_match_their_objects(spent):
    lean, _ = spent
    per_boundary = lean.stats["per_boundary"]
    assert sum(entry["segments"] for entry in per_boundary) == lean.stats["segments"]
    for entry, fit, spline in zip(per_boundary, lean.fits, lean.splines):
        assert fit.spline is spline
        assert entry["segments"] == spline.n_segments
        assert (entry["knots_inserted"], entry["iterations"], entry["converged"]) == (
            fit.knots_inserted, fit.iterations, fit.converged)
        assert entry["hausdorff"] == fit.hausdorff == 0.0 and entry["reason"] is None
        assert entry["budget"] == "polygon"


def test_made_on_access_reads_as_made_up_front(spent):
    lean, full = spent
    assert lean.to_svg() == full.to_svg()
    assert [s.n_segments for s in lean.splines] == [s.n_segments for s in full.splines]
    direct = polygon_fits(lean.points, lean.stats["tolerance"], False)
    for fit, reference in zip(lean.fits, direct):
        np.testing.assert_array_equal(fit.spline.bezier(), reference.spline.bezier())
        np.testing.assert_array_equal(fit.spline.knots, reference.spline.knots)
        assert fit.pieces == reference.pieces
    assert [len(f.snapshots) for f in full.fits] == [1] * len(full.fits)


def test_boundary_list_behaves_like_a_list():
    made = []

    def make(k):
        made.append(k)
        return f"item {k}"

    items = BoundaryList(["a", None, "c", None], make)
    assert len(items) == 4 and items.made() == 2
    assert items[-1] == "item 3" and made == [3]
    assert items[1:3] == ["item 1", "c"] and made == [3, 1]
    assert list(items) == ["a", "item 1", "c", "item 3"] and made == [3, 1]  # each made once
    items[0] = "z"
    assert items == ["z", "item 1", "c", "item 3"] and items != ["z"]
    with pytest.raises(IndexError):
        items[4]
    assert "4 boundaries" in repr(items)
