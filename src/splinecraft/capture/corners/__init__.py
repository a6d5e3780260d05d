"""Corner detectors for digital outlines (thesis chapter 2 and section 4.1.2; §6).

Every detector takes an ``(n, 2)`` polyline -- normally a :class:`~splinecraft.capture.contour.Boundary`
``outline`` (crack midpoints, spacing 1 px on straight runs and 0.71 px where the outline turns) or its
``pixels`` chain -- and returns the **sorted indices** of the points it marks as corners.

=================  ==================================================================================
``"srm05"``        the thesis's three-phase slope detector (ZCT, DT, TA), :func:`srm05`
``"rj73"``         Rosenfeld & Johnston 1973, k-cosine with per-point scale, :func:`rj73`
``"rw75"``         Rosenfeld & Weszka 1975, averaged k-cosine, :func:`rw75`
``"fd77"``         Freeman & Davis 1977, chain cornerity with straight arms, :func:`fd77`
``"bt87"``         Beus & Tiu 1987, FD77 averaged over scales with bounded arms, :func:`bt87`
``"ipan99"``       Chetverikov & Szabo 1999, inscribed triangles, :func:`ipan99`
``"tc89"``         Teh & Chin 1989, region of support + k-cosine, :func:`tc89`
``"tangent-jump"`` this project's detector for outline capture, :func:`tangent_jump` (recommended)
=================  ==================================================================================

Conventions shared by all detectors
-----------------------------------
* ``closed=True`` treats the points as a closed outline (first point not repeated; a repeated closing
  point is ignored). For an open polyline the two end points are never reported (they are piece
  boundaries anyway) and points whose window runs off an end cannot be corners.
* Consecutive duplicate points are merged before detection; returned indices refer to the input and,
  inside a run of duplicates, to its first point.
* Input validation: ``points`` must be a real ``(n, 2)`` array (``TypeError`` / ``ValueError``
  otherwise); a NaN or infinite coordinate, or one beyond ``MAX_COORDINATE`` = 1e15 px (pixel units:
  squared window lengths would overflow), raises ``ValueError`` naming its index. A parameter outside
  its domain raises ``ValueError`` naming the parameter; :func:`check_params` runs the same check on a
  parameter dict before any outline is seen (so :func:`~splinecraft.capture.trace.trace` refuses a bad
  ``corner_params`` value before it loads the image). An outline with too few points for the
  detector's window (for example the 4-point outline of a single-pixel speck) has **no corners**: the
  detectors return an empty array rather than raise, so that tracing can run every detector on every
  boundary of an image.
* Vectorized with numpy over all points (windows are gathered as ``(n, k)`` arrays); the only Python
  loops run over scales, over candidate corners (a handful per outline), over SRM05's slope runs and
  over the removal steps of SRM05's phase 3.

Measured accuracy and speed on rasterized shapes are in ``BENCHMARKS.md`` ("Corner detectors"), made by
``benchmarks/bench_corners.py``.
"""
from __future__ import annotations

import inspect

from ... import _validation
from ._classic import (bt87, check_bt87_params, check_fd77_params, check_ipan99_params, check_k_cosine_params,
                       check_tc89_params, fd77, ipan99, rj73, rw75, tc89)
from ._jump import check_tangent_jump_params, detection_scale, tangent_jump
from ._thesis import check_srm05_params, srm05

__all__ = [
    "corners",
    "check_params",
    "CORNER_METHODS",
    "CAPTURE_DEFAULT",
    "srm05",
    "rj73",
    "rw75",
    "fd77",
    "bt87",
    "ipan99",
    "tc89",
    "tangent_jump",
    "detection_scale",
]

#: The detector recommended for outline capture (see ``BENCHMARKS.md``, "Corner detectors").
CAPTURE_DEFAULT = "tangent-jump"


# ----------------------------------------------------------------------------------------------------------
# registry and dispatcher
# ----------------------------------------------------------------------------------------------------------
#: Detector name -> function. Every function takes ``(points, *, closed=True, **its own parameters)``.
CORNER_METHODS = {
    "srm05": srm05,
    "rj73": rj73,
    "rw75": rw75,
    "fd77": fd77,
    "bt87": bt87,
    "ipan99": ipan99,
    "tc89": tc89,
    "tangent-jump": tangent_jump,
}

