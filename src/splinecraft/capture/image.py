"""Bitmap loading and binarization: image file / array / PIL image -> bool ink mask.

The first step of outline capture (thesis section 4.1.1, "Finding boundary of planar object"): the scanned or
drawn image becomes a two-level bitmap whose ``True`` pixels are the shape ("ink"). Pixel frame as in
docs/capture.md: row ``r``, column ``c`` covers ``[c, c+1] x [r, r+1]`` (x right, y down).

Conventions
-----------
* **Gray scale.** Every input is reduced to one gray channel on the scale ``0 = black .. 1 = white``:
  8-bit values are divided by 255, 16-bit values by 65535, float arrays must already lie in
  ``[0, 1]``. A 32-bit float PIL image (mode ``"F"``, e.g. a float TIFF) may be on PIL's 8-bit scale: values
  in ``[0, 1]`` are read as for an array, others in ``[0, 255]`` are divided by 255. Colour uses the ITU-R 601 luma ``0.299 R + 0.587 G + 0.114 B`` (the weights of
  PIL's ``convert("L")``, rounded the same way for 8-bit data). Transparency is composited on
  **white** paper, so a black shape on a transparent background is ink; that includes the transparent colour
  of a gray, 16-bit or RGB PNG (its ``tRNS`` chunk): pixels of that colour are paper, as a viewer shows them.
* **Ink is dark** by default: ``ink = gray <= threshold``; ``invert=True`` makes light pixels ink.
  ``threshold="alpha"`` reads the opacity instead: a pixel at least half opaque is ink, whatever its colour
  (a white logo on a transparent background, which compositing on white would erase).
* **Threshold.** ``"background"`` (half way between the paper and the ink under the local lighting: the
  paper's brightness is estimated across the image, so uneven lighting and strokes of any width are
  followed), ``"otsu"`` (global, Otsu's method), ``"sauvola"`` or ``"local"`` (a level per pixel from a
  window) or a fraction of white in ``[0, 1]`` (for an 8-bit gray level ``g`` pass ``g / 255``);
  ``None`` (default) is ``DEFAULT_THRESHOLD`` (``"background"``). When the image has too little contrast for any
  of the methods to mean anything (``max - min < MIN_CONTRAST`` of full scale, e.g. a blank page with JPEG
  noise, or a uniform image) the fixed mid-gray threshold ``0.5`` is used instead, so an all-white image
  has no ink and an all-black image is all ink. When that makes every pixel of an image that does have two
  gray levels ink (12-bit data in a 16-bit array), a ``UserWarning`` says so and how to scale it. The methods, their window and the measurement behind the
  default are in :mod:`splinecraft.capture._binarize`.
* **Bool arrays** are masks already (``True`` = ink); only ``invert`` applies to them. So is a 2-D **integer
  array of 0 and 1 only** (``mask.astype(np.uint8)``, a label image) when ``threshold`` is ``None``: ``1`` = ink,
  as for the bool mask it came from (read as gray, ``0`` and ``1`` of 255 are two shades of black); with an
  explicit ``threshold`` it is gray. When more than three
  quarters of the border pixels are ``True`` and ``True`` touches all four borders, the mask most likely has its
  background as ``True`` (``skimage.data.horse()`` does): an :class:`InkPolarityWarning` (a ``UserWarning``) says so and how to flip it
  (``invert=True`` or ``~mask``); the mask is still used as given.
* **Light on dark** gray images (a negative scan, a dark-mode screenshot, ``skimage.data.coins()``): ink is
  dark, so their background is the shape. When more than three quarters of the border pixels are darker than
  the image's Otsu level (on at most about a million pixels, evenly spread) and dark pixels lie on all four
  borders, the same :class:`InkPolarityWarning` says so and that ``invert=True`` traces the light shapes
  (unless ``invert`` is given). The threshold is applied as asked.
* **Specks.** ``min_speck_area=k`` removes ink components *and* holes (background components not touching
  the image border) with fewer than ``k`` pixels; ink components use the tracer's ``connectivity``, holes
  the complementary one. ``None`` (default) sets ``k`` from the image's noise estimate (the rule is in
  :mod:`~splinecraft.capture._binarize`): 0 for clean images, for bool masks and for images of two gray
  levels (1-bit files, masks saved as 0/255: they carry no gray noise, and a fine pattern such as a
  checkerboard would read as noise), so a single-pixel shape survives; ``0`` removes nothing.
* **Size cap.** Image files, encoded bytes and PIL images are measured from their header before any pixel
  is decoded: more than ``max_pixels`` pixels (default ``MAX_PIXELS`` = 10^8, e.g. 10 000 x 10 000) is a
  ``ValueError``, so a small file that decodes to a huge image (a decompression bomb) costs nothing.
  PIL's own bomb limit (``PIL.Image.MAX_IMAGE_PIXELS``) is raised to ``max_pixels`` while such a file is
  opened when ``max_pixels`` is larger, so ``max_pixels`` is the one cap that decides.
  Numpy arrays are already in memory and are not capped.
* **Bytes** (``bytes``, ``bytearray``, ``memoryview``) are an encoded image file (PNG, JPEG, ...), as read
  from disk or received from a page. They are never read as a file name, even when they spell one (bytes
  may come from an upload, and reading them as a path would let the data pick a file on this machine): a
  path given as bytes is a ``ValueError`` ("not an image file"); when the bytes look like a file name (text
  with a directory separator or an extension; the file system is not consulted) the message says to pass
  it as ``str`` or ``pathlib.Path`` (``os.fsdecode(path)``).
* **Array subclasses.** ``np.matrix``, ``np.memmap`` and other ``ndarray`` subclasses are read as the plain
  array they hold (``np.asarray``). A numpy **masked array** is a ``TypeError``: a masked pixel has no gray level,
  and which one it stands for is the caller's choice. Fill the masked pixels first, usually as
  paper: ``image.filled(255)`` for 8-bit data, ``image.filled(1.0)`` for float (``0`` with ``invert=True``),
  ``mask.filled(False)`` for a bool mask.
* **Files** are closed when loading returns or fails (files PIL opened from a path, and a path that is a pipe,
  such as the shell's ``<(...)``, read whole first; a file object passed in stays open, it belongs to the
  caller). A **PIL image** reads its pixels from its file when first asked (PIL loads lazily): one opened in a
  ``with Image.open(...)`` block and passed after it has lost them, a ``ValueError`` that says so (load it in
  the block, ``img.load()``, or pass the path), as for a truncated file.
* **Multi-frame files** (animated GIF, PNG or WebP, multi-page TIFF) given as a path, bytes or a file object: the
  first frame is used, and a :class:`MultiFrameWarning` says so, with the file's frame count and how to trace
  another frame (open the file with PIL, ``img.seek(k)``, and pass ``img``). A PIL image is used at the frame it
  is at (its owner chose it with ``seek``), without a warning. A file whose frames cannot be counted (cut short
  or damaged after its first frame: PIL reads every frame's header to count them) is traced from its first frame
  when that one is whole, with a :class:`MultiFrameWarning` that says so (``frames`` is ``None``). A Photoshop
  file's layers are not frames: its composite picture is traced (:data:`LAYERED_FORMATS`). Nor is the preview a camera
  embeds in its JPEG (an MPO file: the primary picture and a "large thumbnail", :data:`MPO_PREVIEW_TYPES`): the
  primary picture is traced without a warning; an MPO's other pictures (a stereo pair) are frames.

Memory: 8-bit and 16-bit data stay in their integer type (colour conversion and compositing are done in
row blocks), so an 8000 x 8000 8-bit image needs about 64 MB for the gray channel and 64 MB for the mask.
"""
from __future__ import annotations

