"""``TraceExplorer``: step through outline capture on a bitmap (thesis chapter 4) in JupyterLab.

The kernel runs :func:`splinecraft.trace` (bitmap -> boundaries -> corners -> spline fit with knot
insertion, every iteration kept) and sends the page what to draw: the bitmap as PNG bytes, the boundaries
and corners, and -- per iteration -- the fitted Bézier pieces, the knots and the candidate points the
algorithm accepted or rejected (float32 byte buffers). The page (``js/trace_explorer.js``) only draws,
steps and forwards the controls (detector and its tuning sliders, knot-insertion algorithm, ε, τ, seed,
an image upload). A re-trace runs with a visible busy state and a time budget
(:attr:`TraceExplorer.time_budget_s`). Whatever goes wrong -- a bad value (NaN, ε <= 0), an image that cannot
be read or is too large, a parameter that makes the trace fail or run out of memory or time -- the explorer
keeps the last good settings and result and shows why.
"""
from __future__ import annotations

import inspect
import io
import numbers
import warnings
from pathlib import Path

import numpy as np
import traitlets as t

from .._validation import check_number, file_path
from ..capture import CORNER_METHODS, KNOT_METHODS, load_bitmap, trace
from ..capture.fitting.options import DEFAULT_TAU
from ..capture.trace import ALL_INK_NOTE, BUDGET_NOTE
from ..capture.image import InkPolarityWarning
from ..capture.trace_stages import TraceStages
from . import _explorer_drawing as drawing
from ._assets import load_css, load_esm
from ._base import Bool, Float, Int, WidgetBase, json_numbers, read_str, run_with_budget, short_reason
from ._png import curves_png

__all__ = ["TraceExplorer", "TraceExplorerWarning", "demo_bitmap", "corner_param_specs"]

#: Slider ranges of known corner-detector parameters: name -> (min, max, step, label, title).
KNOWN_CORNER_PARAMS = {
    "zct": (1, 25, 1, "ZCT", "SRM05 zero-crossing threshold: minimum run of equal chain codes (thesis section 2.4)"),
    "dt": (1, 25, 1, "DT", "SRM05 distance threshold: points closer than DT merge into one corner"),
    "ta": (90, 179, 1, "TA (°)", "SRM05 angle threshold: interior angles above TA count as straight (E21)"),
    "max_angle": (90, 179, 1, "max angle °", "interior angles above this are not corners"),
    "alpha_max": (90, 179, 1, "α max °", "IPAN99: widest opening angle of a corner triangle"),
    "d_min": (1, 30, 0.5, "d min (px)", "IPAN99: shortest triangle side"),
    "d_max": (1, 40, 0.5, "d max (px)", "IPAN99: longest triangle side"),
    "s": (1, 15, 1, "s", "FD77: arm length (samples)"),
    "smoothing": (0, 4, 0.05, "smoothing", "tangent-jump: Gaussian smoothing of the resampled outline"),
    "tolerance": (0.05, 2, 0.05, "tolerance", "tangent-jump: how far an arm may leave its line"),
    "min_turn": (5, 90, 1, "min turn °", "tangent-jump: smallest turn that counts as a corner"),
    "min_excess": (5, 90, 1, "min excess °", "tangent-jump: turn concentrated at the point beyond its flanks"),
    "max_arm": (4, 240, 1, "max arm", "tangent-jump: longest arm (samples)"),
    "separation": (1, 10, 1, "separation", "tangent-jump: corners at least this many samples apart"),
}
_TRACE_SETTINGS = ("corner_method", "corner_params", "method", "epsilon", "tau", "seed", "max_iterations")
#: How the bitmap is made from the image (changing one reloads the image and re-traces).
_IMAGE_SETTINGS = ("threshold", "invert", "despeckle")
#: Threshold choices of the page: global (Otsu) or local (Sauvola) (docs/capture.md §9); "fixed" = the number
#: passed as ``threshold=`` to the constructor.
THRESHOLDS = (("otsu", "global (Otsu)"), ("local", "local (Sauvola)"), ("fixed", "fixed level"))
_TRACE_PARAMS = ("epsilon", "method", "corner_method", "corner_params", "seed", "max_iterations", "tau",
                 "threshold", "invert", "min_speck_area", "connectivity", "contour", "fit_params")
