"""Argument checks shared by every layer of splinecraft (engine, capture, command line, widgets).

One wording everywhere: each check names the argument (and the first offending index or key), raises
``TypeError`` for a value of the wrong kind and ``ValueError`` for a value of the right kind outside the
allowed domain, and returns the value converted to the plain type the code works with (``float``,
``int``, ``bool``, a float64 array). Nothing is coerced silently: ``True`` is not an integer, ``"no"`` is
not a bool, ``NaN`` is not a number here.

What counts as what:

* **number** -- a real number: ``int``, ``float``, numpy integers and floats (``numbers.Real``), not
  ``bool``/``np.bool_``; finite unless ``finite=False``.
* **integer** -- ``int`` or a numpy integer (``numbers.Integral``), not ``bool``/``np.bool_``; with
  ``integral_floats=True`` also a float with an integer value (``3.0``).
* **bool** -- ``True``, ``False`` or ``np.bool_`` only.
* **points** -- an ``(n, d)`` array of finite numbers.

**The coincidence rule** (one rule, used by every layer). Two neighbouring points ``p``, ``q`` coincide when

    |p - q| <= COINCIDENT_RTOL * extent,   COINCIDENT_RTOL = 1e-12,

where ``extent`` is the largest coordinate range of the whole point set (``max_k (max_i x_ik - min_i x_ik)``).
The rule is scale-free: scaling or translating every point leaves the verdict unchanged, at any scale
float64 holds (the distances are computed on coordinates divided by the extent, so they neither
underflow near 1e-300 nor overflow near 1e300). A point set whose points are all equal has extent 0
and every pair of neighbours coincides.
"""
from __future__ import annotations

import math
import numbers
from collections.abc import Hashable, Mapping

import numpy as np

__all__ = [
    "COINCIDENT_RTOL",
    "plain",
    "format_index",
    "check_number",
    "check_positive_number",
    "check_int",
    "check_positive_int",
    "check_bool",
    "check_choice",
    "check_options",
    "as_float_array",
    "as_points",
    "check_points",
    "per_item",
    "check_strictly_increasing",
    "point_extent",
    "relative_gaps",
    "check_distinct_neighbours",
    "blank_text",
    "control_character",
    "file_path",
]

#: Neighbouring points closer than this times the extent of the point set coincide (see the module text).
COINCIDENT_RTOL = 1e-12


def _kind(value) -> str:
    return type(value).__name__


def plain(value):
    """``value`` for a message: a numpy scalar as the Python value it holds (``np.float64(0.5)`` -> ``0.5``, whose
    repr numpy 2 writes ``np.float64(0.5)``), also the items of a tuple or list (one level deep, and their own);
    anything else unchanged. A float of less precision than a double (float32, float16) is the shortest decimal that
    reads back as it (numpy's ``str``: ``np.float32(0.1)`` -> ``0.1``, not the ``0.10000000149011612`` it converts to)."""
    if isinstance(value, np.floating) and np.finfo(value.dtype).bits < 64:
        return float(str(value))
    if isinstance(value, np.generic):
        item = value.item()
        return value if isinstance(item, np.generic) else item  # np.longdouble keeps its own type
    if type(value) in (tuple, list):
        return type(value)(plain(item) for item in value)
    return value


def _describe(value) -> str:
    """``repr`` of a value for a message (numpy scalars as plain numbers, :func:`plain`), shortened for long
    input."""
    text = repr(plain(value))
    return text if len(text) <= 80 else text[:77] + "..."


def format_index(flat_index: int, shape: tuple) -> str:
    """Format a flat index as ``[i]`` or ``[i, j]`` for error messages."""
    if len(shape) <= 1:
        return f"[{int(flat_index)}]"
    multi = np.unravel_index(int(flat_index), shape)
    return "[" + ", ".join(str(int(i)) for i in multi) + "]"


# ---------------------------------------------------------------------------------------------- scalars
def _is_real(value) -> bool:
    if type(value) is float or type(value) is int:  # the common case, without the ABC's check (a bool is no int here)
        return True
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def _as_float(value, name) -> float:
    """``float(value)``; an integer beyond the float64 range is a ``ValueError`` naming ``name``."""
    try:
        return float(value)
    except OverflowError:
        raise ValueError(f"{name} = {_describe(value)} is beyond the float64 range") from None


def _bounds_text(minimum, maximum, inclusive) -> str:
    low_closed, high_closed = inclusive
    parts = []
    if minimum is not None:
        parts.append(f"{'>=' if low_closed else '>'} {minimum:g}")
    if maximum is not None:
        parts.append(f"{'<=' if high_closed else '<'} {maximum:g}")
    return " and ".join(parts)


