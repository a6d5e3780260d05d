"""Synthetic shapes with exact outlines, for tuning and checking the outline fit (benchmarks only).

Every shape is rendered by the project itself (no external data): polygons, stars, ellipses, smooth blobs,
lens/teardrop shapes (smooth arcs meeting at sharp tips), rounded rectangles (tangent-continuous joins that
are NOT corners), rings with holes, and glyphs of the system's DejaVu *Serif*, *Sans Bold* and *Sans Mono*
fonts (read by the small TrueType ``glyf`` reader below; skipped when the fonts are absent). The yardstick
uses DejaVu Sans regular, which is deliberately not in this set.

A shape is a dict::

    {"name": str, "width": int, "height": int,
     "contours": [dense (n, 2) closed polyline, first point not repeated, step <= 0.05 px],
     "corners": [(x, y), ...]}       # joins of the exact outline that turn by more than 30 degrees

in the pixel frame of the project (x right, y down, pixel (r, c) covers [c, c+1] x [r, r+1]). A pixel is ink
when its centre is inside the outline (even-odd rule over all contours).

:func:`score_splines` measures a fit the way the yardstick does (symmetric Hausdorff and pooled RMS of the
closest-point distances, cubic segment count, corner precision/recall/F1 for joins turning > 30 degrees matched
one-to-one within 3 px), with an independent implementation.
"""
from __future__ import annotations

import os
import struct

import numpy as np
from scipy.optimize import linear_sum_assignment
from scipy.spatial import cKDTree

CORNER_DEG = 30.0
MATCH_PX = 3.0
STEP = 0.05

# ------------------------------------------------------------------------------------------- primitives


def _line(p0, p1, step=STEP):
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    n = max(1, int(np.ceil(np.hypot(*(p1 - p0)) / step)))
    s = np.arange(n) / n
    return p0 + s[:, None] * (p1 - p0)


def _arc(center, radius, a0, a1, step=STEP):
    """Circular arc from angle a0 to a1 (radians, y-down frame), end excluded."""
    n = max(2, int(np.ceil(abs(a1 - a0) * radius / step)))
    a = a0 + (a1 - a0) * np.arange(n) / n
    return np.column_stack([center[0] + radius * np.cos(a), center[1] + radius * np.sin(a)])


def _quad(p0, p1, p2, step=STEP):
    p0, p1, p2 = (np.asarray(p, float) for p in (p0, p1, p2))
    length = np.hypot(*(p1 - p0)) + np.hypot(*(p2 - p1))
    n = max(2, int(np.ceil(length / step)))
    t = (np.arange(n) / n)[:, None]
    return (1 - t) ** 2 * p0 + 2 * t * (1 - t) * p1 + t**2 * p2


def _turns(points):
    """Turning angle (degrees) at every vertex of a closed dense polyline."""
    a = points - np.roll(points, 1, axis=0)
    b = np.roll(points, -1, axis=0) - points
    cos = (a * b).sum(1) / np.maximum(np.hypot(*a.T) * np.hypot(*b.T), 1e-300)
    return np.degrees(np.arccos(np.clip(cos, -1, 1)))


def _contour_from_pieces(pieces):
    """Concatenate pieces (each with its end point excluded) into a closed dense polyline; corners are the
    piece joins whose turn exceeds 30 degrees (measured on the exact pieces)."""
    pts = np.concatenate(pieces)
    starts = np.cumsum([0] + [len(p) for p in pieces[:-1]])
    corners = []
    for k, s in enumerate(starts):
        prev = pieces[k - 1]
        cur = pieces[k]
        # directions of the last chord before and the first chord after the join
        a = cur[0] - prev[-1]
        b = (cur[1] - cur[0]) if len(cur) > 1 else (pieces[(k + 1) % len(pieces)][0] - cur[0])
        cos = np.dot(a, b) / (np.hypot(*a) * np.hypot(*b))
        if np.degrees(np.arccos(np.clip(cos, -1, 1))) > CORNER_DEG:
            corners.append(tuple(cur[0]))
    return pts, corners


def _shape(name, contours, corners, margin=4, segments=None):
    allp = np.concatenate(contours)
    lo = np.floor(allp.min(0)) - margin
    contours = [c - lo for c in contours]
    corners = [tuple(np.asarray(c) - lo) for c in corners]
    hi = np.ceil(np.concatenate(contours).max(0)) + margin
    return {"name": name, "width": int(hi[0]), "height": int(hi[1]), "contours": contours, "corners": corners,
            "segments": segments}


