// SplineEditor controls: toolbar, canvas buttons, side panel (sliders, overlays) and how they follow the
// model (plain ES module). Every control writes a synced trait or sends a message; the kernel validates
// and answers, and `sync()` shows what the kernel kept.
import { h, sliderRow, selectBox, checkRow, swatch } from "./common.js";
import { COLORS } from "./editor_view.js";
import { exportButtons } from "./export.js";

const OVERLAYS = [
  ["show_control_polygon", "control polygon", { color: COLORS.polygon, dash: "5 4", marker: "circle" }],
  ["show_knots", "knots Fᵢ", { color: COLORS.knots, dash: "none", marker: "dot" }],
  ["show_bezier_points", "class points V, W", { color: COLORS.classPolygon, dash: "3 3", marker: "square" }],
  ["show_tangents", "tangents (Bézier handles)", { color: COLORS.tangents }],
  ["show_comb", "curvature comb", { color: COLORS.comb, dash: "none", marker: "comb" }],
];

export const allEqual = (list) => list.length === 0 || list.every((x) => x === list[0]);

/** The common value of a list, or its median when the values differ (where a "mixed" slider rests). */
export function typical(list) {
  if (!list.length) return NaN;
  if (allEqual(list)) return list[0];
  const sorted = [...list].sort((a, b) => a - b);
  return sorted[Math.floor(sorted.length / 2)];
}

/** Trait writers bound to a model: one value, a whole list, one list entry. */
export function traitWriters(model) {
  const set = (name, value) => { model.set(name, value); model.save_changes(); };
  return {
    set,
    setAll(name, value) { set(name, new Array((model.get(name) ?? []).length).fill(value)); },
    setOne(name, index, value) {
      const list = [...(model.get(name) ?? [])];
      if (index < 0 || index >= list.length) return;
      list[index] = value;
      set(name, list);
    },
  };
}

function createToolbar(model, write, focus, svg, root) {
  const o = model.get("options") ?? {};
  const sel = {
    form: selectBox(o.forms ?? [], model.get("form"), (v) => write.set("form", v), "form"),
    preset: selectBox(o.presets ?? [], model.get("preset"), (v) => write.set("preset", v), "preset"),
    ends: selectBox([], model.get("end_condition"), (v) => write.set("end_condition", v), "end-condition"),
    knots: selectBox(o.knots ?? [], model.get("knots"), (v) => write.set("knots", v), "knots"),
  };
  const closed = checkRow("closed", model.get("closed"), (v) => write.set("closed", v), { testid: "closed", title: "Closed (periodic) curve" });
  const field = (label, control) => h("label", { class: "sc-field" }, h("span", { class: "sc-field-label" }, label), control);
  const fields = { form: field("form", sel.form.select), preset: field("class", sel.preset.select),
    ends: field("ends", sel.ends.select), knots: field("knots", sel.knots.select) };
  const button = (text, title, testid, onClick) =>
    h("button", { class: "sc-button", title, "data-testid": testid, onclick: (e) => { e.preventDefault(); onClick(); focus(); } }, text);
  const buttons = {
    undo: button("↶", "Undo (Ctrl+Z)", "undo", () => model.send({ type: "undo" })),
    redo: button("↷", "Redo (Ctrl+Shift+Z / Ctrl+Y)", "redo", () => model.send({ type: "redo" })),
    fit: button("Fit", "Fit the drawing to the view (F)", "fit", () => model.send({ type: "fit" })),
    delete: button("Delete", "Delete the selected point (Delete, or right-click a point)", "delete", () => {
      const i = model.get("selected");
      if (i >= 0) model.send({ type: "delete", index: i });
    }),
  };
  const large = checkRow("large", model.get("large"), (v) => write.set("large", v), { testid: "large", title: "Presentation size: larger canvas, text and controls" });
  const toolbar = h("div", { class: "sc-toolbar" }, fields.form, fields.preset, fields.ends, fields.knots, closed.row,
    h("span", { class: "sc-spacer" }), large.row);
  const actions = h("div", { class: "sc-actions" }, buttons.undo, buttons.redo, buttons.fit, buttons.delete,
    ...exportButtons(svg, "spline", root, button));
  return { toolbar, actions, sel, closed, fields, buttons, large };
}

