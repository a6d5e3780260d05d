"""What the pixels can decide (issue 9): twins of the truth that render to the same bitmap.

    .venv/bin/python benchmarks/bench_pixel_evidence.py corners [--families oldstyle,arabic,...]
    .venv/bin/python benchmarks/bench_pixel_evidence.py misses [--yardstick ../shared/yardstick]
    .venv/bin/python benchmarks/bench_pixel_evidence.py small [--seeds 11,...,20] [--list]

A *twin* of a shape is another outline whose render (pixel centres inside, even-odd: the renderer of
``heldout_shapes.rasterize``, which drew the held-out bitmaps) is the same bitmap, bit for bit. A tracer sees only
the bitmap, so wherever a twin and the truth differ, any tracer is wrong about one of the two.

* ``corners``: per false corner of ``sc.trace`` (a traced corner farther than 3 px from every true corner) on
  the upright 300-px held-out glyphs of ``--families``: is there a *sharp twin*, the truth with a short arc
  around the false corner replaced by the crossing of its end tangents, that turns by more than 30 degrees
  there (a true corner by the yardstick's definition) within 3 px of the traced corner and renders to the
  same bitmap? The arc is searched over half-widths ``ARC_HALF_WIDTHS`` (px of arc) and centres within 3 px
  of the truth point nearest the traced corner; the sharpest twin found counts. Per true corner, found or
  missed, the *rounded twin* (:func:`rounded_twin`): how far along each side the corner can be rounded off
  (no join of the twin turns by more than 30 degrees there) without changing a pixel. Per missed true corner
  the distance to the nearest other true corner (the scorer matches one to one within 3 px, so of two corners
  closer than that a detector that sees one corner matches one).
* ``misses``: per clean render (held-out, ``shapes2/``, ``shapes/``; no scan-like ones) that ``sc.trace`` misses
  by more than 1 px: where, and how deep the pixel centres near the miss lie on the wrong side of the traced
  outline (the traced outline rendered like the truth and compared with the bitmap; depth = distance of a
  misclassified pixel centre from the traced outline). A trace whose render agrees with the bitmap near a miss
  (no misclassified centre there, or only ones within a few hundredths of a pixel of the curve) is itself close
  to a twin of the truth there: the pixels do not tell it from the truth. (The yardstick's bitmaps come from its
  own renderer; on most of them the pixel-centre rule gives the same bitmap from the truth, on a few not quite,
  e.g. 72 pixels of ``shapes2/dvsc_M``.)
* ``small``: per glyph of ``bench_other_fonts.py`` (``--seeds``) at 48-120 px that ``sc.trace`` misses by more
  than 1 px, each miss (as in ``misses``) classed by where it sits: at a true corner the trace stops short of (a
  tip cut short), at one it overshoots, at a short side (two true corners closer than :data:`SHORT_SIDE`: the face
  of a serif or a stroke end), or away from every true corner (a fillet or a tight curve taken for a corner, or a
  curve). Per miss: whether the traced outline contradicts a pixel centre within 3 px by more than
  :data:`CONTRADICTED` px (else it is, to that depth, a twin of the truth there: no tracer can tell the two
  apart), and how far from the truth the farthest twin of two families reaches there: the rounded twin at the
  true corner of a cut tip (:func:`rounded_twin`), the sharp twin at the miss otherwise (:func:`sharp_twin`).
  A twin that reaches as far from the truth as the trace makes the miss undecidable by construction.

Benchmark only (needs the held-out fonts, and ``--yardstick`` for the yardstick sets); nothing here is tuned
on, and the project's tests do not use it.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))
sys.path.insert(0, str(REPO / "benchmarks"))

import heldout_shapes  # noqa: E402
import synthetic_shapes  # noqa: E402
import splinecraft as sc  # noqa: E402
from bench_corners import MATCH_PX, match  # noqa: E402

#: Half-widths (px of arc) of the truth arc a sharp twin replaces.
ARC_HALF_WIDTHS = (0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0)
#: Centres of that arc, px of arc from the truth point nearest the traced corner.
ARC_SHIFTS = np.arange(-3.0, 3.01, 0.25)
#: The yardstick's corner threshold (degrees).
CORNER_DEG = 30.0


def render(contours, height, width):
    """The bitmap of closed polylines: ``heldout_shapes.rasterize``'s pixel-centre rule."""
    return heldout_shapes.rasterize({"contours": contours, "height": height, "width": width})