import contextlib
import io
import numbers
import os
import stat
import sys
import threading
import warnings
from typing import NamedTuple

import numpy as np

from . import _binarize
from .contour import check_connectivity
from ._binarize import DEFAULT_THRESHOLD, FALLBACK_THRESHOLD, MIN_CONTRAST, THRESHOLD_METHODS

__all__ = ["load_bitmap", "MIN_CONTRAST", "FALLBACK_THRESHOLD", "THRESHOLD_METHODS", "DEFAULT_THRESHOLD",
           "MAX_PIXELS"]

#: Largest image (pixels) decoded from a file, bytes or a PIL image; adjustable per call (``max_pixels=``).
MAX_PIXELS = 100_000_000

# Rows per block for colour conversion / compositing (bounds the temporaries to ~ block * width).
_BLOCK_ROWS = 512

# PIL modes that np.asarray turns into a single gray channel directly.
_GRAY_MODES = {"L", "I;16", "I;16L", "I;16B", "I;16N", "I", "F"}


# ---------------------------------------------------------------------------------------------------
# public API
# ---------------------------------------------------------------------------------------------------
def load_bitmap(image, *, threshold=None, invert=False, min_speck_area=None, connectivity=8,
                max_pixels=MAX_PIXELS) -> np.ndarray:
    """Binarize an image into a bool ink mask ``(H, W)`` (thesis section 4.1.1; docs/capture.md).

    Parameters
    ----------
    image : str | os.PathLike | bytes | file object | numpy.ndarray | PIL.Image.Image
        A path or binary file object of a PNG, JPEG, BMP, GIF or TIFF file (anything PIL reads), or the
        encoded file itself as ``bytes`` (turned by its EXIF orientation tag, as a viewer shows it; of a file
        with several frames, an animated GIF or a multi-page TIFF, the first frame, with a
        :class:`MultiFrameWarning`: for another frame ``k`` pass the PIL image after ``img.seek(k)``); an array of shape ``(H, W)`` (bool mask, or gray), ``(H, W, 1)``,
        ``(H, W, 2)`` (gray + alpha), ``(H, W, 3)`` (RGB) or ``(H, W, 4)`` (RGBA) with dtype bool (2-D only),
        uint8, uint16, another integer type with values in ``[0, 255]``, or float in ``[0, 1]``; or a PIL
        image of any mode. Bytes are always the encoded file, never a file name (pass a path as ``str`` or
        ``pathlib.Path``). An ``ndarray`` subclass (``np.matrix``, ``np.memmap``) is read as ``np.asarray``
        of it; a masked array is refused (fill it first, e.g. ``image.filled(255)``: masked pixels become
        paper).
    threshold : {"background", "otsu", "sauvola", "local"} or float in [0, 1], optional
        How ink (``gray <= level``) is told from paper: the midpoint between the local paper brightness and
        the ink, Otsu's global level, a per-pixel Sauvola or local level, or a fixed fraction of white. ``None``: ``DEFAULT_THRESHOLD``. Images with less than
        ``MIN_CONTRAST`` contrast use ``FALLBACK_THRESHOLD``. Not allowed for bool masks.
    invert : bool, optional
        Light pixels are ink (white shape on black), or, for a bool mask, ``False`` pixels are ink.
    min_speck_area : int >= 0 or None, optional
        Remove ink specks and fill holes with fewer than this many pixels (0 = keep everything). ``None``:
        from the image's noise estimate (0 for clean images and bool masks; module docstring).
    connectivity : {4, 8, "minority"}, optional
        Connectivity of ink components for speck removal (holes use the complementary one; ``"minority"``
        counts as 8 here); pass the value the boundary tracer will use.
    max_pixels : int >= 1, optional
        Largest image decoded from a file, bytes or PIL image (checked on the header, before decoding).

    Returns
    -------
    numpy.ndarray of bool, shape (H, W)
        ``True`` = ink.

    Raises
    ------
    FileNotFoundError
        The path does not exist.
    ValueError
        A file or bytes that are not an image, are truncated or corrupt (the message names the file); an
        image over ``max_pixels``; an empty array, wrong number of dimensions or channels, NaN/inf or
        out-of-range values; a bad threshold.
    TypeError
        Unsupported input type or dtype, a numpy masked array, or a non-bool ``invert``.
    """
    return load_bitmap_reporting_specks(image, threshold=threshold, invert=invert, min_speck_area=min_speck_area,
                                        connectivity=connectivity, max_pixels=max_pixels)[0]


