// Small SVG charts for the lab page: line charts (one or more series) with axes, units,
// characteristic-frequency markers whose labels never collide, identified peaks, drag-to-zoom,
// panning and a hover readout; and a bar chart. No dependencies; the server decimates long
// series. The palette, the marker labels and the label placement are the same as the SVG
// endpoints' (src/plots/style.rs, src/plots/labels.rs): change both together.

const NS = "http://www.w3.org/2000/svg";
const M = { l: 64, r: 16, t: 14, b: 42 };

/** One colour per characteristic line (src/plots/style.rs: `marker_color`). */
export const PALETTE = { bpfo: "#c0392b", bpfi: "#1f6fb5", bsf: "#7d3c98", bsf2: "#148f77", ftf: "#b9770e", shaft: "#5d6d7e" };
/** Series in drawing order (src/plots/style.rs: `SERIES_COLORS`); the first is the ink. */
export const SERIES = ["#1d2329", "#1f6fb5", "#c0392b", "#148f77", "#7d3c98", "#b9770e", "#8c564b", "#5d6d7e"];
const LINE_NAMES = { bpfo: "BPFO", bpfi: "BPFI", bsf: "BSF", bsf2: "2BSF", ftf: "FTF", shaft: "shaft" };

/** `BPFO`, `BPFO×2` (src/plots/labels.rs: `marker_label`). */
export function markerLabel(name, harmonic) {
  const n = LINE_NAMES[name] ?? name;
  return harmonic > 1 ? `${n}×${harmonic}` : n;
}
export const lineName = (name) => LINE_NAMES[name] ?? name;

function el(name, attrs, parent) {
  const e = document.createElementNS(NS, name);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (parent) parent.appendChild(e);
  return e;
}

/** About `n` round tick values covering [lo, hi]. */
export function ticks(lo, hi, n = 6) {
  if (!(hi > lo)) return [lo];
  const raw = (hi - lo) / n;
  const mag = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= raw) || 10 * mag;
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  return out;
}

/** A number as the axes print it (src/plots/labels.rs: `tick_label`). */
export function fmt(v) {
  const a = Math.abs(v);
  if (a === 0) return "0";
  if (!isFinite(v)) return String(v);
  if (a >= 1e5 || a < 1e-3) return v.toExponential(1);
  return Number(v.toPrecision(4)).toString();
}

const overlaps = (a, b) => a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h;

/**
 * Place text labels without overlap (src/plots/labels.rs: `place`): each label takes the
 * first of its candidate positions that stays inside `bounds` and clear of every placed box;
 * a label with no free position is left out (its line stays, and the legend names it).
 * labels: [{ text, cls, color, candidates: [{x, y, anchor}] }] in priority order.
 */
function placeLabels(svg, labels, bounds, taken = []) {
  let dropped = 0;
  for (const l of labels) {
    const t = el("text", { class: `chart-label ${l.cls || ""}`, fill: l.color || "" }, svg);
    t.textContent = l.text;
    const w = t.getComputedTextLength() || l.text.length * 6.2;
    const h = 11;
    let spot = null;
    for (const c of l.candidates) {
      const x = c.anchor === "end" ? c.x - w : c.anchor === "middle" ? c.x - w / 2 : c.x;
      const box = { x: x - 1, y: c.y - h + 2, w: w + 2, h };
      if (box.x < bounds.x || box.x + box.w > bounds.x + bounds.w || box.y < bounds.y || box.y + box.h > bounds.y + bounds.h) continue;
      if (taken.some((b) => overlaps(b, box))) continue;
      spot = { x, y: c.y, box };
      break;
    }
    if (!spot) { t.remove(); dropped++; continue; }
    t.setAttribute("x", spot.x.toFixed(1));
    t.setAttribute("y", spot.y.toFixed(1));
    taken.push(spot.box);
  }
  return dropped;
}

/** Width the chart is drawn at: its box's, so text keeps its size on narrow screens. */
function chartWidth(box) {
  const w = box.getBoundingClientRect().width;
  return Math.max(300, Math.min(1200, Math.round(w || 960)));
}

/**
 * Draw a line chart into `box` (replacing its content).
 * opts: { series: [{x, y, name, color}] | (x, y), xLabel, yLabel, title, range: [x0, x1],
 *         yFromZero, markers: [{x, name, harmonic, sideband}], peaks: [{x, y, name, label, text}]
 *         (a peak with `text`, its error, is a detected one),
 *         yMin (the lowest value shown), onZoom(x0, x1), readout: element for the hover text,
 *         xUnit, yUnit }
 * Returns the svg element.
 */
