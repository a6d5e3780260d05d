"""Fonts, the export/import audit: composite and CFF glyphs read, the curves' (not the control points') box
places a glyph, straight edges stay lines in every format, and ``build`` refuses what it cannot write before
writing anything, with the naming and style fields of a linked family."""
import math
import re
from pathlib import Path

import numpy as np
import pytest
from fontTools.pens.boundsPen import BoundsPen
from fontTools.pens.recordingPen import DecomposingRecordingPen, RecordingPen
from fontTools.ttLib import TTFont

from splinecraft import font
from splinecraft.outline import Outline, from_bezier, from_svg
from splinecraft.outline.contour import Contour

SQUARE = "M0 0 L100 0 L100 100 L0 100 Z"


def _system_font(*parts):
    path = Path("/usr/share/fonts", *parts)
    if not path.is_file():
        pytest.skip(f"{path} is not installed")
    return path


@pytest.fixture
def dejavu_sans():
    return _system_font("truetype", "dejavu", "DejaVuSans.ttf")


@pytest.fixture
def eb_garamond():
    return _system_font("opentype", "ebgaramond", "EBGaramond12-Regular.otf")


def _curve_box(path, name):
    compiled = TTFont(path)
    pen = BoundsPen(compiled.getGlyphSet())
    compiled.getGlyphSet()[name].draw(pen)
    return pen.bounds, compiled["hmtx"][name][0]


# ---------------------------------------------------------------------------------------------- reading
def test_composite_truetype_glyphs_are_decomposed(dejavu_sans):
    ttfont = TTFont(dejavu_sans)
    name = ttfont.getBestCmap()[ord("é")]
    assert ttfont["glyf"][name].isComposite()
    glyph = font.glyph_outline(dejavu_sans, "é")
    recorded = DecomposingRecordingPen(ttfont.getGlyphSet())
    ttfont.getGlyphSet()[name].draw(recorded)
    reference = font._BezierPen()
    recorded.replay(reference.pen)
    ascender = ttfont["hhea"].ascent
    assert len(glyph) == len(reference.contours) == 3
    for contour, expected in zip(glyph.contours, reference.contours):
        got = contour.bezier() * [1, -1] + [0, ascender]  # back to y up
        assert np.abs(got - expected).max() < 1e-9


def test_a_cff_contour_ending_a_rounding_away_from_its_start_is_read(eb_garamond):
    glyph = font.glyph_outline(eb_garamond, "uni20D3")  # its end is 1.5e-5 units from its start
    assert len(glyph) >= 1


def test_the_pen_closes_a_rounding_gap_by_snapping_and_a_real_gap_with_a_line():
    collector = font._BezierPen()
    pen = collector.pen
    for end, pieces in (((1.5e-5, 0.0), 3), ((0.0, 5.0), 4)):
        pen.moveTo((0, 0))
        pen.lineTo((100, 0))
        pen.curveTo((100, 60), (40, 100), (0, 100))
        pen.lineTo(end)
        pen.closePath()
        contour = collector.contours[-1]
        assert len(contour) == pieces and np.array_equal(contour[-1, 3], [0.0, 0.0])
    assert len(from_bezier(collector.contours)) == 2


# ---------------------------------------------------------------------------------------------- placement
def test_the_curve_box_not_the_control_box_places_and_scales_the_glyph(tmp_path):
    """A drop whose left handles reach 40 units past its tip: side bearings, baseline and the default
    scale (tallest curve box = ascender) hold for the curves."""
    drop = from_bezier([np.array([[[0, 50], [-40, 0], [100, 0], [100, 50]],
                                  [[100, 50], [100, 100], [-40, 100], [0, 50]]], float)])
    curves, advance = font.font_contours(drop, scale=8.0, sidebearing=50)
    low = np.min([c[..., 0].min() for c in curves])
    assert low < 0  # the handles reach past the side bearing, the curve does not
    files = font.build({"o": drop}, output_dir=tmp_path, sidebearing=50)
    for kind in ("otf", "ttf"):
        (x_min, y_min, x_max, y_max), width = _curve_box(getattr(files, kind), "o")
        assert abs(x_min - 50) <= 1 and abs(width - x_max - 50) <= 1
        assert abs(y_min) <= 1 and abs(y_max - 800) <= 1


