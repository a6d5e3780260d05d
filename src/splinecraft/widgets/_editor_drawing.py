"""What the SplineEditor's page draws: the ``geometry`` dict of float32 buffers, the comb, labels, the view.

Everything is computed from a curve (:class:`~splinecraft.Spline`) and an editor state dict by the engine's
public methods (``bezier``, ``auxiliary``, ``curvature_comb``, ``joint_curvature``, ``leg_pieces``); the
page (``js/editor_view.js``) only maps the buffers to SVG paths.
"""
from __future__ import annotations

import math

import numpy as np

from ..plot._layers import COMB_CAP
from ._base import f32
from ._forms import SEGMENT_LABELS

__all__ = ["fitted_view", "comb_unit", "comb", "construction", "geometry", "geometry_delta", "clamp_parameter",
           "MAX_COMB_TEETH", "DELTA_MIN_BYTES"]

#: Long curves draw every k-th comb tooth so that at most this many are sent (the envelope keeps every sample).
MAX_COMB_TEETH = 1500
#: At comb size 1 the 90th-percentile tooth is this fraction of the curve's size, and no tooth is longer than
#: ``COMB_CAP`` times that: the rule of the static figures (:func:`splinecraft.plot.comb_teeth`).
COMB_REFERENCE = 0.12
#: Joint labels are written only for curves with at most this many pieces.
MAX_JOINT_LABELS = 60


def fitted_view(points, spline, comb_size: float | None = None) -> list:
    """``[xmin, ymin, xmax, ymax]`` around the points and the Bézier points of the curve, with an 8% margin.

    With ``comb_size`` (the comb is shown) the margin also holds the longest comb tooth (:func:`comb_unit`).
    """
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    cloud = np.vstack([points, spline.bezier().reshape(-1, 2)]) if spline is not None else points
    lo, hi = cloud.min(axis=0), cloud.max(axis=0)
    size = np.maximum(hi - lo, 1e-6 * max(1.0, float(np.abs(cloud).max())))
    pad = (0.08 + (COMB_REFERENCE * COMB_CAP * comb_size if comb_size else 0.0)) * size.max()
    return [float(lo[0] - pad), float(lo[1] - pad), float(lo[0] + size[0] + pad), float(lo[1] + size[1] + pad)]


def clamp_parameter(spline, t):
    """``t`` moved into the curve's parameter interval (None stays None)."""
    if t is None:
        return None
    return float(min(max(t, spline.knots[0]), spline.knots[-1]))


