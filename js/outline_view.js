// OutlineEditor canvas (plain ES module): the SVG layers, the contours the kernel sent (per contour a
// revision, its Bézier pieces as float32 and the deviation of each piece) and how they become paths, knot
// markers, the handles of the selected corners, the selection's box and its handles. It holds no model state: every draw call gets what it draws.
import { s, floats, bezierPath, markersPath, segmentsPath } from "./common.js";

export const COLORS = { curve: "#1565c0", fill: "#90caf9", knot: "#0d47a1", corner: "#d32f2f", selected: "#ff6f00", box: "#6a1b9a",
  handle: "#2e7d32" };
/** Deviation colours: a piece whose deviation (px) is below the limit gets the colour. */
export const DEVIATION_BINS = [[0.5, "#2e7d32"], [1.0, "#9e9d24"], [2.0, "#ef6c00"], [Infinity, "#c62828"]];
const ROTATE_LIFT = 24; // px: the rotate handle sits this far above the box

/**
 * The contours as the kernel sent them, one entry per contour ({revision, bez, deviation, path, el}), so only
 * changed contours are decoded and redrawn. Knot i of contour k starts piece i (closed contours).
 */
export class ContourCache {
  constructor(group = null) {
    this.group = group;
    this.entries = [];
    this.flat = null;
  }

  /** `geometry.contours` of the kernel: [{revision, bezier, deviation}, ...]. */
  update(list) {
    list.forEach((entry, k) => {
      const old = this.entries[k];
      if (old && old.revision === entry.revision && !(entry.deviation && !old.deviation)) return;
      const el = old?.el ?? (this.group ? s("path", { fill: "none", stroke: COLORS.curve, "stroke-width": 1.6, "data-testid": `contour-${k}` }) : null);
      this.entries[k] = { revision: entry.revision, bez: floats(entry.bezier), deviation: entry.deviation ? floats(entry.deviation) : null, path: null, el };
      if (el && !el.parentNode) this.group.append(el);
    });
    while (this.entries.length > list.length) this.entries.pop().el?.remove();
    this.flat = null;
  }

  /** An answer to a move: contour `index` has new pieces (its deviation follows with the release). */
  replace(index, revision, buffer) {
    const entry = this.entries[index];
    if (!entry || !buffer) return;
    Object.assign(entry, { revision, bez: floats(buffer), deviation: null, path: null });
    this.flat = null;
  }

  get length() { return this.entries.length; }
  count(k) { return this.entries[k] ? this.entries[k].bez.length / 8 : 0; }
  has(k, i) { return k >= 0 && k < this.entries.length && i >= 0 && i < this.count(k); }
  knot(k, i) { const b = this.entries[k].bez; return [b[8 * i], b[8 * i + 1]]; }

  /** Every knot in one flat [x0, y0, x1, y1, ...] array, and the [contour, knot] of each. */
  knots() {
    if (!this.flat) {
      const xy = [], owners = [];
      this.entries.forEach((entry, k) => {
        for (let i = 0; i < entry.bez.length / 8; i++) { xy.push(entry.bez[8 * i], entry.bez[8 * i + 1]); owners.push([k, i]); }
      });
      this.flat = { xy: Float64Array.from(xy), owners };
    }
    return this.flat;
  }
}

/**
 * The two handles of each selected corner: {contour, knot, side, x, y, kx, ky}, (x, y) the Bézier control point
 * next to the knot (kx, ky): "out" is b1 of the piece leaving it, "in" b2 of the piece arriving (data units).
 */
export function cornerHandles(cache, corners, pairs) {
  const found = [];
  for (const [k, i] of pairs ?? []) {
    if (!corners?.[k]?.[i] || !cache.has(k, i)) continue;
    const b = cache.entries[k].bez, n = cache.count(k), j = (i - 1 + n) % n, kx = b[8 * i], ky = b[8 * i + 1];
    found.push({ contour: k, knot: i, side: "out", x: b[8 * i + 2], y: b[8 * i + 3], kx, ky });
    found.push({ contour: k, knot: i, side: "in", x: b[8 * j + 4], y: b[8 * j + 5], kx, ky });
  }
  return found;
}

/** Bounding box (data units) of the selected knots, or null when fewer than two distinct knots are selected. */
export function selectionBox(cache, pairs) {
  if (!pairs || pairs.length < 2) return null;
  let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
  for (const [k, i] of pairs) {
    if (!cache.has(k, i)) continue;
    const [x, y] = cache.knot(k, i);
    x0 = Math.min(x0, x); y0 = Math.min(y0, y); x1 = Math.max(x1, x); y1 = Math.max(y1, y);
  }
  if (!(x1 >= x0) || (x1 - x0) + (y1 - y0) === 0) return null;
  return { x0, y0, x1, y1 };
}

