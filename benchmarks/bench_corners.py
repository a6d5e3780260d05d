"""Corner detectors: accuracy and speed on rasterized shapes (capture/corners.py).

    .venv/bin/python benchmarks/bench_corners.py                      # synthetic set + yardstick
    .venv/bin/python benchmarks/bench_corners.py --yardstick DIR --per-family 40 --seed 1 --json out.json
    .venv/bin/python benchmarks/bench_corners.py --speed [REVISION]    # tangent-jump: old code vs now

Every shape is rasterized (pixel (r, c) is ink when its centre (c + 0.5, r + 0.5) is inside, even-odd over
its contours), traced to crack outlines by the project's ``trace_boundaries`` and given to each detector.
Detected corners (the outline points at the returned indices) are matched one-to-one to the true corners
within 3 px (``scipy.optimize.linear_sum_assignment``); TP/FP/FN are pooled over the shapes of a set.
Time is the detector alone (all outlines of a shape), per shape.

* **Synthetic set** (generated here; ``--seed``): families ``polygon`` (regular 3..10-gons including the
  120-144 deg interior angles, and random polygons with every turn >= 33 deg), ``star``, ``glyph``
  (slab-serif block letters I T L H Z V, 60-320 px high), ``mixed`` (lines and arcs: D shapes, pie slices,
  lenses, crescents, teardrops, U shapes), ``smooth`` (circles r 5..200, ellipses whose ends have a radius
  of curvature >= 5 px, smooth blobs, rounded rectangles -- no corners at all) and ``font`` (glyphs of
  DejaVu Serif / Sans Bold / Sans Mono / Serif Bold / Serif Condensed Italic through the team's
  ``benchmarks/synthetic_shapes.py`` reader; skipped when that file or the fonts are missing; the
  yardstick's DejaVu Sans is not used). True corners: joins of the exact outline turning by more than 30
  deg (the yardstick's definition). ``tangent-jump``'s defaults were tuned on seed 0; the report uses
  seed 1 (held out) unless told otherwise.
* **Yardstick** (``--yardstick``, default ``../shared/yardstick`` next to the repository): ``shapes/*.png``
  read with the project's ``load_bitmap``; true corners from ``NAME.json``. Only checked, never tuned on.
* **SRM05 readings**: the thesis's phase 1 is vague; the alternatives of :func:`corners._thesis._srm05_phase1` /
  ``_srm05_phase2`` side by side.
* **Resolution of tangent-jump**: circles of radius 5..200 and ellipses by the radius of curvature of
  their ends; recall by turn angle.
"""
from __future__ import annotations

import argparse
import glob
import importlib
import io
import importlib.util
import json
import os
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import linear_sum_assignment

REPO = Path(__file__).resolve().parents[1]
MATCH_PX = 3.0
CORNER_DEG = 30.0
STEP = 0.05


