// Shared drawing helpers for the splinecraft widgets (plain ES module, no bundler).
//
// The Python side links this file into each widget module (see splinecraft/widgets/_assets.py),
// because anywidget loads a widget's ES module from one string, where relative imports cannot resolve.
// Everything here is pure (DOM building, buffer decoding, coordinate maps, path strings), so it can
// also be imported directly by node for unit tests.

export const SVG_NS = "http://www.w3.org/2000/svg";

/** Create an HTML element with attributes, properties and children. */
export function h(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  setAttrs(node, attrs);
  for (const child of children.flat()) {
    if (child === null || child === undefined || child === false) continue;
    node.append(child instanceof Node ? child : document.createTextNode(String(child)));
  }
  return node;
}

/** Create an SVG element with attributes and children. */
export function s(tag, attrs = {}, ...children) {
  const node = document.createElementNS(SVG_NS, tag);
  setAttrs(node, attrs);
  for (const child of children.flat()) {
    if (child) node.append(child);
  }
  return node;
}

function setAttrs(node, attrs) {
  for (const [key, value] of Object.entries(attrs)) {
    if (value === null || value === undefined || value === false) continue;
    if (key === "class") node.setAttribute("class", value);
    else if (key === "style" && typeof value === "object") Object.assign(node.style, value);
    else if (key.startsWith("on") && typeof value === "function") node.addEventListener(key.slice(2), value);
    else if (key in node && !(node instanceof SVGElement) && key !== "list") node[key] = value;
    else node.setAttribute(key, value === true ? "" : String(value));
  }
}

/**
 * Decode a binary trait value (DataView / ArrayBuffer / typed array / null) as a typed array.
 * The kernel sends little-endian float32 ("f4") or float64 ("f8") arrays as raw bytes.
 */
export function floats(value, kind = "f4") {
  const Ctor = kind === "f8" ? Float64Array : Float32Array;
  if (!value) return new Ctor(0);
  if (value instanceof Ctor) return value;
  let buffer, offset, length;
  if (value instanceof ArrayBuffer) {
    buffer = value; offset = 0; length = value.byteLength;
  } else if (ArrayBuffer.isView(value)) {
    buffer = value.buffer; offset = value.byteOffset; length = value.byteLength;
  } else {
    return new Ctor(0);
  }
  const size = Ctor.BYTES_PER_ELEMENT;
  if (offset % size !== 0) {
    buffer = buffer.slice(offset, offset + length);
    offset = 0;
  }
  return new Ctor(buffer, offset, Math.floor(length / size));
}

/** Same as floats() for little-endian int32 arrays. */
export function ints(value) {
  if (!value) return new Int32Array(0);
  let buffer = value.buffer ?? value, offset = value.byteOffset ?? 0, length = value.byteLength;
  if (offset % 4 !== 0) {
    buffer = buffer.slice(offset, offset + length);
    offset = 0;
  }
  return new Int32Array(buffer, offset, Math.floor(length / 4));
}

/**
 * The kernel refuses a view whose width or height is below VIEW_PRECISION x max(1, |coordinate|) (widgets/_base.py
 * view_problem): the grid and the points could no longer be told apart (x + step == x). Zooming in stops
 * ZOOM_MARGIN times above that, zooming out at MAX_SPAN data units (beyond it the spans overflow to infinity).
 */
export const VIEW_PRECISION = 1e-9;
export const ZOOM_MARGIN = 10;
export const MAX_SPAN = 1e12;

/** The smallest width or height the kernel takes for a view with these coordinates. */
export function smallestSpan(...coordinates) {
  return VIEW_PRECISION * Math.max(1, ...coordinates.map(Math.abs));
}

/**
 * `view` as a rectangle the page can draw: [0, 0, 1, 1] unless it is four finite numbers; about its centre, an
 * empty or inverted side becomes max(1, smallestSpan()) wide, a narrower side smallestSpan(), and a side whose
 * span overflows MAX_SPAN.
 */
export function drawableView(view) {
  if (!(Array.isArray(view) && view.length === 4 && view.every(Number.isFinite))) return [0, 0, 1, 1];
  const least = smallestSpan(...view), out = view.slice();
  for (const [lo, hi] of [[0, 2], [1, 3]]) {
    const span = out[hi] - out[lo];
    if (span >= least && Number.isFinite(span)) continue;
    // empty or inverted: one unit (as many as the numbers need); too narrow: the least span; overflowing: MAX_SPAN
    const half = (span > 0 ? (Number.isFinite(span) ? least : MAX_SPAN) : Math.max(1, least)) / 2;
    const centre = out[lo] / 2 + out[hi] / 2;
    out[lo] = centre - half;
    out[hi] = centre + half;
  }
  return out;
}

