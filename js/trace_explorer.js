// TraceExplorer front end (anywidget ES module): draws the bitmap, its boundaries and corners, and the
// fitted spline of one knot-insertion iteration; forwards the controls to the kernel, which re-traces
// and sends the drawing back (float32 byte buffers in `base_geometry` and `snapshot_geometry`).
import { h, s, floats, Viewport, polylinePath, markersPath, sliderRow, selectBox, checkRow, swatch, isolateKeys, formatNumber } from "./common.js";
import { exportButtons } from "./export.js";

const LARGE = 1.35; // the "large" presentation size scales the canvas by this

const COLORS = {
  boundary: "#78909c",
  curve: "#1565c0",
  final: "#1565c0",
  knots: "#0d47a1",
  corners: "#d32f2f",
  accepted: "#2e7d32",
  rejected: "#ef6c00",
  removed: "#6a1b9a",
  worst: "#c2185b",
};

function render({ model, el }) {
  const width = () => Math.round(model.get("width") * (model.get("large") ? LARGE : 1));
  const height = () => Math.round(model.get("height") * (model.get("large") ? LARGE : 1));
  const vp = new Viewport(width(), height(), model.get("view"));
  let base = decodeBase(model.get("base_geometry"));
  let snap = decodeSnapshot(model.get("snapshot_geometry"));
  let imageUrl = null;

  const root = h("div", { class: "sc-widget sc-trace", tabindex: 0, "data-testid": "trace-explorer" });
  isolateKeys(root);
  el.append(root);

  // ---------------------------------------------------------------- toolbar
  const opts = () => model.get("options") ?? {};
  const setTrait = (name, value) => { model.set(name, value); model.save_changes(); };
  const cornerSel = selectBox(opts().corner_methods ?? [], model.get("corner_method"), (v) => setTrait("corner_method", v), "corner-method");
  const methodSel = selectBox(opts().knot_methods ?? [], model.get("method"), (v) => setTrait("method", v), "knot-method");
  const field = (label, control, title = "") => h("label", { class: "sc-field", title }, h("span", { class: "sc-field-label" }, label), control);
  const upload = h("input", { type: "file", accept: "image/*", class: "sc-upload", "data-testid": "upload", title: "Trace another image" });
  upload.addEventListener("change", async () => {
    const file = upload.files && upload.files[0];
    if (!file) return;
    const buffer = await file.arrayBuffer();
    model.send({ type: "upload", name: file.name, size: buffer.byteLength }, undefined, [buffer]); // (content, callbacks, buffers)
    upload.value = "";
  });
  const busy = h("span", { class: "sc-busy", "data-testid": "busy" });
  // how the bitmap is made from the image: threshold (global or local), invert, despeckle
  const thresholdSel = selectBox(opts().thresholds ?? [], model.get("threshold"), (v) => setTrait("threshold", v), "threshold");
  const invert = checkRow("invert", model.get("invert"), (v) => setTrait("invert", v), { testid: "invert", title: "Light pixels are ink" });
  const despeckle = h("input", { type: "number", class: "sc-number", min: 0, step: 1, "data-testid": "despeckle",
    title: "Remove ink specks and fill holes smaller than this many pixels (empty: automatic)" });
  despeckle.addEventListener("change", () => {
    const text = despeckle.value.trim();
    setTrait("despeckle", text === "" ? null : Math.max(0, Math.round(Number(text))));
  });
  despeckle.addEventListener("keydown", (event) => event.stopPropagation());
  const thresholdField = field("threshold", thresholdSel.select, "Gray level that separates ink from paper (docs/capture.md §9)");
  const large = checkRow("large", model.get("large"), (v) => setTrait("large", v), { testid: "large", title: "Presentation size: larger canvas, text and controls" });
  const toolbar = h("div", { class: "sc-toolbar" },
    field("corners", cornerSel.select, "Corner detector (thesis chapter 2)"),
    field("knot insertion", methodSel.select, "Knot-insertion algorithm (thesis section 4.3)"),
    h("span", { class: "sc-spacer" }), busy, field("image", upload), thresholdField, invert.row,
    field("despeckle", despeckle, "Speck size in pixels (empty: automatic)"), large.row);

  // ---------------------------------------------------------------- canvas
  const svg = s("svg", { class: "sc-canvas", width: width(), height: height(), "data-testid": "canvas" });
  const bg = s("rect", { x: 0, y: 0, width: width(), height: height(), fill: "#f4f6f8" });
  const image = s("image", { preserveAspectRatio: "none", style: "image-rendering: pixelated", opacity: 0.9, "data-testid": "bitmap" });
  const path = (attrs) => { const p = s("path", { fill: "none", ...attrs }); return p; };
  const boundaryPath = path({ stroke: COLORS.boundary, "stroke-width": 1, opacity: 0.8, "data-testid": "boundaries" });
  const finalPath = path({ stroke: COLORS.final, "stroke-width": 1, "stroke-dasharray": "4 3", opacity: 0.5, "data-testid": "final-curve" });
  const curvePath = path({ stroke: COLORS.curve, "stroke-width": 2, "stroke-linejoin": "round", "data-testid": "snapshot-curve" });
  const worstPath = path({ stroke: COLORS.worst, "stroke-width": 7, opacity: 0.35, "stroke-linecap": "round", "data-testid": "worst-piece" });
  const worstContour = path({ stroke: COLORS.worst, "stroke-width": 2.5, opacity: 0.8, "stroke-dasharray": "2 3", "data-testid": "worst-contour" });
  const knotPath = path({ fill: COLORS.knots, stroke: "#fff", "stroke-width": 0.8, "data-testid": "knots" });
  const cornerPath = path({ fill: COLORS.corners, stroke: "#fff", "stroke-width": 1, "data-testid": "corners" });
  const acceptedPath = path({ fill: COLORS.accepted, stroke: "#fff", "stroke-width": 1, "data-testid": "accepted" });
  const rejectedPath = path({ stroke: COLORS.rejected, "stroke-width": 2, "data-testid": "rejected" });
  const removedPath = path({ fill: "none", stroke: COLORS.removed, "stroke-width": 1.8, "data-testid": "removed" });
  svg.append(bg, image, boundaryPath, worstContour, finalPath, worstPath, curvePath, knotPath, cornerPath, acceptedPath, rejectedPath, removedPath);

  const legendItem = (sw, text, testid) => h("span", { class: "sc-legend-item", "data-testid": testid }, sw, text);
  const legend = h("div", { class: "sc-legend", "data-testid": "legend" },
    legendItem(swatch({ color: COLORS.boundary, width: 1 }), "boundary (crack outline)"),
    legendItem(swatch({ color: COLORS.corners, dash: "none", marker: "square" }), "corner"),
    legendItem(swatch({ color: COLORS.curve, width: 2 }), "spline at this iteration"),
    legendItem(swatch({ color: COLORS.knots, dash: "none", marker: "dot" }), "knot"),
    legendItem(swatch({ color: COLORS.accepted, dash: "none", marker: "dot" }), "candidate accepted"),
    legendItem(swatch({ color: COLORS.rejected, dash: "none", marker: "cross" }), "candidate rejected"),
    legendItem(swatch({ color: COLORS.removed, dash: "none", marker: "circle" }), "knot removed"),
    legendItem(swatch({ color: COLORS.worst, width: 6, opacity: 0.35 }), "piece with the largest error"),
    legendItem(swatch({ color: COLORS.worst, width: 2.5, dash: "2 3", opacity: 0.8 }), "its contour"),
    legendItem(swatch({ color: COLORS.final, dash: "4 3", opacity: 0.6 }), "final fit"));

  // ---------------------------------------------------------------- stepper
  const btn = (text, title, testid, onClick) => h("button", { class: "sc-button", title, "data-testid": testid, onclick: (e) => { e.preventDefault(); onClick(); } }, text);
  const firstBtn = btn("«", "First iteration: the corners only (Home)", "first", () => go(0));
  const backBtn = btn("‹ Back", "Step back one iteration (←)", "step-back", () => go(model.get("snapshot_index") - 1));
  const playBtn = btn("▶ Play", "Play / pause (Space)", "play", () => togglePlay());
  const fwdBtn = btn("Next ›", "Step forward one iteration (→)", "step-forward", () => go(model.get("snapshot_index") + 1));
  const lastBtn = btn("»", "Last iteration: the result (End)", "last", () => go(model.get("n_snapshots") - 1));
  const scrub = h("input", { type: "range", class: "sc-range", min: 0, max: 0, step: 1, value: 0, "data-testid": "scrub" });
  scrub.addEventListener("input", () => go(Number(scrub.value)));
  const iterLabel = h("span", { class: "sc-iteration", "data-testid": "iteration" });
  const stepper = h("div", { class: "sc-stepper" }, firstBtn, backBtn, playBtn, fwdBtn, lastBtn, scrub, iterLabel);

  // ---------------------------------------------------------------- side panel
  const section = (title, ...children) => h("div", { class: "sc-section" }, h("div", { class: "sc-section-title" }, title), ...children);
  const cornerParams = h("div", { "data-testid": "corner-params" });
  const ranges = () => opts().ranges ?? {};
  const eps = sliderRow({ label: "ε (px)", title: "Error threshold ε of knot insertion, px (thesis threshold 1, 2, 3)", min: 0.25, max: 6, step: 0.05, value: model.get("epsilon"), onInput: (v, final) => { if (final) setTrait("epsilon", v); }, testid: "epsilon" });
  const tau = sliderRow({ label: "τ (px)", title: "Distance constraint τ of Algorithms 4.2 and 4.3", min: 1, max: 60, step: 0.5, value: model.get("tau") ?? NaN, onInput: (v, final) => { if (final) setTrait("tau", v); }, testid: "tau" });
  const tauAuto = checkRow("τ automatic", model.get("tau") === null, (checked) => setTrait("tau", checked ? null : (tau.value > 0 ? tau.value : 8)), { testid: "tau-auto" });
  const seed = sliderRow({ label: "seed", title: "Seed of the randomised algorithms (4.1, 4.4-4.6)", min: 0, max: 99, step: 1, value: model.get("seed"), onInput: (v, final) => { if (final) setTrait("seed", Number.isFinite(v) ? Math.round(v) : v); }, testid: "seed" });
  const OVERLAYS = [
    ["show_image", "bitmap"], ["show_boundaries", "boundaries"], ["show_corners", "corners"],
    ["show_knots", "knots"], ["show_candidates", "candidates"], ["show_final", "final fit"],
  ];
  const overlays = OVERLAYS.map(([name, label]) => checkRow(label, model.get(name), (v) => setTrait(name, v), { testid: name }));
  const overlayRow = h("div", { class: "sc-overlay-grid" }, ...overlays.map((o) => o.row));
  const info = h("div", { class: "sc-explanation", "data-testid": "iteration-info" });
  const methodNote = h("div", { class: "sc-method-note", "data-testid": "method-note" });
  const stats = h("div", { class: "sc-stats", "data-testid": "stats" });
  // "This iteration" first: it is what you read while stepping (the panel scrolls below it)
  const side = h("div", { class: "sc-side" },
    section("This iteration", info),
    section("Corner detector", cornerParams),
    section("Knot insertion", methodNote, eps.row, tauAuto.row, tau.row, seed.row),
    section("Show", overlayRow));
  side.style.height = `${height()}px`;

  const status = h("div", { class: "sc-status", "data-testid": "status" });
  const summary = h("div", { class: "sc-summary" });
  const actions = h("div", { class: "sc-actions" }, btn("Fit", "Fit the image to the view", "fit", () => fitView()),
    btn("Edit outline", "Open the shown iteration in an OutlineEditor below", "edit-outline", () => model.send({ type: "edit" })),
    ...exportButtons(svg, "trace", root, btn));
  root.append(toolbar, h("div", { class: "sc-body" }, h("div", { class: "sc-canvas-wrap" }, svg, actions), side),
    stepper, legend, stats, h("div", { class: "sc-footer" }, status, summary));

  // ---------------------------------------------------------------- behaviour
  function go(index) {
    const n = model.get("n_snapshots");
    if (n <= 0) return;
    const clamped = Math.max(0, Math.min(n - 1, Math.round(index)));
    if (clamped !== model.get("snapshot_index")) setTrait("snapshot_index", clamped);
  }
  let playTimer = 0;
  function togglePlay() {
    if (playTimer) { stopPlay(); return; }
    if (model.get("snapshot_index") >= model.get("n_snapshots") - 1) go(0);
    playBtn.textContent = "❚❚ Pause";
    root.dataset.playing = "1";
    playTimer = setInterval(() => {
      const i = model.get("snapshot_index"), n = model.get("n_snapshots");
      if (i >= n - 1) stopPlay();
      else go(i + 1);
    }, Math.max(60, model.get("play_interval_ms")));
  }
  function stopPlay() {
    clearInterval(playTimer);
    playTimer = 0;
    playBtn.textContent = "▶ Play";
    root.dataset.playing = "0";
  }
  function fitView() {
    const [w, hgt] = model.get("image_size");
    setTrait("view", [0, 0, w, hgt]);
  }

  let pan = null;
  svg.addEventListener("pointerdown", (event) => {
    if (event.button !== 0) return;
    root.focus({ preventScroll: true });
    svg.setPointerCapture(event.pointerId);
    const rect = svg.getBoundingClientRect();
    pan = { x: event.clientX - rect.left, y: event.clientY - rect.top, id: event.pointerId, view: vp.visible(), moved: false };
  });
  svg.addEventListener("pointermove", (event) => {
    if (!pan || event.pointerId !== pan.id) return;
    const rect = svg.getBoundingClientRect();
    const dx = event.clientX - rect.left - pan.x, dy = event.clientY - rect.top - pan.y;
    if (!pan.moved && Math.hypot(dx, dy) < 3) return;
    pan.moved = true;
    vp.setView(pan.view);
    vp.setView(vp.panned(dx, dy));
    draw();
  });
  const endPan = (event) => {
    if (pan && event.pointerId === pan.id && pan.moved) setTrait("view", vp.visible());
    pan = null;
  };
  svg.addEventListener("pointerup", endPan);
  svg.addEventListener("pointercancel", endPan);
  let wheelTimer = 0;
  svg.addEventListener("wheel", (event) => {
    if (!(event.ctrlKey || event.metaKey || event.altKey)) return;
    event.preventDefault();
    const rect = svg.getBoundingClientRect();
    vp.setView(vp.zoomed(Math.exp(-event.deltaY * 0.002), event.clientX - rect.left, event.clientY - rect.top));
    draw();
    clearTimeout(wheelTimer);
    wheelTimer = setTimeout(() => setTrait("view", vp.visible()), 150);
  }, { passive: false });
  root.addEventListener("keydown", (event) => {
    if (event.target instanceof HTMLInputElement || event.target instanceof HTMLSelectElement) return;
    const i = model.get("snapshot_index");
    const actions = { ArrowLeft: () => go(i - 1), ArrowRight: () => go(i + 1), Home: () => go(0), End: () => go(model.get("n_snapshots") - 1), " ": togglePlay };
    if (actions[event.key]) { actions[event.key](); event.preventDefault(); event.stopPropagation(); }
  });

  // ---------------------------------------------------------------- drawing
  function drawImage() {
    const bytes = model.get("image_png");
    if (imageUrl) URL.revokeObjectURL(imageUrl);
    imageUrl = null;
    if (bytes && bytes.byteLength) {
      imageUrl = URL.createObjectURL(new Blob([bytes], { type: "image/png" }));
      image.setAttribute("href", imageUrl);
    } else {
      image.removeAttribute("href");
    }
  }

  function draw() {
    const [w, hgt] = model.get("image_size") ?? [1, 1];
    image.setAttribute("x", vp.sx(0));
    image.setAttribute("y", vp.sy(0));
    image.setAttribute("width", Math.max(0, vp.k * w));
    image.setAttribute("height", Math.max(0, vp.k * hgt));
    image.style.display = model.get("show_image") ? "" : "none";
    boundaryPath.setAttribute("d", model.get("show_boundaries") ? polylinePath(vp, base.boundaries) : "");
    const big = vp.k > 2 ? 4.5 : 3.5;
    cornerPath.setAttribute("d", model.get("show_corners") ? markersPath(vp, base.corners, big, "square") : "");
    finalPath.setAttribute("d", model.get("show_final") ? piecesPath(base.final) : "");
    curvePath.setAttribute("d", piecesPath(snap.bezier));
    worstPath.setAttribute("d", piecesPath(snap.worst));
    worstContour.setAttribute("d", polylinePath(vp, snap.worst_contour));
    knotPath.setAttribute("d", model.get("show_knots") ? markersPath(vp, snap.knots, 2.6) : "");
    const showCand = model.get("show_candidates");
    acceptedPath.setAttribute("d", showCand ? markersPath(vp, snap.accepted, 4.2) : "");
    rejectedPath.setAttribute("d", showCand ? markersPath(vp, snap.rejected, 3.8, "cross") : "");
    removedPath.setAttribute("d", showCand ? markersPath(vp, snap.removed, 5) : "");
    curvePath.dataset.iteration = String(model.get("snapshot_index"));
  }

  // Bézier pieces of several closed boundaries: start a new subpath wherever pieces do not join
  function piecesPath(bez) {
    const m = Math.floor(bez.length / 8);
    if (!m) return "";
    const parts = [];
    for (let i = 0; i < m; i++) {
      const o = 8 * i;
      const joined = i > 0 && bez[o] === bez[o - 2] && bez[o + 1] === bez[o - 1];
      if (!joined) parts.push(`M${vp.sx(bez[o]).toFixed(2)},${vp.sy(bez[o + 1]).toFixed(2)}`);
      parts.push(`C${vp.sx(bez[o + 2]).toFixed(2)},${vp.sy(bez[o + 3]).toFixed(2)} ${vp.sx(bez[o + 4]).toFixed(2)},${vp.sy(bez[o + 5]).toFixed(2)} ${vp.sx(bez[o + 6]).toFixed(2)},${vp.sy(bez[o + 7]).toFixed(2)}`);
    }
    return parts.join("");
  }

  function buildCornerParams() {
    const specs = (opts().corner_params ?? {})[model.get("corner_method")] ?? [];
    const values = model.get("corner_params") ?? {};
    cornerParams.replaceChildren();
    if (!specs.length) {
      cornerParams.append(h("div", { class: "sc-selection-title sc-muted" }, "This detector has no tuning parameters."));
      return;
    }
    for (const spec of specs) {
      const slider = sliderRow({
        label: spec.label, title: spec.title ?? spec.name, min: spec.min, max: spec.max, step: spec.step,
        value: values[spec.name] ?? spec.default, testid: `corner-${spec.name}`,
        onInput: (v, final) => {
          if (!final) return;
          const next = { ...(model.get("corner_params") ?? {}) };
          next[spec.name] = spec.integer && Number.isFinite(v) ? Math.round(v) : v;
          setTrait("corner_params", next);
        },
      });
      cornerParams.append(slider.row);
    }
  }

  function syncControls() {
    cornerSel.fill(opts().corner_methods ?? []);
    cornerSel.set(model.get("corner_method"));
    methodSel.fill(opts().knot_methods ?? []);
    methodSel.set(model.get("method"));
    methodNote.textContent = (opts().knot_descriptions ?? {})[model.get("method")] ?? "";
    eps.set(model.get("epsilon"));
    const tauValue = model.get("tau");
    tauAuto.set(tauValue === null);
    tau.setDisabled(tauValue === null);
    if (tauValue !== null) tau.set(tauValue);
    const usesTau = (opts().tau_methods ?? []).includes(model.get("method")); // Algorithms 4.2 and 4.3 only
    tauAuto.row.style.display = usesTau ? "" : "none";
    tau.row.style.display = usesTau ? "" : "none";
    seed.set(model.get("seed"));
    thresholdSel.fill(opts().thresholds ?? []);
    thresholdSel.set(model.get("threshold"));
    thresholdField.style.display = opts().image_is_mask ? "none" : "";
    invert.set(model.get("invert"));
    if (document.activeElement !== despeckle) despeckle.value = model.get("despeckle") ?? "";
    overlays.forEach((o, i) => o.set(model.get(OVERLAYS[i][0])));
    stats.innerHTML = model.get("stats_html");
    busy.textContent = model.get("busy") ? "tracing…" : "";
    root.dataset.busy = model.get("busy") ? "1" : "0";
    syncStepper();
    showStatus();
  }

  function syncStepper() {
    const n = model.get("n_snapshots"), i = model.get("snapshot_index");
    scrub.max = String(Math.max(0, n - 1));
    scrub.value = String(i);
    scrub.disabled = n <= 1;
    firstBtn.disabled = backBtn.disabled = i <= 0;
    lastBtn.disabled = fwdBtn.disabled = i >= n - 1;
    playBtn.disabled = n <= 1;
    const it = model.get("iteration_info") ?? {};
    iterLabel.textContent = n ? `iteration ${i} / ${n - 1}` : "no iterations";
    root.dataset.snapshotIndex = String(i);
    root.dataset.nSnapshots = String(n);
    const accepted = it.accepted ?? 0, rejected = it.rejected ?? 0;
    info.innerHTML = n
      ? `<p><b>${it.knots ?? "—"}</b> knots, <b>${it.pieces ?? "—"}</b> Bézier segments; max error <b>${formatNumber(it.max_error, 3)}</b> px ` +
        `(Hausdorff ${formatNumber(it.hausdorff, 3)} px; ε = ${formatNumber(model.get("epsilon"), 3)}).</p>` +
        `<p>Candidates here: <span style="color:${COLORS.accepted}">${accepted} accepted</span>, ` +
        `<span style="color:${COLORS.rejected}">${rejected} rejected</span>` +
        `${it.removed ? `, <span style="color:${COLORS.removed}">${it.removed} knots removed</span>` : ""}.` +
        `${it.note ? " " + it.note : ""}</p>`
      : "";
  }

  function showStatus() {
    const level = model.get("status_level") || "info";
    status.textContent = model.get("status_message") || "";
    status.className = `sc-status sc-status-${level}`;
    root.dataset.statusLevel = level;
    const [w, hgt] = model.get("image_size") ?? [0, 0];
    summary.textContent = `${w} × ${hgt} px`;
  }

  const handlers = [];
  const on = (event, fn) => { model.on(event, fn); handlers.push([event, fn]); };
  on("change:image_png", () => { drawImage(); draw(); });
  on("change:base_geometry", () => { base = decodeBase(model.get("base_geometry")); draw(); });
  on("change:snapshot_geometry", () => { snap = decodeSnapshot(model.get("snapshot_geometry")); draw(); syncStepper(); });
  on("change:view", () => { vp.setView(model.get("view")); draw(); });
  on("change:corner_method", () => { buildCornerParams(); syncControls(); });
  on("change:corner_params", buildCornerParams);
  on("change:options", () => { buildCornerParams(); syncControls(); });
  for (const name of ["method", "epsilon", "tau", "seed", "stats_html", "busy", "threshold", "invert", "despeckle",
    ...OVERLAYS.map(([name]) => name)]) {
    on(`change:${name}`, () => { syncControls(); draw(); });
  }
  for (const name of ["snapshot_index", "n_snapshots", "iteration_info"]) on(`change:${name}`, syncStepper);
  on("change:status_message", showStatus);
  on("change:status_level", showStatus);
  const resize = () => {
    root.classList.toggle("sc-large", !!model.get("large"));
    large.set(model.get("large"));
    for (const node of [svg, bg]) { node.setAttribute("width", width()); node.setAttribute("height", height()); }
    side.style.height = `${height()}px`;
    vp.width = width();
    vp.height = height();
    vp.setView(model.get("view"));
    draw();
  };
  on("change:width", resize);
  on("change:height", resize);
  on("change:large", resize);
  // "Edit outline": the kernel made an OutlineEditor; show its view under the explorer
  const editorSlot = h("div", { class: "sc-editor-slot", "data-testid": "editor-slot" });
  root.append(editorSlot);
  on("msg:custom", async (msg) => {
    if (!msg || msg.type !== "open_editor") return;
    const manager = model.widget_manager;
    const child = await manager.get_model(msg.model_id);
    const view = await manager.create_view(child);
    editorSlot.replaceChildren(view.el);
  });

  drawImage();
  buildCornerParams();
  syncControls();
  resize();
  root.dataset.ready = "1";
  return () => {
    stopPlay();
    if (imageUrl) URL.revokeObjectURL(imageUrl);
    for (const [event, fn] of handlers) model.off(event, fn);
  };
}

function decodeBase(g) {
  g = g ?? {};
  return { boundaries: floats(g.boundaries), corners: floats(g.corners), final: floats(g.final) };
}

function decodeSnapshot(g) {
  g = g ?? {};
  return {
    bezier: floats(g.bezier), worst: floats(g.worst), worst_contour: floats(g.worst_contour), knots: floats(g.knots),
    accepted: floats(g.accepted), rejected: floats(g.rejected), removed: floats(g.removed),
  };
}

export default { render };
