"""Gray image -> ink mask: thresholds, the noise estimate and speck removal (docs/capture.md, §9).

Used by :func:`splinecraft.capture.image.load_bitmap`; every gray value here is on the image's own scale
(``0`` = black .. ``white``), thresholds and noise levels are reported as fractions of white.

Thresholds (``threshold=``)
---------------------------
* ``"background"`` (the default) -- the midpoint between paper and ink under the local lighting. A scan is
  modelled as ``gray = lighting(x) * reflectance``: the paper's brightness ``B(x)`` is estimated from the
  pixels a first pass (``"sauvola"``, on block means for images over ``ROUGH_PIXELS``) calls paper that lie at least ``BACKGROUND_MARGIN`` px from any ink
  (a blurred edge belongs to neither class), as their Gaussian-weighted mean (normalized convolution with
  ``sigma`` = half the window, on blocks of about ``sigma / 4`` px, bilinear back to the pixels), carried into
  areas far from any paper by the nearest estimate; the ink's reflectance ratio ``rho = median(gray / B)`` over
  the ink pixels of the first pass at least ``BACKGROUND_MARGIN`` px from paper (one number: ink reflects a
  fixed share of what the paper does, clipped to ``[0, 1 - MIN_CONTRAST]``); the level is
  ``B (1 + rho) / 2``. The masks are re-estimated from the new level, at most ``BACKGROUND_ROUNDS`` times
  (until a round changes fewer than ``BACKGROUND_SETTLED`` of the pixels). The midpoint is where a blurred edge crosses its true position, so the
  outline neither grows nor shrinks with the blur; under even lighting it is the fixed midpoint of the two
  gray levels (a bilevel image gives ``(lo + hi) / 2`` exactly), and unlike a window statistic it does not
  depend on how much ink a window holds, so strokes wider than the window get no holes and paper far from
  ink no specks. Background-surface estimation from a Sauvola pre-binarization follows Gatos, Pratikakis and
  Perantonis, "Adaptive degraded document image binarization", Pattern Recognition 39 (2006). Strokes
  fainter than half the ink's contrast (pencil on ``skimage.data.text()``) fall on the paper side: use
  ``"sauvola"`` to keep them.
* ``"otsu"`` -- one global level, Otsu's method (:func:`skimage.filters.threshold_otsu`); images with less than
  ``MIN_CONTRAST`` of gray range use ``FALLBACK_THRESHOLD`` (a blank page stays blank).
* ``"sauvola"`` -- a level per pixel from the mean ``m`` and standard deviation ``s`` of a window around it,
  ``m (1 + k (s / R - 1))`` with ``k = 0.2`` and ``R`` half the gray range
  (:func:`skimage.filters.threshold_sauvola`): follows uneven lighting; made for text and line art.
* ``"local"`` -- a level per pixel, the Gaussian-weighted window mean less three times the noise estimate
  (:func:`skimage.filters.threshold_local`, ``method="gaussian"``; without the offset half the paper pixels
  of a window of plain paper would fall below its mean).
* ``"alpha"`` -- the opacity instead of the gray: a pixel at least half opaque is ink (a logo or a cut-out
  on a transparent background, whatever its colours: a white logo made for dark pages included). The image
  must have an alpha channel (RGBA, LA, a palette or gray with a transparent colour, a 2- or 4-channel array).
* a number in ``[0, 1]`` -- a fixed fraction of white.

The window of the local methods is ``window_size(shape)`` pixels: an odd number, 1/8 of the smaller image
side, at least 15 and at most 255. Where a window's standard deviation is below ``MIN_CONTRAST / 2`` and
below twice the noise estimate (blank paper, or the inside of a stroke wider than the window: nothing but
noise) a local level means nothing (half the pixels of a uniform area lie below its own mean): such a pixel
takes the level of the nearest pixel whose window does see an edge (the threshold surface is carried into the
flat areas from the edges). A connected flat area has no edge inside, so it is all paper or all ink: the
pixels of its rim (beside it, on its side of the edges) decide which by majority, and a flat pixel that the
carried level would put in the other class gets that level mirrored about its own gray. So blank paper stays
paper however far the light falls off from where the text is, and a wide stroke stays ink; an image without
any edge uses Otsu's level. The local methods hold a few float arrays of the image's size (about 40 bytes per pixel). ``DEFAULT_THRESHOLD``
is the method ``threshold=None`` stands for; BENCHMARKS.md ("Thresholds") gives the measurement it was chosen
by.

Noise estimate and specks
-------------------------
:func:`estimate_noise`: the standard deviation of the per-pixel noise, from the median absolute value of
the finest diagonal Haar detail (Donoho's MAD estimator, ``sigma = median |d| / 0.6745`` with
``d = (a - b - c + d) / 2`` over 2 x 2 blocks): edges and smooth shading hardly move the median.

:func:`auto_speck_area` (``min_speck_area=None``): with that noise ``sigma``, a paper pixel whose gray lies a
margin ``g`` above the threshold turns into ink with probability ``p = Phi(-g / sigma)`` (``g``: the median
margin of the paper pixels; ink pixels likewise, which opens holes). Independent flips make components of
``k`` pixels at a rate of about ``(8 p)^k`` per pixel (an 8-connected component of ``k`` pixels has fewer than
``8^k`` shapes around a given pixel), so in an image of ``N`` pixels specks of ``k`` or more pixels are
expected less than once when ``N (8 p)^k < 1``. The speck area is the smallest such ``k`` (0 when ``8 p``
is negligible, i.e. a clean image keeps every pixel; at most ``MAX_AUTO_SPECK``). Bool masks carry no gray
level: their default speck area is 0, and so is that of an image of two gray levels (a 1-bit file, a mask
saved as 0/255; ``capture.image``), whose Haar details are its pattern's edges, not noise (on a checkerboard
every window straddles one).

:func:`remove_specks` removes ink components and fills holes with fewer than ``area`` pixels; a background
component touching the image border is never a hole (a speck area larger than the background does not
fill it).

Pinholes
--------
:func:`fill_pinholes` (``sc.trace`` with ``min_speck_area=None``, every input): holes of fewer than
``PINHOLE_AREA`` (3) pixels, as the boundary tracer sees them (its connectivity rule decides what is a hole),
are filled. In a render by the pixel-centre rule such a hole is the trace of a slit or notch narrower than a
pixel, not a hole of the shape: a true hole of at most 2 px lies within the fit's tolerance (epsilon + 1/2 px)
of its filling, while tracing it adds an outline that is not there (potrace's ``turdsize`` default of 2 drops
the same areas). ``min_speck_area=0`` keeps them.

:func:`drop_specks` does the same for ink: outer boundaries of fewer than ``PINHOLE_AREA`` pixels turn into
paper, after the pinholes, while a larger outline is left (a bitmap of nothing but specks keeps them). A 1-bit
bitmap gets no automatic speck area (it has no gray level), and in a render by the pixel-centre rule such a
component is a fragment of a hairline or of a cut-off tip, not an outline of the shape.
"""
from __future__ import annotations

