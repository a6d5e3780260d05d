"""The shared validation kit (splinecraft._validation): one wording, one coincidence rule."""
import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import splinecraft as sc
from splinecraft import _validation as v

FAST = settings(max_examples=60, deadline=None)

NOT_REAL = [True, False, np.bool_(True), "1.0", b"1", None, [1.0], (1.0,), {1.0: 1}, 1 + 2j, np.array([1.0]), object()]


# ---------------------------------------------------------------------------------------------- numbers
@pytest.mark.parametrize("value", NOT_REAL)
def test_check_number_refuses_non_reals_naming_the_argument(value):
    with pytest.raises(TypeError, match=r"^speed must be a real number"):
        v.check_number(value, "speed")


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, np.float64("nan")])
def test_check_number_refuses_non_finite(value):
    with pytest.raises(ValueError, match=r"^speed must be a finite number"):
        v.check_number(value, "speed")


def test_check_number_infinite_allowed_on_request_but_never_nan():
    assert v.check_number(math.inf, "limit", finite=False) == math.inf
    with pytest.raises(ValueError, match="limit"):
        v.check_number(math.nan, "limit", finite=False)
    with pytest.raises(ValueError, match=r"limit must be <= 10"):
        v.check_number(math.inf, "limit", finite=False, maximum=10)


@FAST
@given(st.floats(allow_nan=False, allow_infinity=False), st.floats(-1e6, 1e6), st.floats(0, 1e6),
       st.booleans(), st.booleans())
def test_check_number_bounds_match_the_comparison(value, low, width, low_closed, high_closed):
    high = low + width
    inside = (value > low or (low_closed and value == low)) and (value < high or (high_closed and value == high))
    if inside:
        assert v.check_number(value, "x", minimum=low, maximum=high, inclusive=(low_closed, high_closed)) == value
    else:
        with pytest.raises(ValueError, match=r"^x must be [<>]"):
            v.check_number(value, "x", minimum=low, maximum=high, inclusive=(low_closed, high_closed))


def test_check_number_accepts_numpy_scalars_and_returns_float():
    for value in (np.float32(1.5), np.int64(3), 7, np.uint8(2)):
        result = v.check_number(value, "x")
        assert type(result) is float and result == float(value)
    assert v.check_positive_number(2, "x") == 2.0
    with pytest.raises(ValueError, match=r"x must be > 0, got 0.0"):
        v.check_positive_number(0, "x")


# ---------------------------------------------------------------------------------------------- integers
@pytest.mark.parametrize("value", [True, np.bool_(False), 1.0, 2.5, "3", None, [1], math.nan])
def test_check_int_refuses_bools_floats_and_strings(value):
    with pytest.raises(TypeError, match=r"^count must be an integer"):
        v.check_int(value, "count")


@FAST
@given(st.integers(-10**20, 10**20), st.integers(-100, 100))
def test_check_int_accepts_python_and_numpy_integers(value, minimum):
    if value >= minimum:
        assert v.check_int(value, "n", minimum=minimum) == value
        if -2**63 <= value < 2**63:
            result = v.check_int(np.int64(value), "n", minimum=minimum)
            assert type(result) is int and result == value
    else:
        with pytest.raises(ValueError, match=rf"^n must be >= {minimum}, got {value}$"):
            v.check_int(value, "n", minimum=minimum)


def test_check_int_maximum_and_integral_floats():
    with pytest.raises(ValueError, match=r"n must be <= 5, got 6"):
        v.check_int(6, "n", maximum=5)
    assert v.check_int(3.0, "n", integral_floats=True) == 3
    with pytest.raises(TypeError, match="n must be an integer"):
        v.check_int(3.5, "n", integral_floats=True)
    with pytest.raises(TypeError, match="n must be an integer"):
        v.check_int(math.inf, "n", integral_floats=True)
    with pytest.raises(TypeError, match="n must be an integer"):
        v.check_int(True, "n", integral_floats=True)
    assert v.check_positive_int(np.int32(4), "n") == 4
    with pytest.raises(ValueError, match="n must be >= 1"):
        v.check_positive_int(0, "n")


# ---------------------------------------------------------------------------------------------- bools and choices
@pytest.mark.parametrize("value", [True, False, np.bool_(True), np.bool_(False)])
def test_check_bool_accepts_exact_bools(value):
    result = v.check_bool(value, "closed")
    assert type(result) is bool and result == bool(value)


@pytest.mark.parametrize("value", ["no", "false", "True", 0, 1, 1.0, None, [], np.array(True), np.int64(1)])
def test_check_bool_refuses_everything_else(value):
    with pytest.raises(TypeError, match=r"^closed must be a bool \(True or False\)"):
        v.check_bool(value, "closed")