def test_straight_edges_are_lines_in_the_ufo_as_in_the_compiled_fonts(tmp_path):
    triangle = from_svg("M0 0 L100 0 L50 71 Z")
    recorded = RecordingPen()
    font.to_glyph(triangle, "a", scale=1.0).draw(recorded)
    assert [op for op, _ in recorded.value] == ["moveTo", "lineTo", "lineTo", "closePath"]
    import ufoLib2

    files = font.build({"a": triangle}, output_dir=tmp_path, scale=1.0)
    ufo = RecordingPen()
    ufoLib2.Font.open(files.ufo)["a"].draw(ufo)
    for kind in ("otf", "ttf"):
        compiled = TTFont(getattr(files, kind))
        pen = RecordingPen()
        compiled.getGlyphSet()["a"].draw(pen)
        assert {op for op, _ in pen.value} <= {"moveTo", "lineTo", "closePath"}
    assert {op for op, _ in ufo.value} <= {"moveTo", "lineTo", "closePath"}


def test_a_straight_cubic_that_overshoots_its_end_stays_a_curve():
    # its handles lie on its chord's line but one lies beyond the end: the cubic runs 0 -> 17.8 -> 10 along x,
    # which a lineTo(10, 0) would cut short; the drop's spike below keeps it
    outline = from_svg("M0 0 C30 0 20 0 10 0 L10 -40 Z")
    recorded = RecordingPen()
    font.to_glyph(outline, "a", scale=1.0).draw(recorded)
    assert [op for op, _ in recorded.value][:2] == ["moveTo", "curveTo"]
    triangle = RecordingPen()
    font.to_glyph(from_svg("M0 0 C3 0 7 0 10 0 L10 -40 Z"), "b", scale=1.0).draw(triangle)  # within the chord
    assert [op for op, _ in triangle.value] == ["moveTo", "lineTo", "lineTo", "closePath"]


def test_win_ascent_covers_the_rounded_glyph(tmp_path):
    files = font.build({"a": from_svg(SQUARE)}, output_dir=tmp_path, scale=8.006)  # top at 800.6 units
    for kind in ("otf", "ttf"):
        compiled = TTFont(getattr(files, kind))
        (_, y_min, _, y_max), _ = _curve_box(getattr(files, kind), "a")
        assert compiled["OS/2"].usWinAscent >= math.ceil(y_max) == 801
        assert compiled["OS/2"].usWinDescent >= -math.floor(y_min)


# ---------------------------------------------------------------------------------------------- build
def test_a_glyph_named_space_is_the_space_and_agl_names_get_their_code_points(tmp_path):
    square = from_svg(SQUARE)
    files = font.build({"a": square, "space": square.scale(0.1), "eacute": square}, output_dir=tmp_path)
    cmap = TTFont(files.otf).getBestCmap()
    assert cmap[0x20] == "space" and cmap[0xE9] == "eacute" and cmap[ord("a")] == "a"


@pytest.mark.parametrize("glyphs, options, message", [
    ({"a": Outline([Contour(np.array([[0, 0], [50, 0], [100, 0]], float))])}, {}, "zero height"),
    ({"é": from_svg(SQUARE), "eacute": from_svg(SQUARE)}, {}, r"both the glyph 'eacute'"),
    ({"A": from_svg(SQUARE), "uni0041": from_svg(SQUARE)}, {}, "both map U\\+0041"),
    ({"a": from_svg(SQUARE)}, {"scale": 400}, "16-bit range"),
    ({"a": from_svg("M0 0 C 300 -900 700 900 1000 0 L 1000 500 Z")}, {"ttf_max_error": 1e-6}, "ttf_max_error"),
])
def test_build_refuses_what_it_cannot_write_before_writing(tmp_path, glyphs, options, message):
    with pytest.raises(ValueError, match=message):
        font.build(glyphs, output_dir=tmp_path / "out", **options)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("style, fs_selection, mac_style, weight, family", [
    ("Regular", 0x40, 0, 400, "Test Sans"),
    ("Bold", 0x20, 1, 700, "Test Sans"),
    ("Italic", 0x01, 2, 400, "Test Sans"),
    ("Bold Italic", 0x21, 3, 700, "Test Sans"),
    ("Light", 0x40, 0, 300, "Test Sans Light"),
])
def test_names_and_style_linking(tmp_path, style, fs_selection, mac_style, weight, family):
    files = font.build({"a": from_svg(SQUARE)}, family="Test Sans", style=style, output_dir=tmp_path)
    for kind in ("otf", "ttf"):
        compiled = TTFont(getattr(files, kind))
        names = compiled["name"]
        assert {1, 2, 3, 4, 6} <= {record.nameID for record in names.names}
        assert names.getDebugName(1) == family and names.getDebugName(4) == f"Test Sans {style}"
        assert compiled["OS/2"].fsSelection == fs_selection and compiled["head"].macStyle == mac_style
        assert compiled["OS/2"].usWeightClass == weight


