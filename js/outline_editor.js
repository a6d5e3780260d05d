// OutlineEditor front end (anywidget ES module). The kernel rebuilds every contour with the engine and
// sends its Bézier pieces (float32 buffers, one entry per contour with a revision, so only changed
// contours are re-encoded and redrawn); this module draws them over the bitmap and turns pointer and
// keyboard input into messages: {type: "drag" | "transform" | "corner" | "insert" | "delete" | "undo" |
// "redo" | "tension" | "weight" | "export" | "fit"} and the `selection` trait.
// Drags and handle gestures are throttled to animation frames with at most one message in flight; the
// final position is always sent on pointerup. The kernel applies each gesture to the outline it had when
// the gesture started, so the latest message wins and nothing accumulates.
import { h, s, floats, Viewport, bezierPath, markersPath, sliderRow, checkRow, isolateKeys, formatNumber } from "./common.js";

const COLORS = { curve: "#1565c0", fill: "#90caf9", knot: "#0d47a1", corner: "#d32f2f", selected: "#ff6f00", box: "#6a1b9a" };
const DEVIATION_BINS = [[0.5, "#2e7d32"], [1.0, "#9e9d24"], [2.0, "#ef6c00"], [Infinity, "#c62828"]];
const HIT = 8; // px: how close a pointer must be to grab a knot, a handle or the curve

