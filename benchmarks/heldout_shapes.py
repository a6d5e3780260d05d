"""Held-out shapes for the peers benchmark: glyphs of other font families and scripts, any size and rotation,
clean and scan-like, with their exact outlines (benchmarks only; nothing is tuned on them).

Fonts are the Debian packages listed in :data:`FONT_PACKAGES` (installed by ``scripts/system-deps.sh``
when missing): an old-style serif with soft fillets (EB Garamond), a serif italic and a bold sans
(Liberation), FreeSerif, an Arabic naskh (Amiri) and a CJK mincho (IPA Mincho). DejaVu, the family of the
yardstick and of the synthetic tuning set, is not among them.

A glyph's exact outline comes from the font itself (:mod:`fontTools`, TrueType quadratic and CFF cubic
outlines alike): every segment is kept, the dense polyline (<= 0.1 px spacing) is the truth the traced SVG is
scored against, and the true corners are the joins of consecutive segments whose tangents turn by more than
30 degrees (the yardstick's definition). ``size`` is the font's cap height in pixels; a rotation turns the
outline about its centre before it is placed in the pixel frame (x right, y down, pixel corners on integer
coordinates, 6 px margin).

Rendering: a pixel is ink when its centre is inside the outline (even-odd over the contours). Scan-like
variants follow the recipe of a 4x supersampled render, a Gaussian blur of ``sigma`` px, per-pixel Gaussian
noise of ``noise`` (standard deviation on the 0..1 gray scale, per supersampled pixel), a 4 x 4 mean and a
threshold at 0.5 (:func:`scan_like`).
"""
from __future__ import annotations

import glob
import os

import numpy as np

FONT_DIRS = ("/usr/share/fonts",)
#: Debian packages of the held-out fonts.
FONT_PACKAGES = ("fonts-ebgaramond", "fonts-liberation2", "fonts-hosny-amiri", "fonts-ipafont-mincho",
                 "fonts-freefont-ttf")
#: family label -> (file name, characters)
FAMILIES = {
    "oldstyle": ("EBGaramond12-Regular.otf", "AaBbGgKkMRSWe&"),
    "italic": ("LiberationSerif-Italic.ttf", "AaBbGgKkMRSWe&"),
    "boldsans": ("LiberationSans-Bold.ttf", "AaBbGgKkMRSWe&"),
    "freeserif": ("FreeSerif.ttf", "AaBbGgKkMRSWe&"),
    "arabic": ("Amiri-Regular.ttf", "\u0628\u062c\u0633\u0639\u0642\u0643\u0647\u0645\u0635\u0637"),
    "cjk": ("ipam.ttf", "\u6c38\u6c34\u66f8\u56fd\u611b\u9053\u5c71\u8a9e"),
}
STEP = 0.1
CORNER_DEG = 30.0
#: Segments shorter than this (px of arc) are below the pixel's resolution: a run of them is one join.
MIN_RESOLVED = 1.0
MARGIN = 6


def find_font(file_name):
    for folder in FONT_DIRS:
        hits = glob.glob(os.path.join(folder, "**", file_name), recursive=True)
        if hits:
            return hits[0]
    return None


def available_families():
    return {label: (path, chars) for label, (name, chars) in FAMILIES.items() if (path := find_font(name))}


# ------------------------------------------------------------------------------------------- outlines
def _segments_of_glyph(font, char):
    """Exact closed contours of a glyph in font units: list of lists of ('L', p0, p1) / ('Q', p0, p1, p2) /
    ('C', p0, p1, p2, p3) tuples (fontTools decomposes TrueType's implied on-curve points)."""
    from fontTools.pens.basePen import BasePen

    class Collect(BasePen):
        def __init__(self, glyphs):
            super().__init__(glyphs)
            self.contours, self.current, self.start = [], [], None

        def _moveTo(self, p):
            self.current, self.start = [], p

        def _lineTo(self, p):
            self.current.append(("L", self._getCurrentPoint(), p))

        def _qCurveToOne(self, p1, p2):
            self.current.append(("Q", self._getCurrentPoint(), p1, p2))

        def _curveToOne(self, p1, p2, p3):
            self.current.append(("C", self._getCurrentPoint(), p1, p2, p3))

        def _closePath(self):
            end = self._getCurrentPoint()
            if end is not None and self.start is not None and tuple(end) != tuple(self.start):
                self.current.append(("L", end, self.start))
            if self.current:
                self.contours.append(self.current)
            self.current = []

        _endPath = _closePath

    glyph_set = font.getGlyphSet()
    name = font.getBestCmap().get(ord(char))
    if name is None:
        return None
    pen = Collect(glyph_set)
    glyph_set[name].draw(pen)
    return pen.contours


