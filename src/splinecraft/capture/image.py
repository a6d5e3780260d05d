"""Bitmap loading and binarization: image file / array / PIL image -> bool ink mask.

The first step of outline capture (thesis section 4.1.1, "Finding boundary of planar object"): the scanned or
drawn image becomes a two-level bitmap whose ``True`` pixels are the shape ("ink"). Pixel frame as in
docs/capture.md: row ``r``, column ``c`` covers ``[c, c+1] x [r, r+1]`` (x right, y down).

Conventions
-----------
* **Gray scale.** Every input is reduced to one gray channel on the scale ``0 = black .. 1 = white``:
  8-bit values are divided by 255, 16-bit values by 65535, float images must already lie in
  ``[0, 1]``. Colour uses the ITU-R 601 luma ``0.299 R + 0.587 G + 0.114 B`` (the weights of
  PIL's ``convert("L")``, rounded the same way for 8-bit data). Transparency is composited on
  **white** paper, so a black shape on a transparent background is ink.
* **Ink is dark** by default: ``ink = gray <= threshold``; ``invert=True`` makes light pixels ink.
* **Threshold.** ``None`` (default) uses Otsu's method (:func:`skimage.filters.threshold_otsu`). When
  the image has too little contrast for Otsu to mean anything (``max - min < MIN_CONTRAST`` of full
  scale, e.g. a blank page with JPEG noise, or a uniform image) the fixed mid-gray threshold ``0.5``
  is used instead, so an all-white image has no ink and an all-black image is all ink. An explicit
  ``threshold`` is a fraction of white in ``[0, 1]`` (for an 8-bit gray level ``g`` pass ``g / 255``).
* **Bool arrays** are masks already (``True`` = ink); only ``invert`` applies to them.
* **Specks.** ``min_speck_area=k`` removes ink components *and* holes (background components) with
  fewer than ``k`` pixels (:func:`skimage.morphology.remove_small_objects` /
  :func:`~skimage.morphology.remove_small_holes`); ink components use the tracer's ``connectivity``,
  holes the complementary one. The default ``0`` removes nothing, so a single-pixel shape survives.
* **Multi-frame files** (animated GIF, multi-page TIFF): the first frame is used.

Memory: 8-bit and 16-bit data stay in their integer type (colour conversion and compositing are done in
row blocks), so an 8000 x 8000 8-bit image needs about 64 MB for the gray channel and 64 MB for the mask.
"""
from __future__ import annotations

import inspect
import io
import numbers
import os

import numpy as np

__all__ = ["load_bitmap", "MIN_CONTRAST", "FALLBACK_THRESHOLD"]

#: Below this gray range (fraction of white) an image is treated as uniform: Otsu is not used.
MIN_CONTRAST = 0.1
#: Threshold used for (near-)uniform images, as a fraction of white.
FALLBACK_THRESHOLD = 0.5

# Rows per block for colour conversion / compositing (bounds the temporaries to ~ block * width).
_BLOCK_ROWS = 512

# PIL modes that np.asarray turns into a single gray channel directly.
_GRAY_MODES = {"L", "I;16", "I;16L", "I;16B", "I;16N", "I", "F"}


