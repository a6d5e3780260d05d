"""The JSON form of a :class:`~splinecraft.spline.piecewise.Spline` and its strict reader (§0).

``to_dict`` writes plain lists of floats; ``from_dict`` reads them back exactly and checks every key
against the schema below before anything is built, so a tampered or truncated dict gives a
``TypeError``/``ValueError`` naming the key, never a silent coercion or another exception type.

=====================  ======================================================================
key                    value
=====================  ======================================================================
``type``               optional, the string ``"splinecraft.Spline"``
``version``            optional, the integer 1
``bezier``             required, nested lists (m, 4, d) of finite numbers, m >= 1, d >= 1
``knots``              required, a list of m + 1 strictly increasing finite numbers
``closed``             optional bool (``True``/``False`` only; ``"false"`` is a TypeError)
``auxiliary``          optional dict: string -> nested lists of finite numbers
``auxiliary_shapes``   optional dict: key of ``auxiliary`` -> list of integers >= 0 whose product is
                       the number of values (restores empty and 0-d arrays)
``info``               optional dict of JSON values, at most :data:`splinecraft._json.MAX_DEPTH` deep
=====================  ======================================================================
"""
from __future__ import annotations

import numbers

import numpy as np

from .._json import to_jsonable
from .._validation import as_float_array, check_bool, check_int, check_strictly_increasing

__all__ = ["spline_to_dict", "spline_from_dict", "checked_parts", "snap_joins", "SCHEMA_KEYS", "MAX_AUXILIARY_DIMS",
           "JOIN_RTOL", "JOIN_ULPS"]

SCHEMA_KEYS = ("type", "version", "closed", "knots", "bezier", "auxiliary", "auxiliary_shapes", "info")
TYPE_NAME = "splinecraft.Spline"
#: Most dimensions of an auxiliary array read back.
MAX_AUXILIARY_DIMS = 8
#: Relative tolerance (to the curve's extent: the largest spread of a coordinate over its control points) for
#: the continuity of consecutive pieces and the closure of closed curves, plus :data:`JOIN_ULPS` units in the
#: last place of the largest coordinate (the rounding of joins computed far from the origin): the verdict on a
#: curve does not depend on where it sits.
JOIN_RTOL = 1e-9
JOIN_ULPS = 64


def _relative_gaps(first, second, scale):
    """``|first - second| / scale`` row by row, without overflow at any float64 scale."""
    difference = 0.5 * first / scale - 0.5 * second / scale
    return 2.0 * np.sqrt(np.einsum("ij,ij->i", difference, difference))


def _join(bezier, closed):
    """Check that consecutive pieces join (and a loop closes) within :data:`JOIN_RTOL` of the curve's extent and
    :data:`JOIN_ULPS` of its largest coordinate; make it exact."""
    m = bezier.shape[0]
    scale = float(np.max(np.abs(bezier))) or 1.0
    flat = bezier.reshape(-1, bezier.shape[2])
    extent = float(np.max(0.5 * flat.max(axis=0) / scale - 0.5 * flat.min(axis=0) / scale))  # half, relative
    tolerance = JOIN_RTOL * 2.0 * extent + JOIN_ULPS * np.finfo(float).eps
    if m > 1:
        gaps = _relative_gaps(bezier[1:, 0], bezier[:-1, 3], scale)
        if (gaps > tolerance).any():
            bad = int(np.flatnonzero(gaps > tolerance)[0])
            raise ValueError(
                f"pieces {bad} and {bad + 1} do not join: bezier[{bad}, 3] and bezier[{bad + 1}, 0] "
                f"are {gaps[bad] * scale:.3g} apart"
            )
    if closed:
        gap = float(_relative_gaps(bezier[-1:, 3], bezier[:1, 0], scale)[0])
        if gap > tolerance:
            raise ValueError(
                f"closed=True but the last piece ends {gap * scale:.3g} away from the first point "
                f"(bezier[{m - 1}, 3] != bezier[0, 0])"
            )
    snap_joins(bezier, closed)


def snap_joins(bezier, closed):
    """Make the pieces ``bezier`` (m, 4, d; written in place, a view will do) join exactly: each piece's first
    point set to the previous piece's last, and a loop closed on its first point (what :func:`_join` does after
    its check)."""
    bezier[1:, 0] = bezier[:-1, 3]
    if closed:
        bezier[-1, 3] = bezier[0, 0]


def checked_parts(bezier, knots, closed, auxiliary, info):
    """The checked, copied parts of a :class:`Spline`: ``(bezier, knots, closed, auxiliary, info)``.

    Raises ``TypeError``/``ValueError`` naming the part (and index) for wrong types, shapes, non-finite
    values, non-increasing knots, pieces that do not join or an open loop.
    """
    bezier = as_float_array(bezier, "bezier", copy=True)
    if bezier.ndim != 3 or bezier.shape[1] != 4 or bezier.shape[0] < 1 or bezier.shape[2] < 1:
        raise ValueError(f"bezier must have shape (m, 4, d) with m >= 1, d >= 1; got {bezier.shape}")
    m = bezier.shape[0]
    knots = as_float_array(knots, "knots", ndim=1, copy=True)
    if knots.shape[0] != m + 1:
        raise ValueError(f"knots must have m + 1 = {m + 1} values for {m} pieces, got {knots.shape[0]}")
    check_strictly_increasing(knots, "knots")
    closed = check_bool(closed, "closed")
    _join(bezier, closed)
    knots.flags.writeable = False
    aux = {}
    if auxiliary is not None:
        if not isinstance(auxiliary, dict):
            raise TypeError(f"auxiliary must be a dict of arrays, got {type(auxiliary).__name__}")
        for key, value in auxiliary.items():
            if not isinstance(key, str):
                raise TypeError(f"auxiliary keys must be strings, got {key!r}")
            array = as_float_array(value, f"auxiliary[{key!r}]", copy=True)
            array.flags.writeable = False
            aux[key] = array
    if info is None:
        info = {}
    if not isinstance(info, dict):
        raise TypeError(f"info must be a dict, got {type(info).__name__}")
    return bezier, knots, closed, aux, to_jsonable(info, "info")


