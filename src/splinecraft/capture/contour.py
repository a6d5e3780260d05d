"""Chain-code boundary tracing: bool ink mask -> outer boundaries and holes (thesis section 4.1.1).

The thesis encodes the boundary of the planar object as a Freeman chain code, 4- or 8-connected, found
from a start point chosen by a horizontal (raster) scan. This module traces every boundary of every
component -- outer boundaries and holes -- and returns for each

* the Freeman chain of boundary **pixel centres** (what Moore-neighbour tracing produces for
  8-connectivity; a chain of 4-steps for 4-connectivity) with its chain code, and
* the **crack outline**: the unit pixel edges between ink and background, as their midpoints
  (the input of corner detection and fitting; the true outline lies within about 0.5 px of it).

Frame and conventions (docs/capture.md)
------------------------------------------
x right, y down, pixel (row ``r``, col ``c``) covers ``[c, c+1] x [r, r+1]``; pixel centres at
``(c + 0.5, r + 0.5)``. Freeman code ``k`` is the step at ``45 k`` degrees counter-clockwise *as seen
on screen*: 0 = E ``(+1, 0)``, 1 = NE ``(+1, -1)``, 2 = N ``(0, -1)``, 3 = NW, 4 = W, 5 = SW, 6 = S
``(0, +1)``, 7 = SE (N is up, i.e. ``-y``). Every boundary keeps the ink on its right-hand side (on
screen), so outer boundaries have positive shoelace area in the (x, y-down) frame and holes negative.
Each boundary starts at its top-most, then left-most crack vertex (the raster scan of the thesis): an
outer boundary at the top-left corner of its first ink pixel heading E, a hole heading S.

Algorithm (crack following, the pixel-edge form of Moore-neighbour tracing)
---------------------------------------------------------------------------
1. Every ink/background pixel edge becomes a directed unit *crack* with the ink on its right.
2. The successor of every crack is decided from the two pixels ahead of its head
   vertex -- ahead-left ``AL`` and ahead-right ``AR`` -- which is Moore's clockwise neighbour scan
   reduced to its four outcomes: turn left if ``AL`` is ink (8-connectivity; 4-connectivity needs
   ``AL`` and ``AR``), go straight if ``AR`` is ink, else turn right. The only ambiguous case, the
   diagonal "saddle" (``AL`` ink, ``AR`` background: two ink pixels and two background pixels touching
   only at their corners), is thereby resolved by the connectivity: 8-connected ink joins diagonal pixels,
   4-connected ink keeps them apart (and the background gets the complementary connectivity).
   ``connectivity="minority"`` decides every saddle on its own, by the *minority rule* (potrace's default
   turn policy): the colour that is rarer around the saddle is the one joined across it. The count is
   taken on the square rings of side 4, 6 and 8 pixels centred on the saddle's vertex, the first ring
   whose ink and background counts differ deciding (all equal: ink is joined). A thin dark stroke
   (ink rare) stays one piece, and a thin light gap between two ink areas (paper rare) stays open, so
   neither a hairline nor the pinhole where two strokes touch at a corner makes an extra outline: on
   rendered glyphs of many sizes and rotations this matches the true number of contours far more often
   than either fixed connectivity (BENCHMARKS.md, "Contours"). Both boundaries through a saddle see the
   same decision (it depends on the vertex only), so the cycles stay consistent.
3. The successor permutation splits into cycles (one per boundary). One compiled raster pass
   (:mod:`splinecraft.capture._cracks`) visits the pixel corners row by row and, at each, the crack directions
   E, N, W, S; every crack not yet visited starts a cycle, followed to its end. So the boundaries come in the
   order of their first cracks in raster order, each starting there, and no Python loop runs over boundaries
   or points.
4. The pixel chain is the sequence of ink pixels on the right of consecutive cracks with repeats
   removed; for 4-connectivity the corner pixel is inserted at every left turn so all steps are 4-steps.
5. Components come from the cracks too (no label image): in every pixel row the vertical cracks alternate,
   an N crack starting an ink run and the next S crack ending it; both bound the same run, so their cycles
   belong to the same component (union-find over the cycles). From any hole, the run left of its left-most
   crack ends at a crack of a boundary reaching further left; repeating reaches the outer boundary, so every
   boundary of a component is joined. A hole's ``parent`` is the outer boundary of the component around it.
   Components are numbered like :func:`scipy.ndimage.label` numbers them (raster order of their first
   pixels), which the tests check.

Cost: the image is cropped to the ink's bounding box first. Memory is one byte per pixel corner (the visited
crack directions) plus about 60 bytes per crack; time is linear in the pixels and cracks (steps 2-5 are
compiled: numba, cached on disk). The :class:`Boundary` objects share the tracer's arrays and slice their own
on first access, so a bitmap of noise with 200 000 boundaries makes no 200 000 array copies up front
(BENCHMARKS.md, "Speed (issue 9)").
"""
from __future__ import annotations