def load_bitmap_reporting_specks(image, *, threshold=None, invert=False, min_speck_area=None, connectivity=8,
                                 max_pixels=MAX_PIXELS):
    """:func:`load_bitmap`, and a :class:`SpecksRemovedAllInk` when speck removal left no ink pixel of an
    image that had some (else ``None``): ``(mask, removed)``. :func:`~splinecraft.capture.trace.trace` says so
    instead of "no ink after thresholding"."""
    threshold = _binarize.check_threshold(threshold)
    if not isinstance(invert, (bool, np.bool_)):
        raise TypeError(f"invert must be a bool, got {type(invert).__name__}")
    if min_speck_area is not None:
        min_speck_area = _check_count(min_speck_area, "min_speck_area")
    connectivity = check_connectivity(connectivity)
    max_pixels = _check_count(max_pixels, "max_pixels")

    if isinstance(image, np.ndarray):
        image = _plain_array(image, invert)
        if threshold is None and _is_zero_one_mask(image):
            image = image.astype(bool)  # mask.astype(np.uint8): a mask, not a nearly black gray image
    if isinstance(image, np.ndarray) and image.dtype == bool:
        if image.ndim != 2:
            raise ValueError(f"a bool mask must be 2-D (H, W), got shape {image.shape}")
        _check_not_empty(image.shape)
        if threshold is not None:
            raise ValueError("threshold does not apply to a bool mask (it is already binary); pass threshold=None")
        mask = np.array(image, dtype=bool, order="C")
        if not invert:
            _warn_if_inverted(mask)
        speck = min_speck_area or 0
    else:
        gray, white = _to_gray(image, max_pixels, alpha=threshold == "alpha")
        level = _binarize.threshold_level(gray, white, threshold)
        mask = np.ascontiguousarray(gray <= level)
        _warn_if_flat(gray, white, threshold, mask)
        if not invert and threshold != "alpha":
            _warn_if_light_on_dark(gray, white)
        speck = min_speck_area
        if speck is None and not _two_levels(gray):  # a 1-bit image carries no gray level: 0, as for a mask
            speck = _binarize.auto_speck_area(gray, white, level, mask, _binarize.estimate_noise(gray, white))
        elif speck is None:
            speck = 0
        del gray, level
    if invert:
        np.logical_not(mask, out=mask)
    removed = None
    if speck > 1:
        ink = mask
        mask = _binarize.remove_specks(mask, speck, 4 if connectivity == 4 else 8)
        if not mask.any() and ink.any():
            removed = SpecksRemovedAllInk.measure(ink, speck, 4 if connectivity == 4 else 8,
                                                  estimated=min_speck_area is None)
    return mask, removed


class SpecksRemovedAllInk(NamedTuple):
    """Speck removal took every ink pixel of an image: ``ink`` pixels in all, ``largest`` of them in its
    largest ink component, all below ``min_area``, which the caller gave (``estimated=False``) or the noise
    estimate set (``min_speck_area=None``)."""

    min_area: int
    ink: int
    largest: int
    estimated: bool

    @classmethod
    def measure(cls, ink, min_area, connectivity, estimated):
        from scipy import ndimage

        labels, count = ndimage.label(ink, structure=ndimage.generate_binary_structure(2, 2 if connectivity == 8
                                                                                          else 1))
        largest = int(np.bincount(labels.reshape(-1), minlength=count + 1)[1:].max())
        return cls(int(min_area), int(ink.sum()), largest, bool(estimated))

    def message(self) -> str:
        """One line: what was removed, why, and the ``min_speck_area`` that keeps the largest component."""
        if self.estimated:
            why = (f"specks of fewer than {self.min_area} pixels, a size estimated from the image's noise since "
                   "min_speck_area is not given")
            advice = f"pass min_speck_area={self.largest} or less to keep it, or 0 to keep every pixel"
        else:
            why = f"min_speck_area={self.min_area} removes ink components of fewer than {self.min_area} pixels"
            advice = f"lower min_speck_area to {self.largest} or less to keep it"
        return (f"no shape found: speck removal removed all {self.ink} ink pixels ({why}; the largest ink component "
                f"has {self.largest} pixels): {advice}")


class InkPolarityWarning(UserWarning):
    """A bool mask whose True pixels fill its border, or a gray image whose border is dark: the ink may be
    inverted. ``border_share`` is the share (0..1) of border pixels that are True (dark)."""

    def __init__(self, message, border_share):
        super().__init__(message)
        self.border_share = float(border_share)


