// OutlineEditor input (plain ES module): pointer, wheel and keyboard on the canvas become selections, knot
// drags, handle transforms and messages to the kernel ("drag", "transform", "insert", "delete", "corner",
// "undo", "redo"). Drags and handle gestures go through the shared flow control (drag_controller.js): at
// most one message in flight, the final position always sent on release; the kernel applies each gesture to
// the outline it had when the gesture started, so the latest message wins and nothing accumulates.
//
// Mouse: click a knot to select it (Shift adds or removes), drag a knot (all selected knots move with it) or
// a handle of a selected corner (the curve's control point follows the pointer exactly),
// drag inside the selection's box to move it or its handles to rotate, scale (Shift: per axis) and shear,
// drag the background for a box selection, click the curve to select its contour, double-click the curve to
// insert a knot; the wheel zooms around the pointer, the middle button pans. Keys: arrows (Shift: 10 px),
// Delete/Backspace, C (corner), Ctrl+Z, Ctrl+Shift+Z / Ctrl+Y.
import { hitPoint } from "./editor_input.js";
import { cornerHandles, handles, selectionBox } from "./outline_view.js";

export const HIT = 8; // px: how close a pointer must be to grab a knot, a handle or the curve
const BAND_THRESHOLD = 3; // px before a background press counts as a box selection (else it is a click)
const ZOOM_STEP = 1.15;
const CURVE_SAMPLES = 16; // samples per piece for a click on the curve

/** [contour, knot] of the knot within `radius` px of screen (px, py), nearest first, or null. */
export function hitKnot(vp, cache, px, py, radius = HIT) {
  const { xy, owners } = cache.knots();
  const index = hitPoint(vp, xy, px, py, radius);
  return index >= 0 ? owners[index] : null;
}

/** The corner handle (see outline_view.cornerHandles) within HIT px of (px, py), nearest first, with its
 * squared screen distance `d2`; or null. */
export function hitCornerHandle(vp, grips, px, py) {
  let best = null, bestD = HIT * HIT;
  for (const grip of grips) {
    const dx = vp.sx(grip.x) - px, dy = vp.sy(grip.y) - py, d2 = dx * dx + dy * dy;
    if (d2 <= bestD) { bestD = d2; best = { ...grip, d2 }; }
  }
  return best;
}

/** Whether screen (px, py) lies inside the selection's box (data units; null: no box). */
export function insideBox(vp, box, px, py) {
  return !!box && px >= vp.sx(box.x0) && px <= vp.sx(box.x1) && py >= vp.sy(box.y0) && py <= vp.sy(box.y1);
}

/** The name of the handle (see outline_view.handles) within HIT px of (px, py), or null. */
export function hitHandle(spots, px, py) {
  for (const [name, [x, y]] of Object.entries(spots)) if (Math.hypot(x - px, y - py) <= HIT) return name;
  return null;
}

/** Index of a contour whose curve passes within HIT px of (px, py), or -1. */
export function hitCurve(vp, cache, px, py) {
  const x = vp.dx(px), y = vp.dy(py), tol = vp.len(HIT);
  for (let k = 0; k < cache.length; k++) {
    const b = cache.entries[k].bez;
    for (let o = 0; o < b.length; o += 8) {
      for (let j = 0; j <= CURVE_SAMPLES; j++) {
        const t = j / CURVE_SAMPLES, u = 1 - t;
        const w0 = u * u * u, w1 = 3 * u * u * t, w2 = 3 * u * t * t, w3 = t * t * t;
        const cx = w0 * b[o] + w1 * b[o + 2] + w2 * b[o + 4] + w3 * b[o + 6];
        const cy = w0 * b[o + 1] + w1 * b[o + 3] + w2 * b[o + 5] + w3 * b[o + 7];
        if (Math.hypot(cx - x, cy - y) <= tol) return k;
      }
    }
  }
  return -1;
}

/** Every [contour, knot] whose knot lies on screen inside the rectangle with corners a and b. */
export function knotsInRect(vp, cache, [ax, ay], [bx, by]) {
  const [x0, x1] = [Math.min(ax, bx), Math.max(ax, bx)], [y0, y1] = [Math.min(ay, by), Math.max(ay, by)];
  const { xy, owners } = cache.knots();
  return owners.filter((_, n) => {
    const sx = vp.sx(xy[2 * n]), sy = vp.sy(xy[2 * n + 1]);
    return sx >= x0 && sx <= x1 && sy >= y0 && sy <= y1;
  });
}

/**
 * The affine map [a, b, c, d, e, f] (x' = a x + c y + e, y' = b x + d y + f) of a handle gesture: `g` =
 * {handle, box (data units), x0, y0 (where it was grabbed, data units), shift}, the pointer now at data (x, y).
 * Scale handles keep the opposite corner fixed (uniform unless `shift`), shear handles the opposite edge.
 */