import numpy as np

from ._cracks import FREEMAN_STEPS, MINORITY, boundary_arrays, follow_cracks
from ._lazy import LazyList
from ._saddle import CONNECTIVITIES, check_connectivity

__all__ = ["Boundary", "Boundaries", "trace_boundaries", "hole_boxes", "FREEMAN_STEPS", "chain_to_pixels", "CONNECTIVITIES", "check_connectivity"]

_CRACK_STEPS = FREEMAN_STEPS[::2]  # crack directions 0 E, 1 N, 2 W, 3 S are the even Freeman codes


class _StoreArray:
    """An array attribute of :class:`Boundary`: the value set, else the slice of the tracer's shared arrays,
    made on first read and kept (slot ``_<name>``)."""

    def __set_name__(self, owner, name):
        self.name, self.slot = name, "_" + name

    def __get__(self, boundary, owner=None):
        if boundary is None:
            return self
        value = getattr(boundary, self.slot)
        if value is None:
            value = getattr(boundary._store, self.name)(boundary._cycle)
            setattr(boundary, self.slot, value)
        return value

    def __set__(self, boundary, value):
        setattr(boundary, self.slot, value)


class Boundary:
    """One closed boundary (outer or hole) of an ink mask (thesis section 4.1.1; docs/capture.md).

    Those of :func:`trace_boundaries` hold views of the tracer's shared arrays, sliced when an array attribute
    is first read (then kept; assigning one replaces it); ``Boundary(...)`` takes the arrays themselves.

    Attributes
    ----------
    pixels : ndarray (n, 2) float
        Freeman chain of boundary pixel centres ``(c + 0.5, r + 0.5)``, closed, first point not repeated.
        A single-pixel component has ``n = 1``.
    chain_code : ndarray (n,) int8
        Freeman codes (see module docstring) from ``pixels[i]`` to ``pixels[(i + 1) % n]``; only even
        codes for 4-connectivity; empty for a single pixel (there is no step).
    connectivity : int or str
        4 or 8: connectivity of the ink (the background has the other one); ``"minority"``: decided per
        diagonal contact by the minority rule (module docstring).
    outline : ndarray (m, 2) float
        Crack outline: midpoints of the unit pixel edges between ink and background, in order, closed,
        first point not repeated; ``m >= 4`` (a single pixel gives its 4 edge midpoints).
    crack_vertices : ndarray (m, 2) float
        Pixel corners (integer coordinates) where the cracks start: crack ``i`` runs from
        ``crack_vertices[i]`` to ``crack_vertices[(i + 1) % m]`` and ``outline[i]`` is its midpoint.
    is_hole : bool
        True for the boundary of a hole (background enclosed by ink).
    parent : int or None
        For a hole, the index (in the list returned by :func:`trace_boundaries`) of the outer boundary of
        the component around it; ``None`` for outer boundaries.
    component : int
        0-based index of the ink component (in raster order of the components' first pixels).
    area : int
        Signed shoelace area of the crack polygon ``crack_vertices``: exactly the number of pixels it
        encloses, positive for outer boundaries (ink on the right in the y-down frame), negative for holes.
    """

    __slots__ = ("_pixels", "_chain_code", "_outline", "_crack_vertices", "_store", "_cycle", "connectivity",
                 "is_hole", "parent", "component", "area")

    def __init__(self, pixels, chain_code, connectivity, outline, crack_vertices, is_hole, parent, component,
                 area=0):
        self._pixels, self._chain_code, self._outline, self._crack_vertices = pixels, chain_code, outline, \
            crack_vertices
        self._store, self._cycle = None, -1
        self.connectivity, self.is_hole, self.parent, self.component, self.area = (connectivity, is_hole, parent,
                                                                                   component, area)

    @classmethod
    def _from_store(cls, store, cycle, connectivity, is_hole, parent, component, area):
        """A boundary whose arrays are views of the tracer's shared arrays, made on first access."""
        boundary = cls.__new__(cls)
        boundary._pixels = boundary._chain_code = boundary._outline = boundary._crack_vertices = None
        boundary._store, boundary._cycle = store, cycle
        boundary.connectivity, boundary.is_hole, boundary.parent, boundary.component, boundary.area = (
            connectivity, is_hole, parent, component, area)
        return boundary

    pixels = _StoreArray()
    chain_code = _StoreArray()
    outline = _StoreArray()
    crack_vertices = _StoreArray()

    @property
    def start(self) -> tuple:
        """The first pixel centre of the chain ``(x, y)``."""
        return (float(self.pixels[0, 0]), float(self.pixels[0, 1]))

    @property
    def chain_string(self) -> str:
        """The chain code as a string of digits ``'0'..'7'``."""
        return self.chain_code.astype(np.uint8).tobytes().translate(_DIGITS).decode("ascii")

    def __len__(self) -> int:
        if self._outline is None:
            return self._store.length(self._cycle)
        return int(self._outline.shape[0])

    def __repr__(self) -> str:
        kind = "hole" if self.is_hole else "outer"
        return (
            f"Boundary({kind}, component={self.component}, parent={self.parent}, "
            f"connectivity={self.connectivity}, pixels={len(self.pixels)}, outline={len(self.outline)}, "
            f"area={self.area}, start={self.start})"
        )


