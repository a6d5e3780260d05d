"""``TraceExplorer``: step through outline capture on a bitmap (thesis chapter 4) in JupyterLab.

The kernel runs :func:`splinecraft.trace` (bitmap -> boundaries -> corners -> spline fit with knot
insertion, every iteration kept) and sends the page what to draw: the bitmap as PNG bytes, the boundaries
and corners, and -- per iteration -- the fitted Bézier pieces, the knots and the candidate points the
algorithm accepted or rejected (float32 byte buffers). The page (``js/trace_explorer.js``) only draws,
steps and forwards the controls (detector and its tuning sliders, knot-insertion algorithm, ε, τ, seed,
an image upload). Bad values (NaN, ε <= 0, an image that cannot be read) keep the last good result and
show a short message.
"""
from __future__ import annotations

import html
import inspect
import io
import math
import numbers
from pathlib import Path

import numpy as np
import traitlets as t

from ..capture import CORNER_METHODS, KNOT_METHODS, load_bitmap, trace
from ._assets import load_css, load_esm
from ._base import WidgetBase, f32

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
_TRACE_PARAMS = ("epsilon", "method", "corner_method", "corner_params", "seed", "max_iterations", "tau",
                 "threshold", "invert", "min_speck_area", "connectivity", "contour", "fit_params")
_DISPLAY = ("width", "height", "show_image", "show_boundaries", "show_corners", "show_candidates", "show_final",
            "play_interval_ms", "view")