import inspect
import math
import numbers

import numpy as np

from .. import _validation
from .._validation import check_choice

__all__ = ["THRESHOLD_METHODS", "DEFAULT_THRESHOLD", "BACKGROUND_MARGIN", "BACKGROUND_ROUNDS", "MIN_CONTRAST", "FALLBACK_THRESHOLD", "MAX_AUTO_SPECK",
           "check_threshold", "window_size", "threshold_level", "estimate_noise", "auto_speck_area",
           "remove_specks", "PINHOLE_AREA", "fill_pinholes", "drop_specks"]

#: Reach (px) of the ring of ink around a hole whose gray a hole is compared with (:func:`_fill_holes_without_edges`).
HOLE_RING = 3
#: Holes of fewer than this many pixels are pinholes (module docstring, "Pinholes").
PINHOLE_AREA = 3

#: Names accepted by ``threshold=``.
THRESHOLD_METHODS = ("background", "otsu", "sauvola", "local", "alpha")
#: The method ``threshold=None`` uses (chosen by the measurement in BENCHMARKS.md, "Thresholds").
DEFAULT_THRESHOLD = "background"
#: ``"background"``: pixels within this distance (px) of the other class are left out of either estimate.
BACKGROUND_MARGIN = 2
#: ``"background"``: the first (Sauvola) pass runs on block means of images larger than this (pixels).
ROUGH_PIXELS = 1 << 21
#: ``"background"``: at most this many re-estimates of the masks ...
BACKGROUND_ROUNDS = 4
#: ... which stop once a round changes fewer than this share of the pixels (the noise at the edges).
BACKGROUND_SETTLED = 0.002
#: Below this gray range (fraction of white) an image is treated as uniform: Otsu is not used.
MIN_CONTRAST = 0.1
#: Threshold used for (near-)uniform images, as a fraction of white.
FALLBACK_THRESHOLD = 0.5
#: Largest speck area the noise estimate may choose (pixels).
MAX_AUTO_SPECK = 64
_BLOCK_ROWS = 512