def _comb_samples(spline) -> int:
    return int(np.clip(4000 // max(spline.n_segments, 1), 6, 33))


def comb_unit(spline) -> dict | None:
    """Tooth length per unit curvature and the longest tooth, at comb size 1 (§7; as the static figures).

    The 90th-percentile tooth is 12% of the curve's size and every tooth is capped at ``COMB_CAP`` times
    that, so sharp turns do not shoot off the canvas. The editor keeps the unit until the form, the class,
    the view or the comb switch changes, so that during a drag the comb shows real changes of curvature
    instead of being renormalised on every move.
    """
    bases, tips = spline.curvature_comb(scale=1.0, samples_per_segment=_comb_samples(spline))
    lengths = np.hypot(*(tips - bases).T)  # = |kappa|
    finite = lengths[np.isfinite(lengths)]
    reference = float(np.percentile(finite, 90)) if finite.size else 0.0
    target = COMB_REFERENCE * (float(np.ptp(bases, axis=0).max()) if len(bases) else 0.0)
    if not (reference > 0 and target > 0):
        return None
    return {"scale": target / reference, "cap": COMB_CAP * target}


def _joint_labels(spline) -> list:
    """``κ⁺/κ⁻`` at every joint where curvature jumps (E2: ``ω_{i-1}/ω_i`` in the interpolant, §2.2)."""
    m = spline.n_segments
    if m > MAX_JOINT_LABELS:
        return []
    joints = spline.joint_curvature()
    points = spline.knot_points
    labels = []
    for i in range(m) if spline.closed else range(1, m):
        minus, plus = joints[i]
        if not (math.isfinite(minus) and math.isfinite(plus)):
            continue
        big = max(abs(minus), abs(plus))
        if big <= 1e-12 or abs(plus - minus) <= 1e-3 * big:
            continue
        ratio = plus / minus if abs(minus) > 1e-12 * big else math.inf
        text = f"κ⁺/κ⁻ = {ratio:.2f}" if math.isfinite(ratio) else "κ jumps"
        labels.append({"x": float(points[i][0]), "y": float(points[i][1]), "text": text, "kind": "joint"})
    return labels


def comb(spline, unit: dict | None, size: float):
    """Curvature comb: teeth ``(k, 2, 2)`` with both one-sided teeth at every joint, tip envelope, joint labels.

    ``unit`` is :func:`comb_unit` (None: no teeth), ``size`` the user's comb size (both lengths scale with it).
    """
    bases, tips = spline.curvature_comb(scale=1.0, samples_per_segment=_comb_samples(spline))
    if unit is None:
        tips = bases.copy()
    else:
        lengths = np.hypot(*(tips - bases).T)
        with np.errstate(divide="ignore", invalid="ignore"):
            factor = size * np.minimum(unit["scale"], unit["cap"] / lengths)
        tips = bases + np.where(np.isfinite(factor), factor, 0.0)[:, None] * (tips - bases)
    teeth = np.stack([bases, tips], axis=1)
    if len(teeth) > MAX_COMB_TEETH:
        teeth = teeth[:: math.ceil(len(teeth) / MAX_COMB_TEETH)]
    envelope = np.vstack([tips, tips[:1]]) if spline.closed and len(tips) else tips
    return teeth, envelope, _joint_labels(spline)


def _class_polygon(spline, bezier):
    """Per piece ``F_i, V_i, W_i, F_{i+1}`` (generic cubic) or ``P_i, Q_1, Q_2, P_{i+1}`` (Timmer), NaN-separated."""
    aux = spline.auxiliary
    V, W = aux.get("V", aux.get("Q1")), aux.get("W", aux.get("Q2"))
    if V is None or W is None:
        return None, None
    gap = np.full((bezier.shape[0], 1, 2), np.nan)
    polygon = np.concatenate([bezier[:, :1], V[:, None], W[:, None], bezier[:, 3:], gap], axis=1)
    return polygon, np.stack([V, W], axis=1)


def construction(spline, t: float) -> dict:
    """The de Casteljau construction of the piece at parameter ``t`` (:meth:`Spline.construction`), as buffers.

    ``construction``: the Bézier polygon and the two inner levels of linear interpolation, NaN-separated
    polylines; ``construction_points``: every point of the three levels; ``construction_class``: the class
    polygon ``F_i, V_i, W_i, F_{i+1}`` (Timmer: ``P_i, Q_1, Q_2, P_{i+1}``) the piece comes from (§1, eq 3.5);
    ``t_point``: the curve point; ``t_info``: the piece and the local parameter θ.
    """
    built = spline.construction(t)
    gap = np.full((1, 2), np.nan)
    polylines = np.vstack([built.levels[0], gap, built.levels[1], gap, built.levels[2]])
    out = {
        "construction": f32(polylines),
        "construction_points": f32(np.vstack(built.levels[:3])),
        "t_point": f32(built.point.reshape(1, 2)),
        "t_info": {"t": float(built.parameter), "piece": int(built.piece), "theta": float(built.theta)},
    }
    if built.class_polygon is not None:
        out["construction_class"] = f32(built.class_polygon)
    return out


def geometry(spline, state: dict, display: dict, *, revision: int, seq: int, unit: dict | None) -> dict:
    """The ``geometry`` trait: what the page draws for ``spline`` (built from ``state``).

    ``display`` holds the overlay switches (``show_bezier_points``, ``show_tangents``, ``show_comb``),
    ``comb_scale``, ``selected_interval`` and ``t`` (None: no construction).
    """
    bezier = spline.bezier()
    closed = spline.closed
    out = {
        "revision": revision, "seq": seq, "closed": bool(closed), "bezier": f32(bezier),
        "knots": f32(spline.knot_points[:-1] if closed else spline.knot_points),
        "domain": [float(spline.knots[0]), float(spline.knots[-1])],
    }
    if display.get("t") is not None:
        out.update(construction(spline, display["t"]))
    if display["show_bezier_points"] and state["form"] != "segment":
        polygon, vw = _class_polygon(spline, bezier)
        if polygon is not None:
            out["class_polygon"], out["vw"] = f32(polygon), f32(vw)
    if display["show_tangents"]:
        out["tangents"] = f32(np.stack([bezier[:, 0], bezier[:, 1], bezier[:, 3], bezier[:, 2]], axis=1))
    labels = []
    if display["show_comb"]:
        teeth, envelope, joint_labels = comb(spline, unit, display["comb_scale"])
        out["comb_teeth"], out["comb_envelope"] = f32(teeth), f32(envelope)
        labels.extend(joint_labels)
    if state["form"] == "segment":
        labels.extend({"x": float(p[0]), "y": float(p[1]), "text": label, "kind": "point"}
                      for p, label in zip(state["points"], SEGMENT_LABELS))
    out["labels"] = labels
    interval = display["selected_interval"]
    if 0 <= interval < len(state["interval_weights"]):
        pieces = spline.leg_pieces(interval)
        if len(pieces):
            out["highlight"] = f32(bezier[pieces])
        if state["form"] == "basis":
            points = state["points"]
            out["highlight_leg"] = f32(np.vstack([points[interval], points[(interval + 1) % len(points)]]))
    return out


#: Buffers a drag update sends as changed rows (bytes per row): a moved point changes a few Bézier pieces of
#: the basis form (§3) and, for the global interpolants, pieces whose change decays with the distance from
#: the point (§2.2), so most float32 rows stay bit-identical.
DELTA_ROWS = {"bezier": 32, "knots": 8}
#: Geometries whose Bézier and knot buffers hold fewer bytes than this (an open curve of up to 100 points) go
#: whole: there the comparison costs the kernel about as much as the bytes it saves cost the kernel and the
#: server (``benchmarks/bench_drag.py --transport``; BENCHMARKS.md, "Drag latency").
DELTA_MIN_BYTES = 4000


def geometry_delta(sent: dict, current: dict) -> dict | None:
    """``current`` as changes to ``sent`` (the geometry the page holds), or None when it goes whole: when its
    rows changed size, or when it is small (:data:`DELTA_MIN_BYTES`).

    For each buffer of :data:`DELTA_ROWS` of the same size in both, the delta carries ``<name>_rows``
    (int32 indices of the rows whose bytes differ) and ``<name>_data`` (those rows); everything else of
    ``current`` is copied as it is, and ``base`` names the revision of ``sent``. Applying it to ``sent``
    gives ``current`` byte for byte (``js/spline_editor.js``).
    """
    if sum(len(current.get(key) or b"") for key in DELTA_ROWS) < DELTA_MIN_BYTES:
        return None
    out = {key: value for key, value in current.items() if key not in DELTA_ROWS}
    out["base"] = sent["revision"]
    for key, row_bytes in DELTA_ROWS.items():
        new, old = current.get(key), sent.get(key)
        if new is None or old is None or len(new) != len(old) or len(new) % row_bytes:
            return None
        new_rows = np.frombuffer(new, dtype=np.uint8).reshape(-1, row_bytes)
        changed = np.flatnonzero((new_rows != np.frombuffer(old, dtype=np.uint8).reshape(-1, row_bytes)).any(axis=1))
        out[f"{key}_rows"] = changed.astype("<i4").tobytes()
        out[f"{key}_data"] = new_rows[changed].tobytes()
    return out
