"""The compiled tracer (capture/_cracks.py) against the numpy crack tracer it replaced: same boundaries, same
points, same order, bit for bit, on random bitmaps and all three connectivities.

The reference below is the previous implementation (sorted crack keys, the successor permutation ranked by
pointer jumping, runs paired by a lexsort and scipy's connected components), kept here as an independent
formulation of the same algorithm (docs in splinecraft.capture.contour).
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra.numpy import arrays

from splinecraft.capture import _cracks
from splinecraft.capture.contour import FREEMAN_STEPS, trace_boundaries

_CRACK_STEPS = FREEMAN_STEPS[::2]
_CODE_OF_STEP = np.full(9, -1, dtype=np.int8)
for _code, (_dx, _dy) in enumerate(FREEMAN_STEPS):
    _CODE_OF_STEP[3 * (_dy + 1) + (_dx + 1)] = _code
_LEFT = _CRACK_STEPS[[1, 2, 3, 0]]
_AHEAD_LEFT = (_CRACK_STEPS + _LEFT - 1) // 2
_AHEAD_RIGHT = (_CRACK_STEPS - _LEFT - 1) // 2
_RIGHT_OF_TAIL = _AHEAD_RIGHT
_MINORITY_RADII = (2, 3, 4)


# ------------------------------------------------------------------------------------------ the reference
def _minority_joins_ink(sub, head_x, head_y):
    """At each saddle vertex (padded-frame pixel corner ``(head_x, head_y)``): True when ink is joined
    across it, i.e. ink is not the majority on the first ring that is not balanced (module docstring)."""
    reach = max(_MINORITY_RADII)
    wide = np.pad(sub, reach)                       # padded-frame vertex (X, Y) -> wide pixel rows Y-1+reach-1 ...
    offsets = np.arange(-reach, reach)
    rows = (head_y - 1 + reach - 1)[:, None] + offsets[None, :] + 1
    cols = (head_x - 1 + reach - 1)[:, None] + offsets[None, :] + 1
    window = wide[rows[:, :, None], cols[:, None, :]].astype(np.int16) * 2 - 1      # +1 ink, -1 paper
    decided = np.zeros(len(head_x), bool)
    join = np.ones(len(head_x), bool)
    distance = np.maximum(np.abs(offsets + 0.5)[:, None], np.abs(offsets + 0.5)[None, :]) + 0.5
    for radius in _MINORITY_RADII:
        ring = distance == radius
        balance = window[:, ring].sum(axis=1)
        now = ~decided & (balance != 0)
        join[now] = balance[now] < 0                 # ink is the minority: join it
        decided |= now
    return join


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


def reference_boundaries(mask, connectivity):
    """The previous ``trace_boundaries`` as plain dicts (same crop, padding, order and fields)."""
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    if rows.size == 0:
        return []
    row0, col0 = int(rows[0]), int(cols[0])
    sub = mask[row0:int(rows[-1]) + 1, col0:int(cols[-1]) + 1]
    padded = np.pad(sub, 1)
    keys, row_stride = _crack_keys(padded)
    cracks = _follow_cracks(padded, keys, row_stride, connectivity, sub)
    x, y, d, left_turn, offsets = (cracks[k] for k in ("x", "y", "d", "left_turn", "offsets"))
    n_cycles = offsets.size - 1
    cycle_of = np.repeat(np.arange(n_cycles), np.diff(offsets))
    next_index = np.arange(1, x.size + 1)
    next_index[offsets[1:] - 1] = offsets[:-1]
    x64, y64 = x.astype(np.int64), y.astype(np.int64)
    area2 = np.add.reduceat(x64 * y64[next_index] - x64[next_index] * y64, offsets[:-1])
    chain_col, chain_row, codes, kept_offsets = _pixel_chain(x64, y64, d, left_turn, offsets, connectivity)
    is_hole = area2 < 0
    component = (np.zeros(n_cycles, dtype=np.int64) if int((~is_hole).sum()) == 1
                 else _components(x64, y64, d, cycle_of, is_hole))
    order = np.lexsort((np.arange(n_cycles), is_hole, component))
    offset_x, offset_y = col0 - 1, row0 - 1
    tails = np.column_stack([x64 + offset_x, y64 + offset_y]).astype(float)
    midpoints = tails + 0.5 * _CRACK_STEPS[d]
    centres = np.column_stack([chain_col + offset_x + 0.5, chain_row + offset_y + 0.5])
    result, outer_index = [], {}
    for cycle in order:
        lo, hi, klo, khi = offsets[cycle], offsets[cycle + 1], kept_offsets[cycle], kept_offsets[cycle + 1]
        hole, comp = bool(is_hole[cycle]), int(component[cycle])
        if not hole:
            outer_index[comp] = len(result)
        result.append({
            "pixels": centres[klo:khi], "chain_code": (codes[klo:khi] if khi - klo > 1 else np.zeros(0, np.int8)),
            "outline": midpoints[lo:hi], "crack_vertices": tails[lo:hi], "is_hole": hole,
            "parent": outer_index[comp] if hole else None, "component": comp, "area": int(area2[cycle] // 2)})
    return result


# ------------------------------------------------------------------------------------------ tests
FIELDS = ("pixels", "chain_code", "outline", "crack_vertices", "is_hole", "parent", "component", "area")


def assert_same_boundaries(mask, connectivity):
    expected = reference_boundaries(mask, connectivity)
    found = trace_boundaries(mask, connectivity=connectivity)
    assert len(found) == len(expected)
    for k, (boundary, reference) in enumerate(zip(found, expected)):
        for name in FIELDS:
            value, wanted = getattr(boundary, name), reference[name]
            if isinstance(wanted, np.ndarray):
                assert value.dtype == wanted.dtype and np.array_equal(value, wanted), (k, name)
            else:
                assert value == wanted and type(value) is type(wanted), (k, name)
        assert len(boundary) == len(reference["outline"])
    return found


def crack_fields(mask, connectivity):
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    sub = mask[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1]
    padded = np.pad(sub, 1)
    keys, row_stride = _crack_keys(padded)
    expected = _follow_cracks(padded, keys, row_stride, connectivity, sub)
    found = _cracks.follow_cracks(padded, _cracks.MINORITY if connectivity == "minority" else connectivity)
    return expected, found


@settings(max_examples=80, deadline=None)
@given(mask=arrays(bool, st.tuples(st.integers(1, 24), st.integers(1, 24))),
       connectivity=st.sampled_from(["minority", 4, 8]))
def test_random_bitmaps_bit_for_bit(mask, connectivity):
    assert_same_boundaries(mask, connectivity)


@settings(max_examples=40, deadline=None)
@given(shape=st.tuples(st.integers(5, 60), st.integers(5, 60)), density=st.floats(0.05, 0.95),
       seed=st.integers(0, 2**31 - 1), connectivity=st.sampled_from(["minority", 4, 8]))
def test_random_noise_cracks_in_the_same_order(shape, density, seed, connectivity):
    mask = np.random.default_rng(seed).random(shape) < density
    if not mask.any():
        return
    expected, found = crack_fields(mask, connectivity)
    for name in ("x", "y", "d", "left_turn", "offsets"):
        assert np.array_equal(np.asarray(found[name], np.int64), np.asarray(expected[name], np.int64)), name
    assert_same_boundaries(mask, connectivity)


@pytest.mark.parametrize("connectivity", ["minority", 4, 8])
def test_noise_image_with_many_boundaries(connectivity):
    """A 300 x 300 noise image (a few thousand boundaries, nested holes, saddles everywhere)."""
    mask = np.random.default_rng(7).random((300, 300)) < 0.45
    found = assert_same_boundaries(mask, connectivity)
    assert len(found) > 1000


def test_boundary_arrays_are_read_on_demand_and_settable():
    mask = np.zeros((6, 9), bool)
    mask[1:5, 1:4] = True
    mask[2, 2] = False
    mask[1:3, 6:8] = True
    boundaries = trace_boundaries(mask)
    outer = boundaries[0]
    assert len(outer) == 14  # 3 x 4 pixels: 14 cracks, counted before the outline is read
    assert outer.outline is outer.outline  # made once, then kept
    assert outer.outline.shape == (14, 2)
    replacement = outer.outline[:-2].copy()
    outer.outline = replacement
    assert outer.outline is replacement and len(outer) == 12
    hole = boundaries[1]
    assert hole.is_hole and hole.parent == 0 and hole.area == -1
    assert np.array_equal(hole.crack_vertices, [[2, 2], [2, 3], [3, 3], [3, 2]])


def test_tracer_kernels_are_cached_and_warm_up_runs():
    """The tracer's compiled loops (and the polygons') use numba's on-disk cache, release the GIL, and their
    warm-up covers them without error (the helpers that only compiled loops call have no cache entry of their
    own: their callers' entries hold their code)."""
    from numba.core.registry import CPUDispatcher

    from splinecraft.capture.fitting import budget

    for module, names in ((_cracks, {"_follow_into", "_boundaries_into"}),
                          (budget, {"_turning_into", "_polygons_into"})):
        loops = {name: value for name, value in vars(module).items() if isinstance(value, CPUDispatcher)}
        assert names <= set(loops), sorted(loops)
        for loop in loops.values():
            helper = loop.targetoptions.get("no_cpython_wrapper") is True
            assert loop.targetoptions.get("nogil") is True
            assert loop._cache.__class__.__name__ == ("NullCache" if helper else "FunctionCache"), loop
        module.warm_up()