# ---------------------------------------------------------------------------------------------------
# public API
# ---------------------------------------------------------------------------------------------------
def load_bitmap(image, *, threshold=None, invert=False, min_speck_area=0, connectivity=8) -> np.ndarray:
    """Binarize an image into a bool ink mask ``(H, W)`` (thesis section 4.1.1; docs/capture.md).

    Parameters
    ----------
    image : str | os.PathLike | file object | numpy.ndarray | PIL.Image.Image
        A path or binary file object of a PNG, JPEG, BMP, GIF or TIFF file (anything PIL reads);
        an array of shape ``(H, W)`` (bool mask, or gray), ``(H, W, 1)``, ``(H, W, 2)`` (gray +
        alpha), ``(H, W, 3)`` (RGB) or ``(H, W, 4)`` (RGBA) with dtype bool (2-D only), uint8,
        uint16, another integer type with values in ``[0, 255]``, or float in ``[0, 1]``; or a PIL image
        of any mode.
    threshold : float in [0, 1], optional
        Gray level (fraction of white) separating ink (``gray <= threshold``) from paper. ``None``:
        Otsu's threshold, or ``FALLBACK_THRESHOLD`` for images with less than ``MIN_CONTRAST`` contrast.
        Not allowed for bool masks.
    invert : bool, optional
        Light pixels are ink (white shape on black), or, for a bool mask, ``False`` pixels are ink.
    min_speck_area : int >= 0, optional
        Remove ink specks and fill holes with fewer than this many pixels (0 = keep everything).
    connectivity : {4, 8}, optional
        Connectivity of ink components for speck removal (holes use the complementary one); pass the
        value the boundary tracer will use.

    Returns
    -------
    numpy.ndarray of bool, shape (H, W)
        ``True`` = ink.

    Raises
    ------
    FileNotFoundError
        The path does not exist.
    ValueError
        A file that is not an image, is truncated or corrupt (the message names the file); an empty
        array, wrong number of dimensions or channels, NaN/inf or out-of-range values; a bad threshold.
    TypeError
        Unsupported input type or dtype, or a non-bool ``invert``.
    """
    threshold = _check_threshold(threshold)
    if not isinstance(invert, (bool, np.bool_)):
        raise TypeError(f"invert must be a bool, got {type(invert).__name__}")
    min_speck_area = _check_count(min_speck_area, "min_speck_area")
    if connectivity not in (4, 8) or isinstance(connectivity, bool):
        raise ValueError(f"connectivity must be 4 or 8, got {connectivity!r}")

    if isinstance(image, np.ndarray) and image.dtype == bool:
        if image.ndim != 2:
            raise ValueError(f"a bool mask must be 2-D (H, W), got shape {image.shape}")
        _check_not_empty(image.shape)
        if threshold is not None:
            raise ValueError("threshold does not apply to a bool mask (it is already binary); pass threshold=None")
        mask = np.array(image, dtype=bool, order="C")
    else:
        gray, white = _to_gray(image)
        mask = _binarize(gray, white, threshold)
        del gray
    if invert:
        np.logical_not(mask, out=mask)
    if min_speck_area > 1:
        mask = _remove_specks(mask, min_speck_area, connectivity)
    return mask


# ---------------------------------------------------------------------------------------------------
# validation helpers
# ---------------------------------------------------------------------------------------------------
def _check_threshold(threshold):
    if threshold is None:
        return None
    if isinstance(threshold, (bool, np.bool_)) or not isinstance(threshold, numbers.Real):
        raise TypeError(f"threshold must be a number in [0, 1] or None, got {type(threshold).__name__}")
    threshold = float(threshold)
    if not np.isfinite(threshold) or not 0.0 <= threshold <= 1.0:
        raise ValueError(
            f"threshold must be a fraction of white in [0, 1], got {threshold!r} "
            f"(for an 8-bit gray level g pass g / 255)"
        )
    return threshold


def _check_count(value, name):
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be a non-negative int, got {type(value).__name__}")
    if value < 0:
        raise ValueError(f"{name} must be >= 0, got {value}")
    return int(value)


def _check_not_empty(shape):
    if len(shape) < 2 or shape[0] == 0 or shape[1] == 0:
        raise ValueError(f"image is empty (shape {shape}); it needs at least one pixel")


# ---------------------------------------------------------------------------------------------------
# input -> (gray array, white value)
# ---------------------------------------------------------------------------------------------------
def _to_gray(image):
    """Return ``(gray, white)``: a 2-D numeric array and the value that means white."""
    from PIL import Image

    if isinstance(image, Image.Image):
        return _pil_to_gray(image, name="PIL image")
    if isinstance(image, (str, bytes, os.PathLike)):
        return _pil_to_gray(_open_image_file(image), name=os.fsdecode(image))
    if isinstance(image, (io.IOBase,)) or (hasattr(image, "read") and hasattr(image, "seek")):
        name = getattr(image, "name", "image file object")
        return _pil_to_gray(_open_image_file(image, name=str(name)), name=str(name))
    if isinstance(image, np.ndarray):
        return _array_to_gray(image)
    raise TypeError(
        "image must be a path, a binary file object, a numpy array or a PIL image, "
        f"got {type(image).__name__}"
    )


