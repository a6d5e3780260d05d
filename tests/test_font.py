"""Fonts: UFO + OTF (CFF) + TTF (cu2qu) from outlines, read back with fontTools and FreeType; glyphs of fonts
as outlines."""
import numpy as np
import pytest
from fontTools.pens.recordingPen import DecomposingRecordingPen
from fontTools.ttLib import TTFont
from PIL import Image, ImageDraw
from scipy.spatial import cKDTree

import splinecraft as sc
from splinecraft import datasets, font
from splinecraft.outline import from_knots
from splinecraft.outline.contour import bezier_signed_area

DEJAVU = "DejaVu Sans"


def _edited(trace):
    """An OutlineEditor of ``trace`` after designer's edits: a corner's handle pulled, then the run that
    starts at that corner scaled per axis (the font must hold what the editor shows)."""
    editor = sc.OutlineEditor(trace)
    contour = editor.outline.contours[0]
    corner = int(np.flatnonzero(contour.corners)[0])
    editor.move_handle(0, corner, "out", contour.bezier()[corner, 1] + [-6.0, 4.0])
    corners = np.flatnonzero(contour.corners)
    end = int(corners[1]) if corners.size > 1 else corner + len(contour)
    run = (corner + np.arange(end - corner + 1)) % len(contour)
    editor.scale(1.2, 0.9, knots=[(0, int(i)) for i in run])
    assert editor.status_level == "info", editor.status_message
    return editor


@pytest.fixture(scope="module")
def traced():
    d = sc.trace(datasets.thesis_object("D"))
    return {"D": d, "E": _edited(d), "o": from_knots([
        np.array([[20, 10], [60, 30], [20, 50], [-20, 30]], float) + 30,
        (np.array([[20, 22], [36, 30], [20, 38], [4, 30]], float) + 30, [True] * 4)])}


@pytest.fixture(scope="module")
def built(traced, tmp_path_factory):
    return font.build(traced, family="Test Sans", output_dir=tmp_path_factory.mktemp("font"), units_per_em=1000,
                      ascender=800, descender=-200)


def _samples(curves, per_piece=40):
    theta = np.linspace(0, 1, per_piece)
    one = 1 - theta
    weights = np.stack([one ** 3, 3 * one * one * theta, 3 * one * theta * theta, theta ** 3], axis=1)
    return np.concatenate([np.einsum("sk,pkd->psd", weights, b).reshape(-1, 2) for b in curves])


def _recorded_curves(ttfont, name):
    """Contours of a compiled glyph as cubic Bézier arrays (quadratic pieces raised exactly)."""
    pen = DecomposingRecordingPen(ttfont.getGlyphSet())
    ttfont.getGlyphSet()[name].draw(pen)
    collector = font._BezierPen()
    for operator, arguments in pen.value:
        getattr(collector.pen, operator)(*arguments)
    return collector.contours


def _hausdorff(a, b):
    """Symmetric distance between two densely sampled outlines (samples <= 0.4 units apart: error <= 0.2)."""
    return max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max())


def test_build_writes_ufo_otf_and_ttf(built):
    assert built.ufo.is_dir() and built.otf.is_file() and built.ttf.is_file()
    assert set(built.paths) == {"ufo", "otf", "ttf"}
    import ufoLib2

    ufo = ufoLib2.Font.open(built.ufo)
    assert {"D", "o", "space", ".notdef"} <= set(ufo.keys())
    assert ufo["D"].unicodes == [ord("D")] and ufo.info.unitsPerEm == 1000
    otf, ttf = TTFont(built.otf), TTFont(built.ttf)
    assert "CFF " in otf and "glyf" in ttf
    assert otf.getBestCmap()[ord("D")] == "D" and ttf.getBestCmap()[ord("o")] == "o"


@pytest.mark.parametrize("kind", ["otf", "ttf"])
def test_compiled_glyphs_match_the_outline_within_one_font_unit(traced, built, kind):
    compiled = TTFont(getattr(built, kind))
    for key, source in traced.items():
        expected, _ = font.font_contours(source, scale=built.scale, sidebearing=50)
        got = _recorded_curves(compiled, key)
        assert len(got) == len(expected)
        assert _hausdorff(_samples(got, 1500), _samples(expected, 1500)) <= 1.0


def test_winding_follows_each_format(traced, built):
    """Outer contour counter-clockwise (y up) in CFF and the UFO, clockwise in TrueType; the hole opposite."""
    for kind, outer_sign in (("otf", 1), ("ttf", -1)):
        curves = _recorded_curves(TTFont(getattr(built, kind)), "D")
        areas = sorted((bezier_signed_area(c) for c in curves), key=abs, reverse=True)
        assert np.sign(areas[0]) == outer_sign and np.sign(areas[1]) == -outer_sign


