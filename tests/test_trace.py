"""Tests of the outline-capture pipeline (capture/trace.py) and its SVG helpers (capture/svg.py).

References are analytic: rendered discs, squares and polygons are compared with their exact outlines;
the SVG is re-parsed and compared with the splines' own Bézier points.
"""
import json
import math

import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st
from PIL import Image

from splinecraft.capture.image import InkPolarityWarning
from splinecraft.capture.contour import chain_to_pixels
from splinecraft.capture.fitting import KNOT_METHODS
from splinecraft.capture.svg import format_number, parse_path_data, path_data, read_svg_paths, svg_document
from splinecraft.capture.fitting import DEFAULT_EPSILON
from splinecraft.capture.trace import TraceResult, TraceSnapshot, trace
from splinecraft.spline import Spline


# ------------------------------------------------------------------------------------------ helpers
def render_disc(size, cx, cy, radius):
    yy, xx = np.mgrid[:size, :size] + 0.5
    return (xx - cx) ** 2 + (yy - cy) ** 2 <= radius**2


def render_convex_polygon(size, vertices):
    """Pixels whose centre lies inside the convex polygon (vertices clockwise on screen)."""
    yy, xx = np.mgrid[:size, :size] + 0.5
    inside = np.ones((size, size), bool)
    for (x0, y0), (x1, y1) in zip(vertices, np.roll(vertices, -1, axis=0)):
        inside &= (x1 - x0) * (yy - y0) - (y1 - y0) * (xx - x0) >= 0
    return inside


def bezier_samples(bezier, per_piece=64):
    """Points of cubic Béziers (m, 4, 2) by the Bernstein form (independent of Spline)."""
    t = np.linspace(0.0, 1.0, per_piece, endpoint=False)[:, None]
    basis = np.hstack([(1 - t) ** 3, 3 * t * (1 - t) ** 2, 3 * t**2 * (1 - t), t**3])  # (k, 4)
    return np.einsum("kj,mjd->mkd", basis, np.asarray(bezier)).reshape(-1, 2)


def distance_to_polygon(points, vertices):
    a = np.asarray(vertices, float)
    b = np.roll(a, -1, axis=0)
    ab = b - a
    ap = points[:, None, :] - a[None]
    t = np.clip((ap * ab).sum(-1) / (ab * ab).sum(-1), 0, 1)
    return np.linalg.norm(ap - t[..., None] * ab, axis=-1).min(axis=1)


def curve_to_polygon_deviation(result, vertices):
    """Two-sided max deviation between all traced curves and the polygon outline ``vertices``."""
    curve = np.vstack([bezier_samples(s.bezier()) for s in result.splines])
    forward = distance_to_polygon(curve, vertices).max()
    dense = np.vstack([v + np.linspace(0, 1, 200, endpoint=False)[:, None] * (w - v)
                       for v, w in zip(np.asarray(vertices, float), np.roll(vertices, -1, axis=0))])
    backward = distance_to_polygon(dense, curve).max()  # curve samples are < 0.1 px apart
    return max(forward, backward)


def signed_area(points):
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def knot_set(snapshot):
    return set(np.concatenate([np.asarray(k).ravel() for k in snapshot.knot_indices]).tolist())


RANDOM_METHODS = [m for m in ("random", "euclidean", "positional", "random3", "equal3", "fuzzy") if m in KNOT_METHODS]


# ------------------------------------------------------------------------------------------ accuracy
@pytest.mark.parametrize("epsilon", [1.0, 2.0])
def test_disc_within_epsilon_plus_half_pixel(epsilon):
    cx, cy, radius = 40.3, 38.7, 27.4
    result = trace(render_disc(80, cx, cy, radius), epsilon=epsilon)
    assert isinstance(result, TraceResult) and len(result.splines) == 1
    curve = bezier_samples(result.splines[0].bezier())
    assert np.abs(np.hypot(curve[:, 0] - cx, curve[:, 1] - cy) - radius).max() <= epsilon + 0.5
    angles = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    circle = np.column_stack([cx + radius * np.cos(angles), cy + radius * np.sin(angles)])
    assert distance_to_polygon(circle, curve).max() <= epsilon + 0.5
    assert result.stats["converged"] and result.stats["hausdorff"] <= epsilon + 0.5