def _open_image_file(source, name=None):
    """Open and fully decode an image file with PIL; wrap PIL's errors in ValueError naming the file."""
    from PIL import Image, UnidentifiedImageError

    if name is None:
        name = os.fsdecode(source)
        if not os.path.exists(name):
            raise FileNotFoundError(f"image file not found: {name}")
        if os.path.isdir(name):
            raise ValueError(f"{name}: is a directory, not an image file")
    try:
        img = Image.open(source)
    except UnidentifiedImageError:
        raise ValueError(f"{name}: not an image file (PIL cannot identify its format)") from None
    except Image.DecompressionBombError as exc:
        raise ValueError(f"{name}: image too large for PIL's decompression-bomb limit: {exc}") from None
    except MemoryError:
        raise
    except Exception as exc:  # OSError, SyntaxError, ... from a format plugin
        raise ValueError(f"{name}: cannot read image file: {exc}") from None
    try:
        if getattr(img, "n_frames", 1) > 1:
            img.seek(0)
        img.load()
    except MemoryError:
        raise
    except Exception as exc:  # truncated data: OSError("image file is truncated ..."), SyntaxError, ...
        raise ValueError(f"{name}: truncated or corrupt image file ({type(exc).__name__}: {exc})") from None
    return img


def _pil_to_gray(img, name):
    mode = img.mode
    _check_not_empty((img.height, img.width))
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
    return _array_to_gray(arr)


def _array_to_gray(arr):
    """Validate a numeric array and reduce it to one gray channel; returns ``(gray, white)``."""
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
            f"float image has a non-finite value {arr[bad]!r} at index {tuple(int(i) for i in bad)}; "
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


# ---------------------------------------------------------------------------------------------------
# thresholding and speck removal
# ---------------------------------------------------------------------------------------------------
def _binarize(gray, white, threshold):
    """``gray <= t * white`` with Otsu's ``t`` by default (see module docstring for the fallback)."""
    if threshold is None:
        lo, hi = gray.min(), gray.max()
        if float(hi) - float(lo) < MIN_CONTRAST * white:
            level = FALLBACK_THRESHOLD * white
        else:
            level = _otsu_level(gray, int(lo), int(hi)) if gray.dtype.kind == "u" else _otsu_level(gray)
    else:
        level = threshold * white
    return np.ascontiguousarray(gray <= level)


def _otsu_level(gray, lo=None, hi=None):
    """Otsu's threshold (:func:`skimage.filters.threshold_otsu`): the upper edge of the dark class.

    For 8/16-bit data the histogram (one bin per gray level from ``lo`` to ``hi``, as skimage builds it
    for integer images) is counted in row blocks and handed to skimage, which gives the same threshold
    without skimage's full-size temporaries (an 8000 x 8000 image: ~0.4 s instead of ~2 s).
    """
    from skimage.filters import threshold_otsu

    if lo is None:
        return float(threshold_otsu(gray))
    counts = np.zeros(hi + 1, dtype=np.int64)
    for start in range(0, gray.shape[0], _BLOCK_ROWS):
        counts += np.bincount(gray[start:start + _BLOCK_ROWS].reshape(-1), minlength=hi + 1)
    return float(threshold_otsu(hist=(counts[lo:], np.arange(lo, hi + 1))))


def _remove_specks(mask, min_area, connectivity):
    """Remove ink components and holes with fewer than ``min_area`` pixels (skimage.morphology)."""
    from skimage import morphology

    ink_conn = 2 if connectivity == 8 else 1
    hole_conn = 1 if connectivity == 8 else 2
    # scikit-image 0.26 renamed min_size (strictly smaller) to max_size (smaller or equal).
    if "max_size" in inspect.signature(morphology.remove_small_objects).parameters:
        mask = morphology.remove_small_objects(mask, max_size=min_area - 1, connectivity=ink_conn)
        mask = morphology.remove_small_holes(mask, max_size=min_area - 1, connectivity=hole_conn)
    else:  # pragma: no cover - older scikit-image
        mask = morphology.remove_small_objects(mask, min_size=min_area, connectivity=ink_conn)
        mask = morphology.remove_small_holes(mask, area_threshold=min_area, connectivity=hole_conn)
    return np.ascontiguousarray(mask, dtype=bool)
