"""Tests of bitmap loading and binarization (capture/image.py).

References: PIL's own colour conversion (``convert("L")``), skimage's Otsu threshold, explicit numpy
formulas, and the masks the test images were drawn from.
"""
import gc
import io
import os
import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra.numpy import arrays
from PIL import Image
from scipy import ndimage
from skimage.filters import threshold_otsu

from splinecraft.capture._binarize import threshold_level
from splinecraft.capture.image import (DEFAULT_THRESHOLD, FALLBACK_THRESHOLD, MIN_CONTRAST, InkPolarityWarning,
                                      _to_gray, load_bitmap)


def shape_mask(height=40, width=50):
    """A disc with a square hole and a separate bar (True = ink)."""
    yy, xx = np.mgrid[:height, :width] + 0.5
    mask = (xx - 18) ** 2 + (yy - 20) ** 2 <= 14**2
    mask[16:24, 14:22] = False
    mask[5:35, 40:45] = True
    return mask


def gray_image(mask, ink=0, paper=255, dtype=np.uint8):
    return np.where(mask, ink, paper).astype(dtype)


def edge_band(mask):
    """Pixels within one pixel of the ink/paper edge (where lossy compression may flip a pixel)."""
    return ndimage.binary_dilation(mask) & ~ndimage.binary_erosion(mask)


# ------------------------------------------------------------------------------ files
@pytest.mark.parametrize(
    "suffix, mode",
    [
        (".png", "L"), (".png", "1"), (".png", "RGB"), (".png", "RGBA"), (".png", "P"), (".png", "LA"),
        (".png", "I;16"), (".bmp", "L"), (".bmp", "RGB"), (".bmp", "1"), (".gif", "P"), (".gif", "L"),
        (".tif", "L"), (".tif", "RGB"), (".tif", "I;16"), (".tiff", "1"),
    ],
)
def test_lossless_files_round_trip(tmp_path, suffix, mode):
    mask = shape_mask()
    gray = gray_image(mask)
    if mode == "I;16":
        img = Image.fromarray(gray.astype(np.uint16) * 257)
    else:
        img = Image.fromarray(gray).convert(mode)
    path = tmp_path / f"shape{suffix}"
    img.save(path)
    np.testing.assert_array_equal(load_bitmap(path), mask)
    np.testing.assert_array_equal(load_bitmap(str(path)), mask)


def test_jpeg_differs_only_at_the_edge(tmp_path):
    mask = shape_mask(80, 100)
    path = tmp_path / "shape.jpg"
    Image.fromarray(gray_image(mask)).save(path, quality=85)
    loaded = load_bitmap(path)
    wrong = loaded != mask
    assert not (wrong & ~edge_band(mask)).any()
    assert wrong.sum() < 0.02 * mask.size



@pytest.mark.parametrize("suffix", [".png", ".jpg", ".webp"])  # (PIL turns TIFFs by their tag itself on load)
@pytest.mark.parametrize("orientation", range(1, 9))
def test_exif_orientation_is_applied_as_a_viewer_shows_it(tmp_path, orientation, suffix):
    """A phone stores the sensor's pixels and an EXIF orientation tag that says how to show them; the bitmap
    is what a viewer shows (PIL's ``ImageOps.exif_transpose`` as the reference)."""
    from PIL import ImageOps

    upright = shape_mask(40, 64)  # not square and without symmetry: every turn and mirror shows
    stored = _stored_for(upright, orientation)
    exif = Image.Exif()
    exif[0x0112] = orientation
    path = tmp_path / f"photo{suffix}"
    stored.save(path, exif=exif.tobytes(), **({"quality": 95} if suffix == ".jpg" else {"lossless": True}
                                              if suffix == ".webp" else {}))
    viewer = np.asarray(ImageOps.exif_transpose(Image.open(path)).convert("L")) < 128
    assert viewer.shape == upright.shape
    loaded = load_bitmap(path)
    np.testing.assert_array_equal(loaded, viewer)
    np.testing.assert_array_equal(load_bitmap(path.read_bytes()), viewer)
    if suffix != ".jpg":  # lossless
        np.testing.assert_array_equal(loaded, upright)


def _tagged(image, orientation):
    exif = Image.Exif()
    exif[0x0112] = orientation
    image.info["exif"] = exif.tobytes()
    image.getexif()[0x0112] = orientation
    return image


def _stored_for(upright, orientation):
    """The stored pixels whose EXIF ``orientation`` shows ``upright``: found by trying each transpose."""
    from PIL import ImageOps

    image = Image.fromarray(gray_image(upright))
    for method in Image.Transpose:
        candidate = image.transpose(method)
        shown = ImageOps.exif_transpose(_tagged(candidate.copy(), orientation))
        if np.array_equal(np.asarray(shown) < 128, upright):
            return candidate
    raise AssertionError(f"no transpose is shown upright under orientation {orientation}")

def test_transparent_png_is_composited_on_white(tmp_path):
    mask = shape_mask()
    rgba = np.zeros(mask.shape + (4,), np.uint8)  # transparent black everywhere ...
    rgba[mask, 3] = 255  # ... except the opaque black shape
    path = tmp_path / "alpha.png"
    Image.fromarray(rgba, "RGBA").save(path)
    np.testing.assert_array_equal(load_bitmap(path), mask)
    palette = Image.fromarray(rgba, "RGBA").convert("P")  # palette with a transparent entry
    np.testing.assert_array_equal(load_bitmap(palette), mask)


@pytest.mark.parametrize("mode", ["L", "RGB", "I;16", "1"])
def test_transparent_colour_of_a_png_is_paper(tmp_path, mode):
    """A gray, 16-bit or RGB PNG may name one colour transparent (its tRNS chunk) instead of carrying an alpha
    channel; a viewer shows those pixels as the page, so they are paper, as an alpha channel's transparent
    pixels are (they were read as their colour: a transparent dark bar was ink). threshold="alpha" traces
    the opaque pixels of such a file, 16-bit included."""
    disc = shape_mask()
    disc[:, 38:] = False                                         # the disc alone ...
    bar = shape_mask() & ~disc                                   # ... and the bar, drawn in the transparent colour
    if mode == "1":                                              # two levels: black is the transparent colour
        gray, key = gray_image(bar), 0
        expected_default, expected_alpha = np.zeros_like(bar), ~bar
    else:
        gray, key = np.where(disc, 0, np.where(bar, 50, 255)).astype(np.uint8), 50
        expected_default, expected_alpha = disc, ~bar
    if mode == "I;16":
        img, key = Image.fromarray(gray.astype(np.uint16) * 257), key * 257
    elif mode == "RGB":
        img, key = Image.fromarray(np.stack([gray] * 3, axis=-1), "RGB"), (key,) * 3
    else:
        img = Image.fromarray(gray).convert(mode)
    path = tmp_path / "keyed.png"
    img.save(path, transparency=key)
    with Image.open(path) as opened:
        assert opened.mode == mode and opened.info["transparency"] == (255 if mode == "1" and key else key)
    for source in (path, path.read_bytes()):
        np.testing.assert_array_equal(load_bitmap(source, threshold=0.5), expected_default)
        np.testing.assert_array_equal(load_bitmap(source, threshold="alpha"), expected_alpha)
    if mode != "1":
        np.testing.assert_array_equal(load_bitmap(path), expected_default)


def test_float_tiff_on_pils_8_bit_scale(tmp_path):
    """PIL's 32-bit float mode "F" (a float TIFF, ``convert("F")``) holds gray on PIL's 0..255 scale; such a file
    was refused ("float image values must lie in [0, 1]") though load_bitmap reads any file PIL reads. 0..255 is
    divided by 255, 0..1 read as for an array, and a range that is neither is an error naming the file."""
    mask = shape_mask()
    path = tmp_path / "float.tif"
    Image.fromarray(gray_image(mask)).convert("F").save(path)
    with Image.open(path) as img:
        assert img.mode == "F" and img.getextrema() == (0.0, 255.0)
    for source in (path, path.read_bytes(), Image.open(path)):
        np.testing.assert_array_equal(load_bitmap(source), mask)
    unit = Image.fromarray(gray_image(mask).astype(np.float32) / 255, "F")
    np.testing.assert_array_equal(load_bitmap(unit), mask)
    wide = Image.fromarray(gray_image(mask).astype(np.float32) * 4, "F")
    with pytest.raises(ValueError, match=r"PIL image: 32-bit float image values lie in \[0, 1020\]"):
        load_bitmap(wide)


