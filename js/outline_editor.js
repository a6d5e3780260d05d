// OutlineEditor front end (anywidget ES module). The kernel rebuilds every contour with the engine and
// sends its Bézier pieces (float32 buffers, one entry per contour with a revision, so only changed contours
// are re-encoded and redrawn); the page draws them over the bitmap (outline_view.js), shows the controls
// (outline_controls.js) and turns input into messages and the `selection` trait (outline_input.js, with the
// flow control of drag_controller.js).
//
// Kernel -> page: synced traits (geometry, corners, selection, point_tension, interval_weights, status,
// max_deviation, view, ...) and, during a gesture, custom "live" messages with the changed contours' pieces.
// Page -> kernel: {type: "drag" | "handle" | "transform" | "corner" | "insert" | "delete" | "undo" | "redo" | "tension" |
// "weight" | "reflect" | "export" | "fit"}, the `selection`, `view` and overlay traits; "ping" with `debug` on.
import { h, Viewport, isolateKeys } from "./common.js";
import { createCanvas, cornerHandles, handles, selectionBox } from "./outline_view.js";
import { createControls } from "./outline_controls.js";
import { createDragFlow, createPing } from "./drag_controller.js";
import { attachInput, gestureMessage } from "./outline_input.js";

const STATUS_TRAITS = ["status_message", "status_level", "max_deviation", "can_undo", "can_redo", "point_tension", "interval_weights"];

/** Test and benchmark hooks on the root element (client coordinates), and ping (debug only). */
function instrument(root, model, canvas, vp) {
  const pinger = createPing(model);
  const rect = () => canvas.svg.getBoundingClientRect();
  const { cache } = canvas;
  root.__splinecraft = {
    screenKnot(k, i) {
      if (!cache.has(k, i)) return null;
      const [x, y] = cache.knot(k, i);
      return [rect().left + vp.sx(x), rect().top + vp.sy(y)];
    },
    screenOf(x, y) { return [rect().left + vp.sx(x), rect().top + vp.sy(y)]; },
    screenHandle(name) {
      const spot = handles(vp, selectionBox(cache, model.get("selection")))[name];
      return spot ? [rect().left + spot[0], rect().top + spot[1]] : null;
    },
    /** The `side` ("in" | "out") handle of selected corner `knot` of contour `k`, or null when it is not shown. */
    screenCornerHandle(k, i, side) {
      const grip = cornerHandles(cache, model.get("corners"), model.get("selection"))
        .find((g) => g.contour === k && g.knot === i && g.side === side);
      return grip ? [rect().left + vp.sx(grip.x), rect().top + vp.sy(grip.y)] : null;
    },
    dataOf(clientX, clientY) { return [vp.dx(clientX - rect().left), vp.dy(clientY - rect().top)]; },
    /** Send `message` to the kernel as the page's input would (tests of refused messages). */
    send(message) { model.send(message); },
    ping: pinger.ping,
  };
  return pinger;
}

/** Listen to the model: redraw what a trait change touches, answer the kernel's custom messages. */
function follow(model, { onGeometry, onLive, resize, drawAll, drawKnots, drawCurves, drawImage, showStatus, canvas, controls, flow, pinger }) {
  const handlers = [];
  const on = (event, fn) => { model.on(event, fn); handlers.push([event, fn]); };
  on("change:geometry", onGeometry);
  on("change:view", () => { drawAll(true); });
  on("change:width", resize);
  on("change:height", resize);
  on("change:selection", () => { drawKnots(); showStatus(); });
  on("change:corners", drawKnots);
  for (const name of STATUS_TRAITS) on(`change:${name}`, showStatus);
  for (const name of ["show_fill", "show_deviation"]) on(`change:${name}`, () => { controls.syncOverlays(); drawCurves(); });
  on("change:show_image", drawImage);
  on("change:image", () => { canvas.dropImage(); drawImage(); });
  on("msg:custom", (msg, buffers) => {
    if (!msg || pinger.handle(msg)) return;
    if (msg.type === "live") onLive(msg, buffers ?? []);
    else if (msg.type === "drag_ack") { flow.acknowledge(msg.seq); if (!msg.ok) drawKnots(); }
  });
  return handlers;
}

function render({ model, el }) {
  const vp = new Viewport(model.get("width"), model.get("height"), model.get("view"));
  const root = h("div", { class: "sc-widget sc-outline", tabindex: 0, "data-testid": "outline-editor" });
  isolateKeys(root);
  el.append(root);
  const setTrait = (name, value) => { model.set(name, value); model.save_changes(); };
  const send = (message) => model.send(message);
  const canvas = createCanvas(model.get("width"), model.get("height"));
  const { cache } = canvas;
  const controls = createControls(model, { send, setTrait });
  root.append(controls.toolbar, h("div", { class: "sc-body" }, h("div", { class: "sc-canvas-wrap" }, canvas.svg), controls.side), controls.footer);

  const drawCurves = (force = false) => canvas.drawCurves(vp, { fill: model.get("show_fill"), deviation: model.get("show_deviation"), force });
  function drawKnots() {
    const pairs = model.get("selection") ?? [], corners = model.get("corners") ?? [];
    canvas.drawKnots(vp, { corners, chosen: new Set(pairs.map(([k, i]) => `${k}:${i}`)), live: flow.live(),
      box: selectionBox(cache, pairs), handles: cornerHandles(cache, corners, pairs) });
  }
  const drawImage = () => canvas.drawImage(vp, { bytes: model.get("image"), frame: model.get("frame"), show: model.get("show_image") });
  const showStatus = () => controls.showStatus(root);
  /** Everything; `newView`: first take the model's view (it changed). */
  function drawAll(newView = false) {
    if (newView) vp.setView(model.get("view"));
    drawImage(); drawCurves(true); drawKnots(); showStatus();
  }

  const flow = createDragFlow(model, { onIdle: drawKnots, message: gestureMessage });
  attachInput({ model, root, svg: canvas.svg, vp, cache, flow, setTrait, drawKnots, drawAll, drawRubber: canvas.drawRubber });

  /** A drawn answer to message `ackSeq`: latency record (debug) and flow control. */
  function answered(ackSeq, tArrive) {
    if (ackSeq > 0) flow.drawn(ackSeq, tArrive, root);
    flow.acknowledge(ackSeq);
  }
  function onGeometry() {
    const tArrive = performance.now();
    const geometry = model.get("geometry") ?? {};
    cache.update(geometry.contours ?? []);
    drawCurves();
    drawKnots();
    showStatus();
    answered(geometry.seq ?? -1, tArrive);
  }
  /** The moves of a gesture: only the changed contours' pieces, in a custom message. */
  function onLive(msg, buffers) {
    const tArrive = performance.now();
    (msg.contours ?? []).forEach((entry, i) => cache.replace(entry.index, entry.revision, buffers[i]));
    drawCurves();
    drawKnots();
    answered(msg.seq ?? -1, tArrive);
  }
  function resize() {
    canvas.resize(model.get("width"), model.get("height"));
    vp.width = model.get("width");
    vp.height = model.get("height");
    vp.setView(model.get("view"));
    drawAll();
  }

  const pinger = instrument(root, model, canvas, vp);
  const handlers = follow(model, { onGeometry, onLive, resize, drawAll, drawKnots, drawCurves, drawImage, showStatus, canvas,
    controls, flow, pinger });
  cache.update((model.get("geometry") ?? {}).contours ?? []);
  drawAll();
  root.dataset.ready = "1";
  return () => {
    flow.dispose();
    canvas.dropImage();
    for (const [event, fn] of handlers) model.off(event, fn);
  };
}

export default { render };