@pytest.mark.parametrize("epsilon", [1.0, 2.0])
def test_squares_within_epsilon_plus_half_pixel(epsilon):
    square = [(12, 10), (58, 10), (58, 50), (12, 50)]  # pixel-exact: edges on integer coordinates
    mask = np.zeros((64, 70), bool)
    mask[10:50, 12:58] = True
    result = trace(mask, epsilon=epsilon)
    assert curve_to_polygon_deviation(result, square) <= epsilon + 0.5
    angle = np.radians(23.0)
    c, s = math.cos(angle), math.sin(angle)
    rotated = [(50 + 30 * (c * x - s * y), 50 + 30 * (s * x + c * y)) for x, y in [(-1, -1), (1, -1), (1, 1), (-1, 1)]]
    result = trace(render_convex_polygon(100, rotated), epsilon=epsilon)
    assert curve_to_polygon_deviation(result, rotated) <= epsilon + 0.5


def test_ring_outer_and_hole():
    size, cx, cy = 90, 45.0, 45.0
    mask = render_disc(size, cx, cy, 38) & ~render_disc(size, cx, cy, 17)
    result = trace(mask, epsilon=1.0)
    outer, hole = result.boundaries
    assert not outer.is_hole and hole.is_hole and hole.parent == 0
    assert result.stats["holes"] == 1 and result.stats["outer"] == 1
    areas = [signed_area(bezier_samples(s.bezier())) for s in result.splines]
    assert areas[0] > 0 > areas[1]  # orientation of the curves follows the boundaries
    assert abs(areas[0] - math.pi * 38**2) < 0.03 * math.pi * 38**2
    assert abs(-areas[1] - math.pi * 17**2) < 0.06 * math.pi * 17**2
    for spline, radius in zip(result.splines, (38, 17)):
        curve = bezier_samples(spline.bezier())
        assert np.abs(np.hypot(curve[:, 0] - cx, curve[:, 1] - cy) - radius).max() <= 1.5


def test_several_components_from_a_file(tmp_path):
    mask = render_disc(100, 30, 30, 20) | render_disc(100, 72, 70, 18)
    mask[60:95, 5:20] = True
    path = tmp_path / "parts.png"
    Image.fromarray(np.where(mask, 0, 255).astype(np.uint8)).save(path)
    result = trace(path, epsilon=2.0)
    assert result.stats["boundaries"] == 3 and result.stats["holes"] == 0
    np.testing.assert_array_equal(result.mask, mask)


# ------------------------------------------------------------------------------------------ outputs
def test_svg_reparsed_equals_the_splines():
    mask = render_disc(70, 35, 35, 30) & ~render_disc(70, 35, 35, 12)
    result = trace(mask, epsilon=1.5)
    exact = read_svg_paths(result.to_svg(decimals=None))
    assert (exact["width"], exact["height"], exact["viewBox"]) == ("70", "70", "0 0 70 70")
    (path,) = exact["paths"]
    assert path["fill_rule"] == "evenodd"
    assert len(path["subpaths"]) == len(result.splines) == 2
    for (bezier, closed), spline in zip(path["subpaths"], result.splines):
        assert closed
        np.testing.assert_array_equal(bezier, spline.bezier())
    rounded = read_svg_paths(result.to_svg())["paths"][0]["subpaths"]
    for (bezier, _), spline in zip(rounded, result.splines):
        assert np.abs(bezier - spline.bezier()).max() <= 0.5e-4 + 1e-12


def test_json_round_trip():
    mask = render_disc(50, 25, 25, 20) & ~render_disc(50, 25, 25, 7)
    result = trace(mask, epsilon=2.0)
    data = json.loads(result.to_json(include_points=True, include_snapshots=True))
    assert data["type"] == "splinecraft.TraceResult" and (data["width"], data["height"]) == (50, 50)
    assert data["stats"]["segments"] == result.stats["segments"]
    for entry, boundary, spline in zip(data["boundaries"], result.boundaries, result.splines):
        pixels = chain_to_pixels(entry["chain_start"], [int(c) for c in entry["chain_code"]])
        np.testing.assert_array_equal(pixels, boundary.pixels)
        np.testing.assert_array_equal(Spline.from_dict(entry["spline"]).bezier(), spline.bezier())
        assert len(entry["points"]) == entry["contour_points"]
        assert len(entry["snapshots"]) >= 1
    assert parse_path_data(data["svg_path"])[0][0].shape == result.splines[0].bezier().shape