def test_a_truetype_plus_of_overlapping_contours_keeps_its_centre(tmp_path):
    """A TrueType "+" whose second contour starts at a point inside the first: the font fills the overlap by the
    nonzero rule, and so do the rebuilt OTF and TTF (both bars outer, the same direction), not a hole."""
    from fontTools.pens.pointInsidePen import PointInsidePen
    from line_fonts import line_font

    line_font(tmp_path / "plus.ttf", "plus", ord("+"), [[(0, 40), (0, 80), (200, 80), (200, 40)],
                                                        [(80, 60), (80, 200), (120, 200), (120, 0), (80, 0)]], 300,
              family="Plus")

    def winding(path, point):
        ttfont = TTFont(path)
        inside = PointInsidePen(ttfont.getGlyphSet(), point)
        ttfont.getGlyphSet()["plus"].draw(inside)
        return inside.getWinding()

    assert winding(tmp_path / "plus.ttf", (100, 60)) != 0
    outline = font.glyph_outline(tmp_path / "plus.ttf", "+")
    files = font.build({"+": outline}, output_dir=tmp_path / "out", scale=1.0, sidebearing=0)
    for kind in ("otf", "ttf"):
        assert abs(winding(getattr(files, kind), (100, 60))) == 2
        assert abs(winding(getattr(files, kind), (100, 20))) == 1 and winding(getattr(files, kind), (20, 20)) == 0
    assert outline.nesting_depths().tolist() == [0, 0]


@pytest.mark.parametrize("options, error, words", [
    ({"style": None}, TypeError, "style must be a non-empty string"),
    ({"style": "  "}, ValueError, "style must be a non-empty string"),
    ({"family": None}, TypeError, "family must be a non-empty string"),
    ({"units_per_em": 5}, ValueError, "units_per_em must be >= 16.*16 to 16384"),
    ({"units_per_em": 100_000}, ValueError, "units_per_em must be <= 16384"),
    ({"units_per_em": math.nan}, TypeError, "units_per_em must be an integer"),
    ({"ascender": math.nan}, ValueError, "ascender must be a finite number"),
    ({"ascender": 10**6}, ValueError, "ascender must be > 0 and <= 32767"),
    ({"descender": math.nan}, ValueError, "descender must be a finite number"),
    ({"descender": -10**6}, ValueError, "descender must be >= -32768"),
    ({"sidebearing": math.nan}, ValueError, "sidebearing must be a finite number"),
    ({"glyphs": {"\ud800": from_svg(SQUARE)}}, ValueError, "U\\+D800, not a Unicode character"),
    ({"family": "Bad\x00Name"}, ValueError, r"family 'Bad\\x00Name' holds U\+0000 at index 3"),
    ({"style": "Bold\tItalic"}, ValueError, r"style 'Bold\\tItalic' holds U\+0009 at index 4"),
    ({"family": "Two\u2028Lines"}, ValueError, r"family .* holds U\+2028"),
    ({"family": "Sans\x85"}, ValueError, r"family .* holds U\+0085"),
    ({"family": "Sans\ud800"}, ValueError, r"family .* holds U\+D800"),
    ({"style": "Regular\uffff"}, ValueError, r"style .* holds U\+FFFF"),
])
def test_build_names_a_bad_argument_and_its_range_before_writing(tmp_path, options, error, words):
    options = {"glyphs": {"a": from_svg(SQUARE)}, **options}
    with pytest.raises(error, match=words):
        font.build(output_dir=tmp_path / "out", **options)
    assert not (tmp_path / "out").exists()


def test_to_glyph_refuses_a_surrogate_code_point_and_a_nan_sidebearing():
    with pytest.raises(ValueError, match="U\\+DFFF"):
        font.to_glyph(from_svg(SQUARE), "a", unicode=0xDFFF)
    with pytest.raises(ValueError, match="sidebearing"):
        font.to_glyph(from_svg(SQUARE), "a", sidebearing=math.nan)