def _warn_if_inverted(mask):
    """Warn when a bool mask looks like True = background (module docstring, "Bool arrays")."""
    if not (mask[0].any() and mask[-1].any() and mask[:, 0].any() and mask[:, -1].any()):
        return  # does not touch every side (the usual case: the border is gathered only where it does)
    border = np.concatenate([mask[0], mask[-1], mask[1:-1, 0], mask[1:-1, -1]])
    if 4 * int(border.sum()) > 3 * border.size and not mask.all():
        share = border.mean()
        _warn(InkPolarityWarning(
            f"the mask's True pixels cover {100 * share:.0f}% of its border and touch every side: "
            "True is ink here, so the background may be the traced shape; if True marks the background, "
            "pass invert=True (or ~mask)", share))


#: Formats whose PIL "frames" (``n_frames``) are the layers of one picture, numbered from 1, not pictures of their
#: own: such a file opens at its composite picture (what a viewer shows), which is traced, without a
#: :class:`MultiFrameWarning` (``seek(0)`` asked a layered Photoshop file for a frame it does not have).
LAYERED_FORMATS = ("PSD",)
#: MP types (CIPA DC-007, the Multi-Picture Format of camera JPEGs, PIL's format ``"MPO"``) of the pictures that are
#: a preview of the primary picture, not pictures of their own: a camera writes its photo with one "large
#: thumbnail" for its own screen. A file whose other pictures are all previews is one picture, traced without a
#: :class:`MultiFrameWarning`; a stereo pair (disparity), a panorama's or multi-angle set's pictures are frames.
MPO_PREVIEW_TYPES = ("Large Thumbnail (VGA Equivalent)", "Large Thumbnail (Full HD Equivalent)")


class MultiFrameWarning(UserWarning):
    """An image file (path, bytes or file object) with several frames, an animated GIF, PNG or WebP or a
    multi-page TIFF: only one frame is traced. ``frames`` is the file's frame count (``None``: they could not be
    counted, the file is truncated or corrupt after its first frame, which was traced), ``frame`` the index of the
    frame traced (0, the first). To trace frame ``k``: ``img = PIL.Image.open(file); img.seek(k)`` and pass
    ``img`` (a PIL image is traced at the frame it is at)."""

    def __init__(self, message, frames, frame=0):
        super().__init__(message)
        self.frames = None if frames is None else int(frames)
        self.frame = int(frame)


def _warn_if_several_frames(name, frames, uncounted=None):
    """Say that only the first of the ``frames`` frames of image file ``name`` is traced (module docstring,
    "Multi-frame files"); ``frames`` is ``None`` when counting them failed with ``uncounted``."""
    if frames is None:
        _warn(MultiFrameWarning(
            f"{name}: its frames could not be counted (the file is truncated or corrupt after its first frame: "
            f"{type(uncounted).__name__}: {_short(str(uncounted), 80)}); traced frame 0 (the first), which is whole",
            None, 0))
    elif frames > 1:
        _warn(MultiFrameWarning(
            f"{name}: the file has {frames} frames (an animated or multi-page image); traced frame 0 (the first) "
            "only. To trace frame k, pick it with PIL and pass the image: img = PIL.Image.open(file); "
            "img.seek(k); trace(img)", frames, 0))


def _warn(warning):
    """``warnings.warn`` pointing at the first frame outside this package (the user's call of ``sc.trace``,
    ``load_bitmap``, a widget ...), whichever path inside the package led here."""
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    frame, level = sys._getframe(1), 2  # stacklevel 2: the frame that called _warn
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(package + os.sep):
        frame, level = frame.f_back, level + 1
    warnings.warn(warning, stacklevel=level)


#: The polarity test of gray images reads at most about this many pixels for the Otsu level.
_POLARITY_SAMPLE = 1 << 20


def _warn_if_light_on_dark(gray, white):
    """Warn when a gray image looks like light shapes on a dark background (module docstring, "Light on
    dark"): its border mostly below the image's Otsu level, dark on every side."""
    from skimage.filters import threshold_otsu

    if min(gray.shape) < 3:
        return
    step = max(1, int(np.ceil(np.sqrt(gray.size / _POLARITY_SAMPLE))))
    sample = gray[::step, ::step]
    lo, hi = sample.min(), sample.max()
    if float(hi) - float(lo) < _binarize.MIN_CONTRAST * white:
        return
    level = threshold_otsu(sample)
    sides = (gray[0], gray[-1], gray[1:-1, 0], gray[1:-1, -1])
    dark = [side <= level for side in sides]
    count, total = sum(int(d.sum()) for d in dark), sum(d.size for d in dark)
    if 4 * count > 3 * total and all(d.any() for d in dark):
        share = count / total
        _warn(InkPolarityWarning(
            f"{100 * share:.0f}% of the image's border is darker than its Otsu level ({float(level) / white:.2f} "
            "of white): dark is ink, so a dark background may be traced as the shape; if the shapes are light on "
            "dark, pass invert=True", share))


# ---------------------------------------------------------------------------------------------------
# validation helpers
# ---------------------------------------------------------------------------------------------------
def _is_zero_one_mask(image):
    """A 2-D integer array holding 0 and 1 only (and both): a mask as ``mask.astype(int)`` makes it."""
    if image.ndim != 2 or image.dtype.kind not in "iu" or image.size == 0:
        return False
    lo, hi = image.min(), image.max()
    return lo == 0 and hi == 1


