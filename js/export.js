// Export what a widget's canvas shows, as an SVG or a PNG download (plain ES module, shared by the widgets).
//
// The SVG is the canvas element itself, serialized with the computed look of its text (labels are styled
// by the stylesheet, which a standalone file does not carry). The PNG is that SVG drawn into a canvas at
// `scale` times the size. Both are downloaded through a temporary object URL.
import { h } from "./common.js";

const TEXT_STYLE = ["font-family", "font-size", "font-weight", "fill", "stroke", "stroke-width", "paint-order"];

/** The canvas as a standalone SVG document (inline styles for text, an opaque background). */
export function serializeSvg(svg) {
  const copy = svg.cloneNode(true);
  copy.setAttribute("xmlns", "http://www.w3.org/2000/svg");
  const source = svg.querySelectorAll("text"), target = copy.querySelectorAll("text");
  source.forEach((node, i) => {
    const style = getComputedStyle(node);
    target[i].setAttribute("style", TEXT_STYLE.map((key) => `${key}:${style.getPropertyValue(key)}`).join(";"));
  });
  return `<?xml version="1.0" encoding="UTF-8"?>\n${new XMLSerializer().serializeToString(copy)}\n`;
}

function download(blob, filename, root) {
  const url = URL.createObjectURL(blob);
  const link = h("a", { href: url, download: filename, style: { display: "none" } });
  root.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

/** Download the canvas as `name.svg`. */
export function downloadSvg(svg, name, root) {
  download(new Blob([serializeSvg(svg)], { type: "image/svg+xml" }), `${name}.svg`, root);
}

/** The canvas as PNG bytes (a Promise of a Blob), `scale` pixels per screen pixel. */
export function pngBlob(svg, scale = 2) {
  const width = Number(svg.getAttribute("width")), height = Number(svg.getAttribute("height"));
  const url = URL.createObjectURL(new Blob([serializeSvg(svg)], { type: "image/svg+xml" }));
  return new Promise((resolve, reject) => {
    const image = new Image();
    image.onload = () => {
      const canvas = document.createElement("canvas");
      canvas.width = Math.round(width * scale);
      canvas.height = Math.round(height * scale);
      const context = canvas.getContext("2d");
      context.fillStyle = "#ffffff";
      context.fillRect(0, 0, canvas.width, canvas.height);
      context.drawImage(image, 0, 0, canvas.width, canvas.height);
      URL.revokeObjectURL(url);
      canvas.toBlob((blob) => (blob ? resolve(blob) : reject(new Error("PNG encoding failed"))), "image/png");
    };
    image.onerror = () => { URL.revokeObjectURL(url); reject(new Error("the SVG could not be drawn")); };
    image.src = url;
  });
}

/** Download the canvas as `name.png`. */
export async function downloadPng(svg, name, root, scale = 2) {
  download(await pngBlob(svg, scale), `${name}.png`, root);
}

/** Two buttons, "SVG" and "PNG", that download what `svg` shows (file names `name.svg`, `name.png`). */
export function exportButtons(svg, name, root, button) {
  return [
    button("SVG", "Download the drawing as SVG", "export-svg", () => downloadSvg(svg, name, root)),
    button("PNG", "Download the drawing as PNG (twice the screen size)", "export-png", () => downloadPng(svg, name, root)),
  ];
}