def _capture_module(name):
    """``splinecraft.capture.<name>``, loaded from its file while sibling modules imported by the package
    ``__init__`` are still being written."""
    try:
        return importlib.import_module(f"splinecraft.capture.{name}")
    except ImportError:
        alias = f"_bench_capture_{name}"
        if alias in sys.modules:
            return sys.modules[alias]
        path = REPO / "src" / "splinecraft" / "capture" / f"{name}.py"
        spec = importlib.util.spec_from_file_location(alias, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[alias] = module
        spec.loader.exec_module(module)
        return module


cm = _capture_module("corners")
contour = _capture_module("contour")
image = _capture_module("image")


# ================================================================================== synthetic shapes
def _line(p0, p1):
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    n = max(1, int(np.ceil(np.hypot(*(p1 - p0)) / STEP)))
    return p0 + (np.arange(n) / n)[:, None] * (p1 - p0)


def _arc(center, radius, a0, a1):
    n = max(2, int(np.ceil(abs(a1 - a0) * radius / STEP)))
    a = a0 + (a1 - a0) * np.arange(n) / n
    return np.column_stack([center[0] + radius * np.cos(a), center[1] + radius * np.sin(a)])


def _closed(fn, length):
    n = int(np.ceil(length / STEP))
    return fn(2 * np.pi * np.arange(n) / n)


def _pieces(pieces):
    """Pieces (end point excluded) -> closed dense polyline and corners (x, y, turn) at joins turning > 30."""
    pts = np.concatenate(pieces)
    found = []
    for k, cur in enumerate(pieces):
        a = cur[0] - pieces[k - 1][-1]
        b = (cur[1] if len(cur) > 1 else pieces[(k + 1) % len(pieces)][0]) - cur[0]
        turn = np.degrees(np.arccos(np.clip(np.dot(a, b) / (np.hypot(*a) * np.hypot(*b)), -1, 1)))
        if turn > CORNER_DEG:
            found.append((cur[0][0], cur[0][1], turn))
    return pts, found


def _polygon(vertices):
    v = np.asarray(vertices, float)
    return _pieces([_line(v[i], v[(i + 1) % len(v)]) for i in range(len(v))])


def _transform(contours, corners, angle, scale=1.0):
    c, s = np.cos(angle), np.sin(angle)
    R = np.array([[c, -s], [s, c]]) * scale
    return [p @ R.T for p in contours], [tuple(np.asarray(q[:2]) @ R.T) + tuple(q[2:]) for q in corners]


def _regular_polygon(rng, n):
    r = rng.uniform(12, 150) if n > 4 else rng.uniform(10, 150)
    a = 2 * np.pi * np.arange(n) / n
    pts, corners = _polygon(np.column_stack([np.cos(a), np.sin(a)]) * r)
    return _transform([pts], corners, rng.uniform(0, 2 * np.pi))


def _random_polygon(rng, min_turn=33.0, min_edge=7.0):
    while True:
        k = rng.integers(4, 12)
        ang = np.sort(rng.uniform(0, 2 * np.pi, k))
        radii = rng.uniform(0.35, 1.0, k) * rng.uniform(25, 170)
        v = np.column_stack([np.cos(ang), np.sin(ang)]) * radii[:, None]
        e = np.roll(v, -1, 0) - v
        if np.hypot(*e.T).min() < min_edge:
            continue
        a, b = np.roll(e, 1, 0), e
        turn = np.degrees(np.arccos(np.clip((a * b).sum(1) / (np.hypot(*a.T) * np.hypot(*b.T)), -1, 1)))
        if turn.min() >= min_turn and turn.max() <= 165:
            pts, corners = _polygon(v)
            return [pts], corners


def _star(rng):
    n = rng.integers(4, 9)
    ro = rng.uniform(30, 180)
    a = np.pi * np.arange(2 * n) / n
    r = np.where(np.arange(2 * n) % 2 == 0, ro, ro * rng.uniform(0.35, 0.7))
    pts, corners = _polygon(np.column_stack([np.cos(a), np.sin(a)]) * r[:, None])
    return _transform([pts], corners, rng.uniform(0, 2 * np.pi))


def _serif_letter(rng):
    """Slab-serif block letters, height 1 (y down), as polygons; drawn 60..320 px high."""
    letter = "ITLHZV"[rng.integers(6)]
    w, sw, st = rng.uniform(0.09, 0.16), rng.uniform(0.18, 0.3), rng.uniform(0.05, 0.09)
    if letter == "I":
        v = [(-sw, 0), (sw, 0), (sw, st), (w, st), (w, 1 - st), (sw, 1 - st), (sw, 1), (-sw, 1),
             (-sw, 1 - st), (-w, 1 - st), (-w, st), (-sw, st)]
    elif letter == "T":
        h = 0.45
        v = [(-h, 0), (h, 0), (h, 0.22), (h - st, 0.22), (h - st, st + 0.04), (w, st + 0.04), (w, 1 - st),
             (sw, 1 - st), (sw, 1), (-sw, 1), (-sw, 1 - st), (-w, 1 - st), (-w, st + 0.04),
             (-h + st, st + 0.04), (-h + st, 0.22), (-h, 0.22)]
    elif letter == "L":
        v = [(-sw, 0), (sw, 0), (sw, st), (w, st), (w, 1 - 2 * st), (0.5, 1 - 2 * st), (0.5, 0.75),
             (0.5 + st, 0.75), (0.5 + st, 1), (-sw, 1), (-sw, 1 - st), (-w, 1 - st), (-w, st), (-sw, st)]
    elif letter == "H":
        g = 0.38
        v = [(-g - sw, 0), (-g + sw, 0), (-g + sw, st), (-g + w, st), (-g + w, 0.45), (g - w, 0.45),
             (g - w, st), (g - sw, st), (g - sw, 0), (g + sw, 0), (g + sw, st), (g + w, st),
             (g + w, 1 - st), (g + sw, 1 - st), (g + sw, 1), (g - sw, 1), (g - sw, 1 - st),
             (g - w, 1 - st), (g - w, 0.57), (-g + w, 0.57), (-g + w, 1 - st), (-g + sw, 1 - st),
             (-g + sw, 1), (-g - sw, 1), (-g - sw, 1 - st), (-g - w, 1 - st), (-g - w, st), (-g - sw, st)]
    elif letter == "Z":
        v = [(-0.4, 0), (0.42, 0), (0.42, 0.1), (-0.22, 0.88), (0.3, 0.88), (0.3, 0.75), (0.42, 0.75),
             (0.42, 1), (-0.42, 1), (-0.42, 0.9), (0.22, 0.12), (-0.28, 0.12), (-0.28, 0.22), (-0.4, 0.22)]
    else:
        v = [(-0.5, 0), (-0.18, 0), (-0.18, st), (-0.28, st), (0.02, 0.78), (0.3, st), (0.2, st), (0.2, 0),
             (0.5, 0), (0.5, st), (0.4, st), (0.05, 1), (-0.03, 1), (-0.4, st), (-0.5, st)]
    pts, corners = _polygon(v)
    angle = rng.uniform(-0.6, 0.6) if rng.uniform() < 0.6 else rng.uniform(0, 2 * np.pi)
    return _transform([pts], corners, angle, rng.uniform(60, 320))


def _d_shape(rng):
    h = rng.uniform(30, 300)
    t = h * rng.uniform(0.12, 0.25)

    def outline(x0, y0, hh, w):
        n = int(np.ceil(np.pi * max(hh / 2, w) / STEP))
        a = -np.pi / 2 + np.pi * np.arange(n) / n
        bowl = np.column_stack([x0 + w * np.cos(a), y0 + hh / 2 + hh / 2 * np.sin(a)])
        return [_line((x0, y0 + hh), (x0, y0)), bowl]

    o, c1 = _pieces(outline(0, 0, h, h * 0.7))
    i, c2 = _pieces(outline(t, t, h - 2 * t, h * 0.7 - 1.3 * t))
    return _transform([o, i[::-1]], c1 + c2, rng.uniform(0, 2 * np.pi))


def _pie(rng):
    r, span = rng.uniform(15, 180), rng.uniform(0.6, 1.8) * np.pi
    pts, corners = _pieces([_line((0, 0), (r, 0)), _arc((0, 0), r, 0, span),
                            _line((r * np.cos(span), r * np.sin(span)), (0, 0))])
    return _transform([pts], corners, rng.uniform(0, 2 * np.pi))


def _lens(rng):
    chord = rng.uniform(30, 300)
    bulge = chord * rng.uniform(0.12, 0.45)
    radius = ((chord / 2) ** 2 + bulge ** 2) / (2 * bulge)
    off, ang = radius - bulge, np.arcsin(chord / 2 / radius)
    pts, corners = _pieces([_arc((0, off), radius, -np.pi / 2 - ang, -np.pi / 2 + ang),
                            _arc((0, -off), radius, np.pi / 2 - ang, np.pi / 2 + ang)])
    return _transform([pts], corners, rng.uniform(0, 2 * np.pi))


def _crescent(rng):
    R = rng.uniform(20, 180)
    r, d = R * rng.uniform(0.75, 0.95), R * rng.uniform(0.25, 0.5)
    x = (R ** 2 - r ** 2 + d ** 2) / (2 * d)
    y = np.sqrt(max(R ** 2 - x ** 2, 1e-9))
    a_out, a_in = np.arctan2(y, x), np.arctan2(y, x - d)
    pts, corners = _pieces([_arc((0, 0), R, a_out, 2 * np.pi - a_out), _arc((d, 0), r, 2 * np.pi - a_in, a_in)])
    return _transform([pts], corners, rng.uniform(0, 2 * np.pi))


def _teardrop(rng):
    r = rng.uniform(10, 120)
    L = r * rng.uniform(1.8, 3.5)
    beta = np.arccos(r / L)
    p1, p2 = (r * np.cos(beta), r * np.sin(beta)), (r * np.cos(beta), -r * np.sin(beta))
    pts, corners = _pieces([_line((L, 0), p1), _arc((0, 0), r, beta, 2 * np.pi - beta), _line(p2, (L, 0))])
    return _transform([pts], corners, rng.uniform(0, 2 * np.pi))


def _u_shape(rng):
    """Two stems and a round bottom: corners only at the stem ends (the stem/arc joins are smooth)."""
    h = rng.uniform(40, 300)
    R = h * rng.uniform(0.3, 0.45)
    r = R - R * rng.uniform(0.25, 0.5)
    n_in, n_out = max(2, int(np.ceil(np.pi * r / STEP))), max(2, int(np.ceil(np.pi * R / STEP)))
    a_in = np.pi - np.pi * np.arange(n_in) / n_in
    a_out = np.pi * np.arange(n_out) / n_out
    pieces = [_line((-R, 0), (-r, 0)), _line((-r, 0), (-r, h - R)),
              np.column_stack([r * np.cos(a_in), h - R + r * np.sin(a_in)]),
              _line((r, h - R), (r, 0)), _line((r, 0), (R, 0)), _line((R, 0), (R, h - R)),
              np.column_stack([R * np.cos(a_out), h - R + R * np.sin(a_out)]), _line((-R, h - R), (-R, 0))]
    pts, corners = _pieces(pieces)
    return _transform([pts], corners, rng.uniform(0, 2 * np.pi))


def _circle(rng):
    r = float(np.exp(rng.uniform(np.log(5), np.log(200))))
    return [_closed(lambda t: np.column_stack([r * np.cos(t), r * np.sin(t)]), 2 * np.pi * r)], []


def _ellipse(rng):
    a = float(np.exp(rng.uniform(np.log(8), np.log(200))))
    b = max(a * rng.uniform(0.3, 1.0), np.sqrt(5 * a))          # radius of curvature b^2/a >= 5 px
    pts = _closed(lambda t: np.column_stack([a * np.cos(t), b * np.sin(t)]), 2 * np.pi * a)
    return _transform([pts], [], rng.uniform(0, np.pi))


def _blob(rng):
    R = float(np.exp(rng.uniform(np.log(6), np.log(200))))
    K = rng.integers(2, 6)
    count = int(np.ceil(2 * np.pi * R * 1.6 / STEP))
    t = 2 * np.pi * np.arange(count) / count
    for _ in range(100):
        amp = rng.normal(size=K) * rng.uniform(0.05, 0.25) / np.arange(2, K + 2)
        ph = rng.uniform(0, 2 * np.pi, K)
        r = R * (1 + sum(amp[k] * np.cos((k + 2) * t + ph[k]) for k in range(K)))
        pts = np.column_stack([r * np.cos(t), r * np.sin(t)])
        d1 = (np.roll(pts, -1, 0) - np.roll(pts, 1, 0)) / 2
        d2 = np.roll(pts, -1, 0) - 2 * pts + np.roll(pts, 1, 0)
        kappa = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(*d1.T) ** 3
        if 1 / kappa.max() >= max(5.0, R / 4):                   # smooth at the scale of the shape
            return [pts], []
    return [_closed(lambda s: np.column_stack([R * np.cos(s), R * np.sin(s)]), 2 * np.pi * R)], []


def _rounded_rect(rng):
    w, h = rng.uniform(30, 300), rng.uniform(30, 300)
    r = rng.uniform(10, max(11, min(w, h) / 2 - 1))
    pts, corners = _pieces([_line((r, 0), (w - r, 0)), _arc((w - r, r), r, -np.pi / 2, 0),
                            _line((w, r), (w, h - r)), _arc((w - r, h - r), r, 0, np.pi / 2),
                            _line((w - r, h), (r, h)), _arc((r, h - r), r, np.pi / 2, np.pi),
                            _line((0, h - r), (0, r)), _arc((r, r), r, np.pi, 1.5 * np.pi)])
    return _transform([pts], corners, rng.uniform(0, 2 * np.pi))


def _filleted_polygon(rng, radius=None, min_turn=35.0, max_turn=160.0):
    """A random polygon (turns of ``min_turn``..``max_turn`` deg, convex and concave) at a random rotation
    whose corners are, each with probability 1/2, rounded by a circular fillet of radius 1-8 px (``radius``
    fixes it): the sharp ones are its true corners, the filleted ones are not (tangent-continuous joins).
    Returns ``(contours, corners)``; every corner entry is ``(x, y, turn, fillet_radius)`` with radius 0 for
    sharp ones, so that the benchmark can report by radius (``fillet_corners``)."""
    while True:
        k = int(rng.integers(4, 10))
        ang = np.sort(rng.uniform(0, 2 * np.pi, k))
        v = np.column_stack([np.cos(ang), np.sin(ang)]) * (rng.uniform(0.35, 1.0, k) * rng.uniform(40, 170))[:, None]
        e = np.roll(v, -1, 0) - v
        a, b = np.roll(e, 1, 0), e
        cosine = (a * b).sum(1) / (np.hypot(*a.T) * np.hypot(*b.T))
        turn = np.degrees(np.arccos(np.clip(cosine, -1, 1)))
        if turn.min() < min_turn or turn.max() > max_turn:
            continue
        radii = np.where(rng.uniform(size=k) < 0.5, 0.0,
                         radius if radius is not None else rng.uniform(1.0, 8.0, k))
        tangent = radii * np.tan(np.radians(turn) / 2)
        edge = np.hypot(*e.T)
        if np.any(tangent + np.roll(tangent, -1) + 8.0 > edge):
            continue
        break
    pieces, corners = [], []
    for i in range(k):
        u1, u2 = a[i] / np.hypot(*a[i]), b[i] / np.hypot(*b[i])
        left = np.sign(u1[0] * u2[1] - u1[1] * u2[0])
        if radii[i] > 0:
            t0 = v[i] - tangent[i] * u1
            centre = t0 + left * radii[i] * np.array([-u1[1], u1[0]])
            start = np.arctan2(*(t0 - centre)[::-1])
            pieces.append(_arc(centre, radii[i], start, start + left * np.radians(turn[i])))
            begin = v[i] + tangent[i] * u2
        else:
            begin = v[i]
        end = v[(i + 1) % k] - tangent[(i + 1) % k] * u2
        pieces.append(_line(begin, end))
        corners.append((v[i][0], v[i][1], turn[i], radii[i]))
    pts = np.concatenate(pieces)
    contours, placed = _transform([pts], corners, rng.uniform(0, 2 * np.pi))
    return contours, [c[:3] for c in placed if c[3] == 0], {"fillets": [c for c in placed if c[3] > 0]}


FONT_FILES = ("DejaVuSerif.ttf", "DejaVuSans-Bold.ttf", "DejaVuSansMono.ttf", "DejaVuSerif-Bold.ttf",
              "DejaVuSerifCondensed-Italic.ttf")
FONT_CHARS = "ABEFHKMNRTVWXYZbdfhkmnpqrtwxyz1247#&%$@"


def _team_glyph_reader():
    try:
        sys.path.insert(0, str(REPO / "benchmarks"))
        import synthetic_shapes as team
        font_dir = getattr(team, "FONT_DIR", "/usr/share/fonts/truetype/dejavu")
        if all(os.path.exists(os.path.join(font_dir, f)) for f in FONT_FILES):
            return team
    except ImportError:
        pass
    return None


def _font_glyph(rng, team):
    while True:
        font = FONT_FILES[rng.integers(len(FONT_FILES))]
        ch = FONT_CHARS[rng.integers(len(FONT_CHARS))]
        size = float(np.exp(rng.uniform(np.log(60), np.log(300))))
        try:
            g = team.glyph(font, ch, size)
        except (ValueError, KeyError):
            continue
        if g["contours"]:
            angle = 0.0 if rng.uniform() < 0.5 else rng.uniform(-0.5, 0.5)
            return _transform(g["contours"], g["corners"], angle)


FAMILIES = {
    "polygon": lambda rng: (_regular_polygon(rng, int(rng.integers(3, 11))) if rng.uniform() < 0.5
                            else _random_polygon(rng)),
    "star": _star,
    "glyph": _serif_letter,
    "mixed": lambda rng: [_d_shape, _pie, _lens, _crescent, _teardrop, _u_shape][rng.integers(0, 6)](rng),
    "smooth": lambda rng: [_circle, _ellipse, _blob, _rounded_rect][rng.integers(0, 4)](rng),
}


def _shape(name, family, contours, corners, rng, margin=5, fillets=()):
    shift = -np.concatenate(contours).min(0) + margin + rng.uniform(0, 1, 2)
    contours = [p + shift for p in contours]
    corners = [tuple(np.asarray(q[:2]) + shift) + tuple(q[2:]) for q in corners]
    fillets = [tuple(np.asarray(q[:2]) + shift) + tuple(q[2:]) for q in fillets]
    hi = np.ceil(np.concatenate(contours).max(0)) + margin
    return {"name": name, "family": family, "width": int(hi[0]), "height": int(hi[1]),
            "contours": contours, "corners": corners, "fillets": fillets}


def rasterize(shape):
    """Even-odd scanline fill over all contours: pixel (r, c) is ink when (c + 0.5, r + 0.5) is inside."""
    H, W = shape["height"], shape["width"]
    xs, rows = [], []
    for c in shape["contours"]:
        p, q = c, np.roll(c, -1, axis=0)
        y0, y1 = p[:, 1], q[:, 1]
        r0 = np.ceil(np.minimum(y0, y1) - 0.5).astype(int)
        r1 = np.ceil(np.maximum(y0, y1) - 0.5).astype(int)
        count = np.maximum(r1 - r0, 0)
        edge = np.repeat(np.arange(len(p)), count)
        row = np.repeat(r0, count) + (np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count))
        t = (row + 0.5 - y0[edge]) / (y1[edge] - y0[edge])
        xs.append(p[edge, 0] + t * (q[edge, 0] - p[edge, 0]))
        rows.append(row)
    xs, rows = np.concatenate(xs), np.concatenate(rows)
    order = np.lexsort((xs, rows))
    xs, rows = xs[order], rows[order]
    acc = np.zeros((H, W + 1), np.int32)
    np.add.at(acc, (rows[0::2], np.clip(np.ceil(xs[0::2] - 0.5).astype(int), 0, W)), 1)
    np.add.at(acc, (rows[1::2], np.clip(np.ceil(xs[1::2] - 0.5).astype(int), 0, W)), -1)
    return np.cumsum(acc, axis=1)[:, :W] > 0


