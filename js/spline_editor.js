// SplineEditor front end (anywidget ES module). The kernel computes every curve and overlay; this
// module only draws them (SVG) and turns pointer/keyboard input into messages and trait updates.
//
// Kernel -> page: synced traits (points, point_tension, interval_weights, alpha, beta, form, ...) and
// `geometry`, a dict of little-endian float32 byte buffers (Bézier pieces, knots, class polygon,
// tangent handles, curvature comb) plus a little JSON.
// Page -> kernel: trait updates (sliders, dropdowns, selection, view) and custom messages
// {type: "drag" | "add" | "delete" | "select_at" | "undo" | "redo" | "fit"}.
// Drags are throttled to animation frames with at most one drag message in flight; the final
// position is always sent on pointerup.
import { h, s, floats, Viewport, bezierPath, polylinePath, segmentsPath, markersPath, sliderRow, selectBox, checkRow, swatch, isolateKeys, formatNumber } from "./common.js";

const COLORS = {
  curve: "#1565c0",
  polygon: "#90a4ae",
  point: "#263238",
  selected: "#e53935",
  knots: "#0d47a1",
  classPolygon: "#ef6c00",
  tangents: "#2e7d32",
  comb: "#8e24aa",
  highlight: "#ffd54f",
};

const HIT_RADIUS = 9; // px: how close a pointer must be to grab a point