def test_check_choice_strings():
    assert v.check_choice("wang", "method", ("wang", "subdivide")) == "wang"
    with pytest.raises(ValueError, match=r"method must be one of \['subdivide', 'wang'\], got 'x'"):
        v.check_choice("x", "method", ("wang", "subdivide"))
    for bad in (["wang"], {"wang": 1}, {"wang"}, np.array(["wang"]), 3, None, True):
        with pytest.raises(TypeError, match=r"^method must be one of"):
            v.check_choice(bad, "method", ("wang", "subdivide"))


def test_check_choice_numbers_and_none():
    assert v.check_choice(None, "mode", (None, 4, 8)) is None
    assert v.check_choice(np.int64(8), "mode", (None, 4, 8)) == 8
    with pytest.raises(TypeError, match="mode must be one of"):
        v.check_choice(True, "mode", (0, 1))
    with pytest.raises(ValueError, match=r"mode must be one of \[None, 4, 8\], got 5"):
        v.check_choice(5, "mode", (None, 4, 8))
    with pytest.raises(TypeError, match="mode must be one of"):
        v.check_choice([4], "mode", (None, 4, 8))


# ---------------------------------------------------------------------------------------------- option mappings
def test_check_options():
    assert v.check_options(None, "corner_params") == {}
    options = {"smoothing": 2.0}
    result = v.check_options(options, "corner_params", allowed=("smoothing", "threshold"))
    assert result == options and result is not options
    with pytest.raises(TypeError, match=r"corner_params has an unknown key 'method'; accepted keys: \['smoothing'"):
        v.check_options({"method": "rj73"}, "corner_params", allowed=("smoothing", "threshold"))
    with pytest.raises(TypeError, match=r"corner_params\['closed'\] cannot be set here: trace sets it"):
        v.check_options({"closed": False}, "corner_params", reserved=("closed",), reserved_reason="trace sets it")
    with pytest.raises(TypeError, match="corner_params keys must be strings"):
        v.check_options({1: 2}, "corner_params")
    with pytest.raises(TypeError, match="corner_params must be a dict"):
        v.check_options([("a", 1)], "corner_params")


# ---------------------------------------------------------------------------------------------- arrays and points
@pytest.mark.parametrize("value, error, text", [
    ("abc", TypeError, "points must be numeric"),
    ([[0, 0], [1]], TypeError, "points must be a numeric array"),
    ([["0", "0"], ["1", "2"]], TypeError, "points must be numeric, got a list containing strings"),
    ([(0, 0), (1, "2")], TypeError, "points must be numeric, got a list containing strings"),
    (np.array([[1j, 0]]), TypeError, "points must be real"),
    ([[0, 0], [np.nan, 1]], ValueError, r"points\[1, 0\] is nan"),
    (None, TypeError, "points must be numeric, got None"),  # numpy would read None as NaN
    ([[0, 0], [None, 1]], TypeError, "points must be numeric, got a list containing None"),
    (np.array([[0, 0], [None, 1]], dtype=object), TypeError, "points must be numeric, got an object array containing None"),
    ([[0, 0], [1, np.inf]], ValueError, r"points\[1, 1\] is inf"),
    ([0, 1, 2], ValueError, r"points must be an \(n, d\) array"),
    (np.zeros((0, 2)), ValueError, "points needs at least 2 points, got 0"),
    (np.zeros((3, 0)), ValueError, "points must have 2 coordinates per point, got 0"),
    ([[0, 0, 0], [1, 1, 1]], ValueError, "points must have 2 coordinates per point"),
])
def test_check_points_errors(value, error, text):
    with pytest.raises(error, match=text):
        v.check_points(value, "points", min_count=2, dim=2)


def test_check_points_returns_float_array():
    with pytest.raises(ValueError, match="points must have at least one coordinate per point"):
        v.check_points(np.zeros((3, 0)))
    points = v.check_points([[0, 0], [1, 2]], min_count=2)
    assert points.dtype == np.float64 and points.shape == (2, 2)


def test_per_item_and_increasing():
    np.testing.assert_array_equal(v.per_item(2, 3, "w", what="one per leg"), [2.0, 2.0, 2.0])
    with pytest.raises(ValueError, match=r"w has length 2 but 3 values are needed \(one per leg\)"):
        v.per_item([1, 2], 3, "w", what="one per leg")
    with pytest.raises(TypeError, match="w must be a number"):
        v.per_item(True, 3, "w", what="one per leg")
    with pytest.raises(ValueError, match=r"knots\[2\] = 1.0 <= knots\[1\] = 2.0"):
        v.check_strictly_increasing(np.array([0.0, 2.0, 1.0]), "knots")


