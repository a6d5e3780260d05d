"""Hostile input to outline capture's first stages: images, masks, outlines and parameters.

Every case ends in a ``TypeError`` / ``ValueError`` whose message names the argument, or in a valid result:
a bool mask of the image's shape (``load_bitmap``), boundaries whose signed areas add up to the ink
(``trace_boundaries``), sorted in-range corner indices (``corners``), a finite traced outline (``trace``).
Nothing here may hang or raise another exception type. The inputs are small, so the whole file runs in
seconds.
"""
from __future__ import annotations

import importlib
import io
import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import array_shapes, arrays
from PIL import Image

import splinecraft as sc
from splinecraft.capture import CORNER_METHODS, load_bitmap, trace_boundaries
from splinecraft.capture.corners import corners
from splinecraft.capture.image import InkPolarityWarning

FUZZ = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])

# ---------------------------------------------------------------------------------------------- strategies
hostile_numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**30, 10**30), st.booleans(), st.none(),
    st.text(max_size=4), st.lists(st.integers(), max_size=2), st.just(b"\x00"), st.just(1e-320),
)

image_dtypes = st.sampled_from([np.bool_, np.uint8, np.uint16, np.int16, np.int64, np.float32, np.float64,
                                np.complex64, np.object_])


@st.composite
def hostile_arrays(draw):
    dtype = draw(image_dtypes)
    shape = draw(array_shapes(min_dims=0, max_dims=4, min_side=0, max_side=7))
    if dtype is np.object_:
        return np.empty(shape, dtype=object)
    if dtype is np.complex64:
        return np.zeros(shape, dtype)
    elements = None
    if np.dtype(dtype).kind == "f":
        elements = st.one_of(st.floats(-2, 2, width=32), st.sampled_from([np.nan, np.inf]))
    return draw(arrays(dtype, shape, elements=elements))


def encoded(mask, fmt="png"):
    buffer = io.BytesIO()
    Image.fromarray(np.where(mask, 0, 255).astype(np.uint8)).save(buffer, fmt)
    return buffer.getvalue()


def hostile_images():
    garbage = st.binary(max_size=64)
    truncated = st.integers(1, 60).map(lambda n: encoded(np.eye(8, dtype=bool))[:n])
    others = st.one_of(st.none(), st.integers(), st.floats(), st.text(max_size=5).map(lambda t: "\x00" + t),
                       st.lists(st.integers(0, 1), max_size=3), st.dictionaries(st.text(max_size=2), st.integers()))
    return st.one_of(hostile_arrays(), garbage, truncated, others)


def names_the_argument(error, *names):
    text = str(error).lower()
    assert any(name in text for name in names), f"{type(error).__name__}: {error}"


# ---------------------------------------------------------------------------------------------- load_bitmap
@FUZZ
@given(hostile_images())
def test_load_bitmap_of_a_hostile_image(image):
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            mask = load_bitmap(image)
    except (TypeError, ValueError) as error:
        names_the_argument(error, "image", "mask", "array", "bytes", "dtype", "value", "path")
        return
    except FileNotFoundError as error:         # documented: a path that does not exist
        assert isinstance(image, str) and "not found" in str(error)
        return
    assert mask.dtype == bool and mask.ndim == 2
    if isinstance(image, np.ndarray):
        assert mask.shape == image.shape[:2]
    for warning in caught:  # only the documented ones: ink polarity, or low contrast thresholded into ink
        assert isinstance(warning.message, InkPolarityWarning) or (
            "made every pixel ink" in str(warning.message) and mask.all()), warning.message


@FUZZ
@given(threshold=hostile_numbers | st.sampled_from(["otsu", "sauvola", "local", "Otsu", "0.5"]),
       invert=hostile_numbers, min_speck_area=hostile_numbers, connectivity=hostile_numbers | st.just("minority"),
       max_pixels=hostile_numbers)
def test_load_bitmap_with_hostile_parameters(threshold, invert, min_speck_area, connectivity, max_pixels):
    gray = (np.add.outer(np.arange(12), np.arange(15)) * 7 % 256).astype(np.uint8)
    kwargs = dict(threshold=threshold, invert=invert, min_speck_area=min_speck_area, connectivity=connectivity,
                  max_pixels=max_pixels)
    try:
        mask = load_bitmap(gray, **kwargs)
    except (TypeError, ValueError) as error:
        names_the_argument(error, *kwargs)
        return
    assert mask.shape == gray.shape and mask.dtype == bool