@pytest.mark.parametrize("kind", ["otf", "ttf"])
def test_compiled_glyph_rendered_by_freetype_matches_the_outline(traced, built, kind):
    """Rasterize the compiled 'D' with FreeType (fontTools' FreeTypePen, nonzero rule, no hinting) at 1 px =
    4 font units, and the outline with PIL (even-odd); the pixels that differ lie within 1 px + 1 unit of the
    outline, and the ink areas agree. Both renders are shifted by a quarter pixel: an edge of the outline on a
    pixel boundary (a traced pixel corner lies on one, and its sides run along it) is a tie that the two
    rasterizers break the opposite ways (FreeType: coverage above one half; PIL: the polygon's edge pixels are
    in), one column of pixels along the whole side."""
    from fontTools.pens.freetypePen import FreeTypePen

    units_per_px, size, shift = 4.0, 260, 0.25
    compiled = TTFont(getattr(built, kind))
    pen = FreeTypePen(compiled.getGlyphSet())
    compiled.getGlyphSet()["D"].draw(pen)
    # font units -> pixels: x / 4, y flipped with the baseline on row 220, both shifted
    rendered = pen.array(width=size, height=size,
                         transform=(1 / units_per_px, 0, 0, 1 / units_per_px, shift, 40 - shift)) > 0.5
    curves, _ = font.font_contours(traced["D"], scale=built.scale, sidebearing=50)
    mask = np.zeros((size, size), bool)
    for bezier in curves:  # even-odd: every contour flips the pixels it covers
        polygon = _samples([bezier], 60) / units_per_px * [1, -1] + [shift, 220 + shift]
        layer = Image.new("1", (size, size), 0)
        ImageDraw.Draw(layer).polygon([tuple(p) for p in polygon], fill=1)
        mask ^= np.asarray(layer)
    assert mask.sum() > 5000
    differ = np.argwhere(rendered != mask)[:, ::-1] + 0.5
    boundary = np.concatenate([_samples([b], 200) / units_per_px * [1, -1] + [shift, 220 + shift] for b in curves])
    assert differ.size and cKDTree(boundary).query(differ)[0].max() <= 1.0 + 1.0 / units_per_px
    assert abs(int(rendered.sum()) - int(mask.sum())) < 0.01 * mask.sum()


def test_glyph_outline_reads_an_installed_font_and_round_trips_through_a_built_font(tmp_path):
    glyph = font.glyph_outline(DEJAVU, "o")
    assert len(glyph) == 2 and glyph.name == "o" and glyph.baseline is not None
    files = font.build({"o": glyph}, family="Round Trip", output_dir=tmp_path, scale=1.0,
                       units_per_em=2048, ascender=1901, descender=-483, sidebearing=0)
    original = TTFont(font._resolve_font(DEJAVU))
    reference = _recorded_curves(original, "o")
    low = min(float(c[..., 0].min()) for c in reference)
    for kind in ("otf", "ttf"):
        again = _recorded_curves(TTFont(getattr(files, kind)), "o")
        shifted = [c - [low, 0] for c in reference]
        assert _hausdorff(_samples(again, 1500), _samples(shifted, 1500)) <= 1.0


def test_glyph_outline_by_path_name_and_code_point():
    path = font._resolve_font(DEJAVU)
    by_char = font.glyph_outline(path, "A")
    assert np.array_equal(by_char.contours[0].bezier(), font.glyph_outline(path, 0x41).contours[0].bezier())
    assert np.array_equal(by_char.contours[0].bezier(), font.glyph_outline(path, "A").contours[0].bezier())
    assert font.glyph_outline(path, "eight").name == "eight"


def test_glyph_outline_errors(tmp_path):
    with pytest.raises(ValueError, match="no glyph for"):
        font.glyph_outline(DEJAVU, "\uE000")
    with pytest.raises(ValueError, match="no glyph named"):
        font.glyph_outline(DEJAVU, "no-such-glyph")
    with pytest.raises(ValueError, match="no closed contours"):
        font.glyph_outline(DEJAVU, " ")
    broken = tmp_path / "broken.ttf"
    broken.write_bytes(b"not a font at all")
    with pytest.raises(ValueError, match="cannot read the font file"):
        font.glyph_outline(broken, "a")
    with pytest.raises(FileNotFoundError, match="no font file"):
        font.glyph_outline(tmp_path / "missing.ttf", "a")
    with pytest.raises(ValueError, match="no installed font family"):
        font.glyph_outline("No Such Family Anywhere", "a")


def test_build_argument_errors(traced, tmp_path):
    with pytest.raises(ValueError, match="non-empty dict"):
        font.build({}, output_dir=tmp_path)
    with pytest.raises(ValueError, match="ascender"):
        font.build(traced, output_dir=tmp_path, ascender=-5)
    with pytest.raises(ValueError, match="glyph key"):
        font.build({"two words": traced["o"]}, output_dir=tmp_path)
    with pytest.raises(TypeError, match=r"glyphs\['x'\]"):
        font.build({"x": 42}, output_dir=tmp_path)


def test_to_glyph_gives_a_ufo_glyph_with_the_advance(traced):
    glyph = font.to_glyph(traced["o"], "o", scale=2.0, sidebearing=10)
    low, high = traced["o"].bounds()
    assert glyph.unicodes == [ord("o")] and glyph.width == round((high[0] - low[0]) * 2 + 20)
    assert len(glyph.contours) == 2