_DIGITS = bytes.maketrans(bytes(range(8)), b"01234567")


def chain_to_pixels(start, chain_code) -> np.ndarray:
    """Decode a Freeman chain: the points ``start, start + step(c_0), ...`` (one per code, closed chains
    return to ``start`` after the last code, which is therefore not repeated).

    Parameters
    ----------
    start : (2,) array_like
        First point ``(x, y)``.
    chain_code : (n,) array_like of int in 0..7

    Returns
    -------
    ndarray (max(n, 1), 2) float
    """
    codes = np.asarray(chain_code)
    if codes.ndim != 1:
        raise ValueError(f"chain_code must be 1-D, got shape {codes.shape}")
    if codes.size and (codes.dtype.kind not in "iu" or codes.min() < 0 or codes.max() > 7):
        raise ValueError("chain_code entries must be integers in 0..7")
    start = np.asarray(start, dtype=float).reshape(2)
    steps = FREEMAN_STEPS[codes.astype(np.int64)]
    points = np.vstack([start, start + np.cumsum(steps, axis=0)])
    return points[:-1] if codes.size else points


def _as_mask(mask) -> np.ndarray:
    array = np.asarray(mask)
    if array.dtype != bool:
        if array.dtype.kind not in "iuf":
            raise TypeError(f"mask must be a bool array (True = ink), got dtype {array.dtype}")
        if array.size and not np.isin(array, (0, 1)).all():
            raise ValueError("mask must be bool or hold only 0 and 1 (True/1 = ink)")
        array = array.astype(bool)
    if array.ndim != 2:
        raise ValueError(f"mask must be 2-D (H, W), got shape {array.shape}")
    if array.shape[0] == 0 or array.shape[1] == 0:
        raise ValueError(f"mask is empty (shape {array.shape})")
    return array


def trace_boundaries(mask, *, connectivity=8) -> list:
    """Trace all outer boundaries and holes of an ink mask (thesis section 4.1.1; docs/capture.md).

    Parameters
    ----------
    mask : (H, W) array_like of bool
        ``True`` = ink. 0/1 integer or float arrays are accepted.
    connectivity : {8, 4, "minority"}
        Connectivity of the ink components: 8 joins diagonal neighbours (Moore neighbourhood), 4 only
        edge neighbours; holes use the complementary connectivity. ``"minority"`` joins, at each diagonal
        contact, the colour that is rarer around it (module docstring).

    Returns
    -------
    Boundaries (a list-like sequence of Boundary; ``[]`` when the mask has no ink)
        Grouped by component (raster order of each component's first pixel): the outer boundary, then
        its holes (raster order of their first pixels). The objects are made on first access; their scalar
        attributes are also arrays of the sequence (:class:`Boundaries`).

    Raises
    ------
    TypeError, ValueError
        For a non-2-D, empty or non-binary mask, or a connectivity other than 4, 8 or "minority".
    """
    connectivity = check_connectivity(connectivity)
    mask = _as_mask(mask)

    rows = np.flatnonzero(mask.any(axis=1))
    if rows.size == 0:
        return []
    cols = np.flatnonzero(mask.any(axis=0))
    row0, col0 = int(rows[0]), int(cols[0])
    sub = mask[row0:int(rows[-1]) + 1, col0:int(cols[-1]) + 1]
    padded = np.zeros((sub.shape[0] + 2, sub.shape[1] + 2), dtype=sub.dtype)  # np.pad(sub, 1), without its overhead
    padded[1:-1, 1:-1] = sub

    cracks = follow_cracks(padded, MINORITY if connectivity == "minority" else connectivity)
    return _build_boundaries(cracks, connectivity, offset=(col0 - 1, row0 - 1), shape=padded.shape)


