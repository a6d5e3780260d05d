// A marker layer of the live canvas kept as its own raster, repainted only where its markers moved
// (plain ES module; used by live_canvas.js).
//
// A marker layer is a small circle or square at every point or knot: 1000 of each at 1000 points. A 2D
// canvas rasterises every stroked arc of a path anew on every frame, in software raster on the main
// thread (several ms per 1000 markers, more than the rest of the frame). During a drag only a few of them
// move (the dragged point, the knots near it), so each marker layer is held in an offscreen canvas of the
// live canvas's size, cut into square tiles. A tile's pixels are always painted the same way: cleared,
// clipped to the tile, and the layer's markers whose ink meets the tile drawn as one path of the same
// `markersPath` data, filled then stroked as the layer's path is. A frame compares the markers' centres
// with the ones painted and repaints the tiles that a moved marker meets (where it was and where it is);
// the other tiles keep their pixels, so the raster is exactly the one a repaint of every tile gives. The
// live canvas copies the raster in the layer's place (one `drawImage`).
import { markersPath } from "./common.js";

/** Tile side (device px). */
export const TILE = 64;
/** More moved markers than this (or a changed size, radius or shape) repaint every tile. */
export const MAX_MOVED = 48;
const SCREEN = { sx: (x) => x, sy: (y) => y }; // markersPath of centres already in CSS px

/** Same value, NaN included (a hidden marker stays hidden). */
const same = (a, b) => a === b || (a !== a && b !== b);

/**
 * Indices of the markers whose centre differs between `painted` and `centers` (flat x, y in CSS px),
 * or null when they are more than `limit` (or the count changed): then every tile is repainted.
 */
export function movedMarkers(painted, centers, limit = MAX_MOVED) {
  if (!painted || painted.length !== centers.length) return null;
  const moved = [];
  for (let i = 0; 2 * i + 1 < centers.length; i++) {
    if (same(painted[2 * i], centers[2 * i]) && same(painted[2 * i + 1], centers[2 * i + 1])) continue;
    if (moved.length === limit) return null;
    moved.push(i);
  }
  return moved;
}

/**
 * Tile grid of a `width` x `height` (device px) raster at `ratio` device px per CSS px, for markers whose
 * ink reaches `reach` CSS px from their centre: {columns, rows, tilesOf(x, y, visit)}; `tilesOf` calls
 * `visit(key)` for each tile (key = row * columns + column) that the ink of a marker at (x, y) meets.
 */
export function tileGrid(width, height, ratio, reach) {
  const columns = Math.ceil(width / TILE), rows = Math.ceil(height / TILE);
  const span = (c, count) => [Math.max(0, Math.floor(((c - reach) * ratio - 1) / TILE)),
    Math.min(count - 1, Math.floor(((c + reach) * ratio + 1) / TILE))];
  return {
    columns, rows,
    tilesOf(x, y, visit) {
      if (!Number.isFinite(x) || !Number.isFinite(y)) return;
      const [c0, c1] = span(x, columns), [r0, r1] = span(y, rows);
      for (let r = r0; r <= r1; r++) for (let c = c0; c <= c1; c++) visit(r * columns + c);
    },
  };
}

/** The centres (flat, CSS px) of the markers meeting each tile of `wanted` (a Set of keys; null: every tile). */
export function markersByTile(grid, centers, wanted = null) {
  const byTile = new Map();
  for (let i = 0; 2 * i + 1 < centers.length; i++) {
    const x = centers[2 * i], y = centers[2 * i + 1];
    grid.tilesOf(x, y, (key) => {
      if (wanted && !wanted.has(key)) return;
      let list = byTile.get(key);
      if (!list) byTile.set(key, (list = []));
      list.push(x, y);
    });
  }
  return byTile;
}

