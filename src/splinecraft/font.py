"""Fonts from outlines and outlines from fonts, with fontTools and ufoLib2.

* :func:`build` writes a UFO source (ufoLib2), a compiled OpenType font with CFF outlines (exact cubics) and a
  TrueType font (quadratics from fontTools' ``cu2qu``, within ``ttf_max_error`` font units of the cubics), and
  returns the paths. :func:`to_glyph` makes one UFO glyph. Everything is checked and compiled in memory
  before any file is written (16-bit coordinates, duplicate glyphs or code points, ``cu2qu`` failures are
  a ``ValueError``), and the three are written all or nothing (:func:`_write_all`: a failure leaves the
  previous files as they were); the style name sets the linked-family fields (name IDs 1-6, ``fsSelection``,
  ``macStyle``, ``usWeightClass``; :func:`_set_style`).
* :func:`glyph_outline` reads a glyph of any font file (or installed family, found with ``fc-match``) into an
  :class:`~splinecraft.outline.Outline` (quadratic TrueType pieces raised to cubics exactly, components
  decomposed).

Frames. Outlines live in a y-down frame (pixels of a bitmap); font units are y-up with the baseline at 0. A
point ``(x, y)`` maps to ``((x - x_min) s + sidebearing, (baseline - y) s)`` with ``s = scale`` font units per
frame unit, ``x_min`` the left of the glyph's curves and ``baseline`` the outline's own (``Outline.baseline``,
set for font glyphs) or else the bottom of its curves (the curves' own box, :meth:`Outline.curve_bounds`, not the
control points'). The default scale is the same for every glyph of a
font: the tallest glyph (curve bounding box) spans ``ascender`` units.

Winding. Contours are oriented by nesting depth (even = filled, odd = hole), the rule of the outline model
(:func:`splinecraft.outline.model.nesting_depths`): a contour is nested in another only when it lies inside it
as a whole, so contours that partly overlap (a "+" of two bars, a swash crossing a stem; common in fonts, which
fill by the nonzero rule) keep the same direction and fill as their union, as in the font they came from. In
the UFO and the CFF font filled contours run counter-clockwise (y up, the PostScript rule), in the TrueType font clockwise (the TrueType rule; ``cu2qu`` reverses them). Rounding to integer font
units moves the curve by at most ``sqrt(2) / 2`` units (the Bézier convex hull), so the OTF is within 0.71
units and the TTF within ``ttf_max_error + 0.71`` units of the outline.
"""
from __future__ import annotations

import hashlib
import math
import os
import re
import shutil
import subprocess
import tempfile
import unicodedata
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._validation import blank_text, check_int, check_number, check_positive_number
from .outline import Outline, as_outline
from .outline.contour import bezier_signed_area
from .outline.model import nesting_depths

__all__ = ["build", "to_glyph", "glyph_outline", "font_contours", "FontFiles", "TTF_MAX_ERROR"]

#: Default maximum distance (font units) between a cubic and its TrueType quadratic approximation.
TTF_MAX_ERROR = 0.25


@dataclass
class FontFiles:
    """What :func:`build` wrote, and the scale it used (font units per frame unit)."""

    ufo: Path
    otf: Path
    ttf: Path
    scale: float
    ttf_max_error: float

    @property
    def paths(self) -> dict:
        return {"ufo": self.ufo, "otf": self.otf, "ttf": self.ttf}


# ---------------------------------------------------------------------------------------------- geometry
def _reverse(bezier):
    return bezier[::-1, ::-1].copy()


def font_contours(source, *, scale=1.0, baseline=None, sidebearing=0.0):
    """The contours of ``source`` in font units (y up), PostScript winding: a list of ``(m, 4, 2)`` arrays,
    and the advance width ``(x_max - x_min) s + 2 sidebearing`` (see the module docstring).

    ``x_min``, ``x_max`` and the default baseline are those of the curves' own bounding box
    (:meth:`Outline.curve_bounds`), not of the control points: a handle reaching past the curve does not
    move the glyph."""
    outline = as_outline(source)
    scale = check_positive_number(scale, "scale")
    sidebearing = check_number(sidebearing, "sidebearing")
    low, high = outline.curve_bounds()
    if baseline is None:
        baseline = outline.baseline if outline.baseline is not None else float(high[1])
    else:
        baseline = check_number(baseline, "baseline")
    curves = []
    for bezier in outline.bezier():
        mapped = np.empty_like(bezier)
        mapped[..., 0] = (bezier[..., 0] - low[0]) * scale + sidebearing
        mapped[..., 1] = (baseline - bezier[..., 1]) * scale
        curves.append(mapped)
    for k, depth in enumerate(nesting_depths(curves)):
        if (bezier_signed_area(curves[k]) > 0) != (depth % 2 == 0):
            curves[k] = _reverse(curves[k])
    return curves, float((high[0] - low[0]) * scale + 2 * sidebearing)


def _xy(point):
    """A point as plain Python numbers (ints where integral: UFO files and charstrings want those)."""
    return tuple(int(v) if float(v).is_integer() else float(v) for v in point)


