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

from ._jit import HELPER_OPTIONS, JIT_OPTIONS, compact

__all__ = ["MIN_RUN", "MIN_TREAD", "PixelCorners", "pixel_corners", "outline_pixel_corners", "corner_vertices",
           "with_pixel_corners", "merge_pixel_corners", "pixel_corners_of_outlines"]

#: Fewest cracks of each of the two straight runs that meet at a pixel corner.
MIN_RUN = 3

#: Fewest cracks of the treads beyond a flat run for the run to count as a flat side of its own (not a staircase's
#: tread) where it is longer by more than one crack than them: a bend whose treads are single cracks turns
#: sharply (a round end of a few pixels), one of two-crack treads gently (a bowl of radius 24 px beside its flat
#: side can give treads of 2, 2, 2).
MIN_TREAD = 2

#: Points per call of :func:`pixel_corners` in :func:`pixel_corners_of_outlines` (its work arrays are five of the
#: points' length, besides the result: a bounded chunk keeps a noise image of millions of contour points within its
#: memory).
CHUNK_POINTS = 1 << 18

_UNIT = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])  # direction codes 0..3 -> unit step


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
        return PixelCorners(index[order], self.vertex[order])


@njit(**HELPER_OPTIONS)
def _run(base, rank, step, k):
    """Index of the run ``step`` places after run ``rank`` (negative: before), cyclically among the ``k`` runs of
    an outline stored from ``base``."""
    return base + ((rank + step) % k + k) % k


@njit(**HELPER_OPTIONS)
def _tread(length, direction, base, rank, k, m, way):
    """Whether run ``m`` places from run ``rank`` continues at its far end (``way`` +1: after it, -1: before) as
    a staircase's tread (:func:`pixel_corners`): a step of one crack, then a run the same way, unless the run is
    longer by more than one crack than a whole tread of at least :data:`MIN_TREAD` cracks beyond it (the longer
    of the first two whole treads: the first can be a crack or two short with the phase of the pixels, 2, 3
    beside a bowl of radius 24)."""
    own = direction[_run(base, rank, m, k)]
    continues = length[_run(base, rank, m + way, k)] == 1 and direction[_run(base, rank, m + 2 * way, k)] == own
    whole = length[_run(base, rank, m + 3 * way, k)] == 1 and direction[_run(base, rank, m + 4 * way, k)] == own
    second = whole and length[_run(base, rank, m + 5 * way, k)] == 1 \
        and direction[_run(base, rank, m + 6 * way, k)] == own
    tread_length = length[_run(base, rank, m + 2 * way, k)]
    if second and length[_run(base, rank, m + 4 * way, k)] > tread_length:
        tread_length = length[_run(base, rank, m + 4 * way, k)]
    flat = whole and tread_length >= MIN_TREAD and length[_run(base, rank, m, k)] > tread_length + 1
    return continues and not flat


@njit(**HELPER_OPTIONS)
def _runs(points, o, n, code, first, length, direction):
    """The runs of cracks of one direction of the outline of ``n`` points from row ``o``: per point its crack's
    direction code (``code``), per run (in order from the outline's first point, stored from ``o``) its first
    point, its cracks and its direction. Returns the number of runs, or -1 when the points are not the
    midpoints of a closed chain of unit cracks."""
    for i in range(n):
        # a crack midpoint has one integer and one half-integer coordinate; its direction of travel points from
        # the point before it towards the point after it along its own axis
        x, y = points[o + i, 0], points[o + i, 1]
        fx, fy = abs(x - np.floor(x)), abs(y - np.floor(y))
        horizontal = fy == 0.0 and fx == 0.5
        if not (horizontal or (fx == 0.0 and fy == 0.5)):
            return -1
        before, after = o + (i + n - 1) % n, o + (i + 1) % n
        if horizontal:
            code[o + i] = 0 if points[after, 0] - points[before, 0] > 0 else 2
        else:
            code[o + i] = 1 if points[after, 1] - points[before, 1] > 0 else 3
    k = 0
    for i in range(n):
        before = o + (i + n - 1) % n
        # a closed chain of unit cracks: each crack starts where the one before it ends
        for axis in range(2):
            if not points[before, axis] + 0.5 * _UNIT[code[before], axis] == \
                    points[o + i, axis] - 0.5 * _UNIT[code[o + i], axis]:
                return -1
        if code[o + i] != code[before]:
            first[o + k] = i
            k += 1
    for r in range(k):
        following = first[o + (r + 1) % k]
        length[o + r] = (following - first[o + r] + n) % n
        if length[o + r] == 0:
            length[o + r] = n
        direction[o + r] = code[o + first[o + r]]
    return k


