"""Outline capture end to end: image -> boundaries -> corners -> spline fit with knot insertion.

:func:`trace` runs the pipeline of thesis chapter 4 on every boundary of a bitmap (outer contours and
holes of all components): binarization (:func:`~splinecraft.capture.image.load_bitmap`), chain-code
boundaries (:func:`~splinecraft.capture.contour.trace_boundaries`, thesis section 4.1.1), corners
(:func:`~splinecraft.capture.corners.corners`, thesis section 4.1.2 and chapter 2), and the piecewise spline fit with
knot insertion until the error is below ``epsilon`` (:func:`~splinecraft.capture.fitting.fit_outline`,
thesis sections 4.2-4.3). The :class:`TraceResult` keeps every intermediate result, the statistics of thesis tables
4.1-4.61, every iteration (per boundary and merged for stepping) and writes SVG and JSON.

Documented outcomes for degenerate input
----------------------------------------
* all-white image (no ink after thresholding): ``ValueError("no shape found ...")``;
* all-black image: the ink is the whole frame, the result is the frame rectangle (4 corners);
* small outlines (fewer than ``fitting.SMALL_OUTLINE`` = 64 contour points: single pixels, dominos, specks,
  short diagonal chains) with the default method ``"lsq"``: all fitted together by
  :func:`~splinecraft.capture.fitting.fit_small_outlines` (interpolant through contour points with knot
  insertion, corners interpolated; converged means within ``epsilon`` everywhere); below
  :data:`CORNERLESS_CONTOUR` = 20 points without corner detection, as one closed periodic curve. Any other
  contour too short for the corner detector: no corners, one closed periodic curve. Both are recorded in
  :attr:`TraceResult.notes`;
* 1-pixel-wide lines: the crack outline goes round the line (a thin closed shape of width 1);
* empty arrays, non-image or truncated files: ``ValueError`` / ``FileNotFoundError`` from
  :func:`~splinecraft.capture.image.load_bitmap`, naming the file;
* ``epsilon <= 0`` (or NaN, inf): ``ValueError``. ``max_iterations`` bounds the knot insertion, so a
  run never hangs; an unconverged boundary is reported in ``stats["converged"]``, and
  ``stats["per_boundary"][k]["reason"]`` (also in :attr:`TraceResult.notes`) says why it did not converge.

Large and noisy images
----------------------
An 8000 x 8000 8-bit PNG (a filled disc of radius 3900 px with a hole, an island in the hole and a
triangular notch: 3 boundaries, 48 306 contour points), measured with
``/usr/bin/time -v splinecraft trace big.png -o big.svg`` on the 2-core development machine: 2.3 s wall
(in-process 1.55 s: load 0.62 s, boundaries 0.12 s, corners 0.09 s, fit 0.66 s), peak resident memory
283 MB (commit 5aa9c7e). Memory is a few bytes per pixel (the gray image and the mask, one byte each, plus bool
temporaries) and scales linearly.
The cost per boundary does not depend on the image size. Images with thousands of specks (scanner noise)
fit their small outlines together in one batch (``fitting.fit_small_outlines``). Uniform random noise (30 %
ink, ``np.random.default_rng(0).random((size, size)) < 0.3``, ``keep_snapshots=False``, median of repeated
runs interleaved in one process against ``fit_params={"small_outline": 0}``, the previous behaviour):
200 x 200 (2270 boundaries, 2174 under 64 points) 2.0 s instead of 11.1 s (5.5x; the ~100 larger outlines
take most of the rest) and every small outline converges; 40 x 40 (103 boundaries) 0.09 s instead of
0.50 s (5.6x). The price is more Bézier pieces on the specks (about 1.3x: 10 331 instead of 7964 for the
200 x 200 image), since the small path interpolates contour points. 17 of the larger outlines of that image
(a corner every few steps) get stuck in the regression spline and are refitted by the same interpolant path
(``fit_outline``'s ``fallback``): then every boundary converges, in 2.5 s (commit 5aa9c7e, median of 3).
``min_speck_area`` removes specks.
"""
from __future__ import annotations

import inspect
import json
import math
import numbers
import time
from dataclasses import dataclass, field

import numpy as np