_MAX_UPLOAD_BYTES = 20_000_000
_MAX_PIXELS = 4_000_000


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
        ``show_image``, ``show_boundaries``, ``show_corners``, ``show_candidates``, ``show_final``,
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
    """

    _esm = load_esm("trace_explorer.js")
    _css = load_css()
    kept = "result"
    warning_class = TraceExplorerWarning
    panel_plot = "convergence_figure"
    panel_extra_width = 292
    messages = {**WidgetBase.messages, "upload": "_on_upload"}
    page_traits = frozenset(_TRACE_SETTINGS + _DISPLAY + ("snapshot_index",))

    image_png = t.Bytes(b"").tag(sync=True)
    image_size = t.List([1, 1]).tag(sync=True)
    corner_method = t.Unicode("").tag(sync=True)
    corner_params = t.Dict().tag(sync=True)
    method = t.Unicode("").tag(sync=True)
    epsilon = t.Float(2.0, allow_none=True).tag(sync=True)
    tau = t.Float(None, allow_none=True).tag(sync=True)
    seed = t.Int(0, allow_none=True).tag(sync=True)
    max_iterations = t.Int(200).tag(sync=True)

    snapshot_index = t.Int(0).tag(sync=True)
    n_snapshots = t.Int(0).tag(sync=True)
    play_interval_ms = t.Int(350).tag(sync=True)
    show_image = t.Bool(True).tag(sync=True)
    show_boundaries = t.Bool(True).tag(sync=True)
    show_corners = t.Bool(True).tag(sync=True)
    show_candidates = t.Bool(True).tag(sync=True)
    show_final = t.Bool(False).tag(sync=True)
    view = t.List([0.0, 0.0, 1.0, 1.0]).tag(sync=True)
    width = t.Int(600).tag(sync=True)
    height = t.Int(440).tag(sync=True)

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
        self._result = None
        super().__init__(**display)
        self._extra = {k: trace_params[k] for k in ("threshold", "invert", "min_speck_area", "connectivity",
                                                      "contour", "fit_params") if k in trace_params}
        settings = {
            "corner_method": trace_params.get("corner_method") or "",  # "" = trace()'s default
            "corner_params": dict(trace_params.get("corner_params") or {}),
            "method": trace_params.get("method") or "",
            "epsilon": float(trace_params.get("epsilon", 2.0)),
            "tau": trace_params.get("tau"),
            "seed": trace_params.get("seed", 0),
            "max_iterations": int(trace_params.get("max_iterations", 200)),
        }
        mask = self._load(demo_bitmap() if image is None else image)
        result = self._run(mask, settings)  # raises for bad constructor arguments
        # show the defaults trace() resolved (params records the names it used)
        settings["corner_method"] = settings["corner_method"] or str(result.params.get("corner_method") or "")
        settings["method"] = settings["method"] or str(result.params.get("method") or "")
        with self._quiet(), self.hold_sync():
            for name, value in settings.items():
                setattr(self, name, value)
            self.options = self._options()
        self._set_image(mask)
        self._accept(result)
        self._set_status(self._summary_message(), "info")

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
        try:
            mask = self._load(image)
            result = self._run(mask, self._settings())
        except (ValueError, TypeError, OSError) as exc:
            self._reject(str(exc))
            return False
        self._set_image(mask)
        self._accept(result)
        self._set_status(self._summary_message(), "info")
        return True

    def to_svg(self) -> str:
        """The traced outline as an SVG document (exact cubic Béziers, the bitmap's pixel frame)."""
        return self._result.to_svg()

    def save_svg(self, path) -> Path:
        path = Path(path)
        path.write_text(self.to_svg(), encoding="utf-8")
        return path

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
        if isinstance(image, (bytes, bytearray, memoryview)):
            if len(image) > _MAX_UPLOAD_BYTES:
                raise ValueError(f"the image is too large ({len(image)} bytes; limit {_MAX_UPLOAD_BYTES})")
            from PIL import Image, UnidentifiedImageError

            try:
                image = Image.open(io.BytesIO(bytes(image)))
                image.load()
            except (UnidentifiedImageError, OSError) as exc:
                raise ValueError(f"not a readable image: {exc}") from None
        keys = ("threshold", "invert", "min_speck_area", "connectivity")
        mask = load_bitmap(image, **{k: self._extra[k] for k in keys if k in self._extra})
        if mask.size > _MAX_PIXELS:
            raise ValueError(f"the bitmap has {mask.size} pixels; the explorer takes up to {_MAX_PIXELS}")
        return mask

    def _run(self, mask, settings):
        epsilon = settings["epsilon"]
        if epsilon is None or not math.isfinite(epsilon) or not 0 < epsilon <= 1000:
            raise ValueError(f"ε must be a number > 0, got {epsilon}")
        tau = settings["tau"]
        if tau is not None and (not math.isfinite(tau) or tau <= 0):
            raise ValueError(f"τ must be a number > 0 (or automatic), got {tau}")
        if settings["seed"] is None or settings["seed"] < 0:
            raise ValueError(f"the seed must be an integer ≥ 0, got {settings['seed']}")
        if settings["max_iterations"] < 0:
            raise ValueError("max_iterations must be ≥ 0")
        for name, value in settings["corner_params"].items():
            if value is None or (isinstance(value, float) and not math.isfinite(value)):
                raise ValueError(f"corner parameter {name} must be a number, got {value}")
        params = dict(self._extra)
        for key in ("threshold", "invert", "min_speck_area"):
            params.pop(key, None)  # the mask is already binary
        return trace(
            mask, epsilon=epsilon, method=settings["method"] or None,
            corner_method=settings["corner_method"] or None, corner_params=settings["corner_params"],
            seed=settings["seed"], max_iterations=settings["max_iterations"], keep_snapshots=True, tau=tau,
            **params,
        )

    def _accept(self, result):
        self._result = result
        count = max(len(result.snapshots), 1)
        with self._quiet(), self.hold_sync():
            self.n_snapshots = count
            self.snapshot_index = count - 1
            self.base_geometry = self._base_geometry(result)
            self.stats_html = self._stats_html(result)
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
    @staticmethod
    def _base_geometry(result) -> dict:
        rings = []
        for points in result.points:
            ring = np.vstack([points, points[:1], [[np.nan, np.nan]]])
            rings.append(ring)
        corners = [np.asarray(points)[np.asarray(idx, dtype=int)] for points, idx in zip(result.points, result.corners)
                   if len(idx)]
        final = np.concatenate([s.bezier() for s in result.splines], axis=0)
        return {
            "boundaries": f32(np.vstack(rings)) if rings else b"",
            "corners": f32(np.vstack(corners)) if corners else b"",
            "final": f32(final),
        }

    def _current(self):
        snapshots = self._result.snapshots
        if not snapshots:
            return None
        return snapshots[int(np.clip(self.snapshot_index, 0, len(snapshots) - 1))]

    def _publish_snapshot(self):
        result = self._result
        merged = self._current()
        if merged is None:
            bezier = np.concatenate([s.bezier() for s in result.splines], axis=0)
            self.snapshot_geometry = {"bezier": f32(bezier)}
            self.iteration_info = {"iteration": 0, "pieces": len(bezier)}
            return
        bezier = merged.bezier
        knots, accepted, rejected, removed = [], [], [], []
        for points, snapshot in zip(result.points, merged.snapshots):
            indices = np.unique(np.concatenate([np.asarray(k, dtype=int).reshape(-1) for k in snapshot.knot_indices])) \
                if len(snapshot.knot_indices) else np.zeros(0, dtype=int)
            knots.append(np.asarray(points)[indices % len(points)])
            for candidate in snapshot.candidates or []:
                point = candidate.get("point")
                if point is None:
                    continue
                action = candidate.get("action", "insert")
                if action == "insert":
                    (accepted if candidate.get("accepted") else rejected).append(point)
                elif action == "remove" and candidate.get("accepted"):
                    removed.append(point)
        worst, worst_contour = self._worst_piece(result, merged)
        self.snapshot_geometry = {
            "iteration": int(merged.iteration),
            "bezier": f32(bezier),
            "worst": f32(worst),
            "worst_contour": f32(worst_contour),
            "knots": f32(np.vstack(knots)) if knots else b"",
            "accepted": f32(np.asarray(accepted, dtype=float).reshape(-1, 2)),
            "rejected": f32(np.asarray(rejected, dtype=float).reshape(-1, 2)),
            "removed": f32(np.asarray(removed, dtype=float).reshape(-1, 2)),
        }
        finished = int(np.sum(merged.finished)) if len(merged.finished) else 0
        total = len(merged.snapshots)
        phases = {getattr(s, "phase", "insert") for s, done in zip(merged.snapshots, merged.finished) if not done}
        notes = []
        if self.snapshot_index == 0:
            if self._result.params.get("method") == "lsq":
                notes.append("Iteration 0 is the first fit: the corners, and knots where the contour's curvature "
                             "calls for them.")
            else:
                notes.append("Iteration 0 is the first fit, with the corners as the only knots.")
        elif "remove" in phases:
            notes.append(f"Knot removal round: {len(removed)} knot(s) dropped where the fit stays within ε.")
        if finished and finished < total and self.snapshot_index > 0:
            notes.append(f"{finished} of {total} boundaries have already finished.")
        if self.snapshot_index > 0 and any(getattr(s, "thesis_stop", False) for s in merged.snapshots):
            notes.append("The thesis's stopping rule (no candidate above ε) would stop here.")
        note = " ".join(notes)
        self.iteration_info = {
            "iteration": int(merged.iteration),
            "knots": int(merged.knots),
            "pieces": int(len(bezier)),
            "max_error": float(merged.max_error),
            "hausdorff": float(merged.hausdorff),
            "accepted": len(accepted),
            "rejected": len(rejected),
            "removed": len(removed),
            "note": note,
        }

    @staticmethod
    def _worst_piece(result, merged):
        """Bézier segments and contour points of the corner-to-corner piece with the largest thesis error.

        ``piece_max_error`` has one entry per piece between corners; piece ``k`` of a boundary is drawn by
        ``len(knot_indices[k]) - 1`` consecutive Bézier segments and approximates the contour points from its
        first to its last knot index (wrapping past index 0).
        """
        best = None
        offset = 0
        for boundary, snapshot in enumerate(merged.snapshots):
            errors = np.asarray(snapshot.piece_max_error, dtype=float)
            counts = [len(k) - 1 for k in snapshot.knot_indices]
            if errors.size and np.isfinite(errors).any() and len(counts) == errors.size:
                k = int(np.nanargmax(errors))
                if best is None or errors[k] > best[0]:
                    best = (float(errors[k]), boundary, k, offset + sum(counts[:k]), counts[k])
            offset += len(snapshot.bezier)
        if best is None:
            return np.zeros((0, 4, 2)), np.zeros((0, 2))
        _error, boundary, k, first_row, count = best
        segments = merged.bezier[first_row:first_row + count]
        points = np.asarray(result.points[boundary])
        indices = merged.snapshots[boundary].knot_indices[k]
        first, last = int(indices[0]), int(indices[-1])
        span = np.arange(first, last + 1 if last > first else last + len(points) + 1) % len(points)
        return segments, points[span]

    @staticmethod
    def _stats_html(result) -> str:
        stats = result.stats
        params = result.params

        def number(value, digits=2):
            if value is None:
                return "—"
            if isinstance(value, (bool, np.bool_)):
                return "yes" if value else "no"
            if isinstance(value, numbers.Integral):
                return f"{int(value):,}"
            if isinstance(value, numbers.Real):
                return "—" if not math.isfinite(value) else f"{value:.{digits}f}"
            return html.escape(str(value))

        columns = [
            ("Total number of points on contour", number(stats.get("contour_points"))),
            ("Number of corner points", number(stats.get("corners"))),
            ("Number of knots inserted", number(stats.get("knots_inserted"))),
            ("Total number of iterations", number(stats.get("iterations"))),
            ("Execution time (s)", number(stats.get("time_s"), 3)),
            ("Threshold value ε (px)", number(params.get("epsilon"))),
            ("% reduction in dataset (Table 4.61)", number(stats.get("data_reduction_pct_thesis"))),
            ("% reduction, stored numbers", number(stats.get("data_reduction_pct"))),
            ("Cubic segments", number(stats.get("segments"))),
            ("Max error, thesis (px)", number(stats.get("max_error"), 3)),
            ("Hausdorff distance (px)", number(stats.get("hausdorff"), 3)),
            ("Converged", number(stats.get("converged"))),
        ]
        head = "".join(f"<th>{html.escape(label)}</th>" for label, _value in columns)
        row = "".join(f"<td>{value}</td>" for _label, value in columns)
        caption = html.escape(
            f"Algorithm {params.get('method')}, corners {params.get('corner_method')}, seed {params.get('seed')}. "
            "The first six columns are those of thesis Tables 4.1–4.60.")
        return (f'<table class="sc-table" data-testid="stats-table"><thead><tr>{head}</tr></thead>'
                f'<tbody><tr>{row}</tr></tbody></table><div class="sc-caption">{caption}</div>')

    def _options(self) -> dict:
        corner = [[name, name] for name in CORNER_METHODS]
        return {
            "corner_methods": corner,
            "knot_methods": [[name, name] for name in KNOT_METHODS],
            "knot_descriptions": {name: str(description) for name, description in KNOT_METHODS.items()},
            "corner_params": {name: corner_param_specs(name) for name in CORNER_METHODS},
        }

    def _summary_message(self) -> str:
        stats = self._result.stats
        return (f"Traced {stats.get('boundaries', len(self._result.boundaries))} boundar"
                f"{'y' if stats.get('boundaries', 0) == 1 else 'ies'}: {stats.get('segments')} pieces, "
                f"{stats.get('iterations')} iterations. Step with ◀ ▶ or the slider.")

    # ------------------------------------------------------------------ changes
    @t.observe("corner_method", "corner_params", "method", "epsilon", "tau", "seed", "max_iterations")
    def _on_setting(self, change):
        if self._applying:
            return
        name = change["name"]
        settings = self._settings()
        if name == "corner_method":
            # keep only parameters the new detector takes
            allowed = {spec["name"] for spec in corner_param_specs(settings["corner_method"])}
            settings["corner_params"] = {k: v for k, v in settings["corner_params"].items() if k in allowed}
        with self._quiet():
            self.busy = True
        try:
            result = self._run(self._mask, settings)
        except (ValueError, TypeError) as exc:
            with self._quiet():
                self.busy = False
                setattr(self, name, change["old"])
            self._reject(str(exc), resync=(name,))
            return
        with self._quiet(), self.hold_sync():
            self.busy = False
            if settings["corner_params"] != self.corner_params:
                self.corner_params = settings["corner_params"]
        self._accept(result)
        self._set_status(self._summary_message(), "info")

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
        if not buffers:
            self._reject("the upload arrived without data")
            return
        name = str(content.get("name", "upload"))
        if self.load(bytes(buffers[0])):
            self._set_status(f"{name}: {self._summary_message()}", "info")
