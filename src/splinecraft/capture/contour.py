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
2. The successor of every crack is decided at once (numpy) from the two pixels ahead of its head
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
3. The successor permutation splits into cycles (one per boundary); cycle membership and the position
   of each crack in its cycle are found by pointer jumping (``O(E log L)`` for ``E`` cracks and longest
   boundary ``L``, all in numpy), so no Python loop runs over boundary points.
4. The pixel chain is the sequence of ink pixels on the right of consecutive cracks with repeats
   removed; for 4-connectivity the corner pixel is inserted at every left turn so all steps are 4-steps.
5. Components come from the cracks too (no label image): boundaries bounding the same horizontal ink
   run belong to the same component (see :func:`_components`); a hole's ``parent`` is the outer boundary
   of the component around it. Components are numbered like :func:`scipy.ndimage.label` numbers them
   (raster order of their first pixels), which the tests check.

Cost: the image is cropped to the ink's bounding box first. Memory is a few bool copies of the cropped
mask plus about 100 bytes per crack; time is a few full-image numpy passes plus ``O(E log E)`` in the
number of cracks ``E``: an 8000 x 8000 disc (31 200 cracks) traces in about 0.25 s.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._saddle import CONNECTIVITIES, _minority_joins_ink, check_connectivity

__all__ = ["Boundary", "trace_boundaries", "FREEMAN_STEPS", "chain_to_pixels", "CONNECTIVITIES", "check_connectivity"]

#: Freeman code -> (dx, dy) step in the (x right, y down) frame; codes count counter-clockwise on screen.
FREEMAN_STEPS = np.array(
    [[1, 0], [1, -1], [0, -1], [-1, -1], [-1, 0], [-1, 1], [0, 1], [1, 1]], dtype=np.int64
)
# Crack directions 0 = E, 1 = N, 2 = W, 3 = S are the even Freeman codes (crack d <-> Freeman 2d).
_CRACK_STEPS = FREEMAN_STEPS[::2]
# (dx, dy) + 1 -> Freeman code, flattened as 3 * (dy + 1) + (dx + 1); -1 marks the zero step.
_CODE_OF_STEP = np.full(9, -1, dtype=np.int8)
for _code, (_dx, _dy) in enumerate(FREEMAN_STEPS):
    _CODE_OF_STEP[3 * (_dy + 1) + (_dx + 1)] = _code


def _pixel_offsets(vectors):
    """Pixel (col, row) offsets from a vertex for the pixels whose centres are at vertex + vectors/2."""
    return (vectors - 1) // 2


_LEFT = _CRACK_STEPS[[1, 2, 3, 0]]  # left-hand normal of each crack direction (on screen)
# Pixels around the head vertex of a crack in direction d: ahead-left and ahead-right.
_AHEAD_LEFT = _pixel_offsets(_CRACK_STEPS + _LEFT)
_AHEAD_RIGHT = _pixel_offsets(_CRACK_STEPS - _LEFT)
# Ink pixel on the right of a crack, relative to its tail vertex: centre at tail + (D - L) / 2.
_RIGHT_OF_TAIL = _pixel_offsets(_CRACK_STEPS - _LEFT)