def spline_to_dict(spline) -> dict:
    """JSON-able representation (plain lists of floats); exact round trip via :func:`spline_from_dict`."""
    aux = spline._auxiliary
    return {
        "type": TYPE_NAME,
        "version": 1,
        "closed": spline._closed,
        "knots": spline._knots.tolist(),
        "bezier": spline._bezier.tolist(),
        "auxiliary": {key: value.tolist() for key, value in aux.items()},
        "auxiliary_shapes": {key: list(value.shape) for key, value in aux.items()},
        "info": to_jsonable(spline._info, "info"),
    }


def _numbers(value, name, *, max_dims):
    """Nested lists of real numbers as a float64 array (no strings, None, bools-only or objects)."""
    if isinstance(value, (str, bytes)) or isinstance(value, (dict, set)):
        raise TypeError(f"from_dict: {name} must be (nested) lists of numbers, got {type(value).__name__}")
    try:
        array = np.asarray(value)
    except (ValueError, TypeError, OverflowError, RecursionError) as exc:
        raise ValueError(f"from_dict: {name} must be regular nested lists of numbers: {exc}") from None
    if array.dtype.kind not in "iuf":
        raise TypeError(f"from_dict: {name} must hold numbers only, got values of type {array.dtype}")
    if array.ndim > max_dims:
        raise ValueError(f"from_dict: {name} has {array.ndim} dimensions, at most {max_dims} are allowed")
    array = array.astype(float)
    if array.size and not np.isfinite(array).all():
        raise ValueError(f"from_dict: {name} holds a non-finite value; all values must be finite")
    return array


def _mapping(data, key):
    value = data.get(key)
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise TypeError(f"from_dict: {key} must be a dict, got {type(value).__name__}")
    for name in value:
        if not isinstance(name, str):
            raise TypeError(f"from_dict: {key} keys must be strings, got {name!r}")
    return value


def _shape(value, key):
    if not isinstance(value, (list, tuple)):
        raise TypeError(f"from_dict: auxiliary_shapes[{key!r}] must be a list of integers, got {type(value).__name__}")
    if len(value) > MAX_AUXILIARY_DIMS:
        raise ValueError(f"from_dict: auxiliary_shapes[{key!r}] has {len(value)} dimensions, "
                         f"at most {MAX_AUXILIARY_DIMS} are allowed")
    return tuple(check_int(size, f"from_dict: auxiliary_shapes[{key!r}][{i}]", minimum=0)
                 for i, size in enumerate(value))


def _auxiliary(data):
    arrays = _mapping(data, "auxiliary")
    shapes = _mapping(data, "auxiliary_shapes")
    for key in shapes:
        if key not in arrays:
            raise ValueError(f"from_dict: auxiliary_shapes[{key!r}] has no array in auxiliary")
    auxiliary = {}
    for key, value in arrays.items():
        array = _numbers(value, f"auxiliary[{key!r}]", max_dims=MAX_AUXILIARY_DIMS)
        if key in shapes:
            shape = _shape(shapes[key], key)
            if int(np.prod(shape, dtype=object)) != array.size:
                raise ValueError(f"from_dict: auxiliary_shapes[{key!r}] = {list(shape)} does not fit the "
                                 f"{array.size} values of auxiliary[{key!r}]")
            array = array.reshape(shape)
        auxiliary[key] = array
    return auxiliary


def _check_header(data):
    if not isinstance(data, dict):
        raise TypeError(f"from_dict expects a dict, got {type(data).__name__}")
    for key in data:
        if key not in SCHEMA_KEYS:
            raise ValueError(f"from_dict: unknown key {key!r}; a Spline dict has the keys {list(SCHEMA_KEYS)}")
    kind = data.get("type", TYPE_NAME)
    if not isinstance(kind, str) or kind != TYPE_NAME:
        raise ValueError(f"not a splinecraft.Spline dict: type={kind!r}")
    version = data.get("version", 1)
    if isinstance(version, bool) or not isinstance(version, numbers.Integral) or version != 1:
        raise ValueError(f"from_dict: version must be 1, got {version!r}")
    for key in ("bezier", "knots"):
        if key not in data:
            raise ValueError(f"from_dict: missing key {key!r}")


def spline_from_dict(cls, data):
    """Rebuild a spline from :func:`spline_to_dict` output (also after a JSON round trip), strictly."""
    _check_header(data)
    closed = check_bool(data.get("closed", False), "from_dict: closed")
    bezier = _numbers(data["bezier"], "bezier", max_dims=3)
    knots = _numbers(data["knots"], "knots", max_dims=1)
    auxiliary = _auxiliary(data)
    info = data.get("info")
    if info is None:
        info = {}
    if not isinstance(info, dict):
        raise TypeError(f"from_dict: info must be a dict, got {type(info).__name__}")
    info = to_jsonable(info, "info")
    return cls(bezier, knots, closed=closed, auxiliary=auxiliary, info=info)
