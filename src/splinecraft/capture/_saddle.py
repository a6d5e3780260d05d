"""The tracer's connectivity argument (docs in :mod:`splinecraft.capture.contour`, step 2; the minority rule for
diagonal pixel contacts is compiled with the crack follower, :mod:`splinecraft.capture._cracks`)."""
from __future__ import annotations

import numbers

import numpy as np

from .. import _validation

__all__ = ["CONNECTIVITIES", "check_connectivity"]

#: Values of the tracer's ``connectivity`` argument.
CONNECTIVITIES = ("minority", 4, 8)


def check_connectivity(connectivity):
    """4, 8 or "minority" (the tracer's connectivity argument, returned as ``int`` or ``str``), by the rule of
    :mod:`splinecraft._validation`: an integer (Python or numpy) or a ``str`` that is not one of them is a
    ``ValueError``, a value of another type (``None``, a bool, a float such as ``8.0``, a sequence) a
    ``TypeError``; both name the argument. ``None`` is no default: the defaults differ between the layers."""
    if isinstance(connectivity, str):
        if connectivity == "minority":
            return connectivity
        raise ValueError(f"connectivity must be 4, 8 or 'minority', got {connectivity!r}")
    if isinstance(connectivity, numbers.Integral) and not isinstance(connectivity, (bool, np.bool_)):
        if int(connectivity) in CONNECTIVITIES[1:]:
            return int(connectivity)
        raise ValueError(f"connectivity must be 4, 8 or 'minority', got {int(connectivity)}")
    raise TypeError(f"connectivity must be 4, 8 or 'minority', got {_validation._describe(connectivity)} "
                    f"({type(connectivity).__name__})")