/** Screen positions of the box's handles: rotate, scale at the corners, shear on the top and right edges. */
export function handles(vp, box) {
  if (!box) return {};
  const [X0, Y0, X1, Y1] = [vp.sx(box.x0), vp.sy(box.y0), vp.sx(box.x1), vp.sy(box.y1)];
  const cx = (X0 + X1) / 2, cy = (Y0 + Y1) / 2;
  return {
    rotate: [cx, Y0 - ROTATE_LIFT], "scale-nw": [X0, Y0], "scale-ne": [X1, Y0], "scale-sw": [X0, Y1], "scale-se": [X1, Y1],
    "shear-top": [cx, Y0], "shear-right": [X1, cy],
  };
}

const setAll = (node, attrs) => { for (const [key, value] of Object.entries(attrs)) node.setAttribute(key, value); };

/** Each piece coloured by its deviation from the source contour (DEVIATION_BINS). */
function drawDeviation(L, vp, cache, show) {
  L.deviation.replaceChildren();
  if (!show) return;
  const bins = DEVIATION_BINS.map(() => []);
  for (const entry of cache.entries) {
    if (!entry.deviation) continue;
    for (let i = 0; i < entry.deviation.length; i++) {
      const bin = DEVIATION_BINS.findIndex(([limit]) => entry.deviation[i] < limit);
      bins[bin].push(bezierPath(vp, entry.bez.subarray(8 * i, 8 * i + 8), false));
    }
  }
  bins.forEach((parts, b) => L.deviation.append(s("path", { d: parts.join(""), fill: "none", stroke: DEVIATION_BINS[b][1], "stroke-width": 4, opacity: 0.8, "data-testid": `deviation-${b}` })));
}

/** The selection's box and its handles. */
function drawBox(L, vp, box) {
  if (!box) { L.box.setAttribute("visibility", "hidden"); L.handles.setAttribute("d", ""); return; }
  const X0 = vp.sx(box.x0), Y0 = vp.sy(box.y0);
  setAll(L.box, { x: X0, y: Y0, width: Math.max(vp.sx(box.x1) - X0, 1), height: Math.max(vp.sy(box.y1) - Y0, 1), visibility: "visible" });
  const parts = [];
  for (const [name, [x, y]] of Object.entries(handles(vp, box))) {
    if (name === "rotate") parts.push(`M${x - 5},${y}a5,5 0 1,0 10,0a5,5 0 1,0 -10,0M${x},${y + 5}L${x},${Y0}`);
    else if (name.startsWith("shear")) parts.push(`M${x},${y - 5}l5,5l-5,5l-5,-5Z`);
    else parts.push(`M${x - 4},${y - 4}h8v8h-8Z`);
  }
  L.handles.setAttribute("d", parts.join(""));
}

/** The bitmap (PNG bytes) under the outline, `frame` = [width, height] in data units. */
function drawImage(L, vp, { bytes, frame, show }) {
  const has = bytes && bytes.byteLength > 0 && show;
  L.image.setAttribute("visibility", has ? "visible" : "hidden");
  if (!has) return;
  if (!L.image.dataset.url) L.image.dataset.url = URL.createObjectURL(new Blob([bytes], { type: "image/png" }));
  L.image.setAttribute("href", L.image.dataset.url);
  setAll(L.image, { x: vp.sx(0), y: vp.sy(0), width: frame[0] * vp.k, height: frame[1] * vp.k });
}
/** Release the bitmap's object URL (a new image, or the widget is gone). */
function dropImage(L) {
  if (L.image.dataset.url) URL.revokeObjectURL(L.image.dataset.url);
  delete L.image.dataset.url;
}

