// SplineEditor input (plain ES module): pointer, touch, wheel and keyboard on the canvas become drags,
// pans, zooms and messages to the kernel ("add", "delete", "select_at", "undo", "redo", "fit").
//
// Mouse: drag a point; drag the background to pan; click the curve to select its interval; double-click to
// add a point; right-click a point to delete it; Ctrl/Alt + wheel zooms (a plain wheel scrolls the page).
// Touch: drag; double tap adds. Keys: Delete/Backspace, Ctrl+Z, Ctrl+Shift+Z / Ctrl+Y, Escape, F.

export const HIT_RADIUS = 9; // px: how close a pointer must be to grab a point
const PAN_THRESHOLD = 3; // px before a background press counts as a pan (else it is a click)
const DOUBLE_TAP_MS = 350;
const DOUBLE_TAP_PX = 24;

/** (x, y) moved to the nearest grid crossing of spacing `step`. */
export function snapped(x, y, step) {
  return [Math.round(x / step) * step, Math.round(y / step) * step];
}

/** Index of the point within HIT_RADIUS of screen (px, py), nearest first, or -1. */
export function hitPoint(vp, flat, px, py, radius = HIT_RADIUS) {
  let best = -1, bestD = radius * radius;
  for (let i = 0, n = flat.length / 2; i < n; i++) {
    const dx = vp.sx(flat[2 * i]) - px, dy = vp.sy(flat[2 * i + 1]) - py;
    const d2 = dx * dx + dy * dy;
    if (d2 <= bestD) { bestD = d2; best = i; }
  }
  return best;
}

/**
 * Wire the input of one editor. `ctx`: {model, root, svg, curveHit, vp, flow, points() (the drawn points: the
 * kernel's, with a dragged point where the page draws it),
 * setTrait(name, value), drawPoints(), drawAll(), focus(), readout(xy or null), gridStep()}. Returns {dispose}.
 */