from .contour import trace_boundaries
from .corners import CAPTURE_DEFAULT as CORNER_CAPTURE_DEFAULT
from .corners import CORNER_METHODS
from .corners import corners as detect_corners
from .fitting import DEFAULT_EPSILON, KNOT_METHODS, SMALL_OUTLINE, _check_options, fit_outline, fit_small_outlines
from .image import load_bitmap
from .svg import path_data, svg_document

__all__ = ["trace", "TraceResult", "TraceSnapshot", "SHORT_CONTOUR"]

#: Contours with fewer points than this whose corner detection fails are fitted without corners.
SHORT_CONTOUR = 64
#: Contours with fewer points than this skip corner detection when they take the small-outline path of
#: ``"lsq"`` (single pixels, dominos, specks, short diagonal chains): one periodic closed curve.
CORNERLESS_CONTOUR = 20


def _default_of(function, name):
    parameter = inspect.signature(function).parameters.get(name)
    if parameter is None or parameter.default is inspect.Parameter.empty:
        return None
    return parameter.default


# ---------------------------------------------------------------------------------------------------
# result objects
# ---------------------------------------------------------------------------------------------------
@dataclass(eq=False)
class TraceSnapshot:
    """All boundaries at one iteration of knot insertion (the merged view for stepping).

    Attributes
    ----------
    iteration : int
        Iteration number (0 = the initial fit with corners only).
    snapshots : list of fitting.Snapshot
        Per boundary, the snapshot in force at this iteration: its own snapshot of that iteration, or its
        last one when the boundary finished earlier.
    finished : ndarray of bool
        Per boundary: it had already finished (no snapshot later than this iteration).
    """

    iteration: int
    snapshots: list
    finished: np.ndarray

    @property
    def bezier(self) -> np.ndarray:
        """All pieces of all boundaries, shape ``(pieces, 4, 2)``."""
        return np.concatenate([np.asarray(s.bezier, dtype=float) for s in self.snapshots], axis=0)

    @property
    def piece_boundary(self) -> np.ndarray:
        """Boundary index of every row of :attr:`bezier`."""
        counts = [len(s.bezier) for s in self.snapshots]
        return np.repeat(np.arange(len(counts)), counts)

    @property
    def piece_max_error(self) -> np.ndarray:
        """Thesis error of every piece (spline point vs its contour point), concatenated."""
        return np.concatenate([np.asarray(s.piece_max_error, dtype=float) for s in self.snapshots])

    @property
    def piece_hausdorff(self) -> np.ndarray:
        """Geometric deviation (two-sided, px) of every piece, concatenated."""
        return np.concatenate([np.asarray(s.piece_hausdorff, dtype=float) for s in self.snapshots])

    @property
    def knots(self) -> int:
        """Number of knots (corners included) over all boundaries."""
        return int(sum(_knot_count(s.knot_indices) for s in self.snapshots))

    @property
    def max_error(self) -> float:
        return float(self.piece_max_error.max(initial=0.0))

    @property
    def hausdorff(self) -> float:
        return float(self.piece_hausdorff.max(initial=0.0))

    def splines(self) -> list:
        """The curve of every boundary at this iteration (:class:`~splinecraft.spline.Spline`)."""
        return [s.spline() for s in self.snapshots]

    def to_svg(self, width, height, *, decimals=4) -> str:
        """SVG of the outline at this iteration (same frame and form as :meth:`TraceResult.to_svg`)."""
        return svg_document(path_data([s.bezier for s in self.snapshots], decimals=decimals), width, height)