def test_decompression_bomb_is_refused_from_the_header():
    # a 1-bit PNG of 13 000 x 13 000 pixels (169 Mpx) is a few hundred KB: it must be refused before decoding
    bomb = Image.new("1", (13_000, 13_000), 1)
    buffer = io.BytesIO()
    bomb.save(buffer, "png")
    data = buffer.getvalue()
    assert len(data) < 1_000_000
    with pytest.raises(ValueError, match="max_pixels"):
        load_bitmap(data)
    with pytest.raises(ValueError, match="max_pixels"):
        sc.trace(data)


# ---------------------------------------------------------------------------------------------- trace_boundaries
@FUZZ
@given(arrays(np.bool_, array_shapes(min_dims=2, max_dims=2, min_side=1, max_side=12)),
       st.sampled_from([4, 8, "minority"]))
def test_boundaries_of_any_mask_add_up(mask, connectivity):
    boundaries = trace_boundaries(mask, connectivity=connectivity)
    assert sum(b.area for b in boundaries) == int(mask.sum())
    assert all(np.isfinite(b.outline).all() for b in boundaries)


@FUZZ
@given(hostile_arrays(), hostile_numbers)
def test_trace_boundaries_of_hostile_input(mask, connectivity):
    try:
        trace_boundaries(mask, connectivity=connectivity)
    except (TypeError, ValueError) as error:
        names_the_argument(error, "mask", "connectivity")


# ---------------------------------------------------------------------------------------------- corners
coordinates = st.one_of(st.floats(-1e300, 1e300), st.sampled_from([np.nan, np.inf, -np.inf]))


@st.composite
def hostile_outlines(draw):
    kind = draw(st.sampled_from(["random", "scaled", "duplicates", "tiny", "shape"]))
    if kind == "shape":
        return draw(arrays(np.float64, array_shapes(min_dims=0, max_dims=3, max_side=4)))
    n = draw(st.integers(0, 60))
    if kind == "random":
        return draw(arrays(np.float64, (n, 2), elements=coordinates))
    angles = np.linspace(0, 2 * np.pi, max(n, 1), endpoint=False)
    ring = np.column_stack([np.cos(angles), np.sin(angles)]) * np.where(np.arange(max(n, 1)) % 5 == 0, 1, 0.6)[:, None]
    if kind == "scaled":
        return ring * draw(st.sampled_from([1e-300, 1e-9, 1.0, 1e7, 1e150, 1e300]))
    if kind == "duplicates":
        return np.repeat(ring * 20, draw(st.integers(1, 4)), axis=0)
    return ring * 1e-12 + 5.0


@FUZZ
@given(hostile_outlines(), st.sampled_from(sorted(CORNER_METHODS)), st.booleans())
def test_corners_of_a_hostile_outline(points, method, closed):
    try:
        found = corners(points, method, closed=closed)
    except (TypeError, ValueError) as error:
        names_the_argument(error, "points")
        return
    assert found.dtype == np.intp and np.all(np.diff(found) > 0)
    assert found.size == 0 or (0 <= found[0] and found[-1] < len(points))


PARAMETERS = ["smoothing", "tolerance", "min_turn", "min_excess", "flank", "max_arm", "separation", "zct", "dt",
              "ta", "m", "max_angle", "s", "threshold", "s_min", "s_max", "arm_limit", "d_min", "d_max",
              "alpha_max", "closed", "method", "bogus"]


@FUZZ
@given(st.sampled_from(sorted(CORNER_METHODS)), st.sampled_from(PARAMETERS),
       hostile_numbers | st.sampled_from([1e9, 10**12, -1, 0, 3, (4, 10), (10, 4), (0, 10**9)]))
def test_corners_with_a_hostile_parameter(method, name, value):
    angles = np.linspace(0, 2 * np.pi, 120, endpoint=False)
    outline = np.column_stack([np.cos(angles), np.sin(angles)]) * 30 * np.where(np.arange(120) % 30 < 15, 1, 0.7)[:, None]
    try:
        found = corners(outline, method, **{name: value})
    except (TypeError, ValueError) as error:
        names_the_argument(error, name, "params", "method", "closed")
        return
    assert found.dtype == np.intp and (found.size == 0 or found[-1] < len(outline))


@FUZZ
@given((hostile_numbers | st.sampled_from([["tangent-jump"], {"srm05": 1}, "SRM05", "harris"])).filter(
    lambda method: not (isinstance(method, str) and method in CORNER_METHODS)))
def test_corners_with_a_hostile_method(method):
    with pytest.raises((TypeError, ValueError)) as caught:
        corners(np.eye(2), method)
    names_the_argument(caught.value, "method")