def synthetic_set(seed=1, per_family=40, fonts=True):
    """The synthetic families (:data:`FAMILIES`, DejaVu glyphs as ``font`` where the fonts are installed) and
    the ``fillet`` family (:func:`_filleted_polygon`, drawn from a stream of its own), traced to crack
    outlines."""
    rng = np.random.default_rng(seed)
    team = _team_glyph_reader() if fonts else None
    families = dict(FAMILIES)
    if team is not None:
        families["font"] = lambda r: _font_glyph(r, team)
    shapes = []
    for family, make in families.items():
        for k in range(per_family):
            contours, corners = make(rng)
            shapes.append(_shape(f"{family}{k}", family, contours, corners, rng))
    fillet_rng = np.random.default_rng(1000 + seed)     # its own stream: the other families stay as they were
    for k in range(per_family):
        contours, corners, extra = _filleted_polygon(fillet_rng)
        shapes.append(_shape(f"fillet{k}", "fillet", contours, corners, fillet_rng, **extra))
    for s in shapes:
        s["outlines"] = [b.outline for b in contour.trace_boundaries(rasterize(s))]
    return shapes, team is not None


# ================================================================================== yardstick
def yardstick_set(folder):
    shapes = []
    for png in sorted(glob.glob(os.path.join(folder, "shapes", "*.png"))):
        gt = json.load(open(png[:-4] + ".json"))
        if gt.get("corners") is None:
            continue
        mask = image.load_bitmap(png)
        shapes.append({"name": gt["name"], "family": "yardstick",
                       "corners": [(c["x"], c["y"], c.get("angle", np.nan)) for c in gt["corners"]],
                       "outlines": [b.outline for b in contour.trace_boundaries(mask)]})
    return shapes