def polygon_shape(name, vertices):
    v = np.asarray(vertices, float)
    pieces = [_line(v[i], v[(i + 1) % len(v)]) for i in range(len(v))]
    pts, corners = _contour_from_pieces(pieces)
    return _shape(name, [pts], corners, segments=len(v))


def regular_polygon(name, n, radius, rotation=0.0):
    a = rotation + 2 * np.pi * np.arange(n) / n
    return polygon_shape(name, np.column_stack([radius * np.cos(a), radius * np.sin(a)]))


def star(name, n, r_out, r_in, rotation=-np.pi / 2):
    a = rotation + np.pi * np.arange(2 * n) / n
    r = np.where(np.arange(2 * n) % 2 == 0, r_out, r_in)
    return polygon_shape(name, np.column_stack([r * np.cos(a), r * np.sin(a)]))


def ellipse(name, rx, ry, rotation=0.0):
    n = int(np.ceil(2 * np.pi * max(rx, ry) / STEP))
    a = 2 * np.pi * np.arange(n) / n
    x, y = rx * np.cos(a), ry * np.sin(a)
    c, s = np.cos(rotation), np.sin(rotation)
    return _shape(name, [np.column_stack([c * x - s * y, s * x + c * y])], [], segments=4)


def blob(name, radius, seed, harmonics=4, amplitude=0.18):
    rng = np.random.default_rng(seed)
    n = int(np.ceil(2 * np.pi * radius * 1.6 / STEP))
    a = 2 * np.pi * np.arange(n) / n
    r = np.ones(n)
    for k in range(2, harmonics + 2):
        r += amplitude / k * rng.normal() * np.cos(k * a + rng.uniform(0, 2 * np.pi))
    r *= radius
    return _shape(name, [np.column_stack([r * np.cos(a), r * np.sin(a)])], [])


def lens(name, chord, bulge):
    """Two circular arcs through (+-chord/2, 0): smooth sides, two sharp tips."""
    half = chord / 2
    radius = (half**2 + bulge**2) / (2 * bulge)
    off = radius - bulge
    ang = np.arcsin(half / radius)
    top = _arc((0, off), radius, -np.pi / 2 - ang, -np.pi / 2 + ang)  # left tip -> right tip over the top
    bot = _arc((0, -off), radius, np.pi / 2 - ang, np.pi / 2 + ang)   # right tip -> left tip
    pts, corners = _contour_from_pieces([top, bot])
    return _shape(name, [pts], corners, segments=2)


def rounded_rect(name, w, h, r):
    pieces = [
        _line((r, 0), (w - r, 0)), _arc((w - r, r), r, -np.pi / 2, 0),
        _line((w, r), (w, h - r)), _arc((w - r, h - r), r, 0, np.pi / 2),
        _line((w - r, h), (r, h)), _arc((r, h - r), r, np.pi / 2, np.pi),
        _line((0, h - r), (0, r)), _arc((r, r), r, np.pi, 1.5 * np.pi),
    ]
    pts, corners = _contour_from_pieces(pieces)
    return _shape(name, [pts], corners, segments=8)


def _circle_points(radius, centre=(0.0, 0.0)):
    n = int(np.ceil(2 * np.pi * radius / STEP))
    a = 2 * np.pi * np.arange(n) / n
    return np.column_stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a)])


def ring(name, r_out, r_in, offset=(0.0, 0.0)):
    """Annulus (a hole inside a disc); ``offset`` moves the hole's centre."""
    return _shape(name, [_circle_points(r_out), _circle_points(r_in, offset)[::-1]], [], segments=8)