export function transformMatrix(g, x, y) {
  const b = g.box, cx = (b.x0 + b.x1) / 2, cy = (b.y0 + b.y1) / 2;
  if (g.handle === "move") return [1, 0, 0, 1, x - g.x0, y - g.y0];
  if (g.handle === "rotate") {
    const a = Math.atan2(y - cy, x - cx) - Math.atan2(g.y0 - cy, g.x0 - cx), c = Math.cos(a), sn = Math.sin(a);
    return [c, sn, -sn, c, cx - c * cx + sn * cy, cy - sn * cx - c * cy];
  }
  if (g.handle.startsWith("scale")) {
    const ax = g.handle.endsWith("w") ? b.x1 : b.x0, ay = g.handle.includes("n") ? b.y1 : b.y0;
    let sx = (x - ax) / (g.x0 - ax || 1), sy = (y - ay) / (g.y0 - ay || 1);
    if (!g.shift) {
      const vx = g.x0 - ax, vy = g.y0 - ay;
      sx = sy = ((x - ax) * vx + (y - ay) * vy) / (vx * vx + vy * vy || 1);
    }
    return [sx, 0, 0, sy, ax - sx * ax, ay - sy * ay];
  }
  if (g.handle === "shear-top") { const k = (x - g.x0) / (b.y0 - b.y1 || 1); return [1, 0, k, 1, -k * b.y1, 0]; }
  const k = (y - g.y0) / (b.x1 - b.x0 || 1); // shear-right
  return [1, k, 0, 1, 0, -k * b.x0];
}

/** The message of a gesture of the flow control: a knot drag or a transform of the selection. */
export function gestureMessage(g) {
  if (g.kind === "drag") return { type: "drag", contour: g.contour, knot: g.knot, x: g.x, y: g.y };
  if (g.kind === "handle") return { type: "handle", contour: g.contour, knot: g.knot, side: g.side, x: g.x, y: g.y };
  return { type: "transform", matrix: g.matrix };
}

const local = (svg, event) => { const r = svg.getBoundingClientRect(); return [event.clientX - r.left, event.clientY - r.top]; };

/** Zoom with the wheel around the pointer, pan with the middle button; the view is a page trait. */
function attachPanZoom({ svg, vp, setTrait, drawAll }) {
  let pan = null;
  svg.addEventListener("wheel", (event) => {
    event.preventDefault();
    const [px, py] = local(svg, event);
    vp.setView(vp.zoomed(event.deltaY < 0 ? ZOOM_STEP : 1 / ZOOM_STEP, px, py));
    setTrait("view", vp.visible());
  }, { passive: false });
  svg.addEventListener("pointerdown", (event) => {
    if (event.button !== 1) return;
    event.preventDefault();
    svg.setPointerCapture(event.pointerId);
    const [px, py] = local(svg, event);
    pan = { px, py, view: vp.visible(), pointerId: event.pointerId };
  });
  svg.addEventListener("pointermove", (event) => {
    if (!pan || event.pointerId !== pan.pointerId) return;
    const [px, py] = local(svg, event);
    vp.setView(pan.view);
    vp.setView(vp.panned(px - pan.px, py - pan.py));
    drawAll();
  });
  const endPan = (event) => {
    if (!pan || event.pointerId !== pan.pointerId) return;
    pan = null;
    setTrait("view", vp.visible());
  };
  svg.addEventListener("pointerup", endPan);
  svg.addEventListener("pointercancel", endPan);
}

/** The handle of a selected corner under the pointer, unless a knot is nearer. */
function grabbedCornerHandle({ model, vp, cache }, knot, px, py) {
  const grip = hitCornerHandle(vp, cornerHandles(cache, model.get("corners"), model.get("selection")), px, py);
  if (!grip || !knot) return grip;
  const [x, y] = cache.knot(knot[0], knot[1]);
  return grip.d2 < (vp.sx(x) - px) ** 2 + (vp.sy(y) - py) ** 2 ? grip : null;
}

/**
 * A press of the left button: grab a handle of the box, a corner's handle or a knot (select it and drag it), or
 * the box; else start a box selection (returned).
 */
function press(ctx, event, px, py) {
  const { model, vp, cache, flow } = ctx;
  const box = selectionBox(cache, model.get("selection"));
  const handle = hitHandle(handles(vp, box), px, py);
  const knot = handle ? null : hitKnot(vp, cache, px, py);
  const grip = handle ? null : grabbedCornerHandle(ctx, knot, px, py);
  if (grip) {
    const { contour, knot: index, side, x, y } = grip;
    flow.begin({ kind: "handle", contour, knot: index, side, x, y, ox: vp.sx(x) - px, oy: vp.sy(y) - py }, event.pointerId);
    return null;
  }
  if (knot) {
    const key = `${knot[0]}:${knot[1]}`, pairs = model.get("selection") ?? [];
    const chosen = pairs.some(([k, i]) => `${k}:${i}` === key);
    if (event.shiftKey) {
      const others = pairs.filter(([k, i]) => `${k}:${i}` !== key);
      ctx.setTrait("selection", chosen ? others : [...others, knot]);
      return null;
    }
    if (!chosen) ctx.setTrait("selection", [knot]);
    const [x, y] = cache.knot(knot[0], knot[1]);
    flow.begin({ kind: "drag", contour: knot[0], knot: knot[1], x, y, ox: vp.sx(x) - px, oy: vp.sy(y) - py }, event.pointerId);
    return null;
  }
  if (handle || insideBox(vp, box, px, py)) {
    flow.begin({ kind: "transform", handle: handle ?? "move", box, x0: vp.dx(px), y0: vp.dy(py), shift: event.shiftKey,
      matrix: [1, 0, 0, 1, 0, 0] }, event.pointerId);
    return null;
  }
  return { px, py, shift: event.shiftKey, pointerId: event.pointerId, moved: false };
}

