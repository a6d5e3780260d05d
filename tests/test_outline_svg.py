"""Outlines from SVG: the project's own files, potrace's form (groups with transforms, relative commands),
and refusals naming the subpath."""
import re

import numpy as np
import pytest

from splinecraft.outline import Outline, as_outline, from_svg
from test_outline import _winding  # the same winding-number reference, one copy

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
    with pytest.raises(ValueError, match="<circle>"):
        from_svg('<svg xmlns="http://www.w3.org/2000/svg"><circle r="3"/></svg>')
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


def _svg(body, attributes='width="20" height="20"'):
    return f'<svg xmlns="http://www.w3.org/2000/svg" {attributes}>{body}</svg>'


SQUARE = '<path d="M0 0 L10 0 L10 10 L0 10 Z"/>'
HIDDEN = '<path d="M100 100 L200 100 L200 200 Z"/>'


@pytest.mark.parametrize("wrapper", [
    "<defs>{}</defs>", "<symbol id='s'>{}</symbol>", "<mask id='m'>{}</mask>", "<clipPath id='c'>{}</clipPath>",
    "<marker id='k'>{}</marker>", "<pattern id='p'>{}</pattern>", "<g display='none'>{}</g>",
    "<g style='fill:red; display : none'><g>{}</g></g>", "<g><path style='display:none' d='M100 100 L200 100 L200 200 Z'/></g>",
])
def test_paths_that_are_never_drawn_are_skipped(wrapper):
    outline = from_svg(_svg(wrapper.format(HIDDEN) + SQUARE))
    assert len(outline) == 1  # before: the hidden triangle came in as a second contour
    assert np.allclose(outline.bounds()[1], [10, 10])
    # the style property overrides the presentation attribute: this one is drawn
    assert len(from_svg(_svg(f'<g display="none" style="display:inline">{HIDDEN}</g>' + SQUARE))) == 2


def test_a_rect_in_a_clip_path_does_not_abort_the_import():
    outline = from_svg(_svg(f'<clipPath id="c"><rect width="20" height="20"/></clipPath>'
                            '<path clip-path="url(#c)" d="M0 0 L10 0 L10 10 L0 10 Z"/>'))
    assert len(outline) == 1 and np.allclose(outline.bounds()[1], [10, 10])


def test_drawn_rects_and_polygons_are_read_as_lines():
    outline = from_svg(_svg('<rect x="1" y="2" width="3" height="4"/><polygon points="10,0 20,0 20,10"/>'
                            '<rect width="0" height="5"/>'))
    assert len(outline) == 2  # the zero-width rect draws nothing
    rect, triangle = (c.bezier() for c in outline.contours)
    assert np.allclose(rect[:, 0], [[1, 2], [4, 2], [4, 6], [1, 6]]) and outline.contours[0].corners.all()
    assert np.allclose(triangle[:, 0], [[10, 0], [20, 0], [20, 10]]) and outline.contours[1].corners.all()


def test_an_open_polyline_is_refused_unless_closed():
    body = '<polyline points="0,0 10,0 10,10"/>'
    with pytest.raises(ValueError, match="<polyline> \\(shape 0\\), subpath 0 is not closed"):
        from_svg(_svg(body))
    assert np.allclose(from_svg(_svg(body), close_open=True).contours[0].bezier()[-1, 3], [0, 0])


@pytest.mark.parametrize("body, message", [
    ('<circle cx="5" cy="5" r="3"/>', "<circle> elements are not converted"),
    ('<ellipse rx="5" ry="3"/>', "<ellipse> elements are not converted"),
    ('<rect width="5" height="5" rx="1"/>', "<rect> with rounded corners"),
    ('<line x2="5" y2="5"/>', "<line> encloses no area"),
    ('<polygon points="0,0 10,0 10"/>', "<polygon> points must be an even count"),
    ('<svg viewBox="0 0 5 5"><path d="M0 0 L10 0 L10 10 Z"/></svg>', "nested <svg> with its own viewBox"),
])
def test_shapes_that_are_not_converted_are_refused_naming_the_element(body, message):
    with pytest.raises(ValueError, match=message):
        from_svg(_svg(body))


