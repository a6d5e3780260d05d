// SplineEditor canvas: the SVG layers and how the kernel's geometry buffers become paths (plain ES module).
//
// The kernel sends `geometry` (float32 byte buffers: Bézier pieces, knots, class polygon, tangent handles,
// curvature comb, highlight) and `points` (float64 bytes); this module decodes them and writes the path
// data. It holds no model state: every draw call gets what it draws.
import { s, floats, ints, bezierPath, polylinePath, segmentsPath, markersPath } from "./common.js";
import { createLivePainter } from "./live_canvas.js";

export const COLORS = {
  curve: "#1565c0",
  polygon: "#90a4ae",
  point: "#263238",
  selected: "#e53935",
  knots: "#0d47a1",
  classPolygon: "#ef6c00",
  tangents: "#2e7d32",
  comb: "#8e24aa",
  highlight: "#ffd54f",
  construction: "#00897b",
  tPoint: "#d81b60",
};

const GEOMETRY_BUFFERS = ["bezier", "knots", "vw", "class_polygon", "tangents", "comb_teeth", "comb_envelope",
  "highlight", "highlight_leg", "construction", "construction_points", "construction_class", "t_point"];

/** The kernel's points (float64 bytes x0, y0, x1, y1, ..., or a nested list) as a Float64Array. */
export function decodePoints(value) {
  if (Array.isArray(value)) return Float64Array.from(value.flat());
  return floats(value, "f8");
}

/** The `geometry` trait with every buffer decoded as a Float32Array. */
export function decodeGeometry(g) {
  const out = { ...(g ?? {}) };
  for (const key of GEOMETRY_BUFFERS) out[key] = floats(out[key]);
  return out;
}

/**
 * The `geometry` trait decoded, given the geometry decoded before (`previous`). During a drag the kernel
 * sends only the rows of the Bézier pieces and knots whose bytes changed (`bezier_rows`/`bezier_data`,
 * `knots_rows`/`knots_data`) against its revision `base`; they are written into copies of `previous`'s
 * buffers. Returns null when `previous` is not that revision (the page must ask for the whole geometry).
 */
export function updateGeometry(previous, g) {
  if (!g || g.base === undefined) return decodeGeometry(g);
  if (!previous || previous.revision !== g.base) return null;
  const out = decodeGeometry(g);
  for (const [key, width] of [["bezier", 8], ["knots", 2]]) {
    const rows = ints(g[`${key}_rows`]), data = floats(g[`${key}_data`]), copy = previous[key].slice();
    for (let r = 0; r < rows.length; r++) copy.set(data.subarray(width * r, width * (r + 1)), width * rows[r]);
    out[key] = copy;
  }
  return out;
}

/** The far end of each tangent handle (flat [ax, ay, bx, by, ...] -> [bx, by, ...]). */
export function tangentTips(seg) {
  const n = Math.floor(seg.length / 4), out = new Float32Array(2 * n);
  for (let i = 0; i < n; i++) { out[2 * i] = seg[4 * i + 2]; out[2 * i + 1] = seg[4 * i + 3]; }
  return out;
}

/** Grid lines every 1, 2 or 5 x 10^k data units, about 12 across the larger side of the view. */
export function gridStep(span) {
  const raw = span / 12;
  const magnitude = 10 ** Math.floor(Math.log10(raw));
  return [1, 2, 5, 10].map((m) => m * magnitude).find((m) => m >= raw) ?? 10 * magnitude;
}

/** Most grid lines per direction (about 12 to 30 are drawn; more means a broken step). */
export const MAX_GRID_LINES = 400;

/**
 * The grid's coordinates in [lo, hi], every `step`: none when they would be more than `max` (a step the
 * numbers cannot tell apart, x + step == x) or when lo, hi or step is not a finite number.
 */
export function gridLines(lo, hi, step, max = MAX_GRID_LINES) {
  const first = Math.ceil(lo / step), last = Math.floor(hi / step);
  if (!(step > 0) || !Number.isFinite(first) || !Number.isFinite(last) || last - first >= max) return [];
  const out = [];
  for (let i = 0; i <= last - first; i++) out.push((first + i) * step);
  return out;
}