export function lineChart(box, opts) {
  box.replaceChildren();
  const W = chartWidth(box);
  const H = W < 600 ? 260 : 320;
  const series = opts.series || [{ x: opts.x, y: opts.y, color: SERIES[1] }];
  const svg = el("svg", { viewBox: `0 0 ${W} ${H}`, width: W, height: H, role: "img", "aria-label": opts.title || `${opts.yLabel} against ${opts.xLabel}` }, box);
  const all = series.flatMap((s) => s.x);
  const x0 = opts.range ? opts.range[0] : all.length ? Math.min(...series.map((s) => s.x[0])) : 0;
  const x1 = opts.range ? opts.range[1] : all.length ? Math.max(...series.map((s) => s.x[s.x.length - 1])) : 1;
  let ylo = Infinity, yhi = -Infinity;
  for (const s of series) for (let i = 0; i < s.x.length; i++) {
    if (s.x[i] < x0 || s.x[i] > x1 || !isFinite(s.y[i])) continue;
    if (s.y[i] < ylo) ylo = s.y[i];
    if (s.y[i] > yhi) yhi = s.y[i];
  }
  if (!isFinite(ylo)) { ylo = 0; yhi = 1; }
  if (opts.yFromZero) ylo = Math.min(0, ylo);
  if (opts.yMin !== undefined) ylo = Math.max(ylo, opts.yMin);
  if (yhi === ylo) { yhi += 1; ylo -= 1; }
  // headroom above the highest line for the marker labels' rows
  const pad = (yhi - ylo) * (opts.markers?.length ? 0.3 : 0.05); yhi += pad; if (!opts.yFromZero) ylo -= (yhi - ylo) * 0.04;
  const px = (v) => M.l + ((v - x0) / ((x1 - x0) || 1)) * (W - M.l - M.r);
  const py = (v) => H - M.b - ((v - ylo) / (yhi - ylo)) * (H - M.t - M.b);
  const plotBox = { x: M.l, y: M.t, w: W - M.l - M.r, h: H - M.t - M.b };
  const tickBoxes = [];
  const xt = ticks(x0, x1, Math.max(3, Math.floor((W - M.l - M.r) / 90)));
  for (const t of xt) {
    el("line", { class: "grid", x1: px(t), x2: px(t), y1: M.t, y2: H - M.b }, svg);
    el("text", { x: px(t), y: H - M.b + 16, "text-anchor": "middle", class: "tick" }, svg).textContent = fmt(t);
  }
  for (const t of ticks(ylo, yhi, 5)) {
    el("line", { class: "grid", x1: M.l, x2: W - M.r, y1: py(t), y2: py(t) }, svg);
    el("text", { x: M.l - 6, y: py(t) + 4, "text-anchor": "end", class: "tick" }, svg).textContent = fmt(t);
  }
  el("line", { class: "axis", x1: M.l, x2: W - M.r, y1: H - M.b, y2: H - M.b }, svg);
  el("line", { class: "axis", x1: M.l, x2: M.l, y1: M.t, y2: H - M.b }, svg);
  el("text", { x: (M.l + W - M.r) / 2, y: H - 6, "text-anchor": "middle", class: "axis-title" }, svg).textContent = opts.xLabel;
  el("text", { x: 14, y: (M.t + H - M.b) / 2, "text-anchor": "middle", class: "axis-title", transform: `rotate(-90 14 ${(M.t + H - M.b) / 2})` }, svg).textContent = opts.yLabel;
  const clipId = `clip-${Math.random().toString(36).slice(2)}`;
  el("rect", { x: M.l, y: M.t, width: plotBox.w, height: plotBox.h }, el("clipPath", { id: clipId }, el("defs", {}, svg)));
  const inside = el("g", { "clip-path": `url(#${clipId})` }, svg);
  const markers = (opts.markers || []).filter((m) => m.x >= x0 && m.x <= x1);
  for (const m of markers) {
    el("line", { class: `marker${m.sideband ? " sideband" : ""}`, stroke: PALETTE[m.name] || "#888", x1: px(m.x), x2: px(m.x), y1: M.t, y2: H - M.b,
      "data-marker": m.sideband ? `${markerLabel(m.name, m.harmonic)}${m.sideband > 0 ? "+" : "−"}shaft` : markerLabel(m.name, m.harmonic) }, inside);
  }
  series.forEach((s, k) => {
    let d = "";
    for (let i = 0; i < s.x.length; i++) if (isFinite(s.y[i])) d += `${d ? "L" : "M"}${px(s.x[i]).toFixed(1)},${py(s.y[i]).toFixed(1)}`;
    el("path", { class: "series", d, stroke: s.color || SERIES[k % SERIES.length], "data-name": s.name || "" }, inside);
  });
  const peaks = (opts.peaks || []).filter((p) => p.x >= x0 && p.x <= x1 && isFinite(p.y));
  // detected peaks filled, the others hollow (identified, but not above the noise)
  for (const p of peaks) el("circle", { class: `peak${p.text ? " detected" : ""}`, cx: px(p.x), cy: py(p.y), r: 3.5, stroke: PALETTE[p.name] || "#333",
    fill: p.text ? PALETTE[p.name] || "#333" : "#fff", "data-peak": p.label }, inside);
  // labels: fundamentals first, then identified peaks' errors, then harmonics
  const lanes = [0, 1, 2, 3].map((k) => M.t + 11 + k * 12);
  const markerLabels = markers.filter((m) => !m.sideband).map((m) => ({
    text: markerLabel(m.name, m.harmonic), color: PALETTE[m.name], cls: "marker-label", harmonic: m.harmonic,
    candidates: [...lanes.map((y) => ({ x: px(m.x) + 3, y })), ...lanes.map((y) => ({ x: px(m.x) - 3, y, anchor: "end" }))],
  }));
  const peakLabels = peaks.filter((p) => p.text).map((p) => ({
    text: p.text, color: PALETTE[p.name], cls: "peak-label", harmonic: 1.5,
    candidates: [-8, -20, -32].map((dy) => ({ x: px(p.x), y: py(p.y) + dy, anchor: "middle" }))
      .concat([{ x: px(p.x) + 6, y: py(p.y) + 4 }, { x: px(p.x) - 6, y: py(p.y) + 4, anchor: "end" }]),
  }));
  const order = [...markerLabels, ...peakLabels].sort((a, b) => a.harmonic - b.harmonic);
  const dropped = placeLabels(svg, order, plotBox, tickBoxes);
  svg.dataset.hiddenLabels = dropped;
  // hover: a cross-hair on the first series with frequency, amplitude and the nearest marker
  const cross = el("line", { class: "crosshair", y1: M.t, y2: H - M.b, visibility: "hidden" }, svg);
  const dot = el("circle", { class: "hover-dot", r: 3, visibility: "hidden" }, svg);
  const toX = (ev) => {
    const r = svg.getBoundingClientRect();
    const sx = ((ev.clientX - r.left) / r.width) * W;
    return x0 + ((Math.min(Math.max(sx, M.l), W - M.r) - M.l) / (W - M.l - M.r)) * (x1 - x0);
  };
  const hover = (ev) => {
    const s = series[0];
    if (!opts.readout || !s.x.length) return;
    const xv = toX(ev);
    let lo = 0, hi = s.x.length - 1;
    while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (s.x[mid] < xv) lo = mid; else hi = mid; }
    const i = Math.abs(s.x[lo] - xv) <= Math.abs(s.x[hi] - xv) ? lo : hi;
    cross.setAttribute("x1", px(s.x[i])); cross.setAttribute("x2", px(s.x[i])); cross.setAttribute("visibility", "visible");
    dot.setAttribute("cx", px(s.x[i])); dot.setAttribute("cy", py(s.y[i])); dot.setAttribute("visibility", "visible");
    let near = null;
    for (const m of markers) if (!near || Math.abs(m.x - s.x[i]) < Math.abs(near.x - s.x[i])) near = m;
    const nearText = near ? `; nearest marker ${near.sideband ? `${markerLabel(near.name, near.harmonic)} ${near.sideband > 0 ? "+" : "−"} shaft` : markerLabel(near.name, near.harmonic)} at ${fmt(near.x)} ${opts.xUnit || ""}` : "";
    opts.readout.textContent = `${fmt(s.x[i])} ${opts.xUnit || ""}: ${fmt(s.y[i])} ${opts.yUnit || ""}${nearText}`;
  };
  svg.addEventListener("pointerleave", () => { cross.setAttribute("visibility", "hidden"); dot.setAttribute("visibility", "hidden"); });
  let start = null, rect = null;
  svg.addEventListener("pointerdown", (ev) => {
    if (!opts.onZoom) return;
    start = toX(ev);
    rect = el("rect", { class: "selection", x: px(start), y: M.t, width: 0, height: H - M.t - M.b }, svg);
    svg.setPointerCapture(ev.pointerId);
  });
  svg.addEventListener("pointermove", (ev) => {
    hover(ev);
    if (start === null) return;
    const cur = toX(ev);
    rect.setAttribute("x", px(Math.min(start, cur)));
    rect.setAttribute("width", Math.abs(px(cur) - px(start)));
  });
  svg.addEventListener("pointerup", (ev) => {
    if (start === null) return;
    const end = toX(ev);
    rect.remove();
    const [a, b] = [Math.min(start, end), Math.max(start, end)];
    start = null;
    if (b - a > (x1 - x0) * 0.01) opts.onZoom(a, b);
  });
  return svg;
}

