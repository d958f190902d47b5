// Small SVG charts for the lab page: a line chart with axes, units, vertical markers and
// drag-to-zoom, and a bar chart. No dependencies; the server decimates long series.

const NS = "http://www.w3.org/2000/svg";
const W = 960, H = 320, M = { l: 64, r: 16, t: 14, b: 42 };

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

export function fmt(v) {
  const a = Math.abs(v);
  if (a === 0) return "0";
  if (a >= 1e5 || a < 1e-3) return v.toExponential(1);
  return Number(v.toPrecision(4)).toString();
}

/**
 * Draw a line chart into `box` (replacing its content).
 * opts: { x: number[], y: number[], xLabel, yLabel, markers: [{x, label, cls}],
 *         onZoom(x0, x1) }  Returns the svg element.
 */
export function lineChart(box, opts) {
  box.replaceChildren();
  const svg = el("svg", { viewBox: `0 0 ${W} ${H}`, role: "img", "aria-label": `${opts.yLabel} against ${opts.xLabel}` }, box);
  const { x, y } = opts;
  const x0 = x.length ? x[0] : 0, x1 = x.length ? x[x.length - 1] : 1;
  let ylo = Infinity, yhi = -Infinity;
  for (const v of y) { if (v < ylo) ylo = v; if (v > yhi) yhi = v; }
  if (!isFinite(ylo)) { ylo = 0; yhi = 1; }
  if (opts.yFromZero) ylo = Math.min(0, ylo);
  if (yhi === ylo) { yhi += 1; ylo -= 1; }
  const pad = (yhi - ylo) * 0.05; yhi += pad; if (!opts.yFromZero) ylo -= pad;
  const px = (v) => M.l + ((v - x0) / ((x1 - x0) || 1)) * (W - M.l - M.r);
  const py = (v) => H - M.b - ((v - ylo) / (yhi - ylo)) * (H - M.t - M.b);
  for (const t of ticks(x0, x1)) {
    el("line", { class: "grid", x1: px(t), x2: px(t), y1: M.t, y2: H - M.b }, svg);
    el("text", { x: px(t), y: H - M.b + 16, "text-anchor": "middle" }, svg).textContent = fmt(t);
  }
  for (const t of ticks(ylo, yhi, 5)) {
    el("line", { class: "grid", x1: M.l, x2: W - M.r, y1: py(t), y2: py(t) }, svg);
    el("text", { x: M.l - 6, y: py(t) + 4, "text-anchor": "end" }, svg).textContent = fmt(t);
  }
  el("line", { class: "axis", x1: M.l, x2: W - M.r, y1: H - M.b, y2: H - M.b }, svg);
  el("line", { class: "axis", x1: M.l, x2: M.l, y1: M.t, y2: H - M.b }, svg);
  el("text", { x: (M.l + W - M.r) / 2, y: H - 6, "text-anchor": "middle" }, svg).textContent = opts.xLabel;
  el("text", { x: 14, y: (M.t + H - M.b) / 2, "text-anchor": "middle", transform: `rotate(-90 14 ${(M.t + H - M.b) / 2})` }, svg).textContent = opts.yLabel;
  // labels on four staggered rows, so neighbouring lines stay readable
  (opts.markers || []).filter((m) => m.x >= x0 && m.x <= x1).forEach((m, i) => {
    el("line", { class: `marker ${m.cls || ""}`, x1: px(m.x), x2: px(m.x), y1: M.t, y2: H - M.b, "data-marker": m.label }, svg);
    el("text", { class: `marker-label ${m.cls || ""}`, x: px(m.x) + 2, y: M.t + 10 + (i % 4) * 11 }, svg).textContent = m.label;
  });
  let d = "";
  for (let i = 0; i < x.length; i++) d += `${i ? "L" : "M"}${px(x[i]).toFixed(1)},${py(y[i]).toFixed(1)}`;
  el("path", { class: "series", d }, svg);
  if (opts.onZoom) {
    // drag across the plot to zoom into that range
    const toX = (ev) => {
      const r = svg.getBoundingClientRect();
      const sx = ((ev.clientX - r.left) / r.width) * W;
      return x0 + ((Math.min(Math.max(sx, M.l), W - M.r) - M.l) / (W - M.l - M.r)) * (x1 - x0);
    };
    let start = null, rect = null;
    svg.addEventListener("pointerdown", (ev) => {
      start = toX(ev);
      rect = el("rect", { class: "selection", x: px(start), y: M.t, width: 0, height: H - M.t - M.b }, svg);
      svg.setPointerCapture(ev.pointerId);
    });
    svg.addEventListener("pointermove", (ev) => {
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
  }
  return svg;
}

/** A bar chart of `values` at labels `labels`. */
export function barChart(box, { labels, values, xLabel, yLabel, highlight }) {
  box.replaceChildren();
  const svg = el("svg", { viewBox: `0 0 ${W} ${H * 0.7}`, role: "img", "aria-label": `${yLabel} by ${xLabel}` }, box);
  const h = H * 0.7;
  const hi = Math.max(...values, 1e-12) * 1.1;
  const bw = (W - M.l - M.r) / values.length;
  const py = (v) => h - M.b - (v / hi) * (h - M.t - M.b);
  for (const t of ticks(0, hi, 4)) {
    el("line", { class: "grid", x1: M.l, x2: W - M.r, y1: py(t), y2: py(t) }, svg);
    el("text", { x: M.l - 6, y: py(t) + 4, "text-anchor": "end" }, svg).textContent = fmt(t);
  }
  values.forEach((v, i) => {
    el("rect", { x: M.l + i * bw + bw * 0.15, y: py(v), width: bw * 0.7, height: h - M.b - py(v),
      fill: i === highlight ? "#0b5cad" : "#9bb7d4" }, svg);
    el("text", { x: M.l + (i + 0.5) * bw, y: h - M.b + 16, "text-anchor": "middle" }, svg).textContent = labels[i];
  });
  el("line", { class: "axis", x1: M.l, x2: W - M.r, y1: h - M.b, y2: h - M.b }, svg);
  el("text", { x: (M.l + W - M.r) / 2, y: h - 6, "text-anchor": "middle" }, svg).textContent = xLabel;
  el("text", { x: 14, y: h / 2, "text-anchor": "middle", transform: `rotate(-90 14 ${h / 2})` }, svg).textContent = yLabel;
  return svg;
}