# ================================================================================== scoring
def match(found, truth, tol=MATCH_PX):
    """One-to-one matching within ``tol`` px -> (tp, fp, fn, hit flags of the truth)."""
    found = np.asarray(found, float).reshape(-1, 2)
    truth = np.asarray([tuple(t)[:2] for t in truth], float).reshape(-1, 2)
    hit = np.zeros(len(truth), bool)
    if len(found) and len(truth):
        dist = np.hypot(*(found[:, None, :] - truth[None, :, :]).transpose(2, 0, 1))
        rows, cols = linear_sum_assignment(np.where(dist <= tol, dist, 1e6))
        hit[cols[dist[rows, cols] <= tol]] = True
    tp = int(hit.sum())
    return tp, len(found) - tp, len(truth) - tp, hit


def evaluate(detector, shapes, tol=MATCH_PX):
    """Pooled scores per family and overall, per-shape F1, seconds per shape, recall by turn."""
    fam, per_shape, turn_hits = {}, {}, []
    seconds = 0.0
    for s in shapes:
        t0 = time.perf_counter()
        found = [o[detector(o)] for o in s["outlines"]]
        seconds += time.perf_counter() - t0
        found = np.concatenate(found) if found else np.zeros((0, 2))
        tp, fp, fn, hit = match(found, s["corners"], tol)
        for key in (s["family"], "all"):
            acc = fam.setdefault(key, [0, 0, 0])
            acc[0] += tp
            acc[1] += fp
            acc[2] += fn
        per_shape[s["name"]] = _f1(tp, fp, fn)
        turn_hits += [(c[2], h) for c, h in zip(s["corners"], hit) if len(c) > 2]
    return {"families": {k: (*v, *_prf(*v)) for k, v in fam.items()}, "per_shape": per_shape,
            "ms_per_shape": 1e3 * seconds / max(len(shapes), 1), "turn_hits": turn_hits}