def d_shape(name, size):
    """A 'D': straight stem, half-ellipse bowl, with a hole of the same kind (corners at the stem ends)."""
    def outline(x0, y0, h, w):
        r = h / 2
        n = int(np.ceil(np.pi * max(r, w) / STEP))
        a = -np.pi / 2 + np.pi * np.arange(n) / n
        bowl = np.column_stack([x0 + w * np.cos(a), y0 + r + r * np.sin(a)])
        return [_line((x0, y0 + h), (x0, y0)), bowl]

    t = size * 0.16
    outer_pieces = outline(0, 0, size, size * 0.75)
    inner_pieces = outline(t, t, size - 2 * t, size * 0.75 - 1.3 * t)
    outer, c1 = _contour_from_pieces(outer_pieces)
    inner, c2 = _contour_from_pieces(inner_pieces)
    return _shape(name, [outer, inner[::-1]], c1 + c2, segments=6)  # per contour: stem, two quarter ellipses


# ------------------------------------------------------------------------------------ TrueType glyphs

class _TrueType:
    """Minimal reader of simple (non-composite) TrueType glyph outlines (tables cmap 4, loca, glyf, head)."""

    def __init__(self, path):
        self.data = open(path, "rb").read()
        count = struct.unpack(">H", self.data[4:6])[0]
        self.tables = {}
        for i in range(count):
            tag, _cs, off, length = struct.unpack(">4sIII", self.data[12 + 16 * i: 28 + 16 * i])
            self.tables[tag.decode("latin1")] = (off, length)
        head = self.tables["head"][0]
        self.units = struct.unpack(">H", self.data[head + 18: head + 20])[0]
        self.long_loca = struct.unpack(">h", self.data[head + 50: head + 52])[0] == 1
        self.cmap = self._read_cmap()

    def _read_cmap(self):
        d, off = self.data, self.tables["cmap"][0]
        n = struct.unpack(">H", d[off + 2: off + 4])[0]
        for i in range(n):
            pid, eid, sub = struct.unpack(">HHI", d[off + 4 + 8 * i: off + 12 + 8 * i])
            base = off + sub
            if struct.unpack(">H", d[base: base + 2])[0] == 4 and pid in (0, 3):
                segx2 = struct.unpack(">H", d[base + 6: base + 8])[0]
                seg = segx2 // 2
                ends = struct.unpack(f">{seg}H", d[base + 14: base + 14 + segx2])
                p = base + 16 + segx2
                starts = struct.unpack(f">{seg}H", d[p: p + segx2])
                deltas = struct.unpack(f">{seg}h", d[p + segx2: p + 2 * segx2])
                ro_pos = p + 2 * segx2
                ranges = struct.unpack(f">{seg}H", d[ro_pos: ro_pos + segx2])
                return (starts, ends, deltas, ranges, ro_pos)
        raise ValueError("no cmap format 4")

    def glyph_index(self, char):
        code = ord(char)
        starts, ends, deltas, ranges, ro_pos = self.cmap
        for k in range(len(ends)):
            if starts[k] <= code <= ends[k]:
                if ranges[k] == 0:
                    return (code + deltas[k]) & 0xFFFF
                addr = ro_pos + 2 * k + ranges[k] + 2 * (code - starts[k])
                g = struct.unpack(">H", self.data[addr: addr + 2])[0]
                return (g + deltas[k]) & 0xFFFF if g else 0
        return 0

    def contours(self, char):
        """List of closed contours, each a list of (x, y, on_curve) in font units."""
        d = self.data
        g = self.glyph_index(char)
        loca = self.tables["loca"][0]
        if self.long_loca:
            a, b = struct.unpack(">II", d[loca + 4 * g: loca + 4 * g + 8])
        else:
            a, b = (2 * v for v in struct.unpack(">HH", d[loca + 2 * g: loca + 2 * g + 4]))
        if a == b:
            return []
        p = self.tables["glyf"][0] + a
        nc = struct.unpack(">h", d[p: p + 2])[0]
        if nc < 0:
            raise ValueError(f"composite glyph {char!r} not supported")
        ends = struct.unpack(f">{nc}H", d[p + 10: p + 10 + 2 * nc])
        npts = ends[-1] + 1
        q = p + 10 + 2 * nc
        ilen = struct.unpack(">H", d[q: q + 2])[0]
        q += 2 + ilen
        flags = []
        while len(flags) < npts:
            f = d[q]
            q += 1
            flags.append(f)
            if f & 8:
                flags.extend([f] * d[q])
                q += 1
        coords = []
        for short, same in ((2, 16), (4, 32)):
            val, out = 0, []
            for f in flags:
                if f & short:
                    delta = d[q]
                    q += 1
                    val += delta if f & same else -delta
                elif not f & same:
                    val += struct.unpack(">h", d[q: q + 2])[0]
                    q += 2
                out.append(val)
            coords.append(out)
        res, start = [], 0
        for e in ends:
            res.append([(coords[0][i], coords[1][i], bool(flags[i] & 1)) for i in range(start, e + 1)])
            start = e + 1
        return res


