"""The shared widget base: strict message fields, page updates one key at a time, status and resync."""
from __future__ import annotations

import math
import threading

import pytest
import traitlets as t
from hypothesis import given, settings, strategies as st

from splinecraft.widgets._base import (
    VIEW_PRECISION, BadMessage, WidgetBase, read_bool, read_int, read_number, read_str, run_with_budget, view_problem,
)


class Probe(WidgetBase):
    """A minimal widget on the base: one page-writable trait, one kernel-only trait, one message."""

    kept = "probe"
    page_traits = frozenset({"size", "flag"})
    messages = {**WidgetBase.messages, "poke": "_on_poke", "explode": "_on_explode"}
    size = t.Int(5, min=1, max=10).tag(sync=True)
    flag = t.Bool(False).tag(sync=True)
    count = t.Int(0).tag(sync=True)

    def __init__(self, **traits):
        super().__init__(**traits)
        self.resynced, self.sent = [], []
        # resyncs send one named trait or everything (None); hold_sync's own flushes pass sets
        self.send_state = lambda key=None: isinstance(key, (set, frozenset)) or self.resynced.append(key)
        self.send = lambda content, buffers=None: self.sent.append(content)

    def _on_poke(self, content, _buffers):
        self.count = read_int(content, "by", low=1, high=3)

    def _on_explode(self, _content, _buffers):
        self.count = 99
        raise MemoryError("out of memory in a handler")

    def _save_good(self):
        return self.count

    def _restore_good(self, saved):
        self.count = saved


@pytest.mark.parametrize("value, ok", [(3, True), (True, False), (3.0, False), ("3", False), (None, False), (9, False)])
def test_read_int_is_exact(value, ok):
    if ok:
        assert read_int({"n": value}, "n", low=0, high=5) == value
    else:
        with pytest.raises(BadMessage, match="n"):
            read_int({"n": value}, "n", low=0, high=5)


@pytest.mark.parametrize("value", [math.nan, math.inf, None, True, "1.5", [1.0]])
def test_read_number_refuses_non_finite_and_non_numbers(value):
    with pytest.raises(BadMessage, match="x"):
        read_number({"x": value}, "x")
    assert read_number({"x": 2}, "x") == 2.0 and read_number({}, "x", default=None) is None


@pytest.mark.parametrize("value", ["no", 0, 1, None, "true"])
def test_read_bool_is_exact(value):
    with pytest.raises(BadMessage, match="final"):
        read_bool({"final": value}, "final")
    assert read_bool({}, "final", default=False) is False and read_bool({"final": True}, "final") is True


def test_read_str_choices_and_missing_fields():
    assert read_str({"m": "a"}, "m", choices=("a", "b")) == "a"
    with pytest.raises(BadMessage, match="one of"):
        read_str({"m": "c"}, "m", choices=("a", "b"))
    with pytest.raises(BadMessage, match="no field"):
        read_str({}, "m")


def test_page_updates_apply_one_key_at_a_time_and_answer_bad_values():
    probe = Probe()
    probe.set_state({"size": 7, "flag": "no"})  # a string for a bool: refused, the good size is kept
    assert probe.size == 7 and probe.flag is False
    assert probe.status_level == "error" and "flag" in probe.status_message
    assert probe.resynced == ["flag"]
    probe.set_state({"size": -100})
    assert probe.size == 7 and probe.resynced[-1] == "size"
    probe.set_state({"count": 10**9})  # kernel-only trait
    assert probe.count == 0 and "may not set count" in probe.status_message


def test_messages_are_dispatched_and_failures_restore_and_resync():
    probe = Probe()
    probe._handle_message(probe, {"type": "poke", "by": 2}, [])
    assert probe.count == 2
    for bad in ({"type": "poke", "by": True}, {"type": "poke"}, {"type": "nope"}, "text", {"type": None}):
        probe.resynced.clear()
        probe._handle_message(probe, bad, [])
        assert probe.count == 2 and probe.status_level == "error" and len(probe.resynced) == 1
    probe._handle_message(probe, {"type": "explode"}, [])
    assert probe.count == 2 and "MemoryError" in probe.status_message


