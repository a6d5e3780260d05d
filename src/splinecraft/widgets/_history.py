"""Undo and redo for the editors: a bounded stack of states, one step per gesture.

A gesture is a run of changes with the same ``key`` (a slider being moved, a point being dragged) that
follow each other within ``coalesce_seconds``: only the state before its first change is recorded, so
one undo step takes back the whole gesture. ``key=None`` always records a step (add, delete, a value
set from code).
"""
from __future__ import annotations

import time

__all__ = ["History"]


class History:
    """Undo/redo stacks of states (any objects; the caller passes copies it will not mutate)."""

    def __init__(self, limit: int = 200, coalesce_seconds: float = 1.0):
        self.limit = int(limit)
        self.coalesce_seconds = float(coalesce_seconds)
        self._undo: list = []
        self._redo: list = []
        self._last = (None, 0.0)

    def __len__(self) -> int:
        return len(self._undo)

    @property
    def can_undo(self) -> bool:
        return bool(self._undo)

    @property
    def can_redo(self) -> bool:
        return bool(self._redo)

    def push(self, previous, *, key=None) -> bool:
        """Record ``previous`` (the state before a change) unless it continues the current gesture ``key``.

        Returns True when a step was recorded. A new step clears the redo stack.
        """
        now = time.monotonic()
        last_key, last_time = self._last
        self._last = (key, now)
        if key is not None and key == last_key and now - last_time < self.coalesce_seconds and self._undo:
            return False
        self._undo.append(previous)
        del self._undo[:-self.limit]
        self._redo.clear()
        return True

    def touch(self, key) -> None:
        """Continue gesture ``key`` without recording (its first change was recorded already)."""
        self._last = (key, time.monotonic())

    def break_gesture(self) -> None:
        """The next change starts a new step even if it has the same key."""
        self._last = (None, 0.0)

    def undo(self, current):
        """The state to go back to (``current`` moves to the redo stack), or None."""
        if not self._undo:
            return None
        self._redo.append(current)
        self.break_gesture()
        return self._undo.pop()

    def redo(self, current):
        """The state to go forward to (``current`` moves to the undo stack), or None."""
        if not self._redo:
            return None
        self._undo.append(current)
        self.break_gesture()
        return self._redo.pop()

    def saved(self):
        """The stacks as they are, for :meth:`restore` (a step that turns out not to apply leaves them unchanged)."""
        return list(self._undo), list(self._redo), self._last

    def restore(self, saved) -> None:
        """Put back the stacks :meth:`saved` returned."""
        undo, redo, self._last = saved
        self._undo[:], self._redo[:] = undo, redo

    def discard_last(self) -> None:
        """Drop the most recent undo step (the change it was recorded for did not happen)."""
        if self._undo:
            self._undo.pop()
        self.break_gesture()