/** A keyed legend (HTML, under a chart, never over its data): [{ text, color, dashed, dot }]. */
export function legend(entries) {
  const ul = document.createElement("ul");
  ul.className = "legend";
  for (const e of entries) {
    const li = document.createElement("li");
    const key = el("svg", { width: 22, height: 10, "aria-hidden": "true" });
    if (e.dot) el("circle", { cx: 11, cy: 5, r: 3.5, class: "peak", stroke: e.color }, key);
    else el("line", { x1: 0, x2: 22, y1: 5, y2: 5, stroke: e.color, "stroke-width": 2, "stroke-dasharray": e.dashed || "" }, key);
    li.append(key, ` ${e.text}`);
    ul.append(li);
  }
  return ul;
}

/** A bar chart of `values` at labels `labels`, bar `highlight` in red, and an optional
 * horizontal `reference` line (src/plots/kurtosis.rs draws the same). */
export function barChart(box, { labels, values, xLabel, yLabel, highlight, reference }) {
  box.replaceChildren();
  const W = chartWidth(box);
  const h = W < 600 ? 200 : 224;
  const svg = el("svg", { viewBox: `0 0 ${W} ${h}`, width: W, height: h, role: "img", "aria-label": `${yLabel} by ${xLabel}` }, box);
  const hi = Math.max(...values, reference ?? 0, 1e-12) * 1.15;
  const bw = (W - M.l - M.r) / values.length;
  const py = (v) => h - M.b - (v / hi) * (h - M.t - M.b);
  for (const t of ticks(0, hi, 4)) {
    el("line", { class: "grid", x1: M.l, x2: W - M.r, y1: py(t), y2: py(t) }, svg);
    el("text", { x: M.l - 6, y: py(t) + 4, "text-anchor": "end", class: "tick" }, svg).textContent = fmt(t);
  }
  values.forEach((v, i) => {
    el("rect", { x: M.l + i * bw + bw * 0.15, y: py(v), width: bw * 0.7, height: h - M.b - py(v),
      fill: i === highlight ? PALETTE.bpfo : PALETTE.bpfi }, svg);
    el("text", { x: M.l + (i + 0.5) * bw, y: h - M.b + 16, "text-anchor": "middle", class: "tick" }, svg).textContent = labels[i];
  });
  if (reference !== undefined && isFinite(reference)) el("line", { x1: M.l, x2: W - M.r, y1: py(reference), y2: py(reference), stroke: SERIES[0], "stroke-width": 1 }, svg);
  el("line", { class: "axis", x1: M.l, x2: W - M.r, y1: h - M.b, y2: h - M.b }, svg);
  el("text", { x: (M.l + W - M.r) / 2, y: h - 6, "text-anchor": "middle", class: "axis-title" }, svg).textContent = xLabel;
  el("text", { x: 14, y: h / 2, "text-anchor": "middle", class: "axis-title", transform: `rotate(-90 14 ${h / 2})` }, svg).textContent = yLabel;
  return svg;
}