def _around(contours, point):
    """The contour nearest ``point`` (its index and points), the index ``k`` of its point nearest ``point``, and
    the cumulative arc lengths from ``k`` forward and backward along it (closed)."""
    nearest = [np.hypot(*(np.asarray(c, float) - point).T) for c in contours]
    which = int(np.argmin([d.min() for d in nearest]))
    line = np.asarray(contours[which], float)
    k = int(np.argmin(nearest[which]))
    edge = np.roll(np.hypot(*(np.roll(line, -1, axis=0) - line).T), -k)
    return which, line, k, np.cumsum(edge), np.cumsum(edge[::-1])


def _arc_index(arc_forward, arc_backward, at, n, k):
    """Index of the contour point ``at`` px of arc from point ``k`` (forward when positive)."""
    if at >= 0:
        return (k + int(np.searchsorted(arc_forward, at)) + 1) % n
    return (k - int(np.searchsorted(arc_backward, -at)) - 1) % n


def sharp_twin(contours, bitmap, point):
    """The sharpest twin of the closed polylines ``contours`` with a corner near ``point``: the arc of the
    nearest contour around it replaced by the crossing of the arc's end tangents (module docstring). Returns
    ``(half_width, turn_deg, corner_xy)`` or None when no such twin renders to ``bitmap``."""
    which, line, k, forward, backward = _around(contours, point)
    n = len(line)
    height, width = bitmap.shape
    best = None
    for half in ARC_HALF_WIDTHS:
        for shift in ARC_SHIFTS:
            i0 = _arc_index(forward, backward, shift - half, n, k)
            i1 = _arc_index(forward, backward, shift + half, n, k)
            t0, t1 = line[i0] - line[(i0 - 1) % n], line[(i1 + 1) % n] - line[i1]
            t0, t1 = t0 / np.hypot(*t0), t1 / np.hypot(*t1)
            cross = t0[0] * t1[1] - t0[1] * t1[0]
            turn = float(np.degrees(np.arccos(np.clip(t0 @ t1, -1.0, 1.0))))
            if turn <= CORNER_DEG or abs(cross) < 1e-9 or (best is not None and turn <= best[1]):
                continue
            chord = line[i1] - line[i0]
            reach = (chord[0] * t1[1] - chord[1] * t1[0]) / cross
            corner = line[i0] + reach * t0
            if reach < 0 or reach > 3 * half + 2 or np.hypot(*(corner - point)) > MATCH_PX:
                continue
            keep = np.arange(i1, i0 + 1 + (n if i0 < i1 else 0)) % n      # i1 forward to i0
            twin = list(contours)
            twin[which] = np.vstack([line[keep], corner[None]])
            if np.array_equal(render(twin, height, width), bitmap):
                best = (half, turn, corner)
    return best


#: Cut-backs (px along each side) of the rounded twins tried, smallest first.
CUT_BACKS = (0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0)


def rounded_twin(contours, bitmap, corner):
    """The largest cut-back ``t`` (px, from :data:`CUT_BACKS`) for which the truth with its corner at ``corner``
    rounded off -- the arc from ``t`` px before to ``t`` px after it replaced by the quadratic Bezier whose
    control point is the corner (tangent to both sides where they are straight; its joins turn by a tenth of
    the corner's turn, so it has no corner) -- renders to ``bitmap``; 0.0 when none does."""
    which, line, k, forward, backward = _around(contours, corner)
    n = len(line)
    height, width = bitmap.shape
    s = np.linspace(0.0, 1.0, 11)[1:-1, None]
    largest = 0.0
    for cut in CUT_BACKS:
        if cut >= 0.45 * min(forward[-1], backward[-1]):
            break
        i0, i1 = _arc_index(forward, backward, -cut, n, k), _arc_index(forward, backward, cut, n, k)
        start, end = line[i0], line[i1]
        fillet = (1 - s) ** 2 * start + 2 * s * (1 - s) * line[k] + s**2 * end
        keep = np.arange(i1, i0 + 1 + (n if i0 < i1 else 0)) % n
        twin = list(contours)
        twin[which] = np.vstack([line[keep], fillet])
        if not np.array_equal(render(twin, height, width), bitmap):
            break
        largest = cut
    return largest


