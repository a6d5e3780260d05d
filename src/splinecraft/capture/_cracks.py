"""Compiled crack following: every boundary of a padded ink mask in one raster pass (the algorithm of
:mod:`splinecraft.capture.contour`, steps 1-3; docs/capture.md §10).

The raster scan visits the pixel corners (vertices) row by row, left to right, and at each vertex the crack
directions E, N, W, S in this order: the order of the keys ``(Y * (W + 1) + X) * 4 + d`` of the contour
module. Only the vertices whose 2 x 2 pixels are not all alike are visited (numpy finds them: no crack starts
elsewhere). The first crack of a boundary met that way is its smallest key, so starting a cycle at every crack
not yet visited and following successors until it closes lists the boundaries in the order of their first
cracks, each from that crack, exactly as sorting the keys and ranking the successor permutation does. Memory:
a byte per vertex for the visited directions and one for the vertices to visit, the index of each vertex to
visit, and the per-crack output. numba, compiled on first use and cached on disk (``cache=True``,
:mod:`splinecraft.capture._jit`).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from ._jit import HELPER_OPTIONS as _HELPER, JIT_OPTIONS, compact, union_join, union_root as _root

__all__ = ["FREEMAN_STEPS", "follow_cracks", "boundary_arrays", "MINORITY", "warm_up"]

#: ``connectivity`` code of the minority rule in :func:`follow_cracks` (4 and 8 stand for themselves).
MINORITY = 0

#: Freeman code -> (dx, dy) step in the (x right, y down) frame; codes count counter-clockwise on screen
#: (re-exported by :mod:`splinecraft.capture.contour`).
FREEMAN_STEPS = np.array(
    [[1, 0], [1, -1], [0, -1], [-1, -1], [-1, 0], [-1, 1], [0, 1], [1, 1]], dtype=np.int64
)
# Crack directions 0 = E, 1 = N, 2 = W, 3 = S are the even Freeman codes (crack d <-> Freeman 2d).
_CRACK_STEPS = FREEMAN_STEPS[::2]
_LEFT = _CRACK_STEPS[[1, 2, 3, 0]]  # left-hand normal of each crack direction (on screen)
# (column, row) offsets from a vertex of the pixels whose centres are at vertex + vector / 2: ahead-left and
# ahead-right of the head vertex of a crack of each direction. The ink pixel right of a crack sits at the
# ahead-right offset from its tail (centre at tail + (D - L) / 2).
_AHEAD_LEFT_X, _AHEAD_LEFT_Y = ((_CRACK_STEPS + _LEFT - 1) // 2).T.copy()
_AHEAD_RIGHT_X, _AHEAD_RIGHT_Y = ((_CRACK_STEPS - _LEFT - 1) // 2).T.copy()
_STEP_X, _STEP_Y = _CRACK_STEPS.T.copy()
# (dx, dy) + 1 -> Freeman code, flattened as 3 * (dy + 1) + (dx + 1); -1 marks the zero step.
_CODE_OF_STEP = np.full(9, -1, dtype=np.int8)
_CODE_OF_STEP[3 * (FREEMAN_STEPS[:, 1] + 1) + (FREEMAN_STEPS[:, 0] + 1)] = np.arange(8)


@njit(**_HELPER)
def _ink(padded, row, col):
    """1 for an ink pixel, 0 for paper and for pixels outside the array."""
    if row < 0 or col < 0 or row >= padded.shape[0] or col >= padded.shape[1]:
        return 0
    return 1 if padded[row, col] else 0


@njit(**_HELPER)
def _starts_at(padded, vertex_x, vertex_y):
    """Bit ``d`` set when a crack of direction ``d`` has its tail at the vertex (ink on its right)."""
    up_left = _ink(padded, vertex_y - 1, vertex_x - 1)
    up_right = _ink(padded, vertex_y - 1, vertex_x)
    down_left = _ink(padded, vertex_y, vertex_x - 1)
    down_right = _ink(padded, vertex_y, vertex_x)
    return ((down_right & (1 - up_right)) | ((up_right & (1 - up_left)) << 1)
            | ((up_left & (1 - down_left)) << 2) | ((down_left & (1 - down_right)) << 3))


@njit(**JIT_OPTIONS)
def _follow_into(padded, connectivity, starts, visited, tail_x, tail_y, direction, left_turn, offsets):
    """Fill the per-crack arrays in cycle order (``visited``: zeros, one byte per vertex); returns the number of
    cycles, or -1 when a crack has no successor (the tracer's invariant broken). ``starts``: the flat indices
    ``Y * (W + 1) + X`` of the vertices where a crack may start, ascending (raster order): those whose 2 x 2
    pixels are not all alike (:func:`follow_cracks`); no crack has its tail anywhere else."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    written = np.int64(0)
    cycles = np.int64(0)
    height, width = padded.shape
    for start in starts:
        vertex_y, vertex_x = start // (width + 1), start % (width + 1)
        starting = _starts_at(padded, vertex_x, vertex_y) & ~visited[vertex_y, vertex_x]
        for first in range(4):
            if not (starting >> first) & 1 or (visited[vertex_y, vertex_x] >> first) & 1:
                continue
            offsets[cycles] = written
            cycles += 1
            x, y, d = vertex_x, vertex_y, first
            while True:
                if written >= tail_x.shape[0] or not (_starts_at(padded, x, y) >> d) & 1:
                    return -1
                visited[y, x] |= np.uint8(1 << d)
                head_x, head_y = x + _STEP_X[d], y + _STEP_Y[d]
                # Does the boundary turn left at the head vertex? (ahead-right ink: it goes straight on.)
                ahead_left = _ink(padded, head_y + _AHEAD_LEFT_Y[d], head_x + _AHEAD_LEFT_X[d])
                ahead_right = _ink(padded, head_y + _AHEAD_RIGHT_Y[d], head_x + _AHEAD_RIGHT_X[d]) == 1
                if connectivity == 8:
                    left = ahead_left == 1
                elif ahead_left == 1 and not ahead_right and connectivity == MINORITY:
                    # The minority rule at the saddle (contour module, step 2): on the square rings of
                    # side 4, 6 and 8 pixels centred on the head vertex, the first whose ink and paper
                    # counts differ decides; ink is joined when it is not the majority there (all rings
                    # balanced: joined). Ring ``radius``: the offsets -radius..radius-1 with a first or
                    # last one on either axis.
                    left = True
                    for radius in range(2, 5):
                        balance = np.int64(0)
                        for row_offset in range(-radius, radius):
                            edge_row = row_offset == -radius or row_offset == radius - 1
                            step = 1 if edge_row else 2 * radius - 1
                            for col_offset in range(-radius, radius, step):
                                balance += 2 * _ink(padded, head_y + row_offset, head_x + col_offset) - 1
                        if balance != 0:
                            left = balance < 0
                            break
                else:
                    left = ahead_left == 1 and ahead_right
                tail_x[written], tail_y[written], direction[written] = x, y, d
                left_turn[written] = left
                written += 1
                d = (d + (1 if left else (0 if ahead_right else 3))) & 3
                x, y = head_x, head_y
                if x == vertex_x and y == vertex_y and d == first:
                    break
                if (visited[y, x] >> d) & 1:
                    return -1
    offsets[cycles] = written
    return cycles


def follow_cracks(padded, connectivity):
    """The cracks of ``padded`` (a bool mask with a background border) in cycle order.

    ``connectivity`` is 4, 8 or :data:`MINORITY`. Returns a dict of the tail ``x``, ``y`` (int32, padded frame:
    pixel (i, j) covers [j, j+1] x [i, i+1]), direction ``d`` (int8), the ``left_turn`` flag at the head and the
    cycle ``offsets`` (int64, length cycles + 1).
    """
    padded = np.ascontiguousarray(padded, dtype=np.bool_)
    # A crack lies between every two unlike neighbours. A vertex starts cracks only where its 2 x 2 pixels are
    # not all alike, and then two or four of the four pairs around it differ (an even number: going round the
    # four pixels returns to the first), so any three of the pairs tell. The padded mask's border is
    # background: no crack touches the outer vertices.
    unlike_below, unlike_right = padded[1:] != padded[:-1], padded[:, 1:] != padded[:, :-1]
    count = int(np.count_nonzero(unlike_below)) + int(np.count_nonzero(unlike_right))
    mixed = np.zeros((padded.shape[0] + 1, padded.shape[1] + 1), dtype=np.bool_)
    np.logical_or(unlike_right[1:], unlike_right[:-1], out=mixed[1:-1, 1:-1])
    mixed[1:-1, 1:-1] |= unlike_below[:, 1:]
    starts = np.flatnonzero(mixed)
    tail_x = np.empty(count, dtype=np.int32)
    tail_y = np.empty(count, dtype=np.int32)
    direction = np.empty(count, dtype=np.int8)
    left_turn = np.empty(count, dtype=np.bool_)
    offsets = np.empty(count + 1, dtype=np.int64)
    visited = np.zeros((padded.shape[0] + 1, padded.shape[1] + 1), dtype=np.uint8)
    cycles = _follow_into(padded, int(connectivity), starts, visited, tail_x, tail_y, direction, left_turn, offsets)
    if cycles < 0:
        raise RuntimeError("internal error: a crack has no successor (tracer invariant broken)")
    return {"x": tail_x, "y": tail_y, "d": direction, "left_turn": left_turn, "offsets": offsets[:cycles + 1].copy()}


@njit(**JIT_OPTIONS)
def _boundaries_into(tail_x, tail_y, direction, left_turn, offsets, four, offset_x, offset_y, area2, is_hole,
                     buffer_col, buffer_row, chain_col, chain_row, codes, kept_offsets, row_start, fill, filed, cycle_of,
                     parent, run_cycle, run_kind, number_of_root, component, midpoints, centres):
    """Steps 4-5 of the contour module for every cycle of :func:`follow_cracks`, in one kernel (each kernel
    costs its own compile and Python wrapper): twice its signed shoelace area and whether it is a hole; its pixel
    chain; its component; the crack midpoints and the chain's pixel centres. Returns the number of chain
    pixels, -1 when a chain step is longer than one pixel, -2 when the ink runs do not alternate or a group has
    no outer cycle (the tracer's invariants broken).

    The chain (step 4): the ink pixel on the right of each crack (and, for 4-connectivity, the corner pixel
    ahead-right at each left turn), the last of each run of repeats kept (one pixel where all are equal), and
    the Freeman code of each step to the next kept pixel (``buffer_*``: room for the longest cycle's pixels).
    The component (step 5): in every pixel row an N crack starts an ink run and the next S crack to its right
    ends it; the cycles of both are joined (union-find); components are numbered in the order of their outer
    cycles. ``row_start`` .. ``number_of_root`` are the scratch arrays of :func:`_component_work` (separate
    arguments: a tuple of arrays costs compile time). Midpoints: tail + half a step; centres: pixel + 1/2; both
    in the image frame (``offset_*`` = the padded frame's origin there)."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    n_cycles = offsets.shape[0] - 1
    # twice the signed shoelace area of every cycle of crack tails (integers: exact)
    for cycle in range(n_cycles):
        lo, hi = offsets[cycle], offsets[cycle + 1]
        total = np.int64(0)
        for i in range(lo, hi):
            j = i + 1 if i + 1 < hi else lo
            total += np.int64(tail_x[i]) * tail_y[j] - np.int64(tail_x[j]) * tail_y[i]
        area2[cycle] = total
        is_hole[cycle] = total < 0
    # the pixel chains
    kept = np.int64(0)
    kept_offsets[0] = 0
    for cycle in range(n_cycles):
        emitted = np.int64(0)
        for i in range(offsets[cycle], offsets[cycle + 1]):
            d = direction[i]
            buffer_col[emitted] = tail_x[i] + _AHEAD_RIGHT_X[d]  # the pixel right of the tail
            buffer_row[emitted] = tail_y[i] + _AHEAD_RIGHT_Y[d]
            emitted += 1
            if four and left_turn[i]:
                buffer_col[emitted] = tail_x[i] + _STEP_X[d] + _AHEAD_RIGHT_X[d]
                buffer_row[emitted] = tail_y[i] + _STEP_Y[d] + _AHEAD_RIGHT_Y[d]
                emitted += 1
        first = kept
        for j in range(emitted):
            k = j + 1 if j + 1 < emitted else 0
            if buffer_col[j] != buffer_col[k] or buffer_row[j] != buffer_row[k]:
                chain_col[kept], chain_row[kept] = buffer_col[j], buffer_row[j]
                kept += 1
        if kept == first:
            chain_col[kept], chain_row[kept] = buffer_col[0], buffer_row[0]
            kept += 1
        for j in range(first, kept):
            k = j + 1 if j + 1 < kept else first
            step_x, step_y = chain_col[k] - chain_col[j], chain_row[k] - chain_row[j]
            if abs(step_x) > 1 or abs(step_y) > 1:
                return -1
            codes[j] = _CODE_OF_STEP[3 * (step_y + 1) + (step_x + 1)]
        kept_offsets[cycle + 1] = kept
    # the components
    height, width = row_start.shape[0] - 2, run_cycle.shape[0] - 1
    # Vertical cracks filed by pixel row (counting sort): N tails sit on the row's lower edge, S on its upper.
    for i in range(offsets[n_cycles]):
        if direction[i] & 1:
            row_start[(tail_y[i] - 1 if direction[i] == 1 else tail_y[i]) + 1] += 1
    for row in range(height + 1):
        row_start[row + 1] += row_start[row]
    for row in range(height + 2):  # an element loop: a slice assignment compiles numba's shape-error messages
        fill[row] = row_start[row]
    for cycle in range(n_cycles):
        for i in range(offsets[cycle], offsets[cycle + 1]):
            cycle_of[i] = cycle
            if direction[i] & 1:
                row = tail_y[i] - 1 if direction[i] == 1 else tail_y[i]
                filed[fill[row]] = i
                fill[row] += 1
    for cycle in range(n_cycles):
        parent[cycle] = cycle
    for row in range(height + 1):
        if row_start[row] == row_start[row + 1]:
            continue
        first_x, last_x = width, np.int64(0)
        for f in range(row_start[row], row_start[row + 1]):  # mark the row's cracks, then walk its columns
            x = tail_x[filed[f]]
            run_cycle[x], run_kind[x] = cycle_of[filed[f]], direction[filed[f]]
            if x < first_x:
                first_x = x
            if x > last_x:
                last_x = x
        opened = np.int64(-1)  # not the literal -1: that would compile _root a second time
        for x in range(first_x, last_x + 1):
            if run_kind[x] == 1:
                if opened >= 0:
                    return -2
                opened = run_cycle[x]
            elif run_kind[x] == 3:
                if opened < 0:
                    return -2
                union_join(parent, opened, run_cycle[x])
                opened = -1
            run_kind[x] = 0
        if opened >= 0:
            return -2
    count = np.int64(0)
    for cycle in range(n_cycles):
        number_of_root[cycle] = -1
    for cycle in range(n_cycles):
        if not is_hole[cycle]:
            number_of_root[_root(parent, cycle)] = count
            count += 1
    for cycle in range(n_cycles):
        component[cycle] = number_of_root[_root(parent, cycle)]
        if component[cycle] < 0:
            return -2
    # the crack midpoints and the chains' pixel centres
    for i in range(tail_x.shape[0]):
        midpoints[i, 0] = float(tail_x[i] + offset_x) + 0.5 * _STEP_X[direction[i]]
        midpoints[i, 1] = float(tail_y[i] + offset_y) + 0.5 * _STEP_Y[direction[i]]
    for i in range(kept):
        centres[i, 0] = float(chain_col[i] + offset_x) + 0.5
        centres[i, 1] = float(chain_row[i] + offset_y) + 0.5
    return kept


def _component_work(direction, offsets, width, height):
    """Scratch arrays of the components in :func:`_boundaries_into` (allocated here: allocation in compiled code
    costs compile time): the rows' first filed cracks and fill positions, the filed vertical cracks, each crack's
    cycle, the union-find parents, the row's cycle and kind per vertex column (the cycle of its crack; kind 0 none,
    1 N, 3 S), each root's component."""
    n_cycles, count = offsets.shape[0] - 1, int(offsets[-1])
    vertical = int(np.count_nonzero(direction & 1))
    return (np.zeros(height + 2, dtype=np.int64), np.empty(height + 2, dtype=np.int64), np.empty(vertical, np.int64),
            np.empty(count, dtype=np.int64), np.empty(n_cycles, dtype=np.int64), np.zeros(width + 1, dtype=np.int64),
            np.zeros(width + 1, dtype=np.int8), np.empty(n_cycles, dtype=np.int64))


