"""Algorithm 3.1: the G2 piecewise Timmer curve (§5.4, thesis section 3.3.3, errata E16-E18)."""
from __future__ import annotations

import math

import numpy as np

from ..._validation import check_bool, check_positive_number
from ..piecewise import Spline
from ..tangents import _chords
from .pieces import _G2_CODES, _G2_RTOL, _ZERO_RTOL, _make_spline, _tangent_input, _timmer_cross_terms, scaled_points, unscale_alpha

#: Band :math:`[1/R, R]` around :math:`\alpha_{ref}` outside which ``info["wild"]`` flags a piece when
#: ``clamp`` is None (with a clamp, its ratio is the band).
WILD_RATIO = 16.0

# ----------------------------------------------------------------------------------------------------------
# Algorithm 3.1: G2 piecewise Timmer
# ----------------------------------------------------------------------------------------------------------
def _solve_joint(s_i, c_i, target, alpha_ref, chord, clamp):
    """Solve :math:`\\tfrac38S\\alpha^2-\\tfrac12C\\alpha-K^*=0` for a batch of targets (§5.4 steps 2-4).

    ``target`` has shape (G,); ``s_i, c_i, alpha_ref, chord`` are scalars. Returns ``alpha`` (G,) and the
    status code (G,) as an index into ``_G2_CODES``. The roots use the cancellation-free form
    :math:`q=-\\tfrac12(b+\\operatorname{sgn}(b)\\sqrt{b^2-4ac})`, :math:`\\alpha\\in\\{q/a,\\ c/q\\}` with
    :math:`b^2-4ac=(C^2+6SK^*)/4` (E18). Call inside ``np.errstate(divide/invalid/over="ignore")``.
    """
    alpha = np.full(target.shape, alpha_ref)
    code = np.zeros(target.shape, dtype=np.int8)
    if abs(s_i) <= _ZERO_RTOL * chord:
        if abs(c_i) <= _ZERO_RTOL:
            # kappa_i(0) = 0 for every alpha: a G2 joint only if the target curvature is 0 too
            code[np.abs(target) * chord > 1e-9] = 2
            return alpha, code
        best = -2.0 * target / c_i                    # linear case: -C/2 alpha - K* = 0
        ok = (best > 0.0) & np.isfinite(best)
        vertex = -1.0
    else:
        disc = c_i * c_i + 6.0 * s_i * target
        b = -0.5 * c_i
        q = -0.5 * (b + (0.5 if b >= 0.0 else -0.5) * np.sqrt(disc))     # NaN where disc < 0
        root_1 = q / (0.375 * s_i)
        root_2 = np.where(q != 0.0, -target / q, np.nan)
        ok_1 = (root_1 > 0.0) & np.isfinite(root_1)
        ok_2 = (root_2 > 0.0) & np.isfinite(root_2)
        distance_1 = np.where(ok_1, np.abs(np.log(np.where(ok_1, root_1, 1.0) / alpha_ref)), np.inf)
        distance_2 = np.where(ok_2, np.abs(np.log(np.where(ok_2, root_2, 1.0) / alpha_ref)), np.inf)
        best = np.where(distance_2 < distance_1, root_2, root_1)
        ok = ok_1 | ok_2
        vertex = 2.0 * c_i / (3.0 * s_i)
    alpha[ok] = best[ok]
    if not ok.all():
        # Step 4: vertex of the parabola kappa_i(0)(alpha) if positive, else alpha_ref (clamped)
        value = vertex if vertex > 0.0 else alpha_ref
        if clamp is not None:
            value = min(max(value, alpha_ref / clamp), alpha_ref * clamp)
        alpha[~ok] = value
        code[~ok] = 1
    return alpha, code