def test_corner_cost_does_not_grow_with_the_coordinates():
    # 200 points on a circle of radius 1e7 px: resampled relative to its own spacing, not at 1 px
    angles = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    circle = 1e7 * np.column_stack([np.cos(angles), np.sin(angles)])
    for method in CORNER_METHODS:
        found = corners(circle, method)
        assert found.size == 0 or found[-1] < 200
    with pytest.raises(ValueError, match="smoothing"):
        corners(circle, "tangent-jump", smoothing=1e9)


# ---------------------------------------------------------------------------------------------- trace
def small_mask():
    mask = np.zeros((24, 24), bool)
    mask[4:20, 4:20] = True
    mask[9:14, 9:14] = False
    return mask


@pytest.mark.parametrize("kwargs, name", [
    (dict(corner_method=["tangent-jump"]), "corner_method"),
    (dict(corner_method="harris"), "corner_method"),
    (dict(corner_params={"method": "srm05"}), "corner_params"),
    (dict(corner_params={"closed": False}), "corner_params"),
    (dict(corner_params={"zct": 3}), "corner_params"),
    (dict(corner_params={"smoothing": 1e9}), "smoothing"),
    (dict(connectivity="eight"), "connectivity"),
    (dict(threshold="niblack"), "threshold"),
    (dict(min_speck_area=-3), "min_speck_area"),
])
def test_trace_names_the_bad_argument(kwargs, name):
    with pytest.raises((TypeError, ValueError)) as caught:
        sc.trace(small_mask(), **kwargs)
    names_the_argument(caught.value, name)


def square_mask(side=9):
    """One square of ``4 side`` contour points: 36 for the default, a short contour (fewer than 64 points)."""
    mask = np.zeros((side + 10, side + 10), bool)
    mask[5:5 + side, 5:5 + side] = True
    return mask


@pytest.mark.parametrize("side", [9, 60])
@pytest.mark.parametrize("kwargs, message", [
    (dict(corner_params={"min_turn": -5}), r"corner_params\['min_turn'\] must be >= 0 and < 180, got -5"),
    (dict(corner_method="srm05", corner_params={"ta": 500}), r"corner_params\['ta'\] must be > 0 and < 180, got 500"),
    (dict(corner_method="bt87", corner_params={"s_min": 9}), r"corner_params\['s_max'\] must be >= "),
])
def test_trace_refuses_a_bad_corner_params_value_up_front(side, kwargs, message):
    """A bad value used to be checked by the detector: on a short contour (36 points) it became the note "too few
    for corner detection" and the square got no corners; on a large one it came after loading and tracing, as
    "boundary 0: corner detection failed"."""
    with pytest.raises(ValueError, match=message) as caught:
        sc.trace(square_mask(side), **kwargs)
    assert "boundary" not in str(caught.value)


def test_trace_checks_corner_params_before_the_image():
    with pytest.raises(ValueError, match=r"corner_params\['min_turn'\]"):
        sc.trace("/nonexistent/shape.png", corner_params={"min_turn": -5})


def test_corner_detection_of_a_short_contour_does_not_hide_a_parameter_error():
    trace_module = importlib.import_module("splinecraft.capture.trace")  # the module, not the function
    points = np.asarray(trace_boundaries(square_mask())[0].outline, float)
    assert len(points) < trace_module.SHORT_CONTOUR
    notes = []
    with pytest.raises(ValueError, match=r"corner_params\['min_turn'\]"):
        trace_module._detect(points, 0, "tangent-jump", {"min_turn": -5}, notes)
    assert notes == []
    assert len(trace_module._detect(points, 0, "tangent-jump", {}, notes)) == 4 and notes == []


def test_trace_of_a_masked_array_or_a_matrix():
    gray = np.where(small_mask(), 0, 255).astype(np.uint8)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(TypeError, match=r"masked array.*filled\(255\)"):
            sc.trace(np.ma.masked_array(gray, mask=gray > 0))
        matrix = np.asarray(gray).view(np.matrix)
        assert sc.trace(matrix).stats["boundaries"] == sc.trace(gray).stats["boundaries"] == 2


def test_trace_of_a_path_given_as_bytes(tmp_path):
    path = tmp_path / "shape.png"
    path.write_bytes(encoded(small_mask()))
    with pytest.raises(ValueError, match=r"not an image file.*pass it as str or pathlib\.Path"):
        sc.trace(bytes(path))
    assert sc.trace(path).stats["boundaries"] == 2


def test_trace_of_png_bytes_and_of_garbage_bytes():
    result = sc.trace(encoded(small_mask()))
    assert result.stats["boundaries"] == 2 and math.isfinite(result.stats["hausdorff"])
    with pytest.raises(ValueError, match="not an image"):
        sc.trace(b"GIF89a but not really")


