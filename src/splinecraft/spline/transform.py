"""Exact geometric maps of a :class:`~splinecraft.spline.piecewise.Spline`: reversal and affine images (§0).

Bézier pieces map to Bézier pieces, so both are exact; the auxiliary geometry and the metadata follow
the pieces (see :meth:`Spline.reversed` and :meth:`Spline.transformed`).
"""
from __future__ import annotations

import numpy as np

from .._json import to_jsonable
from .._validation import as_float_array

__all__ = ["VECTOR_AUXILIARY_KEYS", "reversed_spline", "transformed_spline"]

#: Auxiliary keys that hold free vectors (derivatives), not points: an affine map applies only its
#: linear part to them and reversal flips their sign.
VECTOR_AUXILIARY_KEYS = frozenset({"tangents"})

#: Auxiliary keys holding one entry per knot (``m + 1`` open, ``m`` closed), and the basis form's control points
#: (``m + 3`` open, ``m`` closed, piece ``i`` over the leg ``P_i P_{i+1}`` of a loop, §4.3): reversed, a loop's
#: entries are also rotated by one, so that entry 0 stays at the same place.
_PER_KNOT_KEYS = frozenset({"tangents", "F", "control_points"})

#: Auxiliary arrays that trade roles when a curve is traversed backwards.
_REVERSED_ROLES = {"V": "W", "W": "V", "Q1": "Q2", "Q2": "Q1"}


def reversed_spline(spline):
    """The same curve traversed backwards (see :meth:`Spline.reversed`)."""
    planar = np.ascontiguousarray(spline._planar[::-1, :, ::-1])
    knots = (spline._knots[0] + spline._knots[-1]) - spline._knots[::-1]
    m = spline.n_segments
    aux = {}
    for key, value in spline._auxiliary.items():
        target = _REVERSED_ROLES.get(key, key)
        flipped = value[::-1]
        if spline._closed and key in _PER_KNOT_KEYS and value.shape[0] == m:
            flipped = np.roll(flipped, 1, axis=0)
        if key in VECTOR_AUXILIARY_KEYS:
            flipped = -flipped
        aux[target] = flipped
    info = dict(spline._info)
    if "alpha" in info or "beta" in info:
        info["alpha"], info["beta"] = spline._info.get("beta"), spline._info.get("alpha")
    for key, value in info.items():
        # Per-piece (m) and per-knot (m + 1) metadata lists follow the pieces backwards.
        if key != "end_derivatives" and isinstance(value, list) and len(value) in (m, m + 1):
            info[key] = value[::-1]
    if isinstance(info.get("end_derivatives"), list) and len(info["end_derivatives"]) == 2:
        # the derivatives at the two ends (timmer_gc2's [D_1, D_n]): swapped, and negated with the direction
        first, last = info["end_derivatives"]
        info["end_derivatives"] = [[-float(x) for x in last], [-float(x) for x in first]]
    knots = np.ascontiguousarray(knots)
    aux = {key: np.array(value) for key, value in aux.items()}
    return type(spline)._from_trusted(planar, knots, closed=spline._closed, auxiliary=aux,
                                      info=to_jsonable(info, "info"))


def transformed_spline(spline, matrix, offset=None):
    """Affine image ``x -> matrix @ x + offset`` (see :meth:`Spline.transformed`)."""
    d = spline.dim
    matrix = as_float_array(matrix, "matrix")
    if matrix.shape != (d, d):
        raise ValueError(f"matrix must have shape ({d}, {d}), got {matrix.shape}")
    offset = np.zeros(d) if offset is None else as_float_array(offset, "offset")
    if offset.shape != (d,):
        raise ValueError(f"offset must have shape ({d},), got {offset.shape}")
    with np.errstate(over="ignore", invalid="ignore"):
        planar = np.matmul(matrix, spline._planar) + offset[:, None]
    if not np.isfinite(planar).all():
        raise ValueError("matrix and offset map the curve beyond the float64 range")
    aux = {}
    for key, value in spline._auxiliary.items():
        if value.ndim >= 1 and value.shape[-1] == d:
            with np.errstate(over="ignore", invalid="ignore"):
                value = value @ matrix.T
                if key not in VECTOR_AUXILIARY_KEYS:
                    value = value + offset
            if not np.isfinite(value).all():
                raise ValueError(f"matrix and offset map auxiliary[{key!r}] beyond the float64 range")
        aux[key] = value
    return type(spline)(planar.transpose(2, 0, 1), spline._knots, closed=spline._closed, auxiliary=aux,
                        info=dict(spline._info))