def read_pipe(path):
    """The bytes of ``path`` when it names a pipe (the shell's ``<(...)``, ``/dev/stdin``), read whole and
    closed: a pipe can be read only once. ``None`` for anything else (a file, a missing path)."""
    try:
        if not stat.S_ISFIFO(os.stat(path).st_mode):
            return None
    except (OSError, ValueError):
        return None
    with open(path, "rb") as stream:
        return stream.read()


def _two_levels(gray):
    """The gray image holds at most two distinct values (a 1-bit image, or a mask saved as 0/255). Its noise
    estimate then measures the pattern, not noise: on a checkerboard or a halftone every 2 x 2 window straddles
    an edge. Read in row blocks, stopping at the first block with a third value."""
    lo, hi = gray.min(), gray.max()
    for start in range(0, gray.shape[0], _BLOCK_ROWS):
        block = gray[start:start + _BLOCK_ROWS]
        if not ((block == lo) | (block == hi)).all():
            return False
    return True


def _warn_if_flat(gray, white, threshold, mask):
    """Warn when a gray image with some contrast, but less than ``MIN_CONTRAST`` of white, was thresholded at
    the fixed ``FALLBACK_THRESHOLD`` into ink only (module docstring, "Threshold"): e.g. 12-bit data in a
    16-bit array, whose gray range is below 7 % of 65535. (Paper only is a blank page with some noise.)"""
    if not (threshold is None or isinstance(threshold, str)) or not mask.all():
        return
    lo, hi = float(gray.min()), float(gray.max())
    if lo == hi or hi - lo >= _binarize.MIN_CONTRAST * white:
        return
    _warn(UserWarning(
        f"the image's gray levels span {lo:g}-{hi:g} of white = {white:g} ({100 * (hi - lo) / white:.1f}%), "
        f"less than the {100 * _binarize.MIN_CONTRAST:.0f}% any threshold method needs, so the fixed level "
        f"{_binarize.FALLBACK_THRESHOLD:g} of white made every pixel ink; if the "
        "data use fewer bits than their dtype (e.g. 12-bit values in uint16), scale them first (image / "
        "image.max()), or pass threshold= as a fraction of white"))


def _check_count(value, name):
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be a non-negative int, got {type(value).__name__}")
    if value < 0:
        raise ValueError(f"{name} must be >= 0, got {value}")
    return int(value)


def _plain_array(image, invert):
    """``image`` as a plain ndarray (module docstring, "Array subclasses"); a masked array is a TypeError
    saying how to fill it."""
    if isinstance(image, np.ma.MaskedArray):
        if image.dtype.kind == "b":
            fill, means = ("True", "background (False is ink with invert=True)") if invert else \
                ("False", "background (True is ink)")
        else:
            white = "1.0" if image.dtype.kind == "f" else "65535" if image.dtype == np.uint16 else "255"
            fill, means = ("0", "black paper (light is ink with invert=True)") if invert else \
                (white, "white paper (dark is ink)")
        raise TypeError(
            "image is a numpy masked array, which is not supported (a masked pixel has no gray level to "
            f"threshold): fill the masked pixels first, e.g. image.filled({fill}) to make them {means}, and "
            "pass the filled array")
    if type(image) is not np.ndarray:  # np.matrix, np.memmap, ...: the plain array they hold
        image = np.asarray(image)
    return image


def _check_not_empty(shape):
    if len(shape) < 2 or shape[0] == 0 or shape[1] == 0:
        raise ValueError(f"image is empty (shape {shape}); it needs at least one pixel")


# ---------------------------------------------------------------------------------------------------
# input -> (gray array, white value)
# ---------------------------------------------------------------------------------------------------
def _to_gray(image, max_pixels=MAX_PIXELS, alpha=False):
    """Return ``(gray, white)``: a 2-D numeric array and the value that means white. With ``alpha`` the gray
    is the transparency, ``white - alpha`` (opaque is black), for ``threshold="alpha"``."""
    from PIL import Image

    if isinstance(image, Image.Image):
        _check_size(image, "PIL image", max_pixels)
        load_pil_pixels(image, "PIL image")
        return _pil_to_gray(image, name="PIL image", alpha=alpha)
    if isinstance(image, (bytes, bytearray, memoryview)):
        data = bytes(image)
        if not data:
            raise ValueError("image bytes are empty; pass the bytes of an encoded image file (PNG, JPEG, ...)")
        name = f"image bytes ({len(data)} bytes)"
        img = _open_image_file(io.BytesIO(data), name=name, max_pixels=max_pixels, hint=_path_hint(data))
        return _pil_to_gray(img, name=name, alpha=alpha)
    if isinstance(image, (str, os.PathLike)):
        return _pil_to_gray(_open_image_file(image, max_pixels=max_pixels), name=os.fsdecode(image), alpha=alpha)
    if isinstance(image, (io.IOBase,)) or (hasattr(image, "read") and hasattr(image, "seek")):
        name = getattr(image, "name", "image file object")
        return _pil_to_gray(_open_image_file(image, name=str(name), max_pixels=max_pixels), name=str(name),
                            alpha=alpha)
    if isinstance(image, np.ndarray):
        return _array_to_gray(_plain_array(image, False), alpha=alpha)
    raise TypeError(
        "image must be a path, a binary file object, a numpy array or a PIL image, "
        f"got {type(image).__name__}"
    )