def test_stats_definitions():
    result = trace(render_disc(60, 30, 30, 24), epsilon=1.0)
    stats = result.stats
    n_points = sum(len(p) for p in result.points)
    segments = sum(s.n_segments for s in result.splines)
    assert stats["contour_points"] == n_points == sum(len(b.outline) for b in result.boundaries)
    assert stats["segments"] == segments
    assert stats["corners"] == sum(len(c) for c in result.corners)
    assert stats["knots_inserted"] == sum(f.knots_inserted for f in result.fits)
    assert stats["iterations"] == max(f.iterations for f in result.fits)
    assert stats["data_reduction_pct"] == pytest.approx(100 * (1 - 6 * segments / (2 * n_points)))
    assert stats["data_reduction_pct_thesis"] == pytest.approx(100 * (1 - stats["knots_inserted"] / n_points))
    assert stats["time_s"] >= sum(stats["time_breakdown"].values()) * 0.999
    assert result.params["epsilon"] == 1.0 and result.params["method"] in KNOT_METHODS


# ------------------------------------------------------------------------------------------ snapshots
@pytest.mark.parametrize("method", [None, "fuzzy"])
def test_snapshots_consistent(method):
    mask = render_disc(80, 40, 40, 33) & ~render_disc(80, 47, 40, 10)
    mask[5:12, 5:30] = True
    result = trace(mask, epsilon=1.0, method=method)
    for fit in result.fits:
        snaps = fit.snapshots
        assert snaps[0].iteration == 0
        for before, after in zip(snaps, snaps[1:]):
            if getattr(after, "phase", "insert") == "remove":  # lsq's final knot-removal rounds
                assert knot_set(after) <= knot_set(before)
            else:
                assert knot_set(before) <= knot_set(after)  # knots only grow while inserting
        np.testing.assert_allclose(np.asarray(snaps[-1].bezier), fit.spline.bezier())
    merged = result.snapshots
    assert [m.iteration for m in merged] == list(range(result.stats["iterations"] + 1))
    assert all(isinstance(m, TraceSnapshot) for m in merged)
    for m in merged:
        assert m.knots == sum(len(knot_set(s)) for s in m.snapshots)
        for fit, chosen in zip(result.fits, m.snapshots):
            assert chosen is [s for s in fit.snapshots if s.iteration <= m.iteration][-1]
    if method == "fuzzy":
        knots = [m.knots for m in merged]
        assert knots == sorted(knots)
    assert merged[-1].finished.all() and not merged[0].finished.all()
    final = np.concatenate([s.bezier() for s in result.splines])
    np.testing.assert_allclose(merged[-1].bezier, final)
    assert len(merged[-1].piece_boundary) == len(final)
    assert merged[-1].hausdorff == max(f.snapshots[-1].hausdorff for f in result.fits)
    assert merged[-1].hausdorff == pytest.approx(max(f.hausdorff for f in result.fits), abs=0.01)
    lean = trace(mask, epsilon=1.0, method=method, keep_snapshots=False)
    assert lean.snapshots == []
    for a, b in zip(lean.splines, result.splines):
        np.testing.assert_array_equal(a.bezier(), b.bezier())


@pytest.mark.parametrize("method", RANDOM_METHODS)
def test_seeded_runs_reproducible(method):
    mask = render_disc(60, 30, 30, 25) & ~render_disc(60, 30, 30, 9)
    first = trace(mask, epsilon=1.5, method=method, seed=11)
    second = trace(mask, epsilon=1.5, method=method, seed=11)
    for a, b in zip(first.splines, second.splines):
        np.testing.assert_array_equal(a.bezier(), b.bezier())
    for key in ("knots_inserted", "iterations", "segments", "corners"):
        assert first.stats[key] == second.stats[key]


# ------------------------------------------------------------------------------------------ bad input
def test_all_white_has_no_shape():
    with pytest.raises(ValueError, match="no shape found"):
        trace(np.full((20, 20), 255, np.uint8))
    with pytest.raises(ValueError, match="no shape found"):
        trace(np.zeros((20, 20), np.uint8), invert=True)


