"""Affine maps of the plane for outline transforms (thesis section 3.3: transform only the control points).

Every map is ``x -> A x + b`` with a 2x2 linear part ``A`` and an offset ``b``. :func:`affine_parts` reads a
2x3 ``[[a, c, e], [b, d, f]]`` or 3x3 homogeneous matrix (last row ``[0, 0, 1]``; the SVG ``matrix(a b c d e
f)`` order) and refuses non-finite or singular ones. The builders return 3x3 matrices about a centre point.
"""
from __future__ import annotations

import math

import numpy as np

from .._validation import check_number

__all__ = ["affine_parts", "translation", "rotation", "scaling", "shearing", "reflection", "SINGULAR_RTOL",
           "MAX_COORDINATE", "MIN_EXTENT", "check_reach"]

#: A linear part with ``|det A| <= SINGULAR_RTOL * |A|_max^2`` is refused as singular (it would flatten the shape).
#: The test is made on ``A / |A|_max``, so that it does not depend on the scale (a scale of 1e200 squares to
#: infinity, one of 1e-200 to zero).
SINGULAR_RTOL = 1e-12
#: Largest coordinate a transform may produce: beyond it an outline's areas and lengths (squares of coordinate
#: differences) overflow float64 (about 1.8e308), and orientation and nesting are lost.
MAX_COORDINATE = 1e150
#: Smallest extent (largest coordinate range) of a contour a transform may produce: below it the contour's
#: area underflows towards float64's subnormals and zero (about 2.2e-308), and orientation and nesting are lost.
MIN_EXTENT = 1e-150


def affine_parts(matrix, name="matrix"):
    """``(A, b)`` of a 2x3 or 3x3 affine matrix; ``ValueError`` naming the problem for a bad one."""
    if isinstance(matrix, (str, bytes)):
        raise TypeError(f"{name} must be a 2x3 or 3x3 array of numbers, got {type(matrix).__name__}")
    try:
        array = np.array(matrix, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a 2x3 or 3x3 array of numbers, got {type(matrix).__name__}") from None
    if array.shape not in ((2, 3), (3, 3)):
        raise ValueError(f"{name} must be a 2x3 or 3x3 affine matrix, got shape {array.shape}")
    if not np.isfinite(array).all():
        raise ValueError(f"{name} has non-finite entries: {array.tolist()}")
    if array.shape == (3, 3) and not np.allclose(array[2], [0.0, 0.0, 1.0], rtol=0, atol=1e-12):
        raise ValueError(f"{name}'s last row must be [0, 0, 1] (an affine map, not a projective one), got "
                         f"{array[2].tolist()}")
    linear, offset = array[:2, :2], array[:2, 2]
    size = float(np.abs(linear).max())
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # LAPACK's LU of an exactly singular A
        relative = float(np.linalg.det(linear / size)) if size > 0 else 0.0  # det(A) / |A|_max^2, scale-free
    if not abs(relative) > SINGULAR_RTOL:
        raise ValueError(f"{name} is singular (determinant {relative:.3g} x {size:.3g}^2): it would collapse the "
                         "shape onto a line or a point")
    return linear, offset


def check_reach(points, name="the transformed outline", *, given=False):
    """``ValueError`` when a coordinate of the points of one contour ``points`` (``(..., 2)``) is beyond
    ±:data:`MAX_COORDINATE` (or not finite), or their extent is below :data:`MIN_EXTENT`. ``given``: the
    points are an input (a contour being built), not the result of a transform; the message says so."""
    points = np.asarray(points, float).reshape(-1, 2)
    if not points.size:
        return
    if not (np.abs(points) <= MAX_COORDINATE).all():
        worst = float(np.nanmax(np.where(np.isfinite(points), np.abs(points), np.inf)))
        raise ValueError(f"{name} {'has' if given else 'would reach'} a coordinate of {worst:.3g}, beyond "
                         f"±{MAX_COORDINATE:g} where its areas and lengths overflow: use a smaller "
                         f"{'unit' if given else 'scale or offset'}")
    extent = float((points.max(axis=0) - points.min(axis=0)).max())
    if not extent >= MIN_EXTENT:
        raise ValueError(f"{name} {'spans' if given else 'would shrink a contour to'} an extent of {extent:.3g}, "
                         f"below {MIN_EXTENT:g} where its area vanishes in floating point: use a larger "
                         f"{'unit' if given else 'scale'}")


def _about(linear, center):
    """3x3 matrix of ``x -> linear (x - center) + center``."""
    center = np.asarray(center, float).reshape(2)
    matrix = np.eye(3)
    matrix[:2, :2] = linear
    matrix[:2, 2] = center - linear @ center
    return matrix


def translation(dx, dy):
    """``x -> x + (dx, dy)``."""
    matrix = np.eye(3)
    matrix[:2, 2] = [check_number(dx, "dx"), check_number(dy, "dy")]
    return matrix


def rotation(degrees, center=(0.0, 0.0)):
    """Rotation by ``degrees`` about ``center``; positive turns from +x towards +y (clockwise on screen,
    where y points down)."""
    angle = math.radians(check_number(degrees, "degrees"))
    cos, sin = math.cos(angle), math.sin(angle)
    return _about(np.array([[cos, -sin], [sin, cos]]), center)


def scaling(sx, sy=None, center=(0.0, 0.0)):
    """Scale by ``sx`` along x and ``sy`` (default ``sx``: uniform) along y about ``center``."""
    sx = check_number(sx, "sx")
    sy = sx if sy is None else check_number(sy, "sy")
    return _about(np.diag([sx, sy]), center)


def shearing(kx, ky=0.0, center=(0.0, 0.0)):
    """Shear ``x' = x + kx y``, ``y' = y + ky x`` about ``center`` (``kx = tan(slant)`` slants a glyph)."""
    return _about(np.array([[1.0, check_number(kx, "kx")], [check_number(ky, "ky"), 1.0]]), center)


def reflection(axis="vertical", center=(0.0, 0.0)):
    """Mirror about a line through ``center``: ``"vertical"`` (left-right flip), ``"horizontal"`` (up-down),
    or a number = the line's angle in degrees from +x."""
    if axis == "vertical":
        degrees = 90.0
    elif axis == "horizontal":
        degrees = 0.0
    elif isinstance(axis, str):
        raise ValueError(f"axis must be 'vertical', 'horizontal' or an angle in degrees, got {axis!r}")
    else:
        degrees = check_number(axis, "axis")
    angle = 2.0 * math.radians(degrees)
    return _about(np.array([[math.cos(angle), math.sin(angle)], [math.sin(angle), -math.cos(angle)]]), center)