def smallest_radius(contours, point, reach=6.0):
    """The truth's smallest radius of curvature (px) within ``reach`` px of arc of its point nearest ``point``
    (turn of consecutive edges of the dense polyline over their mean length)."""
    _, line, k, forward, backward = _around(contours, point)
    n = len(line)
    edge_vec = np.roll(line, -1, axis=0) - line
    edge = np.hypot(*edge_vec.T)
    lo = k - int(np.searchsorted(backward, reach)) - 1
    hi = k + int(np.searchsorted(forward, reach)) + 1
    at = np.arange(lo, hi + 1) % n
    angle = np.arctan2(edge_vec[at, 1], edge_vec[at, 0])
    turn = np.abs(np.angle(np.exp(1j * np.diff(angle))))
    length = 0.5 * (edge[at[:-1]] + edge[at[1:]])
    curvature = turn / np.maximum(length, 1e-12)
    return float(1.0 / curvature.max()) if curvature.max() > 0 else np.inf


def report_corners(families):
    """Per family (upright 300-px held-out glyphs): false corners and their sharp twins, missed corners and
    their nearest true neighbour."""
    pooled = {}
    for shape in heldout_shapes.heldout_set():
        upright = shape["family"] in families and shape["group"] == shape["family"]
        if not upright and shape["group"] not in families:
            continue
        label = shape["family"] if upright else shape["group"]
        contours = [np.asarray(c, float) for c in shape["contours"]]
        bitmap = render(contours, shape["height"], shape["width"])
        traced = sc.trace(bitmap)
        found = np.asarray([c for b in synthetic_shapes.svg_beziers(traced.to_svg())
                            for c in synthetic_shapes.bezier_corners(b)], float).reshape(-1, 2)
        truth = np.asarray(shape["corners"], float).reshape(-1, 2)
        tp, fp, fn, hit = match(found, truth)
        cell = pooled.setdefault(label, {"tp": 0, "fp": 0, "fn": 0, "twin30": 0, "twin60": 0, "fn_pair": 0,
                                         "turns": [], "cut_tp": [], "cut_fn": [], "radii": []})
        cell["tp"], cell["fp"], cell["fn"] = cell["tp"] + tp, cell["fp"] + fp, cell["fn"] + fn
        print(f"\n{shape['name']}: {len(truth)} true corners, {len(found)} traced, {tp} matched")
        for point in found:
            if len(truth) and np.hypot(*(truth - point).T).min() <= MATCH_PX:
                continue
            twin = sharp_twin(contours, bitmap, point)
            radius = smallest_radius(contours, point)
            cell["radii"].append(radius)
            if twin is None:
                print(f"    false ({point[0]:7.1f}, {point[1]:7.1f}): truth's radius {radius:.2f} px, no sharp twin")
                continue
            half, turn, corner = twin
            cell["twin30"] += 1
            cell["twin60"] += turn > 60.0
            cell["turns"].append(turn)
            print(f"    false ({point[0]:7.1f}, {point[1]:7.1f}): truth's radius {radius:.2f} px, sharp twin turning {turn:5.1f} deg at "
                  f"{np.hypot(*(corner - point)):.2f} px (arc +-{half} px replaced)")
        for j in range(len(truth)):
            cut = rounded_twin(contours, bitmap, truth[j])
            cell["cut_tp" if hit[j] else "cut_fn"].append(cut)
            if hit[j]:
                continue
            others = np.delete(truth, j, axis=0)
            gap = np.hypot(*(others - truth[j]).T).min() if len(others) else np.inf
            cell["fn_pair"] += gap < MATCH_PX
            print(f"    missed ({truth[j][0]:7.1f}, {truth[j][1]:7.1f}): nearest other true corner {gap:.1f} px; "
                  f"rounded off over {cut} px each side, the same bitmap")
    print("\n| group | TP | FP | FN | corner F1 | FP with a sharp twin (> 30 deg / > 60 deg) | median twin turn |"
          " FN within 3 px of another true corner | rounded twin's cut-back, median TP / FN (px) |"
          " truth's radius at the FP, min-median-max (px) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for label, c in pooled.items():
        tp, fp, fn = c["tp"], c["fp"], c["fn"]
        f1 = 2 * tp / (2 * tp + fp + fn) if tp + fp + fn else 1.0
        turn = f"{np.median(c['turns']):.0f} deg" if c["turns"] else "-"
        cuts = " / ".join(f"{np.median(c[key]):.2f}" if c[key] else "-" for key in ("cut_tp", "cut_fn"))
        print(f"| {label} | {tp} | {fp} | {fn} | {f1:.3f} | {c['twin30']} / {c['twin60']} of {fp} | {turn} | "
              f"{c['fn_pair']} of {fn} | {cuts} | {_spread(c['radii'])} |")
    return pooled


def _spread(values):
    """min - median - max of the finite ``values``, and how many are straight (infinite radius)."""
    values = np.asarray(values, float)
    finite = values[np.isfinite(values)]
    text = " - ".join(f"{v:.2f}" for v in np.quantile(finite, [0.0, 0.5, 1.0])) if finite.size else "-"
    straight = int((~np.isfinite(values)).sum())
    return text + (f" ({straight} straight)" if straight else "")


def _misses_of(dense_truth, dense_traced, limit=1.0, gap=5):
    """Clusters of points beyond ``limit`` px, both ways: (direction, distance, xy) of each cluster's worst."""
    out = []
    truth_points, traced_points = np.concatenate(dense_truth), np.concatenate(dense_traced)
    to_trace = np.min([synthetic_shapes._dist_to_polyline(truth_points, t) for t in dense_traced], axis=0)
    to_truth = np.min([synthetic_shapes._dist_to_polyline(traced_points, t) for t in dense_truth], axis=0)
    for direction, points, dist in (("truth beyond the trace", truth_points, to_trace),
                                    ("trace beyond the truth", traced_points, to_truth)):
        far = np.flatnonzero(dist > limit)
        for group in np.split(far, np.flatnonzero(np.diff(far) > gap) + 1) if far.size else []:
            worst = group[np.argmax(dist[group])]
            if not any(d == direction and np.hypot(*(at - points[worst])) < 1e-9 for d, _, at in out):
                out.append((direction, float(dist[worst]), points[worst]))   # a point repeated at a join: once
    return out


def report_misses(yardstick):
    """Clean renders beyond 1 px: per miss, the misclassified pixel centres of the traced outline's render
    within 3 px, and their depth."""
    import bench_peers

    shapes = [s for s in bench_peers.heldout() if s["group"] != "scan"]
    if yardstick and os.path.isdir(yardstick):
        for subset in ("shapes2", "shapes"):
            shapes += [s for s in bench_peers.yardstick_shapes(yardstick, subset) if s["group"] != "scan"]
    rows, depths_near, depths_far = [], [], []
    for entry in shapes:
        bitmap = entry["mask"]
        truth = [np.asarray(c["dense"], float) for c in entry["truth"]["contours"]]
        traced = [synthetic_shapes._dense_bezier(b) for b in synthetic_shapes.svg_beziers(sc.trace(bitmap).to_svg())]
        misses = _misses_of(truth, traced)
        wrong = np.argwhere(render(traced, *bitmap.shape) != bitmap)[:, ::-1] + 0.5   # (x, y) pixel centres
        if not len(wrong):
            continue
        depth = np.min([synthetic_shapes._dist_to_polyline(wrong, t) for t in traced], axis=0)
        near = np.zeros(len(wrong), bool)
        for _, _, at in misses:
            near |= np.hypot(*(wrong - at).T) <= MATCH_PX
        depths_near.append(depth[near])
        depths_far.append(depth[~near])
        for direction, dist, at in misses:
            close = np.hypot(*(wrong - at).T) <= MATCH_PX
            deepest = float(depth[close].max()) if close.any() else 0.0
            rows.append((entry["set"], entry["name"], direction, dist, at, int(close.sum()), deepest))
    print("| set | shape | miss | px | at | misclassified centres within 3 px | deepest (px) |")
    print("|---|---|---|---|---|---|---|")
    for set_, name, direction, dist, at, count, deepest in rows:
        print(f"| {set_} | {name} | {direction} | {dist:.2f} | ({at[0]:.1f}, {at[1]:.1f}) | {count} | {deepest:.2f} |")
    near, far = np.concatenate(depths_near), np.concatenate(depths_far)
    shallow = sum(deepest <= 0.1 for *_, deepest in rows)
    print(f"\n{len(rows)} misses on {len({r[1] for r in rows})} shapes; {shallow} have no misclassified pixel centre "
          f"within 3 px deeper than 0.1 px. Depth of misclassified centres elsewhere (all {len(shapes)} clean "
          f"renders, {len(far)} centres): median {np.median(far):.3f}, 99th percentile "
          f"{np.quantile(far, 0.99):.3f}, max {far.max():.3f} px; near misses ({len(near)}): median "
          f"{np.median(near):.3f}, max {near.max():.3f} px.")
    return rows


#: ``small`` mode: the glyph sizes (px); how near (px) a true corner makes a miss a corner's, for a tip cut short
#: (the truth beyond the trace) and for an overshoot (the trace beyond the truth: a tip that overshoots lies up to
#: a few px beyond its corner); two true corners closer than ``SHORT_SIDE`` px are the ends of one short side;
#: the depth (px) of a misclassified pixel centre from which the trace contradicts the pixels.
SMALL_SIZES = (48, 64, 120)
AT_CORNER = {"truth beyond the trace": 0.5, "trace beyond the truth": 2.0}
SHORT_SIDE = 3.5
CONTRADICTED = 0.1


def miss_class(direction, corner_distances):
    """Where a miss sits: ``direction`` (as :func:`_misses_of`) and the distances (px) from its farthest point to
    every true corner."""
    ordered = np.sort(corner_distances) if len(corner_distances) else np.array([np.inf])
    at_corner = ordered[0] <= AT_CORNER[direction]
    short_side = at_corner and len(ordered) > 1 and ordered[1] <= SHORT_SIDE
    if direction == "truth beyond the trace":
        return ("short side, rounded off" if short_side else "tip cut short" if at_corner else
                "truth beyond the trace, no true corner")
    return ("short side, a tip overshoots it" if short_side else "tip overshoots" if at_corner else
            "false corner on a fillet or a tight curve")


def twin_reach(truth, bitmap, direction, at, corners):
    """How far (px) from the truth the farthest twin found reaches at a miss (its farthest point ``at``): at the
    true corner of a cut tip (``corners``, the true corners, nearest to ``at``), the rounded twin's curve at its
    nearest to that corner; elsewhere the sharp twin's corner, from the truth."""
    if direction == "truth beyond the trace" and len(corners):
        corner = corners[np.argmin(np.hypot(*(corners - at).T))]
        if np.hypot(*(corner - at)) <= AT_CORNER[direction]:
            cut = rounded_twin(truth, bitmap, corner)
            if cut == 0.0:
                return 0.0
            _, line, k, forward, backward = _around(truth, corner)
            n = len(line)
            start, end = line[_arc_index(forward, backward, -cut, n, k)], line[_arc_index(forward, backward, cut, n, k)]
            s = np.linspace(0.0, 1.0, 41)[:, None]
            fillet = (1 - s) ** 2 * start + 2 * s * (1 - s) * line[k] + s ** 2 * end
            return float(np.hypot(*(fillet - line[k]).T).min())
    found = sharp_twin(truth, bitmap, at)
    if found is None:
        return 0.0
    return float(np.min([synthetic_shapes._dist_to_polyline(found[2][None], t)[0] for t in truth]))


def report_small(seeds, listing=False):
    """The misses of the 48-120 px glyphs of ``bench_other_fonts.py`` (``seeds``), classed (``small`` mode)."""
    import bench_other_fonts

    rows, glyph_count = [], 0
    for seed in seeds:
        for _, shape in bench_other_fonts.glyphs(seed):
            if shape["size"] not in SMALL_SIZES:
                continue
            glyph_count += 1
            bitmap = heldout_shapes.rasterize(shape)
            truth = [np.asarray(c, float) for c in shape["contours"]]
            corners = np.asarray(shape["corners"], float).reshape(-1, 2)
            traced = [synthetic_shapes._dense_bezier(b)
                      for b in synthetic_shapes.svg_beziers(sc.trace(bitmap).to_svg())]
            misses = _misses_of(truth, traced)
            if not misses:
                continue
            wrong = np.argwhere(render(traced, *bitmap.shape) != bitmap)[:, ::-1] + 0.5   # (x, y) pixel centres
            depth = np.min([synthetic_shapes._dist_to_polyline(wrong, t) for t in traced], axis=0) \
                if len(wrong) else np.zeros(0)
            for direction, dist, at in misses:
                close = np.hypot(*(wrong - at).T) <= MATCH_PX if len(wrong) else np.zeros(0, bool)
                rows.append({"seed": seed, "name": shape["name"], "size": shape["size"], "direction": direction,
                             "dist": dist, "class": miss_class(direction, np.hypot(*(corners - at).T)),
                             "deepest": float(depth[close].max()) if close.any() else 0.0,
                             "twin": twin_reach(truth, bitmap, direction, at, corners)})
    glyphs = {(r["seed"], r["name"]) for r in rows}
    decidable = {(r["seed"], r["name"]) for r in rows if r["deepest"] > CONTRADICTED}
    print(f"{glyph_count} glyphs of {'/'.join(map(str, SMALL_SIZES))} px (seeds {','.join(map(str, seeds))}); "
          f"{len(glyphs)} beyond 1 px with {len(rows)} misses; {len(decidable)} of them with a miss where the trace "
          f"contradicts a pixel centre by more than {CONTRADICTED} px.\n")
    print("| where the miss sits | misses | glyphs | " + " / ".join(map(str, SMALL_SIZES)) + " px | px, median (max) | "
          f"trace contradicts a centre by > {CONTRADICTED} px | a twin reaches as far (within 0.25 px) |")
    print("|---|---|---|---|---|---|---|")
    for name in sorted({r["class"] for r in rows}, key=lambda c: -sum(r["class"] == c for r in rows)):
        group = [r for r in rows if r["class"] == name]
        sizes = " / ".join(str(sum(r["size"] == size for r in group)) for size in SMALL_SIZES)
        dist = np.array([r["dist"] for r in group])
        twin = np.array([r["twin"] for r in group])
        print(f"| {name} | {len(group)} | {len({(r['seed'], r['name']) for r in group})} | {sizes} | "
              f"{np.median(dist):.2f} ({dist.max():.2f}) | {sum(r['deepest'] > CONTRADICTED for r in group)} | "
              f"{int((twin >= dist).sum())} ({int((twin >= dist - 0.25).sum())}) |")
    if listing:
        print("\n| seed | glyph | miss | px | class | deepest misclassified centre (px) | twin reach (px) |")
        print("|---|---|---|---|---|---|---|")
        for r in rows:
            print(f"| {r['seed']} | {r['name']} | {r['direction']} | {r['dist']:.2f} | {r['class']} | "
                  f"{r['deepest']:.2f} | {r['twin']:.2f} |")
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mode", choices=("corners", "misses", "small"))
    parser.add_argument("--families", default="oldstyle,arabic,italic,boldsans,freeserif,cjk,small,rotated")
    parser.add_argument("--yardstick", default=str(REPO.parent / "shared" / "yardstick"))
    parser.add_argument("--seeds", default="11,12,13,14,15,16,17,18,19,20", help="small: bench_other_fonts' seeds")
    parser.add_argument("--list", action="store_true", help="small: every miss's row")
    args = parser.parse_args(argv)
    if args.mode == "corners":
        report_corners(args.families.split(","))
    elif args.mode == "small":
        report_small([int(s) for s in args.seeds.split(",")], args.list)
    else:
        report_misses(args.yardstick)


if __name__ == "__main__":
    main()
