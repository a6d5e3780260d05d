"""Input validation shared by the spline engine (private).

Every helper raises ``TypeError`` for values of the wrong kind and ``ValueError`` for values of the
right kind but outside the allowed domain, and names the offending argument and, where it applies, the
first offending index -- never a silent NaN.
"""
from __future__ import annotations

import numbers

import numpy as np

__all__ = [
    "as_float_array",
    "as_points",
    "per_item",
    "check_strictly_increasing",
    "check_bool",
    "check_choice",
    "format_index",
]


def format_index(flat_index: int, shape: tuple) -> str:
    """Format a flat index as ``[i]`` or ``[i, j]`` for error messages."""
    if len(shape) <= 1:
        return f"[{int(flat_index)}]"
    multi = np.unravel_index(int(flat_index), shape)
    return "[" + ", ".join(str(int(i)) for i in multi) + "]"


def as_float_array(value, name: str, *, ndim: int | None = None, copy: bool = False) -> np.ndarray:
    """Convert ``value`` to a finite float64 array.

    Raises
    ------
    TypeError
        If ``value`` is not numeric (strings, objects, complex numbers, booleans arrays are accepted
        as 0/1 only when numeric).
    ValueError
        If the number of dimensions differs from ``ndim`` or an entry is NaN or infinite (the message
        names the first such index).
    """
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be numeric, got {type(value).__name__}")
    if isinstance(value, np.ndarray) and value.dtype.kind not in "biuf":
        if value.dtype.kind == "c":
            raise TypeError(f"{name} must be real, got complex values")
        if value.dtype.kind != "O":
            raise TypeError(f"{name} must be a numeric array, got dtype {value.dtype}")
    try:
        array = np.array(value, dtype=float, copy=True) if copy else np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric array, got {type(value).__name__}: {exc}") from None
    if ndim is not None and array.ndim != ndim:
        raise ValueError(f"{name} must have {ndim} dimension(s), got shape {array.shape}")
    if array.size and not np.isfinite(array).all():
        bad = int(np.flatnonzero(~np.isfinite(array))[0])
        raise ValueError(
            f"{name}{format_index(bad, array.shape)} is {float(array.reshape(-1)[bad])!r}; "
            f"all values must be finite"
        )
    return array


def as_points(value, name: str, *, min_count: int, dim: int | None = None) -> np.ndarray:
    """Validate an ``(n, d)`` array of finite points with at least ``min_count`` rows."""
    points = as_float_array(value, name)
    if points.ndim != 2:
        raise ValueError(f"{name} must be an (n, d) array of points, got shape {points.shape}")
    if dim is not None and points.shape[1] != dim:
        raise ValueError(f"{name} must have {dim} coordinates per point, got {points.shape[1]}")
    if points.shape[1] < 1:
        raise ValueError(f"{name} must have at least one coordinate per point")
    if points.shape[0] < min_count:
        raise ValueError(f"{name} needs at least {min_count} points, got {points.shape[0]}")
    return points


def per_item(value, count: int, name: str, *, what: str) -> np.ndarray:
    """Broadcast a scalar to ``(count,)`` or validate a 1-d array of length ``count``.

    ``what`` says what the entries belong to (e.g. ``"one per point"``) for the length message.
    """
    if isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)):
        scalar = float(value)
        if not np.isfinite(scalar):
            raise ValueError(f"{name} is {scalar!r}; all values must be finite")
        return np.full(count, scalar)
    array = as_float_array(value, name)
    if array.ndim == 0:
        return np.full(count, float(array))
    if array.ndim != 1:
        raise ValueError(f"{name} must be a scalar or a 1-d array ({what}), got shape {array.shape}")
    if array.shape[0] != count:
        raise ValueError(
            f"{name} has length {array.shape[0]} but {count} values are needed ({what})"
        )
    return array


def check_strictly_increasing(values: np.ndarray, name: str) -> None:
    """Raise ``ValueError`` naming the first ``i`` with ``values[i+1] <= values[i]``."""
    if values.shape[0] < 2:
        return
    steps = np.diff(values)
    if not (steps > 0).all():
        bad = int(np.flatnonzero(~(steps > 0))[0])
        raise ValueError(
            f"{name} must be strictly increasing, but {name}[{bad + 1}] = {float(values[bad + 1])!r} "
            f"<= {name}[{bad}] = {float(values[bad])!r}"
        )


def check_bool(value, name: str) -> bool:
    """Accept Python and numpy booleans only."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise TypeError(f"{name} must be a bool, got {type(value).__name__}")


def check_choice(value, name: str, choices) -> str:
    """Check that ``value`` is one of the strings in ``choices``."""
    if not isinstance(value, str):
        raise TypeError(f"{name} must be one of {sorted(choices)}, got {type(value).__name__}")
    if value not in choices:
        raise ValueError(f"{name} must be one of {sorted(choices)}, got {value!r}")
    return value


def check_positive_number(value, name: str) -> float:
    """A finite real number > 0."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    value = float(value)
    if not np.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return value


def check_int(value, name: str, *, minimum: int | None = None) -> int:
    """An integer (Python or numpy, not bool) >= ``minimum``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    value = int(value)
    if minimum is not None and value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return value
