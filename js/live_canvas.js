// The editor's drawing during a drag, painted on one <canvas> over the SVG (plain ES module).
//
// A drag redraws large paths on every frame (a 1000-piece curve, 1000 point and knot markers, the control
// polygon). The browser rasterises an SVG in tiles and replays every path whose bounds meet a tile in each
// of them, so such a frame costs several times the drawing; a 2D canvas draws each path once. While a drag
// is live the SVG keeps receiving the same path data (the DOM stays the truth: tests and exports read it),
// its path layers are not displayed, and this canvas paints the very same path strings (Path2D) with the
// layers' own stroke and fill attributes, in the layers' order, once per animation frame. The labels move
// to a small SVG above the canvas for the drag, so they stay on top. When the drag ends the SVG shows again.
// A marker layer (its path data written with `markers()`) keeps its own raster between frames and repaints
// only the markers that moved (marker_cache.js); the canvas copies it in the layer's place.
import { createMarkerLayers, paintShape } from "./marker_cache.js";

const NONE = new Set(["none", "transparent", ""]);

/** How a layer path is painted: its presentation attributes as 2D-canvas state. */
function layerStyle(path) {
  const attr = (name, fallback) => path.getAttribute(name) ?? fallback;
  const dash = attr("stroke-dasharray", "");
  return {
    path,
    fill: NONE.has(attr("fill", "black")) ? null : attr("fill", "black"),
    stroke: NONE.has(attr("stroke", "none")) ? null : attr("stroke", "none"),
    width: Number(attr("stroke-width", 1)),
    alpha: Number(attr("opacity", 1)),
    dash: dash && dash !== "none" ? dash.split(/[\s,]+/).map(Number) : [],
    cap: attr("stroke-linecap", "butt"),
    join: attr("stroke-linejoin", "miter"),
  };
}

/** Size and place the canvas `element` (device pixels) and the label `overlay` exactly over `svg`. */
function placeOver(svg, element, overlay, context) {
  const width = Number(svg.getAttribute("width")), height = Number(svg.getAttribute("height"));
  const ratio = window.devicePixelRatio || 1;
  element.width = Math.round(width * ratio);
  element.height = Math.round(height * ratio);
  for (const node of [element, overlay]) {
    Object.assign(node.style, { left: `${svg.offsetLeft}px`, top: `${svg.offsetTop}px`, width: `${width}px`, height: `${height}px` });
  }
  overlay.setAttribute("width", width);
  overlay.setAttribute("height", height);
  context.setTransform(ratio, 0, 0, ratio, 0, 0);
}

/**
 * Live painter for an editor canvas: `svg` (the drawing), `paths` (its layer paths, bottom to top),
 * `labels` (the <g> of text labels). Returns {element, overlay, begin(), end(), invalidate(), markers(),
 * active, cached}: put `element` and `overlay` right after the SVG in its (positioned) wrapper. With
 * `cached = false` every layer is painted as a whole path on every frame (to compare the two).
 */
export function createLivePainter(svg, paths, labels) {
  const element = document.createElement("canvas");
  const overlay = document.createElementNS(svg.namespaceURI, "svg");
  for (const node of [element, overlay]) {
    Object.assign(node.style, { position: "absolute", left: "0px", top: "0px", pointerEvents: "none", display: "none" });
  }
  element.dataset.testid = "live-canvas";
  const context = element.getContext("2d");
  const place = () => placeOver(svg, element, overlay, context);
  const cache = new Map(); // path element -> {d, shape: Path2D}
  const markerLayers = createMarkerLayers(); // the layers drawn from their rasters during a drag
  let styles = null, active = false, rafId = 0, cached = true;

  function shapeOf(path) {
    const d = path.getAttribute("d") || "";
    let entry = cache.get(path);
    if (!entry || entry.d !== d) cache.set(path, (entry = { d, shape: d ? new Path2D(d) : null }));
    return entry.shape;
  }

  function paint() {
    rafId = 0;
    if (!active) return;
    context.clearRect(0, 0, element.width, element.height);
    for (const style of styles) {
      if (!style.fill && !style.stroke) continue;
      context.globalAlpha = style.alpha;
      if (cached && markerLayers.paint(context, style, element.width, element.height)) continue;
      const shape = shapeOf(style.path);
      if (shape) paintShape(context, style, shape);
    }
    context.globalAlpha = 1;
  }

  return {
    element, overlay,
    get active() { return active; },
    /** Marker layers from their rasters (true) or as whole paths on every frame (false); repaints at once.
     *  A change drops the rasters: the next cached paint starts them afresh. */
    get cached() { return cached; },
    set cached(value) {
      if (cached !== !!value) markerLayers.clear();
      cached = !!value;
      paint();
    },
    /** How many marker raster updates of this drag repainted the whole layer, the moved markers, nothing. */
    get updates() { return { ...markerLayers.updates }; },
    /** Layer `path` now has path data `d`: markers of `radius`, `shape` at `centers` (CSS px, flat x, y). */
    markers: markerLayers.set,
    /** A drag starts moving: paint on the canvas from now on, hide the SVG's path layers. */
    begin() {
      if (active) return;
      active = true;
      styles = styles ?? paths.map(layerStyle);
      markerLayers.clear();
      place();
      overlay.append(labels);
      element.style.display = overlay.style.display = "block";
      for (const path of paths) path.style.display = "none";
      paint();
    },
    /** The drawing changed: repaint at the next animation frame (coalesced). */
    invalidate() { if (active && !rafId) rafId = requestAnimationFrame(paint); },
    /** The drag is over: the SVG shows its layers again. */
    end() {
      if (!active) return;
      active = false;
      if (rafId) cancelAnimationFrame(rafId);
      rafId = 0;
      for (const path of paths) path.style.display = "";
      svg.append(labels);
      element.style.display = overlay.style.display = "none";
      context.clearRect(0, 0, element.width, element.height);
      cache.clear();
      markerLayers.clear();
    },
  };
}
