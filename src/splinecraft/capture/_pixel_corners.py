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

__all__ = ["MIN_RUN", "MIN_TREAD", "PixelCorners", "pixel_corners", "outline_pixel_corners", "corner_vertices",
           "with_pixel_corners", "merge_pixel_corners", "pixel_corners_of_outlines"]

#: Fewest cracks of each of the two straight runs that meet at a pixel corner.
MIN_RUN = 3

#: Fewest cracks of the treads beyond a flat run for the run to count as a flat side of its own (not a staircase's
#: tread) where it is longer by more than one crack than them: a bend whose treads are single cracks turns
#: sharply (a round end of a few pixels), one of two-crack treads gently (a bowl of radius 24 px beside its flat
#: side can give treads of 2, 2, 2).
MIN_TREAD = 2

#: Points per call of :func:`pixel_corners` in :func:`pixel_corners_of_outlines` (its temporaries are some 30 arrays of
#: the points' length: a bounded chunk keeps a noise image of millions of contour points within its memory).
CHUNK_POINTS = 1 << 18

_UNIT = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])  # direction codes 0..3 -> unit step
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


def pixel_corners(points, lengths):
    """Pixel corners of closed crack outlines stacked one after the other (``points`` ``(N, 2)``, outline
    ``b`` has ``lengths[b]`` points, first point not repeated).

    Returns ``(at, vertex)``: ``at[i]`` (bool, ``N``) says that the outline turns at a pixel corner between
    its point before ``i`` (cyclically) and point ``i``, and ``vertex[i]`` (``(N, 2)``, NaN elsewhere) is that
    corner, the vertex shared by the two cracks. An outline whose points are not the midpoints of a closed
    chain of unit cracks gets none. Vectorized over all outlines; an outline's result does not depend on the
    others."""
    points = np.asarray(points, float).reshape(-1, 2)
    lengths = np.asarray(lengths, dtype=np.int64).reshape(-1)
    total = points.shape[0]
    at = np.zeros(total, bool)
    vertex = np.full((total, 2), np.nan)
    if total == 0:
        return at, vertex
    offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    outline = np.repeat(np.arange(lengths.shape[0]), lengths)
    local = np.arange(total) - offsets[outline]
    n = lengths[outline]
    prev = offsets[outline] + (local - 1) % n
    nxt = offsets[outline] + (local + 1) % n
    # a crack midpoint has one integer and one half-integer coordinate; its direction of travel points from
    # the point before it towards the point after it along its own axis
    frac = np.abs(points - np.floor(points))
    horizontal = (frac[:, 1] == 0.0) & (frac[:, 0] == 0.5)
    vertical = (frac[:, 0] == 0.0) & (frac[:, 1] == 0.5)
    travel = points.take(nxt, axis=0) - points.take(prev, axis=0)  # (take: numpy 2.4's row indexing is 5-15x slower)
    code = np.where(horizontal, np.where(travel[:, 0] > 0, 0, 2), np.where(travel[:, 1] > 0, 1, 3))
    unit = _UNIT.take(code, axis=0)
    # a closed chain of unit cracks: each crack starts where the one before it ends
    chained = (horizontal | vertical) & np.all((points + 0.5 * unit).take(prev, axis=0) == points - 0.5 * unit, axis=1)
    good = np.bincount(outline[~chained], minlength=lengths.shape[0]) == 0
    good &= lengths >= 4
    if not good.any():
        return at, vertex
    # runs of cracks of one direction: run starts, and per outline its runs in order (cyclically)
    start = good[outline] & (code != code[prev])
    first = np.flatnonzero(start)  # global index of every run's first crack, sorted (by outline, then index)
    run_outline = outline[first]
    count = np.bincount(run_outline, minlength=lengths.shape[0])
    run_offset = np.concatenate([[0], np.cumsum(count)[:-1]])
    j = np.arange(first.shape[0]) - run_offset[run_outline]  # a run's rank in its outline
    k = count[run_outline]
    # the runs REACH places before each run to REACH places after it, within its outline (column REACH + m: the
    # run m places after, negative m before), and their lengths and directions
    around = run_offset[run_outline][:, None] + (j[:, None] + np.arange(-_REACH, _REACH + 1)[None, :]) % k[:, None]
    following = first[around[:, _REACH + 1]]
    length = (following - first) % lengths[run_outline]
    length = np.where(length == 0, lengths[run_outline], length)
    direction = code[first]
    lengths_at, directions_at = length[around], direction[around]

    def length_of(m):
        return lengths_at[:, _REACH + m]

    def direction_of(m):
        return directions_at[:, _REACH + m]

    def tread(m, way):  # run m continues at its far end (way +1: after it, -1: before) as a staircase's tread
        continues = (length_of(m + way) == 1) & (direction_of(m + 2 * way) == direction_of(m))
        # ... unless it is longer by more than one crack than a whole tread of that staircase (``beyond`` or the
        # one after it, with a step at both ends) of MIN_TREAD cracks or more: the runs of a digital straight
        # segment differ by at most one and its end runs can only be shorter, so the run is then no tread of an
        # off-axis side but a straight side of its own, from which the outline bends away gently (a flat side
        # running into a curve; a round end of a few pixels turns through treads of single cracks)
        whole = (length_of(m + 3 * way) == 1) & (direction_of(m + 4 * way) == direction_of(m))
        # the longer of the first two whole treads (the first can be a crack or two short with the phase of
        # the pixels: 2, 3 beside a bowl of radius 24)
        second = whole & (length_of(m + 5 * way) == 1) & (direction_of(m + 6 * way) == direction_of(m))
        tread_length = np.maximum(length_of(m + 2 * way), np.where(second, length_of(m + 4 * way), 0))
        flat = whole & (tread_length >= MIN_TREAD) & (length_of(m) > tread_length + 1)
        return continues & ~flat

    # the vertex before run j is a pixel corner: runs j - 1 and j long enough, neither a staircase's tread
    before_tread = tread(-1, -1)  # (used twice)
    corner = (length_of(-1) >= MIN_RUN) & (length >= MIN_RUN)
    corner &= ~before_tread & ~tread(0, 1)
    # the end of a stroke one or two pixels wide: a run shorter than MIN_RUN between two long runs the opposite
    # ways round (a U-turn), each of them not a staircase's tread at its far end; both of its vertices
    end = (length < MIN_RUN) & (length_of(-1) >= MIN_RUN) & (length_of(1) >= MIN_RUN)
    end &= direction_of(-1) == (direction_of(1) + 2) % 4
    end &= ~before_tread & ~tread(1, 1)
    end &= k >= 4
    corner |= end
    corner[around[:, _REACH + 1][end]] = True
    # a block (four runs: the crack outline is a rectangle) of any size: its four vertices. Below 3 x 3 pixels
    # the runs are too short for the rules above, yet no other shape renders as a rectangle that small
    corner |= k == 4
    corner &= k >= 4
    index = first[corner]
    at[index] = True
    vertex[index] = points.take(index, axis=0) - 0.5 * unit.take(index, axis=0)
    return at, vertex


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
    out = np.where(at[here][:, None], vertex.take(here, axis=0),
                   np.where(at[after][:, None], vertex.take(after, axis=0), np.nan))
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
