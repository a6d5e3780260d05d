"""Plain JSON values from numpy-flavoured Python data (shared by every layer of splinecraft).

:func:`to_jsonable` turns metadata made of dicts, lists, tuples, numpy arrays and numpy scalars into
the plain types ``json`` writes (``dict``/``list``/``str``/``int``/``float``/``bool``/``None``). Nesting
is bounded (:data:`MAX_DEPTH`), so a self-referencing or hostile structure gives a ``ValueError``
naming where it happened, never a ``RecursionError``.
"""
from __future__ import annotations

import math
import numbers

import numpy as np

__all__ = ["MAX_DEPTH", "to_jsonable"]

#: Deepest nesting of dicts and lists accepted (metadata of this package is at most a few levels deep).
MAX_DEPTH = 32

_NON_FINITE = ("keep", "none", "error")


def to_jsonable(value, where: str = "value", *, non_finite: str = "keep", coerce: bool = False,
                max_depth: int = MAX_DEPTH):
    """``value`` as plain JSON types, checked all the way down.

    Parameters
    ----------
    value
        ``None``, ``bool``/``np.bool_``, ``str``, integers, real numbers, numpy arrays, and dicts, lists
        and tuples of these (tuples become lists).
    where : str
        Name of the value for error messages; nested items are named ``where['key'][3]``.
    non_finite : {"keep", "none", "error"}
        What becomes of NaN and +-inf: kept as floats (Python's ``json`` writes them as ``NaN``,
        ``Infinity``), replaced by ``None`` (strict JSON), or a ``ValueError`` naming the item.
    coerce : bool
        ``False``: dict keys must be strings and any other type is a ``TypeError`` naming the item.
        ``True`` (for reports): keys and unknown values are converted with ``str``.
    max_depth : int
        Deeper nesting is a ``ValueError``.
    """
    if non_finite not in _NON_FINITE:
        raise ValueError(f"non_finite must be one of {list(_NON_FINITE)}, got {non_finite!r}")
    return _convert(value, where, non_finite, bool(coerce), max_depth)


def _name(where):
    """The printed name of a place: ``where`` is a name, or ``(parent, key)`` for a dict value (``key`` a string)
    or a list item (an int), built only when an error needs it (every item of a large result would format one)."""
    keys = []
    while isinstance(where, tuple):
        where, key = where
        keys.append(f"[{key!r}]" if isinstance(key, str) else f"[{key}]")
    return where + "".join(reversed(keys))


def _convert(value, where, non_finite, coerce, depth):
    kind = type(value)
    if kind is float or kind is np.float64:  # the common leaves first, as the checks below would answer for them
        if math.isfinite(value) or non_finite == "keep":
            return float(value)
    elif kind is int or kind is str or kind is bool or value is None:
        return value
    elif kind is np.int64:
        return int(value)
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        number = float(value)
        if math.isfinite(number) or non_finite == "keep":
            return number
        if non_finite == "none":
            return None
        raise ValueError(f"{_name(where)} is {number!r}; JSON values must be finite")
    if depth <= 0 and isinstance(value, (dict, list, tuple, np.ndarray)):
        raise ValueError(f"{_name(where)} is nested too deeply (more than {MAX_DEPTH} levels)")
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "biuf":
            if not coerce:
                raise TypeError(f"{_name(where)} must be JSON-able, got an array of dtype {value.dtype}")
            return str(value)
        if value.ndim < depth and (value.dtype.kind != "f" or non_finite == "keep" or np.isfinite(value).all()):
            return value.tolist()  # numbers as the items' checks give them: int, float, bool
        return _convert(value.tolist(), where, non_finite, coerce, depth)
    if isinstance(value, dict):
        out = {}
        for key, item in value.items():
            if not isinstance(key, str):
                if not coerce:
                    raise TypeError(f"{_name(where)} keys must be strings, got {key!r}")
                key = str(key)
            out[key] = _convert(item, (where, key), non_finite, coerce, depth - 1)
        return out
    if isinstance(value, (list, tuple)):
        out = []
        keep = non_finite == "keep"
        for i, item in enumerate(value):
            kind = type(item)  # the common leaves here, as _convert would answer for them (no call per number)
            if (kind is float and (keep or math.isfinite(item))) or kind is int or kind is str or kind is bool \
                    or item is None:
                out.append(item)
            elif kind is np.float64 and (keep or math.isfinite(item)):
                out.append(float(item))
            else:
                out.append(_convert(item, (where, i), non_finite, coerce, depth - 1))
        return out
    if coerce:
        return str(value)
    raise TypeError(f"{_name(where)} must be JSON-able, got {type(value).__name__}")