def load_pil_pixels(img, name):
    """Decode the pixels of a PIL image passed in (PIL loads them lazily, from its file); its failures become a
    ValueError naming the image: a file closed before the pixels were loaded (PIL's bare ``AssertionError``: an
    image opened in a ``with Image.open(...)`` block and used after it), truncated data, a closed image."""
    try:
        img.load()
    except MemoryError:
        raise
    except Exception as exc:
        if isinstance(exc, (AssertionError, AttributeError)) and getattr(img, "fp", False) is None:
            raise ValueError(f"{name}: its pixels were never loaded and its file is closed (PIL reads them lazily: "
                             "an image opened in a `with Image.open(...)` block must be loaded in it, img.load(), "
                             "or pass the file's path)") from None
        if isinstance(exc, (OSError, SyntaxError, EOFError)):
            raise ValueError(f"{name}: truncated or corrupt image ({type(exc).__name__}: {exc})") from None
        raise ValueError(f"{name}: cannot read its pixels ({type(exc).__name__}: {exc})") from None


def _check_size(img, name, max_pixels):
    """Refuse an image whose header says it has more than ``max_pixels`` pixels (nothing decoded yet)."""
    pixels = int(img.width) * int(img.height)
    if pixels > max_pixels:
        raise ValueError(
            f"{name}: {img.width} x {img.height} = {pixels} pixels is more than max_pixels={max_pixels} "
            "(checked before decoding; pass a larger max_pixels to load it anyway)")


#: Longest bytes that can be a file name worth a hint (PATH_MAX of Linux).
_PATH_BYTES = 4096


def _path_hint(data):
    """For bytes that are not an image: a hint when they look like a file name, as ``os.fsencode(path)`` gives
    (short printable text with a directory separator or a file extension). Only the text is looked at, never
    the file system: bytes may come from anywhere (module docstring, "Bytes")."""
    if len(data) > _PATH_BYTES:
        return ""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        return ""
    separators = {"/", os.sep, os.altsep} - {None}
    if not text.isprintable() or not (any(sep in text for sep in separators) or len(os.path.splitext(text)[1]) > 1):
        return ""
    return (f"; if {_short(text)!r} is a file name, pass it as str or pathlib.Path (e.g. os.fsdecode(path)): "
            "bytes are read as the encoded image file itself, never as a path")


def _short(text, limit=60):
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _open_image_file(source, name=None, max_pixels=MAX_PIXELS, hint=""):
    """Open an image file with PIL, check its size from the header, then decode it; PIL's errors become
    ValueError naming the file (``hint`` is added to the "not an image file" one). A file PIL opened itself
    (from a path) is closed before this returns or raises; the returned image holds its pixels."""
    from PIL import Image, UnidentifiedImageError

    if name is None:
        name = os.fsdecode(source)
        if "\x00" in name:
            raise ValueError(f"image path {name!r} contains a NUL character; it cannot name a file")
        if not os.path.exists(name):
            raise FileNotFoundError(f"image file not found: {name}")
        if os.path.isdir(name):
            raise ValueError(f"{name}: is a directory, not an image file")
        if os.path.isfile(name) and os.path.getsize(name) == 0:  # a failed download or copy, a placeholder
            raise ValueError(f"{name}: the file is empty (0 bytes), not an image")
        # a pipe (the shell's <(...), /dev/stdin): PIL reads it into memory itself but leaves the file it opened
        # unclosed (ResourceWarning), so it is read here, once, and closed
        piped = read_pipe(name)
        if piped is not None:
            source = io.BytesIO(piped)
    try:
        with warnings.catch_warnings(), _pil_limit_at_least(max_pixels):
            # PIL's soft size warning: the cap below decides (module docstring)
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            img = Image.open(source)
    except UnidentifiedImageError:
        raise ValueError(f"{name}: not an image file (PIL cannot identify its format){hint}") from None
    except Image.DecompressionBombError as exc:
        # PIL refuses at twice its MAX_IMAGE_PIXELS, which _pil_limit_at_least keeps at or above max_pixels:
        # the image is over max_pixels too, and a larger max_pixels does load it.
        raise ValueError(f"{name}: more than max_pixels={max_pixels} pixels (PIL: {exc}); checked before "
                         "decoding; pass a larger max_pixels to load it anyway") from None
    except MemoryError:
        raise
    except Exception as exc:  # OSError, SyntaxError, ... from a format plugin
        raise ValueError(f"{name}: cannot read image file: {exc}") from None
    with img:  # closes the file PIL opened (multi-frame formats keep it open for seeking), data or error
        _check_size(img, name, max_pixels)
        try:
            with warnings.catch_warnings(), _pil_limit_at_least(max_pixels):
                # our own cap has been applied; PIL's checks (seeking a frame runs one) are moot
                warnings.simplefilter("ignore", Image.DecompressionBombWarning)
                frames, uncounted = _frame_count(img)
                if frames is None or frames > 1:
                    img.seek(0)
                img.load()
        except MemoryError:
            raise
        except Exception as exc:  # truncated data: OSError("image file is truncated ..."), SyntaxError, ...
            raise ValueError(f"{name}: truncated or corrupt image file ({type(exc).__name__}: {exc})") from None
        _warn_if_several_frames(name, frames, uncounted)
        return _upright(img)


def _frame_count(img):
    """``(frames, None)``: the number of frames of an opened image file (1 for a layered one, :data:`LAYERED_FORMATS`;
    the pictures but the previews of a camera's MPO JPEG, :data:`MPO_PREVIEW_TYPES`),
    or ``(None, error)`` when counting them failed: PIL reads the header of every frame, and a file cut short or
    damaged after its first frame fails there while the first frame, the one traced, is whole."""
    if img.format in LAYERED_FORMATS:
        return 1, None
    try:
        if img.format == "MPO":  # previews of the primary picture are not frames (MPO_PREVIEW_TYPES)
            entries = img.mpinfo[0xB002]
            return sum(entry["Attribute"]["MPType"] not in MPO_PREVIEW_TYPES for entry in entries), None
        return getattr(img, "n_frames", 1), None
    except MemoryError:
        raise
    except Exception as exc:  # noqa: BLE001 - a format plugin's own errors (struct.error, IndexError, TypeError ...)
        return None, exc