def _prf(tp, fp, fn):
    p = tp / (tp + fp) if tp + fp else 1.0
    r = tp / (tp + fn) if tp + fn else 1.0
    return p, r, (2 * p * r / (p + r) if p + r else 0.0)


def _f1(tp, fp, fn):
    return _prf(tp, fp, fn)[2]


# ================================================================================== reports
def _table(headers, rows):
    out = ["| " + " | ".join(headers) + " |", "|" + "|".join("---" for _ in headers) + "|"]
    out += ["| " + " | ".join(str(x) for x in r) + " |" for r in rows]
    return "\n".join(out)


def report_methods(title, shapes, methods, families):
    results = {m: evaluate(lambda o, m=m: cm.corners(o, m), shapes) for m in methods}
    rows = []
    for m in methods:
        r = results[m]
        tp, fp, fn, p, rc, f1 = r["families"]["all"]
        row = [m, tp, fp, fn, f"{p:.3f}", f"{rc:.3f}", f"**{f1:.3f}**"]
        row += [f"{r['families'][f][5]:.3f}" if f != "smooth" else str(r["families"][f][1])
                for f in families if f in r["families"]]
        row.append(f"{r['ms_per_shape']:.1f}")
        rows.append(row)
    headers = ["method", "TP", "FP", "FN", "P", "R", "F1"]
    present = [f for f in families if f in results[methods[0]]["families"]]
    headers += [f"F1 {f}" if f != "smooth" else "FP smooth" for f in present]
    headers.append("ms/shape")
    print(f"\n### {title}\n")
    print(_table(headers, rows))
    return results


