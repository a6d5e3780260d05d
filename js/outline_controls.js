// OutlineEditor controls (plain ES module): the toolbar (undo, redo, corner, delete, mirror, fit, export,
// overlays), the side panel (tension and weight of the selected knots) and the status line. Every control
// sends a message or writes a synced trait; the kernel validates and answers, and `showStatus()` shows what
// it kept.
import { h, sliderRow, checkRow, formatNumber } from "./common.js";

const OVERLAYS = [["show_image", "bitmap"], ["show_fill", "fill"], ["show_deviation", "deviation"]];

/** The distinct values of a per-knot table (list of lists) at the selected [contour, knot] pairs. */
export function selectedValues(table, pairs) {
  return [...new Set(pairs.map(([k, i]) => table[k]?.[i]))];
}

function createToolbar(model, send, setTrait) {
  const button = (text, title, testid, onClick) =>
    h("button", { class: "sc-button", title, "data-testid": testid, onclick: (e) => { e.preventDefault(); onClick(); } }, text);
  const buttons = {
    undo: button("↶ Undo", "Undo (Ctrl+Z)", "undo", () => send({ type: "undo" })),
    redo: button("↷ Redo", "Redo (Ctrl+Y)", "redo", () => send({ type: "redo" })),
    corner: button("Corner ⇄ smooth", "Toggle the selected knots between corner and smooth GC² joint (C)", "toggle-corner", () => send({ type: "corner" })),
    delete: button("Delete", "Delete the selected knots (Delete)", "delete", () => send({ type: "delete" })),
    mirrorX: button("Mirror ⇆", "Reflect the selection (or the whole shape) left-right", "mirror-vertical", () => send({ type: "reflect", axis: "vertical" })),
    mirrorY: button("Mirror ⇅", "Reflect the selection (or the whole shape) upside down", "mirror-horizontal", () => send({ type: "reflect", axis: "horizontal" })),
    fit: button("Fit", "Fit the outline to the view", "fit", () => send({ type: "fit" })),
    export: button("Export SVG", "Write the outline to export_path", "export", () => send({ type: "export" })),
  };
  const overlays = OVERLAYS.map(([name, label]) => checkRow(label, model.get(name), (v) => setTrait(name, v), { testid: name }));
  const toolbar = h("div", { class: "sc-toolbar" }, ...Object.values(buttons), h("span", { class: "sc-spacer" }), ...overlays.map((o) => o.row));
  return { toolbar, buttons, overlays };
}

/** Build the toolbar, side panel and footer; `showStatus(root)` and `syncOverlays()` make them show the model. */
export function createControls(model, { send, setTrait }) {
  const bar = createToolbar(model, send, setTrait);
  const tension = sliderRow({ label: "tension v", title: "Point tension of the selected knots (§2.5)", min: -1, max: 50, step: 0.1, value: 0,
    onInput: (v, final) => { if (final) send({ type: "tension", value: v }); }, testid: "tension" });
  const weight = sliderRow({ label: "weight ω", title: "Interval weight of the pieces after the selected knots", min: 0.05, max: 20, step: 0.05, value: 1, scale: "log",
    onInput: (v, final) => { if (final) send({ type: "weight", value: v }); }, testid: "weight" });
  const status = h("div", { class: "sc-status", "data-testid": "status" });
  const deviationLabel = h("span", { class: "sc-summary", "data-testid": "max-deviation" });
  const side = h("div", { class: "sc-side" },
    h("div", { class: "sc-section" }, h("div", { class: "sc-section-title" }, "Selected knots"), tension.row, weight.row));
  const footer = h("div", { class: "sc-footer" }, status, deviationLabel);

  /** Status line, max deviation, undo/redo and the sliders of the selected knots ("mixed" when they differ). */
  function showStatus(root) {
    status.textContent = model.get("status_message") ?? "";
    status.dataset.level = model.get("status_level") ?? "info";
    const dev = model.get("max_deviation");
    deviationLabel.textContent = dev === null || dev === undefined ? "" : `max deviation ${formatNumber(dev, 2)} px`;
    bar.buttons.undo.disabled = !model.get("can_undo");
    bar.buttons.redo.disabled = !model.get("can_redo");
    const pairs = model.get("selection") ?? [];
    const vt = selectedValues(model.get("point_tension") ?? [], pairs);
    const vw = selectedValues(model.get("interval_weights") ?? [], pairs);
    tension.set(vt.length === 1 ? vt[0] : null, vt[0] ?? 0);
    weight.set(vw.length === 1 ? vw[0] : null, vw[0] ?? 1);
    tension.setDisabled(!pairs.length);
    weight.setDisabled(!pairs.length);
    root.dataset.nselected = String(pairs.length);
  }
  function syncOverlays() { bar.overlays.forEach((o, i) => o.set(model.get(OVERLAYS[i][0]))); }

  return { toolbar: bar.toolbar, side, footer, showStatus, syncOverlays };
}
