"""Tiny TrueType fonts of straight contours for the font tests (fontTools' FontBuilder), written to a file."""
from __future__ import annotations


def line_font(path, glyph, code, contours, advance, family="Lines"):
    """A TrueType font at ``path`` whose glyph ``glyph`` (mapped from code point ``code``) is the closed polygons
    ``contours`` (lists of (x, y) in font units, y up, 1000 units per em), ``advance`` wide; returns ``path``."""
    from fontTools.fontBuilder import FontBuilder
    from fontTools.pens.ttGlyphPen import TTGlyphPen

    pen = TTGlyphPen(None)
    for contour in contours:
        pen.moveTo(contour[0])
        for point in contour[1:]:
            pen.lineTo(point)
        pen.closePath()
    builder = FontBuilder(1000, isTTF=True)
    builder.setupGlyphOrder([".notdef", glyph])
    builder.setupCharacterMap({code: glyph})
    builder.setupGlyf({".notdef": TTGlyphPen(None).glyph(), glyph: pen.glyph()})
    builder.setupHorizontalMetrics({".notdef": (500, 0), glyph: (advance, 0)})
    builder.setupHorizontalHeader(ascent=800, descent=-200)
    builder.setupNameTable({"familyName": family, "styleName": "Regular"})
    builder.setupOS2()
    builder.setupPost()
    builder.save(str(path))
    return path