# ---------------------------------------------------------------------------------------------- coincidence rule
def unit_steps(count):
    return st.lists(st.tuples(st.floats(-1, 1), st.floats(-1, 1)), min_size=count, max_size=count)


@FAST
@given(unit_steps(6), st.integers(-300, 300), st.floats(-1e6, 1e6))
@example([(4e-123, 1e-123)] * 6, 0, 1.0)  # a shift that erases the gaps: no premise, no verdict to keep
def test_coincidence_verdict_is_scale_and_translation_free(raw, exponent, shift):
    points = np.cumsum(np.asarray(raw), axis=0)
    points[2] = points[1] + 1e-13 * (points[3] - points[1])  # likely coincident with points[1]
    base_gaps = v.relative_gaps(points)
    scaled = points * 10.0**exponent + shift * 10.0**exponent
    if not np.isfinite(scaled).all():
        return
    gaps = v.relative_gaps(scaled)
    assert np.isfinite(gaps).all()
    # the verdict moves only where a gap sits within rounding of the threshold: adding the shift rounds every
    # coordinate by up to eps * (|shift| + |point|), i.e. by that over the extent in relative units
    extent = v.point_extent(points)
    if not extent > 0:
        return
    rounding = 8 * np.finfo(float).eps * (abs(shift) + np.abs(points).max() + 1.0) / extent
    clear = np.abs(base_gaps - v.COINCIDENT_RTOL) > 1e-6 * v.COINCIDENT_RTOL + rounding
    verdict = base_gaps > v.COINCIDENT_RTOL
    np.testing.assert_array_equal((gaps > v.COINCIDENT_RTOL)[clear], verdict[clear])


def test_relative_gaps_at_the_float_limits():
    big = np.array([[-1.7e308, 0.0], [1.7e308, 1e308], [1.0e308, -1.7e308]])
    gaps = v.relative_gaps(big, closed=True)
    assert np.isfinite(gaps).all() and (gaps > 0.1).all()
    tiny = np.array([[0.0, 0.0], [3e-320, 0.0], [3e-320, 4e-320]])
    gaps = v.relative_gaps(tiny)
    np.testing.assert_allclose(gaps, [0.75, 1.0], rtol=0.2)  # subnormal inputs: few significant bits


def test_check_distinct_neighbours_messages():
    points = np.array([[0.0, 0.0], [1.0, 1.0], [1.0, 1.0 + 1e-13], [2.0, 0.0]])
    with pytest.raises(ValueError, match=r"points\[1\] and points\[2\] coincide"):
        v.check_distinct_neighbours(points)
    loop = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
    with pytest.raises(ValueError, match=r"points\[3\] and points\[0\] coincide \(points\[3\] repeats points\[0\]\)"):
        v.check_distinct_neighbours(loop, closed=True)
    v.check_distinct_neighbours(loop[:3], closed=True)
    with pytest.raises(ValueError, match=r"P\[0\] and P\[1\] coincide"):
        v.check_points(np.ones((3, 2)), "P", distinct=True)
    assert v.point_extent(np.ones((1, 2))) == 0.0


def test_one_rule_in_the_engine():
    from splinecraft import interpolate
    from splinecraft.spline.knots import COINCIDENT_RTOL, remove_coincident

    assert COINCIDENT_RTOL == v.COINCIDENT_RTOL
    for scale in (1e-200, 1.0, 1e200):
        points = scale * np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.5e-12], [2.0, 1.0]])
        with pytest.raises(ValueError, match=r"points\[1\] and points\[2\] coincide"):
            interpolate(points)
        kept, index = remove_coincident(points)
        np.testing.assert_array_equal(index, [0, 1, 3])


def test_an_integral_float_out_of_range_is_named_as_given():
    """corner_params={'m': 1e300} (an integral float, accepted where floats with an integer value are) was
    refused as 'must be <= 200, got 10000000000000000525047602552044202487044685811081591549158541072300...'
    (all 301 digits of int(1e300)); a huge int is shortened like any long value."""
    import re

    from splinecraft._validation import check_int

    with pytest.raises(ValueError, match=r"^m must be <= 200, got 1e\+300$"):
        check_int(1e300, "m", maximum=200, integral_floats=True)
    with pytest.raises(ValueError, match=r"^m must be >= 1, got -5\.0$"):
        check_int(-5.0, "m", minimum=1, integral_floats=True)
    with pytest.raises(ValueError, match=r"^m must be >= 1, got -5$"):
        check_int(-5, "m", minimum=1)
    with pytest.raises(ValueError) as caught:
        check_int(10 ** 400, "m", maximum=200)
    assert len(str(caught.value)) < 120 and re.search(r"got 1000+\.\.\.$", str(caught.value))