_PIL_LIMIT_LOCK = threading.Lock()


@contextlib.contextmanager
def _pil_limit_at_least(max_pixels):
    """PIL's own decompression-bomb check (an error above ``2 * PIL.Image.MAX_IMAGE_PIXELS``, 179 Mpx by
    default) raised, for this ``Image.open``, so that it never refuses an image within ``max_pixels``: the
    cap of this module is the one that decides. The limit is PIL's global; it is changed only when
    ``max_pixels`` is above it (never at the default ``MAX_PIXELS``), under a lock, and restored on the way out.
    Another thread opening an image with PIL directly in that moment sees the raised limit."""
    from PIL import Image

    limit = Image.MAX_IMAGE_PIXELS
    if limit is None or 2 * limit >= max_pixels:
        yield
        return
    with _PIL_LIMIT_LOCK:
        saved = Image.MAX_IMAGE_PIXELS
        Image.MAX_IMAGE_PIXELS = None if saved is None else max(saved, max_pixels)
        try:
            yield
        finally:
            Image.MAX_IMAGE_PIXELS = saved


def _upright(img):
    """The image as a viewer shows it: turned and mirrored by its EXIF orientation tag (phone cameras store the
    sensor's pixels and a tag that says how to turn them), unchanged without a tag or with orientation 1."""
    from PIL import ImageOps

    try:
        orientation = img.getexif().get(0x0112, 1)  # the EXIF "Orientation" tag
    except Exception:  # a malformed EXIF block: the pixels as stored
        return img
    if orientation not in range(2, 9):
        return img
    return ImageOps.exif_transpose(img)


def _no_alpha(what):
    return ValueError(f"{what} has no alpha channel: threshold='alpha' traces the opaque pixels of an image with "
                      "transparency (RGBA, LA, a palette or gray with a transparent colour); use another threshold")


def _keyed_transparent(img):
    """The transparent pixels of a gray, 16-bit or RGB image with a transparent colour (PNG's ``tRNS`` chunk:
    ``img.info["transparency"]``, one gray level or one RGB triple), as a bool array, or ``None`` when the
    image has no such colour (palette and alpha modes carry their transparency in their data)."""
    key = img.info.get("transparency")
    if key is None or isinstance(key, bytes) or img.mode not in _GRAY_MODES | {"1", "RGB"}:
        return None
    arr = np.asarray(img)
    if img.mode == "1":  # PIL reads a 1-bit key as 0 or 255
        return arr == bool(key)
    if arr.ndim == 3:
        key = np.asarray(key).reshape(-1)
        if key.size != arr.shape[2]:
            return None
        return np.all(arr == key.astype(arr.dtype), axis=2)
    if np.ndim(key) != 0:
        return None
    return arr == key


def _pil_to_gray(img, name, alpha=False, keyed=True):
    mode = img.mode
    _check_not_empty((img.height, img.width))
    transparent = _keyed_transparent(img) if keyed else None
    if transparent is not None:  # a transparent colour: composited on white as an alpha channel is
        if alpha:
            return np.where(transparent, np.uint8(255), np.uint8(0)), 255
        gray, white = _pil_to_gray(img, name, keyed=False)  # these modes convert nothing: the key is not seen
        return np.where(transparent, np.asarray(white, dtype=gray.dtype), gray), white
    if alpha:
        if not img.has_transparency_data:
            raise _no_alpha(name)
        return 255 - np.asarray(img.convert("RGBA"))[..., 3], 255
    if mode == "1":
        return np.asarray(img, dtype=np.uint8), 1  # True = white in PIL's 1-bit mode
    if mode in ("P", "PA"):
        img, mode = img.convert("RGBA"), "RGBA"
    elif mode in ("LA", "La"):
        if mode == "La":
            img = img.convert("LA")
        arr = np.asarray(img)
        return _composite_on_white(arr[..., 0], arr[..., 1], 255), 255
    elif mode == "RGBa":
        img, mode = img.convert("RGBA"), "RGBA"
    elif mode not in _GRAY_MODES and mode not in ("RGB", "RGBA"):
        try:  # CMYK, YCbCr, LAB, HSV, RGBX, ...
            img, mode = img.convert("RGB"), "RGB"
        except Exception as exc:
            raise ValueError(f"{name}: unsupported image mode {mode!r}: {exc}") from None

    arr = np.asarray(img)
    if mode in ("RGB", "RGBA"):
        return _array_to_gray(arr)
    if mode == "I":  # 32-bit integer gray: 8-bit data or 16-bit data stored widened
        if arr.size and arr.min() < 0:
            raise ValueError(f"{name}: 32-bit integer image has negative values")
        white = 255 if (arr.size == 0 or arr.max() <= 255) else 65535
        if arr.max() > 65535:
            raise ValueError(f"{name}: 32-bit integer image values exceed 65535; cannot tell where white is")
        return arr.astype(np.uint8 if white == 255 else np.uint16), white
    if mode == "F":  # 32-bit float gray: PIL's scale is 0..255 (convert("F") of an 8-bit image); 0..1 as arrays
        finite = np.isfinite(arr)
        if not finite.all():
            return _array_to_gray(arr)  # names the first non-finite value
        lo, hi = float(arr.min()), float(arr.max())
        if lo >= 0.0 and 1.0 < hi <= 255.0:
            return (arr / np.float32(255)).astype(np.float32), 1.0
        if lo < 0.0 or hi > 255.0:
            raise ValueError(f"{name}: 32-bit float image values lie in [{lo:g}, {hi:g}]; gray must lie in [0, 1] or, "
                             "on PIL's 8-bit scale, in [0, 255]: cannot tell where white is")
    return _array_to_gray(arr)