_DISPLAY = ("width", "height", "show_image", "show_boundaries", "show_corners", "show_knots", "show_candidates",
            "show_final", "play_interval_ms", "view", "large")
_MAX_UPLOAD_BYTES = 20_000_000
#: Largest bitmap the explorer traces (pixels); larger uploads are refused from their header, before decoding.
MAX_PIXELS = 4_000_000
#: Default time budget of one re-trace, seconds (``TraceExplorer.time_budget_s``).
TIME_BUDGET_S = 60.0
#: Knot-insertion methods that take the distance constraint tau (thesis Algorithms 4.2, 4.3).
TAU_METHODS = tuple(DEFAULT_TAU)


class _Upload(bytes):
    """The bytes of a file the page uploaded, with its ``name`` (the messages of reading it name the file, not "image
    bytes (N bytes)")."""

    def __new__(cls, data, name):
        upload = super().__new__(cls, bytes(data))
        upload.name = name
        return upload


def _for_the_page(warning: Warning) -> str:
    """A tracing warning as the status line says it: the ink-polarity warning names the page's control."""
    if isinstance(warning, InkPolarityWarning):
        return (f"the ink covers {100 * warning.border_share:.0f}% of the border and touches every side, so the "
                f"background may be the traced shape: toggle invert if so.")
    return str(warning)


class TraceExplorerWarning(UserWarning):
    """A value set from code was rejected; the explorer kept its last good result."""


def demo_bitmap(size: int = 96) -> np.ndarray:
    """A small test shape (bool mask, True = ink): a rounded 'D' with a hole and four sharp corners."""
    yy, xx = np.mgrid[0:size, 0:size] + 0.5
    s = size / 96.0
    stem = (xx >= 14 * s) & (xx <= 40 * s) & (yy >= 12 * s) & (yy <= 84 * s)
    bowl = ((xx - 40 * s) ** 2 / (44 * s) ** 2 + (yy - 48 * s) ** 2 / (36 * s) ** 2 <= 1.0) & (xx >= 40 * s)
    hole = ((xx - 40 * s) ** 2 / (24 * s) ** 2 + (yy - 48 * s) ** 2 / (18 * s) ** 2 <= 1.0) & (xx >= 30 * s)
    return (stem | bowl) & ~hole


def corner_param_specs(method: str) -> list:
    """Slider descriptions for the numeric keyword parameters of a corner detector (for the page)."""
    function = CORNER_METHODS.get(method)
    if function is None or not callable(function):
        return []
    specs = []
    for name, parameter in inspect.signature(function).parameters.items():
        default = parameter.default
        if parameter.kind not in (parameter.KEYWORD_ONLY, parameter.POSITIONAL_OR_KEYWORD):
            continue
        if default is inspect.Parameter.empty or isinstance(default, bool) or not isinstance(default, numbers.Real):
            continue
        if name in ("closed",):
            continue
        integer = isinstance(default, numbers.Integral)
        if name in KNOWN_CORNER_PARAMS:
            lo, hi, step, label, title = KNOWN_CORNER_PARAMS[name]
        else:
            value = float(default)
            if integer:
                lo, hi, step = (0, 10, 1) if value <= 0 else (1, max(3 * int(value), 10), 1)
            elif 0 < value <= 1:
                lo, hi, step = 0.0, 1.0, 0.01
            elif value > 1:
                lo, hi, step = 0.0, round(3 * value, 6), round(value / 50, 6)
            else:
                lo, hi, step = 0.0, 10.0, 0.05
            label, title = name, f"{method}: {name} (default {default})"
        specs.append({"name": name, "label": label, "title": title, "min": lo, "max": hi, "step": step,
                      "default": default, "integer": integer})
    return specs