function createSidePanel(model, write) {
  const range = (name) => ((model.get("options") ?? {}).ranges ?? {})[name] ?? [0, 1, 0.01];
  const slider = (name, label, title, onInput, scale = "linear") => {
    const [lo, hi, st] = range(name);
    return sliderRow({ label, title, min: lo, max: hi, step: st, value: NaN, onInput, testid: name, scale });
  };
  const sliders = {
    tension: slider("point_tension", "v", "Point tension v for every point (§2.2): v > 0 tightens the curve towards the polygon", (v) => write.setAll("point_tension", v)),
    weight: slider("interval_weights", "ω", "Interval weight ω for every interval (§2.2): penalises bending", (v) => write.setAll("interval_weights", v), "log"),
    alpha: slider("alpha", "α", "Class parameter α", (v) => write.set("alpha", v)),
    beta: slider("beta", "β", "Class parameter β", (v) => write.set("beta", v)),
    pointTension: slider("point_tension", "vᵢ", "Point tension of the selected point", (v) => write.setOne("point_tension", model.get("selected"), v)),
    intervalWeight: slider("interval_weights", "ωᵢ", "Interval weight of the selected interval", (v) => write.setOne("interval_weights", model.get("selected_interval"), v), "log"),
    comb: slider("comb_scale", "size", "Length of the comb teeth (relative)", (v) => write.set("comb_scale", v), "log"),
    t: sliderRow({ label: "t", title: "Parameter t: the point P(t) and the de Casteljau construction of its piece", min: 0, max: 1,
      step: "any", value: NaN, onInput: (v) => write.set("t", v), testid: "t" }),
  };
  const tOn = checkRow("parameter slider", model.get("t") !== null, (on) => {
    const [t0, t1] = (model.get("geometry") ?? {}).domain ?? [0, 1];
    write.set("t", on ? t0 + 0.37 * (t1 - t0) : null);
  }, { testid: "t-on", title: "Show a point P(t) moving along the curve with its construction" });
  const aids = ["show_grid", "snap"].map((name) => checkRow(name === "snap" ? "snap to grid" : "grid", model.get(name),
    (v) => write.set(name, v), { testid: name, title: name === "snap" ? "Dragged points jump to the grid lines" : "Grid lines" }));
  const overlays = {};
  const overlayRows = OVERLAYS.map(([name, label, look]) => {
    overlays[name] = checkRow(label, model.get(name), (v) => write.set(name, v), { swatch: swatch(look), testid: name });
    return overlays[name].row;
  });
  const selectionTitle = h("div", { class: "sc-selection-title", "data-testid": "selection-title" });
  const curveLegend = h("div", { class: "sc-check sc-legend-only" }, swatch({ color: COLORS.curve, width: 2.5 }), h("span", {}, "curve"));
  const section = (title, ...children) => h("div", { class: "sc-section" }, h("div", { class: "sc-section-title" }, title), ...children);
  const sections = {
    t: section("Parameter t", tOn.row, sliders.t.row),
    tension: section("Tension (all)", sliders.tension.row, sliders.weight.row),
    class: section("Class parameters", sliders.alpha.row, sliders.beta.row),
    selection: section("Selection", selectionTitle, sliders.pointTension.row, sliders.intervalWeight.row),
  };
  const side = h("div", { class: "sc-side" }, sections.t, sections.tension, sections.class, sections.selection,
    section("Show", curveLegend, ...overlayRows, sliders.comb.row, h("div", { class: "sc-overlay-grid" }, ...aids.map((a) => a.row))));
  return { side, sliders, overlays, sections, selectionTitle, range, tOn, aids };
}