/** The editor's SVG canvas with its layers (bottom to top) and the draw calls for them. */
export function createCanvas(width, height) {
  const svg = s("svg", { class: "sc-canvas", width, height, "data-testid": "canvas" });
  const layer = (attrs) => { const p = s("path", { fill: "none", ...attrs }); svg.append(p); return p; };
  const bg = s("rect", { x: 0, y: 0, width, height, fill: "#fcfcfd", class: "sc-bg" });
  svg.append(bg);
  const L = {
    grid: layer({ stroke: "#eef1f4", "stroke-width": 1, "data-testid": "grid" }),
    highlightCurve: layer({ stroke: COLORS.highlight, "stroke-width": 9, "stroke-linecap": "round", opacity: 0.75, "data-testid": "highlight" }),
    highlightLeg: layer({ stroke: COLORS.highlight, "stroke-width": 7, "stroke-linecap": "round", opacity: 0.75 }),
    polygon: layer({ stroke: COLORS.polygon, "stroke-width": 1.2, "stroke-dasharray": "5 4", "data-testid": "control-polygon" }),
    combTeeth: layer({ stroke: COLORS.comb, "stroke-width": 0.8, opacity: 0.45, "data-testid": "comb-teeth" }),
    combEnvelope: layer({ stroke: COLORS.comb, "stroke-width": 1.4, opacity: 0.9, "data-testid": "comb-envelope" }),
    classPolygon: layer({ stroke: COLORS.classPolygon, "stroke-width": 1.1, "stroke-dasharray": "3 3", opacity: 0.9, "data-testid": "class-polygon" }),
    tangents: layer({ stroke: COLORS.tangents, "stroke-width": 1.6, "data-testid": "tangents" }),
    tangentEnds: layer({ fill: COLORS.tangents, stroke: "none" }),
    curveHit: layer({ stroke: "transparent", "stroke-width": 14, "pointer-events": "stroke", class: "sc-curve-hit" }),
    curve: layer({ stroke: COLORS.curve, "stroke-width": 2.4, "stroke-linejoin": "round", "data-testid": "curve", "pointer-events": "none" }),
    vw: layer({ fill: COLORS.classPolygon, stroke: "#fff", "stroke-width": 0.8, "data-testid": "vw-points", "pointer-events": "none" }),
    knots: layer({ fill: COLORS.knots, stroke: "#fff", "stroke-width": 0.8, "data-testid": "knots", "pointer-events": "none" }),
    points: layer({ fill: "#ffffff", stroke: COLORS.point, "stroke-width": 1.6, "data-testid": "points", "pointer-events": "none" }),
    selected: layer({ fill: COLORS.selected, stroke: "#fff", "stroke-width": 1.5, "data-testid": "selected-point", "pointer-events": "none" }),
    constructionClass: layer({ stroke: COLORS.classPolygon, "stroke-width": 1.2, "stroke-dasharray": "4 3", "pointer-events": "none", "data-testid": "construction-class" }),
    construction: layer({ stroke: COLORS.construction, "stroke-width": 1.3, "pointer-events": "none", "data-testid": "construction" }),
    constructionPoints: layer({ fill: COLORS.construction, stroke: "#fff", "stroke-width": 0.8, "pointer-events": "none" }),
    tPoint: layer({ fill: COLORS.tPoint, stroke: "#fff", "stroke-width": 1.5, "pointer-events": "none", "data-testid": "t-point" }),
  };
  const labels = s("g", { class: "sc-labels", "pointer-events": "none" });
  svg.append(labels);
  const live = createLivePainter(svg, Object.values(L), labels); // paints the layers during a drag

  /** Write marker layer `layer`: a marker of `radius` at each point of `xy` (data units; null: none). */
  function setMarkers(layer, vp, xy, radius, shape = "circle") {
    const d = xy ? markersPath(vp, xy, radius, shape) : "";
    layer.setAttribute("d", d);
    const n = xy ? Math.floor(xy.length / 2) : 0, centers = new Float64Array(2 * n);
    for (let i = 0; i < n; i++) { centers[2 * i] = vp.sx(xy[2 * i]); centers[2 * i + 1] = vp.sy(xy[2 * i + 1]); }
    live.markers(layer, d, centers, radius, shape);
  }

  function resize(w, h) {
    for (const node of [svg, bg]) { node.setAttribute("width", w); node.setAttribute("height", h); }
    if (live.active) { live.end(); live.begin(); }
  }

  function drawGrid(vp, show = true) {
    if (!show) { L.grid.setAttribute("d", ""); return; }
    const [x0, y0, x1, y1] = vp.visible();
    const step = gridStep(Math.max(x1 - x0, y1 - y0));
    const parts = [];
    for (const x of gridLines(x0, x1, step)) parts.push(`M${vp.sx(x).toFixed(1)},0V${vp.height}`);
    for (const y of gridLines(y0, y1, step)) parts.push(`M0,${vp.sy(y).toFixed(1)}H${vp.width}`);
    L.grid.setAttribute("d", parts.join(""));
    live.invalidate();
  }

  /** Curve and overlays; `show` = {knots, vw, tangents, comb}. */
  function drawGeometry(vp, g, show) {
    const d = bezierPath(vp, g.bezier, !!g.closed);
    L.curve.setAttribute("d", d);
    L.curveHit.setAttribute("d", d);
    L.highlightCurve.setAttribute("d", bezierPath(vp, g.highlight, false));
    L.highlightLeg.setAttribute("d", polylinePath(vp, g.highlight_leg, false));
    setMarkers(L.knots, vp, show.knots ? g.knots : null, 3.2);
    L.classPolygon.setAttribute("d", show.vw ? polylinePath(vp, g.class_polygon, false) : "");
    setMarkers(L.vw, vp, show.vw ? g.vw : null, 3, "square");
    L.tangents.setAttribute("d", show.tangents ? segmentsPath(vp, g.tangents) : "");
    setMarkers(L.tangentEnds, vp, show.tangents ? tangentTips(g.tangents) : null, 2.2);
    L.combTeeth.setAttribute("d", show.comb ? segmentsPath(vp, g.comb_teeth) : "");
    L.combEnvelope.setAttribute("d", show.comb ? polylinePath(vp, g.comb_envelope, false) : "");
    const tOn = g.t_point.length === 2;
    L.constructionClass.setAttribute("d", tOn ? polylinePath(vp, g.construction_class, false) : "");
    L.construction.setAttribute("d", tOn ? polylinePath(vp, g.construction, false) : "");
    setMarkers(L.constructionPoints, vp, tOn ? g.construction_points : null, 2.6);
    setMarkers(L.tPoint, vp, tOn ? g.t_point : null, 5.5);
    const tLabel = tOn && g.t_info ? [{ x: g.t_point[0], y: g.t_point[1], kind: "t",
      text: `t = ${g.t_info.t.toFixed(3)} (piece ${g.t_info.piece}, θ = ${g.t_info.theta.toFixed(2)})` }] : [];
    labels.replaceChildren(...[...(g.labels ?? []), ...tLabel].filter((lab) => lab.kind !== "joint" || show.comb).map((lab) =>
      s("text", { x: vp.sx(lab.x) + (lab.dx ?? 8), y: vp.sy(lab.y) + (lab.dy ?? -8), class: `sc-label sc-label-${lab.kind ?? "point"}` },
        document.createTextNode(lab.text))));
    L.curve.dataset.revision = String(g.revision ?? 0);
    L.curve.dataset.seq = String(g.seq ?? -1);
    live.invalidate();
  }

  /** Points (flat xy), the control polygon and the selected point. */
  function drawPoints(vp, flat, { closed, polygon, selected }) {
    const n = flat.length / 2;
    L.polygon.setAttribute("d", polygon ? polylinePath(vp, flat, closed) : "");
    setMarkers(L.points, vp, flat, n > 400 ? 3 : 4.5);
    setMarkers(L.selected, vp, selected >= 0 && selected < n ? flat.subarray(2 * selected, 2 * selected + 2) : null, 6);
    live.invalidate();
  }

  return { svg, layers: L, live, resize, drawGrid, drawGeometry, drawPoints };
}