def _glyph_contour(points, scale, dx, dy):
    """TrueType quadratic contour -> dense polyline (pixel frame), its > 30 degree corners and its number of
    segments (lines and quadratic arcs)."""
    pts = [(dx + scale * x, dy - scale * y, on) for x, y, on in points]
    # expand implied on-curve points
    full = []
    n = len(pts)
    for i in range(n):
        cur, nxt = pts[i], pts[(i + 1) % n]
        full.append(cur)
        if not cur[2] and not nxt[2]:
            full.append(((cur[0] + nxt[0]) / 2, (cur[1] + nxt[1]) / 2, True))
    k0 = next(i for i, p in enumerate(full) if p[2])
    full = full[k0:] + full[:k0]
    pieces, i, n = [], 0, len(full)
    while i < n:
        p0 = full[i]
        p1 = full[(i + 1) % n]
        if p1[2]:
            if np.hypot(p1[0] - p0[0], p1[1] - p0[1]) > 1e-9:
                pieces.append(_line(p0[:2], p1[:2]))
            i += 1
        else:
            p2 = full[(i + 2) % n]
            pieces.append(_quad(p0[:2], p1[:2], p2[:2]))
            i += 2
    return (*_contour_from_pieces(pieces), len(pieces))


FONT_DIR = "/usr/share/fonts/truetype/dejavu"
GLYPH_FONTS = ("DejaVuSerif.ttf", "DejaVuSans-Bold.ttf", "DejaVuSansMono.ttf")


def glyph(font_file, char, height_px=300, rotation_deg=0.0):
    """A glyph of ``font_file`` at a cap height of about ``height_px``, turned by ``rotation_deg`` (about its
    origin, before the frame is fitted around it); ``segments`` is the font's own count."""
    font = _TrueType(os.path.join(FONT_DIR, font_file))
    scale = height_px / (0.73 * font.units)  # cap height ~ height_px
    turn = np.radians(rotation_deg)
    matrix = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    contours, corners, segments = [], [], 0
    for raw in font.contours(char):
        c, k, count = _glyph_contour(raw, scale, 0.0, 0.0)
        contours.append(c @ matrix.T)
        corners.extend(tuple(matrix @ np.asarray(xy)) for xy in k)
        segments += count
    tag = font_file.replace("DejaVu", "").replace(".ttf", "")
    suffix = f"_r{rotation_deg:g}" if rotation_deg else ""
    return _shape(f"{tag}_{char}_{height_px}{suffix}", contours, corners, segments=segments)


def fonts_available():
    return all(os.path.exists(os.path.join(FONT_DIR, f)) for f in GLYPH_FONTS)


# ------------------------------------------------------------------------------------------ rasterizing

def rasterize(shape):
    """Ink mask (H, W): pixel centres inside the outline (even-odd over all contours); the scanline fill of
    ``heldout_shapes.rasterize`` (linear in edges + pixels, so 1200-px glyphs render in a fraction of a second)."""
    from heldout_shapes import rasterize as scanline_fill

    return scanline_fill(shape)


# ------------------------------------------------------------------------------------------- the set

def tuning_set(include_glyphs=True, glyph_chars="BDGKMRSWaegk&3ACEHNPQUVXZ25ry", sizes=(300,)):
    """The synthetic set the fit is tuned on (deterministic)."""
    shapes = [
        regular_polygon("square45", 4, 70, np.pi / 4 + 0.0),
        regular_polygon("square_r17", 4, 60, np.radians(17)),
        regular_polygon("triangle", 3, 80, 0.3),
        regular_polygon("hexagon", 6, 50, 0.1),
        star("star5", 5, 90, 38),
        star("star7_thin", 7, 80, 45, 0.2),
        ellipse("disc40", 40, 40),
        ellipse("disc8", 8, 8),
        ellipse("ellipse", 110, 45, 0.4),
        blob("blob1", 80, 1),
        blob("blob2", 60, 2, harmonics=6, amplitude=0.3),
        blob("blob3", 120, 3),
        lens("lens", 160, 50),
        lens("leaf", 120, 22),
        rounded_rect("roundrect", 180, 120, 30),
        ring("ring", 70, 45),
        d_shape("D_hand", 200),
        polygon_shape("arrow", [(0, 30), (100, 30), (100, 0), (150, 50), (100, 100), (100, 70), (0, 70)]),
    ]
    if include_glyphs and fonts_available():
        for k, ch in enumerate(glyph_chars):
            font = GLYPH_FONTS[k % len(GLYPH_FONTS)]
            for size in sizes:
                try:
                    shapes.append(glyph(font, ch, size))
                except ValueError:
                    pass
    return shapes



