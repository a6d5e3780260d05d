"""Spline engine benchmark: rebuild + sample a curve after one point moves (issue 2).

For every size n, each repetition moves one random point by a few pixels, then rebuilds and samples:

* interpolant  -- ``splinecraft.interpolate`` (natural ends, chord knots), then ``sample`` with a fixed
  number of samples per segment, or adaptively to a flatness tolerance in pixels;
* basis form   -- ``splinecraft.basis_spline`` on the same points as control points (uniform knots);
* scipy        -- ``scipy.interpolate.CubicSpline`` (natural, the same chord knots, computed in the loop)
  evaluated at the same parameters as the fixed sampling. This is the same curve as the interpolant with
  v = 0, omega = 1, so the ratio compares like with like.

All variants run round-robin inside one repetition loop (same machine state), timed with
``time.perf_counter``; the table reports medians. Points are a smooth random walk with 8 px steps.

    python benchmarks/bench_engine.py                 # n = 10 .. 100000
    python benchmarks/bench_engine.py --sizes 1000 --repeats 500
"""
from __future__ import annotations

import argparse
import os
import platform
import sys
import time

import numpy as np
import scipy
from scipy.interpolate import CubicSpline

import splinecraft as sc


def make_points(n, rng, step=8.0):
    """A smooth random walk (pixel units): heading changes by N(0, 0.3) rad per step."""
    heading = np.cumsum(rng.normal(0.0, 0.3, n))
    return np.cumsum(step * np.stack([np.cos(heading), np.sin(heading)], axis=1), axis=0)


def default_repeats(n):
    if n <= 1000:
        return 300
    if n <= 10_000:
        return 100
    return 25


def run_size(n, repeats, per_segment, tolerance, rng):
    points = make_points(n, rng)
    theta = np.arange(per_segment) / per_segment

    def interp_build(p):
        return sc.interpolate(p)

    def interp_fixed(p):
        return sc.interpolate(p).sample(samples_per_segment=per_segment)

    def interp_adaptive(p):
        return sc.interpolate(p).sample(tolerance=tolerance)

    def basis_build(p):
        return sc.basis_spline(p)

    def basis_fixed(p):
        return sc.basis_spline(p).sample(samples_per_segment=per_segment)

    def basis_adaptive(p):
        return sc.basis_spline(p).sample(tolerance=tolerance)

    def chord_knots(p):
        legs = np.diff(p, axis=0)
        knots = np.empty(len(p))
        knots[0] = 0.0
        np.cumsum(np.sqrt(np.einsum("ij,ij->i", legs, legs)), out=knots[1:])
        return knots

    def scipy_build(p):
        return CubicSpline(chord_knots(p), p, bc_type="natural")

    def scipy_fixed(p):
        knots = chord_knots(p)
        spline = CubicSpline(knots, p, bc_type="natural")
        params = np.append((knots[:-1, None] + np.diff(knots)[:, None] * theta).ravel(), knots[-1])
        return spline(params)

    cases = {
        "interp_build": interp_build,
        "scipy_build": scipy_build,
        "interp_fixed": interp_fixed,
        "scipy_fixed": scipy_fixed,
        "interp_adaptive": interp_adaptive,
        "basis_build": basis_build,
        "basis_fixed": basis_fixed,
        "basis_adaptive": basis_adaptive,
    }
    # sanity: the interpolant and scipy agree (v = 0, omega = 1, natural, chord knots)
    check = np.abs(interp_fixed(points)[1] - scipy_fixed(points)).max()
    assert check < 1e-6 * np.abs(points).max(), check
    timings = {name: [] for name in cases}
    for name, case in cases.items():  # warm-up
        case(points)
    for _ in range(repeats):
        index = rng.integers(n)
        points[index] += rng.uniform(-3.0, 3.0, 2)  # one point moves
        for name, case in cases.items():
            start = time.perf_counter()
            case(points)
            timings[name].append(time.perf_counter() - start)
    medians = {name: float(np.median(values)) for name, values in timings.items()}
    adaptive_points = sc.interpolate(points).sample(tolerance=tolerance)[0].size
    basis_points = sc.basis_spline(points).sample(tolerance=tolerance)[0].size
    return medians, adaptive_points, basis_points


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 100, 1000, 10_000, 100_000])
    parser.add_argument("--repeats", type=int, default=None, help="repetitions per size (default: by size)")
    parser.add_argument("--samples-per-segment", type=int, default=16)
    parser.add_argument("--tolerance", type=float, default=0.25, help="adaptive flatness tolerance in px")
    parser.add_argument("--seed", type=int, default=2)
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)

    def ms(seconds):
        return f"{seconds * 1e3:.3f}" if seconds < 0.01 else f"{seconds * 1e3:.1f}"

    rows = []
    for n in args.sizes:
        repeats = args.repeats or default_repeats(n)
        medians, adaptive_points, basis_points = run_size(n, repeats, args.samples_per_segment, args.tolerance, rng)
        rows.append((n, repeats, medians, adaptive_points, basis_points))
        print(f"# n={n} done", file=sys.stderr)

    k = args.samples_per_segment
    print(f"Median wall time per update (one point moved, rebuild + sample), ms; {k} samples/segment fixed, "
          f"adaptive tolerance {args.tolerance} px. Ratio = splinecraft / scipy (< 1: faster).\n")
    print(f"| n | repeats | interpolate build | CubicSpline build | ratio | interpolate + {k}/seg | CubicSpline + {k}/seg "
          f"| ratio | interpolate + adaptive (points) | µs per point (adaptive) |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for n, repeats, t, adaptive_points, _ in rows:
        print(
            f"| {n} | {repeats} | {ms(t['interp_build'])} | {ms(t['scipy_build'])} | "
            f"{t['interp_build'] / t['scipy_build']:.2f} | {ms(t['interp_fixed'])} | {ms(t['scipy_fixed'])} | "
            f"{t['interp_fixed'] / t['scipy_fixed']:.2f} | {ms(t['interp_adaptive'])} ({adaptive_points}) | "
            f"{t['interp_adaptive'] / n * 1e6:.2f} |"
        )
    print()
    print(f"| n | basis_spline build | basis + {k}/seg | ratio to CubicSpline + {k}/seg | basis + adaptive (points) "
          f"| µs per point (adaptive) |")
    print("|---:|---:|---:|---:|---:|---:|")
    for n, repeats, t, _, basis_points in rows:
        print(
            f"| {n} | {ms(t['basis_build'])} | {ms(t['basis_fixed'])} | {t['basis_fixed'] / t['scipy_fixed']:.2f} | "
            f"{ms(t['basis_adaptive'])} ({basis_points}) | {t['basis_adaptive'] / n * 1e6:.2f} |"
        )
    load = os.getloadavg() if hasattr(os, "getloadavg") else ("?",)
    print(
        f"\nPython {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
        f"{os.cpu_count()} cores, load average at the end {load[0]:.1f}."
    )


if __name__ == "__main__":
    main()