def test_a_scale_that_rounds_a_glyph_flat_warns(tmp_path):
    with pytest.warns(UserWarning, match=r"glyphs\['a'\] is 1e-10 x 1e-10 font units at scale=1e-12"):
        files = font.build({"a": from_svg(SQUARE)}, output_dir=tmp_path, scale=1e-12)
    assert files.otf.exists()
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        font.build({"a": from_svg(SQUARE)}, output_dir=tmp_path, scale=0.02)  # 2 units: small, not flat


@pytest.mark.parametrize("key", ["\x00", "\t", "\x7f", "\x85", "uni0009"])
def test_a_control_character_key_is_refused_and_named(tmp_path, key):
    """A glyph key that is (or whose AGL name maps to) a C0 / C1 control character gets no glyph and no cmap
    entry: ``build`` names the key, before writing anything."""
    with pytest.raises(ValueError, match=re.escape(repr(key)) + ".* control character U\\+00"):
        font.build({"a": from_svg(SQUARE), key: from_svg(SQUARE)}, output_dir=tmp_path / "out")
    assert not (tmp_path / "out").exists()
    with pytest.raises(ValueError, match="control character U\\+001F"):
        font.to_glyph(from_svg(SQUARE), "a", unicode=0x1F)


@pytest.mark.parametrize("units_per_em, ascender, descender, warns", [
    (16, 800, -200, True),
    (1000, 800, -2001, True),
    (1000, 2001, -200, True),
    (1000, 2000, -2000, False),
    (2048, 1901, -483, False),
])
def test_metrics_far_outside_the_em_warn_with_the_numbers(tmp_path, units_per_em, ascender, descender, warns):
    """OpenType does not bound the ascender by the em, so metrics beyond twice units_per_em (glyphs several em
    tall: metrics meant for another em) build, with a warning naming the numbers."""
    import warnings

    options = dict(output_dir=tmp_path, units_per_em=units_per_em, ascender=ascender, descender=descender)
    if warns:
        words = f"ascender={ascender} / descender={descender} .*units_per_em={units_per_em}"
        with pytest.warns(UserWarning, match=words):
            files = font.build({"a": from_svg(SQUARE)}, **options)
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            files = font.build({"a": from_svg(SQUARE)}, **options)
    assert TTFont(files.otf)["head"].unitsPerEm == units_per_em


@pytest.mark.parametrize("family, style", [("Łódź Sans", "Regular"), ("日本語", "Light"), ("Test Sans", "標準"),
                                           ("Ünïcödé Sans " * 8, "Extra Bold Italic")])
def test_unicode_names_go_into_the_name_table_and_the_postscript_name_is_ascii(tmp_path, family, style):
    """Names outside Latin-1 build: the name table holds them whole (IDs 1/2 or 16/17, and 4), while the
    PostScript name (ID 6, the CFF FontName) and the CFF's own name strings are printable ASCII."""
    import ufoLib2

    files = font.build({"a": from_svg(SQUARE)}, family=family, style=style, output_dir=tmp_path)
    postscript = set()
    for kind in ("otf", "ttf"):
        names = TTFont(getattr(files, kind))["name"]
        assert names.getDebugName(4) == f"{family} {style}"
        assert (names.getDebugName(16) or names.getDebugName(1)) == family
        assert (names.getDebugName(17) or names.getDebugName(2)) == style
        assert re.fullmatch(r"[A-Za-z0-9-]{1,63}", names.getDebugName(6))
        postscript.add(names.getDebugName(6))
    assert len(postscript) == 1
    cff = TTFont(files.otf)["CFF "].cff
    top = cff.topDictIndex[0]
    assert cff.fontNames == list(postscript)
    assert all(text.isascii() and text.isprintable() for text in (top.FullName, top.FamilyName, top.Weight))
    info = ufoLib2.Font.open(files.ufo).info
    assert (info.familyName, info.styleName, info.postscriptFontName) == (family, style, postscript.pop())