export function attachInput(ctx) {
  const { model, root, svg, curveHit, vp, flow } = ctx;
  // During a drag the canvas does not move (a resize waits for the release): its screen box is read once
  // at the press, not on every move (reading it after a redraw would force a layout per move).
  let dragRect = null;
  const local = (event) => {
    const rect = (flow.active && dragRect) || svg.getBoundingClientRect();
    return [event.clientX - rect.left, event.clientY - rect.top];
  };
  // hit-tests and grabs use the points where they are drawn: a released drag the kernel has not answered yet
  // is at its drawn place (a press there grabs the point again instead of panning)
  const hit = (px, py) => hitPoint(vp, ctx.points(), px, py);
  const clearSelection = () => {
    model.set("selected", -1);
    model.set("selected_interval", -1);
    model.save_changes();
  };
  let pan = null, wheelTimer = 0, lastTap = null;

  svg.addEventListener("pointerdown", (event) => {
    if (event.button !== 0) return;
    ctx.focus();
    const [px, py] = local(event);
    const index = hit(px, py);
    if (index >= 0) {
      event.preventDefault();
      svg.setPointerCapture(event.pointerId);
      dragRect = svg.getBoundingClientRect();
      const flat = ctx.points();
      const x = flat[2 * index], y = flat[2 * index + 1];
      flow.start(index, x, y, event.pointerId, vp.sx(x) - px, vp.sy(y) - py);
      if (model.get("selected") !== index) ctx.setTrait("selected", index);
      ctx.drawPoints();
      return;
    }
    if (event.target === curveHit) return; // a click on the curve: handled on click
    svg.setPointerCapture(event.pointerId);
    pan = { x: px, y: py, pointerId: event.pointerId, moved: false, view: vp.visible(), local: null };
  });

  svg.addEventListener("pointermove", (event) => {
    const [px, py] = local(event);
    ctx.readout([vp.dx(px), vp.dy(py)]);
    const drag = flow.active;
    if (drag && event.pointerId === drag.pointerId) {
      let x = vp.dx(px + drag.ox), y = vp.dy(py + drag.oy);
      if (model.get("snap")) [x, y] = snapped(x, y, ctx.gridStep());
      flow.move(x, y);
      ctx.drawPoints();
      return;
    }
    if (pan && event.pointerId === pan.pointerId) {
      const dx = px - pan.x, dy = py - pan.y;
      if (!pan.moved && Math.hypot(dx, dy) < PAN_THRESHOLD) return;
      pan.moved = true;
      vp.setView(pan.view);
      pan.local = vp.panned(dx, dy);
      vp.setView(pan.local);
      ctx.drawAll();
      return;
    }
    svg.style.cursor = hit(px, py) >= 0 ? "grab" : "";
  });

  function endPointer(event) {
    const drag = flow.active;
    if (drag && event.pointerId === drag.pointerId) {
      flow.end();
      ctx.drawPoints();
    }
    if (pan && event.pointerId === pan.pointerId) {
      if (pan.moved && pan.local) ctx.setTrait("view", pan.local);
      else if (!pan.moved && event.type === "pointerup" && (model.get("selected") >= 0 || model.get("selected_interval") >= 0)) {
        clearSelection();
      }
      pan = null;
    }
  }
  svg.addEventListener("pointerup", endPointer);
  svg.addEventListener("pointercancel", endPointer);
  svg.addEventListener("pointerleave", () => ctx.readout(null));

  curveHit.addEventListener("click", (event) => {
    const [px, py] = local(event);
    model.send({ type: "select_at", x: vp.dx(px), y: vp.dy(py), tol: vp.len(HIT_RADIUS) });
  });

  function addAt(px, py) {
    if (hit(px, py) >= 0) return;
    model.send({ type: "add", x: vp.dx(px), y: vp.dy(py), tol: vp.len(HIT_RADIUS) });
  }
  svg.addEventListener("dblclick", (event) => {
    event.preventDefault();
    addAt(...local(event));
  });
  // touch: a double tap adds a point (browsers do not reliably send dblclick for touch)
  svg.addEventListener("pointerup", (event) => {
    if (event.pointerType !== "touch") return;
    const [px, py] = local(event), now = performance.now();
    if (lastTap && now - lastTap.t < DOUBLE_TAP_MS && Math.hypot(px - lastTap.x, py - lastTap.y) < DOUBLE_TAP_PX) {
      lastTap = null;
      addAt(px, py);
    } else {
      lastTap = { t: now, x: px, y: py };
    }
  });

  svg.addEventListener("contextmenu", (event) => {
    if (flow.active) { event.preventDefault(); return; } // no delete while a point is dragged: its index moves
    const index = hit(...local(event));
    if (index < 0) return;
    event.preventDefault();
    event.stopPropagation();
    model.send({ type: "delete", index });
  });

  svg.addEventListener("wheel", (event) => {
    if (!(event.ctrlKey || event.metaKey || event.altKey)) return; // a plain wheel scrolls the notebook
    event.preventDefault();
    const [px, py] = local(event);
    vp.setView(vp.zoomed(Math.exp(-event.deltaY * 0.002), px, py));
    ctx.drawAll();
    clearTimeout(wheelTimer);
    wheelTimer = setTimeout(() => ctx.setTrait("view", vp.visible()), 150);
  }, { passive: false });

  root.addEventListener("keydown", (event) => {
    const target = event.target;
    if (target instanceof HTMLInputElement || target instanceof HTMLSelectElement) return;
    // while a point is dragged its moves name it by index: a delete or undo would hand them another point
    if (flow.active) return;
    const key = event.key, mod = event.ctrlKey || event.metaKey;
    let handled = true;
    if ((key === "Delete" || key === "Backspace") && model.get("selected") >= 0) {
      model.send({ type: "delete", index: model.get("selected") });
    } else if (mod && (key === "z" || key === "Z") && !event.shiftKey) {
      model.send({ type: "undo" });
    } else if (mod && (((key === "z" || key === "Z") && event.shiftKey) || key === "y")) {
      model.send({ type: "redo" });
    } else if (key === "Escape") {
      clearSelection();
    } else if (key === "f" && !mod) {
      model.send({ type: "fit" });
    } else {
      handled = false;
    }
    if (handled) { event.preventDefault(); event.stopPropagation(); }
  });

  return { dispose() { clearTimeout(wheelTimer); } };
}
