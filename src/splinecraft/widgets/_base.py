"""What every splinecraft widget shares: status, rejection of bad input, page traffic, companion figures.

A widget subclasses :class:`WidgetBase` (itself an ``anywidget.AnyWidget``) and gets

* the ``status_message`` / ``status_level`` / ``busy`` traits, :meth:`~WidgetBase._set_status` and
  :meth:`~WidgetBase._busy` (a visible busy state around long work, with :func:`run_with_budget`);
* :meth:`~WidgetBase._quiet` -- a context for the widget's own trait changes: observers return early
  while ``self._applying`` is non-zero;
* :meth:`~WidgetBase._reject` -- "kept the last good ...": an error status, a :attr:`warning_class`
  warning when the bad value came from code, and a resync of the page when it came from the page;
* :meth:`~WidgetBase.set_state` -- trait updates from the page, applied one key at a time (a bad value
  does not drop the good ones sent with it); only :attr:`page_traits` may be written by the page; a value
  the trait type refuses (a string for a bool) gets a status and a resync instead of a traceback;
* :meth:`~WidgetBase._handle_message` -- custom messages ``{"type": ...}`` dispatched through
  :attr:`messages` to methods ``handler(content, buffers)``; any exception (a bad field, a MemoryError)
  restores the state saved before the message (:meth:`~WidgetBase._save_good` /
  :meth:`~WidgetBase._restore_good`) and sets a status; after an exception or a :meth:`~WidgetBase._reject`
  the page is resynced (:meth:`~WidgetBase._resync_after`, then the whole state);
* strict readers of message fields (:func:`read_int`, :func:`read_number`, :func:`read_bool`,
  :func:`read_str`) raising :class:`BadMessage` that names the field -- exact types (a bool is not an
  int), ranges and finiteness;
* :meth:`~WidgetBase._plot` -- companion figures (bqplot) created on first use and updated by
  :meth:`~WidgetBase._update_plots`; :meth:`~WidgetBase.panel` shows the widget above
  :attr:`panel_plot`;
* exact trait types (:class:`Bool`, :class:`Int`, :class:`Float`: a bool is not a number, 0 is not
  False), :class:`NumberList`, and :class:`PointList` with its float64 byte transport
  (:func:`points_to_json`, :func:`points_from_json`; capped at the widget's ``max_points``);
* :func:`f32` -- the float32 byte buffers the pages decode.

Debug hooks for benchmarks (drag latency records, ping) are off unless ``debug=True`` is passed (or
:data:`DEBUG_ENV` is set in the kernel's environment).
"""
from __future__ import annotations

import concurrent.futures
import contextlib
import logging
import math
import numbers
import os
import sys
import time
import warnings

import anywidget
import numpy as np
import traitlets as t

from .._validation import check_bool, check_choice, check_int, check_number

__all__ = ["WidgetBase", "BadMessage", "Bool", "Int", "Float", "NumberList", "PointList", "json_numbers",
           "points_to_json", "points_from_json", "read_int", "read_number", "read_bool", "read_str",
           "f32", "run_with_budget", "short_reason", "view_problem", "VIEW_PRECISION", "DEBUG_ENV"]

#: Environment variable that switches the benchmark hooks on for every widget of a kernel.
DEBUG_ENV = "SPLINECRAFT_WIDGET_DEBUG"
#: Longest reason the status line shows (it wraps): the engine's refusals end with their advice, e.g. the safe
#: point tensions of a row, about 300 characters in.
_MAX_REASON = 360
_NOT_RESYNCED = frozenset({"layout", "tabbable", "tooltip"})
_REQUIRED = object()
_log = logging.getLogger("splinecraft.widgets")


class BadMessage(ValueError):
    """A message from the page has a missing or bad field; the text names the field."""


def f32(array) -> bytes:
    """Little-endian float32 bytes of an array (the page decodes them as a ``Float32Array``)."""
    return np.ascontiguousarray(np.asarray(array, dtype="<f4")).tobytes()


# ---------------------------------------------------------------------------------------------- exact traits
class Bool(t.Bool):
    """A bool trait that takes only ``True``/``False`` (``np.bool_`` too): not 0, 1 or ``"no"``."""

    def validate(self, obj, value):
        if isinstance(value, (bool, np.bool_)):
            return bool(value)
        self.error(obj, value)


