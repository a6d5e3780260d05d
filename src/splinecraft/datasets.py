"""Deterministic test bitmaps and point sets: the thesis's five objects, teaching shapes, editor demos.

Chapter 4 of the thesis evaluates its knot-insertion algorithms on five scanned objects (tables
4.1-4.61): the Arabic word 'Ali' (علي), an apple, a plane, the letter 'D' and a plane made of several
parts ("Mult_Seg_Plane"). The scans are not available, so this module draws objects *like* them,
procedurally, with numpy only: every object is an implicit shape ``f(x, y) <= 0`` built from exact
primitives (discs, ellipses, polygons, stroked curves of varying width) combined by union, intersection
and difference. Two things follow from that:

* the bitmap is a *sampling* of a known shape (pixel ``(r, c)`` is ink iff the pixel centre
  ``(c + 0.5, r + 0.5)`` is inside), identical on every machine (no fonts, no text shaping:
  PIL without libraqm does not join Arabic letters, so 'Ali' is drawn as strokes that follow the
  joined Naskh word as DejaVu Sans renders it);
* the *true* outline is known: :func:`true_outline` returns it as dense polylines lying on the zero set
  (to 1e-3 px), so a traced result can be scored by its geometric deviation from the real shape and
  not only from the pixel staircase (used by ``benchmarks/thesis_tables.py``).

Frame: the pixel frame of the capture modules (x right, y down, pixel ``(r, c)`` covers
``[c, c+1] x [r, r+1]``). Outer outlines have positive shoelace area in that frame, holes negative
(the orientation of :class:`splinecraft.Boundary`).

Public functions
----------------
thesis_object(name, size=None) -> bool mask            names in :data:`THESIS_OBJECTS`
shape(name, size=128) -> bool mask                      names in :data:`SHAPES`
true_outline(name, size=None) -> list of (n, 2) arrays  any name of the two lists above
shape_corners(name, size=None) -> (k, 2) array          exact corners of the shapes and of 'D'
sample_points(name) -> (n, 2) array; sample_closed(name) -> bool    names in :data:`SAMPLE_POINTS`
"""
from __future__ import annotations

import functools
import numbers

import numpy as np

from . import _validation
from ._implicit import (difference, disc, ellipse, half_plane, intersection, polygon, project, refine_closed,
                        smooth_union, stroke, union, vesica)

__all__ = [
    "THESIS_OBJECTS",
    "THESIS_TITLES",
    "SHAPES",
    "SAMPLE_POINTS",
    "thesis_object",
    "shape",
    "true_outline",
    "shape_corners",
    "sample_points",
    "sample_closed",
]

# ----------------------------------------------------------------------------------------------
# The objects. Each builder returns (f, width, height) in its own design units (y down); the
# bitmap scales the longer side to ``size`` pixels.
# ----------------------------------------------------------------------------------------------


def _ali():
    """The Arabic word 'Ali' (علي) in a Naskh-like style: ayn (initial), lam (medial), ya (final).

    Drawn in the units of a 300-px DejaVu Sans rendering of the joined word (read right to left):
    the ayn's open 'c' head over its rising, square-cut tail on the right, the tall lam with
    filleted foot, then the ya's hump, curl and deep bowl, and its two square dots below. Three
    components (the word, two dots), no holes.
    """
    lam = polygon([(307, 50), (333, 50), (333, 262), (307, 262)])
    baseline = stroke([(300, 264), (340, 264), (400, 262), (440, 250), (475, 233), (525, 210)],
                      [13.5, 13.5, 13.5, 13, 12.5, 12])
    tail_cut = half_plane((517, 212), (1, 0))
    ayn_head = stroke([(492, 135), (455, 137), (430, 150), (414, 172), (412, 195), (422, 218),
                       (442, 236), (452, 246)], [12, 12, 12.5, 13, 13, 13, 13, 13])
    head_cut = half_plane((484, 135), (1, 0))
    word = smooth_union(lam, intersection(baseline, tail_cut), 10)
    word = union(word, intersection(ayn_head, head_cut))
    ya = stroke([(322, 264), (292, 264), (264, 257), (242, 238), (224, 218), (204, 211), (187, 224),
                 (184, 247), (200, 268), (203, 288), (180, 302), (140, 306), (95, 303), (64, 289),
                 (52, 262), (56, 232), (60, 215)],
                 [13.5, 13.5, 14, 15.5, 16, 15, 13.5, 12.5, 12.5, 12.5, 12.5, 12.5, 12.5, 12.5,
                  12.5, 12.5, 12.5])
    tip_cut = half_plane((0, 224), (0, -1))
    word = union(word, intersection(ya, tip_cut))
    dots = union(polygon([(94, 330), (115, 330), (115, 351), (94, 351)]),
                 polygon([(130, 330), (151, 330), (151, 351), (130, 351)]))
    drawing = union(word, dots)

    def f(x, y):  # shift the drawing into a canvas with a margin
        return drawing(x + 15.0, y + 28.0)
    return f, 540.0, 345.0