class TraceExplorer(WidgetBase):
    """Step through the outline capture of a bitmap: corners, spline fit and knot insertion.

    Parameters
    ----------
    image : path, ndarray, PIL image or None
        The bitmap (see :func:`splinecraft.capture.load_bitmap`); ``None`` shows :func:`demo_bitmap`.
        The page also has an upload control.
    **trace_params
        Passed to :func:`splinecraft.trace` (``epsilon``, ``method``, ``corner_method``, ``corner_params``,
        ``seed``, ``max_iterations``, ``tau``, ``threshold``, ``invert``, ``min_speck_area``,
        ``connectivity``, ``contour``, ``fit_params``), plus display options ``width``, ``height``,
        ``show_image``, ``show_boundaries``, ``show_corners``, ``show_knots``, ``show_candidates``, ``show_final``,
        ``play_interval_ms``.

    Synced traits
    -------------
    corner_method, corner_params, method, epsilon, tau (None = the algorithm's default), seed,
    max_iterations : the trace settings (changing one re-traces)
    snapshot_index, n_snapshots : the iteration shown (0 = corners only) and how many there are
    iteration_info : dict -- knots, pieces, max_error, hausdorff, accepted/rejected candidates of the shown
        iteration
    stats_html : the result's statistics in the columns of thesis tables 4.1-4.61
    status_message, status_level, busy

    Attributes
    ----------
    result : TraceResult -- the last good trace
    convergence_figure : bqplot Figure -- knots and max error per iteration (see :meth:`panel`)
    time_budget_s : float or None -- longest a re-trace may take, seconds > 0 (default 60; None: no limit);
        after that the explorer keeps the last good result (the abandoned work finishes in the background).
        A value that is not a finite number > 0 or None raises ``TraitError`` and keeps the last one.
    """

    _esm = load_esm("trace_explorer.js")
    _css = load_css()
    kept = "result"
    warning_class = TraceExplorerWarning
    panel_plot = "convergence_figure"
    panel_extra_width = 292
    messages = {**WidgetBase.messages, "upload": "_on_upload", "edit": "_on_edit"}
    page_traits = frozenset(_TRACE_SETTINGS + _IMAGE_SETTINGS + _DISPLAY + ("snapshot_index",))

    time_budget_s = Float(TIME_BUDGET_S, allow_none=True)

    image_png = t.Bytes(b"").tag(sync=True)
    image_size = t.List([1, 1]).tag(sync=True)
    corner_method = t.Unicode("").tag(sync=True)
    corner_params = t.Dict().tag(sync=True)
    method = t.Unicode("").tag(sync=True)
    epsilon = Float(2.0, allow_none=True).tag(sync=True, to_json=json_numbers)
    tau = Float(None, allow_none=True).tag(sync=True, to_json=json_numbers)
    seed = Int(0, allow_none=True).tag(sync=True)
    max_iterations = Int(200, min=1, max=100_000).tag(sync=True)
    threshold = t.Unicode("otsu").tag(sync=True)
    invert = Bool(False).tag(sync=True)
    despeckle = Int(None, allow_none=True, min=0, max=1_000_000).tag(sync=True)

    snapshot_index = Int(0).tag(sync=True)
    n_snapshots = Int(0).tag(sync=True)
    play_interval_ms = Int(350, min=20, max=60_000).tag(sync=True)
    show_image = Bool(True).tag(sync=True)
    show_boundaries = Bool(True).tag(sync=True)
    show_corners = Bool(True).tag(sync=True)
    show_knots = Bool(True).tag(sync=True)
    show_candidates = Bool(True).tag(sync=True)
    show_final = Bool(False).tag(sync=True)
    view = t.List([0.0, 0.0, 1.0, 1.0]).tag(sync=True)
    width = Int(600, min=120, max=4000).tag(sync=True)
    height = Int(440, min=120, max=4000).tag(sync=True)

    base_geometry = t.Dict().tag(sync=True)
    snapshot_geometry = t.Dict().tag(sync=True)
    iteration_info = t.Dict().tag(sync=True)
    stats_html = t.Unicode("").tag(sync=True)
    options = t.Dict().tag(sync=True)

    def __init__(self, image=None, **trace_params):
        unknown = set(trace_params) - set(_TRACE_PARAMS) - set(_DISPLAY) - {"debug"}
        if unknown:
            raise TypeError(f"TraceExplorer got unexpected argument(s): {', '.join(sorted(unknown))}")
        display = {k: trace_params.pop(k) for k in list(trace_params) if k in _DISPLAY + ("debug",)}
        view = self._given_view(display)
        self._result = None
        self._stages = TraceStages()  # boundaries, corners and noise of the last bitmaps (a slider re-fits only)
        super().__init__(**display)
        self._extra = {k: trace_params[k] for k in ("threshold", "connectivity", "contour", "fit_params")
                       if k in trace_params}
        level = trace_params.get("threshold")
        with self._quiet():
            self.threshold = "fixed" if isinstance(level, numbers.Real) else (level or "otsu")
            self.invert = trace_params.get("invert", False)
            self.despeckle = trace_params.get("min_speck_area")
        settings = {
            "corner_method": trace_params.get("corner_method") or "",  # "" = trace()'s default
            "corner_params": dict(trace_params.get("corner_params") or {}),
            "method": trace_params.get("method") or "",
            "epsilon": check_number(trace_params.get("epsilon", 2.0), "epsilon"),
            "tau": trace_params.get("tau"),
            "seed": trace_params.get("seed", 0),
            "max_iterations": int(trace_params.get("max_iterations", 200)),
        }
        self._source = demo_bitmap() if image is None else image
        # raises for bad constructor arguments; the bitmap's warnings go to the status line and to the caller
        (mask, result), self._load_notes = self._noting_warnings(lambda: self._load_and_run(self._source, settings))
        for note in self._load_notes:
            warnings.warn(note, UserWarning, stacklevel=2)
        # show the defaults trace() resolved (params records the names it used)
        settings["corner_method"] = settings["corner_method"] or str(result.params.get("corner_method") or "")
        settings["method"] = settings["method"] or str(result.params.get("method") or "")
        with self._quiet(), self.hold_sync():
            for name, value in settings.items():
                setattr(self, name, value)
            self.options = self._options()
        self._set_image(mask)
        if view is not None:  # shown instead of the whole bitmap
            with self._quiet():
                self.view = view
        self._accept(result)
        self._show_summary("", self._load_notes)

    # ------------------------------------------------------------------ public API
    @property
    def result(self):
        """The last good :class:`~splinecraft.capture.trace.TraceResult`."""
        return self._result

    @property
    def mask(self) -> np.ndarray:
        """The bitmap being traced (bool, True = ink)."""
        return self._mask

    def step(self, delta: int = 1) -> int:
        """Move ``delta`` iterations (clamped); returns the new index."""
        return self.go_to(self.snapshot_index + int(delta))

    def go_to(self, index: int) -> int:
        """Show iteration ``index`` (clamped to the available snapshots); returns it."""
        index = int(np.clip(int(index), 0, max(self.n_snapshots - 1, 0)))
        self.snapshot_index = index
        return index

    def load(self, image) -> bool:
        """Trace a new image (path, array, PIL image or encoded bytes); False (with a message) if it fails."""
        if isinstance(image, (bytes, bytearray, memoryview)) and not isinstance(image, _Upload):
            image = bytes(image)
        settings = self._settings()
        try:
            with self._busy():
                (mask, result), notes = self._noting_warnings(lambda: run_with_budget(
                    lambda: self._load_and_run(image, settings), self.time_budget_s, "tracing the image"))
        except Exception as exc:  # noqa: BLE001 - unreadable, too large, out of memory or time: keep the last result
            self._reject(short_reason(exc))
            return False
        self._source = image
        with self._quiet():
            self.options = self._options()
        self._set_image(mask)
        self._accept(result)
        self._load_notes = notes
        self._show_summary("", notes)
        return True

    def edit(self, **params):
        """The shown iteration in an :class:`~splinecraft.widgets.outline_editor.OutlineEditor` (``self.editor``);
        the page's "Edit outline" button opens it below the explorer."""
        from .outline_editor import OutlineEditor

        last = len(self._result.snapshots) - 1
        iteration = None if self.snapshot_index >= last else self.snapshot_index
        self.editor = OutlineEditor(self._result, iteration=iteration, **params)
        return self.editor

    def _on_edit(self, _content, _buffers):
        editor = self.edit()
        self.send({"type": "open_editor", "model_id": editor.model_id})
        self._set_status("Opened the shown iteration in an OutlineEditor (explorer.editor).", "info")

    def to_svg(self) -> str:
        """The traced outline as an SVG document (exact cubic Béziers, the bitmap's pixel frame)."""
        return self._result.to_svg()

    def save_svg(self, path) -> Path:
        """Write :meth:`to_svg` to ``path``; returns the path. A blank ``path`` is a ``ValueError`` (as
        :meth:`splinecraft.outline.Outline.save_svg`: '' is the current folder to ``pathlib``, ' ' a file called
        space)."""
        path = file_path(path, "trace.svg")
        path.write_text(self.to_svg(), encoding="utf-8")
        return path

    def to_png(self, width: int = 800, *, bitmap: bool = True) -> bytes:
        """PNG bytes of the traced outline over the bitmap (light grey; ``bitmap=False`` leaves it out)."""
        height, columns = self._mask.shape
        return curves_png([s.bezier() for s in self._result.splines], width=width,
                          height=max(16, int(round(width * height / columns))), frame=(0, 0, columns, height),
                          background=self._mask if bitmap else None, stroke_width=2.0)

    @property
    def convergence_figure(self):
        """bqplot Figure: knots and max error per iteration, with ε and the shown iteration marked."""
        from ._convergence_plot import ConvergencePlot

        return self._plot("convergence", ConvergencePlot).figure

    # ------------------------------------------------------------------ tracing
    def _settings(self) -> dict:
        return {name: getattr(self, name) for name in
                ("corner_method", "corner_params", "method", "epsilon", "tau", "seed", "max_iterations")}

    def _load(self, image) -> np.ndarray:
        """The bitmap of ``image`` with the image settings (``load_bitmap`` reads a file's header before decoding).
        An upload is read as a file object named as the page's file, so that a message names it."""
        if isinstance(image, (bytes, bytearray, memoryview)) and memoryview(image).nbytes > _MAX_UPLOAD_BYTES:
            raise ValueError(f"the image is too large ({memoryview(image).nbytes} bytes; limit {_MAX_UPLOAD_BYTES})")
        if isinstance(image, _Upload):
            image, name = io.BytesIO(image), image.name
            image.name = name
        options = {"invert": self.invert, "min_speck_area": self.despeckle, "max_pixels": MAX_PIXELS}
        if "connectivity" in self._extra:
            options["connectivity"] = self._extra["connectivity"]
        if not (isinstance(image, np.ndarray) and image.dtype == bool):  # a bool mask has no threshold
            options["threshold"] = self._extra.get("threshold") if self.threshold == "fixed" else self.threshold
        mask = load_bitmap(image, **options)
        if mask.size > MAX_PIXELS:
            raise ValueError(f"the bitmap has {mask.size} pixels; the explorer takes up to {MAX_PIXELS}")
        return mask

    def _load_and_run(self, image, settings):
        mask = self._load(image)
        return mask, self._run(mask, settings)

    @staticmethod
    def _noting_warnings(function):
        """``function()`` and the messages of the user warnings raised while it runs (for example that a
        bitmap's ink touches every border, so it may be inverted): the status line shows them, where a Python
        warning from the tracing thread would go unseen. Other warnings are passed on. Called on the kernel's
        thread around :func:`run_with_budget` (``catch_warnings`` is process-wide: entered by the worker, it
        would also swallow the warnings of a timed-out call's rejection on this thread)."""
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            value = function()
        notes = []
        for record in caught:
            if issubclass(record.category, UserWarning):
                notes.append(short_reason(_for_the_page(record.message)))
            else:
                warnings.warn_explicit(record.message, record.category, record.filename, record.lineno)
        return value, list(dict.fromkeys(notes))

    def _show_summary(self, prefix: str, notes) -> None:
        """The summary status, or a warning status that adds the trace's warnings to it, and the notes of the trace
        that say its result is not all that was asked for (an image whose every pixel is ink: its outline is the
        frame; a spent time budget), as the command line warns of them (``batch._work.note_lines``)."""
        message = f"{prefix}{self._summary_message()}"
        notes = list(dict.fromkeys([*notes, *(short_reason(note) for note in self._result.notes
                                              if note.startswith((ALL_INK_NOTE, BUDGET_NOTE)))]))
        if notes:
            self._set_status(f"{message} Warning: {' '.join(notes)}", "warning")
        else:
            self._set_status(message, "info")

    def _run(self, mask, settings):
        """``trace`` with these settings (it checks them and names a bad one)."""
        method = settings["method"] or None
        if settings["epsilon"] is None:
            raise ValueError("ε must be a number > 0, got nothing (NaN)")
        if settings["seed"] is None:
            raise ValueError("the seed must be an integer ≥ 0, got nothing")
        for name, value in settings["corner_params"].items():
            if isinstance(value, bool) or not isinstance(value, numbers.Real):
                raise TypeError(f"corner parameter {name} must be a number, got {value!r:.40}")
        if settings["tau"] is not None and method not in TAU_METHODS:
            # kept for a later switch to euclidean or positional: a tau no method takes (NaN, inf, < 0) is refused now,
            # not taken as the good state of which a later switch of the method would fail with it
            check_number(settings["tau"], f"tau (nearness of the methods {', '.join(TAU_METHODS)})", minimum=0.0)
        tau = settings["tau"] if method in TAU_METHODS else None
        params = {k: v for k, v in self._extra.items() if k != "threshold"}  # the mask is already binary
        # despeckle None: trace's default cleaning of the bitmap (pinholes and specks of 1-2 px); a number: the
        # bitmap is cleaned as asked already (0 keeps every pixel), as sc.trace(image, min_speck_area=k) does
        params["min_speck_area"] = None if self.despeckle is None else 0
        return trace(
            mask, epsilon=settings["epsilon"], method=method, corner_method=settings["corner_method"] or None,
            corner_params=settings["corner_params"], seed=settings["seed"], max_iterations=settings["max_iterations"],
            keep_snapshots=True, tau=tau, stages=self._stages, **params,
        )

    def _accept(self, result):
        self._result = result
        self._good = {**self._settings(), **{name: getattr(self, name) for name in _IMAGE_SETTINGS}}
        count = max(len(result.snapshots), 1)
        with self._quiet(), self.hold_sync():
            self.n_snapshots = count
            self.snapshot_index = count - 1
            self.base_geometry = drawing.base_geometry(result)
            self.stats_html = drawing.stats_html(result)
            self._publish_snapshot()
        if "convergence" in self._plots:
            self._plots["convergence"].update(self)

    def _set_image(self, mask):
        from PIL import Image

        self._mask = mask
        ink = np.array([176, 190, 197], dtype=np.uint8)
        rgb = np.where(mask[..., None], ink, np.uint8(255)).astype(np.uint8)
        buffer = io.BytesIO()
        Image.fromarray(rgb, mode="RGB").save(buffer, format="PNG")
        height, width = mask.shape
        with self._quiet(), self.hold_sync():
            self.image_png = buffer.getvalue()
            self.image_size = [int(width), int(height)]
            self.view = [0.0, 0.0, float(width), float(height)]

    # ------------------------------------------------------------------ drawing data
    def _current(self):
        snapshots = self._result.snapshots
        if not snapshots:
            return None
        return snapshots[int(np.clip(self.snapshot_index, 0, len(snapshots) - 1))]

    def _publish_snapshot(self):
        merged = self._current()
        geometry, info = drawing.snapshot_geometry(self._result, merged)
        self.snapshot_geometry = geometry
        if merged is not None:
            info["note"] = drawing.iteration_note(self._result, merged, self.snapshot_index, info["removed"])
        self.iteration_info = info

    def _options(self) -> dict:
        corner = [[name, name] for name in CORNER_METHODS]
        return {
            "corner_methods": corner,
            "knot_methods": [[name, name] for name in KNOT_METHODS],
            "knot_descriptions": {name: str(description) for name, description in KNOT_METHODS.items()},
            "corner_params": {name: corner_param_specs(name) for name in CORNER_METHODS},
            "tau_methods": list(TAU_METHODS),
            "thresholds": [list(choice) for choice in THRESHOLDS if choice[0] != "fixed" or "threshold" in self._extra],
            "image_is_mask": bool(isinstance(self._source, np.ndarray) and self._source.dtype == bool),
        }

    def _summary_message(self) -> str:
        stats = self._result.stats
        return (f"Traced {stats.get('boundaries', len(self._result.boundaries))} boundar"
                f"{'y' if stats.get('boundaries', 0) == 1 else 'ies'}: {stats.get('segments')} pieces, "
                f"{stats.get('iterations')} iterations. Step with ◀ ▶ or the slider.")

    # ------------------------------------------------------------------ changes
    @t.observe(*_TRACE_SETTINGS)
    def _on_setting(self, change):
        if self._applying:
            return
        settings = self._settings()
        if change["name"] == "corner_method":
            # keep only parameters the new detector takes
            allowed = {spec["name"] for spec in corner_param_specs(settings["corner_method"])}
            settings["corner_params"] = {k: v for k, v in settings["corner_params"].items() if k in allowed}
        try:
            with self._busy():
                result, notes = self._noting_warnings(lambda: run_with_budget(
                    lambda: self._run(self._mask, settings), self.time_budget_s, "the re-trace"))
        except BaseException as exc:  # even MemoryError or Ctrl+C: the last good settings come back
            self._restore_settings()
            if not isinstance(exc, Exception):
                raise
            self._reject(short_reason(exc), resync=_TRACE_SETTINGS)
            return
        with self._quiet(), self.hold_sync():
            if settings["corner_params"] != self.corner_params:
                self.corner_params = settings["corner_params"]
        self._accept(result)
        self._show_summary("", notes)

    def _restore_settings(self):
        """Put back the settings of the last good result."""
        with self._quiet(), self.hold_sync():
            for name, value in self._good.items():
                if getattr(self, name) != value:
                    setattr(self, name, value)

    @t.observe(*_IMAGE_SETTINGS)
    def _on_image_setting(self, change):
        if self._applying:
            return
        if change["name"] == "threshold" and change["new"] not in dict(THRESHOLDS):
            self._restore_settings()
            self._reject(f"threshold must be one of {', '.join(dict(THRESHOLDS))}, got {change['new']!r:.40}",
                         resync=_IMAGE_SETTINGS)
            return
        if change["name"] == "threshold" and change["new"] == "fixed" and "threshold" not in self._extra:
            self._restore_settings()  # "fixed" is the level given to the constructor; without one it is not offered
            self._reject("threshold 'fixed' needs a level: give TraceExplorer(..., threshold=<number>)",
                         resync=_IMAGE_SETTINGS)
            return
        if self.load(self._source):
            self._show_summary(f"Bitmap made again ({change['name']}); ", self._load_notes)
        else:
            self._restore_settings()
            if self._from_page:
                for name in _IMAGE_SETTINGS:
                    self.send_state(name)

    @t.validate("time_budget_s")
    def _valid_budget(self, proposal):
        value = proposal["value"]
        if value is None:
            return None
        try:
            return check_number(value, "time_budget_s", minimum=0.0, inclusive=False)
        except (TypeError, ValueError) as exc:
            raise t.TraitError(f"{exc} (seconds of a re-trace; None: no limit)") from None

    @t.observe("view")
    def _on_view(self, change):
        self._keep_good_view(change)

    @t.observe("snapshot_index")
    def _on_index(self, change):
        if self._applying:
            return
        index = change["new"]
        if not 0 <= index < max(self.n_snapshots, 1):
            with self._quiet():
                self.snapshot_index = change["old"]
            self._reject(f"there is no iteration {index} (0..{self.n_snapshots - 1})", resync=("snapshot_index",))
            return
        with self._quiet(), self.hold_sync():
            self._publish_snapshot()
        if "convergence" in self._plots:
            self._plots["convergence"].mark(self)

    def _on_upload(self, content, buffers):
        name = read_str(content, "name", default="upload").strip() or "upload"
        if not buffers:
            self._reject("the upload arrived without data")
            return
        if not memoryview(buffers[0]).nbytes:
            self._reject(f"{name}: the file is empty (0 bytes), not an image")
            return
        if self.load(_Upload(buffers[0], name)):
            self._show_summary(f"{name}: ", self._load_notes)

    def _save_good(self):
        return self._result, dict(getattr(self, "_good", {}))

    def _restore_good(self, saved) -> None:
        result, good = saved
        if result is not None and result is not self._result:
            self._accept(result)
        self._good = good
        self._restore_settings()
