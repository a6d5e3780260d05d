"""The strict JSON reader of Spline (Spline.from_dict) and the sampling bounds."""
import copy
import json
import math

import numpy as np
import pytest

import splinecraft as sc
from splinecraft.spline.piecewise import Spline

HEART = np.array([[0.0, 0.6], [0.5, 1.0], [1.0, 0.6], [0.0, -1.0], [-1.0, 0.6], [-0.5, 1.0]])
WAVE = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 3.0], [4.0, 1.0], [6.0, 2.0], [7.0, 0.0]])


def test_sample_with_a_tiny_tolerance_is_bounded():
    curve = sc.basis_spline(WAVE * 1e300)
    with pytest.warns(RuntimeWarning, match="max_points"):
        params, points = curve.sample(tolerance=1e-300, max_points=1000)
    assert len(points) <= 1000 and np.isfinite(points).all()


def test_timmer_gc1_with_a_tiny_alpha():
    """alpha = 1e-308 makes handles of length 4/(3 alpha): either a finite curve or a plain error."""
    try:
        curve = sc.timmer_gc1(WAVE, alpha=1e-308)
    except ValueError as exc:
        assert "alpha" in str(exc)
    else:
        with pytest.warns(RuntimeWarning, match="coarser sampling"):  # 4 million points would be needed
            params, points = curve.sample()
        assert np.isfinite(points).all()
    curve = sc.timmer_gc1(WAVE, alpha=1e-300)
    with pytest.warns(RuntimeWarning, match="coarser sampling"):
        assert np.isfinite(curve.sample()[1]).all()


# ---------------------------------------------------------------------------------------------- from_dict
def spline_dict():
    return sc.interpolate(WAVE).to_dict()


@pytest.mark.parametrize("change, error, text", [
    (lambda d: d.update(closed="false"), TypeError, "from_dict: closed must be a bool"),
    (lambda d: d.update(closed=1), TypeError, "from_dict: closed must be a bool"),
    (lambda d: d["auxiliary_shapes"].update(F=[-6, 2]), ValueError, r"auxiliary_shapes\['F'\]\[0\] must be >= 0"),
    (lambda d: d["auxiliary_shapes"].update(F=[3, 2]), ValueError, r"auxiliary_shapes\['F'\] = \[3, 2\] does not fit"),
    (lambda d: d["auxiliary_shapes"].update(F="6,2"), TypeError, r"auxiliary_shapes\['F'\] must be a list"),
    (lambda d: d["auxiliary_shapes"].update(G=[1]), ValueError, r"auxiliary_shapes\['G'\] has no array"),
    (lambda d: d.update(bezier="abc"), TypeError, "bezier must be"),
    (lambda d: d.update(bezier=[[["0", 0]]]), TypeError, "bezier must hold numbers only"),
    (lambda d: d.update(bezier=None), TypeError, "bezier must hold numbers"),
    (lambda d: d.update(bezier=[[[0, 0], [1, 1]]]), ValueError, r"bezier must have shape \(m, 4, d\)"),
    (lambda d: d["bezier"][0][1].__setitem__(0, math.nan), ValueError, "bezier holds a non-finite value"),
    (lambda d: d.update(knots={"a": 1}), TypeError, "knots must be"),
    (lambda d: d.update(knots=d["knots"][::-1]), ValueError, "knots must be strictly increasing"),
    (lambda d: d.update(knots=[[0.0]] * 6), ValueError, "knots has 2 dimensions"),
    (lambda d: d.update(auxiliary=[1, 2]), TypeError, "from_dict: auxiliary must be a dict"),
    (lambda d: d["auxiliary"].update(F=[[math.inf, 0]]), ValueError, r"auxiliary\['F'\] holds a non-finite"),
    (lambda d: d.update(info="x"), TypeError, "from_dict: info must be a dict"),
    (lambda d: d.update(info={"x": object()}), TypeError, r"info\['x'\] must be JSON-able"),
    (lambda d: d.update(version="1"), ValueError, "version must be 1"),
    (lambda d: d.update(version=True), ValueError, "version must be 1"),
    (lambda d: d.update(type="other"), ValueError, "not a splinecraft.Spline dict"),
    (lambda d: d.update(extra=1), ValueError, "unknown key 'extra'"),
    (lambda d: d.pop("knots"), ValueError, "missing key 'knots'"),
])
def test_from_dict_strict_schema(change, error, text):
    data = spline_dict()
    change(data)
    with pytest.raises(error, match=text):
        Spline.from_dict(data)


def test_from_dict_depth_and_cycles():
    data = spline_dict()
    deep = 1.0
    for _ in range(10_000):
        deep = [deep]
    data["info"] = {"x": deep}
    with pytest.raises(ValueError, match="nested too deeply"):
        Spline.from_dict(data)
    data = spline_dict()
    data["bezier"] = deep
    with pytest.raises(ValueError, match="bezier"):
        Spline.from_dict(data)
    loop = []
    loop.append(loop)
    data = spline_dict()
    data["auxiliary"]["F"] = loop
    with pytest.raises(ValueError, match=r"auxiliary\['F'\]"):
        Spline.from_dict(data)


def test_from_dict_round_trip_still_exact():
    for curve in (sc.interpolate(WAVE), sc.basis_spline(HEART, closed=True), sc.timmer_g2(HEART, closed=True),
                  sc.generic_segment([0, 0], [1, 1], [2, 1], [3, 0])):
        again = Spline.from_dict(json.loads(json.dumps(curve.to_dict())))
        np.testing.assert_array_equal(again.bezier(), curve.bezier())
        assert again.info == curve.info and again.closed == curve.closed
        for key, value in curve.auxiliary.items():
            np.testing.assert_array_equal(again.auxiliary[key], value)
    data = sc.interpolate(WAVE).to_dict()
    data["auxiliary"]["empty"] = []
    data["auxiliary_shapes"]["empty"] = [0, 2]
    assert Spline.from_dict(copy.deepcopy(data)).auxiliary["empty"].shape == (0, 2)