@dataclass(eq=False)
class TraceResult:
    """Everything :func:`trace` computed (docs/capture.md).

    Attributes
    ----------
    mask : ndarray (H, W) bool
        The binarized bitmap (True = ink).
    boundaries : list of Boundary
        Outer boundaries and holes of all components (see :func:`trace_boundaries`).
    points : list of ndarray (n, 2)
        The contour fitted for each boundary (``Boundary.outline`` or ``Boundary.pixels``).
    corners : list of ndarray of int
        Corner indices into ``points[k]``.
    fits : list of fitting.FitResult
        Per boundary: pieces, knot indices, snapshots, errors, convergence.
    splines : list of Spline
        The final closed curve of every boundary, in the pixel frame.
    snapshots : list of TraceSnapshot
        Merged per-iteration view (iteration 0 .. max over boundaries); empty when
        ``keep_snapshots=False``. The last one equals the result.
    boundary_snapshots : list of list of fitting.Snapshot
        Per boundary, its own snapshots (``fits[k].snapshots``).
    stats : dict
        The columns of thesis tables 4.1-4.61 and more; see :func:`trace`.
    params : dict
        The settings used (defaults resolved to names).
    notes : list of str
        Fallbacks taken (e.g. a contour too short for corner detection).
    """

    mask: np.ndarray
    boundaries: list
    points: list
    corners: list
    fits: list
    splines: list
    snapshots: list
    stats: dict
    params: dict
    notes: list = field(default_factory=list)

    @property
    def width(self) -> int:
        return int(self.mask.shape[1])

    @property
    def height(self) -> int:
        return int(self.mask.shape[0])

    @property
    def boundary_snapshots(self) -> list:
        return [list(fit.snapshots) for fit in self.fits]

    def bezier(self) -> list:
        """Bézier control points of every boundary's final curve, a list of ``(m, 4, 2)`` arrays."""
        return [spline.bezier() for spline in self.splines]

    def svg_path_data(self, *, decimals=4) -> str:
        """The ``d`` attribute of :meth:`to_svg`: one closed subpath of cubic Béziers per boundary."""
        return path_data(self.bezier(), decimals=decimals)

    def to_svg(self, *, decimals=4, fill="black", title=None) -> str:
        """Standalone SVG: one ``<path>`` of exact cubic Béziers, ``fill-rule="evenodd"`` (holes stay
        empty), ``width``/``height``/``viewBox`` = the bitmap size in its pixel frame.

        ``decimals`` rounds coordinates (``None``: exact floats).
        """
        return svg_document(self.svg_path_data(decimals=decimals), self.width, self.height, fill=fill,
                            title=title)

    def to_dict(self, *, include_points=False, include_snapshots=False) -> dict:
        """JSON-able summary: size, settings, stats and, per boundary, its chain code, corners, knots and
        final spline (``Spline.to_dict``). Optionally the fitted contour points and all snapshots.
        Non-finite numbers become ``None``.
        """
        boundaries = []
        for k, (boundary, points, corner_idx, fit, spline) in enumerate(
            zip(self.boundaries, self.points, self.corners, self.fits, self.splines)
        ):
            entry = {
                "index": k,
                "is_hole": bool(boundary.is_hole),
                "parent": boundary.parent,
                "component": int(boundary.component),
                "connectivity": int(boundary.connectivity),
                "area": int(boundary.area),
                "chain_start": list(boundary.start),
                "chain_code": boundary.chain_string,
                "contour_points": int(len(points)),
                "corners": np.asarray(corner_idx).tolist(),
                "pieces": [[int(a), int(b)] for a, b in fit.pieces],
                "knot_indices": [np.asarray(k_idx).tolist() for k_idx in fit.knot_indices],
                "knots_inserted": int(fit.knots_inserted),
                "iterations": int(fit.iterations),
                "converged": bool(fit.converged),
                "max_error": _finite_or_none(fit.max_error),
                "hausdorff": _finite_or_none(fit.hausdorff),
                "spline": spline.to_dict(),
            }
            if include_points:
                entry["points"] = np.asarray(points).tolist()
            if include_snapshots:
                entry["snapshots"] = [_snapshot_dict(s) for s in fit.snapshots]
            boundaries.append(entry)
        return _jsonable({
            "type": "splinecraft.TraceResult",
            "version": 1,
            "width": self.width,
            "height": self.height,
            "params": self.params,
            "stats": self.stats,
            "notes": list(self.notes),
            "boundaries": boundaries,
            "svg_path": self.svg_path_data(decimals=None),
        })

    def to_json(self, *, indent=None, include_points=False, include_snapshots=False) -> str:
        """:meth:`to_dict` as strict JSON (no NaN)."""
        return json.dumps(
            self.to_dict(include_points=include_points, include_snapshots=include_snapshots),
            indent=indent, allow_nan=False,
        )

    def __repr__(self) -> str:
        s = self.stats
        return (
            f"TraceResult({self.width}x{self.height}, boundaries={s['boundaries']} (holes={s['holes']}), "
            f"contour_points={s['contour_points']}, corners={s['corners']}, "
            f"knots_inserted={s['knots_inserted']}, iterations={s['iterations']}, segments={s['segments']}, "
            f"hausdorff={s['hausdorff']:.3g} px, time={s['time_s'] * 1e3:.1f} ms)"
        )