@pytest.mark.parametrize("attributes, frame, low, high", [
    ('viewBox="-20 -20 40 40"', (40, 40), (20, 20), (30, 30)),  # the origin is moved
    ('width="200" height="200" viewBox="0 0 20 20"', (200, 200), (0, 0), (100, 100)),  # scaled to the size
    ('width="200" viewBox="0 0 20 40"', (200, 400), (0, 0), (100, 100)),  # the missing side keeps the aspect
    ('width="200" height="100" viewBox="0 0 10 10"', (200, 100), (50, 0), (150, 100)),  # xMidYMid meet
    ('width="200" height="100" viewBox="0 0 10 10" preserveAspectRatio="xMinYMin slice"', (200, 100), (0, 0),
     (200, 200)),
    ('width="200" height="100" viewBox="0 0 10 10" preserveAspectRatio="none"', (200, 100), (0, 0), (200, 100)),
    ('width="80pt" height="30pt" viewBox="0 0 40 30"', (80, 30), (20, 0), (30, 10)),  # print size: viewBox units
    ('width="100%" height="100%" viewBox="5 5 20 20"', (20, 20), (-5, -5), (5, 5)),
])
def test_the_viewbox_maps_the_curves_into_the_frame(attributes, frame, low, high):
    outline = from_svg(_svg('<path d="M0 0 L10 0 L10 10 L0 10 Z"/>', attributes))
    assert np.allclose((outline.width, outline.height), frame)
    assert np.allclose(outline.bounds()[0], low) and np.allclose(outline.bounds()[1], high)
    again = from_svg(outline.to_svg())  # the re-export shows the same picture
    assert np.allclose(again.bounds()[0], low) and np.allclose(again.bounds()[1], high)


def test_physical_sizes_without_a_viewbox_are_px_at_96_dpi_and_other_units_are_refused():
    outline = from_svg(_svg(SQUARE, 'width="10mm" height="1in"'))
    assert np.allclose((outline.width, outline.height), (96 / 2.54, 96))
    assert np.allclose(outline.bounds()[1], [10, 10])  # user units are px
    with pytest.raises(ValueError, match="<svg> width='10em' is not read"):
        from_svg(_svg(SQUARE, 'width="10em" height="10"'))
    with pytest.raises(ValueError, match="viewBox '0 0 10' must be four numbers"):
        from_svg(_svg(SQUARE, 'viewBox="0 0 10"'))


PLUS = "M0 40 L200 40 L200 80 L0 80 Z M80 0 L120 0 L120 200 L80 200 Z"  # two bars, the same direction


def test_a_plus_of_overlapping_bars_keeps_its_centre_under_nonzero():
    """nonzero is the SVG default: the centre of the "+" (winding 2) is ink, and it stays ink after the round
    trip (the export writes fill-rule nonzero with both bars outer)."""
    from splinecraft.capture.svg import read_svg_paths

    outline = from_svg(_svg(f'<path d="{PLUS}"/>', 'width="200" height="200"'))
    document = read_svg_paths(outline.to_svg())
    path, = document["paths"]
    assert path["fill_rule"] == "nonzero"
    curves = [bezier for bezier, _ in path["subpaths"]]
    assert _winding(curves, [100, 60]) != 0 and _winding(curves, [100, 20]) != 0
    assert _winding(curves, [20, 20]) == 0
    assert len(outline) == 2 and outline.nesting_depths().tolist() == [0, 0]
    again = from_svg(outline.to_svg())
    assert _winding(again.oriented_bezier(), [100, 60]) != 0


@pytest.mark.parametrize("attributes", ['fill-rule="evenodd"', 'style="fill:black; fill-rule: evenodd"'])
def test_the_fill_rule_is_read_from_the_path_or_its_group(attributes):
    """A square inside a square drawn the same way: a hole under evenodd (kept, and written as a hole), ink on
    both sides under nonzero (it adds nothing, so it is dropped); the rule is inherited from a group."""
    nested = "M0 0 L100 0 L100 100 L0 100 Z M30 30 L70 30 L70 70 L30 70 Z"
    evenodd = from_svg(_svg(f'<g {attributes}><path d="{nested}"/></g>', 'width="100" height="100"'))
    assert len(evenodd) == 2 and evenodd.nesting_depths().tolist() == [0, 1]
    assert _winding(evenodd.oriented_bezier(), [50, 50]) == 0
    nonzero = from_svg(_svg(f'<path d="{nested}"/>', 'width="100" height="100"'))
    assert len(nonzero) == 1 and _winding(nonzero.oriented_bezier(), [50, 50]) != 0
    # a hole drawn the other way is a hole under both rules
    hole = "M0 0 L100 0 L100 100 L0 100 Z M30 30 L30 70 L70 70 L70 30 Z"
    for rule in ("nonzero", "evenodd"):
        outline = from_svg(_svg(f'<path fill-rule="{rule}" d="{hole}"/>', 'width="100" height="100"'))
        assert len(outline) == 2 and _winding(outline.oriented_bezier(), [50, 50]) == 0