def _bezier(points, t):
    points = np.asarray(points, float)
    degree = len(points) - 1
    t = np.asarray(t, float)[:, None]
    from math import comb
    return sum(comb(degree, i) * (1 - t) ** (degree - i) * t ** i * points[i] for i in range(degree + 1))


def _end_tangents(points):
    """(start direction, end direction) of a Bézier given by its control points (coincident ones skipped)."""
    points = np.asarray(points, float)
    start = next((points[i] - points[0] for i in range(1, len(points))
                  if np.hypot(*(points[i] - points[0])) > 1e-9), np.zeros(2))
    end = next((points[-1] - points[-1 - i] for i in range(1, len(points))
                if np.hypot(*(points[-1] - points[-1 - i])) > 1e-9), np.zeros(2))
    return start, end


def _turn(u, v):
    nu, nv = np.hypot(*u), np.hypot(*v)
    if nu < 1e-12 or nv < 1e-12:
        return 0.0
    return float(np.degrees(np.arccos(np.clip(np.dot(u, v) / (nu * nv), -1, 1))))


def _place(contours, transform):
    """Apply an affine map ``(matrix, offset)`` to every control point; drop zero-length segments."""
    matrix, offset = transform
    placed = []
    for segs in contours:
        out = []
        for seg in segs:
            pts = np.asarray(seg[1:], float) @ matrix.T + offset
            if np.hypot(*(pts[-1] - pts[0])) > 1e-9 or np.ptp(pts, axis=0).max() > 1e-9:
                out.append((seg[0], pts))
        if out:
            placed.append(out)
    return placed


def _segment_length(pts):
    rough = _bezier(pts, np.linspace(0, 1, 33))
    return float(np.hypot(*np.diff(rough, axis=0).T).sum())


def _contour_corners(segs, lengths):
    """True corners of one placed contour: joins turning by more than ``CORNER_DEG``, where a run of
    segments shorter than ``MIN_RESOLVED`` px counts as one join (the turn from the tangent entering the run
    to the tangent leaving it; the corner at the middle of the run). A contour made only of such segments
    keeps the plain rule."""
    n = len(segs)
    tiny = np.asarray(lengths) < MIN_RESOLVED
    if tiny.all() or not tiny.any():
        tiny = np.zeros(n, dtype=bool)
    resolved = np.flatnonzero(~tiny)
    corners = []
    for before, after in zip(resolved, np.roll(resolved, -1)):
        run = [k % n for k in range(before + 1, after + (n if after <= before else 0))]
        turn = _turn(_end_tangents(segs[before][1])[1], _end_tangents(segs[after][1])[0])
        if turn > CORNER_DEG:
            point = 0.5 * (segs[run[0]][1][0] + segs[after][1][0]) if run else segs[after][1][0]
            corners.append((float(point[0]), float(point[1])))
    return corners


def _dense_and_corners(contours):
    dense, corners = [], []
    for segs in contours:
        parts, lengths = [], []
        for kind, pts in segs:
            length = _segment_length(pts)
            n = max(2, int(np.ceil(length / STEP)))
            parts.append(_bezier(pts, np.arange(n) / n))
            lengths.append(length)
        dense.append(np.concatenate(parts))
        corners.extend(_contour_corners(segs, lengths))
    return dense, corners


def glyph_shape(font_path, char, size, rotate_deg=0.0, label=""):
    """A held-out shape dict (the format of ``synthetic_shapes``) plus ``segments`` (true segment count),
    ``family`` and ``source``; None when the font has no such glyph."""
    from fontTools.ttLib import TTFont

    font = TTFont(font_path, lazy=True)
    contours = _segments_of_glyph(font, char)
    if not contours:
        return None
    os2 = font["OS/2"] if "OS/2" in font else None
    cap = getattr(os2, "sCapHeight", 0) or 0.7 * font["head"].unitsPerEm
    scale = size / cap
    r = np.radians(rotate_deg)
    # font units (y up) -> pixels (y down), rotated counter-clockwise on screen by rotate_deg
    matrix = scale * np.array([[np.cos(r), -np.sin(r)], [-np.sin(r), -np.cos(r)]])
    placed = _place(contours, (matrix, np.zeros(2)))
    allpts = np.concatenate([pts for segs in placed for _, pts in segs])
    offset = MARGIN - np.floor(allpts.min(axis=0))
    placed = [[(kind, pts + offset) for kind, pts in segs] for segs in placed]
    dense, corners = _dense_and_corners(placed)
    hi = np.ceil(np.concatenate(dense).max(axis=0)) + MARGIN
    code = "+".join(f"U+{ord(c):04X}" for c in char)
    return {"name": f"{label}_{code}_{size}px_r{rotate_deg:g}", "width": int(hi[0]), "height": int(hi[1]),
            "contours": dense, "corners": corners, "segments": int(sum(len(s) for s in placed)),
            "family": label, "size": size, "rotate": rotate_deg,
            "source": f"{os.path.basename(font_path)} {code}; cap {size} px; rotated {rotate_deg:g} deg"}