def boundary_arrays(cracks, width, height, four, offset=(0, 0)):
    """Per cycle of :func:`follow_cracks`: twice its signed area, whether it is a hole, its pixel chain
    (columns, rows, Freeman codes, ``kept_offsets``) and its component (contour module, steps 4-5), and the crack
    ``midpoints`` (tail + half a step) and the chains' pixel ``centres``, ``(n, 2)`` floats in the image frame
    (``offset`` = the padded frame's origin there); ``width``, ``height`` are the padded mask's."""
    tail_x, tail_y, direction, left_turn, offsets = (cracks[k] for k in ("x", "y", "d", "left_turn", "offsets"))
    n_cycles = offsets.shape[0] - 1
    area2, is_hole = np.empty(n_cycles, dtype=np.int64), np.empty(n_cycles, dtype=np.bool_)
    capacity = tail_x.shape[0] * (2 if four else 1)
    chain_col = np.empty(capacity, dtype=np.int64)
    chain_row = np.empty(capacity, dtype=np.int64)
    codes = np.empty(capacity, dtype=np.int8)
    kept_offsets = np.empty(n_cycles + 1, dtype=np.int64)
    longest = int(np.diff(offsets).max(initial=0))
    buffer_col, buffer_row = np.empty(2 * longest + 2, dtype=np.int64), np.empty(2 * longest + 2, dtype=np.int64)
    component = np.empty(n_cycles, dtype=np.int64)
    midpoints, centres = np.empty((tail_x.shape[0], 2), dtype=float), np.empty((capacity, 2), dtype=float)
    kept = _boundaries_into(tail_x, tail_y, direction, left_turn, offsets, bool(four), int(offset[0]), int(offset[1]),
                            area2, is_hole, buffer_col, buffer_row, chain_col, chain_row, codes, kept_offsets,
                            *_component_work(direction, offsets, width, height), component, midpoints, centres)
    if kept == -1:
        raise RuntimeError("internal error: pixel chain has a step longer than one pixel")
    if kept < 0:
        raise RuntimeError("internal error: ink runs do not alternate N/S cracks, or a hole has no outer boundary")
    return {"area2": area2, "chain_col": chain_col[:kept].copy(), "chain_row": chain_row[:kept].copy(),
            "codes": codes[:kept].copy(), "kept_offsets": kept_offsets, "is_hole": is_hole, "component": component,
            "midpoints": midpoints, "centres": centres[:kept].copy()}


def warm_up():
    """Compile (empty cache) or load (``cache=True``) every kernel of the tracer, on a tiny mask (a hole, a
    diagonal contact): the first-call cost that ``benchmarks/bench_speed.py jit`` measures."""
    padded = np.zeros((6, 6), dtype=np.bool_)
    padded[1:4, 1:4] = True
    padded[2, 2] = False
    padded[4, 4] = True
    for connectivity in (MINORITY, 4):
        boundary_arrays(follow_cracks(padded, connectivity), 6, 6, connectivity == 4)