/** The chart in `box` as a standalone SVG document (styles inlined), for downloads. */
export function svgDocument(box, title) {
  const svg = box.querySelector("svg");
  const copy = svg.cloneNode(true);
  copy.setAttribute("xmlns", NS);
  const style = document.createElementNS(NS, "style");
  style.textContent = `text{font:11px system-ui,sans-serif;fill:#5b6670}.axis{stroke:#8a949c}.grid{stroke:#eef1f3}
.series{fill:none;stroke-width:1.2}.marker{stroke-width:1;stroke-dasharray:4 3}.marker.sideband{stroke-dasharray:1 3}
.peak{stroke-width:1.5}.chart-label{font-size:10px}.crosshair,.hover-dot,.selection{display:none}`;
  copy.insertBefore(style, copy.firstChild);
  const bg = document.createElementNS(NS, "rect");
  bg.setAttribute("width", "100%"); bg.setAttribute("height", "100%"); bg.setAttribute("fill", "#fff");
  copy.insertBefore(bg, style.nextSibling);
  if (title) { const t = document.createElementNS(NS, "title"); t.textContent = title; copy.insertBefore(t, copy.firstChild); }
  return new XMLSerializer().serializeToString(copy);
}

/** Render an SVG document to a PNG blob at twice its size. */
export async function pngBlob(svgText, width, height) {
  const img = new Image();
  const url = URL.createObjectURL(new Blob([svgText], { type: "image/svg+xml" }));
  try {
    img.src = url;
    await img.decode();
    const canvas = document.createElement("canvas");
    canvas.width = width * 2; canvas.height = height * 2;
    const ctx = canvas.getContext("2d");
    ctx.scale(2, 2);
    ctx.drawImage(img, 0, 0, width, height);
    return await new Promise((r) => canvas.toBlob(r, "image/png"));
  } finally {
    URL.revokeObjectURL(url);
  }
}