/**
 * Uniform data -> screen map that keeps the aspect ratio (like SVG "xMidYMid meet").
 * view = [xmin, ymin, xmax, ymax] in data units; the data frame is y-down (the SVG/pixel frame).
 */
export class Viewport {
  constructor(width, height, view) {
    this.width = width;
    this.height = height;
    this.setView(view);
  }

  setView(view) {
    const [x0, y0, x1, y1] = drawableView(view);
    this.view = [x0, y0, x1, y1];
    this.k = Math.min(this.width / (x1 - x0), this.height / (y1 - y0));
    this.ox = (this.width - this.k * (x1 - x0)) / 2 - this.k * x0;
    this.oy = (this.height - this.k * (y1 - y0)) / 2 - this.k * y0;
  }

  sx(x) { return this.ox + this.k * x; }
  sy(y) { return this.oy + this.k * y; }
  dx(px) { return (px - this.ox) / this.k; }
  dy(py) { return (py - this.oy) / this.k; }
  /** Data length of `px` screen pixels. */
  len(px) { return px / this.k; }

  /** The visible data rectangle (it can be larger than `view` along one axis). */
  visible() {
    return [this.dx(0), this.dy(0), this.dx(this.width), this.dy(this.height)];
  }

  /**
   * Zoom by `factor` (>1 zooms in) keeping the data point under screen (px, py) fixed. The factor is limited:
   * the visible width and height stay at least ZOOM_MARGIN x smallestSpan() and at most MAX_SPAN (a view
   * already beyond a limit does not go further that way).
   */
  zoomed(factor, px, py) {
    const [x0, y0, x1, y1] = this.visible();
    const small = Math.min(x1 - x0, y1 - y0), large = Math.max(x1 - x0, y1 - y0);
    if (!(factor > 0)) factor = 1;
    if (factor > 1) factor = Math.min(factor, Math.max(1, small / (ZOOM_MARGIN * smallestSpan(x0, y0, x1, y1))));
    else if (factor < 1) factor = Math.max(factor, Math.min(1, large / MAX_SPAN));
    const cx = this.dx(px), cy = this.dy(py);
    return [cx + (x0 - cx) / factor, cy + (y0 - cy) / factor, cx + (x1 - cx) / factor, cy + (y1 - cy) / factor];
  }

  /** Pan by screen pixels. */
  panned(dpx, dpy) {
    const [x0, y0, x1, y1] = this.visible();
    const ddx = dpx / this.k, ddy = dpy / this.k;
    return [x0 - ddx, y0 - ddy, x1 - ddx, y1 - ddy];
  }
}

const fmt = (v) => (Math.round(v * 100) / 100).toString();

/** SVG path data for cubic Bézier pieces (flat array of m*8 numbers: b0 b1 b2 b3, x,y each). */
export function bezierPath(vp, bez, closed = false) {
  const m = Math.floor(bez.length / 8);
  if (m === 0) return "";
  const parts = new Array(m + 2);
  parts[0] = `M${fmt(vp.sx(bez[0]))},${fmt(vp.sy(bez[1]))}`;
  for (let i = 0; i < m; i++) {
    const o = 8 * i;
    parts[i + 1] =
      `C${fmt(vp.sx(bez[o + 2]))},${fmt(vp.sy(bez[o + 3]))} ` +
      `${fmt(vp.sx(bez[o + 4]))},${fmt(vp.sy(bez[o + 5]))} ` +
      `${fmt(vp.sx(bez[o + 6]))},${fmt(vp.sy(bez[o + 7]))}`;
  }
  parts[m + 1] = closed ? "Z" : "";
  return parts.join("");
}

/** SVG path data for a polyline given as a flat [x0,y0,x1,y1,...] array; NaN starts a new run. */
export function polylinePath(vp, xy, closed = false) {
  const n = Math.floor(xy.length / 2);
  const parts = [];
  let pen = false;
  for (let i = 0; i < n; i++) {
    const x = xy[2 * i], y = xy[2 * i + 1];
    if (!Number.isFinite(x) || !Number.isFinite(y)) { pen = false; continue; }
    parts.push(`${pen ? "L" : "M"}${fmt(vp.sx(x))},${fmt(vp.sy(y))}`);
    pen = true;
  }
  if (closed && parts.length > 2) parts.push("Z");
  return parts.join("");
}