/** The editor's SVG canvas with its layers (bottom to top) and the draw calls for them. */
export function createCanvas(width, height) {
  const svg = s("svg", { class: "sc-canvas", width, height, "data-testid": "canvas" });
  const L = {
    bg: s("rect", { x: 0, y: 0, width, height, fill: "#f4f6f8" }),
    image: s("image", { preserveAspectRatio: "none", style: "image-rendering: pixelated", opacity: 0.45, "data-testid": "bitmap" }),
    fill: s("path", { fill: COLORS.fill, "fill-rule": "evenodd", opacity: 0.35, stroke: "none", "data-testid": "fill" }),
    curves: s("g", { "data-testid": "curves" }),
    deviation: s("g", { "data-testid": "deviation" }),
    box: s("rect", { fill: "none", stroke: COLORS.box, "stroke-dasharray": "4 3", "data-testid": "selection-box" }),
    handles: s("path", { fill: "#fff", stroke: COLORS.box, "stroke-width": 1.3, "data-testid": "handles" }),
    cornerLines: s("path", { fill: "none", stroke: COLORS.handle, "stroke-width": 1.2, "data-testid": "corner-handle-lines" }),
    cornerEnds: s("path", { fill: COLORS.handle, stroke: "#fff", "stroke-width": 0.8, "data-testid": "corner-handles" }),
    knots: s("path", { fill: "#fff", stroke: COLORS.knot, "stroke-width": 1.3, "data-testid": "knots" }),
    corners: s("path", { fill: COLORS.corner, stroke: "#fff", "stroke-width": 0.8, "data-testid": "corners" }),
    selected: s("path", { fill: COLORS.selected, stroke: "#fff", "stroke-width": 0.8, "data-testid": "selected" }),
    rubber: s("rect", { fill: "rgba(106,27,154,0.08)", stroke: COLORS.box, "stroke-width": 1, visibility: "hidden", "data-testid": "rubber-band" }),
  };
  svg.append(...Object.values(L));
  const cache = new ContourCache(L.curves);
  let viewKey = "";

  function resize(w, h) { for (const node of [svg, L.bg]) setAll(node, { width: w, height: h }); }

  /** Contour paths (only changed ones, or all when the view moved or `force`), the fill and the deviation. */
  function drawCurves(vp, { fill, deviation, force = false }) {
    const key = `${vp.view.join(",")} ${vp.width}x${vp.height}`;
    for (const entry of cache.entries) {
      if (force || key !== viewKey || entry.path === null) {
        entry.path = bezierPath(vp, entry.bez, true);
        entry.el.setAttribute("d", entry.path);
      }
    }
    viewKey = key;
    L.fill.setAttribute("d", fill ? cache.entries.map((entry) => entry.path).join("") : "");
    drawDeviation(L, vp, cache, deviation);
  }

  /**
   * Knot markers (smooth, corner, selected), the handles of the selected corners (`handles`, see
   * cornerHandles) and the box. `live`: the gesture in progress ({kind: "drag" | "handle", contour, knot, side,
   * x, y}), its knot or handle drawn where the pointer is until the kernel answers.
   */
  function drawKnots(vp, { corners, chosen, live, box, handles: grips = [] }) {
    const smooth = [], sharp = [], picked = [];
    const { xy, owners } = cache.knots();
    const dragged = live && live.kind === "drag" ? live : null, held = live && live.kind === "handle" ? live : null;
    owners.forEach(([k, i], n) => {
      const [x, y] = dragged && dragged.contour === k && dragged.knot === i ? [dragged.x, dragged.y] : [xy[2 * n], xy[2 * n + 1]];
      (chosen.has(`${k}:${i}`) ? picked : (corners[k]?.[i] ? sharp : smooth)).push(x, y);
    });
    L.knots.setAttribute("d", markersPath(vp, smooth, 3.2, "circle"));
    L.corners.setAttribute("d", markersPath(vp, sharp, 3.4, "square"));
    L.selected.setAttribute("d", markersPath(vp, picked, 4, "circle"));
    const ends = [], lines = [];
    for (const grip of grips) {
      const same = held && held.contour === grip.contour && held.knot === grip.knot && held.side === grip.side;
      const [x, y] = same ? [held.x, held.y] : [grip.x, grip.y];
      ends.push(x, y);
      lines.push(grip.kx, grip.ky, x, y);
    }
    L.cornerLines.setAttribute("d", segmentsPath(vp, lines));
    L.cornerEnds.setAttribute("d", markersPath(vp, ends, 3.6, "diamond"));
    drawBox(L, vp, box);
  }

  /** The rubber band of a box selection: a screen rectangle {x, y, width, height}, or null to hide it. */
  function drawRubber(rect) {
    if (rect) setAll(L.rubber, { ...rect, visibility: "visible" });
    else L.rubber.setAttribute("visibility", "hidden");
  }

  return { svg, layers: L, cache, resize, drawCurves, drawKnots, drawRubber,
    drawImage: (vp, image) => drawImage(L, vp, image), dropImage: () => dropImage(L) };
}