def _is_line(piece):
    """Whether a cubic piece is its chord: both handles on the chord segment (relative tolerance 1e-9), not
    beyond its ends (a handle there makes the cubic overshoot its end along the line and come back)."""
    chord = piece[3] - piece[0]
    length = math.hypot(*chord)
    if not length:
        return False
    offsets = piece[1:3] - piece[0]
    off_line = np.abs(offsets[:, 0] * chord[1] - offsets[:, 1] * chord[0])
    along = offsets @ chord
    slack = 1e-9 * length * max(length, 1.0)
    return bool((off_line <= slack).all() and (along >= -slack).all() and (along <= length * length + slack).all())


def _draw(curves, pen, *, rounded=False):
    """Segment-pen drawing; pieces whose control points lie on their chord become lines. Straightness is
    decided on the given (unrounded) curves, so that the UFO (``rounded=True``: integer coordinates) and
    the compiled fonts (which round the same curves themselves) have the same lines."""
    def point(p):
        return _xy(np.round(p) if rounded else p)

    for bezier in curves:
        pen.moveTo(point(bezier[0, 0]))
        for piece in bezier:
            if _is_line(piece):
                pen.lineTo(point(piece[3]))
            else:
                pen.curveTo(point(piece[1]), point(piece[2]), point(piece[3]))
        pen.closePath()


# ---------------------------------------------------------------------------------------------- UFO glyphs
def _glyph_name(key):
    """``(glyph name, code point or None)`` of a glyph key: a single character (its AGL name), or a glyph
    name with the code point the Adobe Glyph List gives it when it names one character (``"space"``,
    ``"eacute"``, ``"uni20AC"``; not suffixed alternates such as ``"a.alt"``, nor ligatures)."""
    from fontTools.agl import UV2AGL, toUnicode

    if isinstance(key, str) and len(key) == 1:
        code = _code_point(ord(key), f"glyph key {key!r}")
        return UV2AGL.get(code, f"uni{code:04X}" if code <= 0xFFFF else f"u{code:05X}"), code
    if isinstance(key, str) and re.fullmatch(r"[A-Za-z_.][A-Za-z0-9_.\-]*", key):
        text = toUnicode(key) if "." not in key else ""
        return key, _code_point(ord(text), f"glyph name {key!r}") if len(text) == 1 else None
    raise ValueError(f"glyph key {key!r} must be a single character or a glyph name")


def _code_point(code, what):
    """``code`` if a cmap may map it: a Unicode scalar value (0 .. 0x10FFFF, not a surrogate U+D800 .. U+DFFF)
    that is not a C0 or C1 control character (U+0000 .. U+001F, U+007F .. U+009F: no glyph draws them) nor a
    noncharacter (U+FDD0 .. U+FDEF, U+nFFFE and U+nFFFF)."""
    if not 0 <= code <= 0x10FFFF or 0xD800 <= code <= 0xDFFF:
        shown = f"U+{code:04X}" if code >= 0 else "negative"  # not U+-001
        raise ValueError(f"{what} is {shown}, not a Unicode character a font can map (0 .. U+10FFFF, "
                         "without the surrogates U+D800 .. U+DFFF)")
    if code < 0x20 or 0x7F <= code <= 0x9F:
        raise ValueError(f"{what} is the control character U+{code:04X}, which a font does not map to a glyph "
                         "(C0 and C1 controls U+0000 .. U+001F, U+007F .. U+009F)")
    if 0xFDD0 <= code <= 0xFDEF or code & 0xFFFE == 0xFFFE:
        # U+FFFF is also the code of the end segment every cmap of format 4 must have (it maps to .notdef)
        raise ValueError(f"{what} is the noncharacter U+{code:04X}, which is not for interchange (U+FDD0 .. "
                         "U+FDEF and the last two code points of every plane, U+FFFE, U+FFFF, U+1FFFE, ...)")
    return code


def _glyph(source, name, unicode, scale, baseline, sidebearing):
    """``(glyph, curves, advance)``: the UFO glyph (integer coordinates) and the unrounded font-unit curves."""
    from ufoLib2.objects import Glyph

    outline = as_outline(source)
    if name is None and outline.name:  # the outline's own name: say whose it is when it cannot name a glyph
        try:
            glyph_name, code = _glyph_name(outline.name)
        except ValueError:
            raise ValueError(f"the outline's name {outline.name!r} is not a single character or a glyph name: "
                             "pass name= (a character such as 'a', or a glyph name such as 'a.alt')") from None
    else:
        glyph_name, code = _glyph_name(name if name is not None else "glyph")
    if unicode is not None:
        code = check_int(unicode, "unicode")
        code = _code_point(code, f"unicode={code}")
    curves, advance = font_contours(outline, scale=scale, baseline=baseline, sidebearing=sidebearing)
    glyph = Glyph(glyph_name)
    glyph.unicodes = [] if code is None else [code]
    glyph.width = round(advance)
    _draw(curves, glyph.getPen(), rounded=True)
    return glyph, curves, round(advance)