def test_reading_a_glyph_closes_its_font_file(tmp_path):
    """``glyph_outline`` opens the font lazily (tables are read on demand) and closes it before it returns,
    after a glyph as after an error, also when fontTools fails half way through a damaged file: no
    ResourceWarning of an unclosed file once the objects are collected."""
    import gc
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ResourceWarning)
        outline = font.glyph_outline(DEJAVU, "o")
        with pytest.raises(ValueError, match="no glyph named"):
            font.glyph_outline(DEJAVU, "no-such-glyph")
        broken = tmp_path / "broken.ttf"
        broken.write_bytes(b"\x00\x01\x00\x00" + b"\xff" * 60)
        with pytest.raises(ValueError, match="cannot read the font file"):
            font.glyph_outline(broken, "o")
        gc.collect()
    assert outline.contours
    assert not [w for w in caught if issubclass(w.category, ResourceWarning)], [str(w.message) for w in caught]


@pytest.mark.parametrize("code", [-1, 0x110000, 10**30])
def test_a_code_point_out_of_range_is_named(code):
    """glyph_outline(font, -1) said "chr() arg not in range(0x110000)" (10**30: an OverflowError about C ints);
    to_glyph(..., unicode=-1) said 'is U+-001'. Both name the value and the range now."""
    with pytest.raises(ValueError) as caught:
        font.glyph_outline(DEJAVU, code)
    assert str(caught.value) == f"char = {code} is not a code point (0 .. 0x10FFFF)"
    square = from_knots([(np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float), [True] * 4)])
    with pytest.raises(ValueError) as caught:
        font.to_glyph(square, "a", unicode=code)
    shown = "negative" if code < 0 else f"U+{code:04X}"
    assert str(caught.value).startswith(f"unicode={code} is {shown}, not a Unicode character a font can map")


def test_a_glyph_named_by_its_outline_says_whose_name_it_is():
    """to_glyph(outline) of an outline named 'my shape' said "glyph key 'my shape' must be a single character or a
    glyph name", a key the caller never gave; an outline name of only white space was taken at all."""
    from splinecraft.outline import Outline

    square = from_knots([(np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float), [True] * 4)])
    named = Outline(square.contours, name="my shape")
    with pytest.raises(ValueError) as caught:
        font.to_glyph(named)
    assert str(caught.value).startswith("the outline's name 'my shape' is not a single character or a glyph name: "
                                        "pass name=")
    assert font.to_glyph(named, "a").name == "a"
    assert font.to_glyph(Outline(square.contours, name="A")).unicodes == [ord("A")]
    assert font.to_glyph(Outline(square.contours, name="")).name == "glyph"
    with pytest.raises(ValueError, match=r"^name is blank \(' ': only white space\): give a name, or None"):
        Outline(square.contours, name=" ")


def _nested_squares_font(path, *, same_turn):
    """A TrueType font whose glyph A is a square with a smaller square inside, of the same turn (nonzero: ink
    inside, as overlapping components leave) or of the opposite turn (a hole)."""
    from line_fonts import line_font

    squares = [[(x0, y0), (x1, y0), (x1, y1), (x0, y1)][::turn]
               for x0, y0, x1, y1, turn in ((100, 0, 700, 600, 1), (300, 200, 500, 400, 1 if same_turn else -1))]
    return line_font(path, "A", 0x41, squares, 800, family="Nested")


@pytest.mark.parametrize("same_turn", [True, False])
def test_glyph_outline_fills_by_the_fonts_nonzero_rule(tmp_path, same_turn):
    """A contour inside another of the same turn adds no ink under the nonzero rule (fontTools' PointInsidePen
    says where the source has ink): it is left out, not read as a hole; one of the opposite turn is a hole."""
    from fontTools.pens.pointInsidePen import PointInsidePen

    source = _nested_squares_font(tmp_path / "nested.ttf", same_turn=same_turn)
    glyph_set = TTFont(str(source)).getGlyphSet()
    probe = PointInsidePen(glyph_set, (400, 300), evenOdd=False)
    glyph_set["A"].draw(probe)
    outline = font.glyph_outline(source, "A")
    assert len(outline) == (1 if probe.getResult() else 2) and probe.getResult() is same_turn
    files = font.build({"A": outline}, family="Nested Again", output_dir=tmp_path / "out", scale=1.0,
                       sidebearing=100)
    again = TTFont(str(files.ttf)).getGlyphSet()
    probe = PointInsidePen(again, (400, 300), evenOdd=False)
    again[TTFont(str(files.ttf)).getBestCmap()[0x41]].draw(probe)
    assert probe.getResult() is same_turn


@pytest.mark.parametrize("key", ["\uffff", "\ufffe", "\ufdd0", "\U0001ffff"])
def test_noncharacters_are_refused_as_glyph_keys(traced, tmp_path, key):
    """U+FFFF is also the end of every format-4 cmap: mapped to a glyph it made two overlapping end segments."""
    with pytest.raises(ValueError, match="noncharacter"):
        font.build({key: traced["D"]}, output_dir=tmp_path)