def _knot_count(knot_indices) -> int:
    """Distinct knots (corners included) of one outline: the distinct contour indices over all pieces."""
    arrays = [np.asarray(k, dtype=np.int64).reshape(-1) for k in knot_indices]
    return int(np.unique(np.concatenate(arrays)).size) if arrays else 0


def _finite_or_none(value):
    value = float(value)
    return value if math.isfinite(value) else None


def _jsonable(value):
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return _finite_or_none(value)
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return str(value)


def _snapshot_dict(snapshot) -> dict:
    return _jsonable({
        "iteration": snapshot.iteration,
        "knot_indices": [np.asarray(k) for k in snapshot.knot_indices],
        "bezier": np.asarray(snapshot.bezier),
        "piece_max_error": np.asarray(snapshot.piece_max_error),
        "piece_hausdorff": np.asarray(snapshot.piece_hausdorff),
        "candidates": list(snapshot.candidates),
    })


# ---------------------------------------------------------------------------------------------------
# trace
# ---------------------------------------------------------------------------------------------------
def trace(
    image,
    *,
    epsilon=DEFAULT_EPSILON,
    method=None,
    corner_method=None,
    corner_params=None,
    seed=0,
    max_iterations=200,
    keep_snapshots=True,
    connectivity=8,
    threshold=None,
    invert=False,
    min_speck_area=0,
    tau=None,
    contour="outline",
    fit_params=None,
) -> TraceResult:
    """Trace the outline of a bitmap into smooth closed splines (thesis chapter 4; docs/capture.md).

    Parameters
    ----------
    image : path, file object, ndarray or PIL image
        See :func:`~splinecraft.capture.image.load_bitmap`.
    epsilon : float > 0
        Error threshold of knot insertion, px (thesis "threshold value" 1, 2, 3). The default is
        ``fitting.DEFAULT_EPSILON`` (0.8 px; the issue's signature says 2.0): the deviation is measured
        from the crack outline, itself up to ~0.5-0.7 px from the true outline, so 0.8 keeps the result
        within about 1 px of the true outline (see the fitting module's docstring and BENCHMARKS.md).
    method : str, optional
        Knot-insertion algorithm, a key of ``KNOT_METHODS`` (thesis Algs 4.1-4.6 and the team's own);
        ``None`` = the default of :func:`~splinecraft.capture.fitting.fit_outline`.
    corner_method : str, optional
        Corner detector, a key of ``CORNER_METHODS``; ``None`` = ``corners.CAPTURE_DEFAULT`` (the corner
        module's recommendation for outline capture, ``"tangent-jump"``). The thesis's detector is
        ``"srm05"``.
    corner_params : dict, optional
        Parameters of the corner detector (e.g. ``{"zct": 7, "dt": 5, "ta": 152}`` for SRM05).
    seed : int >= 0 or None
        Seed of the random algorithms. Boundary ``k`` uses the independent child seed
        ``SeedSequence(seed, spawn_key=(k,))``, so runs with the same seed are identical.
    max_iterations : int >= 1
        Bound on knot-insertion iterations per boundary (never a hang).
    keep_snapshots : bool
        Keep every iteration (per boundary, and the merged :attr:`TraceResult.snapshots`).
    connectivity : {8, 4}
        Ink connectivity of the tracer (and of speck removal).
    threshold, invert, min_speck_area
        Binarization, see :func:`~splinecraft.capture.image.load_bitmap`.
    tau : float, optional
        Distance constraint of Algs 4.2 / 4.3, passed to ``fit_outline``.
    contour : {"outline", "pixels"}
        Fit the crack outline (edge midpoints, default) or the chain of boundary pixel centres.
    fit_params : dict, optional
        Further keyword arguments for ``fit_outline`` (engine parameters). ``small_outline`` (default
        ``fitting.SMALL_OUTLINE`` = 64; 0 = off) sets the contour length below which ``"lsq"`` boundaries are
        fitted together by ``fitting.fit_small_outlines``.

    Returns
    -------
    TraceResult
        With ``stats``:

        * ``contour_points``: points on all fitted contours (thesis "total number of points on contour");
        * ``corners``: corner points; ``knots_inserted``: knots added by the algorithm (corners excluded);
        * ``iterations``: the largest number of iterations of any boundary (boundaries are refined side
          by side, as in the merged snapshots); ``time_s``: wall time of the whole call
          (``time_breakdown`` splits it: load, boundaries, corners, fit);
        * ``segments``: cubic Bézier pieces in the output;
        * ``data_reduction_pct`` = ``100 (1 - stored numbers / contour numbers)``, where the stored
          numbers are the coordinates of the output's Bézier control points (6 per piece of a closed
          curve: two control points and the end point) and the contour numbers are the coordinates of the
          contour points (2 each): ``100 (1 - 3 segments / contour_points)``;
        * ``data_reduction_pct_thesis`` = ``100 (1 - knots_inserted / contour_points)``, the quantity of
          thesis Table 4.61 (it reproduces the table from Tables 4.31-4.60, e.g. 1 - 652/1644 = 60.34 %
          for Alg 4.1, 'Ali', threshold 1);
        * ``max_error`` (thesis error, spline point vs its contour point) and ``hausdorff`` (true
          two-sided geometric deviation, px): maxima over boundaries; ``converged``: all boundaries met
          ``epsilon``; counts of ``boundaries``, ``outer`` and ``holes``; ``per_boundary`` details
          (with ``small_outline``: fitted by the small-outline path, and ``reason``: why the boundary did
          not converge, ``None`` when it did).

    Raises
    ------
    ValueError
        ``epsilon <= 0``, unknown method names, bad options, unreadable images, and
        ``"no shape found"`` when the bitmap has no ink (e.g. all white).
    TypeError
        Options of the wrong type.
    """
    started = time.perf_counter()
    epsilon = _check_epsilon(epsilon)
    max_iterations = _check_int(max_iterations, "max_iterations", minimum=1)
    if not isinstance(keep_snapshots, (bool, np.bool_)):
        raise TypeError(f"keep_snapshots must be a bool, got {type(keep_snapshots).__name__}")
    if isinstance(connectivity, bool) or connectivity not in (4, 8):
        raise ValueError(f"connectivity must be 4 or 8, got {connectivity!r}")
    if contour not in ("outline", "pixels"):
        raise ValueError(f"contour must be 'outline' or 'pixels', got {contour!r}")
    if seed is not None:
        seed = _check_int(seed, "seed")
    method_name = method if method is not None else _default_of(fit_outline, "method")
    if method is not None and method not in KNOT_METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {sorted(KNOT_METHODS)}")
    if corner_method is None:  # the corner module's recommendation for outline capture
        corner_method = CORNER_CAPTURE_DEFAULT
    corner_name = corner_method
    if corner_method not in CORNER_METHODS:
        raise ValueError(f"unknown corner_method {corner_method!r}; choose one of {sorted(CORNER_METHODS)}")
    corner_params = _check_params(corner_params, "corner_params")
    fit_params = _check_params(fit_params, "fit_params")

    mask = load_bitmap(image, threshold=threshold, invert=invert, min_speck_area=min_speck_area,
                       connectivity=connectivity)
    loaded = time.perf_counter()
    boundaries = trace_boundaries(mask, connectivity=connectivity)
    traced = time.perf_counter()
    if not boundaries:
        raise ValueError(
            "no shape found: the bitmap has no ink pixels after thresholding "
            f"(an all-white image? ink is {'light' if invert else 'dark'}; see threshold/invert)"
        )

    small_limit = _small_limit(method_name, fit_params)
    notes = []
    points_list, corner_list, small = [], [], []
    for k, boundary in enumerate(boundaries):
        points = boundary.outline if contour == "outline" else boundary.pixels
        if len(points) < 4:  # pixel chains of tiny components: fall back to the crack outline
            notes.append(f"boundary {k}: pixel chain has {len(points)} point(s); fitted its crack outline")
            points = boundary.outline
        points_list.append(np.asarray(points, dtype=float))
        if len(points) < small_limit:
            small.append(k)
        if len(points) < min(small_limit, CORNERLESS_CONTOUR):
            corner_list.append(np.zeros(0, dtype=np.intp))
        else:
            corner_list.append(_detect(points_list[-1], k, corner_method, corner_params, notes))
    if small:
        skipped = sum(len(points_list[k]) < CORNERLESS_CONTOUR for k in small)
        notes.append(
            f"{len(small)} boundar{'y' if len(small) == 1 else 'ies'} of fewer than {small_limit} contour points "
            "fitted together by the small-outline path of 'lsq' (fitting.fit_small_outlines: interpolant through "
            "contour points, corners interpolated; stats['per_boundary'][k]['small_outline'])"
            + (f"; {skipped} of them (fewer than {CORNERLESS_CONTOUR} points) without corner detection, as one "
               "closed periodic curve" if skipped else ""))
    cornered = time.perf_counter()

    fits = [None] * len(points_list)
    if small:
        small_fits = fit_small_outlines([points_list[k] for k in small], [corner_list[k] for k in small],
                                        epsilon=epsilon, max_iterations=max_iterations,
                                        keep_snapshots=keep_snapshots)
        for k, fit in zip(small, small_fits):
            fits[k] = fit
    for k, (points, corner_idx) in enumerate(zip(points_list, corner_list)):
        if fits[k] is not None:
            continue
        kwargs = dict(fit_params)
        if method is not None:
            kwargs["method"] = method
        if tau is not None:
            kwargs["tau"] = tau
        try:
            fit = fit_outline(
                points, corner_idx, closed=True, epsilon=epsilon, seed=_child_seed(seed, k),
                max_iterations=max_iterations, keep_snapshots=keep_snapshots, **kwargs,
            )
        except ValueError as exc:
            raise ValueError(f"boundary {k} ({len(points)} points, {len(corner_idx)} corners): {exc}") from exc
        fits[k] = fit
    finished = time.perf_counter()

    splines = [fit.spline for fit in fits]
    merged = _merge_snapshots(fits) if keep_snapshots else []
    stats = _stats(boundaries, points_list, corner_list, fits, splines, max_iterations)
    for k, entry in enumerate(stats["per_boundary"]):
        if entry["reason"] is not None:
            notes.append(f"boundary {k} ({entry['contour_points']} points) did not converge: {entry['reason']}")
    stats["time_s"] = finished - started
    stats["time_breakdown"] = {
        "load_s": loaded - started, "boundaries_s": traced - loaded,
        "corners_s": cornered - traced, "fit_s": finished - cornered,
    }
    params = {
        "epsilon": epsilon, "method": method_name, "corner_method": corner_name,
        "corner_params": dict(corner_params), "seed": seed, "max_iterations": max_iterations,
        "connectivity": connectivity, "threshold": threshold, "invert": bool(invert),
        "min_speck_area": min_speck_area, "tau": tau, "contour": contour, "fit_params": dict(fit_params),
    }
    return TraceResult(mask=mask, boundaries=boundaries, points=points_list, corners=corner_list, fits=fits,
                       splines=splines, snapshots=merged, stats=stats, params=_jsonable(params), notes=notes)


