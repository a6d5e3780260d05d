"""The lsq fit's result spline (``fitting.lsq.outline_spline``) is the one the checked constructor builds from the
same pieces, bit for bit: joins snapped the same way, the same knots, auxiliary points and info."""
from __future__ import annotations

import numpy as np

import splinecraft as sc
from splinecraft.capture.fitting.lsq import outline_spline
from splinecraft.spline import Spline


def _same(a, b):
    assert np.array_equal(a.bezier() if callable(a.bezier) else a.bezier, b.bezier() if callable(b.bezier) else b.bezier)
    assert a._planar.tobytes() == b._planar.tobytes()
    assert a._knots.tobytes() == b._knots.tobytes()
    assert a.closed == b.closed and a._info == b._info
    assert a._auxiliary.keys() == b._auxiliary.keys()
    for key in a._auxiliary:
        assert a._auxiliary[key].tobytes() == b._auxiliary[key].tobytes()
        assert not a._auxiliary[key].flags.writeable
    assert not a._planar.flags.writeable and not a._knots.flags.writeable


def test_outline_spline_is_the_checked_constructor():
    rng = np.random.default_rng(3)
    for m in (1, 2, 7):
        bezier = rng.normal(size=(m, 4, 2)) * 50.0
        bezier[1:, 0] = bezier[:-1, 3] * (1.0 + 1e-13)  # joins that agree to rounding only
        bezier[-1, 3] = bezier[0, 0] * (1.0 - 1e-13)
        knots = np.cumsum(rng.random(m + 1) + 0.1)
        info = {"form": "outline_fit", "method": "lsq", "epsilon": 0.8, "pieces": m}
        kept = bezier.copy()
        made = outline_spline(bezier, knots, dict(info))
        _same(made, Spline(bezier, knots, closed=True, auxiliary={"F": bezier[:, 0]}, info=dict(info)))
        assert np.array_equal(bezier, kept)  # the caller's pieces are left as they were


def test_a_traced_outline_has_the_checked_spline():
    mask = np.zeros((40, 40), bool)
    mask[8:30, 6:33] = True
    mask[14:22, 14:24] = False
    result = sc.trace(mask)
    for spline, fit in zip(result.splines, result.fits):
        bezier = fit.spline.bezier() if callable(fit.spline.bezier) else fit.spline.bezier
        checked = Spline(bezier, fit.spline.knots, closed=True, auxiliary=dict(fit.spline._auxiliary),
                         info=dict(fit.spline._info))
        _same(fit.spline, checked)