def test_multiframe_gif_uses_first_frame(tmp_path):
    from splinecraft.capture.image import MultiFrameWarning

    first, second = shape_mask(), ~shape_mask()
    frames = [Image.fromarray(gray_image(m)).convert("P") for m in (first, second)]
    path = tmp_path / "anim.gif"
    frames[0].save(path, save_all=True, append_images=frames[1:])
    with Image.open(path) as img:
        assert img.n_frames == 2
    with pytest.warns(MultiFrameWarning, match="2 frames"):
        np.testing.assert_array_equal(load_bitmap(path), first)


@pytest.mark.parametrize("suffix", ["gif", "tif"])
def test_a_multi_frame_file_says_which_frame_it_traced(tmp_path, suffix):
    """An animated GIF or a multi-page TIFF was traced from its first frame without a word. Now a
    MultiFrameWarning names the file, its frame count, the frame traced and how to trace another (pick the
    frame with PIL and pass the image), for a path, the file's bytes and a file object, pointing at the
    caller's line; the first frame is still what is traced. A one-frame file and a PIL image (traced at the
    frame it is at, which its owner chose) give no warning."""
    import splinecraft as sc
    from splinecraft.capture.image import MultiFrameWarning

    masks = [shape_mask(), np.roll(shape_mask(), 5, axis=1), shape_mask()[::-1]]
    frames = [Image.fromarray(gray_image(m)) for m in masks]
    path = tmp_path / f"pages.{suffix}"
    frames[0].save(path, save_all=True, append_images=frames[1:])
    with path.open("rb") as handle:
        for source, name in ((path, str(path)), (path.read_bytes(), "image bytes"), (handle, str(path))):
            with pytest.warns(MultiFrameWarning) as caught:
                mask = load_bitmap(source)
            np.testing.assert_array_equal(mask, masks[0])
            (warning,) = caught
            message = str(warning.message)
            assert message.startswith(name) and "3 frames" in message and "traced frame 0 (the first)" in message
            assert "seek(k)" in message and warning.filename == __file__
            assert (warning.message.frames, warning.message.frame) == (3, 0)
    with pytest.warns(MultiFrameWarning, match="3 frames"):
        sc.trace(path)
    single = tmp_path / f"one.{suffix}"
    frames[0].save(single)
    with Image.open(path) as img, warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_array_equal(load_bitmap(single), masks[0])
        img.seek(1)
        np.testing.assert_array_equal(load_bitmap(img), masks[1])