@dataclass(eq=False)
class Boundary:
    """One closed boundary (outer or hole) of an ink mask (thesis section 4.1.1; docs/capture.md).

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

    pixels: np.ndarray
    chain_code: np.ndarray
    connectivity: int
    outline: np.ndarray
    crack_vertices: np.ndarray
    is_hole: bool
    parent: int | None
    component: int
    area: int = field(default=0)

    @property
    def start(self) -> tuple:
        """The first pixel centre of the chain ``(x, y)``."""
        return (float(self.pixels[0, 0]), float(self.pixels[0, 1]))

    @property
    def chain_string(self) -> str:
        """The chain code as a string of digits ``'0'..'7'``."""
        return self.chain_code.astype(np.uint8).tobytes().translate(_DIGITS).decode("ascii")

    def __len__(self) -> int:
        return int(self.outline.shape[0])

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
    list of Boundary
        Grouped by component (raster order of each component's first pixel): the outer boundary, then
        its holes (raster order of their first pixels). Empty when the mask has no ink.

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
    padded = np.pad(sub, 1)

    keys, row_stride = _crack_keys(padded)
    cracks = _follow_cracks(padded, keys, row_stride, connectivity, sub)
    del keys
    del padded
    return _build_boundaries(cracks, connectivity, offset=(col0 - 1, row0 - 1))


# ---------------------------------------------------------------------------------------------------
# steps 1-3: cracks, successors, cycles
# ---------------------------------------------------------------------------------------------------
def _crack_keys(padded):
    """Sorted keys ``(Y * (Wp + 1) + X) * 4 + d`` of all cracks (tail vertex (X, Y), direction d).

    Vertex coordinates are in the padded frame (padded pixel (i, j) covers [j, j+1] x [i, i+1]).
    """
    width = padded.shape[1]
    row_stride = width + 1
    flat = padded.reshape(-1)

    def vertex(pixel):  # top-left corner of flat pixel index p = i * width + j -> i * (width + 1) + j
        return pixel + pixel // width

    # Pixel p and the pixel below it (p + width) differ: a horizontal crack.
    upper = np.flatnonzero(flat[width:] != flat[:-width])
    lower = upper + width
    ink_below = flat[lower]
    # E: top edge of an ink pixel under background, tail at its top-left corner;
    # W: bottom edge of an ink pixel over background, tail at its bottom-right corner.
    horizontal = np.where(ink_below, vertex(lower) * 4 + 0, (vertex(lower) + 1) * 4 + 2)
    del upper, lower, ink_below
    # Pixel p and its right neighbour p + 1 differ: a vertical crack (the pair that wraps from one row to
    # the next is two padding pixels, never a crack).
    left = np.flatnonzero(flat[1:] != flat[:-1])
    ink_right = flat[left + 1]
    # N: left edge of an ink pixel right of background, tail at its bottom-left corner;
    # S: right edge of an ink pixel left of background, tail at its top-right corner.
    vertical = np.where(ink_right, (vertex(left + 1) + row_stride) * 4 + 1, (vertex(left) + 1) * 4 + 3)
    del left, ink_right
    keys = np.concatenate([horizontal, vertical]).astype(np.int64, copy=False)
    del horizontal, vertical
    keys.sort()
    return keys, row_stride


def _follow_cracks(padded, keys, row_stride, connectivity, sub=None):
    """Order the cracks into cycles.

    Returns a dict with, in cycle order: tail ``x``, ``y`` (padded frame), direction ``d``, the
    ``left_turn`` flag at the head, cycle ``offsets`` (length cycles + 1).
    """
    count = keys.size
    index_type = np.int32 if count < 2**31 - 1 else np.int64
    direction = (keys & 3).astype(np.int8)
    vertex = keys >> 2
    x = (vertex % row_stride).astype(index_type)
    y = (vertex // row_stride).astype(index_type)
    del vertex

    head_x = x + _CRACK_STEPS[direction, 0].astype(index_type)
    head_y = y + _CRACK_STEPS[direction, 1].astype(index_type)
    ahead_left = padded[head_y + _AHEAD_LEFT[direction, 1], head_x + _AHEAD_LEFT[direction, 0]]
    ahead_right = padded[head_y + _AHEAD_RIGHT[direction, 1], head_x + _AHEAD_RIGHT[direction, 0]]
    if connectivity == 8:
        left_turn = ahead_left
    elif connectivity == 4:
        left_turn = ahead_left & ahead_right
    else:
        left_turn = ahead_left & ahead_right
        saddle = np.flatnonzero(ahead_left & ~ahead_right)
        if saddle.size:
            left_turn[saddle] = _minority_joins_ink(sub, head_x[saddle], head_y[saddle])
    turn = np.where(left_turn, 1, np.where(ahead_right, 0, 3)).astype(np.int8)
    del ahead_left, ahead_right
    next_direction = (direction + turn) & 3
    next_key = (head_y.astype(np.int64) * row_stride + head_x) * 4 + next_direction
    del head_x, head_y, next_direction, turn
    successor = np.searchsorted(keys, next_key).astype(index_type)
    if successor.size and (successor.max() >= count or (keys[successor] != next_key).any()):
        raise RuntimeError("internal error: a crack has no successor (tracer invariant broken)")
    del next_key

    start_of, position, offsets, starts = _cycles(successor)
    del successor
    order = np.empty(count, dtype=index_type)
    cycle = np.searchsorted(starts, start_of)
    order[offsets[cycle] + position] = np.arange(count, dtype=index_type)
    return {
        "x": x[order], "y": y[order], "d": direction[order],
        "left_turn": left_turn[order], "offsets": offsets,
    }


def _cycles(successor):
    """Decompose a permutation into cycles by pointer jumping (vectorized list ranking).

    Returns ``(start_of, position, offsets, starts)``: the smallest index in each element's cycle (the
    cycle's start), the element's distance from that start along the permutation, the cycle offsets in
    the output order (cycles sorted by start index) and the sorted start indices.
    """
    count = successor.size
    ids = np.arange(count, dtype=successor.dtype)
    # Cycle start = minimum index in the cycle. After k rounds, start_of[i] = min over the window of
    # 2^k elements from i. When a round changes nothing, every cycle is shorter than the window
    # (otherwise the window ending just before the minimum would still change), so all are final.
    start_of = ids.copy()
    jump = successor.copy()
    while True:
        candidate = np.minimum(start_of, start_of[jump])
        if np.array_equal(candidate, start_of):
            break
        start_of = candidate
        jump = jump[jump]
    del candidate
    # Distance to the last element of the cycle (the one whose successor is the start).
    is_last = successor == start_of
    to_last = (~is_last).astype(successor.dtype)
    jump = np.where(is_last, ids, successor)
    del is_last
    while True:
        jumped = jump[jump]
        if np.array_equal(jumped, jump):
            break
        to_last += to_last[jump]
        jump = jumped
    del jump, jumped
    length = to_last[start_of] + 1
    position = length - 1 - to_last
    starts = np.flatnonzero(start_of == ids)
    offsets = np.zeros(starts.size + 1, dtype=np.int64)
    np.cumsum(length[starts], out=offsets[1:])
    return start_of, position, offsets, starts


# ---------------------------------------------------------------------------------------------------
# steps 4-5: chains, areas, components
# ---------------------------------------------------------------------------------------------------
def _components(x, y, d, cycle_of, is_hole):
    """Component index of every cycle (outer boundaries numbered in raster order), without a label image.

    In every pixel row the vertical cracks alternate: an N crack starts an ink run, the next S crack ends
    it. Both bound the same run, so their cycles belong to the same component; joining all such pairs
    connects every boundary of a component. (From any hole, the run left of its left-most crack ends at a
    crack of a boundary reaching further left; repeating reaches the outer boundary, which holds the
    component's left-most crack.) Components are then the connected components of this graph
    (:func:`scipy.sparse.csgraph.connected_components`), ``O(E log E)`` for ``E`` cracks.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    vertical = np.flatnonzero(d & 1)
    row = np.where(d[vertical] == 1, y[vertical] - 1, y[vertical])
    order = vertical[np.lexsort((x[vertical], row))]
    starts, ends = order[0::2], order[1::2]
    if not ((d[starts] == 1).all() and (d[ends] == 3).all()):
        raise RuntimeError("internal error: ink runs do not alternate N/S cracks")
    n_cycles = is_hole.size
    graph = coo_matrix(
        (np.ones(starts.size, dtype=np.int8), (cycle_of[starts], cycle_of[ends])), shape=(n_cycles, n_cycles)
    )
    _, group = connected_components(graph, directed=False)
    outer = np.flatnonzero(~is_hole)
    number_of_group = np.full(group.max() + 1, -1, dtype=np.int64)
    number_of_group[group[outer]] = np.arange(outer.size)
    component = number_of_group[group]
    if (component < 0).any():
        raise RuntimeError("internal error: a hole is not connected to an outer boundary")
    return component


def _pixel_chain(x64, y64, d, left_turn, offsets, connectivity):
    """Pixel centres and Freeman codes of every cycle of cracks (thesis section 4.1.1; §10).

    Returns ``(chain_col, chain_row, codes, kept_offsets)``: the chain's pixel columns and rows, the code of
    each step to the next pixel of the same cycle, and the offsets of the cycles in those arrays.
    """
    n_cycles = offsets.size - 1
    # Pixel chain: ink pixel on the right of each crack; 4-connectivity adds the corner at left turns.
    right_col = x64 + _RIGHT_OF_TAIL[d, 0]
    right_row = y64 + _RIGHT_OF_TAIL[d, 1]
    if connectivity == 4:
        emit = 1 + left_turn.astype(np.int64)
        head_x, head_y = x64 + _CRACK_STEPS[d, 0], y64 + _CRACK_STEPS[d, 1]
        corner_col = head_x + _AHEAD_RIGHT[d, 0]
        corner_row = head_y + _AHEAD_RIGHT[d, 1]
        slot = np.cumsum(emit) - emit
        chain_col = np.empty(int(emit.sum()), dtype=np.int64)
        chain_row = np.empty_like(chain_col)
        chain_col[slot], chain_row[slot] = right_col, right_row
        extra = slot[left_turn] + 1
        chain_col[extra], chain_row[extra] = corner_col[left_turn], corner_row[left_turn]
        chain_offsets = np.concatenate([[0], np.cumsum(emit)[offsets[1:] - 1]])
    else:
        chain_col, chain_row, chain_offsets = right_col, right_row, offsets
    chain_next = np.arange(1, chain_col.size + 1)
    chain_next[chain_offsets[1:] - 1] = chain_offsets[:-1]
    # Keep the last pixel of each run of repeats, so every chain starts at the cycle's first pixel.
    keep = (chain_col != chain_col[chain_next]) | (chain_row != chain_row[chain_next])
    kept_per_cycle = np.add.reduceat(keep.astype(np.int64), chain_offsets[:-1])
    keep[chain_offsets[:-1][kept_per_cycle == 0]] = True  # a single pixel: keep one
    kept_per_cycle[kept_per_cycle == 0] = 1
    chain_col, chain_row = chain_col[keep], chain_row[keep]
    kept_offsets = np.zeros(n_cycles + 1, dtype=np.int64)
    np.cumsum(kept_per_cycle, out=kept_offsets[1:])
    kept_next = np.arange(1, chain_col.size + 1)
    kept_next[kept_offsets[1:] - 1] = kept_offsets[:-1]
    step_x = chain_col[kept_next] - chain_col
    step_y = chain_row[kept_next] - chain_row
    if np.abs(step_x).max(initial=0) > 1 or np.abs(step_y).max(initial=0) > 1:
        raise RuntimeError("internal error: pixel chain has a step longer than one pixel")
    codes = _CODE_OF_STEP[3 * (step_y + 1) + (step_x + 1)]
    return chain_col, chain_row, codes, kept_offsets


def _build_boundaries(cracks, connectivity, offset):
    x, y, d, left_turn, offsets = (cracks[k] for k in ("x", "y", "d", "left_turn", "offsets"))
    count = x.size
    n_cycles = offsets.size - 1
    cycle_of = np.repeat(np.arange(n_cycles), np.diff(offsets))
    next_index = np.arange(1, count + 1)
    next_index[offsets[1:] - 1] = offsets[:-1]

    # Exact signed area (shoelace over integer vertices) per cycle.
    x64, y64 = x.astype(np.int64), y.astype(np.int64)
    cross = x64 * y64[next_index] - x64[next_index] * y64
    area2 = np.add.reduceat(cross, offsets[:-1]) if count else np.zeros(0, np.int64)
    del cross

    chain_col, chain_row, codes, kept_offsets = _pixel_chain(x64, y64, d, left_turn, offsets, connectivity)

    # Components: cycles that bound the same horizontal ink run belong to the same component.
    is_hole = area2 < 0
    n_outer = int((~is_hole).sum())
    if n_outer == 1:
        component = np.zeros(n_cycles, dtype=np.int64)
    else:
        component = _components(x64, y64, d, cycle_of, is_hole)
    del cycle_of

    # Order: by component, outer boundary first, then holes; cycles are already in raster order.
    order = np.lexsort((np.arange(n_cycles), is_hole, component))
    offset_x, offset_y = offset
    tails = np.column_stack([x64 + offset_x, y64 + offset_y]).astype(float)
    midpoints = tails + 0.5 * _CRACK_STEPS[d]
    centres = np.column_stack([chain_col + offset_x + 0.5, chain_row + offset_y + 0.5])

    boundaries = []
    outer_index = {}
    for cycle in order:
        lo, hi = offsets[cycle], offsets[cycle + 1]
        klo, khi = kept_offsets[cycle], kept_offsets[cycle + 1]
        hole = bool(is_hole[cycle])
        comp = int(component[cycle])
        chain = codes[klo:khi] if khi - klo > 1 else np.zeros(0, dtype=np.int8)
        if not hole:
            outer_index[comp] = len(boundaries)
        boundaries.append(
            Boundary(
                pixels=centres[klo:khi].copy(),
                chain_code=chain.astype(np.int8),
                connectivity=connectivity,
                outline=midpoints[lo:hi].copy(),
                crack_vertices=tails[lo:hi].copy(),
                is_hole=hole,
                parent=outer_index[comp] if hole else None,
                component=comp,
                area=int(area2[cycle] // 2),
            )
        )
    return boundaries