def test_svg_document_refuses_text_xml_cannot_hold_and_xml_safe_replaces_it():
    import xml.etree.ElementTree as ET

    from splinecraft.spline.svg import svg_document, xml_safe

    for field in ("title", "fill", "stroke"):
        with pytest.raises(ValueError, match=f"{field} .*U\\+001B"):
            svg_document("M0 0 L1 1 Z", 2, 2, **{field: "x\x1by"})
    with pytest.raises(ValueError, match="U\\+DCE9"):
        svg_document("M0 0 L1 1 Z", 2, 2, title="caf\udce9")
    assert xml_safe("caf\udce9\x01\tok\n") == "caf\ufffd\ufffd\tok\n"
    ET.fromstring(svg_document("M0 0 L1 1 Z", 2, 2, title=xml_safe("caf\udce9 & \x07")))


@pytest.mark.parametrize("options, words", [
    ({"fill": None}, "fill must be a string"), ({"fill": 5}, "fill must be a string"),
    ({"title": 5}, "title must be a string or None"), ({"title": b"bytes"}, "title must be a string or None"),
])
def test_to_svg_names_an_argument_of_the_wrong_type(options, words):
    import splinecraft as sc

    mask = np.zeros((30, 30), bool)
    mask[5:25, 5:25] = True
    result = sc.trace(mask)
    for source in (result, as_outline(result)):  # TraceResult.to_svg and Outline.to_svg
        with pytest.raises(TypeError, match=words):
            source.to_svg(**options)
    assert "<title>" not in result.to_svg(title=None) and 'fill="none"' in result.to_svg(fill="none")


def test_transform_arguments_follow_the_svg_number_grammar():
    """``translate(10-5)`` is two numbers (minified SVG writes them so), as in path data."""
    document = ('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="40">'
                '<path transform="translate(10-5)scale(.5.5)" d="M10 20 H30 V40 H10 Z"/></svg>')
    low, high = from_svg(document).curve_bounds()
    np.testing.assert_allclose([low, high], [[15, 5], [25, 15]])


@pytest.mark.parametrize("transform", ["translateX(5)", "rotate(30 5)", "scale()", "translate(4px)", "skew(3)"])
def test_a_transform_that_cannot_be_read_is_refused_naming_it(transform):
    document = ('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="40">'
                f'<g transform="{transform}"><path d="M0 0 H10 V10 H0 Z"/></g></svg>')
    with pytest.raises(ValueError, match=r"SVG transform .*" + re.escape(transform.split("(")[0])):
        from_svg(document)


def test_a_piece_that_loops_back_to_its_start_is_read_exactly():
    """A cubic that ends where it starts (a teardrop tip before a square's sides) is split in exact halves so
    the contour's consecutive knots are distinct (it was an AssertionError 'unreachable')."""
    from splinecraft.capture.svg import parse_path_data
    from splinecraft.outline.contour import bezier_signed_area

    d = "M0 0 C 5 5 -5 5 0 0 L10 0 L10 10 L0 10 Z"
    (pieces, _), = parse_path_data(d)
    contour, = from_svg(d).contours
    bezier = contour.bezier()
    assert len(contour) == 6 and not contour.corners[1]  # the loop's middle is a smooth knot
    np.testing.assert_allclose(bezier[2:], pieces[1:], atol=1e-12)
    theta = np.linspace(0, 1, 9)[:, None]
    loop = pieces[0]

    def point(p, t):
        return (1 - t) ** 3 * p[0] + 3 * (1 - t) ** 2 * t * p[1] + 3 * (1 - t) * t * t * p[2] + t ** 3 * p[3]
    np.testing.assert_allclose(np.vstack([point(bezier[0], theta), point(bezier[1], theta)]),
                               point(loop, np.vstack([theta / 2, 0.5 + theta / 2])), atol=1e-12)
    assert contour.signed_area() == pytest.approx(bezier_signed_area(pieces), rel=1e-12)


@pytest.mark.parametrize("frame", ['<rect x="1" y="1" width="98" height="98" style="fill:none;stroke:#000"/>',
                                   '<g fill="none" stroke="red"><path d="M1 1 H99 V99 H1 Z"/></g>',
                                   '<circle cx="50" cy="50" r="49" fill="none" stroke="black"/>'])