def _apple():
    """An apple: two-lobed body with a top dimple, a curved stem and a pointed leaf (one component)."""
    lobes = smooth_union(disc(37, 56, 28), disc(63, 56, 28), 10)
    bottom = smooth_union(disc(41, 74, 21), disc(59, 74, 21), 8)
    body = smooth_union(lobes, bottom, 8)
    dimple_top = disc(50, 22, 8.5)
    dimple_bottom = disc(50, 100.5, 5.5)
    body = difference(body, dimple_top, dimple_bottom)
    stem = stroke([(50, 34), (51, 24), (54, 14), (58, 7)], [3.0, 2.6, 2.2, 2.0])
    leaf = vesica((53.0, 21.0), (81, 8.5), 6.5)
    sprig = smooth_union(stem, leaf, 2.5)  # fillet: no pinhole in the acute notch
    return smooth_union(body, sprig, 2.0), 100.0, 104.0


def _plane_parts(gap=0.0):
    """Top view of an airliner: fuselage, swept wings with engines, tailplane."""
    fuselage = stroke([(50, 6), (50, 20), (50, 72), (50, 94)], [2.5, 5.5, 5.5, 2.2], 8)
    wings = [polygon([(47, 38), (5, 58), (5, 64), (47, 55)]),
             polygon([(53, 38), (95, 58), (95, 64), (53, 55)])]
    engines = [ellipse(28, 50, 3.2, 7.0), ellipse(72, 50, 3.2, 7.0)]
    tail = [polygon([(48.5, 79), (32, 89), (32, 93), (48.5, 88)]),
            polygon([(51.5, 79), (68, 89), (68, 93), (51.5, 88)])]
    return fuselage, wings, engines, tail


def _plane():
    """A plane (top view): one component with many corners (wing and tail tips, engine nacelles)."""
    fuselage, wings, engines, tail = _plane_parts()
    return union(fuselage, *wings, *engines, *tail), 100.0, 100.0


def _planes():
    """A plane made of several parts ('Mult_Seg_Plane'): separate fuselage, wings, engines, tail.

    The wings and the tailplane are cut free of the fuselage by a gap, the engines are detached pods,
    and the fuselage has a cockpit window and three cabin windows (holes): 7 components, 4 holes.
    """
    fuselage = stroke([(50, 6), (50, 20), (50, 72), (50, 94)], [3.0, 7.0, 7.0, 2.6], 8)
    clearance = stroke([(50, 6), (50, 20), (50, 72), (50, 94)], [5.0, 9.5, 9.5, 4.6], 8)
    windows = [ellipse(50, 17, 3.0, 4.5), disc(50, 35, 2.4), disc(50, 47, 2.4), disc(50, 59, 2.4)]
    body = difference(fuselage, *windows)
    wing_left = polygon([(47, 36), (5, 58), (5, 64), (47, 55)])
    wing_right = polygon([(53, 36), (95, 58), (95, 64), (53, 55)])
    wings = difference(union(wing_left, wing_right), clearance)
    engines = union(ellipse(28, 41, 3.6, 6.5), ellipse(72, 41, 3.6, 6.5))
    engine_clearance = union(ellipse(28, 41, 5.6, 8.5), ellipse(72, 41, 5.6, 8.5))
    wings = difference(wings, engine_clearance)
    tail = difference(union(polygon([(47, 80), (30, 90), (30, 94), (47, 89)]),
                            polygon([(53, 80), (70, 90), (70, 94), (53, 89)])), clearance)
    return union(body, wings, engines, tail), 100.0, 100.0