def size_set(glyph_chars="BDGKMRSWaegk&3", sizes=(48, 64, 600, 1200), analytic_scale=4.0):
    """Renders of the tuning set's shapes at other sizes (deterministic): glyphs at cap heights ``sizes``
    (every other one turned by an angle of 0-90 degrees), and the smooth analytic shapes drawn
    ``analytic_scale`` times larger. ``group`` of each: ``small`` (<= 64 px), ``large`` (>= 600 px) or
    ``analytic-large``."""
    shapes = []
    k = analytic_scale
    for shape in (ellipse("disc40", 40 * k, 40 * k), ellipse("ellipse", 110 * k, 45 * k, 0.4),
                  blob("blob1", 80 * k, 1), blob("blob3", 120 * k, 3), lens("lens", 160 * k, 50 * k),
                  rounded_rect("roundrect", 180 * k, 120 * k, 30 * k), ring("ring", 70 * k, 45 * k),
                  d_shape("D_hand", 200 * k)):
        shape["name"] += f"_x{k:g}"
        shape["group"] = "analytic-large"
        shapes.append(shape)
    if not fonts_available():
        return shapes
    for index, ch in enumerate(glyph_chars):
        font = GLYPH_FONTS[index % len(GLYPH_FONTS)]
        for j, size in enumerate(sizes):
            turn = float((17 + 37 * index) % 90) if (index + j) % 2 else 0.0
            try:
                shape = glyph(font, ch, size, turn)
            except ValueError:
                continue
            shape["group"] = "small" if size <= 64 else "large" if size >= 600 else "medium"
            shapes.append(shape)
    return shapes

def small_set(glyph_chars="BDEGHKMNRSWaegkmnr&3", sizes=(40, 48, 56, 64), polygons=16, blobs=8, seed=9):
    """Small glyph-like renders (deterministic), for the fit of small outlines: glyphs of the tuning fonts at
    cap heights ``sizes`` (one size per glyph in turn, turned by 0-90 degrees, every third upright), random
    polygons (4-8 vertices, 12-30 px across, interior angles of every kind, random rotation) and smooth
    blobs of 8-20 px radius. ``group``: ``small-glyph``, ``small-polygon`` or ``small-blob``."""
    rng = np.random.default_rng(seed)
    shapes = []
    if fonts_available():
        for index, ch in enumerate(glyph_chars):
            font = GLYPH_FONTS[index % len(GLYPH_FONTS)]
            for j in range(2):
                size = sizes[(index + j) % len(sizes)]
                turn = 0.0 if (index + j) % 3 == 0 else float(np.round(rng.uniform(0.0, 90.0), 1))
                try:
                    shape = glyph(font, ch, size, turn)
                except ValueError:
                    continue
                shape["group"] = "small-glyph"
                shapes.append(shape)
    for k in range(polygons):
        n = int(rng.integers(4, 9))
        angles = np.sort(rng.uniform(0.0, 2 * np.pi, n))
        while np.min(np.diff(np.concatenate([angles, angles[:1] + 2 * np.pi]))) < 0.35:
            angles = np.sort(rng.uniform(0.0, 2 * np.pi, n))
        radius = rng.uniform(6.0, 15.0) * rng.uniform(0.6, 1.0, n)
        vertices = np.column_stack([radius * np.cos(angles), radius * np.sin(angles)])
        vertices += rng.uniform(0.0, 1.0, 2)
        shape = polygon_shape(f"poly{k}_{n}", vertices)
        shape["group"] = "small-polygon"
        shapes.append(shape)
    for k in range(blobs):
        shape = blob(f"blob_small{k}", rng.uniform(8.0, 20.0), seed * 100 + k)
        shape["group"] = "small-blob"
        shapes.append(shape)
    return shapes