def _small_limit(method_name, fit_params):
    """Contours with fewer points than this take the small-outline path (0 for the thesis methods); the
    ``fit_params`` are checked here once, as ``fit_outline`` would (the batch does not use them)."""
    if method_name != "lsq":
        return 0
    options = dict(fit_params)
    limit = options.pop("small_outline", SMALL_OUTLINE)
    if isinstance(limit, bool) or not isinstance(limit, numbers.Integral) or limit < 0:
        raise ValueError(f"fit_params['small_outline'] must be an integer >= 0, got {limit!r}")
    _check_options("lsq", options)
    return int(limit)


def _detect(points, k, corner_method, corner_params, notes):
    """Corner indices of one contour; contours too short for the detector get none (closed periodic fit)."""
    kwargs = dict(corner_params, method=corner_method)
    try:
        found = detect_corners(points, closed=True, **kwargs)
    except ValueError as exc:
        if len(points) >= SHORT_CONTOUR:
            raise ValueError(f"boundary {k}: corner detection failed: {exc}") from exc
        notes.append(f"boundary {k}: {len(points)} points are too few for corner detection ({exc}); "
                     "fitted as one closed periodic curve without corners")
        return np.zeros(0, dtype=np.intp)
    return np.asarray(found, dtype=np.intp)