def test_a_stroked_frame_without_fill_is_not_read_as_ink(frame):
    """Only the fill is an outline: a frame drawn with fill="none" around the picture made it a hole."""
    document = ('<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">'
                f'{frame}<g fill="none"><path fill="#000" d="M20 20 H80 V80 H20 Z"/></g></svg>')
    outline = from_svg(document)
    assert len(outline) == 1 and outline.nesting_depths().tolist() == [0]
    np.testing.assert_allclose(outline.curve_bounds(), [[20, 20], [80, 80]])


def test_a_drawing_of_strokes_only_says_why_nothing_was_read():
    document = ('<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">'
                '<path fill="none" stroke="black" d="M20 20 H80 V80 H20 Z"/></svg>')
    with pytest.raises(ValueError, match='no path with a closed subpath .*fill="none"'):
        from_svg(document)


@pytest.mark.parametrize("source", ["", "  \n"])
def test_an_empty_source_is_named_empty_not_a_missing_file(source):
    with pytest.raises(ValueError, match="source is empty"):
        from_svg(source)


@pytest.mark.parametrize("encoding, declared", [("utf-8-sig", "UTF-8"), ("iso-8859-1", "ISO-8859-1"),
                                                ("utf-16", "UTF-16")])
def test_svg_files_are_decoded_by_their_byte_order_mark_or_declared_encoding(tmp_path, encoding, declared):
    document = (f'<?xml version="1.0" encoding="{declared}"?>\n'
                + _svg("<title>Café</title>" + SQUARE))
    path = tmp_path / "square.svg"
    path.write_bytes(document.encode(encoding))
    outline = from_svg(path)
    assert len(outline) == 1 and np.allclose(outline.contours[0].points, [[0, 0], [10, 0], [10, 10], [0, 10]])
    assert from_svg("\ufeff" + _svg(SQUARE)).contours[0].points.shape == (4, 2)  # a string with a mark
    (tmp_path / "data.svg").write_bytes(b"\xef\xbb\xbfM0 0 L10 0 L10 10 Z")
    assert len(from_svg(tmp_path / "data.svg").contours[0].points) == 3
    (tmp_path / "bad.svg").write_bytes(b"M0 0 L10 0 \xe9 L10 10 Z")
    with pytest.raises(ValueError, match="neither an XML document nor UTF-8"):
        from_svg(tmp_path / "bad.svg")


def test_each_path_is_read_with_its_own_rounding():
    """A path written with integers is rounded to half a unit; an exact path beside it keeps its small corner."""
    turn = np.radians(0.5)  # a corner of half a degree at (100, 0) between two cubics, written in full
    handle = 30 * np.array([np.cos(turn), np.sin(turn)])
    exact = (f'<path d="M 0,0 C 30,0 70,0 100,0 C {float(100 + handle[0])!r},{float(handle[1])!r} 130,50 100,100 '
             'C 70,110 10,90 0,0 Z"/>')
    alone = from_svg(_svg(exact, 'width="300" height="300"'))
    mixed = from_svg(_svg(exact + '<rect x="250" y="250" width="10" height="10"/>', 'width="300" height="300"'))
    k = int(np.argmin(np.hypot(*(alone.contours[0].points - [100, 0]).T)))
    assert alone.contours[0].corners[k] and mixed.contours[0].corners[k] and len(mixed) == 2
    np.testing.assert_array_equal(mixed.contours[0].bezier(), alone.contours[0].bezier())


def test_curves_wholly_at_negative_coordinates_need_a_frame():
    with pytest.raises(ValueError, match="frame runs from 0"):
        from_svg("M -30 -30 L -20 -30 L -20 -20 Z")
    with pytest.raises(ValueError, match="translate them to y >= 0"):
        as_outline(np.array([[[5.0, -30], [8, -30], [12, -30], [15, -30]], [[15, -30], [15, -25], [15, -22], [15, -20]],
                             [[15, -20], [12, -24], [8, -27], [5, -30]]]))
    framed = from_svg('<svg xmlns="http://www.w3.org/2000/svg" viewBox="-40 -40 40 40">'
                      '<path d="M -30 -30 L -20 -30 L -20 -20 Z"/></svg>')
    assert framed.width == 40 and (framed.contours[0].points >= 0).all()


@pytest.mark.parametrize("scale", [1e-200, 1e200])
def test_coordinates_beyond_the_transforms_reach_are_refused_when_built(scale):
    """Areas overflow or vanish there: an outline built at such a scale lost its hole's orientation."""
    from splinecraft.outline import from_knots

    square = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    with pytest.raises(ValueError, match="1e[+-]150"):
        from_knots([square * scale])
    with pytest.raises(ValueError, match="1e[+-]150"):
        from_svg(f"M0 0 L{10 * scale:g} 0 L{10 * scale:g} {10 * scale:g} Z")
