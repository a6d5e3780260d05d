"""The tracer's connectivity argument (docs in :mod:`splinecraft.capture.contour`, step 2; the minority rule for
diagonal pixel contacts is compiled with the crack follower, :mod:`splinecraft.capture._cracks`)."""
from __future__ import annotations

import numbers

import numpy as np

__all__ = ["CONNECTIVITIES", "check_connectivity"]

#: Values of the tracer's ``connectivity`` argument.
CONNECTIVITIES = ("minority", 4, 8)


def check_connectivity(connectivity):
    """4, 8 or "minority" (the tracer's connectivity argument); anything else names the argument."""
    if isinstance(connectivity, str):
        if connectivity == "minority":
            return connectivity
    elif (isinstance(connectivity, numbers.Integral) and not isinstance(connectivity, (bool, np.bool_))
          and connectivity in CONNECTIVITIES[1:]):
        return int(connectivity)
    raise ValueError(f"connectivity must be 4, 8 or 'minority', got {connectivity!r}")
