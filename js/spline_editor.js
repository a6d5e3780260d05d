// SplineEditor front end (anywidget ES module). The kernel computes every curve and overlay; the page only
// draws them (editor_view.js), shows the controls (editor_controls.js) and turns input into messages and
// trait updates (editor_input.js, drag_controller.js).
//
// Kernel -> page: synced traits (points, point_tension, interval_weights, alpha, beta, form, ...) and
// `geometry`, a dict of little-endian float32 byte buffers plus a little JSON.
// Page -> kernel: trait updates (sliders, dropdowns, selection, view) and custom messages
// {type: "drag" | "add" | "delete" | "select_at" | "undo" | "redo" | "fit" | "resend"}; "ping" with `debug` on.
import { h, Viewport, isolateKeys } from "./common.js";
import { createCanvas, decodeGeometry, decodePoints, gridStep, updateGeometry } from "./editor_view.js";
import { createControls, traitWriters } from "./editor_controls.js";
import { createDragFlow, createPing } from "./drag_controller.js";
import { attachInput } from "./editor_input.js";

const CONTROL_TRAITS = ["form", "preset", "end_condition", "knots", "closed", "alpha", "beta", "point_tension",
  "interval_weights", "selected", "selected_interval", "can_undo", "can_redo", "explanation_html", "options", "comb_scale",
  "t", "snap"];
const OVERLAY_TRAITS = ["show_control_polygon", "show_knots", "show_bezier_points", "show_tangents", "show_comb", "show_grid"];
const SIDE_WIDTH = 268; // px, .sc-side in widgets.css
const LARGE = 1.35; // the "large" presentation size scales the canvas height by this

/** Test and benchmark hooks on the root element: screen/data coordinates, and ping (debug only). */
function instrument(root, model, svg, vp, pointAt, count, handlers, held) {
  const pinger = createPing(model);
  handlers.push(pinger.handle);
  const rect = () => svg.getBoundingClientRect();
  root.__splinecraft = {
    screenPoint(i) {
      if (!(i >= 0 && i < count())) return null;
      const [x, y] = pointAt(i);
      return [rect().left + vp.sx(x), rect().top + vp.sy(y)];
    },
    screenOf(x, y) { return [rect().left + vp.sx(x), rect().top + vp.sy(y)]; },
    /** The kernel's point `i` as this page holds it (data units). */
    pagePoint(i) { return i >= 0 && i < count() ? pointAt(i) : null; },
    /** The geometry this page holds: revision, Bézier pieces and knots (what it draws). */
    geometry() { const g = held(); return { revision: g.revision, bezier: Array.from(g.bezier), knots: Array.from(g.knots) }; },
    dataOf(clientX, clientY) { return [vp.dx(clientX - rect().left), vp.dy(clientY - rect().top)]; },
    /** Spacing of the grid lines in data units (what snap to grid uses). */
    gridStep() { const [x0, y0, x1, y1] = vp.visible(); return gridStep(Math.max(x1 - x0, y1 - y0)); },
    /** Round trip of an empty message through the kernel: {total, up, down} in ms (needs debug=True). */
    ping: pinger.ping,
  };
}