def to_glyph(source, name=None, *, unicode=None, scale=1.0, baseline=None, sidebearing=50.0):
    """A :class:`ufoLib2.objects.Glyph` of ``source`` (an outline, a TraceResult, an editor, ...).

    ``name`` is a single character (its Unicode code point and AGL name are used) or a glyph name (default
    the outline's name or ``"glyph"``; a name the Adobe Glyph List maps to one character, such as
    ``"space"`` or ``"eacute"``, gets that code point); ``unicode`` overrides the code point. Geometry as in
    :func:`font_contours`, coordinates rounded to integer font units; the advance is the glyph's width plus
    two ``sidebearing``.
    """
    return _glyph(source, name, unicode, scale, baseline, sidebearing)[0]


# ---------------------------------------------------------------------------------------------- names
def _check_name(text, what):
    """``text`` if it can be a font's family or style name: a non-blank string without control characters
    (C0, C1), line or paragraph separators, surrogates or noncharacters (U+FDD0 .. U+FDEF, U+xxFFFE,
    U+xxFFFF), which neither the UFO's XML nor a font's name table can hold as text."""
    if not isinstance(text, str):
        raise TypeError(f"{what} must be a non-empty string, got {type(text).__name__}")
    if not text.strip():
        raise ValueError(f"{what} must be a non-empty string, got {text!r}")
    for index, char in enumerate(text):
        code = ord(char)
        if (unicodedata.category(char) in ("Cc", "Cs", "Zl", "Zp") or 0xFDD0 <= code <= 0xFDEF
                or code & 0xFFFE == 0xFFFE):
            raise ValueError(f"{what} {text!r} holds U+{code:04X} at index {index}: a font name may not hold "
                             "control characters, line breaks, surrogates or noncharacters")
    return text


#: Latin letters that Unicode does not decompose into an ASCII letter and a mark (NFKD leaves them whole).
_LATIN_TO_ASCII = str.maketrans({"Ł": "L", "ł": "l", "Ø": "O", "ø": "o", "Đ": "D", "đ": "d", "Ð": "D", "ð": "d",
                                 "Ħ": "H", "ħ": "h", "Ŧ": "T", "ŧ": "t", "ı": "i", "ß": "ss", "Æ": "AE", "æ": "ae",
                                 "Œ": "OE", "œ": "oe", "Þ": "Th", "þ": "th"})


def _ascii(text, keep="A-Za-z0-9-"):
    """The characters of ``text`` in the class ``keep`` after NFKD decomposition (accents split off) and a
    few Latin letters spelled in ASCII (``"Łódź"`` -> ``"Lodz"``); everything else is dropped."""
    decomposed = unicodedata.normalize("NFKD", text.translate(_LATIN_TO_ASCII))
    return re.sub(f"[^{keep}]", "", decomposed)


def _short_hash(*texts):
    """Eight hex digits of the SHA-1 of ``texts`` (UTF-8, NUL-separated): the same in every run and on every
    machine, unlike ``hash()``."""
    return hashlib.sha1("\0".join(texts).encode("utf-8")).hexdigest()[:8]


def _postscript_parts(family, style):
    """``(family, style)`` in the PostScript characters ``[A-Za-z0-9-]`` (:func:`_ascii`); a name with no such
    character becomes ``Splinecraft<hash>`` (family) or ``<hash>`` (style), a short hash of the Unicode name."""
    return _ascii(family) or f"Splinecraft{_short_hash(family)}", _ascii(style) or _short_hash(style)


def _postscript_name(family, style):
    """The PostScript name (name ID 6, the CFF ``FontName``): ``Family-Style`` of :func:`_postscript_parts`,
    at most 63 characters (OpenType). The name table keeps the full Unicode names (IDs 1, 2, 4, 16, 17)."""
    return "-".join(_postscript_parts(family, style))[:63]


#: Characters no file name may hold on Windows (``/`` and ``\\`` separate paths everywhere).
_UNSAFE_IN_FILE_NAMES = frozenset('<>:"/\\|?*')

#: Longest file stem, in UTF-8 bytes: with ``.ufo`` and a hash it stays far below the usual 255-byte limit.
_MAX_STEM_BYTES = 200


def _stem_part(text):
    """``text`` as part of a file name: NFC, white space dropped (``"Test Sans"`` -> ``"TestSans"``), letters,
    digits and signs of every script kept; path separators, control and format characters and those Windows
    refuses (``<>:"/\\|?*``) become ``_``; no dots at either end (no hidden file, no ``..``)."""
    kept = []
    for char in unicodedata.normalize("NFC", text):
        if char.isspace():
            continue
        unsafe = (char in _UNSAFE_IN_FILE_NAMES or char in (os.sep, os.altsep)
                  or unicodedata.category(char) in ("Cc", "Cf"))
        kept.append("_" if unsafe else char)
    return "".join(kept).strip(".")


def _built_for(path):
    """``"Family Style"`` of the existing output ``path`` (a UFO's family and style names, a font's full name,
    name ID 4), or ``None`` when it is not a readable UFO or font."""
    import plistlib

    from fontTools.ttLib import TTFont

    try:
        if path.suffix == ".ufo":
            with open(path / "fontinfo.plist", "rb") as stream:
                info = plistlib.load(stream)
            return f"{info['familyName']} {info['styleName']}"
        with open(path, "rb") as stream, TTFont(stream, lazy=True) as ttfont:
            return ttfont["name"].getDebugName(4)
    except Exception:  # not a UFO or font file (or a damaged one): not ours to replace
        return None