# ---------------------------------------------------------------------------------------------------
# steps 4-5: chains, areas, components
# ---------------------------------------------------------------------------------------------------
def _build_boundaries(cracks, connectivity, offset, shape):
    """The :class:`Boundary` list of the cracks of a padded mask of ``shape`` (steps 4-5, compiled in
    :func:`~splinecraft.capture._cracks.boundary_arrays`): grouped by component, outer boundary first."""
    arrays = boundary_arrays(cracks, shape[1], shape[0], connectivity == 4, offset)
    area2, is_hole, component = arrays["area2"], arrays["is_hole"], arrays["component"]
    n_cycles = area2.shape[0]
    # Order: by component, outer boundary first, then holes; cycles are already in raster order.
    order = np.lexsort((np.arange(n_cycles), is_hole, component))
    store = _BoundaryStore(cracks["x"], cracks["y"], cracks["offsets"], arrays["midpoints"], arrays["centres"],
                           arrays["codes"], arrays["kept_offsets"], offset)
    # The parent of a hole: the position in ``order`` of its component's outer boundary (the first of its group).
    position = np.empty(n_cycles, dtype=np.int64)
    position[order] = np.arange(n_cycles)
    outer_position = np.zeros(int(component.max(initial=-1)) + 1, dtype=np.int64)
    outer_position[component[~is_hole]] = position[~is_hole]
    parent = np.where(is_hole, outer_position[component], -1)
    return Boundaries(store, order, is_hole[order], parent[order], component[order], area2[order] // 2,
                      connectivity)


class Boundaries(LazyList):
    """The boundaries of one :func:`trace_boundaries` call: a list of :class:`Boundary` (indexing, slicing,
    iteration, ``len``, comparison with a list), each made on first access, and their scalar attributes as
    arrays in the same order (``is_hole``, ``parent`` (-1 for outer boundaries), ``component``, ``area``,
    ``lengths`` = contour points of each crack outline). A bitmap of noise has 10^5 boundaries; code that needs
    one attribute of all of them reads the array instead of making every object."""

    def __init__(self, store, cycles, is_hole, parent, component, area, connectivity):
        super().__init__([None] * cycles.shape[0], self._boundary)
        self._store, self._cycles, self._connectivity = store, cycles, connectivity
        self.is_hole, self.parent, self.component, self.area = is_hole, parent, component, area
        self.lengths = np.diff(store.offsets_array)[cycles]

    def _boundary(self, k) -> Boundary:
        hole = bool(self.is_hole[k])
        return Boundary._from_store(self._store, int(self._cycles[k]), self._connectivity, hole,
                                    int(self.parent[k]) if hole else None, int(self.component[k]), int(self.area[k]))

    def __repr__(self) -> str:
        holes = int(self.is_hole.sum())
        return f"Boundaries({len(self)} boundaries: {len(self) - holes} outer, {holes} holes)"

    def outlines(self) -> list:
        """The crack outline of every boundary (``self[k].outline``, the same arrays), without making the
        :class:`Boundary` objects."""
        midpoints, offsets = self._store.midpoints, self._store.offsets
        return [midpoints[offsets[cycle]:offsets[cycle + 1]] if boundary is None else boundary.outline
                for cycle, boundary in zip(self._cycles.tolist(), self._items)]

    def hole_boxes(self, max_area) -> np.ndarray:
        """``(x0, y0, x1, y1)`` of the crack vertices of every hole enclosing fewer than ``max_area`` pixels, as an
        ``(k, 4)`` int array (image frame)."""
        chosen = np.flatnonzero(self.is_hole & (-self.area < max_area))
        return self._store.boxes(self._cycles[chosen])

    def speck_boxes(self, max_area) -> np.ndarray:
        """``(x0, y0, x1, y1)`` of the crack vertices of every outer boundary enclosing fewer than ``max_area``
        pixels (an ink speck), as an ``(k, 4)`` int array (image frame)."""
        chosen = np.flatnonzero(~self.is_hole & (self.area < max_area))
        return self._store.boxes(self._cycles[chosen])