function render({ model, el }) {
  const vp = new Viewport(model.get("width"), model.get("height"), model.get("view"));
  const root = h("div", { class: "sc-widget sc-outline", tabindex: 0, "data-testid": "outline-editor" });
  isolateKeys(root);
  el.append(root);
  const setTrait = (name, value) => { model.set(name, value); model.save_changes(); };
  const send = (message) => model.send(message);

  // ---------------------------------------------------------------- toolbar and canvas
  const btn = (text, title, testid, onClick) => h("button", { class: "sc-button", title, "data-testid": testid, onclick: (e) => { e.preventDefault(); onClick(); } }, text);
  const undoBtn = btn("↶ Undo", "Undo (Ctrl+Z)", "undo", () => send({ type: "undo" }));
  const redoBtn = btn("↷ Redo", "Redo (Ctrl+Y)", "redo", () => send({ type: "redo" }));
  const cornerBtn = btn("Corner ⇄ smooth", "Toggle the selected knots between corner and smooth GC² joint (C)", "toggle-corner", () => send({ type: "corner" }));
  const deleteBtn = btn("Delete", "Delete the selected knots (Delete)", "delete", () => send({ type: "delete" }));
  const mirrorX = btn("Mirror ⇆", "Reflect the selection (or the whole shape) left-right", "mirror-vertical", () => send({ type: "reflect", axis: "vertical" }));
  const mirrorY = btn("Mirror ⇅", "Reflect the selection (or the whole shape) upside down", "mirror-horizontal", () => send({ type: "reflect", axis: "horizontal" }));
  const fitBtn = btn("Fit", "Fit the outline to the view", "fit", () => send({ type: "fit" }));
  const exportBtn = btn("Export SVG", "Write the outline to export_path", "export", () => send({ type: "export" }));
  const overlays = [["show_image", "bitmap"], ["show_fill", "fill"], ["show_deviation", "deviation"]]
    .map(([name, label]) => checkRow(label, model.get(name), (v) => setTrait(name, v), { testid: name }));
  const tension = sliderRow({ label: "tension v", title: "Point tension of the selected knots (§2.5)", min: -1, max: 50, step: 0.1, value: 0,
    onInput: (v, final) => { if (final) send({ type: "tension", value: v }); }, testid: "tension" });
  const weight = sliderRow({ label: "weight ω", title: "Interval weight of the pieces after the selected knots", min: 0.05, max: 20, step: 0.05, value: 1, scale: "log",
    onInput: (v, final) => { if (final) send({ type: "weight", value: v }); }, testid: "weight" });
  const toolbar = h("div", { class: "sc-toolbar" }, undoBtn, redoBtn, cornerBtn, deleteBtn, mirrorX, mirrorY, fitBtn, exportBtn,
    h("span", { class: "sc-spacer" }), ...overlays.map((o) => o.row));
  const svg = s("svg", { class: "sc-canvas", width: model.get("width"), height: model.get("height"), "data-testid": "canvas" });
  const bg = s("rect", { x: 0, y: 0, width: model.get("width"), height: model.get("height"), fill: "#f4f6f8" });
  const image = s("image", { preserveAspectRatio: "none", style: "image-rendering: pixelated", opacity: 0.45, "data-testid": "bitmap" });
  const fillPath = s("path", { fill: COLORS.fill, "fill-rule": "evenodd", opacity: 0.35, stroke: "none", "data-testid": "fill" });
  const curves = s("g", { "data-testid": "curves" });
  const deviationGroup = s("g", { "data-testid": "deviation" });
  const knotPath = s("path", { fill: "#fff", stroke: COLORS.knot, "stroke-width": 1.3, "data-testid": "knots" });
  const cornerPath = s("path", { fill: COLORS.corner, stroke: "#fff", "stroke-width": 0.8, "data-testid": "corners" });
  const selectedPath = s("path", { fill: COLORS.selected, stroke: "#fff", "stroke-width": 0.8, "data-testid": "selected" });
  const boxRect = s("rect", { fill: "none", stroke: COLORS.box, "stroke-dasharray": "4 3", "data-testid": "selection-box" });
  const handlePath = s("path", { fill: "#fff", stroke: COLORS.box, "stroke-width": 1.3, "data-testid": "handles" });
  const rubber = s("rect", { fill: "rgba(106,27,154,0.08)", stroke: COLORS.box, "stroke-width": 1, visibility: "hidden", "data-testid": "rubber-band" });
  svg.append(bg, image, fillPath, curves, deviationGroup, boxRect, handlePath, knotPath, cornerPath, selectedPath, rubber);
  const status = h("div", { class: "sc-status", "data-testid": "status" });
  const deviationLabel = h("span", { class: "sc-summary", "data-testid": "max-deviation" });
  const side = h("div", { class: "sc-side" }, h("div", { class: "sc-section" }, h("div", { class: "sc-section-title" }, "Selected knots"), tension.row, weight.row));
  root.append(toolbar, h("div", { class: "sc-body" }, h("div", { class: "sc-canvas-wrap" }, svg), side), h("div", { class: "sc-footer" }, status, deviationLabel));

  // ---------------------------------------------------------------- geometry from the kernel
  const cache = []; // per contour: {revision, bez (Float32Array), path (screen-independent), el}
  let viewKey = "";
  const knotXY = (k, i) => { const b = cache[k].bez; return [b[8 * i], b[8 * i + 1]]; };
  const knotCount = (k) => (cache[k] ? cache[k].bez.length / 8 : 0);
  let live = null; // {contour, knot, x, y}: a knot shown where the pointer is while its answer is pending

  function decode() {
    const geometry = model.get("geometry") ?? {};
    const entries = geometry.contours ?? [];
    for (let k = 0; k < entries.length; k++) {
      const entry = entries[k];
      if (!cache[k] || cache[k].revision !== entry.revision || (entry.deviation && !cache[k].deviation)) {
        const el = cache[k]?.el ?? s("path", { fill: "none", stroke: COLORS.curve, "stroke-width": 1.6, "data-testid": `contour-${k}` });
        cache[k] = { revision: entry.revision, bez: floats(entry.bezier), deviation: entry.deviation ? floats(entry.deviation) : null, path: null, el };
        if (!el.parentNode) curves.append(el);
      }
    }
    while (cache.length > entries.length) cache.pop().el.remove();
    return geometry.seq ?? -1;
  }

  function drawCurves(force = false) {
    const key = vp.view.join(",") + model.get("width") + "x" + model.get("height");
    const all = [];
    for (const entry of cache) {
      if (force || key !== viewKey || entry.path === null) {
        entry.path = bezierPath(vp, entry.bez, true);
        entry.el.setAttribute("d", entry.path);
      }
      all.push(entry.path);
    }
    viewKey = key;
    fillPath.setAttribute("d", model.get("show_fill") ? all.join("") : "");
    drawDeviation();
  }

  function drawDeviation() {
    deviationGroup.replaceChildren();
    if (!model.get("show_deviation")) return;
    const bins = DEVIATION_BINS.map(() => []);
    for (const entry of cache) {
      if (!entry.deviation) continue;
      for (let i = 0; i < entry.deviation.length; i++) {
        const bin = DEVIATION_BINS.findIndex(([limit]) => entry.deviation[i] < limit);
        bins[bin].push(bezierPath(vp, entry.bez.subarray(8 * i, 8 * i + 8), false));
      }
    }
    bins.forEach((parts, b) => deviationGroup.append(s("path", { d: parts.join(""), fill: "none", stroke: DEVIATION_BINS[b][1], "stroke-width": 4, opacity: 0.8, "data-testid": `deviation-${b}` })));
  }

  function selectionSet() { return new Set((model.get("selection") ?? []).map(([k, i]) => `${k}:${i}`)); }

  function drawKnots() {
    const corners = model.get("corners") ?? [];
    const chosen = selectionSet();
    const smooth = [], sharp = [], picked = [];
    cache.forEach((entry, k) => {
      for (let i = 0; i < knotCount(k); i++) {
        let [x, y] = knotXY(k, i);
        if (live && live.contour === k && live.knot === i) [x, y] = [live.x, live.y];
        (chosen.has(`${k}:${i}`) ? picked : (corners[k]?.[i] ? sharp : smooth)).push(x, y);
      }
    });
    knotPath.setAttribute("d", markersPath(vp, smooth, 3.2, "circle"));
    cornerPath.setAttribute("d", markersPath(vp, sharp, 3.4, "square"));
    selectedPath.setAttribute("d", markersPath(vp, picked, 4, "circle"));
    drawBox();
  }

  // the selection's bounding box (data units) and its handles (screen px)
  function selectionBox() {
    const pairs = model.get("selection") ?? [];
    if (!pairs.length) return null;
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (const [k, i] of pairs) {
      if (!cache[k] || i >= knotCount(k)) continue;
      const [x, y] = knotXY(k, i);
      x0 = Math.min(x0, x); y0 = Math.min(y0, y); x1 = Math.max(x1, x); y1 = Math.max(y1, y);
    }
    if (!(x1 >= x0)) return null;
    if (pairs.length < 2 || (x1 - x0) + (y1 - y0) === 0) return null;
    return { x0, y0, x1, y1 };
  }
  function handles(box) {
    if (!box) return {};
    const [X0, Y0, X1, Y1] = [vp.sx(box.x0), vp.sy(box.y0), vp.sx(box.x1), vp.sy(box.y1)];
    const cx = (X0 + X1) / 2, cy = (Y0 + Y1) / 2;
    return {
      rotate: [cx, Y0 - 24], "scale-nw": [X0, Y0], "scale-ne": [X1, Y0], "scale-sw": [X0, Y1], "scale-se": [X1, Y1],
      "shear-top": [cx, Y0], "shear-right": [X1, cy],
    };
  }
  function drawBox() {
    const box = selectionBox();
    if (!box) { boxRect.setAttribute("visibility", "hidden"); handlePath.setAttribute("d", ""); return; }
    const X0 = vp.sx(box.x0), Y0 = vp.sy(box.y0);
    Object.entries({ x: X0, y: Y0, width: Math.max(vp.sx(box.x1) - X0, 1), height: Math.max(vp.sy(box.y1) - Y0, 1), visibility: "visible" })
      .forEach(([key, v]) => boxRect.setAttribute(key, v));
    const parts = [];
    for (const [name, [x, y]] of Object.entries(handles(box))) {
      if (name === "rotate") parts.push(`M${x - 5},${y}a5,5 0 1,0 10,0a5,5 0 1,0 -10,0M${x},${y + 5}L${x},${Y0}`);
      else if (name.startsWith("shear")) parts.push(`M${x},${y - 5}l5,5l-5,5l-5,-5Z`);
      else parts.push(`M${x - 4},${y - 4}h8v8h-8Z`);
    }
    handlePath.setAttribute("d", parts.join(""));
  }

  function drawImage() {
    const bytes = model.get("image");
    const [w, hgt] = model.get("frame");
    const has = bytes && bytes.byteLength > 0 && model.get("show_image");
    image.setAttribute("visibility", has ? "visible" : "hidden");
    if (has) {
      if (!image.dataset.url) image.dataset.url = URL.createObjectURL(new Blob([bytes], { type: "image/png" }));
      image.setAttribute("href", image.dataset.url);
      Object.entries({ x: vp.sx(0), y: vp.sy(0), width: w * vp.k, height: hgt * vp.k })
        .forEach(([key, v]) => image.setAttribute(key, v));
    }
  }

  function showStatus() {
    status.textContent = model.get("status_message") ?? "";
    status.dataset.level = model.get("status_level") ?? "info";
    const dev = model.get("max_deviation");
    deviationLabel.textContent = dev === null || dev === undefined ? "" : `max deviation ${formatNumber(dev, 2)} px`;
    undoBtn.disabled = !model.get("can_undo");
    redoBtn.disabled = !model.get("can_redo");
    const pairs = model.get("selection") ?? [];
    const tensions = model.get("point_tension") ?? [], weights = model.get("interval_weights") ?? [];
    const values = (table) => [...new Set(pairs.map(([k, i]) => table[k]?.[i]))];
    const vt = values(tensions), vw = values(weights);
    tension.set(vt.length === 1 ? vt[0] : null, vt[0] ?? 0);
    weight.set(vw.length === 1 ? vw[0] : null, vw[0] ?? 1);
    tension.setDisabled(!pairs.length);
    weight.setDisabled(!pairs.length);
    root.dataset.nselected = String(pairs.length);
  }

  function drawAll() { drawImage(); drawCurves(true); drawKnots(); showStatus(); }

  // ---------------------------------------------------------------- hit tests (screen px)
  const local = (event) => { const r = svg.getBoundingClientRect(); return [event.clientX - r.left, event.clientY - r.top]; };
  function hitKnot(px, py) {
    let best = null, bestD = HIT * HIT;
    cache.forEach((_, k) => {
      for (let i = 0; i < knotCount(k); i++) {
        const [x, y] = knotXY(k, i), dx = vp.sx(x) - px, dy = vp.sy(y) - py, d2 = dx * dx + dy * dy;
        if (d2 <= bestD) { bestD = d2; best = [k, i]; }
      }
    });
    return best;
  }
  function hitHandle(px, py) {
    for (const [name, [x, y]] of Object.entries(handles(selectionBox()))) if (Math.hypot(x - px, y - py) <= HIT) return name;
    return null;
  }
  function hitCurve(px, py) {
    const x = vp.dx(px), y = vp.dy(py), tol = vp.len(HIT);
    for (let k = 0; k < cache.length; k++) {
      const b = cache[k].bez;
      for (let p = 0; p < b.length / 8; p++) {
        for (let j = 0; j <= 16; j++) {
          const t = j / 16, u = 1 - t, o = 8 * p;
          const w = [u * u * u, 3 * u * u * t, 3 * u * t * t, t * t * t];
          const cx = w[0] * b[o] + w[1] * b[o + 2] + w[2] * b[o + 4] + w[3] * b[o + 6];
          const cy = w[0] * b[o + 1] + w[1] * b[o + 3] + w[2] * b[o + 5] + w[3] * b[o + 7];
          if (Math.hypot(cx - x, cy - y) <= tol) return k;
        }
      }
    }
    return -1;
  }
  function insideBox(px, py) {
    const box = selectionBox();
    return box && px >= vp.sx(box.x0) && px <= vp.sx(box.x1) && py >= vp.sy(box.y0) && py <= vp.sy(box.y1);
  }

  // ---------------------------------------------------------------- gestures with flow control
  let seq = 0, gestureId = 0, inFlight = null, pendingSend = false, rafId = 0;
  let gesture = null; // {kind: "drag"|"transform", ...}
  const moveTimes = new Map();
  const latencyLog = () => {
    window.__splinecraft = window.__splinecraft ?? {};
    window.__splinecraft.dragLatencies = window.__splinecraft.dragLatencies ?? [];
    return window.__splinecraft.dragLatencies;
  };
  function message(final) {
    seq += 1;
    if (model.get("debug")) moveTimes.set(seq, { move: gesture.tMove, sent: performance.now() });
    inFlight = { seq, t: performance.now() };
    if (gesture.kind === "drag") {
      send({ type: "drag", contour: gesture.contour, knot: gesture.knot, x: gesture.x, y: gesture.y, seq, gesture: gesture.id, final });
    } else {
      send({ type: "transform", matrix: gesture.matrix, seq, gesture: gesture.id, final });
    }
  }
  function frame() {
    rafId = 0;
    if (!gesture || !pendingSend) return;
    if (inFlight && performance.now() - inFlight.t < 1000) return;
    pendingSend = false;
    message(false);
  }
  function acknowledge(ackSeq) {
    if (inFlight && ackSeq >= inFlight.seq) inFlight = null;
    if (live && live.finalSeq !== undefined && ackSeq >= live.finalSeq) { live = null; drawKnots(); }
    if (gesture && pendingSend && !rafId) rafId = requestAnimationFrame(frame);
  }

  function transformMatrix(g, px, py) {
    const x = vp.dx(px), y = vp.dy(py), b = g.box, cx = (b.x0 + b.x1) / 2, cy = (b.y0 + b.y1) / 2;
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

  let band = null; // rubber-band selection {px, py, shift}
  // zoom with the wheel around the pointer, pan with the middle button; the view is a page trait
  let pan = null;
  svg.addEventListener("wheel", (event) => {
    event.preventDefault();
    const [px, py] = local(event);
    vp.setView(vp.zoomed(event.deltaY < 0 ? 1.15 : 1 / 1.15, px, py));
    setTrait("view", vp.visible());
  }, { passive: false });
  svg.addEventListener("pointerdown", (event) => {
    if (event.button === 1) {
      event.preventDefault();
      svg.setPointerCapture(event.pointerId);
      const [px, py] = local(event);
      pan = { px, py, view: vp.visible(), pointerId: event.pointerId };
    }
  });
  svg.addEventListener("pointermove", (event) => {
    if (!pan || event.pointerId !== pan.pointerId) return;
    const [px, py] = local(event);
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

  svg.addEventListener("pointerdown", (event) => {
    if (event.button !== 0) return;
    root.focus({ preventScroll: true });
    const [px, py] = local(event);
    const handle = hitHandle(px, py);
    const knot = handle ? null : hitKnot(px, py);
    svg.setPointerCapture(event.pointerId);
    event.preventDefault();
    if (knot) {
      const key = `${knot[0]}:${knot[1]}`, chosen = selectionSet();
      if (event.shiftKey) {
        const pairs = (model.get("selection") ?? []).filter(([k, i]) => `${k}:${i}` !== key);
        setTrait("selection", chosen.has(key) ? pairs : [...pairs, knot]);
        return;
      }
      if (!chosen.has(key)) setTrait("selection", [knot]);
      const [x, y] = knotXY(knot[0], knot[1]);
      gesture = { kind: "drag", id: ++gestureId, contour: knot[0], knot: knot[1], x, y, ox: vp.sx(x) - px, oy: vp.sy(y) - py, pointerId: event.pointerId, moved: false, tMove: performance.now() };
      return;
    }
    if (handle || insideBox(px, py)) {
      gesture = { kind: "transform", id: ++gestureId, handle: handle ?? "move", box: selectionBox(), x0: vp.dx(px), y0: vp.dy(py), shift: event.shiftKey, matrix: [1, 0, 0, 1, 0, 0], pointerId: event.pointerId, moved: false, tMove: performance.now() };
      return;
    }
    band = { px, py, shift: event.shiftKey, pointerId: event.pointerId, moved: false };
  });

  svg.addEventListener("pointermove", (event) => {
    const [px, py] = local(event);
    if (gesture && event.pointerId === gesture.pointerId) {
      gesture.moved = true;
      gesture.tMove = performance.now();
      if (gesture.kind === "drag") {
        gesture.x = vp.dx(px + gesture.ox);
        gesture.y = vp.dy(py + gesture.oy);
        live = { contour: gesture.contour, knot: gesture.knot, x: gesture.x, y: gesture.y };
        drawKnots();
      } else {
        gesture.shift = event.shiftKey;
        gesture.matrix = transformMatrix(gesture, px, py);
      }
      pendingSend = true;
      if (!rafId) rafId = requestAnimationFrame(frame);
      return;
    }
    if (band && event.pointerId === band.pointerId) {
      band.moved = band.moved || Math.hypot(px - band.px, py - band.py) > 3;
      Object.entries({ x: Math.min(px, band.px), y: Math.min(py, band.py), width: Math.abs(px - band.px), height: Math.abs(py - band.py), visibility: band.moved ? "visible" : "hidden" })
        .forEach(([key, v]) => rubber.setAttribute(key, v));
      return;
    }
    svg.style.cursor = hitKnot(px, py) || hitHandle(px, py) ? "grab" : insideBox(px, py) ? "move" : "";
  });

  function endPointer(event) {
    const [px, py] = local(event);
    if (gesture && event.pointerId === gesture.pointerId) {
      if (gesture.moved) {
        pendingSend = false;
        message(true);
        if (live) live.finalSeq = seq;
      }
      gesture = null;
      return;
    }
    if (band && event.pointerId === band.pointerId) {
      rubber.setAttribute("visibility", "hidden");
      let pairs = band.shift ? [...(model.get("selection") ?? [])] : [];
      if (band.moved) {
        const [x0, x1] = [Math.min(px, band.px), Math.max(px, band.px)], [y0, y1] = [Math.min(py, band.py), Math.max(py, band.py)];
        cache.forEach((_, k) => {
          for (let i = 0; i < knotCount(k); i++) {
            const [x, y] = knotXY(k, i), sx = vp.sx(x), sy = vp.sy(y);
            if (sx >= x0 && sx <= x1 && sy >= y0 && sy <= y1) pairs.push([k, i]);
          }
        });
      } else {
        const k = hitCurve(px, py);
        if (k >= 0) for (let i = 0; i < knotCount(k); i++) pairs.push([k, i]);
      }
      setTrait("selection", pairs);
      band = null;
    }
  }
  svg.addEventListener("pointerup", endPointer);
  svg.addEventListener("pointercancel", endPointer);
  svg.addEventListener("dblclick", (event) => {
    const [px, py] = local(event);
    if (hitKnot(px, py)) return;
    send({ type: "insert", x: vp.dx(px), y: vp.dy(py), tol: vp.len(HIT) });
  });

  root.addEventListener("keydown", (event) => {
    const key = event.key;
    let handled = true;
    if ((event.ctrlKey || event.metaKey) && key.toLowerCase() === "z") send({ type: event.shiftKey ? "redo" : "undo" });
    else if ((event.ctrlKey || event.metaKey) && key.toLowerCase() === "y") send({ type: "redo" });
    else if (key === "Delete" || key === "Backspace") send({ type: "delete" });
    else if (key === "c" || key === "C") send({ type: "corner" });
    else if (key.startsWith("Arrow") && (model.get("selection") ?? []).length) {
      const step = vp.len(event.shiftKey ? 10 : 1);
      const [dx, dy] = { ArrowLeft: [-step, 0], ArrowRight: [step, 0], ArrowUp: [0, -step], ArrowDown: [0, step] }[key];
      seq += 1;
      send({ type: "transform", matrix: [1, 0, 0, 1, dx, dy], seq, gesture: ++gestureId, final: true });
    } else handled = false;
    if (handled) { event.preventDefault(); event.stopPropagation(); }
  });

  // ---------------------------------------------------------------- kernel -> page
  // a drawn answer to message `ackSeq`: latency record (debug) and flow control
  function answered(ackSeq, tArrive) {
    if (ackSeq > 0 && moveTimes.has(ackSeq)) {
      const times = moveTimes.get(ackSeq), t0 = times.move, tDom = performance.now();
      for (const key of moveTimes.keys()) if (key <= ackSeq) moveTimes.delete(key);
      requestAnimationFrame(() => {
        latencyLog().push({ seq: ackSeq, dom: tDom - t0, frame: performance.now() - t0, wait: times.sent - t0, kernel: tArrive - times.sent, draw: tDom - tArrive });
        root.dataset.lastDrawnSeq = String(ackSeq);
      });
    }
    acknowledge(ackSeq);
  }
  function onGeometry() {
    const tArrive = performance.now();
    const ackSeq = decode();
    drawCurves();
    drawKnots();
    showStatus();
    answered(ackSeq, tArrive);
  }
  // the moves of a gesture: only the changed contours' pieces, in a custom message
  function onLive(msg, buffers) {
    const tArrive = performance.now();
    (msg.contours ?? []).forEach((entry, i) => {
      const cached = cache[entry.index];
      if (!cached || !buffers[i]) return;
      Object.assign(cached, { revision: entry.revision, bez: floats(buffers[i]), deviation: null, path: null });
    });
    drawCurves();
    drawKnots();
    answered(msg.seq ?? -1, tArrive);
  }
  const handlers = [];
  const on = (event, fn) => { model.on(event, fn); handlers.push([event, fn]); };
  on("change:geometry", onGeometry);
  on("change:view", () => { vp.setView(model.get("view")); drawAll(); });
  const resize = () => {
    for (const node of [svg, bg]) { node.setAttribute("width", model.get("width")); node.setAttribute("height", model.get("height")); }
    vp.width = model.get("width");
    vp.height = model.get("height");
    vp.setView(model.get("view"));
    drawAll();
  };
  on("change:width", resize);
  on("change:height", resize);
  on("change:selection", () => { drawKnots(); showStatus(); });
  on("change:corners", drawKnots);
  for (const name of ["status_message", "status_level", "max_deviation", "can_undo", "can_redo", "point_tension", "interval_weights"]) on(`change:${name}`, showStatus);
  for (const name of ["show_fill", "show_deviation"]) on(`change:${name}`, () => { overlays.forEach((o, i) => o.set(model.get(["show_image", "show_fill", "show_deviation"][i]))); drawCurves(); });
  on("change:show_image", drawImage);
  on("change:image", () => { if (image.dataset.url) URL.revokeObjectURL(image.dataset.url); delete image.dataset.url; drawImage(); });
  const pings = new Map();
  let pingId = 0;
  on("msg:custom", (msg, buffers) => {
    if (msg && msg.type === "live") { onLive(msg, buffers ?? []); return; }
    if (msg && msg.type === "pong" && pings.has(msg.id)) { pings.get(msg.id)(msg.kernel_ms); pings.delete(msg.id); return; }
    if (msg && msg.type === "drag_ack") { acknowledge(msg.seq); if (!msg.ok) { live = null; drawKnots(); } }
  });

  // instrumentation for tests and benchmarks (client coordinates)
  root.__splinecraft = {
    screenKnot(k, i) {
      if (!cache[k] || !(i >= 0 && i < knotCount(k))) return null;
      const [x, y] = knotXY(k, i), r = svg.getBoundingClientRect();
      return [r.left + vp.sx(x), r.top + vp.sy(y)];
    },
    screenOf(x, y) { const r = svg.getBoundingClientRect(); return [r.left + vp.sx(x), r.top + vp.sy(y)]; },
    screenHandle(name) {
      const spot = handles(selectionBox())[name], r = svg.getBoundingClientRect();
      return spot ? [r.left + spot[0], r.top + spot[1]] : null;
    },
    dataOf(clientX, clientY) { const r = svg.getBoundingClientRect(); return [vp.dx(clientX - r.left), vp.dy(clientY - r.top)]; },
    ping() {
      return new Promise((resolve) => {
        const id = ++pingId, t0 = performance.now(), wall0 = performance.timeOrigin + t0;
        pings.set(id, (kernelMs) => { const t1 = performance.now(); resolve({ total: t1 - t0, up: kernelMs - wall0, down: performance.timeOrigin + t1 - kernelMs }); });
        send({ type: "ping", id });
      });
    },
  };

  decode();
  drawAll();
  root.dataset.ready = "1";
  return () => {
    if (rafId) cancelAnimationFrame(rafId);
    if (image.dataset.url) URL.revokeObjectURL(image.dataset.url);
    for (const [event, fn] of handlers) model.off(event, fn);
  };
}

export default { render };