/** Build the toolbar, canvas buttons and side panel; `sync()` makes them show the model. */
export function createControls(model, { focus, svg, root }) {
  const write = traitWriters(model);
  const bar = createToolbar(model, write, focus, svg, root);
  const panel = createSidePanel(model, write);
  const explanation = h("div", { class: "sc-explanation", "data-testid": "explanation" });
  const status = h("div", { class: "sc-status", "data-testid": "status" });
  const summary = h("div", { class: "sc-summary", "data-testid": "summary" });

  function syncToolbar(o, uses) {
    const form = model.get("form");
    bar.sel.form.fill(o.forms ?? []);
    bar.sel.form.set(form);
    bar.sel.preset.set(model.get("preset"));
    const endOptions = (o.end_conditions ?? {})[form] ?? [];
    bar.sel.ends.fill(endOptions);
    bar.sel.ends.set(model.get("end_condition"));
    bar.fields.ends.style.display = endOptions.length ? "" : "none";
    bar.fields.ends.querySelector(".sc-field-label").textContent = (o.end_labels ?? {})[form] || "ends";
    bar.sel.knots.set(model.get("knots"));
    bar.fields.knots.style.display = uses.knots ? "" : "none";
    bar.closed.set(model.get("closed"));
    bar.closed.row.style.display = uses.closed === false ? "none" : "";
    bar.fields.preset.style.display = uses.alpha === false || uses.preset === false ? "none" : "";
    bar.buttons.undo.disabled = !model.get("can_undo");
    bar.buttons.redo.disabled = !model.get("can_redo");
    bar.buttons.delete.disabled = !(model.get("selected") >= 0) || uses.add_delete === false;
  }

  function syncSliders(uses) {
    const S = panel.sliders;
    for (const [slider, name] of [[S.tension, "point_tension"], [S.weight, "interval_weights"], [S.alpha, "alpha"], [S.beta, "beta"],
      [S.pointTension, "point_tension"], [S.intervalWeight, "interval_weights"], [S.comb, "comb_scale"]]) {
      const [lo, hi, st] = (name === "alpha" || name === "beta") && uses.alpha_range ? uses.alpha_range : panel.range(name);
      const positive = slider === S.weight || slider === S.intervalWeight || slider === S.comb;
      slider.configure(positive ? Math.max(lo, 1e-6) : lo, hi, st);
    }
    const v = model.get("point_tension") ?? [], w = model.get("interval_weights") ?? [];
    S.tension.set(allEqual(v) ? typical(v) : null, typical(v));
    S.weight.set(allEqual(w) ? typical(w) : null, typical(w));
    panel.sections.tension.style.display = uses.tension ? "" : "none";
    S.alpha.set(model.get("alpha"));
    S.beta.set(model.get("beta"));
    S.alpha.setLabel(uses.alpha_label ?? "α");
    S.alpha.row.title = uses.alpha_title ?? "Class parameter α";
    S.beta.setLabel(uses.beta_label ?? "β");
    S.beta.row.style.display = uses.beta_label === null ? "none" : ""; // Algorithm 3.1 has one scale only
    panel.sections.class.style.display = uses.alpha === false ? "none" : "";
    const free = model.get("preset") === "free" || uses.preset === false;
    S.alpha.setDisabled(!free);
    S.beta.setDisabled(!free);
    const sel = model.get("selected"), selInt = model.get("selected_interval");
    S.pointTension.row.style.display = uses.tension && sel >= 0 && sel < v.length ? "" : "none";
    if (sel >= 0 && sel < v.length) S.pointTension.set(v[sel]);
    S.intervalWeight.row.style.display = uses.tension && selInt >= 0 && selInt < w.length ? "" : "none";
    if (selInt >= 0 && selInt < w.length) S.intervalWeight.set(w[selInt]);
    const parts = [];
    if (sel >= 0) parts.push(`point ${sel}`);
    if (selInt >= 0) parts.push(`interval ${selInt}`);
    panel.selectionTitle.textContent = parts.length ? parts.join(" · ") : "Click a point or the curve to select it.";
    panel.sections.selection.classList.toggle("sc-muted", !parts.length);
    S.comb.set(model.get("comb_scale"));
    const t = model.get("t"), [t0, t1] = (model.get("geometry") ?? {}).domain ?? [0, 1];
    panel.tOn.set(t !== null);
    S.t.configure(t0, t1, "any");
    S.t.row.style.display = t === null ? "none" : "";
    if (t !== null) S.t.set(t);
    panel.aids.forEach((row, i) => row.set(model.get(["show_grid", "snap"][i])));
    bar.large.set(model.get("large"));
  }

  function sync() {
    const o = model.get("options") ?? {};
    const uses = (o.uses ?? {})[model.get("form")] ?? {};
    syncToolbar(o, uses);
    syncSliders(uses);
    for (const [name, row] of Object.entries(panel.overlays)) row.set(model.get(name));
    const vw = panel.overlays.show_bezier_points.row;
    vw.style.display = uses.vw === false ? "none" : "";
    vw.querySelector("span").textContent = uses.vw_label ?? "class points V, W";
    explanation.innerHTML = model.get("explanation_html");
  }

  const readout = h("span", { class: "sc-readout", "data-testid": "readout" });
  /** The status line (kernel's message and level) and the footer summary. */
  function showStatus(root, points, pieces) {
    const level = model.get("status_level") || "info";
    status.textContent = model.get("status_message") || "";
    status.className = `sc-status sc-status-${level}`;
    root.dataset.statusLevel = level;
    summary.textContent = `${points} point${points === 1 ? "" : "s"} · ${pieces} piece${pieces === 1 ? "" : "s"}`;
  }
  /** Data coordinates under the pointer (null: the pointer left the canvas). */
  function showReadout(xy) {
    readout.textContent = xy ? `x ${xy[0].toFixed(1)} y ${xy[1].toFixed(1)}` : "";
  }

  return { toolbar: bar.toolbar, actions: bar.actions, side: panel.side, explanation, status, summary, readout, sync,
    showStatus, showReadout };
}