def _inclusive_pair(inclusive):
    if inclusive is True or inclusive is False or isinstance(inclusive, np.bool_):
        return bool(inclusive), bool(inclusive)
    low, high = inclusive
    return bool(low), bool(high)


def check_number(value, name: str, *, minimum=None, maximum=None, inclusive=True, finite: bool = True) -> float:
    """A real number (not a bool), finite, inside the bounds; returned as ``float``.

    ``inclusive`` is a bool for both ends or a pair ``(low_closed, high_closed)``: ``minimum=0,
    inclusive=False`` means ``> 0``. ``finite=False`` lets ``+-inf`` through the type check (NaN is
    always refused); the bounds still apply.
    """
    if not _is_real(value):
        raise TypeError(f"{name} must be a real number, got {_describe(value)} ({_kind(value)})")
    number = _as_float(value, name)
    shown = plain(value) if isinstance(value, np.floating) else number  # a float32 as given, not its double
    low_closed, high_closed = _inclusive_pair(inclusive)
    if number != number or (finite and not math.isfinite(number)):  # (number: a Python float)
        bounds = _bounds_text(minimum, maximum, (low_closed, high_closed))
        what = f"a finite number {bounds}" if bounds else "a finite number"
        raise ValueError(f"{name} must be {what}, got {shown!r}")
    too_low = minimum is not None and (number < minimum or (not low_closed and number == minimum))
    too_high = maximum is not None and (number > maximum or (not high_closed and number == maximum))
    if too_low or too_high:
        raise ValueError(f"{name} must be {_bounds_text(minimum, maximum, (low_closed, high_closed))}, got {shown!r}")
    return number


def check_positive_number(value, name: str) -> float:
    """A finite real number ``> 0``."""
    return check_number(value, name, minimum=0.0, inclusive=False)


def check_int(value, name: str, *, minimum: int | None = None, maximum: int | None = None,
              integral_floats: bool = False) -> int:
    """An integer (Python or numpy; not a bool) inside ``[minimum, maximum]``; returned as ``int``.

    ``integral_floats=True`` also accepts a finite float with an integer value (``3.0``).
    """
    shown = None  # an integral float is named as given (1e+300, not its 301 digits)
    if type(value) is not int and (isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral)):
        if integral_floats and _is_real(value) and np.isfinite(float(value)) and float(value).is_integer():
            shown, value = repr(float(value)), int(value)
        else:
            raise TypeError(f"{name} must be an integer, got {_describe(value)} ({_kind(value)})")
    number = int(value)
    if minimum is not None and number < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {shown or number}")
    if maximum is not None and number > maximum:
        raise ValueError(f"{name} must be <= {maximum}, got {shown or _describe(number)}")
    return number


def check_positive_int(value, name: str, *, maximum: int | None = None) -> int:
    """An integer ``>= 1`` (and ``<= maximum``)."""
    return check_int(value, name, minimum=1, maximum=maximum)


