"""Boundary noise of a bitmap, and the tolerance that fits the shape rather than the noise (docs/capture.md
§12, "Noisy boundaries").

A clean rendering of a shape (ink where the pixel centre is inside) has a crack outline that is a pixel
staircase: it strays from the smooth boundary of the lightly blurred bitmap by at most about 0.3 px away
from corners, at any size and rotation. A scanned, blurred and thresholded, or otherwise noisy bitmap has
ragged boundaries: bumps and notches a pixel or two wide that stray further. :func:`boundary_noise` measures
that as one number per image; :func:`noise_tolerance` turns it into the fit's tolerance.

Hairlines are not noise: a stroke (or a gap) at most 2 px wide has no smooth boundary of its own after the
blur (the blurred level of a 1.2 px stroke stays below one half), so its points are left out
(:func:`thin_feature_pixels`).
"""
from __future__ import annotations

import numpy as np

__all__ = ["NOISE_SIGMA", "NOISE_QUANTILE", "NOISE_FACTOR", "CLEAN_NOISE", "NOISE_SAMPLE", "THIN_AREA",
           "boundary_noise", "noise_tolerance", "thin_feature_pixels"]

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
#: Thin ink or paper (at most 2 px wide) in a connected piece of at least this many pixels is a hairline, a
#: short spur or serif, or a narrow gap: its contour points are not measured. The noise of a scan is still
#: measured, at its many bumps of 1-3 thin pixels and at its wider bumps: over 145 scan-like renders (blur
#: 0.5-2 px, noise 0.2-0.45) no estimate changes between 10 and 3, while a clean 24-px glyph's serif of 4-9
#: pixels read as 1-4 px of noise with 10 (docs/capture.md §12).
THIN_AREA = 4


def _thin_ink_and_paper(mask):
    """The ink pixels that a morphological opening of the ink by the 3 x 3 cross (4-neighbourhood) removes, and
    likewise the paper pixels for the paper (outside the image: paper). Returns both as bool images of the
    rows of ``mask`` and one more column of paper on either side (all False there).

    The paper's opening is the complement of the ink's closing (its erosion by the cross is the complement of
    the ink's dilation, and the image continued by paper beyond its border is the ink's continued by no ink):
    a paper pixel is thin where the closing of the ink covers it. Both are computed on the flat, row-major
    image with a column of paper on either side and a row above and below, where the four neighbours of a
    pixel are the shifts by 1 and by the padded width: contiguous runs of memory, some 2.5x faster than the
    strided 2-D slices of the image (the erosion and the dilation are set back to no ink in the side columns,
    the image's outside)."""
    rows, cols = mask.shape
    width = cols + 2
    size = (rows + 2) * width
    padded = np.zeros((rows + 2, width), bool)
    padded[1:-1, 1:-1] = mask
    ink = padded.reshape(-1)
    first, stop = width, size - width  # the image's rows (with their side columns), flat
    here, left, right = slice(first, stop), slice(first - 1, stop - 1), slice(first + 1, stop + 1)
    up, down = slice(first - width, stop - width), slice(first + width, stop + width)
    eroded, dilated = np.zeros(size, bool), np.zeros(size, bool)
    np.bitwise_and(ink[here], ink[left], out=eroded[here])
    np.bitwise_or(ink[here], ink[left], out=dilated[here])
    for shifted in (right, up, down):
        eroded[here] &= ink[shifted]
        dilated[here] |= ink[shifted]
    for values in (eroded, dilated):  # beyond the image: no ink
        values.reshape(rows + 2, width)[:, ::width - 1] = False
    opened = eroded[here] | eroded[left]
    closed = dilated[here] & dilated[left]
    for shifted in (right, up, down):
        opened |= eroded[shifted]
        closed &= dilated[shifted]
    thin_ink = np.greater(ink[here], opened, out=opened)  # (in the side columns: no ink)
    thin_paper = np.greater(closed, ink[here], out=closed)  # (the closing is no ink there: the dilation is)
    return thin_ink.reshape(rows, width), thin_paper.reshape(rows, width)


def thin_feature_pixels(mask, min_area=THIN_AREA):
    """Pixels of hairlines and narrow gaps: the ink pixels that a morphological opening of the ink by the
    3 x 3 cross removes (ink at most 2 px wide; outside the image is paper), and likewise the paper pixels
    for the paper (outside the image is paper too), kept where they form 8-connected pieces of at least
    ``min_area`` pixels (a bump or notch of noise is smaller)."""
    from ._iso_kernels import large_pieces

    mask = np.asarray(mask, dtype=bool)
    out = np.zeros(mask.shape, bool)
    # few pixels: their pieces are found among them alone (union-find, linear in their number), not by labelling
    # an image of the mask's size
    for thin in _thin_ink_and_paper(mask):
        if np.count_nonzero(thin) < min_area:  # no piece can be large enough
            continue
        flat = np.flatnonzero(thin)
        row, col = np.divmod(flat[large_pieces(flat, thin.shape[1], min_area)], thin.shape[1])
        out[row, col - 1] = True  # (thin has a column of paper on either side)
    return out


