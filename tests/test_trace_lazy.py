"""Per-boundary results made on access (capture/fitting/results.BoundaryList, fitting/budget.PolygonFits): a
noise image's polygons cost no objects until read, and read the same as when they are made up front."""
from __future__ import annotations

import copy
import pickle

import numpy as np
import pytest

from hypothesis import given, settings, strategies as st

from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.fitting.budget import polygon_fits
from splinecraft.capture.fitting.results import BoundaryList
from splinecraft.capture.trace import trace


def reference_polygons(outlines):
    """The numpy formulation the compiled polygon pass replaced (turning points, thirds, running knots)."""
    lengths = np.array([o.shape[0] for o in outlines], dtype=np.int64)
    offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    points = np.concatenate(outlines).astype(float, copy=False)
    following = np.arange(points.shape[0]) + 1
    following[offsets + lengths - 1] = offsets
    preceding = np.arange(points.shape[0]) - 1
    preceding[offsets] = offsets + lengths - 1
    step = points[following] - points
    direction = step / np.hypot(step[:, 0], step[:, 1])[:, None]
    before = direction[preceding]
    turning = (np.abs(direction[:, 0] * before[:, 1] - direction[:, 1] * before[:, 0])
               + (1.0 - np.einsum("ij,ij->i", direction, before))) > 1e-9
    outline_of = np.repeat(np.arange(lengths.shape[0]), lengths)
    few = np.bincount(outline_of[turning], minlength=lengths.shape[0]) < 3
    turning[np.isin(outline_of, np.flatnonzero(few))] = True
    vertex = np.flatnonzero(turning)
    bounds = np.searchsorted(outline_of[vertex], np.arange(lengths.shape[0] + 1))
    after = np.arange(1, vertex.shape[0] + 1)
    after[bounds[1:] - 1] = bounds[:-1]
    start, end = points[vertex], points[vertex[after]]
    chord = end - start
    planar = np.stack([start, start + chord / 3.0, start + 2.0 * chord / 3.0, end]).transpose(0, 2, 1)
    running = np.cumsum(np.hypot(chord[:, 0], chord[:, 1]))
    base = np.concatenate([[0.0], running])[bounds[:-1]]
    knots = np.zeros(vertex.shape[0] + lengths.shape[0])
    knots[np.arange(vertex.shape[0]) + outline_of[vertex] + 1] = running - base[outline_of[vertex]]
    local = vertex - offsets[outline_of[vertex]]
    pairs = np.column_stack([local, local[after]])
    return planar, knots, pairs, bounds


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


def test_unread_polygons_survive_pickle_and_deepcopy():
    lean = trace(noise_image(24, 5), time_budget=1e-9, keep_snapshots=False)
    copies = [pickle.loads(pickle.dumps(lean)), copy.deepcopy(lean)]
    assert lean.fits.made() == 0 and all(c.fits.made() == 0 for c in copies)
    for copied in copies:
        assert copied.to_svg() == lean.to_svg()
        assert [b.area for b in copied.boundaries] == [b.area for b in lean.boundaries]


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


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), density=st.floats(0.1, 0.9), scale=st.sampled_from([0.0, 0.5, 10.0]))
def test_polygon_pass_matches_the_numpy_formulation(seed, density, scale):
    """Crack outlines of a random bitmap, plus (scale > 0) random polylines on a half-pixel grid or anywhere."""
    rng = np.random.default_rng(seed)
    outlines = [b.outline for b in trace_boundaries(rng.random((30, 30)) < density)]
    if scale:
        outlines += [np.round(rng.normal(size=(int(rng.integers(4, 20)), 2)) * 4) * scale for _ in range(20)]
        outlines = [o for o in outlines if (np.diff(o, axis=0, append=o[:1]) != 0).any(axis=1).all()]
    if not outlines:
        return
    planar, knots, pairs, bounds = reference_polygons(outlines)
    fits = polygon_fits(outlines, 0.8, False)
    assert list(np.diff(bounds)) == list(fits.segments)
    for b, fit in enumerate(fits):
        lo, hi = bounds[b], bounds[b + 1]
        np.testing.assert_array_equal(fit.spline.bezier(), planar[:, :, lo:hi].transpose(2, 0, 1))
        np.testing.assert_array_equal(fit.spline.knots, knots[lo + b: hi + b + 1])
        np.testing.assert_array_equal(np.array(fit.pieces).reshape(-1, 2), pairs[lo:hi])


def test_snapshots_leave_unread_polygons_unmade():
    """Merging the snapshots of a spent budget makes no polygon (it used to make every one of them: 10^5 on a
    2000 x 2000 noise image, twice the time and memory of the trace); reading a snapshot makes its polygons."""
    image = noise_image(40, 3)
    lean, full = trace(image, time_budget=1e-9, keep_snapshots=False), trace(image, time_budget=1e-9)
    assert full.fits.made() == 0 and len(full.snapshots) == 1
    snapshot = full.snapshots[-1]
    assert snapshot.finished.all() and len(snapshot.snapshots) == len(full.fits)
    assert snapshot.snapshots[3] is full.fits[3].snapshots[0] and full.fits.made() == 1
    np.testing.assert_array_equal(snapshot.bezier, np.concatenate([s.bezier() for s in lean.splines]))
    assert full.fits.made() == len(full.fits)
    copied = pickle.loads(pickle.dumps(trace(noise_image(24, 5), time_budget=1e-9)))
    assert copied.fits.made() == 0 and copied.snapshots[-1].to_svg(24, 24) == copied.to_svg()