def _array_to_gray(arr, alpha=False):
    """Validate a numeric array and reduce it to one gray channel; returns ``(gray, white)`` (``alpha``: the
    transparency instead, ``white - alpha``)."""
    if arr.dtype.kind not in "buif":
        raise TypeError(
            f"image array must have a bool, integer or float dtype, got {arr.dtype} "
            "(complex, object and string arrays are not images)"
        )
    if arr.ndim not in (2, 3):
        raise ValueError(f"image array must have shape (H, W) or (H, W, C), got shape {arr.shape}")
    _check_not_empty(arr.shape)
    if arr.ndim == 3 and arr.shape[2] not in (1, 2, 3, 4):
        raise ValueError(
            f"image array must have 1 (gray), 2 (gray+alpha), 3 (RGB) or 4 (RGBA) channels, "
            f"got shape {arr.shape}"
        )
    if arr.dtype.kind == "b":
        raise ValueError(f"a bool image must be a 2-D mask (H, W), got shape {arr.shape}")
    if not arr.dtype.isnative:  # big-endian data, e.g. PIL's "I;16B"
        arr = arr.astype(arr.dtype.newbyteorder("="))
    arr, white = _normalise_dtype(arr)
    if alpha:
        if arr.ndim == 2 or arr.shape[2] not in (2, 4):
            raise _no_alpha(f"an image array of shape {arr.shape}")
        return white - arr[..., -1], white
    if arr.ndim == 2:
        return arr, white
    channels = arr.shape[2]
    if channels == 1:
        return arr[..., 0], white
    if channels == 2:
        return _composite_on_white(arr[..., 0], arr[..., 1], white), white
    gray = _luma(arr[..., :3], white)
    if channels == 4:
        gray = _composite_on_white(gray, arr[..., 3], white)
    return gray, white


def _normalise_dtype(arr):
    """uint8 / uint16 stay; other ints must hold 8-bit values; floats must be finite and in [0, 1]."""
    if arr.dtype == np.uint8:
        return arr, 255
    if arr.dtype == np.uint16:
        return arr, 65535
    if arr.dtype.kind in "iu":
        lo, hi = arr.min(), arr.max()
        if lo < 0 or hi > 255:
            raise ValueError(
                f"integer image of dtype {arr.dtype} must hold 8-bit values in [0, 255], got range "
                f"[{lo}, {hi}] (pass uint16 for 16-bit data, or float in [0, 1])"
            )
        return arr.astype(np.uint8), 255
    # float
    finite = np.isfinite(arr)
    if not finite.all():
        bad = np.unravel_index(int(np.flatnonzero(~finite.reshape(-1))[0]), arr.shape)
        raise ValueError(
            f"float image has a non-finite value {float(arr[bad])!r} at index {tuple(int(i) for i in bad)}; "
            "all values must be finite (NaN is not a gray level)"
        )
    del finite
    lo, hi = float(arr.min()), float(arr.max())
    if lo < 0.0 or hi > 1.0:
        raise ValueError(
            f"float image values must lie in [0, 1] (0 = black, 1 = white), got range [{lo:g}, {hi:g}]"
        )
    if arr.dtype not in (np.float32, np.float64):
        arr = arr.astype(np.float32)
    return arr, 1.0


def _luma(rgb, white):
    """ITU-R 601 luma of an (H, W, 3) array, in row blocks; integer data is rounded as PIL does."""
    height = rgb.shape[0]
    out = np.empty(rgb.shape[:2], dtype=rgb.dtype)
    for start in range(0, height, _BLOCK_ROWS):
        block = rgb[start:start + _BLOCK_ROWS]
        if rgb.dtype == np.uint8:
            # PIL's convert("L"): (R*19595 + G*38470 + B*7471 + 0x8000) >> 16
            acc = block[..., 0].astype(np.uint32) * 19595
            acc += block[..., 1].astype(np.uint32) * 38470
            acc += block[..., 2].astype(np.uint32) * 7471
            acc += 0x8000
            out[start:start + _BLOCK_ROWS] = (acc >> 16).astype(np.uint8)
        else:
            value = block[..., 0] * 0.299 + block[..., 1] * 0.587 + block[..., 2] * 0.114
            if rgb.dtype.kind == "u":
                value = np.clip(np.rint(value), 0, white)
            out[start:start + _BLOCK_ROWS] = value
    return out


def _composite_on_white(gray, alpha, white):
    """``gray * a + white * (1 - a)`` with ``a = alpha / white`` (alpha on the same scale as gray)."""
    height = gray.shape[0]
    out = np.empty(gray.shape, dtype=gray.dtype)
    for start in range(0, height, _BLOCK_ROWS):
        g = gray[start:start + _BLOCK_ROWS].astype(np.float64)
        a = alpha[start:start + _BLOCK_ROWS].astype(np.float64) / white
        value = g * a + white * (1.0 - a)
        if gray.dtype.kind == "u":
            value = np.clip(np.rint(value), 0, white)
        out[start:start + _BLOCK_ROWS] = value
    return out
