"""Geometric outline metrics and the potrace runner shared by benchmarks/thesis_tables.py.

Everything is measured in the pixel frame of the bitmap (x right, y down, pixel corners on integer
coordinates), the frame of :mod:`splinecraft.capture` and of potrace's output once its SVG transform is
applied.

* :func:`densify` -- resample closed polylines so no edge exceeds a spacing;
* :func:`spline_points` / :func:`bezier_points` -- dense points on traced curves;
* :func:`deviation` -- symmetric Hausdorff distance (and RMS of the traced-to-reference distances)
  between two point clouds with a KD-tree; with both clouds spaced <= ``s`` the result is within
  ``s / 2`` of the exact curve-to-curve value;
* :func:`run_potrace` -- trace a bool mask with the ``potrace`` command line at its defaults and read
  back its cubic Béziers (segments and geometry).
"""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
import time
import xml.etree.ElementTree as ET

import numpy as np
from PIL import Image
from scipy.spatial import cKDTree

from splinecraft.capture.svg import parse_path_data

SPACING = 0.05  # px between points of every cloud compared (error of the metric <= SPACING / 2)


def densify(polyline, spacing=SPACING, closed=True):
    """Points along a polyline with consecutive points at most ``spacing`` apart (vectorised)."""
    polyline = np.asarray(polyline, float)
    ring = np.vstack([polyline, polyline[:1]]) if closed else polyline
    edges = np.diff(ring, axis=0)
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    pieces = np.maximum(1, np.ceil(lengths / spacing).astype(int))
    start = np.repeat(ring[:-1], pieces, axis=0)
    step = np.repeat(edges / pieces[:, None], pieces, axis=0)
    offset = np.arange(pieces.sum()) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    points = start + offset[:, None] * step
    return points if closed else np.vstack([points, ring[-1:]])


def bezier_points(bezier, spacing=SPACING):
    """Dense points on cubic Bézier pieces (m, 4, 2): uniform in theta, fine enough for ``spacing``."""
    bezier = np.asarray(bezier, float)
    if bezier.size == 0:
        return np.zeros((0, 2))
    polygon = np.linalg.norm(np.diff(bezier, axis=1), axis=2).sum(axis=1)  # >= arc length
    count = int(max(4, np.ceil(polygon.max() / spacing)))
    theta = np.linspace(0.0, 1.0, count + 1)[:, None]
    s = 1.0 - theta
    weights = np.hstack([s**3, 3 * s * s * theta, 3 * s * theta * theta, theta**3])  # (k, 4)
    return np.einsum("kj,mjd->mkd", weights, bezier).reshape(-1, 2)


def spline_points(splines, spacing=SPACING):
    """Dense points on a list of splinecraft Splines (their exact Bézier pieces)."""
    clouds = [bezier_points(s.bezier(), spacing) for s in splines]
    return np.vstack(clouds) if clouds else np.zeros((0, 2))


def outline_points(outlines, spacing=SPACING):
    """Dense points on closed polylines (reference outlines)."""
    return np.vstack([densify(o, spacing) for o in outlines])


def deviation(traced, reference):
    """Symmetric Hausdorff distance and RMS between two dense point clouds.

    Returns
    -------
    dict with ``hausdorff`` (max of both directions), ``traced_to_reference`` (max over traced points
    of the distance to the reference), ``reference_to_traced`` and ``rms`` (RMS of the traced-to-
    reference distances).
    """
    to_reference = cKDTree(reference).query(traced)[0]
    to_traced = cKDTree(traced).query(reference)[0]
    return {
        "hausdorff": float(max(to_reference.max(), to_traced.max())),
        "traced_to_reference": float(to_reference.max()),
        "reference_to_traced": float(to_traced.max()),
        "rms": float(np.sqrt(np.mean(to_reference**2))),
    }


def potrace_available():
    return shutil.which("potrace") is not None


def ensure_potrace(repo_root):
    """Install Debian's potrace with the project's script if it is missing; True when available."""
    if potrace_available():
        return True
    script = os.path.join(repo_root, "scripts", "system-deps.sh")
    try:
        subprocess.run(["bash", script, "potrace"], check=True, timeout=600)
    except (OSError, subprocess.SubprocessError) as error:
        print(f"# potrace could not be installed ({error}); skipping the potrace comparison")
        return False
    return potrace_available()


def _transform(text):
    """Parse potrace's ``translate(tx,ty) scale(sx,sy)`` group transform."""
    values = {}
    for part in text.replace(",", " ").split(")"):
        if "(" not in part:
            continue
        name, args = part.split("(")
        values[name.strip()] = [float(a) for a in args.split()]
    tx, ty = values.get("translate", [0.0, 0.0])
    sx, sy = values.get("scale", [1.0, 1.0])
    return np.array([sx, sy]), np.array([tx, ty])


def read_potrace_svg(text):
    """Cubic Bézier pieces of a potrace SVG, in the bitmap's pixel frame: list of (m, 4, 2) arrays.

    potrace writes relative path data in units of 0.1 px with y up inside a
    ``translate(0, H) scale(0.1, -0.1)`` group; line segments become exact cubics.
    """
    root = ET.fromstring(text)
    pieces = []
    for group in root.iter("{http://www.w3.org/2000/svg}g"):
        scale, offset = _transform(group.get("transform", ""))
        for path in group.iter("{http://www.w3.org/2000/svg}path"):
            for bezier, _closed in parse_path_data(path.get("d", "")):
                pieces.append(bezier * scale + offset)
    return pieces


def run_potrace(mask, repeats=5):
    """Trace ``mask`` (True = ink) with ``potrace -s`` at its defaults.

    Returns
    -------
    dict with ``pieces`` (list of (m, 4, 2) Bézier arrays, pixel frame), ``segments`` (curve and line
    segments, the number potrace writes), ``time_s`` (median wall time of the CLI over ``repeats``
    runs, process start and file I/O included) and ``version``.
    """
    with tempfile.TemporaryDirectory() as folder:
        source = os.path.join(folder, "in.pbm")
        target = os.path.join(folder, "out.svg")
        Image.fromarray(~np.asarray(mask, bool)).convert("1").save(source)  # PBM: black = ink
        times = []
        for _ in range(repeats):
            start = time.perf_counter()
            subprocess.run(["potrace", "-s", "-o", target, source], check=True, capture_output=True)
            times.append(time.perf_counter() - start)
        with open(target, encoding="utf-8") as handle:
            pieces = read_potrace_svg(handle.read())
    banner = subprocess.run(["potrace", "--version"], capture_output=True, text=True).stdout
    match = re.search(r"potrace\s+\d+(?:\.\d+)*", banner)
    return {"pieces": pieces, "segments": int(sum(len(p) for p in pieces)),
            "time_s": float(np.median(times)), "version": match.group(0) if match else banner.strip()[:40]}