# ---------------------------------------------------------------------------------------------- numpy scalars in messages
def _numpy_scalar_cases():
    import splinecraft as sc
    from splinecraft.font import to_glyph
    from splinecraft.outline.contour import Contour
    from splinecraft.plot._figure import _check_size
    from splinecraft.spline.tangents import end_derivatives
    from splinecraft.widgets._outline_state import _handles_of_row

    mask = np.zeros((20, 20), bool)
    mask[5:15, 5:15] = True
    points = np.array([[0, 0], [1, 2], [3, 3], [4, 1], [6, 2]], float)
    square = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    f, i = np.float64, np.int64
    return [
        (lambda: v.check_number(np.str_("x"), "a"), TypeError, "got 'x' (str_)"),
        (lambda: v.check_int(f(2.5), "n"), TypeError, "got 2.5 (float64)"),
        (lambda: v.check_bool(i(1), "flag"), TypeError, "got 1 (int64)"),
        (lambda: v.check_choice(i(6), "c", (4, 8, "minority")), ValueError, "got 6"),
        (lambda: v.check_choice(np.str_("x"), "c", ("a", "b")), ValueError, "got 'x'"),
        (lambda: v.check_options({np.str_("zct"): 1}, "params", allowed=("ta",)), TypeError, "unknown key 'zct'"),
        (lambda: sc.trace(mask, max_iterations=f(2.5)), TypeError, "max_iterations must be an integer, got 2.5"),
        (lambda: sc.trace(mask, connectivity=f(4.0)), TypeError, "got 4.0 (float64)"),
        (lambda: sc.trace(mask, corner_method="srm05", corner_params={"zct": f(2.5)}), TypeError, "got 2.5"),
        (lambda: sc.trace(mask, fit_params={"geometric_corners": i(3)}), ValueError, "got 3"),
        (lambda: sc.trace(mask, method="fuzzy", fit_params={"fuzzy_weights": (f(0.1), f(0.5))}), ValueError,
         "got (0.1, 0.5)"),
        (lambda: sc.load_bitmap(np.zeros((4, 4), np.uint8), threshold=f(1.5)), ValueError, "got 1.5 "),
        (lambda: sc.interpolate(points, end_condition=i(3)), TypeError, "got 3 (int64)"),
        (lambda: sc.trace_many([mask], jobs=f(1.5)), TypeError, "jobs must be an integer, got 1.5"),
        (lambda: end_derivatives(points, [0, np.nan, 2, 3, 4]), ValueError, "knots[1] is not finite: nan"),
        (lambda: end_derivatives(points, [0, 2, 1, 3, 4]), ValueError, "knots[1]=2.0 >= knots[2]=1.0"),
        (lambda: Contour(square, steps=[1, -1, 1, 1]), ValueError, "steps[1] = -1.0 must be > 0"),
        (lambda: sc.timmer_gc1(points, alpha=[1, -1, 1, 1]), ValueError, "alpha[1] must be > 0, got -1.0"),
        (lambda: sc.datasets.true_outline("star", spacing=f(5.0)), ValueError, "got 5.0"),
        (lambda: _check_size(i(50), 300), ValueError, "width must be a number of pixels between 80 and 4000, got 50"),
        (lambda: _handles_of_row([[f(np.nan), 1.0]], "handles_in"), ValueError, "handles_in[0] = [nan, 1.0]"),
        (lambda: to_glyph(sc.trace(mask, keep_snapshots=False), unicode=i(0x110000)), ValueError,
         "unicode=1114112 is U+110000"),
    ]


def test_messages_show_numpy_scalars_as_plain_numbers():
    """In numpy 2 the repr of a numpy scalar is ``np.float64(0.5)``: messages that put a value in with ``repr`` (or
    ``!r``) said "n must be an integer, got np.float64(2.5) (float64)", "knots[1] is not finite: np.float64(nan)",
    "steps[1] = np.float64(-1.0) must be > 0" (the last two for plain list input: the value came from the array). They
    show the plain number now (``_validation.plain``: numpy scalars, also in a tuple or list, as the Python values they
    hold); the type name, where a message gives it, still says it was numpy's."""
    for call, error, words in _numpy_scalar_cases():
        with pytest.raises(error) as caught:
            call()
        message = str(caught.value)
        assert words in message and "np." not in message, message