def _child_seed(seed, k):
    if seed is None:
        return None
    return int(np.random.SeedSequence(seed, spawn_key=(k,)).generate_state(1, dtype=np.uint32)[0])


def _merge_snapshots(fits) -> list:
    """One TraceSnapshot per iteration 0 .. max, each boundary at its latest snapshot up to then."""
    per_boundary = [list(fit.snapshots) for fit in fits]
    if any(not snaps for snaps in per_boundary):
        return []
    iterations = [np.array([s.iteration for s in snaps]) for snaps in per_boundary]
    last = max(int(it[-1]) for it in iterations)
    merged = []
    for iteration in range(last + 1):
        chosen, finished = [], []
        for snaps, its in zip(per_boundary, iterations):
            position = max(int(np.searchsorted(its, iteration, side="right")) - 1, 0)
            chosen.append(snaps[position])
            finished.append(iteration >= its[-1])
        merged.append(TraceSnapshot(iteration=iteration, snapshots=chosen, finished=np.array(finished)))
    return merged


def _unconverged_reason(fit, max_iterations):
    """Why a boundary's fit did not converge (``None`` when it did)."""
    if fit.converged:
        return None
    if fit.info.get("reason"):
        return str(fit.info["reason"])
    if fit.iterations >= max_iterations:
        return f"max_iterations={max_iterations} reached with a deviation of {fit.hausdorff:.3g} px"
    return (f"knot insertion stopped after {fit.iterations} iterations with a deviation of {fit.hausdorff:.3g} px: "
            "no failing interval could take another knot (knots must stay min_gap contour steps apart) and no "
            "corner was left to release")


