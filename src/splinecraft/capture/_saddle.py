"""The minority rule for diagonal pixel contacts ("saddles") of the crack follower (docs in
:mod:`splinecraft.capture.contour`, step 2)."""
from __future__ import annotations

import numpy as np

__all__ = ["CONNECTIVITIES", "check_connectivity"]

#: Values of the tracer's ``connectivity`` argument.
CONNECTIVITIES = ("minority", 4, 8)


def check_connectivity(connectivity):
    """4, 8 or "minority" (the tracer's connectivity argument); anything else names the argument."""
    if isinstance(connectivity, str):
        if connectivity == "minority":
            return connectivity
    elif not isinstance(connectivity, (bool, np.bool_)) and connectivity in CONNECTIVITIES[1:]:
        return int(connectivity)
    raise ValueError(f"connectivity must be 4, 8 or 'minority', got {connectivity!r}")


#: Half sides of the square rings the minority rule counts on (rings of side 4, 6 and 8 pixels).
_MINORITY_RADII = (2, 3, 4)


def _minority_joins_ink(sub, head_x, head_y):
    """At each saddle vertex (padded-frame pixel corner ``(head_x, head_y)``): True when ink is joined
    across it, i.e. ink is not the majority on the first ring that is not balanced (module docstring)."""
    reach = max(_MINORITY_RADII)
    wide = np.pad(sub, reach)                       # padded-frame vertex (X, Y) -> wide pixel rows Y-1+reach-1 ...
    offsets = np.arange(-reach, reach)
    rows = (head_y - 1 + reach - 1)[:, None] + offsets[None, :] + 1
    cols = (head_x - 1 + reach - 1)[:, None] + offsets[None, :] + 1
    window = wide[rows[:, :, None], cols[:, None, :]].astype(np.int16) * 2 - 1      # +1 ink, -1 paper
    decided = np.zeros(len(head_x), bool)
    join = np.ones(len(head_x), bool)
    distance = np.maximum(np.abs(offsets + 0.5)[:, None], np.abs(offsets + 0.5)[None, :]) + 0.5
    for radius in _MINORITY_RADII:
        ring = distance == radius
        balance = window[:, ring].sum(axis=1)
        now = ~decided & (balance != 0)
        join[now] = balance[now] < 0                 # ink is the minority: join it
        decided |= now
    return join