def test_plain_turns_numpy_scalars_into_python_values():
    assert v.plain(np.float64(0.5)) == 0.5 and type(v.plain(np.float64(0.5))) is float
    assert type(v.plain(np.int64(3))) is int and type(v.plain(np.bool_(True))) is bool
    assert type(v.plain(np.str_("a"))) is str
    assert v.plain((np.float64(1.5), [np.int64(2), "x"])) == (1.5, [2, "x"])
    assert repr(v.plain((np.float64(1.5), [np.int64(2)]))) == "(1.5, [2])"
    array = np.arange(3)
    assert v.plain(array) is array and v.plain("text") == "text" and v.plain(None) is None


def test_float32_scalars_show_the_number_they_were_given_as():
    """A float32 (a value read off a float32 image or array) was shown as the double it converts to:
    ``sc.trace(mask, epsilon=np.float32(1e-4))`` said "got 9.999999747378752e-05", ``np.float32(1.2)`` as a threshold
    "got 1.2000000476837158". Messages show the shortest decimal that reads back as that float32 (numpy's own
    ``str``), ``1e-04`` and ``1.2``, in the shared checks and in ``plain``."""
    import splinecraft as sc

    mask = np.zeros((8, 8), bool)
    mask[2:6, 2:6] = True
    cases = [
        (dict(epsilon=np.float32(1e-4)), "epsilon (px) must be >= 0.001, got 0.0001"),
        (dict(threshold=np.float32(1.2)), "threshold must be a fraction of white in [0, 1], got 1.2 "),
        (dict(noise_factor=np.float32(-0.3)), "noise_factor must be >= 0, got -0.3"),
        (dict(time_budget=np.float16(-0.1)), "time_budget must be > 0, got -0.1"),
        (dict(method="positional", tau=np.float32(60.1)), "must be >= 0 and < 50, got 60.1"),
    ]
    for options, words in cases:
        with pytest.raises(ValueError) as caught:
            sc.trace(mask, **options)
        assert words in str(caught.value), str(caught.value)
    assert v.plain(np.float32(0.1)) == 0.1 and type(v.plain(np.float32(0.1))) is float
    assert repr(v.plain([np.float32(0.7), np.float16(2.2)])) == "[0.7, 2.2]"


def test_the_plain_type_fast_paths_agree_with_the_general_checks():
    """``check_number``, ``check_int`` and ``check_choice`` take plain ``float``/``int``/``str`` values on a fast path
    (session 31): the same answers and errors as the numbers ABCs and the general choice rule give."""
    import numbers

    class Int(int):
        pass

    def outcome(call, *args, **kwargs):
        try:
            return "ok", call(*args, **kwargs)
        except (TypeError, ValueError) as exc:
            return type(exc).__name__, str(exc)

    values = [0, 1, -3, 2**1100, 0.5, -0.0, float("inf"), float("nan"), True, False, np.bool_(True), np.int64(7),
              np.float32(0.25), Int(4), "3", None, 1 + 2j]
    for value in values:
        is_real = isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))
        assert v._is_real(value) == is_real, value
        assert outcome(v.check_number, value, "x", minimum=0.0, inclusive=(True, False), maximum=5.0) == \
            outcome(v.check_number, value, "x", minimum=0.0, inclusive=(np.bool_(True), np.bool_(False)), maximum=5.0)
        result = outcome(v.check_int, value, "n", minimum=-5, maximum=10)
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
            assert result[0] == "TypeError", value
        else:
            assert result == (("ok", int(value)) if -5 <= int(value) <= 10 else result) and result[0] in ("ok", "ValueError")
    for value in ["outline", "pixels", "other", "", "True"]:
        got = outcome(v.check_choice, value, "contour", ("outline", "pixels"))
        assert got == (("ok", value) if value in ("outline", "pixels") else
                       ("ValueError", f"contour must be one of ['outline', 'pixels'], got {v._describe(value)}"))
    assert outcome(v.check_choice, "4", "connectivity", (4, 8, "minority"))[0] == "ValueError"
    assert outcome(v.check_choice, "minority", "connectivity", (4, 8, "minority")) == ("ok", "minority")


def test_masked_points_are_refused_unless_nothing_is_masked():
    data = np.ma.masked_array([[0.0, 0.0], [1.0, 2.0], [3.0, 1.0]], mask=[[0, 0], [0, 1], [0, 0]])
    with pytest.raises(ValueError, match="masked array with masked entries"):
        v.check_points(data)
    with pytest.raises(ValueError, match="masked"):
        sc.interpolate(data)
    unmasked = np.ma.masked_array(data.data, mask=False)
    np.testing.assert_array_equal(v.check_points(unmasked), data.data)