def test_the_postscript_name_spells_latin_letters_in_ascii_and_hashes_other_scripts():
    """NFKD drops the accents (and "Ł" is spelled "L"); a name with no ASCII letter gets a stable hash of the
    whole name, different for different names."""
    assert font._postscript_name("Łódź Sans", "Regular") == "LodzSans-Regular"
    assert font._postscript_name("Café Noir", "Bold") == "CafeNoir-Bold"
    japanese, chinese = font._postscript_name("日本語", "Regular"), font._postscript_name("中文", "Regular")
    assert japanese.startswith("Splinecraft") and chinese.startswith("Splinecraft") and japanese != chinese
    assert japanese == font._postscript_name("日本語", "Regular")


def _snapshot(folder):
    """Every path under ``folder`` (hidden ones too) with its bytes (files) and modification time."""
    return {path.relative_to(folder).as_posix(): (path.read_bytes() if path.is_file() else None,
                                                  path.stat().st_mtime_ns)
            for path in sorted(folder.rglob("*"))}


def _fail_on(suffix, folder=None):
    """A stand-in for a writer or mover (``(self_or_source, destination_or_data)``) that raises ``OSError`` the
    first time its destination ends with ``suffix`` (and, with ``folder``, lies directly in it), and else calls
    the real one."""
    failed = []

    def wrap(real):
        def writer(first, second=None, *args, **kwargs):
            destination = Path(second if isinstance(second, (str, Path)) else first)
            if destination.name.endswith(suffix) and (folder is None or destination.parent == folder) and not failed:
                failed.append(destination)
                raise OSError(f"simulated failure writing {destination.name}")
            return real(first, second, *args, **kwargs) if second is not None else real(first, *args, **kwargs)
        return writer
    return wrap


@pytest.mark.parametrize("failure", ["ufo save", "otf write", "ttf write", "ufo swap", "ttf replace"])
def test_a_failing_write_leaves_the_previous_outputs_as_they_were(tmp_path, monkeypatch, failure):
    """Outputs are written all or nothing: a save, write or move failing at any step leaves the previous UFO,
    OTF and TTF with their bytes and times, and no temporary file; without the failure the same build
    replaces them."""
    import ufoLib2

    square = from_svg(SQUARE)
    first = font.build({"a": square}, family="Test Sans", output_dir=tmp_path)
    before = _snapshot(tmp_path)
    with monkeypatch.context() as patch:
        if failure == "ufo save":
            def save(self, *args, **kwargs):
                raise OSError("simulated failure saving the UFO")
            patch.setattr(ufoLib2.Font, "save", save)
        elif failure.endswith("write"):
            patch.setattr(Path, "write_bytes", _fail_on("." + failure.split()[0])(Path.write_bytes))
        elif failure == "ufo swap":
            patch.setattr(font.os, "rename", _fail_on(".ufo", tmp_path)(font.os.rename))
        else:
            patch.setattr(font.os, "replace", _fail_on(".ttf", tmp_path)(font.os.replace))
        with pytest.raises(OSError, match="simulated failure"):
            font.build({"a": square, "b": square}, family="Test Sans", output_dir=tmp_path)
    assert _snapshot(tmp_path) == before
    second = font.build({"a": square, "b": square}, family="Test Sans", output_dir=tmp_path)
    assert second.paths == first.paths and "b" in ufoLib2.Font.open(second.ufo)
    assert sorted(path.name for path in tmp_path.iterdir()) == sorted(path.name for path in first.paths.values())