function render({ model, el }) {
  const canvasHeight = () => Math.round(model.get("height") * (model.get("large") ? LARGE : 1));
  const vp = new Viewport(model.get("width"), canvasHeight(), model.get("view"));
  let geometry = updateGeometry(null, model.get("geometry")) ?? decodeGeometry({});
  let kernelPoints = decodePoints(model.get("points")); // float64 x0, y0, x1, y1, ... (decoded once per change)
  const count = () => kernelPoints.length / 2;
  const pointAt = (i) => [kernelPoints[2 * i], kernelPoints[2 * i + 1]];

  const root = h("div", { class: "sc-widget sc-editor", tabindex: 0, "data-testid": "spline-editor" });
  isolateKeys(root);
  el.append(root);
  const focus = () => root.focus({ preventScroll: true });
  const canvas = createCanvas(vp.width, vp.height);
  const controls = createControls(model, { focus, svg: canvas.svg, root });
  const body = h("div", { class: "sc-body" }, h("div", { class: "sc-canvas-wrap" }, canvas.svg, canvas.live.element, canvas.live.overlay, controls.actions), controls.side);
  root.append(controls.toolbar, body, controls.explanation,
    h("div", { class: "sc-footer" }, controls.status, controls.readout, controls.summary));
  controls.side.style.height = `${vp.height}px`;

  /** The kernel's points, with a point being dragged shown where the pointer is. */
  function livePoints() {
    const live = flow.live();
    if (!live || live.index >= count()) return kernelPoints;
    const copy = kernelPoints.slice();
    copy[2 * live.index] = live.x;
    copy[2 * live.index + 1] = live.y;
    return copy;
  }
  function drawPoints() {
    if (flow.live()) canvas.live.begin(); // a drag is moving a point: paint on the canvas until it is answered
    else canvas.live.end();
    const flat = livePoints();
    canvas.drawPoints(vp, flat, { closed: model.get("closed") && model.get("form") !== "segment",
      polygon: model.get("show_control_polygon"), selected: model.get("selected") });
    root.dataset.npoints = String(flat.length / 2);
  }
  function drawGeometry() {
    canvas.drawGeometry(vp, geometry, { knots: model.get("show_knots"), vw: model.get("show_bezier_points"),
      tangents: model.get("show_tangents"), comb: model.get("show_comb") });
  }
  function drawAll() { canvas.drawGrid(vp, model.get("show_grid")); drawGeometry(); drawPoints(); }
  const showStatus = () => controls.showStatus(root, count(), Math.floor(geometry.bezier.length / 8));
  const sync = () => { controls.sync(); showStatus(); };

  const flow = createDragFlow(model, { onIdle: drawPoints });
  const write = traitWriters(model);
  const input = attachInput({ model, root, svg: canvas.svg, curveHit: canvas.layers.curveHit, vp, flow,
    points: livePoints, setTrait: write.set, drawPoints, drawAll, focus, readout: controls.showReadout,
    gridStep: () => { const [x0, y0, x1, y1] = vp.visible(); return gridStep(Math.max(x1 - x0, y1 - y0)); } });

  function onGeometry() {
    const tArrive = performance.now();
    const next = updateGeometry(geometry, model.get("geometry"));
    if (!next) { model.send({ type: "resend" }); return; } // a drag's delta to a geometry this view never had
    geometry = next;
    kernelPoints = decodePoints(model.get("points")); // same update; its change event may come later
    drawGeometry();
    drawPoints();
    showStatus();
    const ackSeq = geometry.seq ?? -1;
    if (ackSeq > 0) flow.drawn(ackSeq, tArrive, root);
    flow.acknowledge(ackSeq);
  }
  /** Canvas size: the cell's width beside the side panel; in a cell too narrow for both, the cell's width (up to
   * `width`; the side panel wraps below the canvas), `height`. */
  const cellWidth = () => Math.floor(el.getBoundingClientRect().width);
  const canvasWidth = () => {
    const room = cellWidth() - (controls.side.getBoundingClientRect().width || SIDE_WIDTH) - 4;
    return room > 240 ? room : Math.max(120, Math.min(model.get("width"), cellWidth() - 4));
  };
  function resize() {
    root.classList.toggle("sc-large", !!model.get("large"));
    vp.width = canvasWidth();
    vp.height = canvasHeight();
    canvas.resize(vp.width, vp.height);
    controls.side.style.height = `${vp.height}px`;
    vp.setView(model.get("view"));
    drawAll();
  }
  // the cell changed width (window, side bars): refit the canvas, but never under a point being dragged
  const observer = typeof ResizeObserver === "undefined" ? null : new ResizeObserver(() => {
    if (Math.abs(canvasWidth() - vp.width) > 1 && !flow.active) resize();
  });
  if (observer) observer.observe(el);

  const handlers = [], messageHandlers = [];
  const on = (event, fn) => { model.on(event, fn); handlers.push([event, fn]); };
  on("change:geometry", onGeometry);
  on("change:points", () => { kernelPoints = decodePoints(model.get("points")); drawPoints(); });
  on("change:view", () => { vp.setView(model.get("view")); drawAll(); });
  for (const name of CONTROL_TRAITS) on(`change:${name}`, () => { sync(); if (name === "selected" || name === "closed") drawPoints(); });
  for (const name of OVERLAY_TRAITS) on(`change:${name}`, () => { sync(); drawGeometry(); drawPoints(); });
  on("change:status_message", showStatus);
  on("change:status_level", showStatus);
  on("change:width", resize);
  on("change:height", resize);
  on("change:large", () => { resize(); sync(); });
  messageHandlers.push((msg) => {
    if (msg && msg.type === "drag_ack") {
      flow.acknowledge(msg.seq);
      if (!msg.ok) drawPoints();
    }
  });
  on("msg:custom", (msg) => { for (const handle of messageHandlers) handle(msg); });
  instrument(root, model, canvas.svg, vp, pointAt, count, messageHandlers, () => geometry);
  root.__splinecraft.live = canvas.live; // the drag's canvas painter (tests compare its two ways of painting)

  sync();
  resize();
  if (model.get("geometry")?.base !== undefined) model.send({ type: "resend" }); // opened during a drag
  root.dataset.ready = "1";
  return () => {
    if (observer) observer.disconnect();
    flow.dispose();
    input.dispose();
    for (const [event, fn] of handlers) model.off(event, fn);
  };
}

export default { render };