def _file_stem(family, style, folder):
    """The file stem of the outputs of ``family`` / ``style`` in ``folder``: ``Family-Style`` of
    :func:`_stem_part`, which keeps letters of every script (``日本語-Regular``). A short stable hash of the
    two names is appended (``Family-Style-1a2b3c4d``) when a part would be empty, the stem longer than
    ``_MAX_STEM_BYTES`` (then cut), or when an output of that stem in ``folder`` was built for another name
    (``"A/B"`` and ``"A_B"``, ``"Test Sans"`` and ``"TestSans"``) or is not a font: different names never
    overwrite each other's files."""
    family_part, style_part = _stem_part(family), _stem_part(style)
    stem = f"{family_part or 'Font'}-{style_part or 'Regular'}"
    suffix = f"-{_short_hash(family, style)}"
    if len(stem.encode("utf-8")) > _MAX_STEM_BYTES:
        room = _MAX_STEM_BYTES - len(suffix)
        return stem.encode("utf-8")[:room].decode("utf-8", "ignore").rstrip(".") + suffix
    if not family_part or not style_part:
        return stem + suffix
    full_name = f"{family} {style}"
    for kind in ("ufo", "otf", "ttf"):
        path = folder / f"{stem}.{kind}"
        if os.path.lexists(path) and _built_for(path) != full_name:
            return stem + suffix
    return stem


def _default_scale(outlines, ascender):
    """Font units per frame unit making the tallest glyph's curve bounding box ``ascender`` high."""
    tallest = max(float(np.ptp([bound[1] for bound in outline.curve_bounds()])) for outline in outlines)
    if not tallest > 0:
        raise ValueError("every glyph has zero height, so there is no default scale; pass scale=")
    return ascender / tallest


#: The range of coordinates in glyf, CFF widths and head/hhea metrics (int16).
_INT16 = (-32768, 32767)


def _check_range(name, curves, advance):
    """Refuse a glyph whose rounded coordinates or advance do not fit the fonts' 16-bit fields."""
    points = np.round(np.concatenate([c.reshape(-1, 2) for c in curves])) if curves else np.zeros((1, 2))
    low, high = float(points.min()), float(points.max())
    if low < _INT16[0] or high > _INT16[1] or not 0 <= advance <= 65535:
        value = max((low, high, advance), key=abs)
        raise ValueError(f"glyph {name!r} reaches {value:g} font units, beyond the 16-bit range of font "
                         f"coordinates ({_INT16[0]} .. {_INT16[1]}, advance <= 65535); use a smaller scale")


def _warn_if_flat(key, curves, scale):
    """Warn when rounding to integer font units flattens a glyph: its curves are under one unit wide or tall."""
    if not curves:
        return
    points = np.concatenate([c.reshape(-1, 2) for c in curves])
    size = np.ptp(points, axis=0)
    if size.min() < 1.0:
        warnings.warn(f"glyphs[{key!r}] is {size[0]:.3g} x {size[1]:.3g} font units at scale={scale:g}: rounding "
                      "to integer font units flattens it; use a larger scale (the default makes the tallest "
                      "glyph ascender units high)", UserWarning, stacklevel=3)


