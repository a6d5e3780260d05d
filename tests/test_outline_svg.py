"""Outlines from SVG: the project's own files, potrace's form (groups with transforms, relative commands),
and refusals naming the subpath."""
import numpy as np
import pytest

from splinecraft.outline import Outline, as_outline, from_svg

# potrace's SVG layout: a group flipping y and scaling by 1/10, relative cubic and line commands
POTRACE_SVG = """<?xml version="1.0" standalone="no"?>
<svg version="1.0" xmlns="http://www.w3.org/2000/svg" width="40.000000pt" height="30.000000pt"
 viewBox="0 0 40.000000 30.000000" preserveAspectRatio="xMidYMid meet">
<g transform="translate(0.000000,30.000000) scale(0.100000,-0.100000)" fill="#000000" stroke="none">
<path d="M100 250 c0 -20 20 -40 40 -40 l160 0 c20 0 40 20 40 40 l0 -200 -240 0 z
m60 -60 l0 -100 100 0 0 100 z"/>
</g>
</svg>
"""


def test_potrace_style_svg_is_read_in_the_document_frame():
    outline = from_svg(POTRACE_SVG)
    assert len(outline) == 2 and (outline.width, outline.height) == (40.0, 30.0)
    first = outline.contours[0].bezier()
    # M100 250 -> (10, 30 - 25); the first cubic ends at (100 + 40, 250 - 40) -> (14, 9)
    assert np.allclose(first[0, 0], [10.0, 5.0])
    assert np.allclose(first[0, 3], [14.0, 9.0])
    hole = outline.contours[1].bezier()
    assert np.allclose(hole[0, 0], [16.0, 11.0])  # relative m after z starts from the previous start
    assert outline.contours[1].corners.all()  # a square of lines: every knot a corner


def test_bare_path_data_and_files(tmp_path):
    d = "M 0,0 C 10,0 20,10 20,20 L 0,20 Z"
    outline = as_outline(d)
    assert len(outline.contours[0]) >= 3  # two pieces are split so that the contour has three knots
    assert np.allclose(outline.contours[0].bezier()[0, 0], [0, 0])
    path = tmp_path / "shape.svg"
    path.write_text(outline.to_svg(decimals=None))
    again = as_outline(path)
    assert np.abs(again.contours[0].bezier() - outline.contours[0].bezier()).max() < 1e-9


@pytest.mark.parametrize("d, message", [
    ("M 0,0 L 10,0 L 10,10 Z M 20,20 A 5 5 0 0 1 30,30 Z", "subpath 1 uses an elliptical arc"),
    ("M 0,0 Q 10,0 10,10 Z", "subpath 0 uses a quadratic"),
    ("M 0,0 L 10,0 L 10,10 Z M 20,20 L 30,20 L 30,30", "subpath 1 is not closed"),
])
def test_arcs_and_open_subpaths_are_refused_naming_the_subpath(d, message):
    with pytest.raises(ValueError, match=message):
        from_svg(d)


def test_open_subpaths_can_be_closed_with_a_line():
    outline = from_svg("M 0,0 L 10,0 L 10,10", close_open=True)
    assert np.allclose(outline.contours[0].bezier()[-1, 3], [0, 0])
    assert len(outline.contours[0]) == 3


def test_missing_files_and_broken_documents():
    with pytest.raises(FileNotFoundError, match="no SVG file"):
        from_svg("no/such/file.svg")
    with pytest.raises(ValueError, match="not a readable SVG"):
        from_svg("<svg><path d='M 0 0'></svg>")
    with pytest.raises(ValueError, match="<rect>"):
        from_svg('<svg xmlns="http://www.w3.org/2000/svg"><rect width="3" height="4"/></svg>')
    with pytest.raises(ValueError, match="no path"):
        from_svg('<svg xmlns="http://www.w3.org/2000/svg"></svg>')