def _letter_d():
    """A serif capital 'D': stem with top and bottom serifs, elliptical bowl, one counter (hole)."""
    outer = union(polygon([(16, 10), (52, 10), (52, 90), (16, 90)]),
                  intersection(ellipse(52, 50, 36, 40), half_plane((52, 0), (-1, 0))),
                  polygon([(7, 10), (30, 10), (30, 16), (7, 16)]),
                  polygon([(7, 84), (30, 84), (30, 90), (7, 90)]))
    counter = union(polygon([(35, 22), (52, 22), (52, 78), (35, 78)]),
                    intersection(ellipse(52, 50, 22, 28), half_plane((52, 0), (-1, 0))))
    return difference(outer, counter), 96.0, 100.0


def _square():
    return polygon([(20, 20), (80, 20), (80, 80), (20, 80)]), 100.0, 100.0


def _star():
    """Five-pointed star (10 corners: 5 convex tips, 5 concave)."""
    return polygon(_star_vertices()), 100.0, 100.0


def _disc_shape():
    return disc(50, 50, 38), 100.0, 100.0


def _ellipse_shape():
    return ellipse(50, 50, 42, 24, angle_deg=25.0), 100.0, 100.0


def _blob():
    """A smooth, non-convex blob: a radial Fourier series (fixed coefficients), no corners."""
    harmonics = np.array([2, 3, 5])
    amplitude = np.array([0.16, 0.10, 0.05])
    phase = np.array([0.3, 1.9, 4.0])

    def boundary_radius(angle):
        return 30.0 * (1.0 + (amplitude * np.cos(harmonics * angle[:, None] + phase)).sum(axis=1))

    def f(x, y):
        # radial function: exact zero set r = R(angle); scaled so |grad f| ~ 1 near the boundary
        angle = np.arctan2(y - 50.0, x - 50.0)
        return np.hypot(x - 50.0, y - 50.0) - boundary_radius(angle)
    return f, 100.0, 100.0


_THESIS_BUILDERS = {"ali": _ali, "apple": _apple, "plane": _plane, "D": _letter_d, "planes": _planes}
_SHAPE_BUILDERS = {"square": _square, "star": _star, "disc": _disc_shape, "ellipse": _ellipse_shape,
                   "blob": _blob}

#: The five thesis-like objects, in the order of the thesis's tables (4.1-4.30, 4.61).
THESIS_OBJECTS = ("ali", "apple", "plane", "D", "planes")
#: The thesis's names for them (table captions).
THESIS_TITLES = {"ali": "Arabic word 'Ali'", "apple": "Apple", "plane": "Plane",
                 "D": "English alphabet 'D'", "planes": "Mult_Seg_Plane"}
#: Default bitmap size (longer side, px) per object: contours of the order of the thesis's scans
#: (1644 points for its 'Ali', 1005 for its 'Mult_Seg_Plane'): 1200-2600 crack-outline points here
#: ('ali' 1980, 'apple' 1218, 'plane' 1738, 'D' 1590, 'planes' 2638).
THESIS_DEFAULT_SIZE = {"ali": 420, "apple": 300, "plane": 360, "D": 300, "planes": 360}
#: Teaching shapes for the corner-detector and fitting notebooks and tests.
SHAPES = tuple(_SHAPE_BUILDERS)


def _check_size(size, name="size"):
    if isinstance(size, bool) or not isinstance(size, numbers.Integral):
        raise TypeError(f"{name} must be an int (pixels of the longer side), got {type(size).__name__}")
    size = int(size)
    if not 16 <= size <= 8192:
        raise ValueError(f"{name} must be between 16 and 8192 pixels, got {size}")
    return size


def _lookup(name, builders, what):
    if not isinstance(name, str):
        raise TypeError(f"name must be a str, got {type(name).__name__}")
    if name not in builders:
        raise ValueError(f"unknown {what} {name!r}; valid names: {', '.join(repr(n) for n in builders)}")
    return builders[name]