def build(glyphs, *, family="Splinecraft", style="Regular", output_dir=".", units_per_em=1000, ascender=800,
          descender=-200, scale=None, sidebearing=50, ttf_max_error=TTF_MAX_ERROR) -> FontFiles:
    """Write ``<family>-<style>.ufo``, ``.otf`` (CFF) and ``.ttf`` (quadratic) into ``output_dir``.

    The file stem keeps the names' letters of every script, without white space and with ``_`` for
    characters a file name cannot hold; a short hash of the names is appended where that stem is empty, too
    long, or taken by the files of another name (:func:`_file_stem`).

    Arguments are checked and the fonts compiled before anything is written; the three outputs then replace
    any previous ones together, or (an ``OSError`` while writing) not at all.

    Parameters
    ----------
    glyphs : dict
        Character (or glyph name) -> outline source (Outline, TraceResult, OutlineEditor, SVG, knot lists).
        A ``space`` (a quarter em) and ``.notdef`` are added when missing.
    family, style : str
        Non-empty names.
    units_per_em, ascender, descender : int
        Vertical metrics: ``units_per_em`` 16 to 16384 (OpenType), ``0 < ascender <= 32767``,
        ``-32768 <= descender <= 0``. An ascender or descender beyond twice ``units_per_em`` (legal, but
        glyphs several em tall) is a ``UserWarning``.
    scale : float, optional
        Font units per frame unit for every glyph (default: the tallest glyph spans ``ascender``). A glyph
        less than one font unit wide or tall at this scale (rounding flattens it) is a ``UserWarning``.
    sidebearing : float
        Left and right side bearing, font units.
    ttf_max_error : float
        Maximum distance (font units) of the TrueType quadratics from the cubics (``cu2qu``).

    Returns
    -------
    FontFiles
        ``ufo``, ``otf``, ``ttf`` paths, the ``scale`` used and ``ttf_max_error``.
    """
    import ufoLib2

    if not isinstance(glyphs, dict) or not glyphs:
        raise ValueError("glyphs must be a non-empty dict of character -> outline")
    family, style = _check_name(family, "family"), _check_name(style, "style")
    if not isinstance(output_dir, (str, os.PathLike)) or not isinstance(os.fspath(output_dir), str):
        raise TypeError(f"output_dir must be a path (str or os.PathLike), got {type(output_dir).__name__}")
    if blank_text(os.fspath(output_dir)):  # Path('') is '.', Path(' ') a folder called space: never meant
        raise ValueError(f"output_dir is {blank_text(os.fspath(output_dir))}: give a folder ('.' for the current one)")
    try:
        units_per_em = check_int(units_per_em, "units_per_em", minimum=16, maximum=16384, integral_floats=True)
    except (TypeError, ValueError) as exc:
        raise type(exc)(f"{exc} (OpenType allows 16 to 16384 units per em)") from None
    ascender = int(check_number(ascender, "ascender", minimum=0, maximum=_INT16[1], inclusive=(False, True)))
    descender = int(check_number(descender, "descender", minimum=_INT16[0], maximum=0))
    if not (ascender > 0 >= descender):
        raise ValueError(f"need ascender > 0 >= descender, got {ascender} and {descender}")
    if max(ascender, -descender) > 2 * units_per_em:
        warnings.warn(f"ascender={ascender} / descender={descender} reach beyond twice units_per_em={units_per_em}: "
                      "the glyphs (the tallest spans the ascender) would be several em tall; OpenType allows it, "
                      "but the metrics are likely meant for another units_per_em", UserWarning, stacklevel=2)
    sidebearing = check_number(sidebearing, "sidebearing")
    ttf_max_error = check_positive_number(ttf_max_error, "ttf_max_error")
    outlines = {}
    for key, source in glyphs.items():
        try:
            outlines[key] = as_outline(source)
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"glyphs[{key!r}]: {exc}") from None
    scale = _default_scale(outlines.values(), ascender) if scale is None else check_positive_number(scale, "scale")

    font = ufoLib2.Font()
    info = font.info
    info.familyName, info.styleName = family, style
    info.postscriptFontName = _postscript_name(family, style)
    info.unitsPerEm, info.ascender, info.descender = units_per_em, ascender, descender
    info.capHeight, info.xHeight = ascender, round(ascender * 0.66)
    _set_style(info)
    curves, keys, codes = {}, {}, {}
    for key, outline in outlines.items():
        glyph, glyph_curves, advance = _glyph(outline, key, None, scale, None, sidebearing)
        if glyph.name in keys:
            raise ValueError(f"glyphs[{keys[glyph.name]!r}] and glyphs[{key!r}] are both the glyph {glyph.name!r}")
        for code in glyph.unicodes:
            if code in codes:
                raise ValueError(f"glyphs[{codes[code]!r}] and glyphs[{key!r}] both map U+{code:04X}")
            codes[code] = key
        _check_range(glyph.name, glyph_curves, advance)
        _warn_if_flat(key, glyph_curves, scale)
        keys[glyph.name], curves[glyph.name] = key, glyph_curves
        font.addGlyph(glyph)
    if "space" not in font and 0x20 not in codes:
        font.newGlyph("space").width = units_per_em // 4
        font["space"].unicodes = [0x20]
    if ".notdef" not in font:
        font.newGlyph(".notdef").width = units_per_em // 2
    # compile both fonts in memory first: nothing is written unless all three can be
    otf = _compile(font, curves, cff=True, max_error=ttf_max_error)
    ttf = _compile(font, curves, cff=False, max_error=ttf_max_error)
    output = Path(os.fspath(output_dir))
    created = not output.exists()
    output.mkdir(parents=True, exist_ok=True)
    stem = _file_stem(family, style, output)
    paths = FontFiles(output / f"{stem}.ufo", output / f"{stem}.otf", output / f"{stem}.ttf", scale, ttf_max_error)
    try:
        _write_all(font, {"otf": otf, "ttf": ttf}, paths)
    except BaseException:
        if created:
            try:
                output.rmdir()  # the folder this call made, if it is still empty
            except OSError:
                pass
        raise
    return paths


