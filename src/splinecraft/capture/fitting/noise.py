"""Boundary noise of a bitmap, and the tolerance that fits the shape rather than the noise (docs/capture.md
§12, "Noisy boundaries").

A clean rendering of a shape (ink where the pixel centre is inside) has a crack outline that is a pixel
staircase: it strays from the smooth boundary of the lightly blurred bitmap by at most about 0.3 px away
from corners, at any size and rotation. A scanned, blurred and thresholded, or otherwise noisy bitmap has
ragged boundaries: bumps and notches a pixel or two wide that stray further. :func:`boundary_noise` measures
that as one number per image; :func:`noise_tolerance` turns it into the fit's tolerance.
"""
from __future__ import annotations

import numpy as np

__all__ = ["NOISE_SIGMA", "NOISE_QUANTILE", "NOISE_FACTOR", "CLEAN_NOISE", "NOISE_SAMPLE",
           "boundary_noise", "noise_tolerance"]

#: Standard deviation (px) of the Gaussian that smooths the bitmap for the reference boundary.
NOISE_SIGMA = 1.0
#: Quantile (%) of the distances taken as the noise amplitude.
NOISE_QUANTILE = 99.5
#: The tolerance covers this many noise amplitudes (``trace(noise_factor=)``; 0 turns the rule off).
NOISE_FACTOR = 2.0
#: Noise estimates up to this (px) are the pixel staircase of a clean rendering, not noise.
CLEAN_NOISE = 0.4
#: Contour points this many steps on either side of a corner are left out (the blur rounds corners off).
_CORNER_SPAN = 5
#: Boundaries with fewer contour points are left out (specks say little about the edge of a shape).
_MIN_POINTS = 64
#: At most this many contour points (evenly spread over all qualifying ones) are measured.
NOISE_SAMPLE = 20000


def boundary_noise(mask, contours, corner_lists) -> float:
    """Noise amplitude (px) of the boundaries of a bitmap: the ``NOISE_QUANTILE``-th percentile of the
    distance from the crack-outline points to the 0.5 iso-line of the ink mask smoothed by a Gaussian of
    ``NOISE_SIGMA`` px (exact point-to-segment distances to its marching-squares segments,
    :mod:`._iso_kernels`), over the contours of at least 64 points, without the points within 5 steps of a
    corner (at most ``NOISE_SAMPLE`` = 20 000 of them, evenly spread). About 0.27 px for clean renderings
    (0.23-0.36 over glyphs of three fonts at 48-1200 px, upright
    and rotated, one outlier of 0.62 at 48 px), 0.55-1.1 px for scan-like ones (blur 1-2 px); 0 when no
    contour qualifies."""
    from ._iso_kernels import iso_line_distance

    chosen = [(np.asarray(contours[k], float), np.asarray(corner_lists[k], dtype=np.int64))
              for k in np.flatnonzero(np.fromiter(map(len, contours), np.int64, len(contours)) >= _MIN_POINTS)]
    if not chosen:
        return 0.0
    kept = []
    for points, corners in chosen:
        keep = np.ones(points.shape[0], bool)
        if corners.size:
            keep[(corners[:, None] + np.arange(-_CORNER_SPAN, _CORNER_SPAN + 1)[None, :]) % points.shape[0]] = False
        kept.append(points[keep])
    kept = np.concatenate(kept)
    if not kept.shape[0]:
        return 0.0
    if kept.shape[0] > NOISE_SAMPLE:  # a percentile needs no more; keeps noise images linear in their size
        kept = kept[np.linspace(0, kept.shape[0] - 1, NOISE_SAMPLE).astype(np.int64)]
    # the smoothed bitmap is padded by 4 px (the Gaussian's radius): its iso-line closes around ink that
    # touches the border
    distances = iso_line_distance(kept, mask, NOISE_SIGMA, 4)
    if distances is None:  # the smoothed bitmap never reaches the level (hairlines only)
        return 0.0
    return float(np.percentile(distances, NOISE_QUANTILE))


def noise_tolerance(epsilon, noise, factor=NOISE_FACTOR):
    """The tolerance of the fit: ``epsilon`` while ``noise <= CLEAN_NOISE`` (a clean staircase, whatever
    ``epsilon`` is asked for), else ``max(epsilon, factor * noise)``: on a ragged boundary the fit no longer
    follows the bumps."""
    if float(noise) <= CLEAN_NOISE:
        return float(epsilon)
    return max(float(epsilon), float(factor) * float(noise))