def test_all_black_is_the_frame_rectangle():
    result = trace(np.zeros((30, 40), np.uint8), epsilon=1.0)
    assert len(result.boundaries) == 1
    assert curve_to_polygon_deviation(result, [(0, 0), (40, 0), (40, 30), (0, 30)]) <= 1.5
    assert any("every pixel is ink" in note for note in result.notes)
    mask = np.ones((30, 40), bool)
    mask[0, 0] = False                      # not every pixel: no such note
    with pytest.warns(InkPolarityWarning):  # the polarity warning covers this one
        assert not any("every pixel is ink" in note for note in trace(mask, epsilon=1.0).notes)


def test_single_pixel_and_tiny_components():
    mask = np.zeros((10, 10), bool)
    mask[4, 6] = True
    result = trace(mask, epsilon=0.5)
    (spline,) = result.splines
    assert spline.closed
    assert curve_to_polygon_deviation(result, [(6, 4), (7, 4), (7, 5), (6, 5)]) <= 1.0
    pixels = trace(mask, epsilon=0.5, contour="pixels")  # 1-point chain: falls back to the crack outline
    assert any("crack outline" in note for note in pixels.notes)


def test_one_pixel_wide_line():
    mask = np.zeros((12, 40), bool)
    mask[5, 4:36] = True
    result = trace(mask, epsilon=0.5)
    curve = bezier_samples(result.splines[0].bezier())
    assert curve_to_polygon_deviation(result, [(4, 5), (36, 5), (36, 6), (4, 6)]) <= 1.0
    assert curve[:, 1].min() >= 5 - 1.0 and curve[:, 1].max() <= 6 + 1.0


def test_bad_files(tmp_path):
    text = tmp_path / "notes.png"
    text.write_text("hello")
    with pytest.raises(ValueError, match="not an image"):
        trace(text)
    full = tmp_path / "full.png"
    Image.fromarray((np.random.default_rng(0).random((50, 50)) * 255).astype(np.uint8)).save(full)
    cut = tmp_path / "cut.png"
    cut.write_bytes(full.read_bytes()[:200])
    with pytest.raises(ValueError, match="cut.png"):
        trace(cut)
    with pytest.raises(ValueError, match="empty"):
        trace(np.zeros((0, 0), np.uint8))


@pytest.mark.parametrize("epsilon", [0, -1.0, float("nan"), float("inf")])
def test_epsilon_must_be_positive(epsilon):
    with pytest.raises(ValueError, match="epsilon"):
        trace(render_disc(20, 10, 10, 6), epsilon=epsilon)


def test_option_validation():
    mask = render_disc(20, 10, 10, 6)
    with pytest.raises(TypeError, match="epsilon"):
        trace(mask, epsilon="2")
    with pytest.raises(ValueError, match="method"):
        trace(mask, method="nope")
    with pytest.raises(ValueError, match="corner_method"):
        trace(mask, corner_method="nope")
    with pytest.raises(ValueError, match="connectivity"):
        trace(mask, connectivity=6)
    with pytest.raises(ValueError, match="contour"):
        trace(mask, contour="edges")
    with pytest.raises(ValueError, match="max_iterations"):
        trace(mask, max_iterations=0)
    with pytest.raises(TypeError, match="corner_params"):
        trace(mask, corner_params=[1])


@pytest.mark.parametrize("method", sorted(KNOT_METHODS))
def test_max_iterations_bounds_the_work(method):
    mask = render_disc(80, 40, 40, 35)
    result = trace(mask, epsilon=0.05, method=method, max_iterations=2)  # unreachable epsilon
    assert result.stats["iterations"] <= 2 and not result.stats["converged"]
    assert len(result.snapshots) == result.stats["iterations"] + 1


@pytest.mark.slow
def test_8000_by_8000_image_finishes():
    """A ring on an 8000 x 8000 bitmap traces without exhausting memory (see trace's docstring for the
    measured time and peak memory) and stays within epsilon + 0.5 px of both circles."""
    size, centre, radii = 8000, 4000.0, (3900.0, 1500.0)
    mask = np.zeros((size, size), bool)
    y = np.arange(size) + 0.5 - centre
    for radius, value in zip(radii, (True, False)):  # row slices: no (H, W) float temporaries
        half = np.sqrt(np.maximum(radius**2 - y**2, 0.0))
        lo = np.ceil(centre - half - 0.5).astype(int)
        hi = np.floor(centre + half - 0.5).astype(int)
        for row in np.flatnonzero(half > 0):
            mask[row, lo[row]:hi[row] + 1] = value
    result = trace(mask, keep_snapshots=False)
    assert result.stats["boundaries"] == 2 and result.stats["holes"] == 1
    epsilon = result.params["epsilon"]
    for spline, radius in zip(result.splines, radii):
        curve = bezier_samples(spline.bezier(), per_piece=400)
        assert np.abs(np.hypot(curve[:, 0] - centre, curve[:, 1] - centre) - radius).max() <= epsilon + 0.5