def _write_all(font, compiled, paths):
    """Write the UFO ``font`` and the ``compiled`` font bytes (``{"otf": ..., "ttf": ...}``) to ``paths``, all
    or nothing.

    Everything is first written into a hidden staging folder inside the output folder (the same file system,
    so that moving is renaming). Then each output takes its place: an existing UFO folder is renamed aside
    into the staging folder and the new one renamed in; an existing font file is kept aside (a hard link, or
    a copy with its times) and replaced with ``os.replace``. If any step fails, the moves are undone in
    reverse (the previous outputs are back, bytes and times) and the staging folder is removed; after
    success it is removed with the replaced outputs. Should undoing a move fail too, the other moves are
    still undone and the staging folder, holding what was not restored, is kept and named in the error.
    """
    staging = Path(tempfile.mkdtemp(prefix=".splinecraft-", suffix=".tmp", dir=paths.ufo.parent))
    undo = []  # (action, arguments) restoring the previous state, in the order done
    try:
        font.save(staging / "new.ufo")
        for kind, data in compiled.items():
            (staging / f"new.{kind}").write_bytes(data)
        for kind in ("ufo", *compiled):
            target, new, old = getattr(paths, kind), staging / f"new.{kind}", staging / f"old.{kind}"
            if kind == "ufo":
                if os.path.lexists(target):
                    os.rename(target, old)
                    undo.append((os.rename, old, target))
                os.rename(new, target)
                undo.append((os.rename, target, new))
            else:
                existed = os.path.lexists(target)
                if existed:
                    _keep_aside(target, old)
                    undo.append((os.replace, old, target))
                os.replace(new, target)
                if not existed:
                    undo.append((os.remove, target))
    except BaseException as exc:
        failures = []
        for action, *arguments in reversed(undo):
            try:
                action(*arguments)
            except OSError as failure:
                failures.append(str(failure))
        if failures:
            raise OSError(f"writing the font files failed ({type(exc).__name__}: {exc}) and restoring the previous "
                          f"ones failed too ({'; '.join(failures)}); what was not restored is in "
                          f"{str(staging)!r}") from exc
        shutil.rmtree(staging, ignore_errors=True)
        raise
    shutil.rmtree(staging, ignore_errors=True)


def _keep_aside(path, aside):
    """Keep the file ``path`` as ``aside`` too (a hard link, else a copy with its times), so that replacing
    ``path`` can be undone with ``os.replace(aside, path)``."""
    try:
        os.link(path, aside, follow_symlinks=False)
    except OSError:
        shutil.copy2(path, aside, follow_symlinks=False)


#: usWeightClass of the weight words of a style name (the OpenType OS/2 spec's names).
_WEIGHTS = {"thin": 100, "hairline": 100, "extralight": 200, "ultralight": 200, "light": 300, "regular": 400,
            "normal": 400, "book": 400, "medium": 500, "semibold": 600, "demibold": 600, "bold": 700,
            "extrabold": 800, "ultrabold": 800, "black": 900, "heavy": 900}


def _set_style(info):
    """Style-linking fields of the UFO ``info`` from its style name (the ufo2ft / OpenType conventions).

    "Bold" and "Italic" (or "Oblique") are the linked styles: ``styleMapStyleName`` is ``regular``, ``bold``,
    ``italic`` or ``bold italic``; any other words ("Light", "Condensed") go into ``styleMapFamilyName``
    ("Family Light", with "Family" / "Light Italic" as the typographic names). The weight class comes from
    the weight word (default 400).
    """
    words = info.styleName.split()
    lower = [word.lower().replace("-", "") for word in words]
    bold, italic = "bold" in lower, bool({"italic", "oblique"} & set(lower))
    extra = [w for w, low in zip(words, lower) if low not in ("bold", "italic", "oblique", "regular")]
    info.styleMapStyleName = " ".join(["bold"] * bold + ["italic"] * italic) or "regular"
    info.styleMapFamilyName = " ".join([info.familyName] + extra)
    info.openTypeOS2WeightClass = next((_WEIGHTS[w] for w in lower if w in _WEIGHTS and w != "regular"), 400)
    if extra:
        info.openTypeNamePreferredFamilyName, info.openTypeNamePreferredSubfamilyName = info.familyName, info.styleName


def _naming(info, postscript):
    """Name table strings (IDs 1-6, and 16/17 for styles beyond the four linked ones), fsSelection bits
    (0 italic, 5 bold, 6 regular), head.macStyle bits (0 bold, 1 italic) and usWeightClass."""
    linked = info.styleMapStyleName
    bold, italic = "bold" in linked, "italic" in linked
    names = {"familyName": info.styleMapFamilyName, "styleName": linked.title(),
             "uniqueFontIdentifier": f"1.000;NONE;{postscript}", "fullName": f"{info.familyName} {info.styleName}",
             "version": "Version 1.000", "psName": postscript}
    if info.openTypeNamePreferredFamilyName:
        names["typographicFamily"] = info.openTypeNamePreferredFamilyName
        names["typographicSubfamily"] = info.openTypeNamePreferredSubfamilyName
    fs_selection = (1 << 0) * italic | (1 << 5) * bold | (1 << 6) * (not bold and not italic)
    return names, fs_selection, (1 << 0) * bold | (1 << 1) * italic, info.openTypeOS2WeightClass