# ------------------------------------------------------------------------------------------- scoring

def _dense_bezier(bezier, step=0.1):
    b = np.asarray(bezier, float)
    length = np.hypot(*np.diff(b, axis=1).transpose(2, 0, 1)).sum(1)
    out = []
    for piece, ln in zip(b, length):
        n = max(2, int(np.ceil(ln / step)) + 1)
        t = np.linspace(0, 1, n)[:, None]
        out.append(((1 - t) ** 3) * piece[0] + 3 * t * (1 - t) ** 2 * piece[1]
                   + 3 * t**2 * (1 - t) * piece[2] + t**3 * piece[3])
    return np.concatenate(out)


def _dist_to_polyline(points, line):
    a, b = line, np.roll(line, -1, axis=0)
    k = min(6, len(a))
    _, idx = cKDTree((a + b) / 2).query(points, k=k)
    idx = idx.reshape(len(points), k)
    aa, ab = a[idx], (b - a)[idx]
    ap = points[:, None, :] - aa
    t = np.clip((ap * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-18), 0, 1)
    return np.hypot(*(ap - t[..., None] * ab).transpose(2, 0, 1)).min(axis=1)


def _turn_deg(u, v):
    nu, nv = np.hypot(*u), np.hypot(*v)
    if nu < 1e-12 or nv < 1e-12:
        return 0.0
    return float(np.degrees(np.arccos(np.clip(np.dot(u, v) / (nu * nv), -1, 1))))


def _tangents(piece):
    p = piece
    start = next((p[i] - p[0] for i in (1, 2, 3) if np.hypot(*(p[i] - p[0])) > 1e-9), np.zeros(2))
    end = next((p[3] - p[3 - i] for i in (1, 2, 3) if np.hypot(*(p[3] - p[3 - i])) > 1e-9), np.zeros(2))
    return start, end


def bezier_corners(bezier):
    """Joins of a closed chain of Bézier pieces turning by more than 30 degrees: list of (x, y)."""
    out = []
    for i in range(len(bezier)):
        a = _tangents(bezier[i - 1])[1]
        b = _tangents(bezier[i])[0]
        if _turn_deg(a, b) > CORNER_DEG:
            out.append(tuple(bezier[i][0]))
    return out


def match_corners(found, truth):
    if not truth and not found:
        return 1.0, 1.0, 1.0
    tp = 0
    if found and truth:
        D = np.hypot(*(np.array(found)[:, None, :] - np.array(truth)[None, :, :]).transpose(2, 0, 1))
        r, c = linear_sum_assignment(np.where(D <= MATCH_PX, D, 1e6))
        tp = int((D[r, c] <= MATCH_PX).sum())
    p = tp / len(found) if found else 1.0
    rc = tp / len(truth) if truth else 1.0
    return p, rc, (2 * p * rc / (p + rc) if p + rc else 0.0)


def score_beziers(shape, beziers):
    """beziers: list of (m, 4, 2) closed chains. Returns dict like the yardstick scorer."""
    beziers = [np.asarray(b, float) for b in beziers]
    truth_lines = [np.asarray(c) for c in shape["contours"]]
    traced = [_dense_bezier(b) for b in beziers]
    true_pts = np.concatenate(truth_lines)
    d1 = np.min([_dist_to_polyline(true_pts, t) for t in traced], axis=0)
    tr_pts = np.concatenate(traced)
    d2 = np.min([_dist_to_polyline(tr_pts, t) for t in truth_lines], axis=0)
    found = [c for b in beziers for c in bezier_corners(b)]
    p, r, f1 = match_corners(found, list(shape["corners"]))
    return {"segments": int(sum(len(b) for b in beziers)), "max_dev": float(max(d1.max(), d2.max())),
            "rms_dev": float(np.sqrt(np.mean(np.concatenate([d1, d2]) ** 2))),
            "corners": len(found), "true_corners": len(shape["corners"]),
            "corner_p": p, "corner_r": r, "corner_f1": f1}


# ------------------------------------------------------------------------------------------ SVG reading