# ------------------------------------------------------------------------------------------ svg helpers
def test_format_number():
    assert format_number(1.0) == "1" and format_number(-0.00001) == "0" and format_number(2.50) == "2.5"
    assert format_number(1 / 3, None) == repr(1 / 3) and format_number(3.0, None) == "3"
    with pytest.raises(ValueError, match="non-finite"):
        format_number(float("nan"))


@settings(max_examples=50, deadline=None)
@given(st.lists(st.integers(1, 6), min_size=1, max_size=3), st.integers(0, 2**32 - 1))
def test_path_data_round_trip(pieces, seed):
    rng = np.random.default_rng(seed)
    curves = []
    for m in pieces:
        bezier = rng.normal(scale=100, size=(m, 4, 2))
        bezier[1:, 0] = bezier[:-1, 3]
        bezier[-1, 3] = bezier[0, 0]
        curves.append(bezier)
    parsed = parse_path_data(path_data(curves, decimals=None))
    assert len(parsed) == len(curves)
    for (bezier, closed), original in zip(parsed, curves):
        assert closed
        np.testing.assert_array_equal(bezier, original)


def test_parse_relative_lines_and_errors():
    (square, closed), = parse_path_data("m 1,1 h 2 v 2 l -2,0 z")
    assert closed and square.shape == (4, 4, 2)  # the closing segment is added by z
    np.testing.assert_allclose(square[:, 0], [[1, 1], [3, 1], [3, 3], [1, 3]])
    np.testing.assert_allclose(square[0, 1], [1 + 2 / 3, 1])
    (curve, closed), = parse_path_data("M0 0c1 1 2 2 3 3")
    assert not closed
    np.testing.assert_allclose(curve[0], [[0, 0], [1, 1], [2, 2], [3, 3]])
    with pytest.raises(ValueError, match="unsupported"):
        parse_path_data("M 0 0 A 1 1 0 0 1 2 2")
    with pytest.raises(ValueError, match="start"):
        parse_path_data("C 1 1 2 2 3 3")
    with pytest.raises(ValueError, match="middle"):
        parse_path_data("M 0 0 C 1 1 2")
    with pytest.raises(ValueError, match="shape"):
        path_data([np.zeros((2, 3, 2))])


def test_svg_document_escapes_the_title():
    text = svg_document("M 0,0 Z", 3, 4, title="a<b&c")
    assert "<title>a&lt;b&amp;c</title>" in text and read_svg_paths(text)["width"] == "3"


# ------------------------------------------------------------------------------------------ small outlines
def _two_sided_deviation(bezier, contour):
    """Independent two-sided deviation between Bézier pieces and a closed contour polyline: dense curve
    samples to the contour edges, contour points and edge midpoints to the sampled curve (brute force)."""
    curve = bezier_samples(bezier, per_piece=256)
    contour = np.asarray(contour, float)
    forward = distance_to_polygon(curve, contour).max()
    probes = np.vstack([contour, 0.5 * (contour + np.roll(contour, -1, axis=0))])
    backward = distance_to_polygon(probes, curve).max()
    return max(forward, backward)


