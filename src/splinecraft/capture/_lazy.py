"""A list whose missing items are made on first access, then kept: the per-boundary results of a trace
(:class:`~splinecraft.capture.contour.Boundaries`, :class:`~splinecraft.capture.fitting.results.BoundaryList`),
of which a bitmap of noise has 10^5 that nobody may read."""
from __future__ import annotations

import operator
from collections.abc import Sequence

__all__ = ["LazyList"]


class LazyList(Sequence):
    """``items[k]`` is item ``k``, or ``None`` where ``make(k)`` builds it on first access. Indexing, slicing,
    iteration, ``len``, assignment and comparison with a list behave as on a list (``make`` must be picklable for
    the list to pickle: a top-level function, a bound method or an instance with ``__call__``)."""

    def __init__(self, items, make):
        self._items = list(items)
        self._make = make

    def __len__(self) -> int:
        return len(self._items)

    def __getitem__(self, k):
        if isinstance(k, slice):
            return [self[i] for i in range(*k.indices(len(self._items)))]
        item = self._items[k]
        if item is None:
            k = operator.index(k) % len(self._items)
            item = self._items[k] = self._make(k)
        return item

    def __setitem__(self, k, value):
        self._items[k] = value

    def __iter__(self):
        for k, item in enumerate(self._items):
            yield self[k] if item is None else item

    def __eq__(self, other):
        return isinstance(other, (list, LazyList)) and len(other) == len(self) and all(
            a is b or a == b for a, b in zip(self, other))

    __hash__ = None

    def missing(self) -> list:
        """The indices of the items not made yet."""
        return [k for k, item in enumerate(self._items) if item is None]

    def made(self) -> int:
        """How many items exist (made up front or on access)."""
        return sum(item is not None for item in self._items)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({len(self)} items, {self.made()} made)"