def _solve_joint_scalar(s_i, c_i, target, alpha_ref, chord, clamp):
    """Scalar twin of :func:`_solve_joint` (plain floats; same formulas, same root choice)."""
    if abs(s_i) <= _ZERO_RTOL * chord:
        if abs(c_i) <= _ZERO_RTOL:
            return alpha_ref, (0 if abs(target) * chord <= 1e-9 else 2)
        root = -2.0 * target / c_i
        if root > 0.0 and math.isfinite(root):
            return root, 0
        vertex = -1.0
    else:
        disc = c_i * c_i + 6.0 * s_i * target
        best, best_distance = None, math.inf
        if disc >= 0.0:
            b = -0.5 * c_i
            q = -0.5 * (b + (0.5 if b >= 0.0 else -0.5) * math.sqrt(disc))
            candidates = (q / (0.375 * s_i), -target / q) if q != 0.0 else (q / (0.375 * s_i),)
            for root in candidates:
                if root > 0.0 and math.isfinite(root):
                    distance = abs(math.log(root / alpha_ref))
                    if distance < best_distance:
                        best, best_distance = root, distance
        if best is not None:
            return best, 0
        vertex = 2.0 * c_i / (3.0 * s_i)
    value = vertex if vertex > 0.0 else alpha_ref
    if clamp is not None:
        value = min(max(value, alpha_ref / clamp), alpha_ref * clamp)
    return value, 1


def _g2_sweep(alpha_first, s_term, u_term, c_term, alpha_ref, chords, clamp):
    """Run Algorithm 3.1 from :math:`\\alpha_0` for a batch of start values (vectorised over the batch).

    Returns ``alpha`` (G, m) and ``code`` (G, m), where ``code[:, i]`` is the status of the joint at the
    start of piece ``i`` (``i >= 1``); column 0 is left 0 (the caller decides about a closing joint).
    The recurrence is sequential in the joints; a single start value runs on plain floats, a batch
    runs every joint as one numpy step over the batch.
    """
    batch = np.atleast_1d(np.asarray(alpha_first, dtype=float))
    m = s_term.shape[0]
    if batch.shape[0] == 1:
        alpha, code = [float(batch[0])], [0]
        s_list, u_list, c_list = s_term.tolist(), u_term.tolist(), c_term.tolist()
        ref_list, chord_list = alpha_ref.tolist(), chords.tolist()
        previous = alpha[0]
        for i in range(1, m):
            target = -0.375 * (previous * previous) * u_list[i - 1] - 0.5 * previous * c_list[i - 1]
            previous, status = _solve_joint_scalar(s_list[i], c_list[i], target, ref_list[i], chord_list[i],
                                                   clamp)
            alpha.append(previous)
            code.append(status)
        return np.array([alpha]), np.array([code], dtype=np.int8)
    alpha = np.empty((batch.shape[0], m))
    code = np.zeros((batch.shape[0], m), dtype=np.int8)
    alpha[:, 0] = batch
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for i in range(1, m):
            previous = alpha[:, i - 1]
            target = -0.375 * previous**2 * u_term[i - 1] - 0.5 * previous * c_term[i - 1]   # kappa_{i-1}(1)
            alpha[:, i], code[:, i] = _solve_joint(s_term[i], c_term[i], target, alpha_ref[i], chords[i], clamp)
    return alpha, code


def _closing_mismatch(alpha, s_term, u_term, c_term):
    """:math:`\\kappa_0(0)-\\kappa_{m-1}(1)` for every row of ``alpha`` (G, m) (with :math:`\\beta=\\alpha`),
    and the size below which it counts as zero (relative to the curvatures there, at least
    ``1/mean chord`` passed in as ``curvature_scale``)."""
    first, last = alpha[:, 0], alpha[:, -1]
    kappa_start = 0.375 * first**2 * s_term[0] - 0.5 * first * c_term[0]
    kappa_end = -0.375 * last**2 * u_term[-1] - 0.5 * last * c_term[-1]
    return kappa_start - kappa_end, np.maximum(np.abs(kappa_start), np.abs(kappa_end))