/** SVG path data for independent line segments given as flat [ax,ay,bx,by, ...]. */
export function segmentsPath(vp, xy) {
  const n = Math.floor(xy.length / 4);
  const parts = new Array(n);
  for (let i = 0; i < n; i++) {
    const o = 4 * i;
    parts[i] = `M${fmt(vp.sx(xy[o]))},${fmt(vp.sy(xy[o + 1]))}L${fmt(vp.sx(xy[o + 2]))},${fmt(vp.sy(xy[o + 3]))}`;
  }
  return parts.join("");
}

/** Path data drawing a small marker (circle, square or diamond) at each point of a flat xy array. */
export function markersPath(vp, xy, radius = 3, shape = "circle") {
  const n = Math.floor(xy.length / 2);
  const r = radius, parts = new Array(n);
  for (let i = 0; i < n; i++) {
    const x = vp.sx(xy[2 * i]), y = vp.sy(xy[2 * i + 1]);
    if (!Number.isFinite(x) || !Number.isFinite(y)) { parts[i] = ""; continue; }
    if (shape === "square") {
      parts[i] = `M${fmt(x - r)},${fmt(y - r)}h${fmt(2 * r)}v${fmt(2 * r)}h${fmt(-2 * r)}Z`;
    } else if (shape === "diamond") {
      parts[i] = `M${fmt(x)},${fmt(y - r * 1.3)}l${fmt(r * 1.3)},${fmt(r * 1.3)}l${fmt(-r * 1.3)},${fmt(r * 1.3)}l${fmt(-r * 1.3)},${fmt(-r * 1.3)}Z`;
    } else if (shape === "cross") {
      parts[i] = `M${fmt(x - r)},${fmt(y - r)}L${fmt(x + r)},${fmt(y + r)}M${fmt(x - r)},${fmt(y + r)}L${fmt(x + r)},${fmt(y - r)}`;
    } else {
      parts[i] = `M${fmt(x - r)},${fmt(y)}a${r},${r} 0 1,0 ${fmt(2 * r)},0a${r},${r} 0 1,0 ${fmt(-2 * r)},0`;
    }
  }
  return parts.join("");
}

/** Format a number for a slider read-out. */
export function formatNumber(value, digits = 3) {
  if (value === null || value === undefined || Number.isNaN(value)) return "—";
  if (!Number.isFinite(value)) return value > 0 ? "∞" : "−∞";
  const a = Math.abs(value);
  if (a !== 0 && (a >= 1e5 || a < 1e-3)) return value.toExponential(2);
  return String(Number(value.toFixed(digits)));
}

/**
 * A labelled slider row: range input + number box. `onInput(value, final)` fires while dragging
 * (final = false) and on release / Enter (final = true). The number box accepts any typed value;
 * the kernel validates it and reverts bad ones.
 */