def test_a_failing_write_into_a_new_folder_leaves_no_folder(tmp_path, monkeypatch):
    monkeypatch.setattr(Path, "write_bytes", _fail_on(".ttf")(Path.write_bytes))
    with pytest.raises(OSError, match="simulated failure"):
        font.build({"a": from_svg(SQUARE)}, output_dir=tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_when_restoring_fails_too_the_rest_is_restored_and_the_kept_files_are_named(tmp_path, monkeypatch):
    """A move that keeps failing (the new TTF cannot replace the old one, nor the old one be put back): the UFO
    and OTF are restored all the same, and the error names the staging folder that keeps the rest."""
    square = from_svg(SQUARE)
    files = font.build({"a": square}, output_dir=tmp_path)
    before = _snapshot(tmp_path)
    real_replace = font.os.replace

    def replace(source, destination):
        if Path(destination) == files.ttf:
            raise OSError("simulated lasting failure")
        return real_replace(source, destination)

    monkeypatch.setattr(font.os, "replace", replace)
    with pytest.raises(OSError, match="restoring the previous ones failed too") as raised:
        font.build({"a": square, "b": square}, output_dir=tmp_path)
    kept = Path(re.search(r"is in '(.+)'$", str(raised.value)).group(1))
    assert kept.parent == tmp_path and kept.is_dir()
    after = _snapshot(tmp_path)
    assert {name: after[name] for name in before} == before
    assert {name for name in after if name not in before} == {name for name in after if name.startswith(kept.name)}


def _family_of_outputs(files):
    """The family name each output of ``files`` holds (UFO info, name IDs 16 or 1 of the fonts)."""
    import ufoLib2

    names = {"ufo": ufoLib2.Font.open(files.ufo).info.familyName}
    for kind in ("otf", "ttf"):
        table = TTFont(getattr(files, kind))["name"]
        names[kind] = table.getDebugName(16) or table.getDebugName(1)
    return names


def test_families_in_other_scripts_get_files_of_their_own(tmp_path):
    """The file stem keeps letters of every script: "日本語" and "中文" do not both become "Font-Regular", and
    the second build leaves the first one's files alone."""
    square = from_svg(SQUARE)
    japanese = font.build({"a": square}, family="日本語", output_dir=tmp_path)
    kept = {name: value for name, value in _snapshot(tmp_path).items()}
    chinese = font.build({"b": square}, family="中文", output_dir=tmp_path)
    assert set(japanese.paths.values()).isdisjoint(chinese.paths.values())
    after = _snapshot(tmp_path)
    assert {name: after[name] for name in kept} == kept
    for files, family in ((japanese, "日本語"), (chinese, "中文")):
        assert all(path.name.startswith(family) for path in files.paths.values())
        assert set(_family_of_outputs(files).values()) == {family}
    assert len(list(tmp_path.iterdir())) == 6


@pytest.mark.parametrize("first, second", [("A/B Sans", "A_B Sans"), ("Test Sans", "TestSans"), ("Font", "..."),
                                           ("x" * 300, "x" * 301)])
def test_names_with_the_same_file_stem_do_not_overwrite_each_other(tmp_path, first, second):
    """Names whose file stems would be equal (a path separator made "_", white space dropped, nothing left, cut
    to a length a file system takes) get a hash of the name appended, the same in every build."""
    square = from_svg(SQUARE)
    built = {family: font.build({"a": square}, family=family, output_dir=tmp_path) for family in (first, second)}
    assert set(built[first].paths.values()).isdisjoint(built[second].paths.values())
    for family, files in built.items():
        assert all(path.parent == tmp_path and len(path.name.encode()) < 255 for path in files.paths.values())
        assert set(_family_of_outputs(files).values()) == {family}
        assert font.build({"a": square}, family=family, output_dir=tmp_path).paths == files.paths
    assert len(list(tmp_path.iterdir())) == 6


def test_a_file_name_holds_no_path_separator_or_character_windows_refuses(tmp_path):
    files = font.build({"a": from_svg(SQUARE)}, family='../a<b>:c"d\\e|f?g*h', style="Bold/Italic",
                       output_dir=tmp_path)
    for path in files.paths.values():
        assert path.parent == tmp_path and not set('<>:"/\\|?*') & set(path.name) and not path.name.startswith(".")
    assert set(_family_of_outputs(files).values()) == {'../a<b>:c"d\\e|f?g*h'}


def test_a_file_that_is_not_a_font_of_that_name_is_not_replaced(tmp_path):
    stranger = tmp_path / "TestSans-Regular.otf"
    stranger.write_bytes(b"not a font")
    files = font.build({"a": from_svg(SQUARE)}, family="Test Sans", output_dir=tmp_path)
    assert stranger.read_bytes() == b"not a font" and files.otf != stranger and files.otf.is_file()


@pytest.mark.parametrize("output_dir, error, words", [
    ("", ValueError, "output_dir is empty: give a folder ('.' for the current one)"),  # Path('') is '.'
    (" ", ValueError, "output_dir is blank (' ': only white space): give a folder ('.' for the current one)"),
    (3, TypeError, "output_dir must be a path (str or os.PathLike), got int"),
])
def test_build_refuses_a_blank_output_folder_before_writing(tmp_path, monkeypatch, output_dir, error, words):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(error) as caught:
        font.build({"a": from_svg(SQUARE)}, output_dir=output_dir)
    assert str(caught.value) == words
    assert list(tmp_path.iterdir()) == []