def report_srm05_readings(title, shapes):
    rows = []
    for rule in ("zero-runs", "four-transitions", "all-runs"):
        for pick in ("middle", "first"):
            res = evaluate(lambda o: importlib.import_module("splinecraft.capture.corners._thesis")._srm05(o, True, 7, 5.0, 152.0, rule, pick), shapes)
            cells = [rule + (" (default)" if (rule, pick) == ("zero-runs", "middle") else ""), pick]
            for fam in ("polygon", "star", "glyph", "all"):
                if fam in res["families"]:
                    tp, fp, fn, p, r, f1 = res["families"][fam]
                    cells.append(f"{p:.2f}/{r:.2f}/{f1:.3f}")
            rows.append(cells)
    fams = [f for f in ("polygon", "star", "glyph", "all") if f in {s["family"] for s in shapes} | {"all"}]
    print(f"\n### {title}\n")
    print(_table(["phase 1 rule", "phase 2 pick"] + [f"P/R/F1 {f}" for f in fams], rows))


def _has_false_corner(shape):
    return any(len(cm.tangent_jump(b.outline)) for b in contour.trace_boundaries(rasterize(shape)))


def report_resolution(seed=7):
    rng = np.random.default_rng(seed)
    rows = []
    for lo, hi in ((5, 10), (10, 20), (20, 50), (50, 100), (100, 200)):
        n_any = 0
        count = 60
        for _ in range(count):
            r = float(np.exp(rng.uniform(np.log(lo), np.log(hi))))
            disc = _closed(lambda t: np.column_stack([r * np.cos(t), r * np.sin(t)]), 2 * np.pi * r)
            n_any += _has_false_corner(_shape("c", "smooth", [disc], [], rng))
        rows.append([f"circle r {lo}-{hi}", f"{n_any}/{count}"])
    for rho in (6, 8, 10, 15, 25):
        n_any, count = 0, 60
        for _ in range(count):
            a = float(np.exp(rng.uniform(np.log(max(rho, 10)), np.log(200))))
            b = min(a, np.sqrt(rho * a))
            pts = _closed(lambda t: np.column_stack([a * np.cos(t), b * np.sin(t)]), 2 * np.pi * a)
            contours, _ = _transform([pts], [], rng.uniform(0, np.pi))
            n_any += _has_false_corner(_shape("e", "smooth", contours, [], rng))
        rows.append([f"ellipse, end radius of curvature {rho} px", f"{n_any}/{count}"])
    print("\n### tangent-jump on smooth shapes: shapes with any corner (should be none)\n")
    print(_table(["shapes", "with a false corner"], rows))


def report_turn_recall(results, methods):
    bins = [(30, 40), (40, 50), (50, 70), (70, 110), (110, 180)]
    rows = []
    for m in methods:
        hits = results[m]["turn_hits"]
        cells = [m]
        for lo, hi in bins:
            sel = [h for t, h in hits if lo <= t < hi]
            cells.append(f"{sum(sel)}/{len(sel)}" if sel else "-")
        rows.append(cells)
    print("\n### recall by turn angle of the true corner (synthetic, all families with known turns)\n")
    print(_table(["method"] + [f"{lo}-{hi} deg" for lo, hi in bins], rows))


# ================================================================================== speed of tangent-jump
def report_fillets(shapes):
    """tangent-jump without and with its fillet test on the fillet family: the share of fillets reported as a
    corner (a detected corner within 3 px of the fillet's vertex or within its radius of it), by radius and
    turn, and the recall of the family's sharp corners."""
    family = [s for s in shapes if s["family"] == "fillet"]
    radii, turns = ((1, 2), (2, 4), (4, 6), (6, 8)), ((35, 80), (80, 120), (120, 160))
    rows, sharp = [], {}
    for fillets in (False, True):
        counts = {}
        hits = total = 0
        for s in family:
            found = np.concatenate([o[cm.tangent_jump(o, fillets=fillets)] for o in s["outlines"]])
            for x, y, turn, radius in s["fillets"]:
                d = np.hypot(*(found - [x, y]).T).min() if len(found) else np.inf
                key = (next(r for r in radii if r[0] <= radius <= r[1]), next(t for t in turns if t[0] <= turn <= t[1]))
                cell = counts.setdefault(key, [0, 0])
                cell[0] += d <= max(MATCH_PX, radius)
                cell[1] += 1
            tp, _, fn, _ = match(found, s["corners"])
            hits, total = hits + tp, total + tp + fn
        sharp[fillets] = (hits, total)
        for r in radii:
            rows.append([f"fillets={fillets}", f"r {r[0]}-{r[1]} px"] + [
                f"{counts[(r, t)][0]}/{counts[(r, t)][1]}" if (r, t) in counts else "-" for t in turns])
    print("\n### tangent-jump on fillets (fillet family): fillets reported as corners, by radius and turn\n")
    print(_table(["fillet test", "radius"] + [f"turn {lo}-{hi} deg" for lo, hi in turns], rows))
    print("\nsharp corners of the family found: " + ", ".join(
        f"fillets={k} {h}/{t}" for k, (h, t) in sharp.items()))