@pytest.mark.parametrize("name, ink", [
    ("pixel", [(4, 6)]),
    ("domino", [(4, 6), (4, 7)]),
    ("diagonal3", [(3, 3), (4, 4), (5, 5)]),
])
@pytest.mark.parametrize("epsilon", [0.3, 0.8])
def test_tiny_components_converge_within_epsilon(name, ink, epsilon):
    mask = np.zeros((10, 10), bool)
    for row, col in ink:
        mask[row, col] = True
    result = trace(mask, epsilon=epsilon)
    (fit,) = result.fits
    assert result.stats["converged"] and fit.converged
    assert result.stats["per_boundary"][0]["small_outline"] and result.stats["per_boundary"][0]["reason"] is None
    if name == "diagonal3":  # no corners: interpolated, no corner allowance
        assert fit.hausdorff <= epsilon
        assert _two_sided_deviation(result.splines[0].bezier(), result.points[0]) <= epsilon + 0.01
    else:  # a block: its rectangle, whose pixel corners lie 0.5 px off the crack midpoints (the corner allowance)
        assert result.stats["per_boundary"][0]["corners"] == 4
        assert fit.hausdorff == pytest.approx(0.5) and fit.hausdorff <= fit.info["tolerance_near_corners"]
        rows, cols = np.nonzero(mask)
        joins = result.splines[0].bezier()[:, 0]
        np.testing.assert_allclose(np.sort(joins[:, 0]), np.sort([cols.min(), cols.min(), cols.max() + 1, cols.max() + 1]))
        np.testing.assert_allclose(np.sort(joins[:, 1]), np.sort([rows.min(), rows.min(), rows.max() + 1, rows.max() + 1]))
    assert any("small-outline path" in note for note in result.notes)


def test_noise_image_converges_reproducibly_with_consistent_snapshots():
    """A 40 x 40 speckle image: every boundary converges within epsilon (re-measured independently), two
    runs give the same SVG, the batch gives what fit_outline gives per boundary, snapshots end at the result."""
    from splinecraft.capture.fitting import SMALL_OUTLINE, fit_outline, fit_small_outlines
    from splinecraft.capture.fitting.small import keeps_area

    mask = np.random.default_rng(0).random((40, 40)) < 0.3
    # at epsilon itself (the noise rule would raise it); every speck kept (by default those of 1-2 px are dropped)
    result = trace(mask, epsilon=0.8, noise_factor=0, min_speck_area=0)
    small = [k for k, p in enumerate(result.points) if len(p) < SMALL_OUTLINE]
    assert len(small) > 50 and result.stats["boundaries"] > len(small)  # large outlines too
    collapsed = 0
    for k in small:
        fit = result.fits[k]
        assert fit.converged and fit.hausdorff <= 0.8
        assert _two_sided_deviation(fit.spline.bezier(), result.points[k]) <= 0.81
        single = fit_outline(result.points[k], result.corners[k], epsilon=0.8)
        np.testing.assert_array_equal(single.spline.bezier(), fit.spline.bezier())
        if not fit.info.get("small_outline"):  # its small-outline fit collapsed: fitted by the regression spline
            own = fit_small_outlines([result.points[k]], [result.corners[k]], epsilon=0.8)[0]
            assert not keeps_area(result.points[k], own.spline.bezier())
            collapsed += 1
    assert collapsed < len(small) / 2
    for entry, fit in zip(result.stats["per_boundary"], result.fits):
        assert (entry["reason"] is None) == fit.converged
    again = trace(mask, epsilon=0.8, noise_factor=0, min_speck_area=0)
    assert again.to_svg() == result.to_svg()
    for fit in result.fits:  # the full lsq path's Spline snaps the joins (ulps); the small path is exact
        check = np.testing.assert_array_equal if fit.info.get("small_outline") else np.testing.assert_allclose
        check(np.asarray(fit.snapshots[-1].bezier), fit.spline.bezier())
    merged = result.snapshots
    assert [m.iteration for m in merged] == list(range(result.stats["iterations"] + 1))
    assert merged[-1].finished.all()
    np.testing.assert_allclose(merged[-1].bezier, np.concatenate([s.bezier() for s in result.splines]))
    lean = trace(mask, epsilon=0.8, noise_factor=0, min_speck_area=0, keep_snapshots=False)
    assert lean.to_svg() == result.to_svg() and lean.snapshots == []


def test_small_outline_path_can_be_turned_off():
    mask = np.zeros((12, 12), bool)
    mask[3:8, 3:8] = True
    default = trace(mask)
    full = trace(mask, fit_params={"small_outline": 0})
    assert default.stats["per_boundary"][0]["small_outline"]
    assert not full.stats["per_boundary"][0]["small_outline"]
    assert not any("small-outline" in note for note in full.notes)
    thesis = trace(mask, method="random")
    assert not thesis.stats["per_boundary"][0]["small_outline"]
    with pytest.raises(ValueError, match="small_outline"):
        trace(mask, fit_params={"small_outline": -1})
    with pytest.raises(TypeError, match=r"^fit_params has an unknown key 'no_such_option' for method 'lsq'"):
        trace(mask, fit_params={"no_such_option": 1})


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 10_000), st.integers(10, 56), st.floats(0.05, 0.6), st.sampled_from([0.3, 0.8, 2.0]),
       st.booleans())