/** The release of a box selection: the knots inside the band, or (a click) the contour under the pointer. */
function selectBand(ctx, band, px, py) {
  const { model, vp, cache } = ctx;
  const pairs = band.shift ? [...(model.get("selection") ?? [])] : [];
  if (band.moved) {
    pairs.push(...knotsInRect(vp, cache, [band.px, band.py], [px, py]));
  } else {
    const k = hitCurve(vp, cache, px, py);
    for (let i = 0; k >= 0 && i < cache.count(k); i++) pairs.push([k, i]);
  }
  ctx.setTrait("selection", pairs);
}

/** Left-button gestures: knot drags, handle transforms, box selection; double-click inserts a knot. */
function attachGestures(ctx) {
  const { root, svg, vp, cache, flow } = ctx;
  let band = null; // a box selection in progress {px, py, shift, pointerId, moved}
  svg.addEventListener("pointerdown", (event) => {
    if (event.button !== 0) return;
    root.focus({ preventScroll: true });
    svg.setPointerCapture(event.pointerId);
    event.preventDefault();
    band = press(ctx, event, ...local(svg, event));
  });
  svg.addEventListener("pointermove", (event) => {
    const [px, py] = local(svg, event), g = flow.active;
    if (g && event.pointerId === g.pointerId) {
      if (g.kind === "drag" || g.kind === "handle") {
        flow.update({ x: vp.dx(px + g.ox), y: vp.dy(py + g.oy) });
        ctx.drawKnots(); // the knot or handle follows the pointer until the kernel answers
      } else {
        flow.update({ shift: event.shiftKey, matrix: transformMatrix({ ...g, shift: event.shiftKey }, vp.dx(px), vp.dy(py)) });
      }
      return;
    }
    if (band && event.pointerId === band.pointerId) {
      band.moved = band.moved || Math.hypot(px - band.px, py - band.py) > BAND_THRESHOLD;
      ctx.drawRubber(band.moved ? { x: Math.min(px, band.px), y: Math.min(py, band.py), width: Math.abs(px - band.px), height: Math.abs(py - band.py) } : null);
      return;
    }
    const box = selectionBox(cache, ctx.model.get("selection"));
    const grab = hitKnot(vp, cache, px, py) || hitHandle(handles(vp, box), px, py) || grabbedCornerHandle(ctx, null, px, py);
    svg.style.cursor = grab ? "grab" : insideBox(vp, box, px, py) ? "move" : "";
  });
  function endPointer(event) {
    const g = flow.active;
    if (g && event.pointerId === g.pointerId) { flow.end(); return; }
    if (band && event.pointerId === band.pointerId) {
      ctx.drawRubber(null);
      selectBand(ctx, band, ...local(svg, event));
      band = null;
    }
  }
  svg.addEventListener("pointerup", endPointer);
  svg.addEventListener("pointercancel", endPointer);
  svg.addEventListener("dblclick", (event) => {
    const [px, py] = local(svg, event);
    if (hitKnot(vp, cache, px, py)) return;
    ctx.model.send({ type: "insert", x: vp.dx(px), y: vp.dy(py), tol: vp.len(HIT) });
  });
}

const ARROWS = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, -1], ArrowDown: [0, 1] };

function attachKeys({ model, root, vp, flow }) {
  root.addEventListener("keydown", (event) => {
    // while a drag is in progress its moves apply to the outline it started from: edits wait for the release
    if (flow.active) return;
    const key = event.key, mod = event.ctrlKey || event.metaKey;
    let handled = true;
    if (mod && key.toLowerCase() === "z") model.send({ type: event.shiftKey ? "redo" : "undo" });
    else if (mod && key.toLowerCase() === "y") model.send({ type: "redo" });
    else if (key === "Delete" || key === "Backspace") model.send({ type: "delete" });
    else if (key === "c" || key === "C") model.send({ type: "corner" });
    else if (key in ARROWS && (model.get("selection") ?? []).length) {
      const step = vp.len(event.shiftKey ? 10 : 1), [dx, dy] = ARROWS[key];
      flow.once({ type: "transform", matrix: [1, 0, 0, 1, dx * step, dy * step] });
    } else handled = false;
    if (handled) { event.preventDefault(); event.stopPropagation(); }
  });
}

/**
 * Wire the input of one editor. `ctx`: {model, root, svg, vp, cache (outline_view.ContourCache), flow
 * (drag_controller.createDragFlow with gestureMessage), setTrait(name, value), drawKnots(), drawAll(),
 * drawRubber(rect or null)}.
 */
export function attachInput(ctx) {
  attachPanZoom(ctx);
  attachGestures(ctx);
  attachKeys(ctx);
}