function render({ model, el }) {
  const width = () => model.get("width");
  const height = () => model.get("height");
  const vp = new Viewport(width(), height(), model.get("view"));
  let geometry = decodeGeometry(model.get("geometry"));
  let disposed = false;

  // ---------------------------------------------------------------- DOM
  const root = h("div", { class: "sc-widget sc-editor", tabindex: 0, "data-testid": "spline-editor" });
  isolateKeys(root);
  el.append(root);

  const formSel = selectBox(model.get("options").forms ?? [], model.get("form"), (v) => setTrait("form", v), "form");
  const presetSel = selectBox(model.get("options").presets ?? [], model.get("preset"), (v) => setTrait("preset", v), "preset");
  const endSel = selectBox([], model.get("end_condition"), (v) => setTrait("end_condition", v), "end-condition");
  const knotsSel = selectBox(model.get("options").knots ?? [], model.get("knots"), (v) => setTrait("knots", v), "knots");
  const closedBox = checkRow("closed", model.get("closed"), (v) => setTrait("closed", v), { testid: "closed", title: "Closed (periodic) curve" });
  const button = (text, title, testid, onClick) =>
    h("button", { class: "sc-button", title, "data-testid": testid, onclick: (e) => { e.preventDefault(); onClick(); root.focus({ preventScroll: true }); } }, text);
  const undoBtn = button("↶", "Undo (Ctrl+Z)", "undo", () => model.send({ type: "undo" }));
  const redoBtn = button("↷", "Redo (Ctrl+Shift+Z / Ctrl+Y)", "redo", () => model.send({ type: "redo" }));
  const fitBtn = button("Fit", "Fit the drawing to the view (F)", "fit", () => model.send({ type: "fit" }));
  const deleteBtn = button("Delete", "Delete the selected point (Delete, or right-click a point)", "delete", () => {
    const i = model.get("selected");
    if (i >= 0) model.send({ type: "delete", index: i });
  });

  const field = (label, control) => h("label", { class: "sc-field" }, h("span", { class: "sc-field-label" }, label), control);
  const endField = field("ends", endSel.select);
  const endLabel = endField.querySelector(".sc-field-label");
  const knotsField = field("knots", knotsSel.select);
  const presetField = field("class", presetSel.select);
  const toolbar = h("div", { class: "sc-toolbar" },
    field("form", formSel.select), presetField, endField, knotsField, closedBox.row);
  const actions = h("div", { class: "sc-actions" }, undoBtn, redoBtn, fitBtn, deleteBtn);

  // canvas layers, bottom to top
  const svg = s("svg", { class: "sc-canvas", width: width(), height: height(), "data-testid": "canvas" });
  const layer = (attrs) => { const p = s("path", { fill: "none", ...attrs }); svg.append(p); return p; };
  const bg = s("rect", { x: 0, y: 0, width: width(), height: height(), fill: "#fcfcfd", class: "sc-bg" });
  svg.append(bg);
  const gridPath = layer({ stroke: "#eef1f4", "stroke-width": 1 });
  const highlightCurve = layer({ stroke: COLORS.highlight, "stroke-width": 9, "stroke-linecap": "round", opacity: 0.75, "data-testid": "highlight" });
  const highlightLeg = layer({ stroke: COLORS.highlight, "stroke-width": 7, "stroke-linecap": "round", opacity: 0.75 });
  const polygonPath = layer({ stroke: COLORS.polygon, "stroke-width": 1.2, "stroke-dasharray": "5 4", "data-testid": "control-polygon" });
  const combTeeth = layer({ stroke: COLORS.comb, "stroke-width": 0.8, opacity: 0.45, "data-testid": "comb-teeth" });
  const combEnvelope = layer({ stroke: COLORS.comb, "stroke-width": 1.4, opacity: 0.9, "data-testid": "comb-envelope" });
  const classPolygon = layer({ stroke: COLORS.classPolygon, "stroke-width": 1.1, "stroke-dasharray": "3 3", opacity: 0.9, "data-testid": "class-polygon" });
  const tangentPath = layer({ stroke: COLORS.tangents, "stroke-width": 1.6, "data-testid": "tangents" });
  const tangentEnds = layer({ fill: COLORS.tangents, stroke: "none" });
  const curveHit = layer({ stroke: "transparent", "stroke-width": 14, "pointer-events": "stroke", class: "sc-curve-hit" });
  const curvePath = layer({ stroke: COLORS.curve, "stroke-width": 2.4, "stroke-linejoin": "round", "data-testid": "curve", "pointer-events": "none" });
  const vwMarkers = layer({ fill: COLORS.classPolygon, stroke: "#fff", "stroke-width": 0.8, "data-testid": "vw-points", "pointer-events": "none" });
  const knotMarkers = layer({ fill: COLORS.knots, stroke: "#fff", "stroke-width": 0.8, "data-testid": "knots", "pointer-events": "none" });
  const pointMarkers = layer({ fill: "#ffffff", stroke: COLORS.point, "stroke-width": 1.6, "data-testid": "points", "pointer-events": "none" });
  const selectedMarker = layer({ fill: COLORS.selected, stroke: "#fff", "stroke-width": 1.5, "data-testid": "selected-point", "pointer-events": "none" });
  const labels = s("g", { class: "sc-labels", "pointer-events": "none" });
  svg.append(labels);
  const overlayNote = s("text", { x: 10, y: 18, class: "sc-canvas-note" });
  svg.append(overlayNote);

  // side panel
  const opts = () => model.get("options");
  const range = (name) => (opts().ranges ?? {})[name] ?? [0, 1, 0.01];
  const mkSlider = (name, label, title, onInput, scale = "linear") => {
    const [lo, hi, st] = range(name);
    return sliderRow({ label, title, min: lo, max: hi, step: st, value: NaN, onInput, testid: name, scale });
  };
  const globalTension = mkSlider("point_tension", "v", "Point tension v for every point (§2.2): v > 0 tightens the curve towards the polygon", (v, final) => setAll("point_tension", v, final));
  const globalWeight = mkSlider("interval_weights", "ω", "Interval weight ω for every interval (§2.2): penalises bending", (v, final) => setAll("interval_weights", v, final), "log");
  const alphaSlider = mkSlider("alpha", "α", "Class parameter α", (v, final) => setTrait("alpha", v, final));
  const betaSlider = mkSlider("beta", "β", "Class parameter β", (v, final) => setTrait("beta", v, final));
  const pointTension = mkSlider("point_tension", "vᵢ", "Point tension of the selected point", (v, final) => setOne("point_tension", model.get("selected"), v, final));
  const intervalWeight = mkSlider("interval_weights", "ωᵢ", "Interval weight of the selected interval", (v, final) => setOne("interval_weights", model.get("selected_interval"), v, final), "log");
  const combScale = mkSlider("comb_scale", "size", "Length of the comb teeth (relative)", (v, final) => setTrait("comb_scale", v, final), "log");
  const selectionTitle = h("div", { class: "sc-selection-title", "data-testid": "selection-title" });

  const overlayDefs = [
    ["show_control_polygon", "control polygon", swatch({ color: COLORS.polygon, dash: "5 4", marker: "circle" })],
    ["show_knots", "knots Fᵢ", swatch({ color: COLORS.knots, dash: "none", marker: "dot" })],
    ["show_bezier_points", "class points V, W", swatch({ color: COLORS.classPolygon, dash: "3 3", marker: "square" })],
    ["show_tangents", "tangents (Bézier handles)", swatch({ color: COLORS.tangents })],
    ["show_comb", "curvature comb", swatch({ color: COLORS.comb, dash: "none", marker: "comb" })],
  ];
  const overlayBoxes = {};
  const overlayRows = overlayDefs.map(([name, label, sw]) => {
    const row = checkRow(label, model.get(name), (v) => setTrait(name, v), { swatch: sw, testid: name });
    overlayBoxes[name] = row;
    return row.row;
  });
  const curveLegend = h("div", { class: "sc-check sc-legend-only" }, swatch({ color: COLORS.curve, width: 2.5 }), h("span", {}, "curve"));

  const section = (title, ...children) => h("div", { class: "sc-section" }, h("div", { class: "sc-section-title" }, title), ...children);
  const tensionSection = section("Tension (all)", globalTension.row, globalWeight.row);
  const classSection = section("Class parameters", alphaSlider.row, betaSlider.row);
  const selectionSection = section("Selection", selectionTitle, pointTension.row, intervalWeight.row);
  const explanation = h("div", { class: "sc-explanation", "data-testid": "explanation" });
  const side = h("div", { class: "sc-side" },
    tensionSection, classSection, selectionSection,
    section("Show", curveLegend, ...overlayRows, combScale.row));

  const status = h("div", { class: "sc-status", "data-testid": "status" });
  const summary = h("div", { class: "sc-summary", "data-testid": "summary" });
  const body = h("div", { class: "sc-body" }, h("div", { class: "sc-canvas-wrap" }, svg, actions), side);
  root.append(toolbar, body, explanation, h("div", { class: "sc-footer" }, status, summary));
  side.style.height = `${height()}px`;

  // ---------------------------------------------------------------- model helpers
  function setTrait(name, value, final = true) {
    model.set(name, value);
    model.save_changes();
  }
  function setAll(name, value, final) {
    const n = (model.get(name) ?? []).length;
    setTrait(name, new Array(n).fill(value), final);
  }
  function setOne(name, index, value, final) {
    const list = [...(model.get(name) ?? [])];
    if (index < 0 || index >= list.length) return;
    list[index] = value;
    setTrait(name, list, final);
  }

  // ---------------------------------------------------------------- drawing
  let drag = null; // {index, x, y, pointerId, moved}
  let pendingRelease = null; // a finished drag whose final position the kernel has not answered yet
  let pan = null;
  let localView = null; // view while panning (not yet sent)

  // the kernel's points: float64 bytes x0, y0, x1, y1, ... (decoded once per change)
  let kernelPoints = decodePoints(model.get("points"));
  const count = () => kernelPoints.length / 2;
  const pointAt = (i) => [kernelPoints[2 * i], kernelPoints[2 * i + 1]];
  /** Points to draw: the kernel's, with a point being dragged shown where the pointer is. */
  function points() {
    const live = drag ?? pendingRelease;
    if (live && live.moved && live.index < count()) {
      const copy = kernelPoints.slice();
      copy[2 * live.index] = live.x;
      copy[2 * live.index + 1] = live.y;
      return copy;
    }
    return kernelPoints;
  }

  function drawGrid() {
    const [x0, y0, x1, y1] = vp.visible();
    const span = Math.max(x1 - x0, y1 - y0);
    const stepRaw = span / 12;
    const mag = 10 ** Math.floor(Math.log10(stepRaw));
    const step = [1, 2, 5, 10].map((m) => m * mag).find((m) => m >= stepRaw) ?? 10 * mag;
    const parts = [];
    for (let x = Math.ceil(x0 / step) * step; x <= x1; x += step) parts.push(`M${vp.sx(x).toFixed(1)},0V${height()}`);
    for (let y = Math.ceil(y0 / step) * step; y <= y1; y += step) parts.push(`M0,${vp.sy(y).toFixed(1)}H${width()}`);
    gridPath.setAttribute("d", parts.join(""));
  }

  function drawGeometry() {
    const g = geometry;
    const closed = !!g.closed;
    const d = bezierPath(vp, g.bezier, closed);
    curvePath.setAttribute("d", d);
    curveHit.setAttribute("d", d);
    highlightCurve.setAttribute("d", bezierPath(vp, g.highlight, false));
    highlightLeg.setAttribute("d", polylinePath(vp, g.highlight_leg, false));
    knotMarkers.setAttribute("d", model.get("show_knots") ? markersPath(vp, g.knots, 3.2) : "");
    const showVW = model.get("show_bezier_points");
    classPolygon.setAttribute("d", showVW ? polylinePath(vp, g.class_polygon, false) : "");
    vwMarkers.setAttribute("d", showVW ? markersPath(vp, g.vw, 3, "square") : "");
    const showT = model.get("show_tangents");
    tangentPath.setAttribute("d", showT ? segmentsPath(vp, g.tangents) : "");
    tangentEnds.setAttribute("d", showT ? markersPath(vp, tangentTips(g.tangents), 2.2) : "");
    const showC = model.get("show_comb");
    combTeeth.setAttribute("d", showC ? segmentsPath(vp, g.comb_teeth) : "");
    combEnvelope.setAttribute("d", showC ? polylinePath(vp, g.comb_envelope, false) : "");
    labels.replaceChildren(...(g.labels ?? []).filter((lab) => lab.kind !== "joint" || showC).map((lab) =>
      s("text", { x: vp.sx(lab.x) + (lab.dx ?? 8), y: vp.sy(lab.y) + (lab.dy ?? -8), class: `sc-label sc-label-${lab.kind ?? "point"}` }, document.createTextNode(lab.text))));
    curvePath.dataset.revision = String(g.revision ?? 0);
    curvePath.dataset.seq = String(g.seq ?? -1);
  }

  function tangentTips(seg) {
    // the far end of each handle gets a dot
    const n = Math.floor(seg.length / 4), out = new Float32Array(2 * n);
    for (let i = 0; i < n; i++) { out[2 * i] = seg[4 * i + 2]; out[2 * i + 1] = seg[4 * i + 3]; }
    return out;
  }

  function drawPoints() {
    const flat = points(), n = flat.length / 2;
    const closed = model.get("closed") && model.get("form") !== "segment";
    polygonPath.setAttribute("d", model.get("show_control_polygon") ? polylinePath(vp, flat, closed) : "");
    pointMarkers.setAttribute("d", markersPath(vp, flat, n > 400 ? 3 : 4.5));
    const sel = model.get("selected");
    selectedMarker.setAttribute("d", sel >= 0 && sel < n ? markersPath(vp, flat.subarray(2 * sel, 2 * sel + 2), 6) : "");
    root.dataset.npoints = String(n);
  }

  function drawAll() {
    drawGrid();
    drawGeometry();
    drawPoints();
  }

  // ---------------------------------------------------------------- controls sync
  function syncControls() {
    const o = opts();
    formSel.fill(o.forms ?? []);
    formSel.set(model.get("form"));
    presetSel.set(model.get("preset"));
    const endOptions = (o.end_conditions ?? {})[model.get("form")] ?? [];
    endSel.fill(endOptions);
    endSel.set(model.get("end_condition"));
    endField.style.display = endOptions.length ? "" : "none";
    endLabel.textContent = (o.end_labels ?? {})[model.get("form")] || "ends";
    knotsSel.set(model.get("knots"));
    const uses = (o.uses ?? {})[model.get("form")] ?? {};
    knotsField.style.display = uses.knots ? "" : "none";
    closedBox.set(model.get("closed"));
    closedBox.row.style.display = uses.closed === false ? "none" : "";
    undoBtn.disabled = !model.get("can_undo");
    redoBtn.disabled = !model.get("can_redo");
    const sel = model.get("selected"), selInt = model.get("selected_interval");
    deleteBtn.disabled = !(sel >= 0) || uses.add_delete === false;

    for (const [slider, name] of [[globalTension, "point_tension"], [globalWeight, "interval_weights"], [alphaSlider, "alpha"], [betaSlider, "beta"], [pointTension, "point_tension"], [intervalWeight, "interval_weights"], [combScale, "comb_scale"]]) {
      const [lo, hi, st] = (name === "alpha" || name === "beta") && uses.alpha_range ? uses.alpha_range : range(name);
      slider.configure(slider === globalWeight || slider === intervalWeight || slider === combScale ? Math.max(lo, 1e-6) : lo, hi, st);
    }
    const v = model.get("point_tension") ?? [], w = model.get("interval_weights") ?? [];
    globalTension.set(allEqual(v) ? common(v) : null, common(v));
    globalWeight.set(allEqual(w) ? common(w) : null, common(w));
    tensionSection.style.display = uses.tension ? "" : "none";
    alphaSlider.set(model.get("alpha"));
    betaSlider.set(model.get("beta"));
    alphaSlider.setLabel(uses.alpha_label ?? "α");
    betaSlider.setLabel(uses.beta_label ?? "β");
    classSection.style.display = uses.alpha === false ? "none" : "";
    presetField.style.display = uses.alpha === false || uses.preset === false ? "none" : "";
    const free = model.get("preset") === "free" || uses.preset === false;
    alphaSlider.setDisabled(!free);
    betaSlider.setDisabled(!free);

    pointTension.row.style.display = uses.tension && sel >= 0 && sel < v.length ? "" : "none";
    if (sel >= 0 && sel < v.length) pointTension.set(v[sel]);
    intervalWeight.row.style.display = uses.tension && selInt >= 0 && selInt < w.length ? "" : "none";
    if (selInt >= 0 && selInt < w.length) intervalWeight.set(w[selInt]);
    const parts = [];
    if (sel >= 0) parts.push(`point ${sel}`);
    if (selInt >= 0) parts.push(`interval ${selInt}`);
    selectionTitle.textContent = parts.length ? parts.join(" · ") : "Click a point or the curve to select it.";
    selectionSection.classList.toggle("sc-muted", !parts.length);

    for (const [name, row] of Object.entries(overlayBoxes)) row.set(model.get(name));
    overlayBoxes.show_bezier_points.row.style.display = uses.vw === false ? "none" : "";
    overlayBoxes.show_bezier_points.row.querySelector("span").textContent = uses.vw_label ?? "class points V, W";
    combScale.set(model.get("comb_scale"));
    explanation.innerHTML = model.get("explanation");
    showStatus();
  }

  function showStatus() {
    const level = model.get("status_level") || "info";
    status.textContent = model.get("status_message") || "";
    status.className = `sc-status sc-status-${level}`;
    root.dataset.statusLevel = level;
    const g = geometry;
    summary.textContent = `${count()} points · ${Math.floor(g.bezier.length / 8)} pieces`;
  }

  const allEqual = (list) => list.length === 0 || list.every((x) => x === list[0]);
  const common = (list) => {
    if (!list.length) return NaN;
    if (allEqual(list)) return list[0];
    const sorted = [...list].sort((a, b) => a - b);
    return sorted[Math.floor(sorted.length / 2)];
  };

  // ---------------------------------------------------------------- pointer input
  const local = (event) => {
    const rect = svg.getBoundingClientRect();
    return [event.clientX - rect.left, event.clientY - rect.top];
  };
  function hitPoint(px, py) {
    const pts = kernelPoints, n = count();
    let best = -1, bestD = HIT_RADIUS * HIT_RADIUS;
    for (let i = 0; i < n; i++) {
      const dx = vp.sx(pts[2 * i]) - px, dy = vp.sy(pts[2 * i + 1]) - py;
      const d2 = dx * dx + dy * dy;
      if (d2 <= bestD) { bestD = d2; best = i; }
    }
    return best;
  }

  // Drag flow control: at most one "drag" message in flight; newer positions wait for the ack and
  // are coalesced, so the kernel never falls behind and the latest position always wins.
  let seq = 0, gesture = 0, inFlight = null, pendingSend = false, rafId = 0;
  const moveTimes = new Map(); // seq -> performance.now() of the pointermove it carries
  // instrumentation: window.__splinecraft.dragLatencies gets one record per drawn drag round trip
  const latencyLog = () => {
    window.__splinecraft = window.__splinecraft ?? {};
    window.__splinecraft.dragLatencies = window.__splinecraft.dragLatencies ?? [];
    return window.__splinecraft.dragLatencies;
  };

  function sendDrag(final) {
    seq += 1;
    if (model.get("debug")) moveTimes.set(seq, { move: drag.tMove, sent: performance.now() });
    inFlight = { seq, t: performance.now() };
    model.send({ type: "drag", index: drag.index, x: drag.x, y: drag.y, seq, gesture, final });
  }
  function frame() {
    rafId = 0;
    if (!drag || !pendingSend) return;
    if (inFlight && performance.now() - inFlight.t < 1000) return; // wait for the ack (1 s safety)
    pendingSend = false;
    sendDrag(false);
  }
  function acknowledge(ackSeq) {
    if (inFlight && ackSeq >= inFlight.seq) inFlight = null;
    if (pendingRelease && ackSeq >= pendingRelease.finalSeq) {
      pendingRelease = null;
      drawPoints();
    }
    if (drag && pendingSend && !rafId) rafId = requestAnimationFrame(frame);
  }

  svg.addEventListener("pointerdown", (event) => {
    if (event.button !== 0) return;
    root.focus({ preventScroll: true });
    const [px, py] = local(event);
    const index = hitPoint(px, py);
    if (index >= 0) {
      event.preventDefault();
      svg.setPointerCapture(event.pointerId);
      gesture += 1;
      const p = pointAt(index);
      drag = { index, x: p[0], y: p[1], pointerId: event.pointerId, moved: false, tMove: performance.now(), ox: vp.sx(p[0]) - px, oy: vp.sy(p[1]) - py };
      if (model.get("selected") !== index) setTrait("selected", index);
      drawPoints();
      return;
    }
    if (event.target === curveHit) return; // click on the curve: handled on click
    svg.setPointerCapture(event.pointerId);
    pan = { x: px, y: py, pointerId: event.pointerId, moved: false, view: vp.visible() };
  });

  svg.addEventListener("pointermove", (event) => {
    const [px, py] = local(event);
    if (drag && event.pointerId === drag.pointerId) {
      drag.x = vp.dx(px + drag.ox);
      drag.y = vp.dy(py + drag.oy);
      drag.moved = true;
      drag.tMove = performance.now();
      pendingSend = true;
      drawPoints();
      if (!rafId) rafId = requestAnimationFrame(frame);
      return;
    }
    if (pan && event.pointerId === pan.pointerId) {
      const dx = px - pan.x, dy = py - pan.y;
      if (!pan.moved && Math.hypot(dx, dy) < 3) return;
      pan.moved = true;
      vp.setView(pan.view);
      localView = vp.panned(dx, dy);
      vp.setView(localView);
      drawAll();
      return;
    }
    svg.style.cursor = hitPoint(px, py) >= 0 ? "grab" : "";
  });

  function endPointer(event) {
    if (drag && event.pointerId === drag.pointerId) {
      const finished = drag;
      if (finished.moved) {
        pendingSend = false;
        sendDrag(true); // the final position is never lost
        finished.finalSeq = seq;
        pendingRelease = finished; // keep showing it until the kernel answers
      }
      drag = null;
      drawPoints();
    }
    if (pan && event.pointerId === pan.pointerId) {
      if (pan.moved && localView) setTrait("view", localView);
      else if (!pan.moved && event.type === "pointerup") {
        if (model.get("selected") >= 0 || model.get("selected_interval") >= 0) {
          model.set("selected", -1);
          model.set("selected_interval", -1);
          model.save_changes();
        }
      }
      pan = null;
      localView = null;
    }
  }
  svg.addEventListener("pointerup", endPointer);
  svg.addEventListener("pointercancel", endPointer);

  curveHit.addEventListener("click", (event) => {
    const [px, py] = local(event);
    model.send({ type: "select_at", x: vp.dx(px), y: vp.dy(py), tol: vp.len(HIT_RADIUS) });
  });

  function addAt(px, py) {
    if (hitPoint(px, py) >= 0) return;
    model.send({ type: "add", x: vp.dx(px), y: vp.dy(py), tol: vp.len(HIT_RADIUS) });
  }
  svg.addEventListener("dblclick", (event) => {
    event.preventDefault();
    addAt(...local(event));
  });
  // touch: a double tap adds a point (browsers do not reliably send dblclick for touch);
  // a long press opens no menu on points but deletes them (contextmenu below)
  let lastTap = null;
  svg.addEventListener("pointerup", (event) => {
    if (event.pointerType !== "touch") return;
    const [px, py] = local(event), now = performance.now();
    if (lastTap && now - lastTap.t < 350 && Math.hypot(px - lastTap.x, py - lastTap.y) < 24) {
      lastTap = null;
      addAt(px, py);
    } else {
      lastTap = { t: now, x: px, y: py };
    }
  });

  svg.addEventListener("contextmenu", (event) => {
    const [px, py] = local(event);
    const index = hitPoint(px, py);
    if (index < 0) return;
    event.preventDefault();
    event.stopPropagation();
    model.send({ type: "delete", index });
  });

  svg.addEventListener("wheel", (event) => {
    if (!(event.ctrlKey || event.metaKey || event.altKey)) return; // plain wheel scrolls the notebook
    event.preventDefault();
    const [px, py] = local(event);
    const factor = Math.exp(-event.deltaY * 0.002);
    const view = vp.zoomed(factor, px, py);
    vp.setView(view);
    drawAll();
    clearTimeout(wheelTimer);
    wheelTimer = setTimeout(() => setTrait("view", vp.visible()), 150);
  }, { passive: false });
  let wheelTimer = 0;

  root.addEventListener("keydown", (event) => {
    const target = event.target;
    if (target instanceof HTMLInputElement || target instanceof HTMLSelectElement) return;
    const key = event.key, mod = event.ctrlKey || event.metaKey;
    let handled = true;
    if ((key === "Delete" || key === "Backspace") && model.get("selected") >= 0) {
      model.send({ type: "delete", index: model.get("selected") });
    } else if (mod && (key === "z" || key === "Z") && !event.shiftKey) {
      model.send({ type: "undo" });
    } else if (mod && ((key === "z" || key === "Z") && event.shiftKey || key === "y")) {
      model.send({ type: "redo" });
    } else if (key === "Escape") {
      model.set("selected", -1); model.set("selected_interval", -1); model.save_changes();
    } else if (key === "f" && !mod) {
      model.send({ type: "fit" });
    } else {
      handled = false;
    }
    if (handled) { event.preventDefault(); event.stopPropagation(); }
  });

  // ---------------------------------------------------------------- kernel -> page
  function onGeometry() {
    const tArrive = performance.now();
    geometry = decodeGeometry(model.get("geometry"));
    kernelPoints = decodePoints(model.get("points")); // same update; its change event may come later
    drawGeometry();
    drawPoints();
    showStatus();
    const ackSeq = geometry.seq ?? -1;
    if (ackSeq > 0 && moveTimes.has(ackSeq)) {
      const times = moveTimes.get(ackSeq), t0 = times.move;
      const tDom = performance.now();
      for (const key of moveTimes.keys()) if (key <= ackSeq) moveTimes.delete(key);
      requestAnimationFrame(() => {
        const record = {
          seq: ackSeq, n: root.dataset.npoints | 0,
          dom: tDom - t0, frame: performance.now() - t0, // pointermove -> path in DOM / -> next frame
          wait: times.sent - t0, kernel: tArrive - times.sent, draw: tDom - tArrive, // the parts
        };
        latencyLog().push(record);
        root.dataset.lastDrawnSeq = String(ackSeq);
      });
    }
    acknowledge(ackSeq);
  }

  const handlers = [];
  const on = (event, fn) => { model.on(event, fn); handlers.push([event, fn]); };
  on("change:geometry", onGeometry);
  on("change:points", () => { kernelPoints = decodePoints(model.get("points")); drawPoints(); });
  on("change:view", () => { vp.setView(model.get("view")); drawAll(); });
  for (const name of ["form", "preset", "end_condition", "knots", "closed", "alpha", "beta", "point_tension", "interval_weights", "selected", "selected_interval", "can_undo", "can_redo", "explanation", "options", "comb_scale"]) {
    on(`change:${name}`, () => { syncControls(); if (name === "selected" || name === "closed") drawPoints(); });
  }
  for (const name of ["show_control_polygon", "show_knots", "show_bezier_points", "show_tangents", "show_comb"]) {
    on(`change:${name}`, () => { syncControls(); drawGeometry(); drawPoints(); });
  }
  on("change:status_message", showStatus);
  on("change:status_level", showStatus);
  const pings = new Map();
  let pingId = 0;
  const onMsg = (msg) => {
    if (msg && msg.type === "pong" && pings.has(msg.id)) {
      pings.get(msg.id)(msg.kernel_ms);
      pings.delete(msg.id);
      return;
    }
    if (msg && msg.type === "drag_ack") {
      acknowledge(msg.seq);
      if (!msg.ok) drawPoints();
    }
  };
  on("msg:custom", onMsg);
  on("change:width", resize);
  on("change:height", resize);
  function resize() {
    svg.setAttribute("width", width());
    svg.setAttribute("height", height());
    side.style.height = `${height()}px`;
    bg.setAttribute("width", width());
    bg.setAttribute("height", height());
    vp.width = width();
    vp.height = height();
    vp.setView(model.get("view"));
    drawAll();
  }

  // instrumentation for tests and benchmarks: screen position of point i, relative to the page
  root.__splinecraft = {
    screenPoint(i) {
      if (!(i >= 0 && i < count())) return null;
      const p = pointAt(i);
      const rect = svg.getBoundingClientRect();
      return [rect.left + vp.sx(p[0]), rect.top + vp.sy(p[1])];
    },
    screenOf(x, y) {
      const rect = svg.getBoundingClientRect();
      return [rect.left + vp.sx(x), rect.top + vp.sy(y)];
    },
    /**
     * Round trip of an empty message through the kernel (the transport floor): {total, up, down} in ms,
     * up/down split by the kernel's wall clock (same machine).
     */
    ping() {
      return new Promise((resolve) => {
        const id = ++pingId, t0 = performance.now(), wall0 = performance.timeOrigin + t0;
        pings.set(id, (kernelMs) => {
          const t1 = performance.now(), wall1 = performance.timeOrigin + t1;
          resolve({ total: t1 - t0, up: kernelMs - wall0, down: wall1 - kernelMs });
        });
        model.send({ type: "ping", id });
      });
    },
    dataOf(clientX, clientY) {
      const rect = svg.getBoundingClientRect();
      return [vp.dx(clientX - rect.left), vp.dy(clientY - rect.top)];
    },
  };

  syncControls();
  drawAll();
  root.dataset.ready = "1";

  return () => {
    disposed = true;
    if (rafId) cancelAnimationFrame(rafId);
    for (const [event, fn] of handlers) model.off(event, fn);
  };
}

function decodePoints(value) {
  if (Array.isArray(value)) return Float64Array.from(value.flat());
  return floats(value, "f8");
}

function decodeGeometry(g) {
  g = g ?? {};
  return {
    ...g,
    bezier: floats(g.bezier),
    knots: floats(g.knots),
    vw: floats(g.vw),
    class_polygon: floats(g.class_polygon),
    tangents: floats(g.tangents),
    comb_teeth: floats(g.comb_teeth),
    comb_envelope: floats(g.comb_envelope),
    highlight: floats(g.highlight),
    highlight_leg: floats(g.highlight_leg),
  };
}

export default { render };