# a small outline whose interpolant through every contour point overshoots beside a corner (0.38 px at epsilon
# 0.3): the small-outline path got stuck there and said so; the regression spline's corner zones converge
@example(seed=48, size=48, ink=0.140625, epsilon=0.3, blur=True)
def test_any_bitmap_converges_within_epsilon(seed, size, ink, epsilon, blur):
    """Noise, specks and blurred blobs (many tiny outlines, corners every few steps, thin necks): every
    boundary converges and the result stays within epsilon (+ 0.5 px at extrapolated corner tips, or the
    distance of an extrapolated tip from the pixels where that is more: at most ``tip_reach`` of its angle,
    docs/capture.md §12 "Guarantee")."""
    from scipy import ndimage

    rng = np.random.default_rng(seed)
    values = rng.random((size, size))
    if blur:
        values = ndimage.gaussian_filter(values, 1.5)
    mask = values < np.quantile(values, ink)
    if not mask.any():
        mask[size // 2, size // 2] = True
    result = trace(mask, epsilon=epsilon, noise_factor=0)
    assert result.stats["converged"], [pb.get("reason") for pb in result.stats["per_boundary"]]
    assert result.stats["hausdorff"] <= epsilon + tip_allowance(result) + 1e-9
    assert len(result.splines) == result.stats["boundaries"]
    # with the noise rule (the default) the same holds for the tolerance it chose (epsilon or more), per boundary
    # (a boundary seen at a coarser scale k is fitted with k * min(epsilon, DEFAULT_EPSILON) where that is more)
    adaptive = trace(mask, epsilon=epsilon, keep_snapshots=False)
    tolerance = adaptive.stats["tolerance"]
    assert tolerance >= epsilon and adaptive.stats["converged"]
    allowance = tip_allowance(adaptive)
    for entry in adaptive.stats["per_boundary"]:
        assert entry["tolerance"] == max(tolerance, entry["corner_scale"] * min(epsilon, DEFAULT_EPSILON))
        assert entry["hausdorff"] <= entry["tolerance"] + allowance + 1e-9


def tip_allowance(result):
    """The largest extra tolerance at an extrapolated tip over all boundaries (docs/capture.md §12,
    "Guarantee"): 0.5 px, or an extrapolated tip's distance from the pixel outline where that is more. The tip
    itself is checked against its bound: within ``tip_reach`` of the sharpest corner's angle (at most 5 px)."""
    from splinecraft.capture.fitting.tips import MAX_TIP_REACH

    extra = [fit.info["tolerance_near_corners"] - fit.epsilon for fit in result.fits]
    assert max(extra) <= MAX_TIP_REACH + 1e-9
    return max([0.5] + extra)


@pytest.mark.parametrize("epsilon", [1e-300, 5e-324, 0.0009])
def test_epsilon_below_the_bound_is_refused_by_name(epsilon):
    """Tolerances below MIN_EPSILON (a thousandth of a pixel) are a ValueError naming epsilon, never a huge
    allocation ("Maximum allowed size exceeded")."""
    from splinecraft.capture.fitting import MIN_EPSILON

    assert epsilon < MIN_EPSILON
    with pytest.raises(ValueError, match="epsilon"):
        trace(render_disc(20, 10, 10, 6), epsilon=epsilon)


def test_smallest_epsilon_is_accepted_and_bounded():
    from splinecraft.capture.fitting import MIN_EPSILON

    result = trace(render_disc(20, 10, 10, 6), epsilon=MIN_EPSILON, max_iterations=3, keep_snapshots=False)
    assert result.stats["iterations"] <= 3 + 4  # insertion rounds, then at most the removal rounds


@pytest.mark.parametrize("kwargs, error, name", [
    ({"corner_params": {"closed": False}}, TypeError, "corner_params['closed']"),
    ({"corner_params": {"method": "srm05"}}, TypeError, "corner_params['method']"),
    ({"corner_method": ["srm05"]}, TypeError, "corner_method"),
    ({"method": ["lsq"]}, TypeError, "method"),
    ({"fit_params": {"epsilon": 0.5}}, TypeError, "fit_params['epsilon']"),
    ({"fit_params": {"method": "lsq"}}, TypeError, "fit_params['method']"),
    ({"fit_params": {"small_outline": 2.5}}, TypeError, "small_outline"),
    ({"fit_params": {"initial_density": 1e300}}, ValueError, "initial_density"),
    ({"max_iterations": True}, TypeError, "max_iterations"),
    ({"keep_snapshots": "yes"}, TypeError, "keep_snapshots"),
    ({"tau": 3.0}, ValueError, "tau"),
])
def test_bad_settings_name_their_argument(kwargs, error, name):
    import re

    with pytest.raises(error, match=re.escape(name)):
        trace(render_disc(20, 10, 10, 6), **kwargs)


@pytest.mark.parametrize("d", ["M0 0 L10 0 L10 10 Z 5 5", "M0 0 h10 v10 z 1", "M0 0 L1 0 L1 1 ZZ 2 2"])
def test_numbers_after_a_closepath_are_refused_not_looped_on(d):
    with pytest.raises(ValueError, match="takes no numbers"):
        parse_path_data(d)


@pytest.mark.parametrize("points, snapshots", [(False, False), (True, True)])
def test_to_dict_is_plain_json_as_built(points, snapshots):
    """The per-boundary entries and spline dicts are built from plain values and not walked again (on a noise
    image's thousands of boundaries the walk cost more than the trace): walking the result changes nothing, no
    numpy value slips through, and strict JSON reads back the same."""
    from splinecraft._json import to_jsonable

    noise = np.random.default_rng(3).random((40, 40)) < 0.4
    from splinecraft import datasets

    for image in (noise, datasets.thesis_object("ali")):
        data = trace(image).to_dict(include_points=points, include_snapshots=snapshots)
        assert to_jsonable(data, non_finite="error") == data

        def leaves(value):
            if isinstance(value, dict):
                return [x for item in value.values() for x in leaves(item)]
            if isinstance(value, list):
                return [x for item in value for x in leaves(item)]
            return [value]

        assert {type(x) for x in leaves(data)} <= {int, float, str, bool, type(None)}
        assert json.loads(json.dumps(data, allow_nan=False)) == data


@pytest.mark.parametrize("method", ["random", "euclidean", "fuzzy"])
def test_pixel_chains_of_thin_strokes_trace_with_the_thesis_methods(method):
    """The pixel chain of a stroke one pixel wide visits its pixel centres twice; the thesis methods' interpolant
    takes distinct consecutive knots, so the repeated ones are left out (every 3 x 3 pattern, a 1-px line, an
    L of three pixels): a result, never the engine's "points coincide"."""
    rng = np.random.default_rng(0)
    patterns = [np.pad(np.array([(bits >> i) & 1 for i in range(9)], bool).reshape(3, 3), 2)
                for bits in rng.choice(np.arange(1, 512), 40, replace=False)]
    patterns += [np.pad(np.ones((1, 30), bool), 3), np.pad(np.array([[0, 1, 1], [1, 0, 0]], bool), 2)]
    for mask in patterns:
        for corner_method in ("tangent-jump", "srm05"):
            result = trace(mask, contour="pixels", method=method, corner_method=corner_method, min_speck_area=0,
                           keep_snapshots=False)
            assert len(result.splines) == result.stats["boundaries"] >= 1
            assert all(np.isfinite(s.bezier()).all() for s in result.splines)


def test_the_documented_child_seed_refits_a_boundary_alike():
    """trace's docstring names boundary k's seed; fit_outline with it gives that boundary's fit bit for bit."""
    from splinecraft.capture.fitting import fit_outline

    yy, xx = np.mgrid[0:80, 0:80] + 0.5
    mask = ((xx - 25) ** 2 + (yy - 40) ** 2 < 15 ** 2) | ((xx - 60) ** 2 + (yy - 40) ** 2 < 12 ** 2)
    result = trace(mask, method="random", seed=7, corner_method="srm05")
    for k in range(len(result.splines)):
        child = int(np.random.SeedSequence(7, spawn_key=(k,)).generate_state(1, dtype=np.uint32)[0])
        again = fit_outline(result.points[k], result.corners[k], method="random", seed=child,
                            epsilon=result.stats["tolerance"])
        np.testing.assert_array_equal(again.spline.bezier(), result.splines[k].bezier())