def speck_boxes(boundaries, max_area) -> np.ndarray:
    """The crack boxes ``(x0, y0, x1, y1)`` of the outer boundaries among ``boundaries`` (:class:`Boundaries` or
    any list of :class:`Boundary`) that enclose fewer than ``max_area`` pixels, an ``(k, 4)`` int array."""
    if isinstance(boundaries, Boundaries):
        return boundaries.speck_boxes(max_area)
    boxes = [np.concatenate([np.asarray(b.crack_vertices).min(axis=0), np.asarray(b.crack_vertices).max(axis=0)])
             for b in boundaries if not b.is_hole and int(b.area) < max_area]
    return np.array(boxes, dtype=np.int64).reshape(-1, 4)


def hole_boxes(boundaries, max_area) -> np.ndarray:
    """The crack boxes ``(x0, y0, x1, y1)`` of the holes among ``boundaries`` (:class:`Boundaries` or any list of
    :class:`Boundary`) that enclose fewer than ``max_area`` pixels, an ``(k, 4)`` int array."""
    if isinstance(boundaries, Boundaries):
        return boundaries.hole_boxes(max_area)
    boxes = [np.concatenate([np.asarray(b.crack_vertices).min(axis=0), np.asarray(b.crack_vertices).max(axis=0)])
             for b in boundaries if b.is_hole and -int(b.area) < max_area]
    return np.array(boxes, dtype=np.int64).reshape(-1, 4)


class _BoundaryStore:
    """The arrays of all boundaries of one :func:`trace_boundaries` call, in cycle order; a boundary's arrays
    are slices of them, made when first read (so a bitmap of noise with 10^5 boundaries costs no 10^5 array
    copies)."""

    __slots__ = ("x", "y", "offsets", "offsets_array", "midpoints", "centres", "codes", "kept_offsets", "offset")

    def __init__(self, x, y, offsets, midpoints, centres, codes, kept_offsets, offset):
        self.x, self.y, self.offsets_array, self.offset = x, y, offsets, offset
        self.offsets = offsets.tolist()
        self.midpoints, self.centres = midpoints, centres
        self.codes = codes.astype(np.int8, copy=False)
        self.kept_offsets = kept_offsets.tolist()

    def boxes(self, cycles) -> np.ndarray:
        """``(x0, y0, x1, y1)`` of the crack vertices of each of ``cycles`` (image frame)."""
        if not cycles.shape[0]:
            return np.zeros((0, 4), dtype=np.int64)
        starts = self.offsets_array[:-1]
        box = np.column_stack([np.minimum.reduceat(self.x, starts)[cycles], np.minimum.reduceat(self.y, starts)[cycles],
                               np.maximum.reduceat(self.x, starts)[cycles], np.maximum.reduceat(self.y, starts)[cycles]])
        return box.astype(np.int64) + np.array(self.offset * 2, dtype=np.int64)

    def length(self, cycle) -> int:
        return self.offsets[cycle + 1] - self.offsets[cycle]

    def outline(self, cycle) -> np.ndarray:
        return self.midpoints[self.offsets[cycle]:self.offsets[cycle + 1]]

    def crack_vertices(self, cycle) -> np.ndarray:
        lo, hi = self.offsets[cycle], self.offsets[cycle + 1]
        offset_x, offset_y = self.offset
        return np.column_stack([self.x[lo:hi].astype(np.int64) + offset_x,
                                self.y[lo:hi].astype(np.int64) + offset_y]).astype(float)

    def pixels(self, cycle) -> np.ndarray:
        return self.centres[self.kept_offsets[cycle]:self.kept_offsets[cycle + 1]]

    def chain_code(self, cycle) -> np.ndarray:
        lo, hi = self.kept_offsets[cycle], self.kept_offsets[cycle + 1]
        return self.codes[lo:hi] if hi - lo > 1 else np.zeros(0, dtype=np.int8)