export function sliderRow({ label, title, min, max, step, value, onInput, testid, scale = "linear" }) {
  const toSlider = (v) => (scale === "log" ? Math.log10(Math.max(v, 1e-300)) : v);
  const fromSlider = (u) => (scale === "log" ? 10 ** u : u);
  const range = h("input", { type: "range", class: "sc-range", "data-testid": testid ? `${testid}-range` : null });
  const box = h("input", { type: "number", class: "sc-number", "data-testid": testid ? `${testid}-number` : null });
  const row = h("div", { class: "sc-slider", title: title || "" }, h("label", { class: "sc-slider-label" }, label), range, box);
  const configure = (lo, hi, st) => {
    range.min = String(toSlider(lo));
    range.max = String(toSlider(hi));
    range.step = scale === "log" ? "any" : String(st ?? "any");
    box.step = String(st ?? "any");
  };
  configure(min, max, step);
  let current = value;
  // show(v): the value; show(null, typical): "mixed" (several different values), slider at `typical`
  const show = (v, typical = v) => {
    current = v;
    box.placeholder = v === null ? "mixed" : "";
    if (document.activeElement !== box) box.value = v === null || v === undefined ? "" : formatNumber(v, 4);
    if (Number.isFinite(typical)) range.value = String(toSlider(typical));
  };
  show(value);
  range.addEventListener("input", () => {
    const v = fromSlider(Number(range.value));
    box.value = formatNumber(v, 4);
    onInput(v, false);
  });
  range.addEventListener("change", () => onInput(fromSlider(Number(range.value)), true));
  // a typed value that is no finite number (empty, "abc", "1e999") goes as the text "NaN", "Infinity" or
  // "-Infinity" (JSON has no such numbers: they would arrive as null, which some traits read as "off" or
  // "automatic"); the kernel refuses it with a message and keeps its last good value
  const commitBox = () => {
    const text = box.value.trim();
    const v = text === "" ? NaN : Number(text);
    onInput(Number.isFinite(v) ? v : String(v), true);
  };
  let committedByEnter = false;
  box.addEventListener("change", () => {
    if (committedByEnter) committedByEnter = false;
    else commitBox();
  });
  box.addEventListener("keydown", (event) => {
    event.stopPropagation();
    if (event.key === "Enter") {
      committedByEnter = true;
      commitBox();
      box.blur(); // let the kernel's answer (or the reverted value) show
    }
  });
  return {
    row, range, box,
    set: show,
    get value() { return current; },
    configure,
    setDisabled(disabled) {
      range.disabled = disabled;
      box.disabled = disabled;
      row.classList.toggle("sc-disabled", disabled);
    },
    setLabel(text) { row.querySelector(".sc-slider-label").textContent = text; },
  };
}

/** A <select> built from [[value, label], ...]. */
export function selectBox(options, value, onChange, testid) {
  const select = h("select", { class: "sc-select", "data-testid": testid || null });
  const fill = (opts) => {
    select.replaceChildren(...opts.map(([v, text]) => h("option", { value: v }, text)));
  };
  fill(options);
  select.value = value;
  select.addEventListener("change", () => onChange(select.value));
  select.addEventListener("keydown", (event) => event.stopPropagation());
  return { select, fill, set(v) { select.value = v; } };
}

/** A checkbox with a legend swatch. */
export function checkRow(label, checked, onChange, { swatch = null, testid = null, title = "" } = {}) {
  const box = h("input", { type: "checkbox", "data-testid": testid });
  box.checked = checked;
  box.addEventListener("change", () => onChange(box.checked));
  const parts = [box];
  if (swatch) parts.push(swatch);
  parts.push(h("span", {}, label));
  return { row: h("label", { class: "sc-check", title }, ...parts), box, set(v) { box.checked = v; } };
}

/** A small SVG legend swatch: a line (with optional dash) and/or a marker. */
export function swatch({ color, dash = null, marker = null, width = 2, opacity = 1 }) {
  const svg = s("svg", { width: 26, height: 12, class: "sc-swatch", "aria-hidden": "true" });
  if (dash !== undefined && dash !== "none") {
    svg.append(s("line", { x1: 1, y1: 6, x2: 25, y2: 6, stroke: color, "stroke-width": width, "stroke-dasharray": dash, opacity }));
  }
  if (marker === "circle") svg.append(s("circle", { cx: 13, cy: 6, r: 3.5, fill: "#fff", stroke: color, "stroke-width": 1.5 }));
  if (marker === "dot") svg.append(s("circle", { cx: 13, cy: 6, r: 3, fill: color }));
  if (marker === "square") svg.append(s("rect", { x: 9.5, y: 2.5, width: 7, height: 7, fill: color }));
  if (marker === "cross") svg.append(s("path", { d: "M9,2L17,10M9,10L17,2", stroke: color, "stroke-width": 2 }));
  if (marker === "comb") {
    svg.append(s("path", { d: "M3,10L3,4M8,10L8,2M13,10L13,3M18,10L18,5M23,10L23,7", stroke: color, "stroke-width": 1, opacity: 0.7 }));
    svg.append(s("path", { d: "M3,4L8,2L13,3L18,5L23,7", stroke: color, "stroke-width": 1.5, fill: "none" }));
  }
  return svg;
}

/**
 * Keep keyboard shortcuts and the right-click menu inside the widget: JupyterLab would otherwise run
 * notebook shortcuts (Lumino honours data-lm-suppress-shortcuts) and open its own context menu
 * (suppressed by data-jp-suppress-context-menu).
 */
export function isolateKeys(node) {
  node.setAttribute("data-lm-suppress-shortcuts", "true");
  node.setAttribute("data-jp-suppress-context-menu", "");
}
