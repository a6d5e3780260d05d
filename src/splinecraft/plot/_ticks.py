"""Round tick values for the figures of :mod:`splinecraft.plot` (bqplot picks unround ones on its own).

Linear axes get "nice numbers": steps of 1, 2 or 5 times a power of ten (Heckbert's rule), so an axis
reads 0, 0.2, 0.4 ... or 100, 200, 300 ..., never -0.0038, 0.17, 0.48. Log axes get powers of ten (1, 10,
100), with 2 and 5 between them when the range spans less than two decades. :func:`tick_format` gives the
d3 format string that prints those values with just the digits they need.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["nice_step", "nice_ticks", "nice_limits", "log_ticks", "tick_format"]

_MANTISSAS = (1.0, 2.0, 5.0, 10.0)


def _check_range(low, high, name="range"):
    low, high = float(low), float(high)
    if not (math.isfinite(low) and math.isfinite(high)):
        raise ValueError(f"{name} must be finite, got ({low}, {high})")
    if high < low:
        low, high = high, low
    return low, high


def nice_step(span: float, count: int = 5) -> float:
    """The round step (1, 2 or 5 times a power of ten) nearest to ``span / count`` (Heckbert's rule)."""
    span = abs(float(span))
    if not math.isfinite(span) or span == 0.0:
        return 1.0
    raw = span / max(int(count), 1)
    if not raw > 0.0:  # a subnormal span over many ticks underflows
        return span
    magnitude = 10.0 ** math.floor(math.log10(raw))
    residual = raw / magnitude
    for mantissa, below in zip(_MANTISSAS, (1.5, 3.0, 7.0)):
        if residual < below:
            return mantissa * magnitude
    return 10.0 * magnitude


def _smaller_step(step: float) -> float:
    """The next round step below ``step`` (5 -> 2 -> 1 -> 0.5 ...)."""
    magnitude = 10.0 ** math.floor(math.log10(step) + 1e-9)
    mantissa = round(step / magnitude)
    return {1: 0.5, 2: 1.0, 5: 2.0}.get(mantissa, 1.0) * magnitude


def _decimals(step: float) -> int:
    return max(0, -math.floor(math.log10(step) + 1e-9))


def nice_ticks(low: float, high: float, count: int = 5) -> np.ndarray:
    """Round tick values inside ``[low, high]``: about ``count`` of them, at least two.

    >>> nice_ticks(-0.0038, 0.97).tolist()
    [0.0, 0.2, 0.4, 0.6, 0.8]
    """
    low, high = _check_range(low, high)
    if high == low:
        return np.array([low])
    half = high / 2 - low / 2  # half the span: finite where the span itself overflows (-1e308 .. 1e308)
    step = nice_step(high - low, count) if math.isfinite(high - low) else nice_step(half, max(int(count) // 2, 1))
    while True:
        first, last = math.ceil(low / step - 1e-9), math.floor(high / step + 1e-9)
        if last - first >= 1 or step < half * 2e-6:
            break
        step = _smaller_step(step)
    values = np.arange(first, last + 1) * step
    places = _decimals(step) + 1
    if step < 1.0 and places <= 300:  # steps below 1 leave float noise (0.30000000000000004); 10^places is finite
        values = np.round(values, places)
    values = np.unique(values + 0.0)  # -0.0 -> 0.0
    # a span below the numbers' resolution (0.1 .. 0.1 + 3e-17) rounds its ticks together: its two ends instead
    return values if len(values) >= 2 else np.unique([low, high])


def nice_limits(low: float, high: float, count: int = 5) -> tuple:
    """``[low, high]`` widened outwards to the nearest round steps (a chart's axis range)."""
    low, high = _check_range(low, high)
    if high == low:
        pad = abs(low) * 0.1 or 1.0
        low, high = low - pad, high + pad
    step = nice_step(high - low, count)
    return (float(math.floor(low / step + 1e-9) * step) + 0.0, float(math.ceil(high / step - 1e-9) * step) + 0.0)


def log_ticks(low: float, high: float) -> np.ndarray:
    """Ticks of a log axis inside ``[low, high]`` (both > 0): the powers of ten when three or more fit, else
    also their 2 and 5 multiples (at most 7 ticks), and round linear steps on a range too short for those.

    >>> log_ticks(0.3, 2000).tolist()
    [1.0, 10.0, 100.0, 1000.0]
    """
    low, high = _check_range(low, high)
    if low <= 0:
        raise ValueError(f"a log axis needs a range above 0, got ({low}, {high})")
    first, last = math.floor(math.log10(low) + 1e-9), math.ceil(math.log10(high) - 1e-9)
    decades = 10.0 ** np.arange(first, last + 1, dtype=float)
    inside = lambda values: values[(values >= low * (1 - 1e-9)) & (values <= high * (1 + 1e-9))]  # noqa: E731
    ticks = inside(decades)
    if len(ticks) < 3:
        with_multiples = inside(np.sort(np.concatenate([decades, 2 * decades, 5 * decades])))
        if len(ticks) < 2 or len(with_multiples) <= 7:
            ticks = with_multiples
    if len(ticks) < 2:
        ticks = inside(np.sort(np.concatenate([decades * k for k in range(1, 10)])))
    if len(ticks) < 2:                                   # less than a decade: round linear steps
        ticks = nice_ticks(low, high, 3)
    return ticks


def tick_format(ticks, *, log: bool = False) -> str:
    """A d3 format string that prints ``ticks`` exactly and briefly ("0.2", "150", "1e-4").

    Linear ticks get as many decimals as their step needs; log ticks print plainly from 0.001 to
    99 999 and in exponent form beyond.
    """
    values = np.asarray(ticks, dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return ""
    largest = float(np.abs(values).max())
    if log:
        smallest = float(np.abs(values[values != 0]).min()) if np.any(values != 0) else 1.0
        return "~g" if smallest >= 1e-3 and largest < 1e5 else ".0e"
    step = float(np.min(np.diff(np.unique(values)))) if values.size > 1 else (largest or 1.0)
    # significant digits that tell the ticks apart: those of the largest down to the step's place
    digits = int(min(17, max(2, math.ceil(math.log10(largest / step)) + 1))) if step > 0 and largest > 0 else 2
    if largest >= 1e6:
        return f".{digits}~s"                          # SI prefixes: 1.0001M, not every tick "1M"
    decimals = _decimals(step) if step < 1 else 0
    return f".{decimals}f" if decimals <= 20 else f".{digits - 1}~e"  # d3 caps fixed decimals at 20
