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


def _convert(value, where, non_finite, coerce, depth):
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
        raise ValueError(f"{where} is {number!r}; JSON values must be finite")
    if depth <= 0 and isinstance(value, (dict, list, tuple, np.ndarray)):
        raise ValueError(f"{where} is nested too deeply (more than {MAX_DEPTH} levels)")
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "biuf":
            if not coerce:
                raise TypeError(f"{where} must be JSON-able, got an array of dtype {value.dtype}")
            return str(value)
        return _convert(value.tolist(), where, non_finite, coerce, depth)
    if isinstance(value, dict):
        out = {}
        for key, item in value.items():
            if not isinstance(key, str):
                if not coerce:
                    raise TypeError(f"{where} keys must be strings, got {key!r}")
                key = str(key)
            out[key] = _convert(item, f"{where}[{key!r}]", non_finite, coerce, depth - 1)
        return out
    if isinstance(value, (list, tuple)):
        return [_convert(item, f"{where}[{i}]", non_finite, coerce, depth - 1) for i, item in enumerate(value)]
    if coerce:
        return str(value)
    raise TypeError(f"{where} must be JSON-able, got {type(value).__name__}")