def _frame(builder, size):
    """(f, scale, height_px, width_px) for drawing a design onto a ``size``-px bitmap."""
    f, width, height = builder()
    scale = size / max(width, height)
    return f, scale, max(1, int(round(height * scale))), max(1, int(round(width * scale)))


@functools.lru_cache(maxsize=64)
def _render(kind, name, size):
    builder = (_THESIS_BUILDERS if kind == "thesis" else _SHAPE_BUILDERS)[name]
    f, scale, rows, cols = _frame(builder, size)
    c, r = np.meshgrid(np.arange(cols) + 0.5, np.arange(rows) + 0.5)
    values = f(c.ravel() / scale, r.ravel() / scale).reshape(rows, cols)
    values.flags.writeable = False
    return values


def thesis_object(name, size=None):
    """Bitmap of one of the five thesis-like objects of chapter 4.

    Parameters
    ----------
    name : {'ali', 'apple', 'plane', 'D', 'planes'}
        'ali': the Arabic word علي (word + two dots: 3 components); 'apple': body, stem and leaf
        (1 component); 'plane': airliner top view (1 component, many corners); 'D': serif capital
        with its counter (1 component, 1 hole); 'planes': a plane made of separate parts with
        windows (7 components, 4 holes), the thesis's 'Mult_Seg_Plane'.
    size : int, optional
        Pixels of the longer side (16..8192). Default :data:`THESIS_DEFAULT_SIZE` ``[name]``.

    Returns
    -------
    numpy.ndarray of bool, shape (H, W)
        True = ink. Pixel ``(r, c)`` is ink iff its centre ``(c + 0.5, r + 0.5)`` lies inside the
        shape. Deterministic (pure numpy arithmetic, no fonts, no randomness); a fresh array.

    Raises
    ------
    ValueError
        Unknown name (the message lists the valid ones) or size out of range.
    TypeError
        name not a str, size not an int.
    """
    _lookup(name, _THESIS_BUILDERS, "thesis object")
    size = THESIS_DEFAULT_SIZE[name] if size is None else _check_size(size)
    return _render("thesis", name, size) <= 0.0


def shape(name, size=128):
    """Bitmap of a teaching shape: 'square', 'star', 'disc', 'ellipse' (rotated 25°) or 'blob'.

    Same frame and conventions as :func:`thesis_object`. Known corners: the square has 4 (axis
    aligned, at 20% and 80% of the side), the star 10 (5 tips, 5 inner), disc/ellipse/blob none.
    """
    _lookup(name, _SHAPE_BUILDERS, "shape")
    return _render("shape", name, _check_size(size)) <= 0.0


@functools.lru_cache(maxsize=32)
def _outline(kind, name, size, spacing):
    from skimage import measure

    builders = _THESIS_BUILDERS if kind == "thesis" else _SHAPE_BUILDERS
    f, scale, rows, cols = _frame(builders[name], size)
    values = np.pad(_render(kind, name, size), 1, constant_values=1.0)  # keep every contour closed
    outlines = []
    for contour in measure.find_contours(values, 0.0):
        # contour: (row, col) in the padded grid of pixel centres -> design units
        xy = np.c_[contour[:, 1] - 0.5, contour[:, 0] - 0.5] / scale
        if np.allclose(xy[0], xy[-1]):
            xy = xy[:-1]
        xy = project(f, xy)
        dense = refine_closed(f, xy, spacing / scale) * scale
        area = 0.5 * np.sum(dense[:, 0] * np.roll(dense[:, 1], -1) - np.roll(dense[:, 0], -1) * dense[:, 1])
        outlines.append((dense, area))
    # find_contours keeps the higher values (outside) on a fixed side: outers and holes come out with
    # opposite signs. Make outers positive in the y-down frame (the convention of Boundary).
    if outlines:
        largest = max(outlines, key=lambda item: abs(item[1]))
        sign = 1.0 if largest[1] > 0 else -1.0
        outlines = [(dense if sign > 0 else dense[::-1].copy(), area * sign) for dense, area in outlines]
    result = tuple(dense for dense, _ in outlines)
    for dense in result:
        dense.flags.writeable = False
    return result


