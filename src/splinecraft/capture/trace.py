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
* all-white image (no ink after thresholding): ``ValueError("no shape found ...")``; when the ink there was
  all went to speck removal (``min_speck_area`` above every ink component), the message says so: how many
  pixels, the largest component's size, and the ``min_speck_area`` that keeps it;
* all-black image (every pixel ink): the ink is the whole frame, the result is the frame rectangle (4 corners)
  and a note in :attr:`TraceResult.notes` says so;
* small outlines (fewer than ``fitting.SMALL_OUTLINE`` = 64 contour points: single pixels, dominos, specks,
  short diagonal chains) with the default method ``"lsq"``: all fitted together by
  :func:`~splinecraft.capture.fitting.fit_small_outlines` (interpolant through contour points with knot
  insertion, corners interpolated or, where acute, extrapolated tips, at pixel corners the vertex; converged
  means within ``epsilon`` except
  in a tip's zone); below
  :data:`CORNERLESS_CONTOUR` = 20 points without corner detection, as one closed periodic curve, except for
  their pixel corners (tangent-jump's step 9, docs/capture.md §11: a block of 3 x 3 to 4 x 5 pixels is its
  rectangle; strokes 1-2 px wide have none). Any other
  contour too short for the corner detector: no corners, one closed periodic curve. Both are recorded in
  :attr:`TraceResult.notes`;
* 1-pixel-wide lines: the crack outline goes round the line (a thin closed shape of width 1);
* empty arrays, non-image or truncated files: ``ValueError`` / ``FileNotFoundError`` from
  :func:`~splinecraft.capture.image.load_bitmap`, naming the file;
* ``epsilon`` below ``fitting.MIN_EPSILON`` (0.001 px; also ``<= 0``, NaN, inf): ``ValueError`` naming it.
  ``max_iterations`` bounds the knot insertion, so a run never hangs; an unconverged boundary is reported in
  ``stats["converged"]``, and ``stats["per_boundary"][k]["reason"]`` (also in :attr:`TraceResult.notes`) says
  why it did not converge.

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
``min_speck_area`` removes specks. Corner detection and fitting together run within ``time_budget``
(default 5 s, docs/capture.md §12, "Time budget"): the boundaries it leaves get the polygon of their contour,
reported per boundary in ``stats["per_boundary"][k]["budget"]``, so a noise image of any size ends in time
linear in its size (figures in BENCHMARKS.md, "Time budget").
"""
from __future__ import annotations

import time

import numpy as np

from .. import _validation
from . import _interpreted, _jit
from .contour import Boundaries, check_connectivity, trace_boundaries
from .trace_stats import trace_stats
from .corners import CAPTURE_DEFAULT as CORNER_CAPTURE_DEFAULT
from .corners import CORNER_METHODS
from .corners import check_params as check_corner_params
from .corners import corners as detect_corners
from .corners._jump import checked_detection_scale
from .fitting import DEFAULT_EPSILON, DEFAULT_METHOD, SMALL_OUTLINE, fit_trusted, routes_to_small, unstuck
from .fitting.options import LSQ_DEFAULTS, check_count, check_epsilon, check_flag, check_method, check_options, \
    check_points, check_small_outline, check_tau, extrapolates_tips, make_rng
from .fitting.budget import DEFAULT_TIME_BUDGET, SMALL_CHUNK, STOPPED_FIT_LIMIT, Deadline, polygon_fits
from .fitting.tips import MAX_TIP_REACH
from .fitting.results import BoundaryList
from .fitting.noise import CLEAN_NOISE, NOISE_FACTOR, boundary_noise, noise_tolerance
from .fitting.small import fit_small_trusted, keeps_area
from .fitting._threads import one_blas_thread
from ._binarize import PINHOLE_AREA, drop_specks, fill_pinholes
from ._pixel_corners import merge_pixel_corners, pixel_corners_of_outlines
from .image import MAX_PIXELS, load_bitmap_reporting_specks
from .trace_result import TraceResult, TraceSnapshot, jsonable, merge_snapshots
from .trace_stages import TraceStages

__all__ = ["trace", "TraceResult", "TraceSnapshot", "SHORT_CONTOUR"]

#: The corners of a boundary without corner detection (one shared empty array).
_NO_CORNERS = np.zeros(0, dtype=np.intp)
_NO_CORNERS.flags.writeable = False
#: Contours with fewer points than this whose corner detection fails are fitted without corners.
SHORT_CONTOUR = 64
#: Contours with fewer points than this skip corner detection when they take the small-outline path of
#: ``"lsq"`` (single pixels, dominos, specks, short diagonal chains): one periodic closed curve, unless they
#: have pixel corners (tangent-jump's step 9, found for every boundary at once; docs/capture.md §12, "Small
#: outlines": a block of at least 3 x 3 pixels is its rectangle).
CORNERLESS_CONTOUR = 20
#: How the note of an image whose every pixel is ink begins (its outline is the frame: an all-black image, or a
#: mask whose True marks the background). ``trace_many`` and the command line pass it on as a warning line.
ALL_INK_NOTE = "every pixel is ink"
#: How the notes of a spent ``time_budget`` begin (boundaries left as polygons, knot rounds stopped). ``trace_many`` and
#: the command line pass them on as warning lines.
BUDGET_NOTE = "time budget of"


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
    connectivity="minority",
    threshold=None,
    invert=False,
    min_speck_area=None,
    tau=None,
    contour="outline",
    fit_params=None,
    noise_factor=NOISE_FACTOR,
    time_budget=DEFAULT_TIME_BUDGET,
    stages=None,
    max_pixels=MAX_PIXELS,
) -> TraceResult:
    """Trace the outline of a bitmap into smooth closed splines (thesis chapter 4; docs/capture.md).

    Parameters
    ----------
    image : path, file object, ndarray or PIL image
        See :func:`~splinecraft.capture.image.load_bitmap`.
    epsilon : float > 0
        Error threshold of knot insertion, px (thesis "threshold value" 1, 2, 3), at least
        ``fitting.MIN_EPSILON`` (0.001 px). The default is ``fitting.DEFAULT_EPSILON`` (0.8 px): the deviation
        is measured from the crack outline, itself up to ~0.5-0.7 px from the true outline, so 0.8 keeps the
        result within about 1 px of the true outline (docs/capture.md §12, "Default epsilon").
    method : str, optional
        Knot-insertion algorithm, a key of ``KNOT_METHODS`` (thesis Algs 4.1-4.6 and the deterministic
        default ``"lsq"``);
        ``None`` = the default of :func:`~splinecraft.capture.fitting.fit_outline`.
    corner_method : str, optional
        Corner detector, a key of ``CORNER_METHODS``; ``None`` = ``corners.CAPTURE_DEFAULT`` (the corner
        module's recommendation for outline capture, ``"tangent-jump"``). The thesis's detector is
        ``"srm05"``.
    corner_params : dict, optional
        Parameters of the corner detector (e.g. ``{"zct": 7, "dt": 5, "ta": 152}`` for SRM05). Names, types
        and ranges are checked before the image is read (the detector's own check,
        :func:`splinecraft.capture.corners.check_params`): a bad value raises naming the key and its range.
    seed : int >= 0 or None
        Seed of the random algorithms. Boundary ``k`` uses the independent child seed
        ``int(SeedSequence(seed, spawn_key=(k,)).generate_state(1, dtype=np.uint32)[0])`` (``fit_outline(...,
        seed=that)`` refits it alike), so runs with the same seed are identical.
    max_iterations : int >= 1
        Bound on knot-insertion iterations per boundary (never a hang).
    keep_snapshots : bool
        Keep every iteration (per boundary, and the merged :attr:`TraceResult.snapshots`).
    connectivity : {"minority", 8, 4}
        Ink connectivity of the tracer (and of speck removal): ``"minority"`` (default) joins, at each
        diagonal contact of pixels, the locally rarer colour, so hairlines stay whole and strokes touching
        at a corner leave no pinhole (:mod:`~splinecraft.capture.contour`); 8 or 4 fix it for the image.
        Another int or name is a ``ValueError``, a value of another type (``None``, ``8.0``) a ``TypeError``.
    threshold, invert, min_speck_area
        Binarization, see :func:`~splinecraft.capture.image.load_bitmap`. With ``min_speck_area=None``
        (default) the holes the tracer finds of fewer than ``PINHOLE_AREA`` (3) pixels are filled too, and its
        ink specks of fewer than 3 pixels dropped where a larger outline is left, on any input
        (``_binarize.fill_pinholes``, ``_binarize.drop_specks``; docs/capture.md §10, "Pinholes"; a note says
        how many); ``min_speck_area=0`` keeps every pixel.
    tau : float, optional
        Distance constraint of Algs 4.2 / 4.3, passed to ``fit_outline``.
    contour : {"outline", "pixels"}
        Fit the crack outline (edge midpoints, default) or the chain of boundary pixel centres.
    noise_factor : float >= 0
        Noisy boundaries (docs/capture.md §12, "Noisy boundaries"): when the boundary noise exceeds
        ``fitting.noise.CLEAN_NOISE`` (0.4 px) the fit's tolerance is ``max(epsilon, noise_factor * noise)``;
        ``noise`` is the 99.5th percentile of the distance from the crack outline to the boundary of the
        bitmap smoothed by a 1-px Gaussian (:func:`~splinecraft.capture.fitting.noise.boundary_noise`; about
        0.27 px on clean renderings, which keep ``epsilon``, 0.55-1.1 px on scans), leaving out the points
        beside hairlines and gaps at most 2 px wide, which the blur erases (they are not noise). 0 turns the
        rule off. Above ``CLEAN_NOISE`` the corner tips also follow the pixels instead of being extrapolated
        (``fit_params["geometric_corners"]``, default ``"clean"``; ``stats["extrapolated_tips"]``), and the
        corners of tangent-jump are detected again at the scale of each boundary's noise
        (:func:`~splinecraft.capture.corners.detection_scale`; ``stats["per_boundary"][k]["corner_scale"]``;
        ``corner_params={"scale": 1}`` keeps the pixel scale); a boundary seen at scale ``k > 1`` is fitted
        with the tolerance ``max(tolerance, k * min(epsilon, DEFAULT_EPSILON))``
        (``stats["per_boundary"][k]["tolerance"]``: the clean staircase it is at that scale, not a multiple of an
        epsilon the caller raised), and the square ends of strokes 1-2 px wide are not pixel corners (at that
        noise they are a speck's). ``corner_params={"scale": k}`` sets the scale of every boundary (no pixel
        corners above 1; the same tolerance rule).
    time_budget : float > 0 or None
        Seconds for corner detection and fitting of all boundaries together (not the noise estimate, unless
        corner detection used up its half; docs/capture.md §12, "Time budget"; default
        ``fitting.budget.DEFAULT_TIME_BUDGET`` = 5 s; ``None``: no budget). Boundaries started within it get
        their full fit, whose knot rounds stop when it runs out (``reason`` says so);
        the boundaries left get the polygon of their contour (straight pieces between its turning points,
        deviation 0, no corner detection). ``stats["per_boundary"][k]["budget"]`` is ``None``,
        ``"stopped"`` or ``"polygon"``, and ``stats["time_per_boundary_s"][k]`` is the boundary's corner and
        fit time (the small outlines of a batch share its time evenly).
    fit_params : dict, optional
        Further options of ``fit_outline`` (its ``**options`` and ``small_outline``; the arguments of
        :func:`trace` itself are not accepted here). ``small_outline`` (default
        ``fitting.SMALL_OUTLINE`` = 64; 0 = off) sets the contour length below which ``"lsq"`` boundaries are
        fitted together by ``fitting.fit_small_outlines``.
    max_pixels : int >= 1
        Largest image decoded from a file, bytes or PIL image (default ``image.MAX_PIXELS`` = 10^8), checked
        on its header before any pixel is decoded (a decompression bomb costs nothing): a larger one is a
        ``ValueError``. See :func:`~splinecraft.capture.image.load_bitmap`; it changes no result, so it is not
        in :attr:`TraceResult.params`.
    stages : :class:`~splinecraft.capture.trace_stages.TraceStages`, optional
        Keeps the boundaries, corners and boundary noise of this call for the next one with the same bitmap
        and the same settings of those stages (a re-trace after a change of ``epsilon``, ``method``, ``seed``
        ...: docs/capture.md §13, "Re-tracing"); the result is the one without it. ``None``: nothing kept.

    Returns
    -------
    TraceResult
        With ``stats``:

        * ``contour_points``: points on all fitted contours (thesis "total number of points on contour");
        * ``corners``: corner points; ``knots_inserted``: knots added by the algorithm (corners excluded);
        * ``iterations``: the largest number of iterations of any boundary (boundaries are refined side
          by side, as in the merged snapshots); ``time_s``: wall time of the whole call
          (``time_breakdown`` splits it: load, boundaries, corners, noise estimate, fit);
        * ``segments``: cubic Bézier pieces in the output;
        * ``data_reduction_pct`` = ``100 (1 - stored numbers / contour numbers)``, where the stored
          numbers are the coordinates of the output's Bézier control points (6 per piece of a closed
          curve: two control points and the end point) and the contour numbers are the coordinates of the
          contour points (2 each): ``100 (1 - 3 segments / contour_points)``;
        * ``data_reduction_pct_thesis`` = ``100 (1 - knots_inserted / contour_points)``, the quantity of
          thesis Table 4.61 (it reproduces the table from Tables 4.31-4.60, e.g. 1 - 652/1644 = 60.34 %
          for Alg 4.1, 'Ali', threshold 1);
        * ``max_error`` (thesis error, spline point vs its contour point) and ``hausdorff`` (true
          two-sided geometric deviation, px): maxima over boundaries (a polygon of a spent ``time_budget``
          counts 0: it is its contour); ``converged``: all fitted boundaries met ``epsilon``;
          ``polygons``: the boundaries that got the polygon of their contour instead of a fit (a spent
          ``time_budget``; 0 otherwise; a note says so too); counts of ``boundaries``, ``outer`` and ``holes``; ``per_boundary`` details
          (with ``small_outline``: fitted by the small-outline path, ``reason``: why the boundary did
          not converge, ``None`` when it did, ``corner_scale`` and ``tolerance``: the scale of its corners
          and the tolerance of its fit, see ``noise_factor``);
        * ``boundary_noise`` and ``tolerance`` (``noise_factor``); ``extrapolated_tips``: whether the
          ``"lsq"`` fits extrapolated corner tips (``None`` for the thesis methods);
        * ``kernels``: ``"compiled"``, or ``"interpreted"`` for the first trace of a small bitmap on a cold kernel
          cache, which runs the kernels' Python source (the same result, without ``time_budget``) while a background
          process compiles them (docs/capture.md, "A cold first trace runs the kernels interpreted").

    Raises
    ------
    ValueError
        ``epsilon`` out of range, unknown method names, bad options, unreadable images, and
        ``"no shape found"`` when the bitmap has no ink (e.g. all white).
    TypeError
        Options of the wrong type.
    """
    started = time.perf_counter()
    settings = _check_arguments(epsilon=epsilon, method=method, corner_method=corner_method,
                                corner_params=corner_params, seed=seed, max_iterations=max_iterations,
                                keep_snapshots=keep_snapshots, connectivity=connectivity, tau=tau, contour=contour,
                                fit_params=fit_params)
    connectivity = settings["connectivity"]  # as checked: 4, 8 or "minority"
    noise_factor = _validation.check_number(noise_factor, "noise_factor", minimum=0.0)
    if time_budget is not None:
        time_budget = _validation.check_number(time_budget, "time_budget", minimum=0.0, inclusive=False)
    max_pixels = _validation.check_int(max_pixels, "max_pixels", minimum=1)
    if stages is not None and not isinstance(stages, TraceStages):
        raise TypeError(f"stages must be a TraceStages or None, got {type(stages).__name__}")
    stages = TraceStages(0) if stages is None else stages
    mask, specks_removed_all = load_bitmap_reporting_specks(image, threshold=threshold, invert=invert,
                                                            min_speck_area=min_speck_area, connectivity=connectivity,
                                                            max_pixels=max_pixels)
    if specks_removed_all is not None:  # rather than "no ink after thresholding": there was ink
        raise ValueError(specks_removed_all.message())
    loaded = time.perf_counter()
    # the kernels compiled or loaded before the tracer and the budget start (the first call of a
    # process; cold ones in parallel processes, _jit.warm_up); not counted in any stage of time_breakdown
    tasks = _jit.TRACE_TASKS
    if settings["method"] == "lsq" and settings["fit_params"].get("merge_tolerance",
                                                                     LSQ_DEFAULTS["merge_tolerance"]) > 0:
        tasks += ("merge",)  # where segment merging runs (the default of lsq; merge_tolerance=0 turns it off)
    if settings["corner_method"] == "tangent-jump":
        tasks += ("corners", "pixel corners")
    # a small bitmap on a cold kernel cache: the kernels interpreted while a background process compiles them
    # (_jit.warm_up, capture._interpreted), the same results; without the time budget, which the interpreter's
    # pace would spend where the compiled kernels' does not (a bitmap this small takes milliseconds compiled)
    interpreted = _jit.warm_up(tasks, interpret=lambda: _interpretable(mask))  # asked only when kernels are cold

    def run(mask, budget, interpreted):
        warmed = time.perf_counter()
        key = (stages.mask_key(mask), connectivity, min_speck_area is None)
        (mask, boundaries, notes, pinholes), _ = stages.remember(
            "boundaries", key, lambda: _boundaries(mask, connectivity, min_speck_area, invert))
        traced = time.perf_counter()
        deadline = Deadline(budget)  # corner detection gets the first half of the budget
        key = (key, contour, _small_limit(settings), settings["corner_method"], settings["corner_params"], budget)
        corner_deadline = Deadline(None if budget is None else budget / 2)
        (points_list, corner_list, pixel_list, small, times, undetected, contour_notes), cached = stages.remember(
            "contours", key, lambda: _contours(boundaries, settings, corner_deadline),
            keep=lambda found: not found[5].any())  # kept only when every boundary got its corners
        notes += contour_notes
        if cached:
            times[:] = 0.0  # no corner detection in this call
        detected = time.perf_counter()
        # measured on the boundaries that got their corners: a boundary the corner deadline left without them
        # would count its corners as noise (the blurred iso-line cuts every corner)
        with_corners = np.flatnonzero(~undetected).tolist()

        def measure_noise():
            if noise_factor <= 0:
                return 0.0, {}, True
            noise = boundary_noise(mask, *_noise_contours(boundaries, points_list, corner_list, with_corners, contour))
            return (noise, *_coarse_corners(points_list, noise, undetected, settings, corner_deadline))

        (noise, coarse, _), _ = stages.remember("noise", (key, noise_factor > 0), measure_noise,
                                                keep=lambda found: not undetected.any() and found[2])
        corner_scale = np.ones(len(points_list))
        lengths = np.fromiter(map(len, points_list), np.int64, len(points_list))
        chosen_scale = float(settings["corner_params"].get("scale", 1.0)) \
            if settings["corner_method"] == "tangent-jump" else 1.0
        if chosen_scale != 1.0:     # the caller's scale: every boundary whose corners were detected
            corner_scale[lengths >= min(_small_limit(settings), CORNERLESS_CONTOUR)] = chosen_scale  # as _contours
            corner_scale[undetected] = 1.0
        for k, (scale, found) in coarse.items():
            corner_scale[k], corner_list[k] = scale, found
        if noise > CLEAN_NOISE:     # at this noise the square end of a 1-2 px stroke is a speck's: not a pixel corner
            _drop_stroke_end_corners(corner_list, pixel_list, corner_scale, lengths)
        if coarse:
            scales = corner_scale[list(coarse)]
            notes.append(f"boundary noise {noise:.2f} px: the corners of {len(coarse)} boundar"
                         f"{'y' if len(coarse) == 1 else 'ies'} detected at a coarser scale ({scales.min():g}"
                         f"{'' if scales.min() == scales.max() else f'-{scales.max():g}'} px, corners.detection_scale; "
                         "corner_params={'scale': 1} keeps the pixel scale)")
        if not undetected.any():  # the budget covers corners and fits, not the noise estimate, unless it is spent
            deadline.extend(time.perf_counter() - detected)  # already (noise images: the cap is what matters)
        settings["tolerance"] = noise_tolerance(settings["epsilon"], noise, noise_factor)
        # a boundary seen at the coarser scale k is fitted as the clean staircase it is there: the default epsilon
        # (or the caller's smaller one) in units of k, not a multiple of a raised epsilon
        tolerances = np.maximum(settings["tolerance"], corner_scale * min(settings["epsilon"], DEFAULT_EPSILON))
        if settings["tolerance"] > settings["epsilon"]:
            notes.append(f"boundary noise {noise:.2f} px: fitted with the tolerance {settings['tolerance']:.2f} px "
                         f"(noise_factor {noise_factor:g} x noise) instead of epsilon {settings['epsilon']:g}")
        tips = _resolve_tips(settings, noise)
        if tips is False and settings["options"]["geometric_corners"] == "clean":
            notes.append(f"boundary noise {noise:.2f} px: corner tips follow the pixels (geometric_corners='clean' "
                         f"extrapolates them on clean boundaries only; True extrapolates them anyway)")
        cornered = time.perf_counter()
        with one_blas_thread():  # set once for every fit (each would set and restore it)
            (fits, splines, polygons), budget_state, far = _fit_boundaries(points_list, corner_list, pixel_list, small,
                                                                           settings, deadline, times, undetected,
                                                                           tolerances, pinholes)
        _budget_notes(budget_state, time_budget, notes, far)
        finished = time.perf_counter()

        merged = merge_snapshots(fits) if settings["keep_snapshots"] else []
        stats = trace_stats(boundaries, points_list, corner_list, fits, polygons, budget_state, settings["max_iterations"])
        for k in polygons["fitted"]:
            entry = stats["per_boundary"][k]
            if entry["reason"] is not None:
                notes.append(f"boundary {k} ({entry['contour_points']} points) did not converge: {entry['reason']}")
        stats["time_per_boundary_s"] = times.tolist()
        for entry, scale, tolerance in zip(stats["per_boundary"], corner_scale.tolist(), tolerances.tolist()):
            entry["corner_scale"], entry["tolerance"] = scale, tolerance
        stats["boundary_noise"] = noise
        stats["extrapolated_tips"] = tips
        stats["tolerance"] = settings["tolerance"]
        stats["time_s"] = finished - started
        stats["kernels"] = "interpreted" if interpreted else "compiled"
        stats["time_breakdown"] = {
            "load_s": loaded - started, "boundaries_s": traced - warmed,
            "corners_s": detected - traced, "noise_s": cornered - detected, "fit_s": finished - cornered,
        }
        params = {
            "epsilon": settings["epsilon"], "method": settings["method"], "corner_method": settings["corner_method"],
            "corner_params": dict(settings["corner_params"]), "seed": settings["seed"],
            "max_iterations": settings["max_iterations"], "connectivity": connectivity, "threshold": threshold,
            "invert": bool(invert), "min_speck_area": min_speck_area, "tau": tau, "contour": contour,
            "fit_params": dict(settings["fit_params"]), "noise_factor": noise_factor,
            "time_budget": time_budget,
        }
        return TraceResult(mask=mask, boundaries=boundaries, points=points_list, corners=corner_list, fits=fits,
                           splines=splines, snapshots=merged, stats=stats, params=jsonable(params), notes=notes)

    if interpreted:
        try:
            return run(mask, None, True)
        except Exception as error:  # noqa: BLE001
            if not _interpreted.raised_in_kernel(error):
                raise
            # a kernel whose Python semantics differ from numba's (capture._interpreted): the compiled kernels
            # decide, and raise what is really wrong
            _jit.warm_up(tasks)
    return run(mask, time_budget, False)


#: The most cracks (pixel edges between ink and paper, :func:`_cracks_of`) of a bitmap whose first trace on a cold
#: kernel cache runs the kernels interpreted (:func:`._jit.warm_up`, ``interpret=True``); a larger one waits for
#: the compile. Fully interpreted, a trace takes 1.0-1.9 ms a crack (a 300-px glyph: 1600-2000 cracks; a 1200-px
#: glyph 6000-8300, a 1200-px ideograph 16 000-17 000), but it is not fully interpreted: the background compile
#: puts each kernel back compiled as soon as it is cached (:func:`._interpreted.restore_ready`), so only the kernel
#: calls that start before then run at the interpreter's pace. What bounds the wait is the longest such call, the
#: corners of one long boundary (0.3 ms a crack) after the tracer (0.1 ms a crack): a single wavy boundary of 15 600
#: cracks took 8.8 s at defaults against 19.5 s compiling first, one of 33 700 cracks 14.5 s against 20.7 s, where
#: the compile's 11-20 s (two CPUs, idle to loaded) no longer leaves a clear margin. Glyphs and noise are split into
#: many shorter calls: 1200-px glyphs 5.4-8.3 s against 11.2-26.6 s, an ideograph at 1200 px 9.4 s against 22.5 s,
#: noise bitmaps of 16 000 and 31 000 cracks 8.1 and 9.4 s against 17.9 and 17.2 s (BENCHMARKS.md, "Session 36:
#: the first call of large bitmaps"). 8000 until session 36, when the limit was set by the fully interpreted pace;
#: 4000 before session 33.
INTERPRET_CRACKS = 24000


def _cracks_of(mask):
    """The pixel edges between ink and paper of ``mask`` (bool, paper outside it)."""
    inner = np.count_nonzero(mask[:, 1:] != mask[:, :-1]) + np.count_nonzero(mask[1:] != mask[:-1])
    border = np.count_nonzero(mask[0]) + np.count_nonzero(mask[-1]) + np.count_nonzero(mask[:, 0]) \
        + np.count_nonzero(mask[:, -1])
    return int(inner + border)


def _interpretable(mask):
    """Whether the first trace of ``mask`` on a cold kernel cache may run the kernels interpreted
    (:data:`INTERPRET_CRACKS`)."""
    return _cracks_of(mask) <= INTERPRET_CRACKS


#: Arguments of :func:`~splinecraft.capture.fitting.fit_outline` that :func:`trace` sets itself.
_OWN_ARGUMENTS = ("closed", "epsilon", "method", "tau", "seed", "max_iterations", "keep_snapshots")


def _check_arguments(*, epsilon, method, corner_method, corner_params, seed, max_iterations, keep_snapshots,
                     connectivity, tau, contour, fit_params):
    """Every argument of :func:`trace` but the image ones, checked once; the fit below takes them as given."""
    epsilon = check_epsilon(epsilon)
    max_iterations = check_count(max_iterations, "max_iterations", 1)
    keep_snapshots = check_flag(keep_snapshots, "keep_snapshots")
    connectivity = check_connectivity(connectivity)
    _validation.check_choice(contour, "contour", ("outline", "pixels"))
    if seed is not None:
        seed = check_count(seed, "seed", 0)
    method_name = DEFAULT_METHOD if method is None else check_method(method)
    if corner_method is None:  # the corner module's recommendation for outline capture
        corner_method = CORNER_CAPTURE_DEFAULT
    corner_method = _validation.check_choice(corner_method, "corner_method", CORNER_METHODS)
    corner_params = _validation.check_options(corner_params, "corner_params", reserved=("closed", "method"),
                                              reserved_reason="trace sets it (corner_method= picks the detector)")
    corner_params = check_corner_params(corner_method, corner_params, "corner_params")
    fit_params = _validation.check_options(fit_params, "fit_params", reserved=_OWN_ARGUMENTS,
                                           reserved_reason="pass it to trace() itself")
    options = dict(fit_params)
    small_limit = check_small_outline(options.pop("small_outline", None), "fit_params['small_outline']", method_name)
    return {"epsilon": epsilon, "max_iterations": max_iterations, "keep_snapshots": keep_snapshots, "seed": seed,
            "method": method_name, "tau": check_tau(tau, method_name), "corner_method": corner_method,
            "corner_params": corner_params, "fit_params": fit_params,
            "options": check_options(method_name, options, "fit_params"),
            "small_outline": small_limit, "contour": contour, "connectivity": connectivity}


def _boundaries(mask, connectivity, min_speck_area, invert):
    """The boundaries of ``mask``, the mask with its pinholes filled and its specks dropped (when
    ``min_speck_area`` is ``None``), the notes of both and the centres ``(m, 2)`` of the filled pixels, sorted by x
    (empty: none filled; the notch tips of the fit, :func:`~.fitting.tips.tip_estimates`)."""
    boundaries = trace_boundaries(mask, connectivity=connectivity)
    if not boundaries:
        raise ValueError(
            "no shape found: the bitmap has no ink pixels after thresholding "
            f"(an all-white image? ink is {'light' if invert else 'dark'}; see threshold/invert; a light shape on a "
            "transparent background is composited on white: threshold='alpha' traces its opaque pixels)"
        )
    notes = []
    if len(boundaries) == 1 and mask.all():
        notes.append(f"{ALL_INK_NOTE}: the outline is the image's frame (an all-black image, or a mask whose "
                     f"True marks the background? ink is {'light' if invert else 'dark'}; see threshold/invert)")
    filled_centres = np.zeros((0, 2))
    if min_speck_area is None:
        unfilled = mask
        mask, boundaries, pinholes, specks = _without_pinholes(mask, boundaries, connectivity)
        if pinholes:
            rows, columns = np.nonzero(mask & ~unfilled)  # row-major: sorted by y, then x
            order = np.argsort(columns, kind="stable")
            filled_centres = np.column_stack([columns[order] + 0.5, rows[order] + 0.5])
        done = ([f"filled {pinholes} pinhole{'' if pinholes == 1 else 's'}"] if pinholes else []) + \
            ([f"dropped {specks} speck{'' if specks == 1 else 's'}"] if specks else [])
        if done:
            notes.append(f"{' and '.join(done)} of fewer than {PINHOLE_AREA} pixels (docs/capture.md §10, "
                         "'Pinholes'; min_speck_area=0 keeps them)")
    return mask, boundaries, notes, filled_centres


def _small_limit(settings):
    """The contour length below which boundaries take the small-outline path (0: none does)."""
    return settings["small_outline"] if settings["method"] == "lsq" else 0


def _contours(boundaries, settings, deadline):
    """The contour of every boundary, its corners, its pixel corners (a
    :class:`~._pixel_corners.PixelCorners`, found with tangent-jump's step 9, else ``None``: the fit finds them
    where it needs them), which boundaries take the small-outline path, the seconds of corner detection per
    boundary, which boundaries needed it but did not get it because ``deadline`` had passed, and the notes."""
    small_limit = _small_limit(settings)
    notes = []
    points_list = _contour_points(boundaries, settings["contour"], notes)
    lengths = np.fromiter(map(len, points_list), np.int64, len(points_list))
    small = np.flatnonzero(routes_to_small(settings["method"], lengths, small_limit)).tolist()  # the rule, all at once
    times = np.zeros(len(boundaries))
    undetected = np.zeros(len(boundaries), bool)
    detect = lengths >= min(small_limit, CORNERLESS_CONTOUR)
    corner_list = [_NO_CORNERS] * len(boundaries)
    pixel_list = [None] * len(boundaries)
    corner_params = settings["corner_params"]
    # tangent-jump's step 9, the pixel corners, for all boundaries at once (vectorized, in chunks), also for those
    # without corner detection; the detector itself runs without it, and the fit's corner tips take them from here
    pixel = settings["corner_method"] == "tangent-jump" and corner_params.get("pixel_corners", True) \
        and float(corner_params.get("scale", 1.0)) == 1.0  # a pixel is below a coarser scale
    if pixel:
        corner_params = dict(corner_params, pixel_corners=False)
        pixel_list = pixel_corners_of_outlines(points_list)
    for k in np.flatnonzero(detect).tolist():
        if deadline.passed():  # and so for every later boundary: they get no corners
            undetected[k:] = detect[k:]
            break
        started = time.perf_counter()
        corner_list[k] = _detect(points_list[k], k, settings["corner_method"], corner_params, notes)
        if pixel and pixel_list[k].index.size:
            corner_list[k] = merge_pixel_corners(corner_list[k], pixel_list[k].index, lengths[k])
        times[k] = time.perf_counter() - started
    if pixel:
        for k in np.flatnonzero(~detect).tolist():
            if pixel_list[k].index.size:
                corner_list[k] = pixel_list[k].index.astype(np.intp)
    if small:
        skipped = int((lengths[small] < CORNERLESS_CONTOUR).sum())
        notes.append(
            f"{len(small)} boundar{'y' if len(small) == 1 else 'ies'} of fewer than {small_limit} contour points "
            "fitted together by the small-outline path of 'lsq' (fitting.fit_small_outlines: interpolant through "
            "contour points, acute tips extrapolated where a pre-test passes, pixel corners at their vertex; "
            "stats['per_boundary'][k]['small_outline'])"
            + (f"; {skipped} of them (fewer than {CORNERLESS_CONTOUR} points) without corner detection, as one "
               "closed periodic curve unless they have pixel corners" if skipped else ""))
    return points_list, corner_list, pixel_list, small, times, undetected, notes


def _drop_stroke_end_corners(corner_list, pixel_list, corner_scale, lengths):
    """On a noisy bitmap: drop the pixel corners of the square ends of strokes 1-2 px wide (two pixel corners one
    or two points apart: other pixel corners are at least ``MIN_RUN`` apart, docs/capture.md §11 step 9) from the
    corners and pixel corners of the boundaries seen at the pixel scale (in place; ``lengths``: the points of
    each boundary). At that noise such an end is a speck's or a spike's: on the noisiest scans of
    ``bench_noisy_corners.py`` they were 124 false corners of 453 (``BENCHMARKS.md``, "Session 19").

    All boundaries at once (a noise image has some 100 000): a pixel corner is an end where the next one round
    its outline (the first one, a whole outline on) or the one before it lies at most 2 points away; the corners
    that are such ends are found by one look-up of (boundary, index) keys, and only the boundaries that lose
    some are rebuilt."""
    chosen = [k for k, found in enumerate(pixel_list)
              if found is not None and found.index.size >= 2 and corner_scale[k] == 1.0]
    if not chosen:
        return
    counts = np.fromiter((pixel_list[k].index.size for k in chosen), np.int64, len(chosen))
    index = np.concatenate([pixel_list[k].index for k in chosen]).astype(np.int64, copy=False)
    first = np.cumsum(counts) - counts
    last = first + counts - 1
    following = np.empty_like(index)  # the next pixel corner round the outline (the first, an outline on)
    following[:-1] = index[1:]
    following[last] = index[first] + lengths[chosen]
    near = following - index <= 2
    before = np.empty_like(near)  # whether the one before it (the last, an outline back) is near it
    before[1:] = near[:-1]
    before[first] = near[last]
    end = near | before
    losing = np.flatnonzero(np.add.reduceat(end.astype(np.int64), first) > 0)
    if not losing.size:
        return
    # the corners that are ends: keys (position among the losing boundaries, index), looked up at once
    span = int(lengths[chosen].max()) + 1
    own = np.repeat(np.arange(len(chosen)), counts)
    rank = np.full(len(chosen), -1, np.int64)
    rank[losing] = np.arange(losing.size)
    end_keys = rank[own[end]] * span + index[end]
    corners = [np.asarray(corner_list[chosen[b]]) for b in losing.tolist()]
    corner_counts = np.fromiter(map(len, corners), np.int64, len(corners))
    keys = np.repeat(np.arange(losing.size), corner_counts) * span + \
        np.concatenate(corners).astype(np.int64, copy=False) if corner_counts.sum() else np.zeros(0, np.int64)
    keep = ~np.isin(keys, end_keys)
    cuts = np.cumsum(corner_counts)[:-1].tolist()
    for b, kept in zip(losing.tolist(), np.split(keep, cuts)):
        k = chosen[b]
        found = pixel_list[k]
        rows = ~end[first[b]:last[b] + 1]
        corner_list[k] = corner_list[k][kept]
        pixel_list[k] = type(found)(found.index[rows], found.vertex[rows])


def _coarse_corners(points_list, noise, undetected, settings, deadline):
    """Corners detected again at the scale of the noise (docs/capture.md §12, "Noisy boundaries"): on a bitmap
    whose boundary noise exceeds ``CLEAN_NOISE``, every boundary the noise is measured on (at least
    ``SHORT_CONTOUR`` points, corners detected) whose :func:`~.corners.detection_scale` ``k`` exceeds 1 gets the
    corners of ``tangent_jump(..., scale=k)``; ``{boundary: (k, corners)}`` and whether every boundary was
    seen. Not with another detector or a ``scale`` in ``corner_params``, and no boundary once ``deadline`` has
    passed."""
    if noise <= CLEAN_NOISE or settings["corner_method"] != "tangent-jump" or "scale" in settings["corner_params"]:
        return {}, True
    coarse = {}
    for k, points in enumerate(points_list):
        if deadline.passed():
            return coarse, False
        if undetected[k] or len(points) < SHORT_CONTOUR:
            continue
        scale = checked_detection_scale(points)
        if scale > 1.0:
            coarse[k] = (scale, _detect(points, k, "tangent-jump", {**settings["corner_params"], "scale": scale}, []))
    return coarse, True


def _noise_contours(boundaries, points_list, corner_list, chosen, contour):
    """The contours and corners of the boundaries ``chosen`` that the noise estimate measures: their crack outlines,
    its reference (:func:`~.fitting.noise.boundary_noise`). With ``contour="pixels"`` the fitted contours are pixel
    chains, whose centres lie inside the crack outline (a clean disc read 0.75 px of noise instead of 0.27 and its
    tolerance went up): each chain's corners go to the nearest point of its crack outline."""
    if contour == "outline":
        return [points_list[k] for k in chosen], [corner_list[k] for k in chosen]
    from scipy.spatial import cKDTree

    outlines = _contour_points(boundaries, "outline", [])
    contours, corners = [], []
    for k in chosen:
        found = np.asarray(corner_list[k], dtype=np.int64)
        nearest = cKDTree(outlines[k]).query(points_list[k][found])[1] if found.size else found
        contours.append(outlines[k])
        corners.append(np.unique(np.asarray(nearest, dtype=np.int64)))
    return contours, corners


def _contour_points(boundaries, contour, notes):
    """The contour fitted for every boundary: its crack outline, or its pixel chain (``contour="pixels"``) where
    that has at least 4 points."""
    if contour == "outline":
        if isinstance(boundaries, Boundaries):
            return boundaries.outlines()  # float (n, 2) arrays already
        return [np.asarray(b.outline, dtype=float) for b in boundaries]
    points_list = []
    for k, boundary in enumerate(boundaries):
        points = boundary.pixels
        if len(points) < 4:  # pixel chains of tiny components: fall back to the crack outline
            notes.append(f"boundary {k}: pixel chain has {len(points)} point(s); fitted its crack outline")
            points = boundary.outline
        else:
            points = check_points(points)
        points_list.append(np.asarray(points, dtype=float))
    return points_list


def _resolve_tips(settings, noise):
    """Whether the ``"lsq"`` fits extrapolate corner tips (``fit_params["geometric_corners"]``, default
    ``"clean"``: where the boundary noise is at most ``CLEAN_NOISE``; :func:`.fitting.options.extrapolates_tips`);
    the choice goes into ``settings["fit_options"]`` as a plain bool. ``None`` for the thesis methods."""
    if settings["method"] != "lsq":
        settings["fit_options"] = settings["options"]
        return None
    tips = extrapolates_tips(settings["options"]["geometric_corners"], noisy=float(noise) > CLEAN_NOISE)
    settings["fit_options"] = dict(settings["options"], geometric_corners=tips)
    return tips


def _fit_boundaries(points_list, corner_list, pixel_list, small, settings, deadline, times, undetected, tolerances,
                    pinholes=None):
    """The fit of every boundary: the small ones together (in batches of ``SMALL_CHUNK``), the others one by
    one (trusted arguments, with their pixel corners ``pixel_list`` where the corner stage found them), each
    started only while ``deadline`` has not passed and with its corners detected (else its polygon); a fit whose
    knot rounds the deadline stopped more than ``STOPPED_FIT_LIMIT`` times its tolerance from its contour gets the
    polygon too. ``pinholes``: the centres of the filled pinholes, sorted by x; each boundary fitted one by one
    gets those near it (:func:`_pinholes_near`). Returns the fits, the budget state of each boundary (``None``,
    ``"stopped"`` or ``"polygon"``) and the indices of those stopped fits; adds the fit seconds to ``times``."""
    epsilon, max_iterations, keep = settings["tolerance"], settings["max_iterations"], settings["keep_snapshots"]
    fits, state = [None] * len(points_list), [None] * len(points_list)
    small = [k for k in small if not undetected[k]]
    for first in range(0, len(small), SMALL_CHUNK):
        if deadline.passed():
            break
        chunk = small[first: first + SMALL_CHUNK]
        started = time.perf_counter()
        corners = [np.unique(np.asarray(corner_list[k], dtype=np.int64)) for k in chunk]
        pixel = None if pixel_list[chunk[0]] is None else [pixel_list[k] for k in chunk]  # all found, or none
        for at, (k, fit) in enumerate(zip(chunk, fit_small_trusted([points_list[k] for k in chunk], corners, epsilon,
                                                                   max_iterations, keep, deadline, pixel))):
            if not keeps_area(points_list[k], fit.spline.bezier()):
                continue    # collapsed on a thin stroke: fitted by the regression spline below (as fit_outline)
            if fit.info["stuck"] and settings["fit_options"]["fallback"]:  # the regression spline, if better
                fit = unstuck(fit, points_list[k], corners[at], epsilon, max_iterations, keep, settings["fit_options"],
                              deadline, None if pixel is None else pixel[at], _pinholes_near(pinholes, points_list[k]))
            fits[k] = fit
            if fit.info.get("reason") and deadline.passed():
                state[k] = "stopped"
                if fit.hausdorff > STOPPED_FIT_LIMIT * epsilon:  # far off its contour: its polygon instead
                    fits[k], state[k] = None, "far"
        times[chunk] += (time.perf_counter() - started) / len(chunk)
    method = settings["method"]
    for k, (points, corner_idx) in enumerate(zip(points_list, corner_list)):
        if fits[k] is not None or undetected[k]:
            continue
        if deadline.passed():  # and so for every later boundary: they get their polygon
            break
        started = time.perf_counter()
        rng = make_rng(_child_seed(settings["seed"], k)) if method != "lsq" else None
        try:
            fits[k] = fit_trusted(points, np.unique(np.asarray(corner_idx, dtype=np.int64)), float(tolerances[k]),
                                  method, settings["tau"], rng, max_iterations, keep, 0, settings["fit_options"],
                                  deadline, pixel_list[k], _pinholes_near(pinholes, points))
        except ValueError as exc:
            raise ValueError(f"boundary {k} ({len(points)} points, {len(corner_idx)} corners): {exc}") from exc
        times[k] += time.perf_counter() - started
        if fits[k].info.get("reason") and deadline.passed():
            state[k] = "stopped"
            if fits[k].hausdorff > STOPPED_FIT_LIMIT * tolerances[k]:  # far off its contour: its polygon instead
                fits[k], state[k] = None, "far"
    left = [k for k, fit in enumerate(fits) if fit is None]
    polygons = polygon_fits([points_list[k] for k in left], epsilon, keep)
    far = [k for k in left if state[k] == "far"]
    for k in left:
        state[k] = "polygon"
    return _lazy_fits(fits, left, polygons), state, far


def _pinholes_near(pinholes, points):
    """The centres of ``pinholes`` (sorted by x) within :data:`~.fitting.tips.MAX_TIP_REACH` px of the bounding
    box of ``points`` (where a notch tip of that outline can reach), or ``None``."""
    if pinholes is None or not pinholes.shape[0]:
        return None
    low, high = points.min(axis=0) - MAX_TIP_REACH, points.max(axis=0) + MAX_TIP_REACH
    near = pinholes[np.searchsorted(pinholes[:, 0], low[0], side="left"):
                    np.searchsorted(pinholes[:, 0], high[0], side="right")]
    near = near[(near[:, 1] >= low[1]) & (near[:, 1] <= high[1])]
    return near if near.shape[0] else None


def _lazy_fits(fits, left, polygons):
    """The fits (a :class:`~splinecraft.capture.fitting.results.BoundaryList`) and splines of all boundaries:
    the polygons of ``left`` (``polygons``, a ``PolygonFits``) made when first read."""
    position = dict(zip(left, range(len(left))))
    splines = [None if fit is None else fit.spline for fit in fits]
    return (BoundaryList(fits, _Polygon(polygons, position, "fit")),
            BoundaryList(splines, _Polygon(polygons, position, "spline")),
            {"left": np.asarray(left, dtype=np.int64), "segments": getattr(polygons, "segments", np.zeros(0, int)),
             "fitted": [k for k, fit in enumerate(fits) if fit is not None]})


class _Polygon:
    """Boundary ``k`` -> its polygon's fit or spline (a picklable maker for :class:`BoundaryList`)."""

    def __init__(self, polygons, position, kind):
        self.polygons, self.position, self.kind = polygons, position, kind

    def __call__(self, k):
        index = self.position[k]
        return self.polygons[index] if self.kind == "fit" else self.polygons.spline(index)


def _budget_notes(state, time_budget, notes, far=()):
    polygons, stopped = state.count("polygon"), state.count("stopped")
    if polygons:
        notes.append(f"{BUDGET_NOTE} {time_budget:g} s spent: {polygons} of {len(state)} "
                     f"boundar{'y' if len(state) == 1 else 'ies'} got the polygon of their contour (straight pieces between turning points, no corner "
                     "detection; stats['per_boundary'][k]['budget'] == 'polygon'; trace(time_budget=None) fits "
                     "them all)")
    if stopped:
        notes.append(f"{BUDGET_NOTE} {time_budget:g} s: the knot rounds of {stopped} boundar"
                     f"{'y' if stopped == 1 else 'ies'} stopped before convergence")
    if far:
        notes.append(f"{BUDGET_NOTE} {time_budget:g} s: the knot rounds of boundar{'y' if len(far) == 1 else 'ies'} "
                     f"{', '.join(map(str, far))} stopped more than {STOPPED_FIT_LIMIT:g} times the tolerance from "
                     "the contour, which no fallback fit had time to mend: the polygon of the contour instead "
                     "(fitting.budget.STOPPED_FIT_LIMIT)")


def _without_pinholes(mask, boundaries, connectivity):
    """``mask`` with its pinholes filled (``_binarize.fill_pinholes``), then its ink specks dropped
    (``_binarize.drop_specks``), its boundaries traced again, until neither is left, and the numbers filled and
    dropped. Pinholes are filled until none is left (each round only adds ink, so this ends; one round in
    practice); specks are dropped once, after that (a dropped speck leaves paper beside no other ink, so it
    opens no hole)."""
    filled_total = 0
    while True:
        mask, filled = fill_pinholes(mask, boundaries)
        if not filled:
            break
        filled_total += filled
        boundaries = trace_boundaries(mask, connectivity=connectivity)
    mask, dropped = drop_specks(mask, boundaries)
    if dropped:
        boundaries = trace_boundaries(mask, connectivity=connectivity)
    return mask, boundaries, filled_total, dropped


def _detect(points, k, corner_method, corner_params, notes):
    """Corner indices of one contour; contours too short for the detector get none (closed periodic fit).
    A bad ``corner_params`` value is never taken for a short contour: it raises, naming the key."""
    kwargs = dict(corner_params, method=corner_method)
    try:
        found = detect_corners(points, closed=True, **kwargs)
    except ValueError as exc:
        check_corner_params(corner_method, corner_params, "corner_params")  # checked up front too; raises on a bad one
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