def check_threshold(threshold):
    """``None``, a method name of :data:`THRESHOLD_METHODS` or a fraction of white in ``[0, 1]``."""
    if threshold is None:
        return None
    if isinstance(threshold, str):
        try:
            float(threshold)
        except ValueError:
            return check_choice(threshold, "threshold", THRESHOLD_METHODS)
        raise TypeError(f"threshold must be a number in [0, 1], not the string {threshold!r}, or one of "
                        f"{list(THRESHOLD_METHODS)}")
    if isinstance(threshold, (bool, np.bool_)) or not isinstance(threshold, numbers.Real):
        raise TypeError(f"threshold must be one of {list(THRESHOLD_METHODS)}, a number in [0, 1] or None, "
                        f"got {type(threshold).__name__}")
    value = float(threshold)
    if not math.isfinite(value) or not 0.0 <= value <= 1.0:
        raise ValueError(f"threshold must be a fraction of white in [0, 1], got {_validation.plain(threshold)!r} "
                         f"(for an 8-bit gray level g pass g / 255)")
    return value


def window_size(shape):
    """Window (odd, pixels) of the local thresholds: 1/8 of the smaller side, clipped to [15, 255]."""
    side = int(min(max(15, min(shape) // 8), 255))
    return side if side % 2 else side + 1


def threshold_level(gray, white, threshold):
    """The gray level(s) ``ink = gray <= level`` uses: a scalar, or an array the shape of ``gray`` for the
    local methods (see the module docstring). ``threshold`` is already checked."""
    method = DEFAULT_THRESHOLD if threshold is None else threshold
    if not isinstance(method, str):
        return method * white
    if method == "alpha":  # the gray is the transparency (image.py): at least half opaque is ink
        return FALLBACK_THRESHOLD * white
    lo, hi = float(gray.min()), float(gray.max())
    if hi - lo < MIN_CONTRAST * white:
        return FALLBACK_THRESHOLD * white
    if method == "otsu":
        return _otsu_level(gray, int(lo), int(hi)) if gray.dtype.kind == "u" else _otsu_level(gray)
    if method == "background":
        if not np.any((gray > lo) & (gray < hi)):      # two gray levels: paper hi, ink ratio lo / hi
            return (lo + hi) / 2.0
        return _background_level(gray, white)
    return _window_level(gray, white, method)


def _window_level(gray, white, method):
    """The per-pixel level of ``"sauvola"`` / ``"local"`` (module docstring), on the gray scale."""
    from scipy import ndimage
    from skimage.filters import threshold_local, threshold_sauvola

    lo, hi = float(gray.min()), float(gray.max())
    scaled = gray.astype(np.float32) / np.float32(white)
    window = window_size(gray.shape)
    if method == "sauvola":
        level = threshold_sauvola(scaled, window_size=window)
    else:
        offset = 3.0 * estimate_noise(gray, white)
        level = threshold_local(scaled, block_size=window, method="gaussian", offset=offset)
    mean = ndimage.uniform_filter(scaled, window)
    spread = np.sqrt(np.maximum(ndimage.uniform_filter(scaled * scaled, window) - mean * mean, 0.0))
    flat = spread < max(MIN_CONTRAST / 2, 2.0 * estimate_noise(gray, white))
    if flat.all():
        return _otsu_level(gray, int(lo), int(hi)) if gray.dtype.kind == "u" else _otsu_level(gray)
    if flat.any():                          # windows of nothing but noise: their flat area's class
        level = _flat_area_level(scaled, level, flat)
    return level * white


def _flat_area_level(scaled, level, flat):
    """The level of the flat pixels (module docstring, "flat areas"): a connected flat area has no edge inside,
    so it is all paper or all ink; the pixels of its rim (the pixels beside it whose window sees an edge, on
    the area's side of that edge) vote with their own levels. A flat pixel starts from the level of the
    nearest rim pixel (the threshold surface carried in from the edges) and, where that puts it in the other
    class than its area's vote, takes that level mirrored about its own gray (same margin, the area's side):
    a dim stretch of blank paper far from the text whose light it was measured in stays paper."""
    from scipy import ndimage

    labels, count = ndimage.label(flat)     # 4-connected flat areas
    rim = ndimage.binary_dilation(flat) & ~flat
    owner = ndimage.grey_dilation(labels, footprint=ndimage.generate_binary_structure(2, 1))[rim]
    rim_ink = (scaled[rim] <= level[rim]).astype(np.float64)
    votes = np.bincount(owner, minlength=count + 1).astype(np.float64)
    ink_area = np.bincount(owner, weights=rim_ink, minlength=count + 1) * 2.0 > votes
    nearest = ndimage.distance_transform_edt(flat, return_distances=False, return_indices=True)
    carried = level[nearest[0], nearest[1]]
    area_ink = ink_area[labels]
    wrong = flat & ((scaled <= carried) != area_ink)
    carried[wrong] = 2.0 * scaled[wrong] - carried[wrong]
    return carried


def _background_level(gray, white):
    """The level of ``"background"`` (module docstring): ``B (1 + rho) / 2`` on the gray scale."""
    scaled = gray.astype(np.float32) / np.float32(white)
    ink = _rough_ink(scaled)
    sigma = window_size(gray.shape) / 2.0
    reach = 2 * BACKGROUND_MARGIN + 1               # erosion by a square: a pixel with no other class within
    level = None
    for _ in range(BACKGROUND_ROUNDS):
        paper_core = ~_box_max(ink, reach)
        ink_core = ~_box_max(~ink, reach)
        paper_core = paper_core if paper_core.any() else ~ink
        ink_core = ink_core if ink_core.any() else ink
        if not paper_core.any() or not ink_core.any():
            break
        del level                                  # the last round's level: memory for this round's
        paper = _smooth_surface(scaled, paper_core, sigma)
        np.maximum(paper, np.float32(MIN_CONTRAST / 100), out=paper)
        del paper_core
        ratio = scaled[ink_core] / paper[ink_core]
        del ink_core
        rho = min(max(float(np.median(ratio[::max(1, ratio.size // 1_000_000)])), 0.0), 1.0 - MIN_CONTRAST)
        level = paper                              # in place: the paper surface is not needed again
        level *= np.float32((1.0 + rho) / 2.0)
        del paper
        new_ink = scaled <= level
        changed = np.count_nonzero(new_ink != ink)
        ink = new_ink
        if changed <= BACKGROUND_SETTLED * ink.size:
            break
    if level is None:                              # one class only: nothing to take a midpoint of
        return _otsu_level(gray, int(gray.min()), int(gray.max())) if gray.dtype.kind == "u" else _otsu_level(gray)
    ink = new_ink = None
    _fill_holes_without_edges(scaled, level, rho)
    level *= np.float32(white)
    return level


def _fill_holes_without_edges(scaled, level, rho):
    """Make ink of the holes no edge bounds (in place on ``level``). A hole (paper enclosed by ink) is kept
    when its brightest gray (smoothed by a Gaussian of 1 px) ``h`` and the mean gray ``r`` of the ink within
    ``HOLE_RING`` px around it satisfy ``r <= h (1 + rho) / 2``: were the hole paper, its ink would lie below
    the midpoint. Inside a wide dark area whose ink drifts lighter (uneven toner, a gradient fill), or around
    a small counter in a wide dark area, the first pass can call ink paper, and the paper estimate taken
    there confirms it; the gray is continuous across such a boundary (``r`` close to ``h``), while a true
    counter, however small or blurred, is brighter than its ink by the ink's contrast. Such a stretch that
    reaches a true counter is one hole with it: so each kept hole's part below its own midpoint ``(h + d) /
    2`` (``d`` the darkest smoothed ink around it), piece by piece, takes the same test with the piece's mean
    gray for ``h`` (the dim side of a counter under uneven light passes it; a stretch of ink does not).
    BENCHMARKS.md, "Thresholds, third round", has the cases and the measurement."""
    from scipy import ndimage

    paper = scaled > level
    labels, count = ndimage.label(paper)           # 4-connected paper: the holes of 8-connected ink
    if count == 0:
        return
    is_hole = np.ones(count + 1, bool)
    is_hole[0] = False
    is_hole[labels[0]] = is_hole[labels[-1]] = is_hole[labels[:, 0]] = is_hole[labels[:, -1]] = False
    if not is_hole.any():
        return
    labels[~is_hole[labels]] = 0                   # holes only
    rows, cols = np.nonzero(labels)
    smooth = _blur_near(scaled, rows, cols, HOLE_RING)
    weak, bright, darkest = _weak_pieces(labels, count, scaled, smooth, paper, rho, (rows, cols))
    kept = is_hole & ~weak
    piece = labels[rows, cols]
    dim = kept[piece] & (smooth[rows, cols] < (bright[piece] + darkest[piece]) / 2.0)
    fill = weak[piece]
    if dim.any():                                  # labelled within the dim pixels' box (one pixel more)
        top, bottom, left, right = _box_around(rows[dim], cols[dim], 1, labels.shape)
        parts = np.zeros(labels.shape, labels.dtype)
        parts[rows[dim], cols[dim]] = 1
        parts[top:bottom, left:right], part_count = ndimage.label(parts[top:bottom, left:right])
        part_weak = _weak_pieces(parts, part_count, scaled, smooth, paper, rho, (rows[dim], cols[dim]),
                                 typical=True)[0]
        fill |= part_weak[parts[rows, cols]]
    level[rows[fill], cols[fill]] = np.float32(1.0)


def _weak_pieces(labels, count, scaled, smooth, paper, rho, where, typical=False):
    """Per label of ``labels`` (pieces of paper; 0 = none, ``where`` the rows and columns of the others in
    C order): whether no edge bounds it (``r > h (1 + rho) / 2``, :func:`_fill_holes_without_edges`), its
    brightest smoothed gray ``h`` (with ``typical``: its mean gray, for the dim parts of a hole, whose
    brightest pixels are the blur of the counter beside them) and the darkest smoothed gray of the ink within
    ``HOLE_RING`` px."""
    rows, cols = where
    piece = labels[rows, cols]
    if typical:
        sizes = np.bincount(piece, minlength=count + 1)
        bright = (np.bincount(piece, weights=scaled[rows, cols], minlength=count + 1)
                  / np.maximum(sizes, 1)).astype(np.float32)
    else:
        bright = np.zeros(count + 1, np.float32)
        np.maximum.at(bright, piece, smooth[rows, cols])
    ring_rows, ring_cols, ring_piece = _ring(labels, paper, rows, cols)
    counts = np.bincount(ring_piece, minlength=count + 1)
    sums = np.bincount(ring_piece, weights=scaled[ring_rows, ring_cols], minlength=count + 1)
    ring_mean = sums / np.maximum(counts, 1)
    darkest = np.full(count + 1, np.inf, np.float32)
    np.minimum.at(darkest, ring_piece, smooth[ring_rows, ring_cols])
    weak = (counts > 0) & (ring_mean > bright * (1.0 + rho) / 2.0)
    weak[0] = False
    return weak, bright, darkest

def _ring(labels, paper, rows, cols):
    """The ink pixels within ``HOLE_RING`` px (Chebyshev) of a labelled pixel (``rows, cols``, C order): their
    rows, columns (C order) and the largest label within that reach, ``maximum_filter(labels, 2 HOLE_RING +
    1)`` at the ink pixels. Computed in bands of rows of the labelled pixels' box (no ring lies beyond it), so
    no image-sized temporaries."""
    top, bottom, left, right = _box_around(rows, cols, HOLE_RING, labels.shape)
    found = []
    for start in range(top, bottom, _BLOCK_ROWS):
        stop = min(start + _BLOCK_ROWS, bottom)
        first, last = max(start - HOLE_RING, top), min(stop + HOLE_RING, bottom)
        ring = _box_max(labels[first:last, left:right], 2 * HOLE_RING + 1)[start - first:stop - first]
        ring[paper[start:stop, left:right]] = 0
        band_rows, band_cols = np.nonzero(ring)
        found.append((band_rows + start, band_cols + left, ring[band_rows, band_cols]))
    return tuple(np.concatenate(parts) for parts in zip(*found))


def _box_around(rows, cols, margin, shape):
    """``(top, bottom, left, right)``: the bounding box of the pixels ``rows, cols`` grown by ``margin`` px,
    clipped to an image of ``shape``."""
    return (max(int(rows.min()) - margin, 0), min(int(rows.max()) + margin + 1, shape[0]),
            max(int(cols.min()) - margin, 0), min(int(cols.max()) + margin + 1, shape[1]))


def _blur_near(scaled, rows, cols, reach, sigma=1.0):
    """``scipy.ndimage.gaussian_filter(scaled, sigma)`` at the pixels within ``reach`` px (Chebyshev) of the
    pixels ``rows, cols`` (in C order), bit for bit; other pixels hold 0 or that value. The filter runs on one box per run
    of such rows, grown by the kernel's radius (or cut by the image border, where the filter reflects the
    same way), so a page whose holes sit on text lines blurs the lines, not the margins between them."""
    from scipy import ndimage

    height, width = scaled.shape
    radius = int(4.0 * float(sigma) + 0.5)          # gaussian_filter's default truncate = 4
    out = np.zeros(scaled.shape, np.float32)
    if rows.size == 0:
        return out
    near = np.bincount(rows, minlength=height)      # rows with a pixel, spread by reach below and above
    near = np.convolve(near, np.ones(2 * reach + 1, np.int64))[reach:reach + height] > 0
    edges = np.flatnonzero(np.diff(np.concatenate([[False], near, [False]]).astype(np.int8)))
    starts, stops = edges[0::2], edges[1::2]
    keep = np.concatenate([[True], starts[1:] - stops[:-1] > 2 * radius])   # close runs share one box
    starts, stops = starts[keep], np.concatenate([stops[np.flatnonzero(keep)[1:] - 1], stops[-1:]])
    for start, stop in zip(starts.tolist(), stops.tolist()):
        lo, hi = np.searchsorted(rows, [start - reach, stop + reach])
        left, right = max(int(cols[lo:hi].min()) - reach, 0), min(int(cols[lo:hi].max()) + reach + 1, width)
        top, bottom = max(start - radius, 0), min(stop + radius, height)
        first, last = max(left - radius, 0), min(right + radius, width)
        blurred = ndimage.gaussian_filter(scaled[top:bottom, first:last], sigma)
        out[start:stop, left:right] = blurred[start - top:stop - top, left - first:right - first]
    return out


def _box_max(values, size):
    """``scipy.ndimage.maximum_filter(values, size, mode="nearest")`` for an odd ``size``: the largest value
    of the ``size x size`` square centred on each pixel, clipped at the image border. The same values, by
    shifted whole-array ``np.maximum`` passes, ``size - 1`` per axis (scipy's filter took 1.7 s for a 5 x 5
    square on a 48-Mpx mask, this 0.1 s; BENCHMARKS.md, "Session 13")."""
    radius = size // 2
    for axis in (0, 1):
        source, values = values, values.copy()
        for shift in range(1, radius + 1):
            ahead = [slice(None)] * 2
            behind = [slice(None)] * 2
            ahead[axis], behind[axis] = slice(shift, None), slice(None, -shift)
            np.maximum(values[tuple(ahead)], source[tuple(behind)], out=values[tuple(ahead)])
            np.maximum(values[tuple(behind)], source[tuple(ahead)], out=values[tuple(behind)])
    return values


def _rough_ink(scaled):
    """The first pass of ``"background"``: Sauvola's mask, on block means of about ``f x f`` pixels placed
    symmetrically about the centre (:func:`_centred_blocks`; bilinear would not help: the mask only seeds
    the estimates) when the image has more than ``ROUGH_PIXELS``."""
    height, width = scaled.shape
    factor = max(1, math.ceil(math.sqrt(height * width / ROUGH_PIXELS)))
    if factor == 1:
        return scaled <= _window_level(scaled, 1.0, "sauvola")
    (size_r, rows, off_r), (size_c, cols, off_c) = _centred_blocks(height, factor), _centred_blocks(width, factor)
    padded = np.pad(scaled, ((off_r, rows * size_r - height - off_r), (off_c, cols * size_c - width - off_c)),
                    mode="edge")
    small = padded.reshape(rows, size_r, cols, size_c).mean(axis=(1, 3), dtype=np.float32)
    rough = small <= _window_level(small, 1.0, "sauvola")
    rough = np.repeat(np.repeat(rough, size_r, axis=0), size_c, axis=1)
    return np.ascontiguousarray(rough[off_r:off_r + height, off_c:off_c + width])


def _centred_blocks(length, block):
    """Blocks of about ``block`` px along an axis of ``length`` px, placed symmetrically about its centre:
    ``(size, count, offset)``, the padded axis ``count * size`` px with ``offset`` px before the first pixel
    and as many after the last (``size`` is ``block`` or, for an odd ``length`` and an even ``block``,
    ``block - 1``), so a flip or a quarter turn of the image turns the block grid with it."""
    size = block - 1 if block > 1 and block % 2 == 0 and length % 2 else block
    count = -(-length // size)
    if (count * size - length) % 2:
        count += 1
    return size, count, (count * size - length) // 2


def _smooth_surface(values, support, sigma):
    """Gaussian-weighted mean of ``values`` over the ``support`` pixels (normalized convolution), smooth at
    the scale ``sigma`` px: computed on blocks of about ``max(1, sigma // 4)`` px placed symmetrically about
    the image centre (:func:`_centred_blocks`) and interpolated bilinearly back to the pixels; where no
    support pixel lies within reach, the nearest estimate."""
    from scipy import ndimage

    height, width = values.shape
    block = max(1, int(sigma // 4))
    (size_r, rows, off_r), (size_c, cols, off_c) = _centred_blocks(height, block), _centred_blocks(width, block)
    inner = (slice(off_r, off_r + height), slice(off_c, off_c + width))
    weighted = np.zeros((rows * size_r, cols * size_c), np.float32)
    weighted[inner] = support
    weight = weighted.reshape(rows, size_r, cols, size_c).sum(axis=(1, 3))
    np.multiply(values, weighted[inner], out=weighted[inner])    # the values where supported, else 0
    weighted = weighted.reshape(rows, size_r, cols, size_c).sum(axis=(1, 3))
    spread = (sigma / size_r, sigma / size_c)
    total = ndimage.gaussian_filter(weight, spread, mode="nearest")
    surface = ndimage.gaussian_filter(weighted, spread, mode="nearest") / np.maximum(total, 1e-30)
    reached = total > 1e-3 * size_r * size_c
    if not reached.all():
        nearest = ndimage.distance_transform_edt(~reached, return_distances=False, return_indices=True)
        surface = surface[nearest[0], nearest[1]]
    if size_r == size_c == 1:
        return surface.astype(np.float32)
    # block centres at (k + 1/2) size - 1/2 - offset pixels; linear between them, constant beyond the outer ones
    def weights(count, size, offset, length):
        position = (np.arange(length, dtype=np.float64) + offset + 0.5) / size - 0.5
        start = np.clip(np.floor(position).astype(int), 0, count - 1)
        stop = np.minimum(start + 1, count - 1)
        share = np.clip(position - start, 0.0, 1.0).astype(np.float32)
        return start, stop, share
    r0, r1, rw = weights(rows, size_r, off_r, height)
    c0, c1, cw = weights(cols, size_c, off_c, width)
    along = (surface[:, c0] * (1 - cw) + surface[:, c1] * cw).astype(np.float32)
    out = np.empty((height, width), np.float32)
    for start in range(0, height, _BLOCK_ROWS):     # in bands of rows: no image-sized temporaries
        band = slice(start, start + _BLOCK_ROWS)
        np.multiply(along[r0[band]], (1 - rw[band])[:, None], out=out[band])
        out[band] += along[r1[band]] * rw[band, None]
    return out


def _otsu_level(gray, lo=None, hi=None):
    """Otsu's threshold (:func:`skimage.filters.threshold_otsu`): the upper edge of the dark class.

    For 8/16-bit data the histogram (one bin per gray level from ``lo`` to ``hi``, as skimage builds it
    for integer images) is counted in row blocks and handed to skimage, which gives the same threshold
    without skimage's full-size temporaries (an 8000 x 8000 image: ~0.4 s instead of ~2 s).
    """
    from skimage.filters import threshold_otsu

    if lo is None:
        return float(threshold_otsu(gray))
    counts = np.zeros(hi + 1, dtype=np.int64)
    for start in range(0, gray.shape[0], _BLOCK_ROWS):
        counts += np.bincount(gray[start:start + _BLOCK_ROWS].reshape(-1), minlength=hi + 1)
    return float(threshold_otsu(hist=(counts[lo:], np.arange(lo, hi + 1))))


def estimate_noise(gray, white):
    """Per-pixel noise standard deviation as a fraction of white: the MAD of the finest diagonal Haar detail
    ``(a - b - c + d) / 2`` over every 2 x 2 window (for images over about 4 Mpx, the windows at evenly spaced
    rows and columns, placed symmetrically about the centre), so a flip, a quarter turn or a transpose of the
    image gives the same estimate; 0 for images smaller than 2 x 2."""
    height, width = gray.shape
    if height < 2 or width < 2:
        return 0.0
    stride = _window_stride(gray.shape)
    rows, cols = _centred_starts(height - 1, stride), _centred_starts(width - 1, stride)
    top, bottom = gray[rows].astype(np.float32), gray[rows + 1].astype(np.float32)
    detail = (top[:, cols] - top[:, cols + 1] - bottom[:, cols] + bottom[:, cols + 1]) / (2 * np.float32(white))
    return float(np.median(np.abs(detail)) / 0.6745)


def _window_stride(shape, budget=1 << 22):
    """Every how many rows and columns to read 2 x 2 windows so that at most about ``budget`` are read."""
    return max(1, math.ceil(math.sqrt(shape[0] * shape[1] / budget)))


def _centred_starts(count, stride):
    """About every ``stride``-th of the positions ``0 .. count - 1``, evenly spread and placed symmetrically:
    position ``k`` is taken exactly when ``count - 1 - k`` is."""
    if stride == 1:
        return np.arange(count)
    taken = -(-count // stride)
    first = np.floor(np.arange((taken + 1) // 2) * ((count - 1) / max(taken - 1, 1)) + 0.5).astype(np.int64)
    return np.unique(np.concatenate([first, count - 1 - first]))


def auto_speck_area(gray, white, level, mask, sigma):
    """Default speck area from the noise ``sigma`` (fraction of white): the smallest ``k`` with
    ``N (8 p)^k < 1`` (module docstring); 0 when no speck is expected. The median margins are taken on
    evenly spaced rows and columns placed symmetrically about the centre (at most about 4 Mpx)."""
    if sigma <= 0:
        return 0
    stride = _window_stride(gray.shape)
    rows = np.ix_(_centred_starts(gray.shape[0], stride), _centred_starts(gray.shape[1], stride))
    local = np.ndim(level) == 2
    margin = (gray[rows].astype(np.float32) - (level[rows] if local else np.float32(level))) / np.float32(white)
    ink_rows = mask[rows]
    if ink_rows.all() or not ink_rows.any():
        return 0
    paper = float(np.median(margin[~ink_rows]))
    ink = float(-np.median(margin[ink_rows]))
    flip = max(_normal_tail(paper / sigma), _normal_tail(ink / sigma))
    rate = 8.0 * flip
    count = mask.size
    if rate * count < 1.0:
        return 0
    if rate >= 1.0:
        return MAX_AUTO_SPECK
    return int(min(MAX_AUTO_SPECK, math.floor(math.log(count) / -math.log(rate)) + 1))


def _normal_tail(z):
    """``P(Z > z)`` of a standard normal variable."""
    return 0.5 * math.erfc(z / math.sqrt(2.0))


def remove_specks(mask, min_area, connectivity):
    """Remove ink components and fill holes with fewer than ``min_area`` pixels; background touching the
    image border is never filled. Ink uses ``connectivity``, the background the complementary one."""
    from scipy import ndimage
    from skimage import morphology

    ink_conn = 2 if connectivity == 8 else 1
    if "max_size" in inspect.signature(morphology.remove_small_objects).parameters:
        mask = morphology.remove_small_objects(mask, max_size=min_area - 1, connectivity=ink_conn)
    else:  # pragma: no cover - scikit-image < 0.26
        mask = morphology.remove_small_objects(mask, min_size=min_area, connectivity=ink_conn)
    hole_structure = ndimage.generate_binary_structure(2, 1 if connectivity == 8 else 2)
    labels, count = ndimage.label(~mask, structure=hole_structure)
    if count:
        sizes = np.bincount(labels.reshape(-1), minlength=count + 1)
        small = sizes < min_area
        small[0] = False
        border = np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]]))
        small[border] = False
        if small.any():
            mask = mask | small[labels]
    return np.ascontiguousarray(mask, dtype=bool)


def fill_pinholes(mask, boundaries, area=PINHOLE_AREA):
    """The pixels of the holes of ``boundaries`` (those of ``mask``, from ``trace_boundaries``) that enclose
    fewer than ``area`` <= 3 pixels set to ink (module docstring, "Pinholes").

    Returns ``(mask, filled)``: the mask (a copy when any hole is filled) and the number of holes filled. A hole
    of one or two pixels is a single pixel, two edge neighbours, or two diagonal neighbours whose other two
    pixels of the 2 x 2 block are ink, so the paper pixels of its crack box are exactly its own. The caller
    traces the filled mask again: under the minority rule a filled pixel can change the decision at a nearby
    diagonal contact.
    """
    if isinstance(area, bool) or not isinstance(area, numbers.Integral) or not 0 <= area <= 3:
        raise ValueError(f"area must be an integer in [0, 3] (holes of one or two pixels), got {area!r}")
    from .contour import hole_boxes

    boxes = hole_boxes(boundaries, area)
    if not boxes.shape[0]:
        return mask, 0
    mask = np.array(mask, dtype=bool, copy=True)
    for x0, y0, x1, y1 in boxes.tolist():
        mask[y0:y1, x0:x1] = True
    return mask, boxes.shape[0]


def drop_specks(mask, boundaries, area=PINHOLE_AREA):
    """The pixels of the outer boundaries of ``boundaries`` (those of ``mask``, from ``trace_boundaries``) that
    enclose fewer than ``area`` <= 3 pixels set to paper, the ink counterpart of :func:`fill_pinholes` (module
    docstring, "Pinholes"); nothing is dropped when no other outer boundary is left (a bitmap that is only
    specks keeps them).

    Returns ``(mask, dropped)``: the mask (a copy when any speck is dropped) and the number of specks dropped. An
    ink component of one or two pixels is a single pixel, two edge neighbours, or two diagonal neighbours whose
    other two pixels of the 2 x 2 block are paper, so the ink pixels of its crack box are exactly its own.
    """
    if isinstance(area, bool) or not isinstance(area, numbers.Integral) or not 0 <= area <= 3:
        raise ValueError(f"area must be an integer in [0, 3] (specks of one or two pixels), got {area!r}")
    from .contour import speck_boxes

    boxes = speck_boxes(boundaries, area)
    holes = getattr(boundaries, "is_hole", None)  # a Boundaries object has the array; a list has Boundary items
    outer = int((~holes).sum()) if isinstance(holes, np.ndarray) else sum(not b.is_hole for b in boundaries)
    if not boxes.shape[0] or boxes.shape[0] >= outer:
        return mask, 0
    mask = np.array(mask, dtype=bool, copy=True)
    for x0, y0, x1, y1 in boxes.tolist():
        mask[y0:y1, x0:x1] = False
    return mask, boxes.shape[0]