def true_outline(name, size=None, *, spacing=0.1):
    """The exact outline of a thesis object or teaching shape, in the pixel frame of its bitmap.

    Parameters
    ----------
    name : str
        Any name of :data:`THESIS_OBJECTS` or :data:`SHAPES`.
    size : int, optional
        As for :func:`thesis_object` / :func:`shape` (same defaults), so the outline overlays the
        bitmap of the same size.
    spacing : float, optional
        Maximum distance between consecutive outline points, px (0.01..1).

    Returns
    -------
    list of numpy.ndarray, each (n, 2)
        One closed polyline per boundary (first point not repeated), vertices on the shape's zero
        set (to 1e-3 px, mostly to round-off) and at most ``spacing`` apart; sharp corners are
        vertices. Outer boundaries have positive shoelace area in the (x, y-down) frame, holes
        negative. Between vertices the chord error on an arc of radius R is below
        ``spacing**2 / (8 R)``.

    Notes
    -----
    The boundaries are found by marching squares on the pixel-centre samples (so they have the
    topology of the bitmap), then every vertex is Newton-projected onto the zero set, and edges are
    subdivided to ``spacing`` and projected again; an edge that stays long spans a corner, where the
    intersection of the neighbouring tangent lines is inserted. Results are cached per
    (name, size, spacing); every call returns fresh copies.
    """
    if name in _THESIS_BUILDERS:
        kind, size = "thesis", THESIS_DEFAULT_SIZE[name] if size is None else _check_size(size)
    elif name in _SHAPE_BUILDERS:
        kind, size = "shape", 128 if size is None else _check_size(size)
    else:
        _lookup(name, {**_THESIS_BUILDERS, **_SHAPE_BUILDERS}, "shape")
        raise AssertionError  # unreachable
    if isinstance(spacing, bool) or not isinstance(spacing, numbers.Real) or not 0.01 <= spacing <= 1.0:
        raise ValueError(f"spacing must be a number between 0.01 and 1 px, got {_validation.plain(spacing)!r}")
    return [outline.copy() for outline in _outline(kind, name, size, float(spacing))]


def _star_vertices():
    angles = np.radians(-90 + 36 * np.arange(10))
    radii = np.where(np.arange(10) % 2 == 0, 42.0, 18.0)
    return np.c_[50 + radii * np.cos(angles), 52 + radii * np.sin(angles)]


# Design-unit corners (tangent discontinuities) of the shapes whose corners are known exactly.
_CORNERS = {
    "square": lambda: np.array([[20.0, 20.0], [80.0, 20.0], [80.0, 80.0], [20.0, 80.0]]),
    "star": _star_vertices,
    "disc": lambda: np.zeros((0, 2)),
    "ellipse": lambda: np.zeros((0, 2)),
    "blob": lambda: np.zeros((0, 2)),
    # the serif D: 6 on the outer boundary (serifs and stem), 2 in the counter; the bowls join the
    # straight edges with horizontal tangents, so those joins are smooth (curvature jumps only)
    "D": lambda: np.array([[7.0, 10.0], [7.0, 16.0], [16.0, 16.0], [16.0, 84.0], [7.0, 84.0], [7.0, 90.0],
                           [35.0, 22.0], [35.0, 78.0]]),
}


def shape_corners(name, size=None):
    """The exact corners (tangent discontinuities) of a shape, in the pixel frame of its bitmap.

    Ground truth for corner detectors (chapter 2): 'square' 4, 'star' 10 (5 convex tips, 5 reflex
    corners), 'disc', 'ellipse', 'blob' none, and
    the thesis object 'D' 8 (6 outer: serifs and stem; 2 in the counter). Other thesis objects have
    corners only implicitly (where primitives meet) and raise ``ValueError``.

    Parameters
    ----------
    name : str
        One of 'square', 'star', 'disc', 'ellipse', 'blob', 'D'.
    size : int, optional
        As for :func:`shape` / :func:`thesis_object` (same defaults).

    Returns
    -------
    numpy.ndarray, shape (k, 2)
        Corner coordinates (x, y) in px; they lie on :func:`true_outline`.
    """
    corners = _lookup(name, _CORNERS, "shape with known corners")
    if name in _THESIS_BUILDERS:
        size = THESIS_DEFAULT_SIZE[name] if size is None else _check_size(size)
        _, scale, _, _ = _frame(_THESIS_BUILDERS[name], size)
    else:
        size = 128 if size is None else _check_size(size)
        _, scale, _, _ = _frame(_SHAPE_BUILDERS[name], size)
    return corners() * scale