@pytest.mark.filterwarnings("ignore:Corrupt EXIF data:UserWarning")  # PIL's, reading the cut TIFF's headers
@pytest.mark.parametrize("suffix", ["gif", "tif"])
def test_a_multi_frame_file_damaged_after_its_first_frame_traces_that_frame(suffix):
    """The frame count (``n_frames``: PIL reads every frame's header) of an animated GIF or multi-page TIFF cut
    short after its first frame raised ('unpack_from requires a buffer ...', 'Missing dimensions'), and the whole
    file was refused as "truncated or corrupt", though the one frame traced was whole. That frame is traced, with
    a MultiFrameWarning saying the frames could not be counted (``frames`` is ``None``) and why."""
    from splinecraft.capture.image import MultiFrameWarning

    masks = [shape_mask(), np.roll(shape_mask(), 5, axis=1), shape_mask()[::-1]]
    buffer = io.BytesIO()
    frames = [Image.fromarray(gray_image(m)) for m in masks]
    frames[0].save(buffer, format="GIF" if suffix == "gif" else "TIFF", save_all=True, append_images=frames[1:])
    data = buffer.getvalue()

    def uncountable(cut):
        try:
            Image.open(io.BytesIO(data[:cut])).n_frames
        except EOFError:
            return False
        except Exception:  # noqa: BLE001 - the plugin's own errors, which the loader reported
            return True
        return False

    cut = next(cut for cut in range(len(data) // 3, len(data)) if uncountable(cut))
    for source in (data[:cut], io.BytesIO(data[:cut])):
        with pytest.warns(MultiFrameWarning) as caught:
            mask = load_bitmap(source)
        np.testing.assert_array_equal(mask, masks[0])
        (warning,) = [item for item in caught if item.category is MultiFrameWarning]  # (PIL warns of the EXIF too)
        message = str(warning.message)
        assert "its frames could not be counted (the file is truncated or corrupt after its first frame" in message
        assert "traced frame 0 (the first)" in message and warning.message.frames is None


def layered_psd(composite, layers):
    """The bytes of a minimal 8-bit grayscale Photoshop file: ``composite`` (the flattened picture a viewer shows)
    and its ``layers`` (2-D uint8 arrays of its size), raw, without compression."""
    import struct

    height, width = composite.shape
    header = b"8BPS" + struct.pack(">H6xHIIHH", 1, 1, height, width, 8, 1) + struct.pack(">II", 0, 0)
    info = bytearray(struct.pack(">h", len(layers)))
    for _ in layers:  # bounds, one channel (id 0, gray) of 2 + pixels bytes, normal blending, no extra data
        info += struct.pack(">iiiiHHI", 0, 0, height, width, 1, 0, 2 + height * width)
        info += b"8BIMnorm" + bytes([255, 0, 0, 0]) + struct.pack(">I", 0)
    for layer in layers:
        info += struct.pack(">H", 0) + np.ascontiguousarray(layer, np.uint8).tobytes()
    info += b"\0" * (len(info) % 2)
    section = struct.pack(">I", len(info)) + bytes(info)
    return (header + struct.pack(">I", len(section)) + section + struct.pack(">H", 0)
            + np.ascontiguousarray(composite, np.uint8).tobytes())


def test_a_layered_photoshop_file_is_its_composite_picture(tmp_path):
    """PIL counts a Photoshop file's layers as its frames (``n_frames``), numbered from 1, and opens the
    composite picture. The loader's ``seek(0)`` before reading a multi-frame file asked a layered PSD for a frame
    it does not have: "truncated or corrupt image file (EOFError: attempt to seek outside sequence)". The
    composite is the picture (what a viewer shows; no frame of an animation), traced without a
    MultiFrameWarning."""
    mask = shape_mask()
    layers = [gray_image(mask), gray_image(~mask), np.full(mask.shape, 255, np.uint8)]
    data = layered_psd(gray_image(mask), layers)
    path = tmp_path / "layers.psd"
    path.write_bytes(data)
    with Image.open(path) as img:
        assert (img.format, img.n_frames) == ("PSD", 3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for source in (path, data, io.BytesIO(data)):
            np.testing.assert_array_equal(load_bitmap(source), mask)


def test_a_pil_image_whose_pixels_cannot_be_read_says_why():
    """A PIL image opened in a ``with Image.open(path) as img:`` block and traced after it was a bare
    ``AssertionError`` (PIL loads the pixels lazily and its file was closed; a batch record said only
    'AssertionError'); a PIL image of a truncated file was a bare ``OSError``, and a closed image PIL's
    'Operation on closed image'. Each is a ValueError naming the PIL image and why, as a file's are."""
    mask = shape_mask()
    buffer = io.BytesIO()
    Image.fromarray(gray_image(mask)).save(buffer, format="PNG")
    data = buffer.getvalue()
    with Image.open(io.BytesIO(data)) as lazy:
        pass
    with pytest.raises(ValueError) as caught:
        load_bitmap(lazy)
    message = str(caught.value)
    assert message.startswith("PIL image: its pixels were never loaded and its file is closed")
    assert "img.load()" in message
    with pytest.raises(ValueError, match=r"^PIL image: truncated or corrupt image \(OSError: image file is truncated"):
        load_bitmap(Image.open(io.BytesIO(data[:-30])))
    closed = Image.fromarray(gray_image(mask))
    closed.close()
    with pytest.raises(ValueError, match=r"^PIL image: cannot read its pixels \(ValueError: Operation on closed image"):
        load_bitmap(closed)
    with Image.open(io.BytesIO(data)) as loaded:
        loaded.load()
    np.testing.assert_array_equal(load_bitmap(loaded), mask)  # loaded in the block: its pixels stay


def test_file_object_and_pil_image():
    mask = shape_mask()
    buffer = io.BytesIO()
    Image.fromarray(gray_image(mask)).save(buffer, format="PNG")
    buffer.seek(0)
    np.testing.assert_array_equal(load_bitmap(buffer), mask)
    for mode in ("1", "L", "RGB", "RGBA", "CMYK", "I", "F"):
        img = Image.fromarray(gray_image(mask)).convert(mode)
        if mode == "F":
            img = Image.fromarray(gray_image(mask).astype(np.float32) / 255)
        np.testing.assert_array_equal(load_bitmap(img), mask, err_msg=mode)


# ------------------------------------------------------------------------------ bad files
def test_missing_file():
    with pytest.raises(FileNotFoundError, match="nope.png"):
        load_bitmap("/nonexistent/nope.png")


def test_non_image_file(tmp_path):
    path = tmp_path / "notes.png"
    path.write_text("this is not an image\n")
    with pytest.raises(ValueError, match=r"notes\.png.*not an image"):
        load_bitmap(path)


@pytest.mark.parametrize("suffix", [".png", ".jpg", ".bmp", ".gif", ".tif"])
def test_truncated_file(tmp_path, suffix):
    rng = np.random.default_rng(0)
    img = Image.fromarray((rng.random((120, 160)) * 255).astype(np.uint8))  # incompressible
    full = tmp_path / f"full{suffix}"
    img.save(full)
    data = full.read_bytes()
    path = tmp_path / f"cut{suffix}"
    path.write_bytes(data[: len(data) // 3])
    with pytest.raises(ValueError, match=r"cut\." + suffix[1:]):
        load_bitmap(path)


def test_directory(tmp_path):
    with pytest.raises(ValueError, match="directory"):
        load_bitmap(tmp_path)


# ------------------------------------------------------------------------------ arrays
def test_array_kinds_agree():
    mask = shape_mask()
    gray = gray_image(mask)
    rgb = np.repeat(gray[..., None], 3, axis=2)
    cases = {
        "bool": mask,
        "uint8": gray,
        "uint16": gray.astype(np.uint16) * 257,
        "int64": gray.astype(np.int64),
        "float64": gray / 255.0,
        "float32": (gray / 255.0).astype(np.float32),
        "float16": (gray / 255.0).astype(np.float16),
        "gray1": gray[..., None],
        "gray_alpha": np.dstack([gray, np.full_like(gray, 255)]),
        "rgb": rgb,
        "rgba": np.dstack([rgb, np.full_like(gray, 255)]),
        "rgb_float": rgb / 255.0,
        "big_endian": gray.astype(">u2") * 257,
    }
    for name, array in cases.items():
        np.testing.assert_array_equal(load_bitmap(array), mask, err_msg=name)


def test_coloured_shape_on_coloured_paper():
    mask = shape_mask()
    rgb = np.empty(mask.shape + (3,), np.uint8)
    rgb[mask] = (200, 30, 30)  # red ink, luma ~ 81
    rgb[~mask] = (250, 250, 210)  # cream paper, luma ~ 245
    np.testing.assert_array_equal(load_bitmap(rgb), mask)


@settings(max_examples=50, deadline=None)
@given(arrays(np.uint8, st.tuples(st.integers(1, 12), st.integers(1, 12), st.just(3))))
def test_luma_matches_pil(rgb):
    gray, white = _to_gray(rgb)
    assert white == 255 and gray.dtype == np.uint8
    np.testing.assert_array_equal(gray, np.asarray(Image.fromarray(rgb, "RGB").convert("L")))


@settings(max_examples=50, deadline=None)
@given(arrays(np.uint8, st.tuples(st.integers(1, 12), st.integers(1, 12), st.just(4))))
def test_alpha_composite_on_white(rgba):
    gray, _ = _to_gray(rgba)
    luma = np.asarray(Image.fromarray(np.ascontiguousarray(rgba[..., :3]), "RGB").convert("L")).astype(float)
    alpha = rgba[..., 3] / 255.0
    expected = luma * alpha + 255.0 * (1.0 - alpha)
    assert np.abs(gray - expected).max() <= 0.5 + 1e-9


@settings(max_examples=60, deadline=None)
@given(
    arrays(np.uint8, st.tuples(st.integers(1, 15), st.integers(1, 15))),
    st.floats(0.0, 1.0),
    st.booleans(),
)
def test_explicit_threshold_and_invert(gray, threshold, invert):
    with warnings.catch_warnings():  # random gray may have a dark border: the polarity hint is beside the point
        warnings.simplefilter("ignore", InkPolarityWarning)
        mask = load_bitmap(gray, threshold=threshold, invert=invert, min_speck_area=0)  # no despeckling of noise
    expected = gray <= threshold * 255
    np.testing.assert_array_equal(mask, ~expected if invert else expected)


def test_otsu_is_skimages_level():
    rng = np.random.default_rng(3)
    mask = shape_mask()
    gray = np.clip(np.where(mask, 60, 190) + rng.normal(0, 25, mask.shape), 0, 255).astype(np.uint8)
    level = threshold_otsu(gray)
    np.testing.assert_array_equal(load_bitmap(gray, threshold="otsu", min_speck_area=0), gray <= level)
    np.testing.assert_array_equal(load_bitmap(gray, threshold="otsu", invert=True, min_speck_area=0), gray > level)


def test_background_by_default():
    """``threshold=None`` is the background-normalized midpoint (chosen by BENCHMARKS.md, "Thresholds"); on
    even paper it is the midpoint of the two gray levels, (60 + 190) / 2, whatever the noise."""
    assert DEFAULT_THRESHOLD == "background"
    rng = np.random.default_rng(3)
    mask = shape_mask()
    gray = np.clip(np.where(mask, 60, 190) + rng.normal(0, 8, mask.shape), 0, 255).astype(np.uint8)
    found = load_bitmap(gray, min_speck_area=0)
    np.testing.assert_array_equal(found, load_bitmap(gray, threshold="background", min_speck_area=0))
    np.testing.assert_array_equal(load_bitmap(gray, invert=True, min_speck_area=0), ~found)
    level = threshold_level(gray, 255, "background")
    assert np.abs(level - 125).max() < 8          # the midpoint, up to the noise of the two estimates
    assert (found != mask).mean() < 0.005


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([np.uint8, np.uint16]))
def test_otsu_level_matches_skimage(seed, dtype):
    rng = np.random.default_rng(seed)
    top = np.iinfo(dtype).max
    lo, hi = sorted(rng.integers(0, top + 1, size=2))
    hi = max(hi, lo + int(0.2 * top))  # enough contrast for Otsu to be used
    gray = rng.integers(lo, min(hi, top) + 1, size=(rng.integers(2, 40), rng.integers(2, 40))).astype(dtype)
    if gray.max() - gray.min() < MIN_CONTRAST * top:
        return
    np.testing.assert_array_equal(load_bitmap(gray, threshold="otsu", min_speck_area=0), gray <= threshold_otsu(gray))


@pytest.mark.parametrize(
    "value, ink",
    [(255, False), (0, True), (int(0.3 * 255), True), (int(0.7 * 255), False)],
)
def test_uniform_images_use_the_fallback(value, ink):
    gray = np.full((20, 30), value, np.uint8)
    assert FALLBACK_THRESHOLD == 0.5
    np.testing.assert_array_equal(load_bitmap(gray), np.full(gray.shape, ink))


def test_blank_page_with_noise_has_no_ink():
    rng = np.random.default_rng(1)
    page = (255 - rng.integers(0, int(MIN_CONTRAST * 255) - 1, size=(50, 50))).astype(np.uint8)
    assert not load_bitmap(page).any()
    assert load_bitmap(page, threshold=1.0).all()  # an explicit threshold is always obeyed


# ------------------------------------------------------------------------------ specks
def test_speck_removal():
    mask = np.zeros((40, 40), bool)
    mask[5:30, 5:30] = True
    mask[12, 12] = False  # 1-pixel hole
    mask[20:22, 20:22] = False  # 4-pixel hole
    mask[35, 35] = True  # 1-pixel speck
    mask[34:36, 2:4] = True  # 4-pixel speck
    np.testing.assert_array_equal(load_bitmap(mask, min_speck_area=0), mask)
    cleaned = load_bitmap(mask, min_speck_area=4)  # fewer than 4 pixels goes
    expected = mask.copy()
    expected[12, 12] = True
    expected[35, 35] = False
    np.testing.assert_array_equal(cleaned, expected)
    cleaned = load_bitmap(mask, min_speck_area=5)
    expected[20:22, 20:22] = True
    expected[34:36, 2:4] = False
    np.testing.assert_array_equal(cleaned, expected)


@pytest.mark.parametrize("pattern", ["checkerboard", "single pixel"])
def test_two_level_images_get_no_automatic_speck_area(pattern):
    """A 1-bit image, or a mask saved as 0/255, carries no gray level: like a bool mask it gets no automatic
    speck area (docs/capture.md §10). The noise estimate (the median diagonal Haar detail) read such a pattern as
    noise whenever most 2 x 2 windows straddle an edge: a 32 x 32 checkerboard filled 450 of its 512 holes (and
    traced as one square), and a 3 x 3 image with one black pixel lost it ("no shape found")."""
    import splinecraft as sc

    if pattern == "checkerboard":
        mask = np.add.outer(np.arange(32), np.arange(32)) % 2 == 0
    else:
        mask = np.zeros((3, 3), bool)
        mask[1, 1] = True
    gray = gray_image(mask)
    for image in (gray, gray_image(mask, ink=40, paper=200), Image.fromarray(gray).convert("1"),
                  gray.astype(np.float64) / 255):
        np.testing.assert_array_equal(load_bitmap(image), mask)
        np.testing.assert_array_equal(load_bitmap(image, threshold=0.5), mask)
    result = sc.trace(gray, connectivity=4, min_speck_area=None)
    assert len(result.splines) == int(mask.sum())


def test_speck_connectivity():
    mask = np.zeros((6, 6), bool)
    mask[1, 1] = mask[2, 2] = True  # diagonal pair: one 8-component of 2, two 4-components of 1
    assert load_bitmap(mask, min_speck_area=2, connectivity=8).sum() == 2
    assert load_bitmap(mask, min_speck_area=2, connectivity=4).sum() == 0


# ------------------------------------------------------------------------------ validation
@pytest.mark.parametrize(
    "image, error, match",
    [
        (np.zeros((0, 5), np.uint8), ValueError, "empty"),
        (np.zeros((4, 0), bool), ValueError, "empty"),
        (np.zeros(5, np.uint8), ValueError, "shape"),
        (np.zeros((2, 2, 2, 2), np.uint8), ValueError, "shape"),
        (np.zeros((3, 3, 5), np.uint8), ValueError, "channels"),
        (np.zeros((3, 3, 3), bool), ValueError, "bool"),
        (np.zeros((3, 3), complex), TypeError, "dtype"),
        (np.array([["a"]]), TypeError, "dtype"),
        (np.zeros((3, 3), object), TypeError, "dtype"),
        (np.array([[0.5, np.nan]]), ValueError, r"non-finite value nan at index \(0, 1\)"),
        (np.array([[0.5, np.inf]]), ValueError, r"non-finite value inf at index \(0, 1\)"),
        (np.array([[0.0, 2.0]]), ValueError, r"\[0, 1\]"),
        (np.array([[0, 300]]), ValueError, "8-bit"),
        (np.array([[-1, 3]]), ValueError, "8-bit"),
        ([[0, 1]], TypeError, "numpy array"),
        (42, TypeError, "numpy array"),
    ],
)
def test_bad_arrays(image, error, match):
    with pytest.raises(error, match=match):
        load_bitmap(image)


def test_bad_options():
    gray = np.zeros((3, 3), np.uint8)
    with pytest.raises(ValueError, match=r"threshold.*\[0, 1\].*255"):
        load_bitmap(gray, threshold=128)
    with pytest.raises(ValueError, match="threshold"):
        load_bitmap(gray, threshold=float("nan"))
    with pytest.raises(TypeError, match="threshold"):
        load_bitmap(gray, threshold="0.5")
    with pytest.raises(ValueError, match="bool mask"):
        load_bitmap(np.zeros((3, 3), bool), threshold=0.5)
    with pytest.raises(TypeError, match="invert"):
        load_bitmap(gray, invert=1)
    with pytest.raises(ValueError, match="min_speck_area"):
        load_bitmap(gray, min_speck_area=-1)
    with pytest.raises(TypeError, match="min_speck_area"):
        load_bitmap(gray, min_speck_area=2.5)
    with pytest.raises(ValueError, match="connectivity"):
        load_bitmap(gray, connectivity=6)


def test_bool_invert_and_result_is_a_fresh_array():
    mask = shape_mask()
    out = load_bitmap(mask)
    assert out is not mask and out.dtype == bool and out.flags.c_contiguous
    np.testing.assert_array_equal(load_bitmap(mask, invert=True), ~mask)


# ------------------------------------------------------------------------------ real scans
def lit_gray(mask, darkest=0.12, seed=0):
    """Dark ink on paper whose brightness falls linearly towards the bottom right (uneven lighting)."""
    height, width = mask.shape
    ramp = 1.0 - (1.0 - darkest) * np.add.outer(np.arange(height) / height, np.arange(width) / width) / 2
    noise = np.random.default_rng(seed).normal(0.0, 0.01, mask.shape)
    return np.clip(np.where(mask, 0.05, 0.95) * ramp + noise, 0.0, 1.0)


def text_mask(height=120, width=200):
    """Thin strokes (3 px) like printed text: rows of short bars and rings."""
    yy, xx = np.mgrid[:height, :width] + 0.5
    mask = np.zeros((height, width), bool)
    for row in range(15, height - 10, 30):
        for col in range(10, width - 20, 24):
            mask[row:row + 3, col:col + 14] = True
            ring = np.hypot(xx - col - 7, yy - row - 14)
            mask |= (ring >= 5) & (ring <= 8) & (np.abs(yy - row - 14) < 9) & (np.abs(xx - col - 7) < 9)
    return mask


@pytest.mark.parametrize("method", ["background", "sauvola", "local"])
def test_local_thresholds_follow_uneven_lighting(method):
    mask = text_mask()
    gray = lit_gray(mask)
    found = load_bitmap(gray, threshold=method, min_speck_area=0)
    assert (found != mask).mean() < 0.01
    global_level = load_bitmap(gray, threshold="otsu", min_speck_area=0)
    assert (global_level != mask).mean() > (found != mask).mean()


@pytest.mark.parametrize("falloff", [0.5, 0.4, 0.3])
@pytest.mark.parametrize("method", ["background", "sauvola", "local"])
def test_blank_paper_far_from_the_text_stays_paper_where_the_light_falls_off(method, falloff):
    """Text in the left third of a page, the light falling off linearly to ``falloff`` at the right edge: the
    blank paper on the right is darker than the level measured beside the text, but it is paper (a flat area
    with no edge inside takes the class its rim decides). Carrying the nearest edge's level made 15-40 % of
    it ink at a fall-off of 50 %."""
    height, width = 200, 600
    text = np.zeros((height, width), bool)
    text[:, :200] = text_mask(height, 200)
    ramp = 1.0 - (1.0 - falloff) * (np.arange(width) + 0.5) / width
    gray = ndimage.gaussian_filter(np.where(text, 0.15, 0.92), 1.0) * ramp[None, :]
    gray = np.clip(255 * (gray + np.random.default_rng(1).normal(0.0, 0.01, gray.shape)), 0, 255).astype(np.uint8)
    found = load_bitmap(gray, threshold=method, min_speck_area=0)
    far = ndimage.distance_transform_edt(~text) > 30
    assert not (found & far).any()
    assert found[text].mean() > 0.8  # and the text is found


def test_jpeg_paper_stays_paper_under_the_local_threshold(tmp_path):
    """A JPEG quantizes the fine detail the noise estimate reads away (the estimate is 0, so is "local"'s
    offset): its blank paper is flat, and stays paper."""
    mask = text_mask(240, 320)
    gray = np.clip(255 * (np.where(mask, 0.1, 0.9) + np.random.default_rng(2).normal(0, 0.01, mask.shape)),
                   0, 255).astype(np.uint8)
    path = tmp_path / "page.jpg"
    Image.fromarray(gray).save(path, quality=30)
    far = ndimage.distance_transform_edt(~mask) > 12
    for method in ("background", "sauvola", "local"):
        assert not (load_bitmap(path, threshold=method) & far).any(), method

@pytest.mark.parametrize("method", ["background", "otsu", "sauvola", "local"])
def test_every_threshold_keeps_a_bilevel_image(method):
    mask = shape_mask(80, 100)                 # wide ink areas and wide paper: uniform windows
    np.testing.assert_array_equal(load_bitmap(gray_image(mask), threshold=method), mask)


def blurred_disc(radius, sigma, size, lighting, noise=0.0, seed=0):
    """Gray render (0..1) of a black disc on paper, blurred by a Gaussian of ``sigma`` px (4x supersampled),
    times a lighting ramp falling from 1 at the top left to ``lighting`` at the bottom right, plus noise."""
    fine = (np.mgrid[:4 * size, :4 * size] + 0.5) / 4 - size / 2
    ink = (np.hypot(fine[0], fine[1]) <= radius).astype(float)
    gray = 1.0 - ndimage.gaussian_filter(ink, 4 * sigma).reshape(size, 4, size, 4).mean(axis=(1, 3))
    ramp = 1.0 - (1.0 - lighting) * np.add.outer(np.arange(size), np.arange(size)) / (2 * size)
    return np.clip(gray * ramp + np.random.default_rng(seed).normal(0.0, noise, gray.shape), 0.0, 1.0)


@settings(max_examples=12, deadline=None)
@given(radius=st.floats(12.0, 40.0), sigma=st.floats(0.5, 2.5), lighting=st.floats(0.3, 1.0),
       seed=st.integers(0, 2**16))
def test_background_threshold_keeps_a_blurred_edge_in_place(radius, sigma, lighting, seed):
    """The midpoint between paper and ink under the local lighting is where a blurred edge crosses its true
    position: the ink area of a blurred, unevenly lit disc is its true area (pi r^2, up to the curvature shift
    of a blurred circle's half-level line, about sigma^2 / (2 r), and the pixel rounding); a global level
    puts the edge where the lighting says, not where the disc is."""
    size = int(2 * radius + 8 * sigma + 24)
    gray = blurred_disc(radius, sigma, size, lighting, noise=0.02, seed=seed)
    found = load_bitmap(gray, threshold="background", min_speck_area=0)
    shift = sigma**2 / (2 * radius)
    area_error = abs(found.sum() - np.pi * radius**2)
    assert area_error <= 2 * np.pi * radius * (shift + 0.15) + 6
    labels, count = ndimage.label(found, structure=np.ones((3, 3)))
    assert count == 1 and ndimage.label(~found)[1] == 1          # one disc, no specks, no holes


def test_background_threshold_seeds_large_images_from_block_means(monkeypatch):
    """Images over ROUGH_PIXELS get their first (Sauvola) pass on block means; the final level is still
    per pixel, so the thin strokes of an unevenly lit page come out as with the pass at full size. Blocks of
    2 x 2 against strokes of 3 px: the factor grows as the square root of the pixel count, and so do the
    strokes of a page scanned at a higher resolution."""
    from splinecraft.capture import _binarize

    mask = text_mask()
    gray = lit_gray(mask)
    full = load_bitmap(gray, threshold="background", min_speck_area=0)
    monkeypatch.setattr(_binarize, "ROUGH_PIXELS", mask.size // 4)     # blocks of 2 x 2 pixels
    blocks = load_bitmap(gray, threshold="background", min_speck_area=0)
    assert (blocks != mask).mean() < 0.01 and (full != mask).mean() < 0.01


def test_background_threshold_gives_wide_strokes_no_holes():
    """Ink wider than the window: Sauvola's level tracks the window mean into the ink's own noise (holes),
    the background midpoint stays half way to the paper."""
    yy, xx = np.mgrid[:160, :160]
    mask = (np.abs(xx - 80) < 45) & (np.abs(yy - 80) < 60)        # 90 px wide, the window is 21 px
    gray = np.clip(np.where(mask, 0.0, 1.0) + np.random.default_rng(1).normal(0.0, 0.05, mask.shape), 0, 1)
    found = load_bitmap(gray, threshold="background", min_speck_area=0)
    np.testing.assert_array_equal(found, mask)
    assert (load_bitmap(gray, threshold="sauvola", min_speck_area=0) != mask).sum() > 0


def test_threshold_names_and_default():
    mask = shape_mask()
    gray = gray_image(mask, ink=40, paper=210)
    np.testing.assert_array_equal(load_bitmap(gray), load_bitmap(gray, threshold="background"))
    np.testing.assert_array_equal(load_bitmap(gray), mask)
    with pytest.raises(ValueError, match="threshold.*sauvola"):
        load_bitmap(gray, threshold="niblack")
    with pytest.raises(TypeError, match="threshold"):
        load_bitmap(gray, threshold=["otsu"])


def test_bool_mask_with_the_background_true_warns():
    yy, xx = np.mgrid[:60, :80]
    background_true = np.hypot(xx - 40, yy - 30) > 20          # like skimage.data.horse(): True = paper
    with pytest.warns(UserWarning, match="invert=True"):
        load_bitmap(background_true)
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_bitmap(~background_true)                           # ink in the middle: no warning
        load_bitmap(background_true, invert=True)               # already flipped: no warning
        load_bitmap(np.ones((5, 5), bool))                       # all ink: the documented frame, no warning


def noisy_gray(mask, sd, seed=0):
    rng = np.random.default_rng(seed)
    return np.clip(np.where(mask, 0.2, 0.8) + rng.normal(0.0, sd, mask.shape), 0.0, 1.0)


def test_default_speck_area_comes_from_the_noise():
    yy, xx = np.mgrid[:120, :150] + 0.5
    mask = np.hypot(xx - 60, yy - 60) <= 40
    mask[50:70, 50:70] = False                                   # a hole
    mask[10:110, 120:135] = True                                 # a bar
    gray = noisy_gray(mask, 0.1)
    kept = load_bitmap(gray, min_speck_area=0)
    cleaned = load_bitmap(gray)
    structure = np.ones((3, 3))
    assert ndimage.label(kept, structure)[1] > 3                 # the noise made specks
    assert ndimage.label(cleaned, structure)[1] == ndimage.label(mask, structure)[1]
    assert ndimage.label(~cleaned)[1] == ndimage.label(~mask)[1]  # and no pinholes in the ink


def test_clean_images_lose_no_pixel_by_default():
    single = np.full((9, 9), 255, np.uint8)
    single[4, 4] = 0
    np.testing.assert_array_equal(load_bitmap(single), single == 0)
    gray = noisy_gray(shape_mask(), 0.0)
    np.testing.assert_array_equal(load_bitmap(gray), load_bitmap(gray, min_speck_area=0))


def test_a_speck_area_larger_than_the_background_keeps_the_background():
    mask = np.zeros((30, 30), bool)
    mask[2:28, 2:28] = True                                      # 676 ink pixels, 224 of paper
    mask[12:15, 12:15] = False                                   # a real hole of 9 pixels
    cleaned = load_bitmap(mask, min_speck_area=500)
    assert not cleaned[0].any() and not cleaned[:, 0].any()       # the paper is still paper
    assert cleaned[12:15, 12:15].all()                            # the small hole is filled


def png_bytes(mask):
    buffer = io.BytesIO()
    Image.fromarray(gray_image(mask)).save(buffer, "png")
    return buffer.getvalue()


def test_bytes_are_an_encoded_image():
    mask = shape_mask()
    data = png_bytes(mask)
    for wrapped in (data, bytearray(data), memoryview(data)):
        np.testing.assert_array_equal(load_bitmap(wrapped), mask)
    with pytest.raises(ValueError, match="not an image"):
        load_bitmap(b"this is not an image at all")
    with pytest.raises(ValueError, match="empty"):
        load_bitmap(b"")


def test_size_is_checked_before_decoding(tmp_path, monkeypatch):
    from PIL import ImageFile

    mask = shape_mask()
    path = tmp_path / "shape.png"
    Image.fromarray(gray_image(mask)).save(path)
    data = path.read_bytes()

    def no_decoding(self, *args, **kwargs):
        raise AssertionError("pixels were decoded")

    monkeypatch.setattr(ImageFile.ImageFile, "load", no_decoding)
    for source in (path, data):
        with pytest.raises(ValueError, match="max_pixels"):
            load_bitmap(source, max_pixels=mask.size - 1)


def test_non_image_file_is_a_clear_error(tmp_path):
    path = tmp_path / "notes.png"
    path.write_text("plain text, not a PNG")
    with pytest.raises(ValueError, match="notes.png.*not an image"):
        load_bitmap(path)


# ------------------------------------------------------------------------------ array subclasses, handles, bytes
@pytest.mark.parametrize("image, invert, fill", [
    (np.ma.masked_array(gray_image(shape_mask()), mask=~shape_mask()), False, "255"),
    (np.ma.masked_array(gray_image(shape_mask())), False, "255"),          # nothing masked: still refused
    (np.ma.masked_array(gray_image(shape_mask(), 0.0, 1.0, np.float64)), False, "1.0"),
    (np.ma.masked_array(gray_image(shape_mask(), 0, 65535, np.uint16)), False, "65535"),
    (np.ma.masked_array(gray_image(shape_mask())), True, "0"),
    (np.ma.masked_array(shape_mask()), False, "False"),
    (np.ma.masked_array(shape_mask()), True, "True"),
])
def test_a_masked_array_is_refused_with_how_to_fill_it(image, invert, fill):
    """A masked array used to fail deep in the noise estimate ("cannot convert float NaN to integer") after numpy
    UserWarnings; now it is a TypeError saying how to fill the masked pixels as paper, and nothing else leaks."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(TypeError, match=rf"masked array.*image\.filled\({fill}\)"):
            load_bitmap(image, invert=invert)
    value = (fill == "True") if fill in ("True", "False") else float(fill)
    filled = image.filled(value)        # as the message says: then it loads
    np.testing.assert_array_equal(load_bitmap(filled, invert=invert), load_bitmap(np.asarray(filled), invert=invert))


def test_masked_array_dark_is_ink_wording():
    image = np.ma.masked_array(gray_image(shape_mask()), mask=~shape_mask())
    with pytest.raises(TypeError, match=r"image\.filled\(255\) to make them white paper \(dark is ink\)"):
        _to_gray(image)


def test_matrix_and_other_subclasses_are_read_as_plain_arrays(tmp_path):
    """np.matrix used to raise "only 0-dimensional arrays can be converted to Python scalars"."""
    mask = shape_mask()
    gray = gray_image(mask)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PendingDeprecationWarning)  # numpy's own, on making a matrix
        matrix = np.asmatrix(gray)
        bool_matrix = np.asmatrix(mask)
    np.testing.assert_array_equal(load_bitmap(matrix), mask)
    np.testing.assert_array_equal(load_bitmap(bool_matrix), mask)
    mapped = np.memmap(tmp_path / "gray.u8", dtype=np.uint8, mode="w+", shape=gray.shape)
    mapped[:] = gray
    np.testing.assert_array_equal(load_bitmap(mapped), mask)
    assert type(load_bitmap(mapped)) is np.ndarray
    del mapped


def _unclosed(path, load):
    """The ResourceWarnings about ``path`` raised while ``load()`` runs and its garbage is collected."""
    gc.collect()  # earlier garbage is not ours
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ResourceWarning)
        try:
            load()
        except ValueError:
            pass
        gc.collect()
    return [str(w.message) for w in caught if issubclass(w.category, ResourceWarning) and str(path) in str(w.message)]


@pytest.mark.filterwarnings("ignore::splinecraft.capture.image.MultiFrameWarning")  # tested on its own
@pytest.mark.parametrize("name, kwargs", [
    ("shape.gif", {}), ("shape.ico", {}), ("anim.gif", {}), ("pages.tif", {}), ("truncated.png", {}),
    ("truncated.gif", {}), ("shape.png", {"max_pixels": 10}), ("anim.gif", {"max_pixels": 10}),
])
def test_image_files_are_closed(tmp_path, name, kwargs):
    """GIF, ICO and multi-page files (kept open by PIL for seeking), truncated files and files over max_pixels
    used to leave their handle open (ResourceWarning: unclosed file)."""
    mask = shape_mask()
    frames = [Image.fromarray(gray_image(m)) for m in (mask, ~mask)]
    stem, suffix = name.split(".")
    path = tmp_path / name
    if stem == "truncated":
        full = tmp_path / f"full.{suffix}"
        frames[0].save(full, save_all=True, append_images=frames[1:])
        path.write_bytes(full.read_bytes()[: full.stat().st_size // 2])
    elif stem in ("anim", "pages"):
        frames[0].save(path, save_all=True, append_images=frames[1:])
    else:
        frames[0].save(path)
    assert _unclosed(path, lambda: load_bitmap(path, **kwargs)) == []
    with path.open("rb") as handle:  # a file object belongs to the caller: it stays open
        try:
            load_bitmap(handle, **kwargs)
        except ValueError:
            pass
        assert not handle.closed


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes")
def test_a_pipe_is_read_and_closed(tmp_path):
    """A path that is a pipe (the shell's ``<(...)``, ``/dev/stdin``: ``splinecraft trace <(curl ...)``) was read
    by PIL, which leaves the file it opened unclosed; the command line printed "warning: ResourceWarning:
    unclosed file <_io.BufferedReader name='/dev/fd/63'>" with every such trace."""
    import threading

    mask = shape_mask()
    png = io.BytesIO()
    Image.fromarray(gray_image(mask)).save(png, "PNG")
    path = tmp_path / "pipe"

    def load():
        os.mkfifo(path)
        writer = threading.Thread(target=path.write_bytes, args=(png.getvalue(),))
        writer.start()
        try:
            np.testing.assert_array_equal(load_bitmap(path), mask)
        finally:
            writer.join(timeout=10)
            path.unlink()

    assert _unclosed(path, load) == []


def test_a_path_given_as_bytes_says_to_pass_str(tmp_path):
    """Bytes are the encoded file, never a file name (they may come from an upload); a path given as bytes used
    to get just "image bytes (27 bytes): not an image file"."""
    path = tmp_path / "shape.png"
    Image.fromarray(gray_image(shape_mask())).save(path)
    for wrapped in (os.fsencode(path), bytearray(os.fsencode(path)), memoryview(os.fsencode(path)), b"shape.png"):
        with pytest.raises(ValueError, match=r"not an image file.*pass it as str or pathlib\.Path"):
            load_bitmap(wrapped)
    with pytest.raises(ValueError, match="not an image file") as caught:  # no hint where it cannot be a name
        load_bitmap(b"this is not an image at all")
    assert "pathlib" not in str(caught.value)


# ------------------------------------------------------------------------------ holes without edges, 0/1 masks
def _disc_on_paper(size, radius, paper, ink, hole_radius=0.0):
    """A disc of ink whose gray runs from ink[0] to ink[1] left to right, on paper running likewise (8-bit),
    with an optional paper counter at its centre; and the true mask."""
    rows, cols = np.mgrid[:size, :size] + 0.5
    distance = np.hypot(cols - size / 2, rows - size / 2)
    mask = (distance < radius) & (distance >= hole_radius)
    ramp = np.linspace(0.0, 1.0, size)[None, :]
    gray = np.where(mask, ink[0] + (ink[1] - ink[0]) * ramp, paper[0] + (paper[1] - paper[0]) * ramp)
    return np.rint(gray).astype(np.uint8), mask


@pytest.mark.parametrize("size, radius", [(64, 20), (256, 80), (512, 200)])
@pytest.mark.parametrize("paper, ink", [((200, 250), (20, 40)), ((120, 250), (10, 60)), ((250, 250), (10, 90))])
def test_a_dark_area_whose_ink_drifts_lighter_gets_no_hole(size, radius, paper, ink):
    """Inside a wide dark area the first (Sauvola) pass called the lighter ink paper, and the paper estimate
    taken there confirmed it: a hole of 25-55 % of the disc (11 of these 9 x 2 cases). A hole no edge bounds
    is ink now; the mask is the disc exactly."""
    gray, mask = _disc_on_paper(size, radius, paper, ink)
    np.testing.assert_array_equal(load_bitmap(gray, min_speck_area=0), mask)


@pytest.mark.parametrize("hole_radius", [3.0, 6.0, 30.0])
@pytest.mark.parametrize("paper, ink", [((200, 250), (10, 90)), ((150, 250), (20, 20))])
def test_a_true_counter_is_kept_under_the_same_drift(hole_radius, paper, ink):
    """A counter (paper inside the ink, as bright as the paper outside) has an edge: it stays a hole, small
    or large, blurred or not; and the ink around it stays ink. Around a small counter in a wide dark area
    the first pass called ink paper, even with ink of one gray (about 7 700 pixels wrong), and that stretch
    was one hole with the counter."""
    gray, mask = _disc_on_paper(256, 80, paper, ink, hole_radius=hole_radius)
    np.testing.assert_array_equal(load_bitmap(gray, min_speck_area=0), mask)
    blurred = np.rint(ndimage.gaussian_filter(gray.astype(float), 1.5)).astype(np.uint8)
    found = load_bitmap(blurred, min_speck_area=0)
    holes = ndimage.label(~found)[0]
    centre = holes[128, 128]
    assert centre != 0 and centre not in (holes[0, 0], holes[-1, -1])   # the counter is paper, not ink
    assert abs(int((holes == centre).sum()) - np.pi * hole_radius ** 2) <= 2 * np.pi * hole_radius + 8


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.int64])
def test_an_integer_array_of_zeros_and_ones_is_a_mask(dtype):
    """mask.astype(int): 1 is ink, as in the bool mask it came from; read as gray, 0 and 1 of 255 (or 65535)
    were two shades of black and every pixel became ink: a frame of 4 segments, silently."""
    rows, cols = np.mgrid[:64, :64]
    mask = np.hypot(cols - 32, rows - 32) < 20
    np.testing.assert_array_equal(load_bitmap(mask.astype(dtype)), mask)
    np.testing.assert_array_equal(load_bitmap(mask.astype(dtype), invert=True), ~mask)
    with pytest.warns(UserWarning, match="True pixels cover"):          # the background as 1: the bool rule
        np.testing.assert_array_equal(load_bitmap((~mask).astype(dtype)), ~mask)
    assert load_bitmap(mask.astype(dtype), threshold=0.5).all()          # an explicit threshold: gray, obeyed


def test_low_contrast_data_thresholded_into_ink_only_warns():
    """12-bit data in a 16-bit array span less than MIN_CONTRAST of 65535: the fixed level makes every pixel
    ink, and a warning says how to scale the data; scaled, the shape comes back."""
    rows, cols = np.mgrid[:64, :64]
    mask = np.hypot(cols - 32, rows - 32) < 20
    twelve_bit = np.where(mask, 300, 4000).astype(np.uint16)
    with pytest.warns(UserWarning, match=r"12-bit values in uint16\), scale them first"):
        assert load_bitmap(twelve_bit).all()
    np.testing.assert_array_equal(load_bitmap(twelve_bit / twelve_bit.max()), mask)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert not load_bitmap(np.full((20, 20), 250, np.uint8) - np.eye(20, dtype=np.uint8)).any()  # blank


def _lit_scan(size, seed):
    """A blurred, noisy, unevenly lit gray render (8-bit) of a ring and a bar, odd and even sides mixed."""
    rng = np.random.default_rng(seed)
    height, width = size, size + 1 + seed % 2
    rows, cols = np.mgrid[:height, :width] + 0.5
    distance = np.hypot(cols - 0.45 * width, rows - 0.55 * height)
    ink = ((distance < 0.3 * size) & (distance > 0.15 * size)) | ((np.abs(cols - 0.8 * width) < 4) & (rows > 10))
    gray = ndimage.gaussian_filter(np.where(ink, 0.05, 0.95), 1.5) + rng.normal(0.0, 0.03, ink.shape)
    lighting = 1.0 - 0.5 * (rows / height + cols / width) / 2
    return np.clip(np.rint(255 * gray * lighting), 0, 255).astype(np.uint8)


DIHEDRAL = {
    "rot90": (lambda a: np.rot90(a, 1), lambda a: np.rot90(a, -1)),
    "rot180": (lambda a: np.rot90(a, 2), lambda a: np.rot90(a, 2)),
    "rot270": (lambda a: np.rot90(a, 3), lambda a: np.rot90(a, -3)),
    "flipud": (np.flipud, np.flipud),
    "fliplr": (np.fliplr, np.fliplr),
    "transpose": (np.transpose, np.transpose),
}


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("name", sorted(DIHEDRAL))
def test_default_threshold_turns_with_the_image(name, seed):
    """A quarter turn, a flip or a transpose of a gray image turns its mask with it: the paper estimate's
    blocks, the noise estimate's windows and the speck area are placed symmetrically about the centre. (The
    blocks were anchored at the top-left corner: 1-3 pixels of such renders changed, and 12-100 of coins().)"""
    gray = _lit_scan(131 + 40 * seed, seed)
    forward, back = DIHEDRAL[name]
    turned = load_bitmap(np.ascontiguousarray(forward(gray)))
    np.testing.assert_array_equal(back(turned), load_bitmap(gray))


def test_noise_estimate_is_the_same_for_every_turn():
    gray = _lit_scan(151, 1)
    from splinecraft.capture._binarize import estimate_noise

    expected = estimate_noise(gray, 255)
    assert expected > 0.01
    for forward, _ in DIHEDRAL.values():
        assert estimate_noise(np.ascontiguousarray(forward(gray)), 255) == expected


def test_noise_estimate_reads_at_most_its_budget_of_windows(monkeypatch):
    """Above about 4 Mpx the 2 x 2 windows are read on a grid of rows and columns, at most about 4 M of them
    (a 12 Mpx page read every window: 12 M, three times the budget)."""
    from splinecraft.capture import _binarize

    for shape in ((3000, 4000), (2000, 2000), (5001, 3007), (300, 300)):
        stride = _binarize._window_stride(shape)
        count = len(_binarize._centred_starts(shape[0] - 1, stride)) * len(_binarize._centred_starts(shape[1] - 1, stride))
        assert count <= 1.1 * (1 << 22)
        assert stride == 1 or count >= (1 << 22) / 8


def _text_page(light_on_dark, size=(160, 240)):
    """Bars of 'text' on paper with a little noise: dark on light, or light on dark."""
    ink = np.zeros(size, bool)
    for row in range(20, size[0] - 20, 24):
        for col in range(16, size[1] - 16, 18):
            ink[row:row + 12, col:col + 10] = True
    ink_level, paper_level = (0.85, 0.08) if light_on_dark else (0.08, 0.85)
    gray = np.where(ink, ink_level, paper_level) + np.random.default_rng(0).normal(0, 0.01, size)
    return np.clip(gray * 255, 0, 255).round().astype(np.uint8), ink


@pytest.mark.parametrize("threshold", [None, "otsu", "sauvola", 0.5])
def test_light_on_dark_gray_image_warns_where_the_call_is(threshold):
    import splinecraft as sc

    negative, ink = _text_page(True)
    with pytest.warns(InkPolarityWarning, match="invert=True") as record:
        load_bitmap(negative, threshold=threshold)
    assert record[0].filename == __file__  # the user's line, not the package's
    assert record[0].message.border_share == 1.0
    with pytest.warns(InkPolarityWarning) as record:
        sc.trace(negative, threshold=threshold)
    assert record[0].filename == __file__
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_array_equal(load_bitmap(negative, threshold="otsu", invert=True), ink)
        positive, ink = _text_page(False)
        np.testing.assert_array_equal(load_bitmap(positive, threshold="otsu"), ink)


@pytest.mark.parametrize("mode", ["RGBA", "LA", "P"])  # P: a palette with a transparent entry
def test_alpha_threshold_traces_a_white_logo_on_a_transparent_background(tmp_path, mode):
    """A white logo made for dark pages vanishes when composited on white paper; threshold="alpha" traces
    its opaque pixels, from a file, bytes, a PIL image or an array."""
    import splinecraft as sc

    logo = shape_mask()
    rgba = np.zeros(logo.shape + (4,), np.uint8)
    rgba[..., :3] = 255                                     # white everywhere, opaque only on the logo
    rgba[..., 3] = np.where(logo, 255, 0)
    image = Image.fromarray(rgba, "RGBA")
    if mode != "RGBA":
        image = image.convert(mode)
    path = tmp_path / "logo.png"
    image.save(path)
    with pytest.raises(ValueError, match="threshold='alpha'"):
        sc.trace(path)                                      # the hint names the way out
    for source in (path, path.read_bytes(), Image.open(path)):
        np.testing.assert_array_equal(load_bitmap(source, threshold="alpha"), logo)
    np.testing.assert_array_equal(load_bitmap(rgba, threshold="alpha"), logo)
    np.testing.assert_array_equal(load_bitmap(rgba[..., [0, 3]], threshold="alpha"), logo)
    half = rgba.astype(np.float64) / 255
    half[..., 3] *= 0.6                                     # 60 % opaque is still ink, 40 % not
    np.testing.assert_array_equal(load_bitmap(half, threshold="alpha"), logo)
    half[..., 3] *= 0.4 / 0.6
    assert not load_bitmap(half, threshold="alpha").any()


@pytest.mark.parametrize("source", [np.zeros((8, 8), np.uint8), np.zeros((8, 8, 3), np.uint8),
                                    Image.new("RGB", (8, 8))])
def test_alpha_threshold_without_an_alpha_channel_is_a_clear_error(source):
    with pytest.raises(ValueError, match="has no alpha channel"):
        load_bitmap(source, threshold="alpha")


def test_max_pixels_above_pils_own_limit_loads(tmp_path, monkeypatch):
    """PIL refuses images over twice its MAX_IMAGE_PIXELS before we see them; a max_pixels above that limit
    must still load the image (and leave PIL's limit as it was), one below it must name max_pixels."""
    mask = shape_mask()
    path = tmp_path / "shape.png"
    Image.fromarray(gray_image(mask)).save(path)
    data = path.read_bytes()
    monkeypatch.setattr(Image, "MAX_IMAGE_PIXELS", mask.size // 4)   # PIL errors above mask.size // 2
    for source in (path, data):
        with pytest.raises(Image.DecompressionBombError):
            Image.open(source if isinstance(source, os.PathLike) else io.BytesIO(source))
        np.testing.assert_array_equal(load_bitmap(source, max_pixels=mask.size), mask)
        assert Image.MAX_IMAGE_PIXELS == mask.size // 4
        with pytest.raises(ValueError, match=r"more than max_pixels=.*pass a larger max_pixels"):
            load_bitmap(source, max_pixels=mask.size // 3)
        assert Image.MAX_IMAGE_PIXELS == mask.size // 4


def _mpo_bytes(pictures, mp_types):
    """An MPO file (CIPA DC-007: a camera JPEG with further pictures) of ``pictures`` whose MP entries have the MP
    types ``mp_types`` (PIL writes 'Baseline MP Primary Image' and 'Undefined'; the entries are patched)."""
    import struct

    buffer = io.BytesIO()
    pictures[0].save(buffer, "MPO", save_all=True, append_images=pictures[1:], quality=95)
    data = buffer.getvalue()
    with Image.open(io.BytesIO(data)) as img:
        assert img.format == "MPO"
        entries = img.mpinfo[0xB002]
    for index, (entry, mp_type) in enumerate(zip(entries, mp_types)):
        written = 0x030000 if index == 0 else 0
        old = struct.pack("<LLLHH", written, entry["Size"], entry["DataOffset"], 0, 0)
        assert data.count(old) == 1
        data = data.replace(old, struct.pack("<LLLHH", mp_type, entry["Size"], entry["DataOffset"], 0, 0))
    return data


def test_a_camera_jpeg_with_a_preview_is_one_picture(tmp_path):
    """A camera's JPEG holds its photo and a "large thumbnail" for its own screen (an MPO file, the Multi-Picture
    Format): PIL counts 2 frames, and a MultiFrameWarning said 'the file has 2 frames (an animated or multi-page
    image)' of one photo. The preview is not a frame of the picture: the primary picture is traced without a
    warning. A stereo pair (disparity) has two pictures: it still warns."""
    import splinecraft as sc
    from splinecraft.capture.image import MultiFrameWarning

    mask = shape_mask(80, 100)
    photo = Image.fromarray(gray_image(mask))
    preview = photo.resize((50, 40))
    primary, vga_preview, hd_preview, disparity = 0x030000, 0x010001, 0x010002, 0x020002
    for types in ((primary, vga_preview), (primary, hd_preview)):
        data = _mpo_bytes([photo, preview], types)
        with Image.open(io.BytesIO(data)) as img:
            assert img.n_frames == 2
        path = tmp_path / "camera.jpg"
        path.write_bytes(data)
        for source in (path, data):
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                traced = load_bitmap(source)
            assert traced.shape == mask.shape
            assert not ((traced != mask) & ~edge_band(mask)).any()  # the photo, not the preview (JPEG: edges differ)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            assert sc.trace(path).stats["boundaries"] == 3
    stereo = _mpo_bytes([photo, Image.fromarray(gray_image(np.roll(mask, 3, axis=1)))], (disparity, disparity))
    with pytest.warns(MultiFrameWarning, match="2 frames") as caught:
        load_bitmap(stereo)
    assert caught[0].message.frames == 2
    three = _mpo_bytes([photo, photo, preview], (disparity, disparity, vga_preview))
    with pytest.warns(MultiFrameWarning, match="2 frames"):
        load_bitmap(three)


def test_an_empty_file_says_it_is_empty(tmp_path):
    """A 0-byte file (a failed download or copy) was 'not an image file (PIL cannot identify its format)', as if
    it held another format; empty bytes already said 'image bytes are empty'. The file says so too, on every
    path to it (trace, trace_many's failed record)."""
    import splinecraft as sc

    path = tmp_path / "scan 1.png"
    path.write_bytes(b"")
    with pytest.raises(ValueError) as caught:
        load_bitmap(path)
    assert str(caught.value) == f"{path}: the file is empty (0 bytes), not an image"
    with pytest.raises(ValueError, match=r"the file is empty \(0 bytes\)"):
        sc.trace(str(path))
    (record,) = sc.trace_many([str(path)], progress=False)
    assert record.status == "failed" and "the file is empty (0 bytes)" in record.error