def test_inverted_bool_mask_warns_through_trace():
    with pytest.warns(UserWarning, match="invert=True"):
        result = sc.trace(~small_mask())
    assert result.stats["boundaries"] >= 1


@pytest.mark.parametrize("method", sorted(CORNER_METHODS))
def test_corners_of_an_outline_beyond_pixel_scale_say_so(method):
    """Coordinates of 1e300 px overflowed the detectors' squared lengths (RuntimeWarnings, a meaningless result):
    beyond 1e15 px the outline is refused with the reason; 1e12 px still works."""
    angles = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    ring = np.column_stack([np.cos(angles), np.sin(angles)]) * np.where(np.arange(40) % 5 == 0, 1, 0.6)[:, None]
    with pytest.raises(ValueError, match=r"points\[0\].*pixel units"):
        corners(ring * 1e300, method)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        found = corners(ring * 1e12, method)
    assert found.dtype == np.intp


@pytest.mark.parametrize("smoothing", [5e-324, 1e-310])
def test_a_subnormal_smoothing_is_no_smoothing_without_a_warning(smoothing):
    """A Gaussian of a subnormal width: the offsets of its kernel overflow to inf and their weights to 0 (no
    smoothing), without numpy's 'overflow encountered in divide' (the fuzz test above found it)."""
    import warnings

    angles = np.linspace(0, 2 * np.pi, 120, endpoint=False)
    outline = np.column_stack([np.cos(angles), np.sin(angles)]) * 30 * np.where(np.arange(120) % 30 < 15, 1, 0.7)[:, None]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        found = corners(outline, "tangent-jump", smoothing=smoothing)
    np.testing.assert_array_equal(found, corners(outline, "tangent-jump", smoothing=0.0))


# ---------------------------------------------------------------------------------------------- trace options (session 23)
@pytest.mark.parametrize("spacing", [1e-12, 1e-300, 1e-3])
def test_a_tiny_sample_spacing_is_refused_not_a_memory_error(spacing):
    """fit_params={'sample_spacing': 1e-12} was accepted ((0, 2]) and asked numpy for 1.4 PiB (MemoryError),
    1e-300 was 'OverflowError: int too big to convert', 1e-6 px exhausted the machine's memory: the curve
    samples of the deviation check grow as 1 / spacing."""
    with pytest.raises(ValueError, match=r"^fit_params\['sample_spacing'\] \(px\) must be >= 0\.01"):
        sc.trace(small_mask(), fit_params={"sample_spacing": spacing})
    assert sc.trace(small_mask(), fit_params={"sample_spacing": 0.01}).stats["converged"]