# ------------------------------------------------------------------------------------------- rendering
def rasterize(shape, supersample=1):
    """Ink mask: pixel centres inside the outline (even-odd over the contours), optionally supersampled.

    Scanline fill: every edge of the dense outline toggles, in each pixel row whose centre line it crosses,
    the pixels right of the crossing; a cumulative parity along the row gives the even-odd rule (``O(edges +
    pixels)``)."""
    height, width = shape["height"] * supersample, shape["width"] * supersample
    toggles = np.zeros((height, width + 1), np.int32)
    for line in shape["contours"]:
        p = np.asarray(line, float) * supersample
        q = np.roll(p, -1, axis=0)
        lo, hi = np.minimum(p[:, 1], q[:, 1]), np.maximum(p[:, 1], q[:, 1])
        first = np.ceil(lo - 0.5).astype(np.int64)
        count = np.maximum(np.ceil(hi - 0.5).astype(np.int64) - first, 0)
        edge = np.repeat(np.arange(len(p)), count)
        row = first[edge] + (np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count))
        a, b = p[edge], q[edge]
        x = a[:, 0] + (row + 0.5 - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
        col = np.clip(np.ceil(x - 0.5).astype(np.int64), 0, width)
        inside = (row >= 0) & (row < height)
        np.add.at(toggles, (row[inside], col[inside]), 1)
    return (np.cumsum(toggles, axis=1)[:, :width] & 1).astype(bool)


def scan_like(shape, sigma, noise, seed, supersample=4):
    """Scan-like gray image (0 = black .. 1 = white) and its thresholded ink mask (gray < 0.5)."""
    from scipy.ndimage import gaussian_filter

    ink = rasterize(shape, supersample).astype(float)
    gray = 1.0 - gaussian_filter(ink, sigma * supersample)
    gray += np.random.default_rng(seed).normal(0.0, noise, gray.shape)
    height, width = shape["height"], shape["width"]
    gray = gray.reshape(height, supersample, width, supersample).mean(axis=(1, 3))
    return np.clip(gray, 0.0, 1.0), gray < 0.5


def heldout_set(sizes=(48, 64, 120, 300, 600, 1200), rotations=(0, 7, 23, 45, 61, 90), scans=3, seed=7,
                per_family=6):
    """Deterministic held-out shapes: per family ``per_family`` glyphs at 300 px upright, and each of them
    once more at a size and a rotation drawn from ``sizes`` / ``rotations``; ``scans`` scan-like renders per
    family at 300 px. Every shape has ``group``: the family for upright 300 px glyphs, else ``small``
    (<= 64 px), ``large`` (>= 600 px), ``rotated`` or ``scan``."""
    rng = np.random.default_rng(seed)
    shapes = []
    for label, (path, chars) in available_families().items():
        picked = [chars[i] for i in sorted(rng.choice(len(chars), size=min(per_family, len(chars)), replace=False))]
        for char in picked:
            base = glyph_shape(path, char, 300, 0.0, label)
            if base is None:
                continue
            shapes.append(dict(base, group=label))
            size = int(rng.choice(sizes))
            angle = float(rng.choice(rotations))
            other = glyph_shape(path, char, size, angle, label)
            if other is not None:
                group = "small" if size <= 64 else "large" if size >= 600 else "rotated" if angle else label
                shapes.append(dict(other, group=group))
        for k, char in enumerate(picked[:scans]):
            base = glyph_shape(path, char, 300, 0.0, label)
            sigma, noise = float(rng.uniform(1.0, 2.0)), float(rng.uniform(0.2, 0.3))
            gray, mask = scan_like(base, sigma, noise, seed=1000 + 17 * k + len(shapes))
            shapes.append(dict(base, name="scan_" + base["name"], group="scan", gray=gray, mask=mask,
                               source=base["source"] + f"; scan-like: 4x supersampled, gaussian blur sigma "
                               f"{sigma:.2f} px, noise sd {noise:.2f} per 4x pixel, 4x4 mean, threshold 0.5"))
    return shapes