class Int(t.Int):
    """An int trait that refuses bools (``True`` is not the integer 1 here); numpy integers are fine."""

    def validate(self, obj, value):
        if isinstance(value, (bool, np.bool_)):
            self.error(obj, value)
        if isinstance(value, np.integer):
            value = int(value)
        return super().validate(obj, value)


#: The texts a page's number box sends for a value that is no finite number (JSON has no NaN or infinity):
#: read as those floats, which the widget then refuses with its own message (``js/common.js`` ``sliderRow``).
NONFINITE_TEXT = {"NaN": math.nan, "Infinity": math.inf, "-Infinity": -math.inf}


class Float(t.Float):
    """A float trait that refuses bools; ints and numpy numbers become floats, and the texts of
    :data:`NONFINITE_TEXT` their floats."""

    def validate(self, obj, value):
        if isinstance(value, (bool, np.bool_)):
            self.error(obj, value)
        if isinstance(value, (np.floating, np.integer)):
            value = float(value)
        if isinstance(value, str) and value in NONFINITE_TEXT:
            value = NONFINITE_TEXT[value]
        return super().validate(obj, value)


class NumberList(t.List):
    """A list of numbers; numpy arrays are accepted, ``None`` items and the texts of :data:`NONFINITE_TEXT` (from the
    page) become NaN or infinities, bools are refused.

    A single number is broadcast to the list's current length (``editor.point_tension = 2.0`` sets every
    point's tension, as the constructor's ``point_tension=2.0`` does); the widget then checks the values."""

    def validate(self, obj, value):
        if getattr(obj, "_applying", 0) and isinstance(value, list):
            return value  # the widget's own value, checked already
        if isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)):
            current = obj._trait_values.get(self.name) or [None]
            value = [value] * len(current)
        if isinstance(value, np.ndarray):
            value = value.tolist()
        if isinstance(value, (list, tuple)):
            value = [NONFINITE_TEXT[v] if isinstance(v, str) and v in NONFINITE_TEXT else v for v in value]
            if not all(v is None or (isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_)))
                       for v in value):
                raise t.TraitError(f"{self.name} must be a list of numbers")
            value = [float("nan") if v is None else float(v) for v in value]
        return super().validate(obj, value)


class PointList(t.List):
    """``[[x, y], ...]``; numpy arrays are accepted. At most ``obj.max_points`` points (the widget's cap)."""

    def validate(self, obj, value):
        if getattr(obj, "_applying", 0) and isinstance(value, list):
            return value  # the widget's own value, checked already
        try:
            array = np.array(value, dtype=float)
        except (TypeError, ValueError) as exc:
            raise t.TraitError(f"points must be an (n, 2) array of numbers: {exc}") from None
        if array.size == 0:
            array = array.reshape(0, 2)
        if array.ndim != 2 or array.shape[1] != 2:
            raise t.TraitError(f"points must have shape (n, 2), got {array.shape}")
        if array.shape[0] > obj.max_points:
            raise t.TraitError(f"{array.shape[0]} points; the editor takes at most max_points = {obj.max_points}")
        return array.tolist()