def report_heldout(families, corner_params=None):
    """Per held-out glyph (``heldout_shapes.py``: upright 300 px glyphs of the families in ``families``, and
    every glyph of the groups in it, e.g. ``small``, ``rotated``, ``large``, ``scan``): the true corners,
    the corners of ``sc.trace``'s SVG and their one-to-one match within 3 px (the project's own scorer,
    ``synthetic_shapes``): which true corners are missed and which traced ones are false."""
    sys.path.insert(0, str(REPO / "benchmarks"))
    import heldout_shapes
    import synthetic_shapes
    import splinecraft as sc

    pooled = {}
    for shape in heldout_shapes.heldout_set():
        upright = shape["family"] in families and shape["group"] == shape["family"]
        if not upright and shape["group"] not in families:
            continue
        mask = shape["mask"] if "mask" in shape else heldout_shapes.rasterize(shape)
        result = sc.trace(mask, corner_params=corner_params)
        found = [c for b in synthetic_shapes.svg_beziers(result.to_svg()) for c in synthetic_shapes.bezier_corners(b)]
        tp, fp, fn, hit = match(found, shape["corners"])
        print(f"\n{shape['name']}: {len(shape['corners'])} true corners, {len(found)} traced, {tp} matched")
        for (x, y), ok in zip(shape["corners"], hit):
            print(f"    true   ({x:7.1f}, {y:7.1f}) {'matched' if ok else 'MISSED'}")
        truth = np.asarray(shape["corners"], float).reshape(-1, 2)
        for x, y in found:
            near = np.hypot(*(truth - [x, y]).T).min() if len(truth) else np.inf
            if near > MATCH_PX:
                print(f"    traced ({x:7.1f}, {y:7.1f}) FALSE")
        cell = pooled.setdefault(shape["family"] if upright else shape["group"], [0, 0, 0])
        cell[0], cell[1], cell[2] = cell[0] + tp, cell[1] + fp, cell[2] + fn
    print()
    for family, (tp, fp, fn) in pooled.items():
        print(f"{family}: TP {tp} FP {fp} FN {fn} pooled F1 {_f1(tp, fp, fn):.3f}")


SPEED_BASELINE = "f9c1a15"      # last revision before the arm fits were vectorized over windows


def _corners_at_revision(revision):
    """``splinecraft.capture.corners`` as of a git ``revision`` (a module file or, since the layout of issue 8,
    a package), imported from an exported copy of that revision's ``src`` beside the working tree's modules:
    the working tree's ``splinecraft`` modules are set aside while the old one is imported and put back after,
    so both stay usable in one process (each keeps its own module globals)."""
    import subprocess
    import tarfile
    import tempfile
    folder = tempfile.mkdtemp(prefix=f"corners-{revision}-")
    archive = subprocess.run(["git", "-C", str(REPO), "archive", revision, "src/splinecraft"],
                             check=True, capture_output=True).stdout
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(folder)
    ours = {name: module for name, module in sys.modules.items() if name.split(".")[0] == "splinecraft"}
    for name in ours:
        del sys.modules[name]
    sys.path.insert(0, os.path.join(folder, "src"))
    try:
        return importlib.import_module("splinecraft.capture.corners")
    finally:
        sys.path.remove(os.path.join(folder, "src"))
        for name in [name for name in sys.modules if name.split(".")[0] == "splinecraft"]:
            del sys.modules[name]
        sys.modules.update(ours)