_TOKEN = __import__("re").compile(r"[MmLlHhVvCcZz]|[-+]?(?:\d*\.\d+|\d+\.?)(?:[eE][-+]?\d+)?")
_XFORM = __import__("re").compile(r"(translate|scale)\s*\(([^)]*)\)")


def _transform(text):
    M = np.eye(3)
    for name, args in _XFORM.findall(text or ""):
        v = [float(a) for a in __import__("re").split(r"[\s,]+", args.strip()) if a]
        if name == "translate":
            T = np.array([[1, 0, v[0]], [0, 1, v[1] if len(v) > 1 else 0], [0, 0, 1]])
        else:
            T = np.diag([v[0], v[1] if len(v) > 1 else v[0], 1])
        M = M @ T
    return M


def svg_beziers(svg_text):
    """Closed subpaths of an SVG (potrace's or ours: M L H V C Z, absolute or relative; translate/scale
    transforms on <g>/<path>) as a list of (m, 4, 2) cubic chains (lines become straight cubics)."""
    import xml.etree.ElementTree as ET

    root = ET.fromstring(svg_text)
    out = []

    def walk(el, M):
        M = M @ _transform(el.get("transform"))
        if el.tag.split("}")[-1] == "path":
            toks = _TOKEN.findall(el.get("d", ""))
            i, pos, start, cmd, segs = 0, np.zeros(2), np.zeros(2), None, []

            def take(k):
                nonlocal i
                v = np.array([float(t) for t in toks[i:i + k]])
                i += k
                return v

            while i < len(toks):
                if toks[i].isalpha():
                    cmd = toks[i]
                    i += 1
                rel = cmd.islower()
                C = cmd.upper()
                if C == "Z":
                    if np.hypot(*(pos - start)) > 1e-9:
                        segs.append(np.array([pos, pos + (start - pos) / 3, pos + 2 * (start - pos) / 3, start]))
                    if segs:
                        out.append(np.array(segs))
                    segs, pos = [], start.copy()
                    continue
                if C == "M":
                    p = take(2) + (pos if rel else 0)
                    pos, start = p, p.copy()
                    cmd = "l" if rel else "L"
                    continue
                if C == "L":
                    p = take(2) + (pos if rel else 0)
                    segs.append(np.array([pos, pos + (p - pos) / 3, pos + 2 * (p - pos) / 3, p]))
                    pos = p
                elif C in "HV":
                    v = take(1)[0]
                    p = pos.copy()
                    k = 0 if C == "H" else 1
                    p[k] = v + (pos[k] if rel else 0)
                    segs.append(np.array([pos, pos + (p - pos) / 3, pos + 2 * (p - pos) / 3, p]))
                    pos = p
                elif C == "C":
                    v = take(6).reshape(3, 2) + (pos if rel else 0)
                    segs.append(np.array([pos, v[0], v[1], v[2]]))
                    pos = v[2]
                else:
                    raise ValueError(f"unsupported path command {cmd}")
            if segs:
                out.append(np.array(segs))
            # apply the transform
            for k in range(len(out)):
                pass
        for child in el:
            walk(child, M)
        return M

    # collect with transforms: re-walk per path to apply its matrix
    result = []

    def walk2(el, M):
        M = M @ _transform(el.get("transform"))
        if el.tag.split("}")[-1] == "path":
            before = len(out)
            walk(ET.fromstring(ET.tostring(el)), np.eye(3))
            for chain in out[before:]:
                pts = chain.reshape(-1, 2)
                pts = pts @ M[:2, :2].T + M[:2, 2]
                result.append(pts.reshape(chain.shape))
        else:
            for child in el:
                walk2(child, M)

    walk2(root, np.eye(3))
    return [r for r in result if len(r)]


def run_potrace(mask, potrace="potrace"):
    """Trace a mask with the potrace CLI at its defaults; returns (SVG text, seconds for the process)."""
    import subprocess
    import tempfile
    import time

    from PIL import Image

    with tempfile.TemporaryDirectory() as tmp:
        pbm = os.path.join(tmp, "in.pbm")
        Image.fromarray(~mask).convert("1").save(pbm)
        t0 = time.perf_counter()
        svg = subprocess.run([potrace, "-b", "svg", "-o", "-", pbm], check=True, capture_output=True).stdout
        return svg.decode(), time.perf_counter() - t0