/** Fill, then stroke `shape` (a Path2D) on `context` as layer `style` says (the SVG's miter limit, 4). */
export function paintShape(context, style, shape) {
  if (style.fill) {
    context.fillStyle = style.fill;
    context.fill(shape);
  }
  if (style.stroke) {
    Object.assign(context, { strokeStyle: style.stroke, lineWidth: style.width, lineCap: style.cap,
      lineJoin: style.join, miterLimit: 4 });
    context.setLineDash(style.dash);
    context.stroke(shape);
  }
}

/**
 * The raster of one marker layer (`style`: fill, stroke, width, cap, join of the layer), `width` x `height`
 * device px at `ratio`. `update(markers)` brings it to `markers` = {centers, radius, shape} and returns
 * "whole", "moved" or "same" (what it repainted); `image` is the raster to copy.
 */
export function createMarkerCache(style, width, height, ratio) {
  const image = new OffscreenCanvas(width, height);
  const context = image.getContext("2d");
  let painted = null; // {centers, radius, shape, grid} of the raster

  function paintTile(grid, key, near, { radius, shape }) {
    const x0 = (key % grid.columns) * TILE, y0 = Math.floor(key / grid.columns) * TILE;
    context.save();
    context.setTransform(1, 0, 0, 1, 0, 0);
    context.clearRect(x0, y0, TILE, TILE);
    if (near && near.length) {
      context.beginPath();
      context.rect(x0, y0, TILE, TILE);
      context.clip();
      context.setTransform(ratio, 0, 0, ratio, 0, 0);
      paintShape(context, style, new Path2D(markersPath(SCREEN, near, radius, shape)));
    }
    context.restore();
  }

  return {
    image,
    update(markers) {
      const { centers, radius, shape } = markers;
      const sameKind = painted && painted.radius === radius && painted.shape === shape;
      const moved = sameKind ? movedMarkers(painted.centers, centers) : null;
      let grid = painted?.grid, done;
      if (!moved) {
        grid = tileGrid(width, height, ratio, radius * (shape === "diamond" ? 1.3 : 1) + style.width);
        context.clearRect(0, 0, width, height);
        for (const [key, near] of markersByTile(grid, centers)) paintTile(grid, key, near, markers);
        done = "whole";
      } else if (moved.length) {
        const dirty = new Set();
        for (const i of moved) {
          grid.tilesOf(painted.centers[2 * i], painted.centers[2 * i + 1], (key) => dirty.add(key));
          grid.tilesOf(centers[2 * i], centers[2 * i + 1], (key) => dirty.add(key));
        }
        const byTile = markersByTile(grid, centers, dirty);
        for (const key of dirty) paintTile(grid, key, byTile.get(key), markers);
        done = "moved";
      } else done = "same";
      painted = { centers: Float64Array.from(centers), radius, shape, grid };
      return done;
    },
  };
}

/**
 * The marker layers of a live canvas. `set(path, d, centers, radius, shape)` records what layer `path`'s
 * path data `d` draws; `paint(context, style, width, height)` copies the layer's raster, brought up to date,
 * onto `context` and returns true, or returns false when the layer's data is no longer those markers;
 * `clear()` drops the rasters; `updates` counts the raster updates since, by kind.
 */
export function createMarkerLayers() {
  const layers = new Map(), rasters = new Map(), updates = { whole: 0, moved: 0, same: 0 };
  return {
    updates,
    set(path, d, centers, radius, shape) { layers.set(path, { d, centers, radius, shape }); },
    paint(context, style, width, height) {
      const markers = layers.get(style.path);
      if (!markers || !markers.d || markers.d !== style.path.getAttribute("d")) return false;
      let raster = rasters.get(style.path);
      if (!raster) rasters.set(style.path, (raster = createMarkerCache(style, width, height, window.devicePixelRatio || 1)));
      updates[raster.update(markers)] += 1;
      context.save();
      context.setTransform(1, 0, 0, 1, 0, 0);
      context.drawImage(raster.image, 0, 0);
      context.restore();
      return true;
    },
    clear() {
      rasters.clear();
      Object.assign(updates, { whole: 0, moved: 0, same: 0 });
    },
  };
}