def _is_matched(mismatch, magnitude, curvature_scale):
    return np.abs(mismatch) <= _G2_RTOL * np.maximum(magnitude, curvature_scale)


def _search_closing_alpha(s_term, u_term, c_term, alpha_ref, chords, clamp, curvature_scale):
    """Choose :math:`\\alpha_0` of a closed Algorithm 3.1 curve so that the closing joint is :math:`G^2` too.

    The closing mismatch :math:`\\kappa_0(0)-\\kappa_{N-1}(1)` is a function of :math:`\\alpha_0` alone. It is
    scanned on a log grid of 129 values over :math:`[\\alpha_{ref,0}/R, R\\,\\alpha_{ref,0}]` (``R = clamp`` or
    16), all grid values in one vectorised sweep. Grid values that already close to round-off, and sign
    changes between neighbouring grid values with the same joint-status pattern (so the mismatch is
    continuous between them unless the chosen root switches branch), are candidates. They are tried in
    order of fewest fallback joints, then the tamest chain (smallest
    :math:`\\max_i|\\log(\\alpha_i/\\alpha_{ref,i})|`); brackets are refined with ``scipy.optimize.brentq``
    and accepted only where the status pattern holds and the mismatch really vanishes. Returns
    ``(alpha_0, converged)``; without a zero, ``(alpha_ref_0, False)`` (the open-curve default; the
    closing joint is then reported ``g1_closing``).
    """
    from scipy.optimize import brentq

    ratio = 16.0 if clamp is None else clamp
    grid = alpha_ref[0] * np.geomspace(1.0 / ratio, ratio, 129)

    def sweep(alpha_first):
        with np.errstate(over="ignore", invalid="ignore"):
            alpha, code = _g2_sweep(alpha_first, s_term, u_term, c_term, alpha_ref, chords, clamp)
            mismatch, size = _closing_mismatch(alpha, s_term, u_term, c_term)
            wildness = np.max(np.abs(np.log(alpha / alpha_ref)), axis=1)
        return code[:, 1:], mismatch, np.maximum(size, curvature_scale), wildness

    codes, mismatch, size, wildness = sweep(grid)
    fallbacks = (codes != 0).sum(axis=1)
    exact = np.abs(mismatch) <= 1e-13 * size
    same = (codes[:-1] == codes[1:]).all(axis=1) & np.isfinite(mismatch[:-1]) & np.isfinite(mismatch[1:])
    change = same & (np.sign(mismatch[:-1]) * np.sign(mismatch[1:]) <= 0) & ~exact[:-1] & ~exact[1:]
    # candidates: (fallbacks, wildness, kind, index); kind 0 = exact grid value, 1 = bracket [k, k+1]
    candidates = [(int(fallbacks[k]), float(wildness[k]), 0, int(k)) for k in np.flatnonzero(exact)]
    candidates += [(int(fallbacks[k]), float(max(wildness[k], wildness[k + 1])), 1, int(k))
                   for k in np.flatnonzero(change)]
    candidates.sort()

    def closing(log_alpha):
        return float(sweep(np.array([math.exp(log_alpha)]))[1][0])

    for _, _, kind, k in candidates[:12]:
        if kind == 0:
            return float(grid[k]), True
        try:
            root = brentq(closing, math.log(grid[k]), math.log(grid[k + 1]), xtol=1e-15, rtol=1e-15,
                          maxiter=200)
        except (ValueError, RuntimeError):
            continue
        alpha_0 = math.exp(root)
        code_r, mismatch_r, size_r, _ = sweep(np.array([alpha_0]))
        if (code_r[0] == codes[k]).all() and abs(mismatch_r[0]) <= _G2_RTOL * size_r[0]:
            return alpha_0, True
    return float(alpha_ref[0]), False


