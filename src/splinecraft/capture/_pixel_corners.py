"""Pixel corners of crack outlines: turns of the pixel boundary between two axis-aligned straight sides
(docs/capture.md §11, "Pixel corners"; §12, "Small outlines").

A crack outline (docs/capture.md §10) lists the midpoints of the unit cracks between ink and paper pixels, so
the pixel boundary's own vertices are not contour points: where it turns, the polyline of midpoints cuts the
turn by a chamfer 0.35 px inside it, and a corner detector can only mark one of the two midpoints beside it,
half a pixel along one side. Where both sides of the turn are axis-aligned straight runs, the two sides of the
shape are pinned down exactly as far as the pixels go (every line of the preimage of such a run lies within
half a pixel of the crack line, which is the preimage's centre: the separating line of ``fitting.tips``), and
their crossing is the turn's vertex, the pixel corner. :func:`pixel_corners` finds those vertices:

* both runs that meet at the vertex are at least :data:`MIN_RUN` cracks long (a turn beside a run of one or
  two cracks is a step of a staircase, a rounded corner or a nub, not two straight sides);
* neither run continues beyond its far end as the tread of a staircase (a step of one crack, then a run
  parallel to it the same way): that is a side a little off the axis, whose line (and corner) the run
  alone does not give. A run longer by more than one crack than a whole tread beyond it of :data:`MIN_TREAD`
  cracks or more is no such tread (a digital straight segment's runs differ by at most one, its end runs can
  only be shorter): it is a flat side of its own that bends away gently into a curve;
* or the vertex is one of the two of a run of one or two cracks between two such runs that go the opposite
  ways (a U-turn): the square end of a stroke 1-2 px wide, whose sides are the two long runs and whose end is
  the short one (docs/capture.md §11, "Stroke ends"). A staircase never turns back;
* or the outline has four runs: a block of pixels, whose four vertices are corners at every size (a 1 x 1,
  1 x 2 or 2 x 2 block has runs too short for the rules above; a dot rendered that small is its block).

A smooth curve never makes such a turn: two adjacent runs of three cracks or more at right angles need the
curve to turn by more than 50 degrees within about 3 px, and a fillet of more than 1.7 px radius leaves the
corner pixel out (runs ``L, 1, 1, L``); a fillet below that renders exactly as a sharp corner. Outlines of
any other form (pixel chains, resampled or scaled polylines) have no pixel corners.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from ._jit import JIT_OPTIONS, compact, pymax

__all__ = ["MIN_RUN", "MIN_TREAD", "PixelCorners", "pixel_corners", "outline_pixel_corners", "corner_vertices",
           "with_pixel_corners", "merge_pixel_corners", "pixel_corners_of_outlines"]

#: Fewest cracks of each of the two straight runs that meet at a pixel corner.
MIN_RUN = 3

#: Fewest cracks of the treads beyond a flat run for the run to count as a flat side of its own (not a staircase's
#: tread) where it is longer by more than one crack than them: a bend whose treads are single cracks turns
#: sharply (a round end of a few pixels), one of two-crack treads gently (a bowl of radius 24 px beside its flat
#: side can give treads of 2, 2, 2).
MIN_TREAD = 2

#: Points per call of the kernel in :func:`pixel_corners_of_outlines` (its points and scratch, some 60 bytes a point:
#: a bounded chunk keeps a noise image of millions of contour points within its memory).
CHUNK_POINTS = 1 << 18

# direction codes 0..3 -> half the unit step, x and y (0.5 * (1, 0), (0, 1), (-1, 0), (0, -1): exact)
_HALF_X, _HALF_Y = np.array([0.5, 0.0, -0.5, 0.0]), np.array([0.0, 0.5, 0.0, -0.5])
# The rules look at most this many runs either way from a run (a tread rule at run -1 or 1 reaches 6 more).
_REACH = 7


class PixelCorners(NamedTuple):
    """The pixel corners of one closed outline (:func:`pixel_corners`): ``index``, the sorted indices of the
    points that follow them, and ``vertex`` (``(k, 2)``, in the order of ``index``), the corners themselves."""

    index: np.ndarray
    vertex: np.ndarray

    def rotated(self, rotation, n):
        """The same corners of the outline of ``n`` points read from its point ``rotation`` (index ``i`` becomes
        ``(i - rotation) % n``), sorted again."""
        index = (self.index - rotation) % n
        order = np.argsort(index, kind="stable")
        return PixelCorners(index[order], self.vertex.take(order, axis=0))


@njit(**JIT_OPTIONS)
def _pixel_corners_into(points, lengths, code, run_first, run_length, run_direction, flags, hits, vertex):
    """The pixel corners of the stacked closed outlines (see :func:`pixel_corners`), outline by outline: the global
    index of the point after each vertex into ``hits`` and the vertex into ``vertex`` (both in the order of the
    points); returns how many. Scratch: ``code`` (int8) and ``run_first`` (int64) of at least the points' length,
    ``run_length`` (int64), ``run_direction`` (int8) and ``flags`` (uint8) of ``2 _REACH`` more: an outline's runs
    from position ``_REACH`` on, the last and the first ``_REACH`` of them (cyclically) copied before and after,
    so that the rules read their neighbours without wrapping around."""
    compact()  # run time negligible: code optimized for size (_jit.compact)
    found = 0
    offset = 0
    for outline in range(lengths.shape[0]):
        n = lengths[outline]
        offset += n
        first = offset - n
        if n < 4:
            continue
        # a crack midpoint has one integer and one half-integer coordinate; its direction of travel points from
        # the point before it towards the point after it along its own axis
        good = True
        for i in range(first, offset):
            x, y = points[i, 0], points[i, 1]
            frac_x, frac_y = abs(x - np.floor(x)), abs(y - np.floor(y))
            before = i - 1 if i > first else offset - 1
            after = i + 1 if i < offset - 1 else first
            if frac_y == 0.0 and frac_x == 0.5:
                code[i] = 0 if points[after, 0] - points[before, 0] > 0 else 2
            elif frac_x == 0.0 and frac_y == 0.5:
                code[i] = 1 if points[after, 1] - points[before, 1] > 0 else 3
            else:
                good = False
                break
        if not good:
            continue
        # a closed chain of unit cracks: each crack starts where the one before it ends
        for i in range(first, offset):
            before = i - 1 if i > first else offset - 1
            if points[before, 0] + _HALF_X[code[before]] != points[i, 0] - _HALF_X[code[i]] or \
                    points[before, 1] + _HALF_Y[code[before]] != points[i, 1] - _HALF_Y[code[i]]:
                good = False
                break
        if not good:
            continue
        # runs of cracks of one direction, in order: first crack (global index), direction, length
        count = 0
        for i in range(first, offset):
            if code[i] != code[i - 1 if i > first else offset - 1]:
                run_first[count] = i
                run_direction[_REACH + count] = code[i]
                count += 1
        if count < 4:  # (a closed chain turns at least four times)
            continue
        for run in range(count):
            length = (run_first[run + 1] if run + 1 < count else run_first[0] + n) - run_first[run]
            run_length[_REACH + run] = length
        for at in range(count + 2 * _REACH):  # the copies around
            if at < _REACH or at >= _REACH + count:
                run_length[at] = run_length[_REACH + (at - _REACH) % count]
                run_direction[at] = run_direction[_REACH + (at - _REACH) % count]
        # flags 1 and 2: the run at ``at`` continues at its far end before it (1) or after it (2) as a staircase's
        # tread (a step of one crack, then a run parallel to it the same way) ...
        for at in range(_REACH - 1, _REACH + count + 1):
            flags[at] = 0
            own = run_direction[at]
            for side in range(2):
                way = 2 * side - 1
                if run_length[at + way] != 1 or run_direction[at + 2 * way] != own:
                    continue
                # ... unless it is longer by more than one crack than a whole tread of that staircase (``beyond``
                # or the one after it, with a step at both ends) of MIN_TREAD cracks or more: the runs of a digital
                # straight segment differ by at most one and its end runs can only be shorter, so the run is then
                # no tread of an off-axis side but a straight side of its own, from which the outline bends away
                # gently (a flat side running into a curve; a round end of a few pixels turns through treads of
                # single cracks)
                if run_length[at + 3 * way] == 1 and run_direction[at + 4 * way] == own:
                    # the longer of the first two whole treads (the first can be a crack or two short with the
                    # phase of the pixels: 2, 3 beside a bowl of radius 24)
                    tread_length = run_length[at + 2 * way]
                    if run_length[at + 5 * way] == 1 and run_direction[at + 6 * way] == own:
                        tread_length = pymax(tread_length, run_length[at + 4 * way])
                    if tread_length >= MIN_TREAD and run_length[at] > tread_length + 1:
                        continue
                flags[at] |= 1 << side
        # flag 4: the vertex before the run is a pixel corner (the run and the one before it long enough, neither
        # a staircase's tread); flag 8: the run is the end of a stroke one or two pixels wide, shorter than
        # MIN_RUN between two long runs the opposite ways round (a U-turn), each of them not a staircase's tread
        # at its far end: both of its vertices
        for at in range(_REACH, _REACH + count):
            if run_length[at - 1] < MIN_RUN or flags[at - 1] & 1:
                continue
            if run_length[at] >= MIN_RUN:
                if not flags[at] & 2:
                    flags[at] |= 4
            elif run_length[at + 1] >= MIN_RUN and run_direction[at - 1] == run_direction[at + 1] ^ 2 and \
                    not flags[at + 1] & 2:
                flags[at] |= 8
        # a block (four runs: the crack outline is a rectangle) of any size: its four vertices. Below 3 x 3 pixels
        # the runs are too short for the rules above, yet no other shape renders as a rectangle that small
        for at in range(_REACH, _REACH + count):
            if flags[at] & 12 or flags[at - 1 if at > _REACH else _REACH + count - 1] & 8 or count == 4:
                i = run_first[at - _REACH]
                hits[found] = i
                vertex[found, 0] = points[i, 0] - _HALF_X[code[i]]
                vertex[found, 1] = points[i, 1] - _HALF_Y[code[i]]
                found += 1
    return found


def _corners(points, lengths):
    """The pixel corners of closed crack outlines stacked one after the other (``points`` ``(N, 2)`` float64,
    ``lengths`` int64): the global indices of the points after them, sorted, and the vertices (``(k, 2)``)."""
    total = points.shape[0]
    if lengths.size and (lengths.min() < 0 or int(lengths.sum()) != total):
        raise ValueError(f"lengths: must be non-negative and sum to the {total} points, got {lengths.tolist()}")
    hits, vertex = np.empty(total, np.int64), np.empty((total, 2))
    runs = total + 2 * _REACH
    found = _pixel_corners_into(points, lengths, np.empty(total, np.int8), np.empty(total, np.int64),
                                np.empty(runs, np.int64), np.empty(runs, np.int8), np.empty(runs, np.uint8),
                                hits, vertex)
    return hits[:found], vertex[:found]


def pixel_corners(points, lengths):
    """Pixel corners of closed crack outlines stacked one after the other (``points`` ``(N, 2)``, outline
    ``b`` has ``lengths[b]`` points, first point not repeated).

    Returns ``(at, vertex)``: ``at[i]`` (bool, ``N``) says that the outline turns at a pixel corner between
    its point before ``i`` (cyclically) and point ``i``, and ``vertex[i]`` (``(N, 2)``, NaN elsewhere) is that
    corner, the vertex shared by the two cracks. An outline whose points are not the midpoints of a closed
    chain of unit cracks gets none. One compiled pass over the outlines (:func:`_pixel_corners_into`; the
    vectorized numpy formulation it replaced, some 70 calls, cost 10x more on a 300-px glyph, and
    ``tests/test_pixel_corners.py`` keeps it and pins the kernel to it); an outline's result does not depend on
    the others."""
    points = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    lengths = np.ascontiguousarray(lengths, dtype=np.int64).reshape(-1)
    index, vertices = _corners(points, lengths)
    at = np.zeros(points.shape[0], bool)
    vertex = np.full((points.shape[0], 2), np.nan)
    at[index] = True
    vertex[index] = vertices
    return at, vertex


def outline_pixel_corners(points):
    """The :class:`PixelCorners` of one closed crack outline (:func:`pixel_corners`): the sorted indices of the
    points that follow a pixel corner, and those corners (``(k, 2)``)."""
    points = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    return PixelCorners(*_corners(points, np.array([points.shape[0]], np.int64)))


def corner_vertices(points, lengths, outline, corners, found=None):
    """The pixel corner beside each given corner of stacked crack outlines (``points``, ``lengths`` as in
    :func:`pixel_corners`): ``outline`` and ``corners`` (int arrays of one length) name the outline and the
    index within it of each corner. A corner at one of the two points beside a pixel corner (the point
    before it or the point after it) gets that vertex; others get NaN. Returns ``(k, 2)``.

    ``found``: the :class:`PixelCorners` of every outline, already found (trace's corner stage,
    :func:`pixel_corners_of_outlines`); ``None``: :func:`pixel_corners` finds them here."""
    lengths = np.asarray(lengths, dtype=np.int64).reshape(-1)
    outline = np.asarray(outline, dtype=np.int64).reshape(-1)
    corners = np.asarray(corners, dtype=np.int64).reshape(-1)
    out = np.full((corners.shape[0], 2), np.nan)
    if not corners.size:
        return out
    if found is not None:  # the few pixel corners looked up by index, not spread over every point of the outlines
        if len(found) != lengths.shape[0]:
            raise ValueError(f"found has pixel corners of {len(found)} outlines for {lengths.shape[0]}")
        sizes = lengths.tolist()
        rows = [{index: row for row, index in enumerate(np.asarray(f.index).tolist())} for f in found]
        for k, (b, c) in enumerate(zip(outline.tolist(), corners.tolist())):
            # the vertex between the corner's point and the one before it, else the one after it
            row = rows[b].get(c % sizes[b], rows[b].get((c + 1) % sizes[b]))
            if row is not None:
                out[k] = found[b].vertex[row]
        return out
    at, vertex = pixel_corners(points, lengths)
    offsets = np.cumsum(lengths) - lengths
    n = lengths[outline]
    here = offsets[outline] + corners % n  # the vertex between the corner's point and the one before it
    after = offsets[outline] + (corners + 1) % n  # ... between the corner's point and the one after it
    return np.where(at[here][:, None], vertex.take(here, axis=0),
                    np.where(at[after][:, None], vertex.take(after, axis=0), np.nan))


def with_pixel_corners(found, points):
    """The corners ``found`` (indices into the closed outline ``points``) with its pixel corners
    (:func:`merge_pixel_corners` of :func:`outline_pixel_corners`). Sorted, unique."""
    return merge_pixel_corners(found, outline_pixel_corners(points)[0], len(points))


def merge_pixel_corners(found, index, n):
    """The corners ``found`` (indices into a closed outline of ``n`` points) with its pixel corners ``index``
    (the points after their vertices): every pixel corner is a corner, in place of any corner of ``found`` within
    one point of it (the two midpoints beside the vertex, or the middle crack of a side of three); the rest of
    ``found`` stays. Sorted, unique."""
    found = np.asarray(found, dtype=np.intp).reshape(-1)
    if not len(index):
        return found
    # within one point around the closed outline: a pixel corner at f - 1, f or f + 1 (mod n); looked up, not
    # measured pairwise (found x index took gigabytes on the 262 000-point boundary of a 1000 x 1000 image of noise)
    beside = np.mod(found[:, None] + np.array([-1, 0, 1]), n)
    marked = np.zeros(n, bool)  # the pixel corners' points, looked up by index
    marked[np.mod(np.asarray(index, dtype=np.intp), n)] = True
    near = marked[beside].any(axis=1)
    return np.unique(np.concatenate([found[~near], index])).astype(np.intp)


def pixel_corners_of_outlines(points_list):
    """:func:`outline_pixel_corners` (a :class:`PixelCorners`) of every closed crack outline of ``points_list``, by
    :func:`pixel_corners` on chunks of whole outlines of about ``CHUNK_POINTS`` points (an outline's result does
    not depend on the others; the chunks bound the temporaries)."""
    lengths = np.fromiter(map(len, points_list), np.int64, len(points_list))
    found = []
    first = 0
    while first < len(points_list):
        last = first + max(1, int(np.searchsorted(np.cumsum(lengths[first:]), CHUNK_POINTS, side="right")))
        points = np.ascontiguousarray(np.concatenate(points_list[first:last]), dtype=np.float64).reshape(-1, 2)
        hits, corners = _corners(points, lengths[first:last])  # in the chunk, outline by outline
        offsets = np.cumsum(lengths[first:last]) - lengths[first:last]
        cuts = np.searchsorted(hits, offsets).tolist() + [hits.shape[0]]  # each outline's hits: a slice
        for b, offset in enumerate(offsets.tolist()):
            found.append(PixelCorners(hits[cuts[b]:cuts[b + 1]] - offset, corners[cuts[b]:cuts[b + 1]]))
        first = last
    return found


_WARM = []


def warm_up():
    """Compile or load the kernel once per process (see :func:`.fitting._kernels.warm_up`), on the outline of a
    3 x 4 block of pixels."""
    if _WARM:
        return
    top = [(x + 0.5, 0.0) for x in range(4)] + [(4.0, y + 0.5) for y in range(3)]
    bottom = [(x + 0.5, 3.0) for x in range(3, -1, -1)] + [(0.0, y + 0.5) for y in range(2, -1, -1)]
    _corners(np.array(top + bottom), np.array([14], np.int64))
    _WARM.append(True)