#: Detector function -> the check of its parameters (keyword arguments: every parameter but ``closed``, and
#: ``label``), the one the detector itself runs; it returns the checked values and raises ``TypeError`` /
#: ``ValueError`` naming the parameter, the value and the accepted range.
_PARAM_CHECKS = {
    srm05: check_srm05_params,
    rj73: check_k_cosine_params,
    rw75: check_k_cosine_params,
    fd77: check_fd77_params,
    bt87: check_bt87_params,
    ipan99: check_ipan99_params,
    tc89: check_tc89_params,
    tangent_jump: check_tangent_jump_params,
}


def corners(points, method="srm05", *, closed=True, **params):
    """Corner indices of an outline by the detector ``method`` (a key of :data:`CORNER_METHODS`).

    ``"srm05"`` (the default) is the thesis's detector (chapter 2); for outline capture the project
    recommends ``"tangent-jump"`` (:data:`CAPTURE_DEFAULT`), see ``BENCHMARKS.md``.

    Parameters
    ----------
    points : array_like (n, 2)
        Closed outline (first point not repeated) or open polyline, roughly unit spaced, pixel units.
    method : str
        Detector name.
    closed : bool
        Closed outline (default) or open polyline (its end points are never reported).
    **params
        The detector's own parameters (see its docstring); an unknown name raises ``TypeError`` listing
        the accepted ones, a value outside its domain ``ValueError`` naming it (the detector's check).

    Returns
    -------
    numpy.ndarray of intp
        Sorted, unique indices into ``points``.
    """
    if not isinstance(method, str):
        raise TypeError(f"method must be a string, one of {sorted(CORNER_METHODS)}; got {type(method).__name__}")
    if method not in CORNER_METHODS:
        raise ValueError(f"unknown corner method {method!r}; choose one of {sorted(CORNER_METHODS)}")
    detector = CORNER_METHODS[method]
    _check_keys(method, params, "params")  # the values: the detector checks them itself, by the same rule
    return detector(points, closed=closed, **params)


#: detector function -> its keyword-only parameters but ``closed`` and their defaults (``inspect.signature``
#: once per detector, not once per outline)
_DEFAULTS = {}


def _defaults(detector):
    defaults = _DEFAULTS.get(detector)
    if defaults is None:
        defaults = _DEFAULTS[detector] = {
            key: parameter.default for key, parameter in inspect.signature(detector).parameters.items()
            if parameter.kind is inspect.Parameter.KEYWORD_ONLY and key != "closed"}
    return defaults


def _check_keys(method, params, name):
    accepted = sorted(_defaults(CORNER_METHODS[method]))
    params = _validation.check_options(params, name, reserved=("closed", "method"),
                                       reserved_reason="the outline's closedness and the detector are chosen "
                                       "by the caller")
    for key in params:
        if key not in accepted:
            raise TypeError(f"{name} has an unexpected keyword {key!r} for the {method!r} detector; its "
                            f"parameters are {accepted}")
    return params


def check_params(method, params, name="params"):
    """The keyword parameters of detector ``method`` (a known name), checked before any outline is seen: a dict
    with string keys naming its own parameters (``closed`` and ``method`` are set by the caller), each value in
    its domain. ``TypeError`` names a bad key and lists the accepted ones; a value of the wrong type or outside
    its domain raises ``TypeError`` / ``ValueError`` naming it as ``name[key]``, the value and the accepted
    range, e.g. ``corner_params['min_turn'] must be >= 0 and < 180, got -5.0``. The values are checked by the
    detector's own check (``_PARAM_CHECKS``; the detector runs the same one), together with the defaults of
    the parameters not given (``s_max >= s_min`` of ``"bt87"`` involves both). Returns ``params`` as given (a
    new dict)."""
    params = _check_keys(method, params, name)
    detector = CORNER_METHODS[method]
    try:
        _PARAM_CHECKS[detector](**{**_defaults(detector), **params}, label=lambda key: f"{name}[{key!r}]")
    except (TypeError, ValueError) as exc:
        kind = ValueError if isinstance(exc, ValueError) else TypeError
        raise kind(f"{exc} (the {method!r} corner detector)") from None
    return params