def json_numbers(value, _widget=None):
    """A synced list (nested lists of numbers) with every non-finite float as ``None`` (JSON ``null``): a value the
    widget is about to refuse can reach the page once (ipywidgets echoes a validated value that differs from the
    page's, and a value set from code syncs before the observer reverts it), and NaN or inf is not JSON."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, (list, tuple)):
        return [json_numbers(item) for item in value]
    return value


def points_to_json(value, _widget):
    """``points`` travel to the page as little-endian float64 bytes (x0, y0, x1, y1, ...), not JSON lists."""
    return np.asarray(value, dtype="<f8").reshape(-1).tobytes()


def points_from_json(value, widget):
    if isinstance(value, (bytes, bytearray, memoryview)):
        size = memoryview(value).nbytes
        if size % 16:
            raise t.TraitError(f"points: a buffer of {size} bytes is not a whole number of (x, y) float64 pairs")
        if size // 16 > widget.max_points:
            raise t.TraitError(f"{size // 16} points; the editor takes at most max_points = {widget.max_points}")
        return np.frombuffer(bytes(value), dtype="<f8").reshape(-1, 2).tolist()
    return value


# ---------------------------------------------------------------------------------------------- message fields
def _field(content: dict, name: str, default):
    if name in content:
        return content[name]
    if default is _REQUIRED:
        raise BadMessage(f"the message has no field {name!r}")
    return default


def _checked(check, value, *args, **kwargs):
    try:
        return check(value, *args, **kwargs)
    except (TypeError, ValueError) as exc:
        raise BadMessage(str(exc)) from None


def read_int(content: dict, name: str, *, low: int, high: int, default=_REQUIRED) -> int:
    """Field ``name`` as an int in ``[low, high]`` (a bool or a float is refused)."""
    value = _field(content, name, default)
    if value is default and default is not _REQUIRED:
        return value
    return _checked(check_int, value, name, minimum=low, maximum=high)


def read_number(content: dict, name: str, *, low: float | None = None, high: float | None = None,
                default=_REQUIRED, inclusive=True) -> float:
    """Field ``name`` as a finite float in ``[low, high]`` (a bool, None or NaN is refused); ``inclusive`` as in
    :func:`~splinecraft._validation.check_number` (``(False, True)``: ``(low, high]``)."""
    value = _field(content, name, default)
    if value is default and default is not _REQUIRED:
        return value
    return _checked(check_number, value, name, minimum=low, maximum=high, inclusive=inclusive)


def read_bool(content: dict, name: str, *, default=_REQUIRED) -> bool:
    """Field ``name`` as an exact bool (``"no"``, 0 or 1 are refused)."""
    value = _field(content, name, default)
    if value is default and default is not _REQUIRED:
        return value
    return _checked(check_bool, value, name)


def read_str(content: dict, name: str, *, choices=None, max_length: int = 200, default=_REQUIRED) -> str:
    """Field ``name`` as a string of at most ``max_length`` characters (one of ``choices`` when given)."""
    value = _field(content, name, default)
    if value is default and default is not _REQUIRED:
        return value
    if type(value) is not str or len(value) > max_length:
        raise BadMessage(f"{name} must be a string of at most {max_length} characters, got {type(value).__name__}")
    return value if choices is None else _checked(check_choice, value, name, tuple(choices))


# ---------------------------------------------------------------------------------------------- long work
_WORKER = concurrent.futures.ThreadPoolExecutor(max_workers=1, thread_name_prefix="splinecraft-widget")


def run_with_budget(function, seconds: float, what: str = "the computation"):
    """``function()`` in a worker thread, waiting at most ``seconds``; raises ``TimeoutError`` after that.

    The kernel stays responsive to the page meanwhile (its busy state is visible). Python cannot stop a
    running thread: after a timeout the work finishes in the background and its result is dropped; the
    next call waits in line behind it (one worker), so runaway work never piles up.
    """
    future = _WORKER.submit(function)
    try:
        return future.result(timeout=seconds)
    except concurrent.futures.TimeoutError:
        future.cancel()
        raise TimeoutError(f"{what} took longer than its time budget of {seconds:g} s") from None


#: A view narrower (or lower) than this fraction of its largest coordinate (at least 1) is refused: the page
#: could not tell its grid lines and points apart (``x + step == x``). The page's zoom stops 10 times above it.
VIEW_PRECISION = 1e-9


def view_problem(view) -> str | None:
    """Why ``view`` is not a visible rectangle ``[xmin, ymin, xmax, ymax]`` the page can draw (None if it is).

    Four finite numbers with ``xmax > xmin`` and ``ymax > ymin``; the width and height must be finite (not
    an overflow) and at least :data:`VIEW_PRECISION` times ``max(1, |coordinate|)``.
    """
    shape = "view must be [xmin, ymin, xmax, ymax] of finite numbers with xmax > xmin, ymax > ymin"
    if not (isinstance(view, (list, tuple)) and len(view) == 4
            and all(isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_)) for v in view)):
        return shape
    try:
        x0, y0, x1, y1 = (float(v) for v in view)
    except (OverflowError, TypeError, ValueError):
        return shape
    if not (all(math.isfinite(v) for v in (x0, y0, x1, y1)) and x1 > x0 and y1 > y0):
        return shape
    width, height = x1 - x0, y1 - y0
    if not (math.isfinite(width) and math.isfinite(height)):
        return (f"view is too large: its width (xmax - xmin = {width:g}) and height (ymax - ymin = {height:g}) "
                "must be finite numbers, not overflow")
    smallest = VIEW_PRECISION * max(1.0, abs(x0), abs(y0), abs(x1), abs(y1))
    if min(width, height) < smallest:
        return (f"view is too small for its coordinates: width {width:.3g} and height {height:.3g} must be at "
                f"least {VIEW_PRECISION:g} x max(1, |coordinate|) = {smallest:.3g}")
    return None


def _caller_stacklevel() -> int:
    """Stack level of the first frame outside splinecraft, traitlets and the widget libraries."""
    frame, level = sys._getframe(1), 1
    while frame is not None:
        name = frame.f_globals.get("__name__", "")
        if not name.startswith(("splinecraft.", "traitlets", "ipywidgets", "anywidget", "comm")):
            return level
        frame, level = frame.f_back, level + 1
    return 1


def short_reason(exc: BaseException | str) -> str:
    """The first line of an error, at most :data:`_MAX_REASON` characters (what the status line shows)."""
    if isinstance(exc, BaseException):
        text = str(exc) or type(exc).__name__
        if not isinstance(exc, (ValueError, TypeError, t.TraitError)):
            text = f"{type(exc).__name__}: {text}"
    else:
        text = exc
    text = text.split("\n")[0]
    return text if len(text) <= _MAX_REASON else text[:_MAX_REASON - 1] + "…"


class WidgetBase(anywidget.AnyWidget):
    """Base of the splinecraft widgets: see the module docstring for what it provides.

    Subclasses set the class attributes below and may override :meth:`_save_good`,
    :meth:`_restore_good` and :meth:`_resync_after` (all optional).
    """

    #: Word for what is kept after a bad input ("curve", "result", "outline").
    kept = "state"
    #: Warning category for values rejected from code.
    warning_class: type = UserWarning
    #: Traits the page may set (everything else is the kernel's; a page update of it is refused).
    page_traits: frozenset = frozenset()
    #: Custom message type -> name of the handler method ``handler(content, buffers)``. Subclasses extend it:
    #: ``messages = {**WidgetBase.messages, "drag": "_on_drag"}``.
    messages: dict = {"ping": "_on_ping"}
    #: Name of the figure property :meth:`panel` shows under the widget, and the extra width it gets.
    panel_plot: str | None = None
    panel_extra_width = 270

    status_message = t.Unicode("").tag(sync=True)
    status_level = t.Unicode("info").tag(sync=True)
    busy = Bool(False).tag(sync=True)
    debug = Bool(False).tag(sync=True)
    large = Bool(False).tag(sync=True)

    def __init__(self, **traits):
        self._applying = 0
        self._from_page = False
        self._page_rejections = 0
        self._plots: dict = {}
        traits.setdefault("debug", bool(os.environ.get(DEBUG_ENV)))
        super().__init__(**traits)
        self.on_msg(self._handle_message)

    # ------------------------------------------------------------------ own changes, status
    @contextlib.contextmanager
    def _quiet(self):
        """Trait changes made inside are the widget's own: observers see ``self._applying`` and return."""
        self._applying += 1
        try:
            yield
        finally:
            self._applying -= 1

    def _set_status(self, message: str, level: str = "info") -> None:
        with self._quiet(), self.hold_sync():
            self.status_message = message
            self.status_level = level

    @contextlib.contextmanager
    def _busy(self):
        """``busy`` is True inside (the page shows it at once); always cleared, whatever happens."""
        with self._quiet():
            self.busy = True
        try:
            yield
        finally:
            with self._quiet():
                self.busy = False

    def _reject(self, reason, *, resync=()) -> None:
        """Keep the last good state: error status, a warning (from code) or a resync of ``resync`` (from the page)."""
        reason = short_reason(reason)
        self._set_status(f"Kept the last good {self.kept}: {reason}", "error")
        if self._from_page:
            self._page_rejections += 1
            for name in resync:
                self.send_state(name)
        else:
            warnings.warn(f"{type(self).__name__}: {reason}; kept the last good {self.kept}", self.warning_class,
                          stacklevel=_caller_stacklevel())

    @staticmethod
    def _given_view(params) -> list | None:
        """The ``view`` a constructor was given (taken out of ``params``): None when it was not given, else
        the four floats; a view :func:`view_problem` refuses raises ValueError naming the problem. The
        constructor shows it instead of fitting the view to its contents."""
        view = params.pop("view", None)
        if view is None:
            return None
        problem = view_problem(view)
        if problem:
            raise ValueError(problem)
        return [float(value) for value in view]

    def _keep_good_view(self, change) -> None:
        """The ``view`` observer's rule: a view :func:`view_problem` refuses goes back to the last good one."""
        problem = None if self._applying else view_problem(change["new"])
        if problem:
            with self._quiet():
                self.view = change["old"]
            self._reject(problem, resync=("view",))

    # ------------------------------------------------------------------ page -> kernel
    @contextlib.contextmanager
    def _page(self):
        previous, self._from_page = self._from_page, True
        try:
            yield
        finally:
            self._from_page = previous

    def set_state(self, sync_data):
        """Trait updates from the page, one key at a time; refused keys and values are answered, not raised."""
        with self._page():
            for name, value in dict(sync_data).items():
                if name not in self.page_traits:
                    if name in self.keys:
                        self._reject(f"the page may not set {name}", resync=(name,))
                    continue
                try:
                    super().set_state({name: value})
                except Exception as exc:  # noqa: BLE001 - any failure: status + resync, never a lost traceback
                    _log.debug("page update of %s refused", name, exc_info=True)
                    reason = short_reason(exc)
                    self._reject(reason if reason.startswith(name) else f"{name}: {reason}", resync=(name,))

    def _handle_message(self, _widget, content, buffers):
        """Dispatch a custom message; any failure restores the saved state, sets a status and resyncs the page."""
        with self._page():
            saved = self._save_good()
            try:
                if not isinstance(content, dict):
                    raise BadMessage(f"a message must be an object, got {type(content).__name__}")
                kind = content.get("type")
                if type(kind) is not str or kind not in self.messages:
                    raise BadMessage(f"unknown message type {kind!r:.40}")
                if kind == "ping" and not self.debug:
                    raise BadMessage("ping is a debug message (set debug=True)")
                rejections = self._page_rejections
                getattr(self, self.messages[kind])(content, list(buffers or []))
                refused = self._page_rejections > rejections  # the handler kept the last good state
            except Exception as exc:  # noqa: BLE001 - MemoryError and engine bugs too: the page must hear of it
                if not isinstance(exc, BadMessage):
                    _log.warning("%s: message handler failed", type(self).__name__, exc_info=True)
                try:
                    self._restore_good(saved)
                except Exception:  # noqa: BLE001 - the restore failed too (same cause): still answer the page
                    _log.warning("%s: restoring the last good state failed", type(self).__name__, exc_info=True)
                # "bad message" only for a malformed one: a refused action ("select a knot first") says just why
                self._reject(f"bad message: {short_reason(exc)}" if isinstance(exc, BadMessage) else exc)
                refused = True
            if refused:
                self._resync_after(content)
                self._resync()

    def _resync(self) -> None:
        """Send the page every trait it shows (not the module source, layout or model names)."""
        self.send_state(key=[name for name in self.keys if not name.startswith("_") and name not in _NOT_RESYNCED])

    def _on_ping(self, content, _buffers):
        """Transport round trip for the benchmarks (answered only with ``debug=True``); the answer carries a
        buffer of ``bytes`` zero bytes (default none), to measure what a message's size costs."""
        size = read_int(content, "bytes", low=0, high=1 << 22, default=0)
        self.send({"type": "pong", "id": read_int(content, "id", low=0, high=2**53),
                   "kernel_ms": time.time() * 1e3}, buffers=[bytes(size)] if size else None)

    def _save_good(self):
        """What :meth:`_restore_good` needs to undo a failed message (default: nothing)."""
        return None

    def _restore_good(self, saved) -> None:
        """Put back the state saved by :meth:`_save_good` (default: nothing to do)."""

    def _resync_after(self, content) -> None:
        """Extra answers to a refused message (e.g. a negative drag acknowledgement); default none."""

    # ------------------------------------------------------------------ companion figures
    def _plot(self, name: str, factory):
        """The companion plot ``name``, made by ``factory()`` on first use and then kept in sync."""
        plot = self._plots.get(name)
        if plot is None:
            plot = self._plots[name] = factory()
            plot.update(self)
        return plot

    def panel(self):
        """The widget above its companion figure (an ``ipywidgets.VBox``) -- display this in a notebook."""
        import ipywidgets

        if self.panel_plot is None:
            return ipywidgets.VBox([self])
        figure = getattr(self, self.panel_plot)
        figure.layout.width = f"{self.width + self.panel_extra_width}px"
        return ipywidgets.VBox([self, figure])