# ----------------------------------------------------------------------------------------------
# Point sets for the SplineEditor demos: designed with y up, delivered in the editor's frame.
# ----------------------------------------------------------------------------------------------


def _heart():
    angle = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    x = 16 * np.sin(angle) ** 3
    y = 13 * np.cos(angle) - 5 * np.cos(2 * angle) - 2 * np.cos(3 * angle) - np.cos(4 * angle)
    return np.c_[x, y] / 4.0


_SAMPLE_POINTS = {
    # an open hand-drawn-looking stroke: a wave with an uneven rhythm (thesis Fig 3.4 style)
    "hand": (False, "open hand-drawn stroke with uneven spacing and a sharp turn (interpolant demos)",
             lambda: np.array([[0.0, 0.0], [1.0, 1.6], [2.2, 2.1], [3.1, 1.2], [3.6, -0.4],
                               [4.8, -1.1], [6.3, -0.2], [6.9, 1.5], [8.4, 2.0], [9.5, 0.6]])),
    # the thesis's 'Pot' control polygon (Fig 3.12): an open vase profile
    "pot": (False, "open 'pot' profile like thesis Fig 3.12 (local-support basis demos)",
            lambda: np.array([[1.0, 0.0], [0.0, 0.0], [0.0, 2.0], [1.2, 3.6], [0.4, 5.0],
                              [1.0, 6.0], [3.0, 6.0], [3.6, 5.0], [2.8, 3.6], [4.0, 2.0],
                              [4.0, 0.0], [3.0, 0.0]])),
    # the thesis's 'Square' (Fig 3.13): a closed square control polygon
    "square": (True, "closed square, 8 points (corners and midpoints), like thesis Fig 3.13",
               lambda: np.array([[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [4.0, 2.0], [4.0, 4.0],
                                 [2.0, 4.0], [0.0, 4.0], [0.0, 2.0]])),
    "heart": (True, "closed heart, 12 points", _heart),
    "zigzag": (False, "open zigzag, 7 points (curvature jumps, Timmer demos)",
               lambda: np.array([[0.0, 0.0], [1.0, 2.0], [2.0, 0.0], [3.0, 2.0], [4.0, 0.0],
                                 [5.0, 2.0], [6.0, 0.0]])),
}

#: Editor demo point sets: name -> one-line description.
SAMPLE_POINTS = {name: entry[1] for name, entry in _SAMPLE_POINTS.items()}


def _editor_frame(points):
    """Map a y-up design into the SplineEditor's default drawing (x right, y down, 620 x 440 px).

    Uniform scale (shapes keep their proportions) into the box [60, 560] x [60, 380].
    """
    low, high = points.min(axis=0), points.max(axis=0)
    span = np.maximum(high - low, 1e-12)
    scale = min(500.0 / span[0], 320.0 / span[1])
    centre = (low + high) / 2
    return np.c_[310.0 + (points[:, 0] - centre[0]) * scale, 220.0 - (points[:, 1] - centre[1]) * scale]


def sample_points(name):
    """A small point set for SplineEditor and notebook demos, in the editor's frame.

    Names: 'hand' (open, uneven hand-drawn stroke), 'pot' (open vase profile, thesis Fig 3.12),
    'square' (closed, thesis Fig 3.13), 'heart' (closed, its tip at the bottom), 'zigzag' (open).
    Use :func:`sample_closed` for whether the set is meant as a closed curve.

    The frame is the editor's (and the bitmaps'): x right, **y down**, the points centred in
    ``[60, 560] x [60, 380]`` (the editor's default 620 x 440 view). The shapes are designed with y up
    and flipped, so they appear upright on screen.

    Returns
    -------
    numpy.ndarray, shape (n, 2), float
        A fresh array; consecutive points distinct.
    """
    design = _lookup(name, _SAMPLE_POINTS, "point set")[2]().astype(float)
    return _editor_frame(design)


def sample_closed(name):
    """True if :func:`sample_points` ``(name)`` describes a closed curve (the editor's ``closed``)."""
    return _lookup(name, _SAMPLE_POINTS, "point set")[0]
