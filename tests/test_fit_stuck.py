"""The regression spline ("lsq") must not get stuck with a loop on a smooth curve, and the deviation it reports for
a fit that did not converge must be the curve's real distance from the contour (docs/capture.md §12, "The lsq
method").

The two outlines in tests/data/lsq_stuck_outlines.npz are crack outlines (coordinates times two, as int16) with the
corners the trace found on them:

* ``glyph``: the outer boundary of EB Garamond 08 Italic 'ǎ' (U+01CE), a clean 776 px render turned by 129.6
  degrees, 3028 points, two corners (so the longest piece, ~2400 steps, is beyond the small-outline fallback);
* ``scan``: a boundary of a blurred, noisy scan of Amiri Quran '3' at 856 px turned by 195.6 degrees, 4424
  points, six corners, fitted at the trace's noise-scaled tolerance.

On both the Hoschek steps projected contour points onto a curve that missed the contour there; their
parameters bunched up and left knot intervals with few data points or none beside them, where the
least-squares spline looped (a 3.6 px spike into the ink on the glyph, 4.6 px on the scan) and the knots around
it were too close to take another one. The fit stopped with ``converged=False`` and reported 11.95 px and
7.3 px, several times the loop's real distance from the contour.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from splinecraft.capture.fitting import fit_outline
from splinecraft.capture.fitting.geometry import piece_deviation
from splinecraft.capture.fitting.lsq_model import OutlineRegression

DATA = Path(__file__).resolve().parent / "data" / "lsq_stuck_outlines.npz"


def _case(name):
    data = np.load(DATA)
    epsilon = float(data["scan_epsilon"]) if name == "scan" else 0.8
    return data[f"{name}_points2"].astype(float) / 2.0, data[f"{name}_corners"], epsilon


def _deviation(fit, points):
    """The two-sided closest-point distance of the whole fitted curve and the closed contour, measured without
    the fit's parameterization."""
    return piece_deviation(fit.spline.bezier(), np.vstack([points, points[:1]]), spacing=0.1)


@pytest.mark.parametrize("name", ["glyph", "scan"])
def test_lsq_converges_where_projected_parameters_had_emptied_knot_intervals(name):
    points, corners, epsilon = _case(name)
    fit = fit_outline(points, corners, epsilon=epsilon, fallback=False, keep_snapshots=False)
    assert fit.converged, fit.hausdorff
    tolerance = fit.info["tolerance_near_corners"]  # epsilon, plus the allowance in the corners' zones
    assert fit.hausdorff <= tolerance + 1e-9
    assert _deviation(fit, points) <= tolerance + 0.05  # the reported bound is tight to ~0.05 px


@pytest.mark.parametrize("name", ["glyph", "scan"])
def test_lsq_fit_that_does_not_converge_reports_its_real_deviation(name, monkeypatch):
    """Without the parameter reset the fit stays stuck with its loop: then ``hausdorff`` must be the loop's
    distance from the contour, not the windowed bound of a parameterization that went wrong (before: 11.95 px for
    3.57, and 7.33 px for 4.61)."""
    points, corners, epsilon = _case(name)
    monkeypatch.setattr(OutlineRegression, "reset_parameters", lambda self, dev, stuck, reach=2: [], raising=False)
    fit = fit_outline(points, corners, epsilon=epsilon, fallback=False)
    assert not fit.converged
    real = _deviation(fit, points)
    assert real > 2.0  # the loop is there
    assert real - 0.05 <= fit.hausdorff <= real + 0.05
    assert fit.snapshots[-1].piece_hausdorff.max() == pytest.approx(fit.hausdorff)