def disc_mask(size=40, radius=15):
    yy, xx = np.mgrid[:size, :size]
    return (yy - size // 2) ** 2 + (xx - size // 2) ** 2 < radius ** 2


@pytest.mark.parametrize("options, error, message", [
    ({"interval_weights": [1, 2, 3]}, TypeError, r"^fit_params\['interval_weights'\] must be one number"),
    ({"point_tension": [0.0, 0.0, 0.0]}, TypeError, r"^fit_params\['point_tension'\] must be one number"),
    ({"alpha": np.array(2.0)}, TypeError, r"^fit_params\['alpha'\] must be one number"),
    ({"interval_weights": 0}, ValueError, r"^fit_params\['interval_weights'\] must be > 0"),
    ({"beta": 0}, ValueError, r"^fit_params\['beta'\] must be non-zero"),
    ({"point_tension": float("nan")}, ValueError, r"^fit_params\['point_tension'\] must be a finite number"),
])
def test_thesis_engine_options_are_one_number_checked_before_the_image(options, error, message):
    """fit_params={'interval_weights': [1, 2, 3]} with a thesis method was handed to the interpolant of every
    piece: on a disc at epsilon=5 it matched the 3 seed knots and was applied to arbitrary intervals without a
    word; at epsilon=0.8 it failed after the fit had started, as '4 values are needed (4 for 4 closed points)'
    for a boundary of 116 points. The knots change with every insertion, so only one number can apply."""
    with pytest.raises(error, match=message):
        sc.trace("/nonexistent/shape.png", method="random", epsilon=5, fit_params=options)
    with pytest.raises(error, match=message):
        sc.trace(disc_mask(), method="random", epsilon=5, fit_params=options)
    result = sc.trace(disc_mask(), method="random", epsilon=5, fit_params={"interval_weights": np.int64(2)})
    assert result.params["fit_params"] == {"interval_weights": 2}


@pytest.mark.parametrize("method", ["random", "euclidean", "positional", "random3", "equal3"])
def test_fuzzy_weights_of_another_method_are_refused(method):
    """fit_params={'fuzzy_weights': (0.9, 0.1)} with a method other than 'fuzzy' was checked and then ignored:
    the same curve as without it, no word (tau is refused the same way for the methods without a nearness
    rule)."""
    with pytest.raises(ValueError, match=r"^fit_params\['fuzzy_weights'\] is used by the method 'fuzzy'.*only"):
        sc.trace(small_mask(), method=method, fit_params={"fuzzy_weights": (0.9, 0.1)})
    assert sc.trace(small_mask(), method="fuzzy", fit_params={"fuzzy_weights": (0.9, 0.1)}).stats["segments"] > 0


@pytest.mark.parametrize("key, value, message", [
    ("sample_spacing", -1.0, "fit_params['sample_spacing'] (px) must be >= 0.01 and <= 2, got -1.0"),
    ("sample_spacing", float("nan"),
     "fit_params['sample_spacing'] (px) must be a finite number >= 0.01 and <= 2, got nan"),
    ("sample_spacing", np.float64(-0.5), "fit_params['sample_spacing'] (px) must be >= 0.01 and <= 2, got -0.5"),
    ("initial_density", -1.0, "fit_params['initial_density'] must be >= 0 and <= 1e+06, got -1.0"),
    ("initial_density", float("inf"),
     "fit_params['initial_density'] must be a finite number >= 0 and <= 1e+06, got inf"),
])
def test_bounded_lsq_options_give_their_whole_range_for_any_bad_value(key, value, message):
    """sample_spacing and initial_density were checked twice: first as every real option of lsq (a finite
    number >= 0), then against their own range. A negative or NaN value got the first message, 'sample_spacing
    must be a finite number >= 0', a range that 0 (then refused as 'must be >= 0.01 and <= 2') does not meet;
    every bad value now gets the option's own range."""
    with pytest.raises(ValueError) as caught:
        sc.trace(small_mask(), fit_params={key: value})
    assert str(caught.value) == message


@pytest.mark.parametrize("method, options, error, bare", [
    ("lsq", {"merge_tolerance": -1}, ValueError, "merge_tolerance must be >= 0, got -1.0"),
    ("lsq", {"min_gap": 0}, ValueError, "min_gap must be >= 1, got 0"),
    ("lsq", {"fallback": "yes"}, TypeError, "fallback must be a bool (True or False), got 'yes' (str)"),
    ("lsq", {"joint_continuity": 3}, ValueError, "joint_continuity (1 = C1, 2 = C2) must be <= 2, got 3"),
    ("lsq", {"geometric_corners": "x"}, ValueError, "geometric_corners must be one of [False, True, 'clean'], got 'x'"),
    ("lsq", {"tangent_stride": 2}, ValueError, "'tangent_stride' applies to the thesis methods"),
    ("random", {"tangent_stride": 0}, ValueError, "tangent_stride must be >= 1, got 0"),
    ("random", {"alpha": float("inf")}, ValueError, "alpha must be a finite number, got inf"),
    ("random", {"point_tension_scale": "x"}, ValueError, "point_tension_scale must be one of"),
    ("random", {"fuzzy_weights": (0.9, 0.1)}, ValueError, "fuzzy_weights is used by the method 'fuzzy'"),
    ("fuzzy", {"fuzzy_weights": (0.1, "v")}, TypeError, "fuzzy_weights[1] (v) must be a real number"),
    ("fuzzy", {"fuzzy_weights": (0.1, 0.2)}, ValueError, "fuzzy_weights (w, v) need w > v >= 0"),
])
def test_a_bad_fit_param_is_named_as_the_caller_wrote_it(method, options, error, bare):
    """``trace(fit_params={"merge_tolerance": -1})`` said 'merge_tolerance must be >= 0', the name of a keyword of
    ``fit_outline`` that the caller never wrote; it says ``fit_params['merge_tolerance']`` now, also from
    ``trace_many``. ``fit_outline(merge_tolerance=-1)`` keeps the bare name."""
    (key,) = options
    contour = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])
    with pytest.raises(error) as caught:
        sc.fit_outline(contour, None, method=method, **options)
    assert str(caught.value).startswith(bare), str(caught.value)
    named = f"fit_params[{key!r}]" + bare.removeprefix(repr(key)).removeprefix(key)
    with pytest.raises(error) as caught:
        sc.trace(small_mask(), method=method, fit_params=options)
    assert str(caught.value).startswith(named), str(caught.value)
    with pytest.raises(error) as caught:
        sc.trace_many([small_mask()], method=method, fit_params=options, progress=False)
    assert str(caught.value).startswith(named), str(caught.value)