def check_bool(value, name: str) -> bool:
    """``True``, ``False`` or ``np.bool_``; anything else (``0``, ``"no"``, ``None``) is a ``TypeError``."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise TypeError(f"{name} must be a bool (True or False), got {_describe(value)} ({_kind(value)})")


def _choices_text(choices) -> str:
    if all(isinstance(choice, str) for choice in choices):
        return str(sorted(choices))
    return "[" + ", ".join(repr(choice) for choice in choices) + "]"


def check_choice(value, name: str, choices):
    """``value`` if it is one of ``choices``; returned unchanged.

    A value of another kind than the choices (a list, a number where names are expected, a bool where
    numbers are expected) is a ``TypeError`` naming ``name``, never Python's "unhashable type".
    """
    choices = tuple(choices)
    if type(value) is str:  # the common case: the first choice equal to it that is no flag (else the checks below)
        for choice in choices:
            if choice == value and not isinstance(choice, (bool, np.bool_)):
                return choice
    text = _choices_text(choices)
    if not isinstance(value, Hashable) or isinstance(value, np.ndarray):
        raise TypeError(f"{name} must be one of {text}, got {_kind(value)}")
    is_flag = isinstance(value, (bool, np.bool_))
    if all(isinstance(choice, str) for choice in choices):
        if not isinstance(value, str):
            raise TypeError(f"{name} must be one of {text}, got {_describe(value)} ({_kind(value)})")
    elif is_flag and not any(isinstance(choice, (bool, np.bool_)) for choice in choices):
        raise TypeError(f"{name} must be one of {text}, got {_describe(value)} ({_kind(value)})")
    for choice in choices:
        if choice == value and isinstance(choice, (bool, np.bool_)) == is_flag:
            return choice
    raise ValueError(f"{name} must be one of {text}, got {_describe(value)}")


def check_options(options, name: str, *, allowed=None, reserved=(), reserved_reason: str = "") -> dict:
    """A mapping of keyword options with string keys, as a new ``dict`` (``None`` gives ``{}``).

    ``allowed`` (optional): the accepted keys; an unknown key is a ``TypeError`` naming it and listing the
    accepted ones. ``reserved``: keys the caller sets itself; passing one is a ``TypeError`` naming it
    (``reserved_reason`` says why, e.g. ``"trace sets it from the boundary"``).
    """
    if options is None:
        return {}
    if not isinstance(options, Mapping):
        raise TypeError(f"{name} must be a dict of keyword options, got {_kind(options)}")
    result = {}
    for key, item in options.items():
        if not isinstance(key, str):
            raise TypeError(f"{name} keys must be strings, got {_describe(key)} ({_kind(key)})")
        key = str(key)  # np.str_ too: its repr is np.str_('key')
        if key in reserved:
            why = f": {reserved_reason}" if reserved_reason else ""
            raise TypeError(f"{name}[{key!r}] cannot be set here{why}")
        if allowed is not None and key not in allowed:
            raise TypeError(f"{name} has an unknown key {key!r}; accepted keys: {sorted(allowed)}")
        result[key] = item
    return result


# ---------------------------------------------------------------------------------------------- names
def blank_text(text: str) -> str | None:
    """How ``text`` (a name, a path) is blank, for a message (``"empty"``, ``"blank (' ')"``), or ``None`` when it
    holds a character other than white space. A blank path still names a file (``' '`` is a folder called
    space), which a caller never meant: a variable that was not set, a stray quote."""
    if text.strip():
        return None
    return "empty" if not text else f"blank ({text!r}: only white space)"


def file_path(path, example: str):
    """``path`` (str or os.PathLike) as a ``pathlib.Path`` to write a file to; a blank one is a ``ValueError`` naming
    ``example`` ('' is the current folder to ``pathlib``, ' ' a file called space)."""
    import os
    from pathlib import Path

    text = os.fspath(path)
    if isinstance(text, str) and blank_text(text):
        raise ValueError(f"path is {blank_text(text)}: give a file name such as {example}")
    return Path(text)


def control_character(text: str) -> tuple | None:
    """``(index, code point)`` of the first control character (Unicode category Cc: C0, DEL, C1; NUL, tab and
    newline among them) in ``text``, or ``None``. A name holding one breaks the lines that show it (a manifest,
    the command line's messages) and most file browsers."""
    import unicodedata

    for index, char in enumerate(text):
        if unicodedata.category(char) == "Cc":
            return index, ord(char)
    return None


# ---------------------------------------------------------------------------------------------- arrays
def as_float_array(value, name: str, *, ndim: int | None = None, copy: bool = False) -> np.ndarray:
    """``value`` as a finite float64 array.

    Raises ``TypeError`` for non-numeric input (strings, bytes, complex, objects, ``None`` anywhere, ragged
    nested lists) and ``ValueError`` for the wrong number of dimensions, a NaN/inf entry (naming its index) or a
    masked array with masked entries. Boolean arrays are read as 0/1.
    """
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be numeric, got {_kind(value)}")
    if value is None:  # numpy reads None as NaN: a missing value is not a number, and not a NaN either
        raise TypeError(f"{name} must be numeric, got None")
    if isinstance(value, np.ma.MaskedArray) and np.ma.getmaskarray(value).any():
        # numpy reads the values under the mask as if they were data
        raise ValueError(f"{name} is a masked array with masked entries; fill or drop them first")
    if isinstance(value, np.ndarray) and value.dtype.kind not in "biuf":
        if value.dtype.kind == "c":
            raise TypeError(f"{name} must be real, got complex values")
        if value.dtype.kind != "O":
            raise TypeError(f"{name} must be a numeric array, got dtype {value.dtype}")
        if any(item is None for item in value.reshape(-1)):
            raise TypeError(f"{name} must be numeric, got an object array containing None")
    if not isinstance(value, np.ndarray) and isinstance(value, (list, tuple)):
        try:  # numpy would parse numeric strings inside lists ([["0", "1"]]); refuse them like a str array
            kind = np.asarray(value).dtype.kind
        except (TypeError, ValueError, OverflowError):
            kind = None  # ragged or odd: the conversion below says why
        if kind in ("U", "S"):
            raise TypeError(f"{name} must be numeric, got a list containing strings")
        if kind == "O" and any(item is None for item in np.asarray(value, dtype=object).reshape(-1)):
            raise TypeError(f"{name} must be numeric, got a list containing None")
    try:
        array = np.array(value, dtype=float, copy=True) if copy else np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise TypeError(f"{name} must be a numeric array, got {_kind(value)}: {exc}") from None
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
    """An ``(n, d)`` float64 array of finite points with at least ``min_count`` rows."""
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


def check_points(value, name: str = "points", *, min_count: int = 1, dim: int | None = None,
                 distinct: bool = False, closed: bool = False) -> np.ndarray:
    """Finite ``(n, d)`` points (:func:`as_points`); with ``distinct=True`` also the coincidence rule.

    ``closed=True`` treats the last and the first point as neighbours too.
    """
    points = as_points(value, name, min_count=min_count, dim=dim)
    if distinct:
        check_distinct_neighbours(points, name, closed=closed)
    return points


def per_item(value, count: int, name: str, *, what: str) -> np.ndarray:
    """Broadcast a scalar to ``(count,)`` or validate a 1-d array of length ``count``.

    ``what`` says what the entries belong to (e.g. ``"one per point"``) for the length message.
    """
    if _is_real(value):
        scalar = _as_float(value, name)
        if not np.isfinite(scalar):
            raise ValueError(f"{name} is {scalar!r}; all values must be finite")
        return np.full(count, scalar)
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be a number or an array of numbers, got {_kind(value)}")
    array = as_float_array(value, name)
    if array.ndim == 0:
        return np.full(count, float(array))
    if array.ndim != 1:
        raise ValueError(f"{name} must be a scalar or a 1-d array ({what}), got shape {array.shape}")
    if array.shape[0] != count:
        raise ValueError(f"{name} has length {array.shape[0]} but {count} values are needed ({what})")
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


# ---------------------------------------------------------------------------------------------- coincidence
def _half_extent(points: np.ndarray) -> float:
    """Half the largest coordinate range (always finite for finite points)."""
    if points.shape[0] < 2:
        return 0.0
    return float(np.max(0.5 * points.max(axis=0) - 0.5 * points.min(axis=0)))


def point_extent(points: np.ndarray) -> float:
    """Largest coordinate range ``max_k (max_i x_ik - min_i x_ik)`` of finite ``(n, d)`` points.

    Computed without overflow in the differences; the result is ``inf`` only if the true range exceeds
    the largest float64.
    """
    with np.errstate(over="ignore"):
        return 2.0 * _half_extent(points)


def relative_gaps(points: np.ndarray, closed: bool = False, extent: float | None = None) -> np.ndarray:
    """Distances between neighbouring points divided by the extent of the set (``n - 1``, or ``n`` closed).

    Scale-free and safe at any float64 scale: the differences are divided by the extent before they are
    squared. All zeros for a set of equal points. ``extent`` (optional) is :func:`point_extent` of the
    set, if already known.
    """
    half_extent = 0.5 * extent if extent is not None and np.isfinite(extent) else _half_extent(points)
    half = 0.5 * points
    legs = np.diff(half, axis=0)
    if closed:
        legs = np.concatenate([legs, half[:1] - half[-1:]], axis=0)
    if not half_extent > 0:
        return np.zeros(legs.shape[0])
    legs /= half_extent
    return np.sqrt(np.einsum("ij,ij->i", legs, legs))


def check_distinct_neighbours(points: np.ndarray, name: str = "points", *, closed: bool = False,
                              extent: float | None = None) -> np.ndarray:
    """Apply the coincidence rule; return the relative gaps (:func:`relative_gaps`).

    Raises ``ValueError`` naming the first pair of neighbours that coincide. For a closed set, a last
    point equal to the first is reported as such (a closed curve takes its points without repeating
    the first one at the end).
    """
    gaps = relative_gaps(points, closed, extent)
    coincident = ~(gaps > COINCIDENT_RTOL)
    if coincident.any():
        i = int(np.flatnonzero(coincident)[0])
        n = points.shape[0]
        if closed and i == n - 1:
            raise ValueError(
                f"{name}[{n - 1}] and {name}[0] coincide ({name}[{n - 1}] repeats {name}[0]): a closed curve "
                f"takes N distinct points, do not repeat the first point at the end"
            )
        raise ValueError(
            f"{name}[{i}] and {name}[{(i + 1) % n}] coincide; consecutive points must be distinct "
            f"(merge them first, e.g. with splinecraft.spline.knots.remove_coincident)"
        )
    return gaps
