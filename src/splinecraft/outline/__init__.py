"""Editable outlines: closed contours in the project's spline form, transforms, SVG and JSON (thesis section 5.1:
capture a shape, "then apply all transformations on it").

* :class:`Contour` -- one closed contour: knots, corner flags, corner handles, parameter steps, point tension
  and interval weights; its curve is rebuilt by the engine (:func:`~splinecraft.spline.interpolate`).
* :class:`Outline` -- several contours in one frame (holes, components), with the source contours and bitmap
  of a trace; edits and affine transforms return new outlines; ``to_svg``, ``to_json``/``from_json``.
* :func:`as_outline` -- from a TraceResult, an SVG (file, document or path data), knot lists or Bézier curves;
  font glyphs come from :func:`splinecraft.font.glyph_outline`.
"""
from .contour import Contour, MIN_KNOTS
from .model import Outline, contour_deviation
from .sources import as_outline, from_bezier, from_knots, from_svg, from_trace
from .transforms import affine_parts, reflection, rotation, scaling, shearing, translation

__all__ = [
    "Contour", "MIN_KNOTS", "Outline", "contour_deviation", "as_outline", "from_bezier", "from_knots", "from_svg",
    "from_trace", "affine_parts", "reflection", "rotation", "scaling", "shearing", "translation",
]