def _compile(font, curves, *, cff, max_error):
    """The bytes of an OTF (CFF) or TTF of the UFO's glyphs; outlines are drawn from the unrounded ``curves``
    (glyph name -> font-unit Bézier arrays), so that each format rounds once."""
    import io

    from fontTools.cu2qu.errors import ApproxNotFoundError
    from fontTools.fontBuilder import FontBuilder
    from fontTools.misc.arrayTools import intRect
    from fontTools.pens.boundsPen import BoundsPen
    from fontTools.pens.cu2quPen import Cu2QuPen
    from fontTools.pens.roundingPen import RoundingPen
    from fontTools.pens.t2CharStringPen import T2CharStringPen
    from fontTools.pens.ttGlyphPen import TTGlyphPen

    info = font.info
    order = [".notdef"] + sorted(name for name in font.keys() if name != ".notdef")
    cmap = {code: glyph.name for glyph in font for code in glyph.unicodes}
    builder = FontBuilder(info.unitsPerEm, isTTF=not cff)
    builder.setupGlyphOrder(order)
    builder.setupCharacterMap(cmap)
    metrics, y_min, y_max = {}, 0, 0
    outlines = {}
    for name in order:
        glyph = font[name]

        def draw(pen, name=name, glyph=glyph):
            if name in curves:
                _draw(curves[name], pen)
            else:
                glyph.draw(pen)

        if cff:
            pen = T2CharStringPen(int(glyph.width), None)
            draw(pen)
            outlines[name] = pen.getCharString()
            bounds_pen = BoundsPen(None)  # the curves' box of the charstring (which rounds to integers)
            draw(RoundingPen(bounds_pen))
            bounds = bounds_pen.bounds
        else:
            pen = TTGlyphPen(None)
            try:
                draw(Cu2QuPen(pen, max_error, reverse_direction=True))
            except ApproxNotFoundError:
                raise ValueError(f"glyph {name!r}: cu2qu finds no quadratics within ttf_max_error={max_error:g} "
                                 "font units; use a larger ttf_max_error") from None
            outlines[name] = pen.glyph()
            coordinates = outlines[name].coordinates if outlines[name].numberOfContours > 0 else []
            bounds = (*np.min(coordinates, axis=0), *np.max(coordinates, axis=0)) if len(coordinates) else None
        # hmtx's left side bearing is the glyph's x_min (glyf: of its points; CFF: of its curves)
        bounds = intRect(bounds) if bounds else (0, 0, 0, 0)
        y_min, y_max = min(y_min, bounds[1]), max(y_max, bounds[3])
        metrics[name] = (int(glyph.width), int(bounds[0]))
    postscript = info.postscriptFontName
    names, fs_selection, mac_style, weight = _naming(info, postscript)
    if cff:
        # CFF strings are 8-bit: the Unicode names live in the name table, the CFF gets printable ASCII ones
        family_ps, style_ps = _postscript_parts(info.familyName, info.styleName)
        family_cff = " ".join(_ascii(info.familyName, " -~").split()) or family_ps
        style_cff = " ".join(_ascii(info.styleName, " -~").split()) or style_ps
        builder.setupCFF(postscript, {"FullName": f"{family_cff} {style_cff}", "FamilyName": family_cff,
                                      "Weight": style_cff}, outlines, {})
    else:
        builder.setupGlyf(outlines)
    builder.setupHorizontalMetrics(metrics)
    builder.setupHorizontalHeader(ascent=info.ascender, descent=info.descender)
    builder.setupNameTable(names)
    builder.setupOS2(sTypoAscender=info.ascender, sTypoDescender=info.descender, sTypoLineGap=0,
                     usWinAscent=max(info.ascender, int(y_max)), usWinDescent=max(-info.descender, -int(y_min)),
                     sxHeight=info.xHeight, sCapHeight=info.capHeight, fsSelection=fs_selection,
                     usWeightClass=weight)
    builder.updateHead(macStyle=mac_style)
    builder.setupPost()
    data = io.BytesIO()
    try:
        builder.save(data)
    except Exception as exc:  # fontTools' struct / overflow errors: a value out of a table field's range
        raise ValueError(f"cannot compile the {'OTF' if cff else 'TTF'}: {type(exc).__name__}: {exc}") from None
    return data.getvalue()


# ---------------------------------------------------------------------------------------------- reading
def _resolve_font(font):
    path = Path(os.fspath(font))
    if path.is_file():
        return path
    text = os.fspath(font)
    if path.suffix.lower() in (".ttf", ".otf", ".ttc", ".otc", ".woff", ".woff2") or os.sep in text:
        raise FileNotFoundError(f"no font file {text!r}")
    matcher = shutil.which("fc-match")
    if matcher is None:
        raise FileNotFoundError(f"{text!r} is not a font file, and fc-match is not installed to look up families")
    found = subprocess.run([matcher, "-f", "%{file}\n%{family}", text], capture_output=True, text=True,
                           timeout=30, check=False).stdout.split("\n", 1)
    families = [f.strip().lower() for f in (found[1] if len(found) > 1 else "").split(",")]
    if not found[0] or text.strip().lower() not in families:
        raise ValueError(f"no installed font family {text!r} (fc-list lists the installed fonts)")
    return Path(found[0])


def _open_font(font, font_number):
    from fontTools.ttLib import TTFont

    path = _resolve_font(font)
    stream = open(path, "rb")  # ours to close when fontTools fails half way (TTFont.close closes it otherwise)
    try:
        return TTFont(stream, fontNumber=font_number, lazy=True), path
    except Exception as exc:  # fontTools raises many kinds for a damaged or foreign file
        stream.close()
        raise ValueError(f"cannot read the font file {str(path)!r}: {type(exc).__name__}: {exc}") from None