@njit(**JIT_OPTIONS)
def _pixel_corners_into(points, lengths, code, first, length, direction, corner, at, vertex):
    """:func:`pixel_corners` into ``at`` (all False) and ``vertex`` (all NaN), outline by outline; ``code``,
    ``first``, ``length``, ``direction`` (:func:`_runs`) and ``corner`` (per run: the vertex before it is a pixel
    corner) are work arrays of the points' length."""
    compact()  # run time negligible: code optimized for size (_jit.compact)
    o = 0
    for b in range(lengths.shape[0]):
        n = lengths[b]
        k = _runs(points, o, n, code, first, length, direction) if n >= 4 else -1
        for j in range(k):
            corner[o + j] = False
        for j in range(k if k >= 4 else 0):
            previous, following = _run(o, j, -1, k), _run(o, j, 1, k)
            # the vertex before run j is a pixel corner: runs j - 1 and j long enough, neither a staircase's tread
            before_tread = _tread(length, direction, o, j, k, -1, -1)
            if length[previous] >= MIN_RUN and length[o + j] >= MIN_RUN and not before_tread \
                    and not _tread(length, direction, o, j, k, 0, 1):
                corner[o + j] = True
            # the end of a stroke one or two pixels wide: a run shorter than MIN_RUN between two long runs the
            # opposite ways round (a U-turn), each of them not a staircase's tread at its far end; both vertices
            if length[o + j] < MIN_RUN and length[previous] >= MIN_RUN and length[following] >= MIN_RUN \
                    and direction[previous] == (direction[following] + 2) % 4 and not before_tread \
                    and not _tread(length, direction, o, j, k, 1, 1):
                corner[o + j] = True
                corner[following] = True
        for j in range(k if k >= 4 else 0):
            # a block (four runs: the crack outline is a rectangle) of any size: its four vertices
            if corner[o + j] or k == 4:
                i = o + first[o + j]
                at[i] = True
                for axis in range(2):
                    vertex[i, axis] = points[i, axis] - 0.5 * _UNIT[code[i], axis]
        o += n


def pixel_corners(points, lengths):
    """Pixel corners of closed crack outlines stacked one after the other (``points`` ``(N, 2)``, outline
    ``b`` has ``lengths[b]`` points, first point not repeated).

    Returns ``(at, vertex)``: ``at[i]`` (bool, ``N``) says that the outline turns at a pixel corner between
    its point before ``i`` (cyclically) and point ``i``, and ``vertex[i]`` (``(N, 2)``, NaN elsewhere) is that
    corner, the vertex shared by the two cracks. An outline whose points are not the midpoints of a closed
    chain of unit cracks gets none. Compiled (:func:`_pixel_corners_into`, outline by outline); an outline's
    result does not depend on the others.

    The rules (module docstring), on the runs of cracks of one direction of each outline: the vertex before a
    run is a pixel corner when that run and the one before it have at least :data:`MIN_RUN` cracks and neither
    is a staircase's tread at its far end (:func:`_tread`); both vertices of a run shorter than that between two
    such runs the opposite ways round (a U-turn: a stroke end); all four vertices of an outline of four runs (a
    block); none on an outline of fewer runs."""
    points = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    lengths = np.ascontiguousarray(lengths, dtype=np.int64).reshape(-1)
    total = points.shape[0]
    at = np.zeros(total, bool)
    vertex = np.full((total, 2), np.nan)
    if total == 0:
        return at, vertex
    work = np.empty((4, total), np.int64)
    _pixel_corners_into(points, lengths, work[0], work[1], work[2], work[3], np.empty(total, np.bool_), at, vertex)
    return at, vertex


def warm_up():
    """Compile (empty cache) or load the kernel once per process; part of the tracer's warm-up task
    (:func:`._cracks.warm_up`: every trace finds the pixel corners of its outlines)."""
    if not _WARM:
        pixel_corners(np.array([[0.5, 0.0], [1.0, 0.5], [0.5, 1.0], [0.0, 0.5]]), [4])
        _WARM.append(True)


_WARM = []


def outline_pixel_corners(points):
    """The :class:`PixelCorners` of one closed crack outline (:func:`pixel_corners`): the sorted indices of the
    points that follow a pixel corner, and those corners (``(k, 2)``)."""
    points = np.asarray(points, float)
    at, vertex = pixel_corners(points, [points.shape[0]])
    index = np.flatnonzero(at)
    return PixelCorners(index, vertex[index])


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
    at, vertex = pixel_corners(points, lengths) if found is None else _stacked(found, lengths)
    offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    n = lengths[outline]
    here = offsets[outline] + corners % n  # the vertex between the corner's point and the one before it
    after = offsets[outline] + (corners + 1) % n  # ... between the corner's point and the one after it
    out = np.where(at[here][:, None], vertex[here], np.where(at[after][:, None], vertex[after], np.nan))
    return out


def _stacked(found, lengths):
    """:func:`pixel_corners`' ``(at, vertex)`` of stacked outlines of ``lengths`` points from the
    :class:`PixelCorners` of each (``found``)."""
    if len(found) != lengths.shape[0]:
        raise ValueError(f"found has pixel corners of {len(found)} outlines for {lengths.shape[0]}")
    total = int(lengths.sum())
    at = np.zeros(total, bool)
    vertex = np.full((total, 2), np.nan)
    offsets = np.cumsum(lengths) - lengths
    for offset, (index, corner) in zip(offsets.tolist(), found):
        at[offset + index] = True
        vertex[offset + index] = corner
    return at, vertex


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
        at, vertex = pixel_corners(np.concatenate(points_list[first:last]), lengths[first:last])
        hits = np.flatnonzero(at)  # in the chunk, outline by outline
        offsets = np.cumsum(lengths[first:last]) - lengths[first:last]
        cuts = np.searchsorted(hits, offsets).tolist() + [hits.shape[0]]  # each outline's hits: a slice
        corners = vertex[hits]
        for b, offset in enumerate(offsets.tolist()):
            found.append(PixelCorners(hits[cuts[b]:cuts[b + 1]] - offset, corners[cuts[b]:cuts[b + 1]]))
        first = last
    return found