def _on_thin_features(points, thin):
    """Whether either pixel beside each crack midpoint (pixel corners on integer coordinates: a midpoint on a
    horizontal crack has an integer ``y``) is in ``thin``; a point that is not a crack midpoint looks at the
    pixels beside it across the nearer axis."""
    x, y = points[:, 0], points[:, 1]
    horizontal = np.abs(y - np.round(y)) < 1e-9
    rows = np.floor(np.column_stack([y - 0.5 * horizontal, y + 0.5 * horizontal])).astype(np.int64)
    cols = np.floor(np.column_stack([x - 0.5 * ~horizontal, x + 0.5 * ~horizontal])).astype(np.int64)
    inside = (rows >= 0) & (rows < thin.shape[0]) & (cols >= 0) & (cols < thin.shape[1])
    hit = np.zeros(rows.shape, bool)
    hit[inside] = thin[rows[inside], cols[inside]]
    return hit.any(axis=1)


def boundary_noise(mask, contours, corner_lists) -> float:
    """Noise amplitude (px) of the boundaries of a bitmap: the ``NOISE_QUANTILE``-th percentile of the
    distance from the crack-outline points to the 0.5 iso-line of the ink mask smoothed by a Gaussian of
    ``NOISE_SIGMA`` px (exact point-to-segment distances to its marching-squares segments,
    :mod:`._iso_kernels`), over the contours of at least 64 points, without the points within 5 steps of a
    corner and the points beside hairlines and narrow gaps (:func:`thin_feature_pixels`: at most 2 px wide, in
    pieces of at least ``THIN_AREA`` = 4 pixels, where the blurred bitmap has no boundary of its own: a clean
    ring 1.2 px wide measured 28 px without this rule, a 6-px spur on a clean render 4.5 px), at most ``NOISE_SAMPLE`` = 20 000 of them, evenly
    spread. About 0.27 px for clean renderings (0.23-0.36 over glyphs of three fonts at 48-1200 px, upright and
    rotated, one outlier of 0.62 at 48 px), 0.55-1.1 px for scan-like ones (blur 1-2 px); 0 when no contour
    qualifies."""
    from ._iso_kernels import iso_line_distance

    chosen = [(np.asarray(contours[k], float), np.asarray(corner_lists[k], dtype=np.int64))
              for k in np.flatnonzero(np.fromiter(map(len, contours), np.int64, len(contours)) >= _MIN_POINTS)]
    if not chosen:
        return 0.0
    thin = thin_feature_pixels(mask)
    # one pass over all chosen contours: each point's position within its own contour, and a corner's span
    # marked by its contour's offset (modulo that contour's length)
    sizes = np.fromiter((points.shape[0] for points, _ in chosen), np.int64, len(chosen))
    offsets = np.cumsum(sizes) - sizes
    points = np.concatenate([points for points, _ in chosen])
    keep = np.ones(points.shape[0], bool)
    corner_counts = np.fromiter((corners.size for _, corners in chosen), np.int64, len(chosen))
    if corner_counts.any():
        corners = np.concatenate([corners for _, corners in chosen])
        owner = np.repeat(np.arange(len(chosen)), corner_counts)
        span = corners[:, None] + np.arange(-_CORNER_SPAN, _CORNER_SPAN + 1)[None, :]
        keep[offsets[owner, None] + span % sizes[owner, None]] = False
    if thin.any():  # else no point is beside one (clean renders mostly have none)
        keep &= ~_on_thin_features(points, thin)
    kept = points.compress(keep, axis=0)  # (numpy 2.4's boolean row indexing is some 4x slower)
    if not kept.shape[0]:
        return 0.0
    if kept.shape[0] > NOISE_SAMPLE:  # a percentile needs no more; keeps noise images linear in their size
        kept = kept[np.linspace(0, kept.shape[0] - 1, NOISE_SAMPLE).astype(np.int64)]
    # the smoothed bitmap is padded by 4 px (the Gaussian's radius): its iso-line closes around ink that
    # touches the border
    distances = iso_line_distance(kept, mask, NOISE_SIGMA, 4)
    if distances is None:  # the smoothed bitmap never reaches the level (hairlines only)
        return 0.0
    return _percentile(distances, NOISE_QUANTILE)


def _percentile(values, percent):
    """``float(np.percentile(values, percent))`` of a 1-D float array (numpy's default method, ``"linear"``: the
    two order statistics around the virtual index ``(n - 1) q`` interpolated as ``numpy.lib``'s ``_lerp`` does),
    bit for bit, from one ``partition`` of ``values`` in place (its order is lost) at those two and the last
    (a NaN sorts last, and then is the result): 3 us where ``np.percentile`` took 22 on 3000 values."""
    last = values.shape[0] - 1
    virtual = last * (percent / 100)
    if virtual >= last:  # numpy's index -1 for both, and its gamma measured from there
        below, above, gamma = last, last, virtual + 1
    elif virtual < 0:
        below, above, gamma = 0, 0, virtual
    else:
        below = int(np.floor(virtual))
        above, gamma = below + 1, virtual - below
    values.partition(sorted({below, above, last}))
    if np.isnan(values[last]):
        return float(values[last])
    low, high = float(values[below]), float(values[above])
    difference = high - low
    return high - difference * (1 - gamma) if gamma >= 0.5 else low + difference * gamma


def noise_tolerance(epsilon, noise, factor=NOISE_FACTOR):
    """The tolerance of the fit: ``epsilon`` while ``noise <= CLEAN_NOISE`` (a clean staircase, whatever
    ``epsilon`` is asked for), else ``max(epsilon, factor * noise)``: on a ragged boundary the fit no longer
    follows the bumps."""
    if float(noise) <= CLEAN_NOISE:
        return float(epsilon)
    return max(float(epsilon), float(factor) * float(noise))