def timmer_g2(points, *, closed: bool = False, tangents=None, alpha0=None, clamp=16.0) -> Spline:
    """:math:`G^2` piecewise Timmer curve through ``points`` (Algorithm 3.1; §5.4, thesis section 3.3.3).

    One tangent scale :math:`\\alpha_i=\\beta_i` per piece, chosen joint by joint so that the curvature is
    continuous (thesis eqs 3.106-3.122 with errata E16-E18):

    1. Unit tangents :math:`T_i=\\tilde T_i/\\|\\tilde T_i\\|` for **all** :math:`i=0..n` (E16: eq 3.110 writes
       :math:`D_i` and :math:`i=1..n-1`), from :func:`~splinecraft.spline.tangents.estimate_tangents`
       (eqs 3.106-3.109) unless ``tangents`` is given.
    2. :math:`\\alpha_0` given; default :math:`\\alpha_{ref,0}=4/\\|P_1-P_0\\|` (tangent length = chord,
       Bézier inner points at a third of the chord).
    3. For the joints :math:`i=1..n-1` (E17: not :math:`1..n`, and the loop does not start at 0): target
       :math:`K^*=\\kappa_{i-1}(1)` (§5.3 with :math:`\\alpha_{i-1}`), then solve eq 3.120/3.121
       :math:`\\tfrac38S_i\\alpha^2-\\tfrac12C_i\\alpha-K^*=0`, whose roots are
       :math:`2[C_i\\pm\\sqrt{C_i^2+6S_iK^*}]/(3S_i)` (E18: eq 3.122 prints :math:`-6S_iK^*`). Solved with the
       cancellation-free quadratic formula; :math:`S_i=0` is the linear case :math:`\\alpha=-2K^*/C_i`.
    4. Among positive real roots, the one closest to :math:`\\alpha_{ref,i}=4/\\|P_{i+1}-P_i\\|` in
       :math:`|\\log(\\alpha/\\alpha_{ref,i})|` (our choice, §5.4; the thesis says only "positive").
    5. No positive root (common: 12-15% of joints even on clean ellipse samples): the vertex
       :math:`2C_i/(3S_i)` if positive (it minimises :math:`|\\kappa_i(0)-K^*|` over :math:`\\alpha>0`), else
       :math:`\\alpha_{ref,i}`, clamped to :math:`[\\alpha_{ref,i}/\\text{clamp},\\ \\text{clamp}\\,\\alpha_{ref,i}]`. The joint
       is then only :math:`G^1`: status ``"g1_no_root"`` with its curvature jump. :math:`S_i=C_i=0` (a straight
       piece with aligned tangents) gives :math:`\\kappa_i(0)\\equiv0`: ``"g2"`` if :math:`K^*=0`, else
       ``"g1_degenerate"``. Roots are never clamped (they are what makes the joint :math:`G^2`).

    Closed curves (:math:`N` distinct points, :math:`N` pieces, tangents by the interior formula
    cyclically): the sweep runs over the joints :math:`1..N-1`; the closing joint at :math:`P_0` depends
    on :math:`\\alpha_0` alone. Unless ``alpha0`` is given, :math:`\\alpha_0` is searched on a log grid
    over :math:`[\\alpha_{ref,0}/R, R\\,\\alpha_{ref,0}]` (``R = clamp`` or 16) with refinement, for a value that
    makes the closing joint :math:`G^2` (status ``"g2"``), preferring values with the fewest fallback
    joints elsewhere, then the tamest chain of :math:`\\alpha_i/\\alpha_{ref,i}`. If there is none, :math:`\\alpha_0=\\alpha_{ref,0}` and the closing joint is reported
    ``"g1_closing"`` with its jump. ``info['closing_converged']`` tells which. With ``alpha0`` given, the
    closing joint is simply reported as it comes out.

    Parameters
    ----------
    points : array_like, shape (n+1, 2)
        Open: at least 2 points; closed: at least 3 distinct points, the first not repeated.
    closed : bool
    tangents : array_like, shape (n+1, 2), optional
        Tangent directions to use instead of the §6 estimates (normalised here).
    alpha0 : float, optional
        Tangent scale of the first piece (> 0).
    clamp : float or None
        Clamp ratio (> 1) for fallback values; ``None`` disables clamping.

    Returns
    -------
    Spline
        Knots ``0..m``. ``info``: ``form="timmer_g2"``, ``alpha`` = ``beta`` (per piece), ``joint_status``
        and ``curvature_jump`` per knot, ``alpha0``, ``alpha_ref``, ``closing_converged`` (closed only),
        ``alpha_ratio`` (per piece :math:`\\alpha_i/\\alpha_{ref,i}`) and ``wild`` (per piece: whether that
        ratio lies outside :math:`[1/R, R]`, ``R = clamp``, or :data:`WILD_RATIO` without one). A root is never
        clamped, so a joint can be ``"g2"`` with a wild scale: its handles are ``R`` times shorter (or longer)
        than a third of the chord and its curvature far from the data's (on noisy samples the chain of roots
        can grow hundreds of times, |kappa| ~ 1e7); ``not any(info["wild"])`` means every piece stayed in the
        band.
        ``auxiliary``: ``Q1``, ``Q2``, ``tangents`` (unit).

    Raises
    ------
    ValueError
        Bad points (non-finite, duplicates, too few, not planar), bad ``tangents``, ``alpha0 <= 0``,
        ``clamp <= 1``. A joint without a positive root is *not* an error (see step 5).
    """
    closed = check_bool(closed, "closed")
    pts, exponent = scaled_points(points, closed)
    tan = _tangent_input(pts, tangents, closed)
    if clamp is not None:
        clamp = check_positive_number(clamp, "clamp")
        if clamp <= 1.0:
            raise ValueError(f"clamp must be > 1 (a ratio around alpha_ref) or None, got {clamp!r}")
    chord_vectors = _chords(pts, closed)
    chords = np.linalg.norm(chord_vectors, axis=1)
    alpha_ref = 4.0 / chords
    s_term, u_term, c_term = _timmer_cross_terms(pts, tan, closed)
    curvature_scale = 1.0 / float(np.mean(chords))

    extra = {"alpha_ref": unscale_alpha(alpha_ref, exponent).tolist()}  # alpha has the units of 1 / length
    converged = None
    if alpha0 is not None:
        alpha0 = float(np.ldexp(check_positive_number(alpha0, "alpha0"), exponent))
        if not (np.isfinite(alpha0) and alpha0 > 0):
            raise ValueError("alpha0 is out of range for points of this size (alpha0 times their size leaves float64)")
    elif closed:
        alpha0, converged = _search_closing_alpha(s_term, u_term, c_term, alpha_ref, chords, clamp,
                                                  curvature_scale)
    else:
        alpha0 = float(alpha_ref[0])
    alpha, code = _g2_sweep([alpha0], s_term, u_term, c_term, alpha_ref, chords, clamp)
    alpha, code = alpha[0], code[0]
    labels = [_G2_CODES[c] for c in code]
    if closed:
        mismatch, size = _closing_mismatch(alpha[None, :], s_term, u_term, c_term)
        labels[0] = "g2" if _is_matched(mismatch, size, curvature_scale)[0] else "g1_closing"
        if converged is None:
            converged = labels[0] == "g2"
        extra["closing_converged"] = bool(converged)
    extra["alpha0"] = float(unscale_alpha(alpha0, exponent))
    # roots are never clamped: report the pieces whose scale left the clamp's band around alpha_ref (short
    # handles, a curvature far above the chords' 1 / length: on noisy samples alpha can grow hundreds of times)
    ratio = alpha / alpha_ref
    band = WILD_RATIO if clamp is None else clamp
    extra["alpha_ratio"] = ratio.tolist()
    extra["wild"] = ((ratio > band) | (ratio < 1.0 / band)).tolist()  # per piece: lists follow reversal
    return _make_spline("timmer_g2", pts, tan, alpha, alpha.copy(), closed, labels, extra, exponent=exponent)