def _stats(boundaries, points_list, corner_list, fits, splines, max_iterations) -> dict:
    contour_points = int(sum(len(p) for p in points_list))
    knots_inserted = int(sum(int(fit.knots_inserted) for fit in fits))
    segments = int(sum(s.n_segments for s in splines))
    holes = int(sum(b.is_hole for b in boundaries))
    return {
        "boundaries": len(boundaries),
        "outer": len(boundaries) - holes,
        "holes": holes,
        "contour_points": contour_points,
        "corners": int(sum(len(c) for c in corner_list)),
        "knots_inserted": knots_inserted,
        "iterations": int(max(int(fit.iterations) for fit in fits)),
        "segments": segments,
        "data_reduction_pct": 100.0 * (1.0 - 6.0 * segments / (2.0 * contour_points)),
        "data_reduction_pct_thesis": 100.0 * (1.0 - knots_inserted / contour_points),
        "max_error": float(max(float(fit.max_error) for fit in fits)),
        "hausdorff": float(max(float(fit.hausdorff) for fit in fits)),
        "converged": bool(all(bool(fit.converged) for fit in fits)),
        "per_boundary": [
            {
                "is_hole": bool(b.is_hole), "contour_points": int(len(p)), "corners": int(len(c)),
                "knots_inserted": int(fit.knots_inserted), "iterations": int(fit.iterations),
                "segments": int(s.n_segments), "max_error": float(fit.max_error),
                "hausdorff": float(fit.hausdorff), "converged": bool(fit.converged),
                "small_outline": bool(fit.info.get("small_outline", False)),
                "reason": _unconverged_reason(fit, max_iterations),
            }
            for b, p, c, fit, s in zip(boundaries, points_list, corner_list, fits, splines)
        ],
    }


# ---------------------------------------------------------------------------------------------------
# validation
# ---------------------------------------------------------------------------------------------------
def _check_epsilon(epsilon):
    if isinstance(epsilon, (bool, np.bool_)) or not isinstance(epsilon, numbers.Real):
        raise TypeError(f"epsilon must be a positive number (px), got {type(epsilon).__name__}")
    epsilon = float(epsilon)
    if not math.isfinite(epsilon) or epsilon <= 0:
        raise ValueError(f"epsilon must be a finite number > 0 (px), got {epsilon!r}")
    return epsilon


def _check_int(value, name, minimum=0):
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an int >= {minimum}, got {type(value).__name__}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


def _check_params(params, name):
    if params is None:
        return {}
    if not isinstance(params, dict) or not all(isinstance(k, str) for k in params):
        raise TypeError(f"{name} must be a dict of keyword arguments, got {type(params).__name__}")
    return dict(params)