#: A contour whose end is within this many font units of its start is closed by moving its end onto the start:
#: font coordinates are integers (glyf) or 16.16 fixed point (CFF: steps of 1.5e-5 units, which add up along
#: a charstring), so such a gap is rounding, not a segment. A wider gap gets a closing line.
CLOSE_TOLERANCE = 1e-3


class _BezierPen:
    """A fontTools segment pen collecting closed contours as cubic Bézier arrays; components are drawn
    (decomposed, with their transformation) from ``glyph_set``, the font's glyph set."""

    def __init__(self, glyph_set=None):
        from fontTools.pens.basePen import BasePen

        collector = self

        class Pen(BasePen):
            def _moveTo(self, point):
                collector.current, collector.start = [], np.array(point, float)
                collector.position = collector.start

            def _lineTo(self, point):
                end = np.array(point, float)
                p = collector.position
                collector.current.append([p, p + (end - p) / 3, p + 2 * (end - p) / 3, end])
                collector.position = end

            def _curveToOne(self, a, b, c):
                collector.current.append([collector.position, np.array(a, float), np.array(b, float),
                                          np.array(c, float)])
                collector.position = collector.current[-1][3]

            def _qCurveToOne(self, a, b):
                p, q, end = collector.position, np.array(a, float), np.array(b, float)
                collector.current.append([p, p + 2 * (q - p) / 3, end + 2 * (q - end) / 3, end])
                collector.position = end

            def _closePath(self):
                if not collector.current:
                    return
                bezier = np.array(collector.current)
                if np.hypot(*(bezier[-1, 3] - bezier[0, 0])) <= CLOSE_TOLERANCE:
                    bezier[-1, 3] = bezier[0, 0]
                else:
                    end, start = bezier[-1, 3], bezier[0, 0]
                    bezier = np.vstack([bezier, [[end, end + (start - end) / 3, end + 2 * (start - end) / 3, start]]])
                collector.contours.append(bezier)

            def _endPath(self):
                collector.open_contours += 1

        self.contours, self.open_contours = [], 0
        self.pen = Pen(glyph_set)


def glyph_outline(font, char, *, font_number=0) -> Outline:
    """The contours of a glyph of a font, as an :class:`~splinecraft.outline.Outline` in font units.

    Parameters
    ----------
    font : path or str
        A font file (TrueType, OpenType/CFF, collections with ``font_number``) or the family name of an
        installed font (``"DejaVu Sans"``, looked up with ``fc-match``).
    char : str or int
        A single character (looked up in the font's cmap), a glyph name, or a code point.

    Returns
    -------
    Outline
        In a y-down frame: ``(x, ascender - y)`` (font units), ``width`` = the advance, ``height`` =
        ascender - descender, ``baseline`` = the ascender; composite glyphs are decomposed. Fonts fill by the
        nonzero rule: a contour that lies inside others and adds no ink by it (inside one of the same turn, as
        overlapping components leave) is left out, since the outline reads nesting as holes.

    Raises
    ------
    FileNotFoundError, ValueError
        A missing or unreadable font file, an unknown family, a char or glyph name not in the font, a glyph
        without contours.
    """
    ttfont, path = _open_font(font, font_number)
    with ttfont:  # closes the file (lazy=True reads tables from it on demand)
        if isinstance(char, bool) or not isinstance(char, (str, int)):
            raise TypeError(f"char must be a character, a glyph name or a code point, got {type(char).__name__}")
        if isinstance(char, int) and not 0 <= char <= 0x10FFFF:  # chr() said 'arg not in range(0x110000)'
            raise ValueError(f"char = {char} is not a code point (0 .. 0x10FFFF)")
        if isinstance(char, int) or len(char) == 1:
            code = char if isinstance(char, int) else ord(char)
            name = ttfont.getBestCmap().get(code)
            if name is None:
                raise ValueError(f"{str(path)!r} has no glyph for {chr(code)!r} (U+{code:04X})")
        else:
            name = char
            if name not in ttfont.getGlyphOrder():
                raise ValueError(f"{str(path)!r} has no glyph named {name!r}")
        glyph_set = ttfont.getGlyphSet()
        collector = _BezierPen(glyph_set)
        glyph_set[name].draw(collector.pen)
        if not collector.contours:
            raise ValueError(f"glyph {name!r} of {str(path)!r} has no closed contours (a space or a mark?)")
        ascender, descender = ttfont["hhea"].ascent, ttfont["hhea"].descent
        curves = []
        for bezier in collector.contours:
            flipped = bezier.copy()
            flipped[..., 1] = ascender - bezier[..., 1]
            curves.append(flipped)
        advance = ttfont["hmtx"][name][0]
    from .outline import from_bezier
    from .outline.sources import _nonzero_covered

    if len(curves) > 1:  # fonts fill by the nonzero rule: a contour inside another of the same turn adds no ink
        covered = set(_nonzero_covered(curves))
        curves = [curve for k, curve in enumerate(curves) if k not in covered]
    right = max(float(c[..., 0].max()) for c in curves)
    return from_bezier(curves, width=max(advance, right, 1), height=ascender - descender, baseline=ascender,
                       name=name)
