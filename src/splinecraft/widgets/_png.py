"""PNG pictures of curves for the widgets' ``to_png()`` (PIL only: no browser, no SVG rasterizer needed).

The exact cubic Bézier pieces are sampled finely (:func:`bezier_polyline`), drawn 4 times larger than asked
and scaled down with a Lanczos filter, which gives smooth, anti-aliased lines. The frame is the widgets' own
(x right, y down, like SVG and the page).
"""
from __future__ import annotations

import io

import numpy as np

from .._validation import check_int, check_number

__all__ = ["bezier_polyline", "curves_png"]

_SUPERSAMPLE = 4
_SAMPLES_PER_PIECE = 24


def bezier_polyline(bezier, samples: int = _SAMPLES_PER_PIECE) -> np.ndarray:
    """Points along cubic Bézier pieces ``(m, 4, 2)``, ``samples`` per piece (Bernstein form, §0)."""
    bezier = np.asarray(bezier, dtype=float)
    theta = np.linspace(0.0, 1.0, samples + 1)[:-1, None]
    s = 1.0 - theta
    weights = np.stack([s**3, 3 * theta * s**2, 3 * theta**2 * s, theta**3])  # (4, samples, 1)
    points = np.einsum("jsk,mjd->msd", weights, bezier).reshape(-1, 2)
    return np.vstack([points, bezier[-1, 3]]) if len(bezier) else points


def curves_png(curves, *, width: int = 800, height: int | None = None, margin: float = 0.05, stroke=(21, 101, 192),
               stroke_width: float = 2.5, background=None, frame=None) -> bytes:
    """PNG bytes of Bézier curves (a list of ``(m, 4, 2)`` arrays), fitted into ``width`` x ``height`` pixels.

    ``frame`` ``(x0, y0, x1, y1)``: the data rectangle to show (default: the curves' bounding box plus
    ``margin`` of its size). ``background``: an optional ``(H, W)`` bool mask drawn light grey under the curves
    in the frame ``(0, 0, W, H)`` (the TraceExplorer's bitmap). ``height`` defaults to the frame's aspect.
    """
    from PIL import Image, ImageDraw

    width = check_int(width, "width", minimum=16, maximum=8000)
    margin = check_number(margin, "margin", minimum=0.0, maximum=1.0)
    stroke_width = check_number(stroke_width, "stroke_width", minimum=0.1, maximum=100.0)
    curves = [np.asarray(curve, dtype=float) for curve in curves if len(curve)]
    if frame is None:
        cloud = np.vstack([curve.reshape(-1, 2) for curve in curves]) if curves else np.zeros((1, 2))
        lo, hi = cloud.min(axis=0), cloud.max(axis=0)
        pad = margin * float(max(hi - lo)) or 1.0
        frame = (lo[0] - pad, lo[1] - pad, hi[0] + pad, hi[1] + pad)
    x0, y0, x1, y1 = (float(v) for v in frame)
    if height is None:
        height = int(round(width * (y1 - y0) / max(x1 - x0, 1e-300)))
    height = check_int(height, "height", minimum=16, maximum=8000)
    k = _SUPERSAMPLE
    scale = min(width / (x1 - x0), height / (y1 - y0)) * k
    offset = np.array([(width * k - scale * (x1 - x0)) / 2 - scale * x0, (height * k - scale * (y1 - y0)) / 2 - scale * y0])
    image = Image.new("RGB", (width * k, height * k), (255, 255, 255))
    if background is not None:
        mask = Image.fromarray(np.where(np.asarray(background, dtype=bool), 205, 255).astype(np.uint8), mode="L")
        size = (max(1, int(round(mask.width * scale))), max(1, int(round(mask.height * scale))))
        image.paste(mask.resize(size, Image.NEAREST).convert("RGB"), (int(round(offset[0])), int(round(offset[1]))))
    draw = ImageDraw.Draw(image)
    for curve in curves:
        xy = bezier_polyline(curve) * scale + offset
        draw.line([tuple(p) for p in xy], fill=tuple(stroke), width=max(1, int(round(stroke_width * k))), joint="curve")
    buffer = io.BytesIO()
    image.resize((width, height), Image.LANCZOS).save(buffer, format="PNG")
    return buffer.getvalue()