def report_speed(revision=SPEED_BASELINE, repeats=31):
    """``tangent_jump`` of ``revision`` and of the working tree, interleaved call by call on the outer
    outlines of the thesis objects and of font glyphs; median ms per outline, ratio, identical indices."""
    from splinecraft import datasets
    old = _corners_at_revision(revision)
    cases = []
    for name in ("D", "apple", "plane", "ali"):
        for size in (300, 450):
            outline = max((b.outline for b in contour.trace_boundaries(datasets.thesis_object(name, size))),
                          key=len)
            cases.append((f"{name} {size} px", outline))
    team = _team_glyph_reader()
    if team is not None:
        for font, ch in (("DejaVuSerif.ttf", "R"), ("DejaVuSans-Bold.ttf", "&")):
            g = team.glyph(font, ch, 300.0)
            shape = _shape(ch, "font", g["contours"], g["corners"], np.random.default_rng(0))
            outline = max((b.outline for b in contour.trace_boundaries(rasterize(shape))), key=len)
            cases.append((f"{font[:-4]} '{ch}' 300 px", outline))
    rows = []
    for label, outline in cases:
        same = np.array_equal(old.tangent_jump(outline), cm.tangent_jump(outline))
        wall, cpu = {"old": [], "new": []}, {"old": [], "new": []}
        for _ in range(repeats):
            for key, fn in (("old", old.tangent_jump), ("new", cm.tangent_jump)):
                w0, c0 = time.perf_counter(), time.thread_time()
                fn(outline)
                cpu[key].append(time.thread_time() - c0)
                wall[key].append(time.perf_counter() - w0)
        row = [label, len(outline)]
        for times in (wall, cpu):
            before, after = (1e3 * np.median(times[k]) for k in ("old", "new"))
            row += [f"{before:.1f}", f"{after:.1f}", f"{before / after:.1f}x"]
        rows.append(row + ["yes" if same else "**no**"])
    print(f"\n### tangent-jump speed: {revision} vs working tree (median of {repeats} interleaved calls; "
          "wall clock and thread CPU time)\n")
    print(_table(["outline", "points", f"wall ms {revision}", "wall ms now", "ratio",
                  f"CPU ms {revision}", "CPU ms now", "ratio", "same indices"], rows))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--yardstick", default=str(REPO.parent / "shared" / "yardstick"))
    parser.add_argument("--seed", type=int, default=1, help="synthetic set seed (0 = tangent-jump's tuning set)")
    parser.add_argument("--per-family", type=int, default=40)
    parser.add_argument("--methods", default=",".join(cm.CORNER_METHODS))
    parser.add_argument("--skip-synthetic", action="store_true")
    parser.add_argument("--json", help="write the numbers to this file")
    parser.add_argument("--speed", nargs="?", const=SPEED_BASELINE, metavar="REVISION",
                        help="only time tangent-jump against its code at a git revision "
                             f"(default {SPEED_BASELINE}) and exit")
    parser.add_argument("--heldout", metavar="FAMILIES",
                        help="only list, per upright held-out glyph of these families (comma-separated, e.g. "
                             "oldstyle,arabic) and per glyph of these groups (small, rotated, large, scan), the "
                             "true corners, sc.trace's and their match, and exit")
    parser.add_argument("--fillets", action="store_true", help="with --heldout: trace with tangent-jump's "
                        "fillet test on (corner_params={'fillets': True})")
    args = parser.parse_args(argv)
    if args.heldout:
        report_heldout(args.heldout.split(","), {"fillets": True} if args.fillets else None)
        return
    if args.speed:
        report_speed(args.speed)
        return
    methods = [m for m in args.methods.split(",") if m]
    dump = {}
    print(f"numpy {np.__version__}; python {sys.version.split()[0]}; {os.cpu_count()} cpu")

    if not args.skip_synthetic:
        shapes, fonts = synthetic_set(args.seed, args.per_family)
        fams = ["polygon", "star", "glyph", "mixed", "smooth", "fillet"] + (["font"] if fonts else [])
        print(f"\nsynthetic set: seed {args.seed}, {len(shapes)} shapes "
              f"({args.per_family} per family: {', '.join(fams)}), "
              f"{sum(len(s['corners']) for s in shapes)} true corners"
              + ("" if fonts else "; font family skipped (benchmarks/synthetic_shapes.py or fonts missing)"))
        res = report_methods(f"Synthetic set, seed {args.seed} (3 px matching)", shapes, methods, fams)
        dump["synthetic"] = {m: {k: v for k, v in r.items() if k != "turn_hits"} for m, r in res.items()}
        report_turn_recall(res, methods)
        if "tangent-jump" in methods:
            fillet_res = evaluate(lambda o: cm.tangent_jump(o, fillets=True), shapes)
            tp, fp, fn, p, rc, f1 = fillet_res["families"]["all"]
            print(f"\ntangent-jump with fillets=True: TP {tp} FP {fp} FN {fn} P {p:.3f} R {rc:.3f} F1 {f1:.3f}; "
                  + ", ".join(f"F1 {f} {fillet_res['families'][f][5]:.3f}" for f in fams if f != "smooth"
                              and f in fillet_res["families"])
                  + f"; FP smooth {fillet_res['families'].get('smooth', (0, 0))[1]}; "
                  f"{fillet_res['ms_per_shape']:.1f} ms/shape")
            report_fillets(shapes)
        report_srm05_readings(f"SRM05 readings on the synthetic set, seed {args.seed}", shapes)
        report_resolution()

    if os.path.isdir(os.path.join(args.yardstick, "shapes")):
        shapes = yardstick_set(args.yardstick)
        print(f"\nyardstick: {args.yardstick}, {len(shapes)} shapes with corner annotations, "
              f"{sum(len(s['corners']) for s in shapes)} true corners")
        res = report_methods("Yardstick (checked, not tuned on; 3 px matching)", shapes, methods, [])
        free = [s["name"] for s in shapes if not s["corners"]]
        rows = []
        for m in methods:
            per = res[m]["per_shape"]
            worst = sorted(per.items(), key=lambda kv: kv[1])[:3]
            rows.append([m, f"{np.median(list(per.values())):.3f}",
                         sum(1 for v in per.values() if v == 1.0),
                         sum(0 if per[n] == 1.0 else 1 for n in free),
                         ", ".join(f"{n} {v:.2f}" for n, v in worst)])
        print("\n" + _table(["method", "median F1 per shape", "shapes with F1 = 1",
                             f"corner-free shapes ({len(free)}) with a false corner", "worst shapes"], rows))
        if "tangent-jump" in methods:
            fillet_res = evaluate(lambda o: cm.tangent_jump(o, fillets=True), shapes)
            tp, fp, fn, p, rc, f1 = fillet_res["families"]["all"]
            print(f"\ntangent-jump with fillets=True on the yardstick: TP {tp} FP {fp} FN {fn} P {p:.3f} R {rc:.3f} "
                  f"F1 {f1:.3f}; {fillet_res['ms_per_shape']:.1f} ms/shape")
        report_srm05_readings("SRM05 readings on the yardstick", shapes)
        dump["yardstick"] = {m: {k: v for k, v in r.items() if k != "turn_hits"} for m, r in res.items()}
    else:
        print(f"\nyardstick not found at {args.yardstick}: skipped (pass --yardstick DIR)")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(dump, fh, indent=1, default=float)


if __name__ == "__main__":
    main()