def test_outline_json_files_are_recognised(tmp_path):
    outline = from_svg("M 0,0 L 10,0 L 10,10 L 0,10 Z")
    path = tmp_path / "shape.json"
    path.write_text(outline.to_json())
    assert isinstance(as_outline(path), Outline)
    assert np.array_equal(as_outline(str(path)).contours[0].bezier(), outline.contours[0].bezier())


@pytest.mark.parametrize("d", ["M0 0 L1e1 0 L10 10 Z", "M0,0 L10,0 L10,10 L1E-5,10 Z", "M0 0 L1e+1 0 L10 1.5e1z"])
def test_numbers_with_exponents_are_numbers(d):
    outline = from_svg(d)
    assert np.allclose(outline.contours[0].bezier()[0, 3], [10.0, 0.0])


def test_the_exact_export_with_exponents_is_read_back():
    outline = from_svg("M 1e-05,0 L 10,3.3333e-06 L 10,10 Z")
    text = outline.to_svg(decimals=None)
    assert "e-0" in text
    again = from_svg(text)
    assert np.abs(again.contours[0].bezier() - outline.contours[0].bezier()).max() < 1e-12


def test_file_names_starting_with_m_are_files_and_path_data_is_path_data(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    outline = from_svg("M0 0 L10 0 L10 10 Z")
    outline.save_svg("moon.svg")
    (tmp_path / "Moon.json").write_text(outline.to_json())
    for name in ("moon.svg", "Moon.json"):
        assert np.abs(as_outline(name).contours[0].bezier() - outline.contours[0].bezier()).max() < 1e-3
    with pytest.raises(FileNotFoundError, match="no SVG file 'missing.svg'"):
        from_svg("missing.svg")
    with pytest.raises(FileNotFoundError, match="no JSON file 'missing.json'"):
        as_outline("missing.json")
    assert len(as_outline("m 0 0 l 10 0 l 0 10 z").contours) == 1


def _smooth_contours():
    from splinecraft.outline import Contour

    rng = np.random.default_rng(7)
    for _ in range(12):
        angles = np.sort(rng.uniform(0, 2 * np.pi, 6))
        radii = rng.uniform(20, 60, 6)
        yield Contour(np.c_[radii * np.cos(angles), radii * np.sin(angles)] + 70)


@pytest.mark.parametrize("decimals", [2, 4])
def test_the_rounded_svg_export_keeps_smooth_knots_smooth(decimals):
    """Rounding to ``decimals`` bends every G¹ joint a little; the reader takes the written precision into
    account: smooth knots come back smooth, within a few roundings of the exported curve."""
    kept = total = 0
    for contour in _smooth_contours():
        outline = Outline([contour])
        again = from_svg(outline.to_svg(decimals=decimals))
        kept += int((~again.contours[0].corners).sum())
        total += len(contour)
        assert np.abs(again.contours[0].bezier() - contour.bezier()).max() <= 10 ** -decimals * 8
    assert kept >= 0.75 * total  # before: none (every knot bent by the rounding became a corner)


@pytest.mark.parametrize("decimals", [2, 4])
def test_the_rounded_svg_export_keeps_corners(decimals):
    """Kinks of 2 and 10 degrees (bigger than the rounding can make) stay corners."""
    from splinecraft.outline import Contour

    for degrees in (2.0, 10.0):
        turn = np.radians(degrees)
        points = np.array([[0, 0], [60, 0], [90, 40], [40, 80], [-20, 40]], float) + 50
        out = 20 * np.array([np.cos(turn), np.sin(turn)])
        contour = Contour(points, [True, False, False, False, False], handles_in=[[-20, 0]] + [[0, 0]] * 4,
                          handles_out=[out] + [[0, 0]] * 4)
        again = from_svg(Outline([contour]).to_svg(decimals=decimals))
        assert again.contours[0].corners[0]
        assert (~again.contours[0].corners[1:]).all()


def test_a_title_xml_cannot_hold_is_refused():
    outline = from_svg("M0 0 L10 0 L10 10 Z")
    with pytest.raises(ValueError, match="U\\+0001"):
        outline.to_svg(title="bad\x01title")
    assert "<title>é &amp; co</title>" in outline.to_svg(title="é & co")