def test_ping_answers_only_in_debug_mode():
    probe = Probe()
    probe._handle_message(probe, {"type": "ping", "id": 1}, [])
    assert probe.sent == [] and "debug" in probe.status_message
    probe = Probe(debug=True)
    probe._handle_message(probe, {"type": "ping", "id": 1}, [])
    assert probe.sent[-1]["type"] == "pong" and probe.sent[-1]["id"] == 1


def test_bad_values_from_code_warn_and_from_the_page_do_not():
    probe = Probe()
    with pytest.warns(UserWarning, match="kept the last good probe"):
        probe._reject("no good")
    assert probe.resynced == []


def test_run_with_budget_returns_or_times_out():
    assert run_with_budget(lambda: 41 + 1, 5.0) == 42
    release = threading.Event()
    with pytest.raises(TimeoutError, match="time budget of 0.05 s"):
        run_with_budget(lambda: release.wait(5.0), 0.05, "the probe")
    release.set()
    with pytest.raises(ZeroDivisionError):
        run_with_budget(lambda: 1 / 0, 5.0)


def test_busy_is_cleared_whatever_happens():
    probe = Probe()
    with pytest.raises(RuntimeError):
        with probe._busy():
            assert probe.busy
            raise RuntimeError("boom")
    assert probe.busy is False


# ---------------------------------------------------------------------------------------------- views
@pytest.mark.parametrize("view, words", [
    ([1e17, 0, 1e17 + 32, 1], "too small for its coordinates"),       # x + step == x on the page: it hung
    ([0, 0, 1e-10, 1], "too small for its coordinates"),
    ([1e9, 0, 1e9 + 1e-6, 1e-6], "too small for its coordinates"),
    ([-1e308, -1e308, 1e308, 1e308], "too large"),                    # the width overflows to inf
    ([0, -1e308, 1, 1e308], "too large"),
    ([0, 0, math.nan, 1], "finite numbers"),
    ([0, 0, 10**400, 1], "finite numbers"),                            # an int beyond float
    ([0, 0, 1, 1, 1], "finite numbers"), ([True, 0, 1, 1], "finite numbers"), ([1, 0, 0, 1], "xmax > xmin"),
])
def test_view_problem_refuses_views_the_page_cannot_draw(view, words):
    assert words in view_problem(view)


@given(st.floats(-1e300, 1e300), st.floats(-1e300, 1e300), st.floats(3e-9, 1.0), st.floats(3e-9, 1.0))
@settings(max_examples=200, deadline=None)
def test_view_problem_takes_sides_above_the_precision_and_refuses_those_below(x, y, w, h):
    scale = max(1.0, abs(x), abs(y))  # the sides are relative to the largest coordinate
    assert view_problem([x, y, x + w * scale, y + h * scale]) is None
    assert "too small" in view_problem([x, y, x + 0.5 * VIEW_PRECISION * scale, y + h * scale])
    assert "too small" in view_problem([x, y, x + w * scale, y + 0.5 * VIEW_PRECISION * scale])


def _widgets_with(view):
    """Each widget built with ``view=`` (the outline editor on a traced square, the explorer on its demo)."""
    import numpy as np

    import splinecraft as sc
    from splinecraft.widgets import OutlineEditor, SplineEditor, TraceExplorer

    mask = np.zeros((30, 30), bool)
    mask[5:25, 5:25] = True
    yield lambda: OutlineEditor(sc.trace(mask), view=view)
    yield lambda: SplineEditor(view=view)
    yield lambda: TraceExplorer(view=view)


@pytest.mark.parametrize("index", range(3))
def test_constructors_show_the_view_they_are_given(index):
    """A ``view=`` given to a constructor is the view shown (not replaced by the fitted one)."""
    build = list(_widgets_with((2, -3.5, 102, 77.25)))[index]
    assert build().view == [2.0, -3.5, 102.0, 77.25]


@pytest.mark.parametrize("index", range(3))
@pytest.mark.parametrize("view, words", [([0, 0, math.nan, 1], "finite numbers"), ([0, 0, 1], "finite numbers"),
                                         ([5, 0, 1, 1], "xmax > xmin"), ([0, 0, 1e-12, 1], "too small")])
def test_constructors_refuse_a_bad_view_naming_the_problem(index, view, words):
    build = list(_widgets_with(view))[index]
    with pytest.raises(ValueError, match=words):
        build()
