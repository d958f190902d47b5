// The lab page: submit simulations, studies and recordings, watch jobs (long polls, no
// hammering), look at results, download them, and compare jobs. Plain ES modules served by
// the service; no build step.

import { lineChart, barChart, fmt, legend, markerLabel, lineName, PALETTE, SERIES, svgDocument, pngBlob } from "/assets/plot.js";

const view = document.getElementById("view");
const banner = document.getElementById("banner");
const tokenInput = document.getElementById("token");
tokenInput.value = localStorage.getItem("bearing-sim-token") || "";
tokenInput.addEventListener("change", () => {
  localStorage.setItem("bearing-sim-token", tokenInput.value.trim());
  route();
});

// Each view gets a generation number; loops of an older view stop when it changes.
let generation = 0;

function showBanner(text) {
  banner.textContent = text;
  banner.hidden = !text;
}

/** Call the API: { status, body, headers }. A network failure shows the banner and throws. */
async function api(path, opts = {}) {
  const headers = new Headers(opts.headers || {});
  const token = tokenInput.value.trim();
  if (token) headers.set("Authorization", `Bearer ${token}`);
  let res;
  try {
    res = await fetch(path, { ...opts, headers });
  } catch (e) {
    showBanner(`The service at ${location.origin} is unreachable (${e.message}). Retrying when you act again.`);
    throw e;
  }
  showBanner("");
  const type = res.headers.get("content-type") || "";
  const body = type.includes("json") ? await res.json() : await res.text();
  if (res.status === 401) showBanner("The service requires an API token: enter it at the top right.");
  return { status: res.status, body, headers: res.headers };
}

function h(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k.startsWith("on")) e.addEventListener(k.slice(2), v);
    else if (v !== undefined && v !== null && v !== false) e.setAttribute(k, v === true ? "" : v);
  }
  for (const c of children.flat()) if (c !== null && c !== undefined) e.append(c instanceof Node ? c : String(c));
  return e;
}

const when = (iso) => (iso ? new Date(iso).toLocaleTimeString() : "");
const collection = (kind) => (kind === "analysis" ? "analyses" : "simulations");
/** A table in a box that scrolls sideways by itself, so the page never does. */
const scrollBox = (table) => h("div", { class: "table-scroll" }, table);

/** Save `blob` under `name` (a download the browser offers). */
function save(blob, name) {
  const a = h("a", { href: URL.createObjectURL(blob), download: name, hidden: true });
  document.body.append(a);
  a.click();
  setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
}
const csvCell = (v) => (typeof v === "string" && /[",\n]/.test(v) ? `"${v.replace(/"/g, '""')}"` : v ?? "");
const csv = (rows) => new Blob([rows.map((r) => r.map(csvCell).join(",")).join("\n") + "\n"], { type: "text/csv" });
/** A file name from a job's name: letters, digits and dashes. */
const slug = (s) => (s || "job").toLowerCase().replace(/[^a-z0-9]+/g, "-").replace(/^-|-$/g, "").slice(0, 60) || "job";

/** SVG and PNG buttons for the chart in `box`, named `name`. `name` and `title` may be
 * functions, read at the click: a chart that redraws keeps its buttons, since a button
 * replaced between a press and its release loses the click. */
function chartDownloads(box, name, title) {
  const now = (v) => (typeof v === "function" ? v() : v);
  const svgText = () => svgDocument(box, now(title));
  // nothing to save before the chart is drawn
  return h("span", { class: "downloads" },
    h("button", { type: "button", "data-download": "svg", onclick: () => box.querySelector("svg") && save(new Blob([svgText()], { type: "image/svg+xml" }), `${now(name)}.svg`) }, "SVG"),
    h("button", { type: "button", "data-download": "png", onclick: async () => {
      const s = box.querySelector("svg");
      if (!s) return;
      save(await pngBlob(svgText(), Number(s.getAttribute("width")), Number(s.getAttribute("height"))), `${now(name)}.png`);
    } }, "PNG"));
}

// ---------------------------------------------------------------- jobs list

async function jobsView(gen) {
  const tbody = h("tbody");
  const chosen = new Set();
  const compare = h("button", { id: "compare", disabled: true, onclick: () => { location.hash = `#/compare/${[...chosen].join(",")}`; } }, "Compare selected");
  view.replaceChildren(
    h("h2", {}, "Jobs"),
    h("p", { class: "muted" }, "Simulations and analyses, newest first. States update as they change. Tick two or more finished jobs to compare them. ", compare),
    scrollBox(h("table", { id: "jobs" },
      h("thead", {}, h("tr", {}, h("th", {}, ""), h("th", {}, "kind"), h("th", {}, "job"), h("th", {}, "state"),
        h("th", {}, "progress"), h("th", { class: "hide-narrow" }, "created"), h("th", { class: "hide-narrow" }, "finished"), h("th", {}, ""))),
      tbody)),
  );
  const rows = new Map();
  const render = (job) => {
    const kind = collection(job.kind);
    const key = `${kind}:${job.id}`;
    const actions = h("td", {});
    if (job.state === "queued" || job.state === "running") {
      actions.append(h("button", { onclick: () => cancel(kind, job.id), "aria-label": `cancel ${job.label}` }, "Cancel"));
    } else {
      actions.append(h("button", { onclick: () => remove(kind, job.id), "aria-label": `delete ${job.label}` }, "Delete"));
    }
    const tick = h("input", { type: "checkbox", class: "pick", "aria-label": `compare ${job.label}`, disabled: job.state !== "succeeded", checked: chosen.has(key),
      onchange: (ev) => { if (ev.target.checked) chosen.add(key); else chosen.delete(key); compare.disabled = chosen.size < 2; } });
    const row = h("tr", { "data-id": job.id, "data-state": job.state },
      h("td", {}, tick),
      h("td", {}, job.kind),
      h("td", { class: "job-name" }, h("a", { href: `#/${kind}/${job.id}` }, job.label || job.id)),
      h("td", { class: `state-${job.state}` }, job.state),
      h("td", {}, h("progress", { max: 1, value: job.progress ?? 0, "aria-label": "progress" })),
      h("td", { class: "hide-narrow" }, when(job.created_at)),
      h("td", { class: "hide-narrow" }, when(job.finished_at)),
      actions);
    const old = rows.get(job.id);
    if (old) old.replaceWith(row); else tbody.append(row);
    rows.set(job.id, row);
  };
  const refresh = async () => {
    const [s, a] = await Promise.all([api("/v1/simulations?limit=50"), api("/v1/analyses?limit=50")]);
    if (gen !== generation) return [];
    const jobs = [...(s.body.items || []), ...(a.body.items || [])]
      .sort((x, y) => (x.created_at < y.created_at ? 1 : -1));
    tbody.replaceChildren();
    rows.clear();
    jobs.forEach(render);
    if (!jobs.length) tbody.append(h("tr", {}, h("td", { colspan: 8, class: "muted" }, "No jobs yet. Start a simulation or analyse a recording.")));
    return jobs;
  };
  const watched = new Set();
  const watch = (job) => {
    if (watched.has(job.id) || !(job.state === "queued" || job.state === "running")) return;
    watched.add(job.id);
    follow(gen, collection(job.kind), job.id, (j) => render(j)).finally(() => watched.delete(job.id));
  };
  try {
    (await refresh()).forEach(watch);
  } catch { /* banner shown */ }
  // new jobs from other clients appear within 10 s; running ones are long-polled
  while (gen === generation) {
    await sleep(10000);
    if (gen !== generation) break;
    try { (await refresh()).forEach(watch); } catch { /* banner shown */ }
  }
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

/** Long-poll a job until it finishes (or the view changes), calling `onChange` with each version. */
async function follow(gen, kind, id, onChange) {
  let etag = null;
  while (gen === generation) {
    let r;
    try {
      r = await api(`/v1/${kind}/${id}?wait=25`, { headers: etag ? { "If-None-Match": etag } : {} });
    } catch {
      await sleep(3000);
      continue;
    }
    if (r.status === 304) continue;
    if (r.status !== 200) return null;
    etag = r.headers.get("etag");
    onChange(r.body);
    if (["succeeded", "failed", "cancelled"].includes(r.body.state)) return r.body;
  }
  return null;
}

async function cancel(kind, id) {
  const r = await api(`/v1/${kind}/${id}/cancel`, { method: "POST" });
  if (r.status >= 400) showBanner(r.body.detail || `cancel failed (${r.status})`);
  route();
}

async function remove(kind, id) {
  const r = await api(`/v1/${kind}/${id}`, { method: "DELETE" });
  if (r.status >= 400) showBanner(r.body.detail || `delete failed (${r.status})`);
  if (location.hash.includes(id)) location.hash = "#/"; else route();
}

// ---------------------------------------------------------------- numbers typed into forms

const NUMBER = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;

/**
 * A typed number, or why it is not one: { value } or { error }. Blank is an error (the form
 * shows the preset's value to start with, so blank never silently means "the default").
 */
function parseNumber(text, { blank } = {}) {
  const t = text.trim();
  if (t === "") return { error: blank || "required: enter a number" };
  if (!NUMBER.test(t)) return { error: `"${t}" is not a number` };
  return { value: Number(t) };
}

/** A number field: text input (nothing is rounded or dropped by the browser), unit and range shown. */
function field(path, label, value, extra = {}) {
  const id = `f-${path.replace(/[^a-z0-9]/gi, "-")}`;
  const hint = [extra.unit && `unit ${extra.unit}`, extra.range].filter(Boolean).join(", ");
  return h("div", { class: "field", "data-path": path },
    h("label", { for: id }, label),
    extra.options
      ? h("select", { id, name: path }, extra.options.map((o) => h("option", { value: o, selected: o === value }, o)))
      : h("input", { id, name: path, type: "text", inputmode: extra.text ? "text" : "decimal", autocomplete: "off", spellcheck: "false",
        value: extra.text ? value : Number(Number(value).toPrecision(12)), "aria-describedby": `${id}-hint` }),
    hint ? h("div", { class: "hint", id: `${id}-hint` }, hint) : null,
    h("div", { class: "error", "aria-live": "polite" }),
    h("div", { class: "warning", "aria-live": "polite" }));
}

function clearMarks(form) {
  form.querySelectorAll(".field").forEach((f) => {
    f.classList.remove("invalid");
    for (const c of [".error", ".warning"]) { const e = f.querySelector(c); if (e) e.textContent = ""; }
  });
}

function markField(form, path, message, cls = "error") {
  const box = form.querySelector(`.field[data-path="${CSS.escape(path)}"]`);
  if (!box) return false;
  if (cls === "error") box.classList.add("invalid");
  box.querySelector(`.${cls}`).textContent = message;
  return true;
}

// ---------------------------------------------------------------- submit a simulation

// Form fields: [path in the scene, label, unit shown, factor from the shown unit to SI, range]
const FIELDS = [
  ["operating.speed.steady_rpm", "Steady speed", "rev/min", 1, "> 0"],
  ["operating.speed.initial_rpm", "Initial speed", "rev/min", 1, ">= 0"],
  ["operating.speed.ramp_time", "Ramp time", "s", 1, ">= 0"],
  ["operating.axial_load", "Axial load", "N", 1, ">= 0"],
  ["operating.radial_load", "Radial load", "N", 1, ">= 0"],
  ["solver.duration", "Duration", "s", 1, "> 0; the preset's: "],
  ["solver.sample_rate", "Output sample rate", "Hz", 1, "> 0"],
  ["solver.rtol", "Relative tolerance", "-", 1, "0 < rtol < 1"],
];
const FAULT_FIELDS = [["width", "Width", "mm", 1e-3, "> 0"], ["depth", "Depth", "mm", 1e-3, ">= 0"], ["angle", "Angle", "deg", Math.PI / 180, "position on the ring"]];

function getPath(obj, path) {
  return path.split(".").reduce((o, k) => (o == null ? undefined : o[k]), obj);
}
function setPath(obj, path, value) {
  const keys = path.split(".");
  let o = obj;
  keys.slice(0, -1).forEach((k) => { o = o[k] ??= {}; });
  o[keys.at(-1)] = value;
}

/** Characteristic frequencies (Hz) from the geometry at a shaft speed, to warn before a run. */
function kinematics(bearing, rpm) {
  const fr = rpm / 60;
  const pitch = (bearing.inner_groove_diameter + bearing.outer_groove_diameter) / 2;
  const g = (bearing.ball_diameter / pitch) * Math.cos(bearing.contact_angle);
  return { fr, bpfo: (bearing.ball_count / 2) * fr * (1 - g), bpfi: (bearing.ball_count / 2) * fr * (1 + g) };
}

/** Likely mistakes in parsed values: [path, warning]. */
function warnings(scene, v, faults) {
  const out = [];
  const dur = v["solver.duration"], ramp = v["operating.speed.ramp_time"], fs = v["solver.sample_rate"];
  if (dur !== undefined && ramp !== undefined && ramp > 0 && dur <= ramp * 1.2) {
    out.push(["solver.duration", `the run ends ${dur <= ramp ? "inside" : "just after"} the ${fmt(ramp)} s speed ramp: the analysed window sees a changing speed or is too short`]);
  }
  const rpm = v["operating.speed.steady_rpm"];
  if (rpm > 0 && fs > 0 && dur > 0) {
    const k = kinematics(scene.bearing, rpm);
    if (3 * k.bpfi > 0.4 * fs) out.push(["solver.sample_rate", `3×BPFI is ${fmt(3 * k.bpfi)} Hz, near the Nyquist frequency ${fmt(fs / 2)} Hz`]);
    const window = dur - (ramp || 0);
    if (window > 0 && 1 / window > k.bpfo / 4) out.push(["solver.duration", `the steady window (${fmt(window)} s) resolves ${fmt(1 / window)} Hz: BPFO (${fmt(k.bpfo)} Hz) sits in the first few bins, near DC`]);
  }
  const r = scene.bearing.ball_diameter / 2;
  faults.forEach((f, i) => {
    if (!(f.width > 0 && f.depth >= 0)) return;
    const reach = f.width / 2 >= r ? r : r - Math.sqrt(r * r - (f.width / 2) ** 2);
    if (f.depth > reach) out.push([`faults[${i}].depth`, `deeper than a ball can feel in a ${fmt(f.width * 1e3)} mm wide defect (${fmt(reach * 1e3)} mm): the extra depth changes nothing`]);
  });
  return out;
}

async function newView(gen) {
  const presets = (await api("/v1/presets")).body.items.filter((p) => p.simulation);
  if (gen !== generation) return;
  const preset = (await api(`/v1/presets/${presets[0].name}`)).body;
  const scene = preset.scene;
  const form = h("form", { novalidate: true, id: "submit-form" });
  const patch = h("pre", { class: "patch", id: "patch", "aria-label": "request body" });
  const caseSelect = h("select", { id: "fault-case", name: "fault_case" },
    preset.fault_cases.map((c) => h("option", { value: c, selected: c === "compound" }, c)));
  const faultBox = h("div", { class: "grid" });
  const fieldsWithPreset = FIELDS.map(([p, l, u, f, range]) => {
    const preset_value = getPath(scene, p);
    return field(p, `${l} (${u})`, preset_value / f, { unit: u, range: range.endsWith(": ") ? `${range}${fmt(preset_value / f)}` : range });
  });
  const general = h("div", { class: "grid" },
    field("name", "Job name", "", { text: true, range: "blank: the preset's name for the fault case" }),
    fieldsWithPreset,
    field("solver.integrator", "Integrator", scene.solver.integrator, { options: ["auto_slip", "auto_etd", "etd_rk4", "rk4_fsal", "slip_implicit", "rk4_adaptive", "rk4_fixed", "rosenbrock_w", "auto"] }),
    field("solver.fidelity", "Fidelity level", scene.solver.fidelity || "full", { options: ["full", "quasi_static_balls", "concentric_cage"] }));
  const caseFaults = () => preset.fault_case_faults?.[caseSelect.value]?.faults || [];
  const renderFaults = () => {
    faultBox.replaceChildren(...caseFaults().map((f, i) => h("fieldset", {},
      h("legend", {}, `${f.ring} race defect`),
      FAULT_FIELDS.map(([k, l, u, factor, range]) => field(`faults[${i}].${k}`, `${l} (${u})`, f[k] / factor, { unit: u, range })),
      h("input", { type: "hidden", name: `faults[${i}].ring`, value: f.ring }))));
    update();
  };
  /** The request, or the fields that do not parse: { body } or { errors: [[path, message]] }. */
  const read = () => {
    const overrides = {}, errors = [], values = {};
    for (const [p, , u, factor] of FIELDS) {
      const r = parseNumber(form.elements[p].value, { blank: `required: a value in ${u} (the preset's is ${fmt(getPath(scene, p) / factor)})` });
      if (r.error) errors.push([p, r.error]); else { values[p] = r.value * factor; setPath(overrides, p, r.value * factor); }
    }
    const name = form.elements.name.value.trim();
    if (name) overrides.name = name;
    setPath(overrides, "solver.integrator", form.elements["solver.integrator"].value);
    setPath(overrides, "solver.fidelity", form.elements["solver.fidelity"].value);
    const faults = caseFaults().map((f, i) => {
      const out = { ring: f.ring };
      for (const [k, , u, factor] of FAULT_FIELDS) {
        const r = parseNumber(form.elements[`faults[${i}].${k}`].value, { blank: `required: a value in ${u}` });
        if (r.error) errors.push([`faults[${i}].${k}`, r.error]); else out[k] = r.value * factor;
      }
      return out;
    });
    if (faults.length) overrides.faults = faults;
    return { body: { preset: preset.name, fault_case: caseSelect.value, overrides }, errors, warnings: warnings(scene, values, faults) };
  };
  const update = () => {
    const r = read();
    clearMarks(form);
    for (const [p, m] of r.errors) markField(form, p, m);
    for (const [p, m] of r.warnings) markField(form, p, m, "warning");
    patch.textContent = JSON.stringify(r.body, null, 2);
  };
  caseSelect.addEventListener("change", renderFaults);
  form.addEventListener("input", update);
  const status = h("p", { id: "submit-status", "aria-live": "polite" });
  form.addEventListener("submit", async (ev) => {
    ev.preventDefault();
    update();
    const req = read();
    if (req.errors.length) {
      status.textContent = `Not submitted: ${req.errors.length} field${req.errors.length > 1 ? "s need" : " needs"} a value.`;
      form.querySelector(".field.invalid input")?.focus();
      return;
    }
    status.textContent = "Submitting…";
    const r = await api("/v1/simulations", { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(req.body) });
    if (r.status === 202 || r.status === 200) {
      location.hash = `#/simulations/${r.body.id}`;
      return;
    }
    status.textContent = r.body.detail || `refused (${r.status})`;
    for (const e of r.body.errors || []) markField(form, e.path.replace(/^scene\./, ""), e.message);
  });
  form.append(
    h("fieldset", {}, h("legend", {}, "Bearing and fault"),
      h("div", { class: "grid" },
        h("div", { class: "field" }, h("label", { for: "preset" }, "Preset"),
          h("select", { id: "preset", disabled: presets.length < 2 }, presets.map((p) => h("option", { value: p.name }, p.title)))),
        h("div", { class: "field", "data-path": "fault_case" }, h("label", { for: "fault-case" }, "Fault case"), caseSelect, h("div", { class: "error" }))),
      faultBox),
    h("fieldset", {}, h("legend", {}, "Operating point and solver"), general),
    h("p", {}, h("button", { type: "submit", class: "primary" }, "Submit simulation")),
    status,
    h("h3", {}, "Request body (a JSON merge patch over the preset)"), patch);
  view.replaceChildren(h("h2", {}, "New simulation"),
    h("p", { class: "muted" }, "Every field starts at the preset's value; a blank or unreadable field is an error, never a silent default. Warnings point at likely mistakes and do not stop a run."), form);
  renderFaults();
}

// ---------------------------------------------------------------- upload a recording
// The file goes to the service's one reader: listed first (POST /v1/recordings/inspect),
// so the channels, sample rate and shaft speed the file carries are shown and a channel is
// chosen, with a time plot of it; then uploaded as it is (POST /v1/analyses?filename=...).

const RECORDING_TYPES = ".mat,.wav,.csv,.tsv,.tab,.txt,.f32le,.f32,.raw,.bin,.json";
const PREVIEW_POINTS = 2000;

async function uploadView() {
  const form = h("form", { id: "upload-form" });
  const status = h("p", { id: "upload-status", "aria-live": "polite" });
  const about = h("p", { id: "recording-about", class: "muted" });
  const preview = h("div", { id: "recording-preview" });
  const previewBox = h("div", { class: "plot", hidden: true }, h("h3", {}, "The chosen channel"), preview);
  const field = (path, label, input) =>
    h("div", { class: "field", "data-path": path }, h("label", { for: input.id }, label), input, h("div", { class: "error" }));
  const channel = h("select", { id: "channel" });
  form.append(
    h("div", { class: "grid" },
      field("file", "Recording (.mat, .wav, .csv/.tsv, f32 little-endian, JSON array)", h("input", { id: "file", type: "file", accept: RECORDING_TYPES, required: true })),
      field("channel", "Channel", channel),
      field("sample_rate", "Sample rate (Hz)", h("input", { id: "fs", type: "number", step: "any" })),
      field("shaft_rpm", "Shaft speed (rev/min)", h("input", { id: "rpm", type: "number", step: "any" })),
      h("div", { class: "field" }, h("label", { for: "bearing" }, "Bearing"), h("select", { id: "bearing" }, ["cwru6205", "h7005c"].map((b) => h("option", { value: b }, b)))),
      field("kurtogram_levels", "Kurtogram levels (blank: none)", h("input", { id: "kurtogram", type: "number", min: 1, max: 12, step: 1 }))),
    about, previewBox,
    h("p", {}, h("button", { type: "submit", class: "primary" }, "Analyse")), status);
  const fileInput = form.querySelector("#file"), fsInput = form.querySelector("#fs"), rpmInput = form.querySelector("#rpm");
  let listing = null, previews = [];

  const clearErrors = () => form.querySelectorAll(".field.invalid").forEach((b) => {
    b.classList.remove("invalid"); b.querySelector(".error").textContent = "";
  });
  const showProblem = (r) => {
    status.textContent = r.body.detail || `refused (${r.status})`;
    for (const e of r.body.errors || []) {
      // uploads name options by their query parameter, JSON ones as options.<name>
      const box = form.querySelector(`.field[data-path="${CSS.escape(e.path)}"]`)
        || form.querySelector(`.field[data-path="${CSS.escape(e.path.replace(/^options\./, ""))}"]`);
      if (box) { box.classList.add("invalid"); box.querySelector(".error").textContent = e.message; }
    }
  };
  const plotChannel = () => {
    const c = listing && listing.channels[Number(channel.value)];
    const y = c && previews[c.index];
    previewBox.hidden = !(y && y.length);
    if (previewBox.hidden) return;
    const rate = listing.sample_rate ? listing.sample_rate.value : Number(fsInput.value) || null;
    const step = c.samples / y.length;
    const x = y.map((_, k) => (rate ? (k * step) / rate : k * step));
    lineChart(preview, { x, y, xLabel: rate ? "time (s)" : "sample", yLabel: c.unit ? `${c.name} (${c.unit})` : c.name });
  };
  channel.addEventListener("change", plotChannel);
  fsInput.addEventListener("change", plotChannel);

  fileInput.addEventListener("change", async () => {
    clearErrors();
    listing = null; previews = [];
    channel.replaceChildren();
    about.textContent = ""; previewBox.hidden = true;
    const file = fileInput.files[0];
    if (!file) return;
    status.textContent = "Reading the file…";
    const q = new URLSearchParams({ filename: file.name, preview: PREVIEW_POINTS });
    const r = await api(`/v1/recordings/inspect?${q}`, { method: "POST", headers: { "Content-Type": "application/octet-stream" }, body: await file.arrayBuffer() });
    if (r.status !== 200) { showProblem(r); return; }
    status.textContent = "";
    listing = r.body;
    previews = listing.channels.map((c) => c.preview || []);
    for (const c of listing.channels) {
      const text = `${c.index}: ${c.name} (${c.samples} samples${c.unit ? `, ${c.unit}` : ""})`;
      channel.append(h("option", { value: c.index }, text));
    }
    const rate = listing.sample_rate, speed = listing.shaft_rpm;
    // what the file carries fills the fields; what it lacks is left as the user typed it
    if (rate) fsInput.value = rate.value;
    fsInput.placeholder = rate ? "" : "not in the file: required";
    if (speed) rpmInput.value = speed.value;
    rpmInput.placeholder = speed ? "" : "not in the file: required";
    about.textContent = [
      `${listing.format} file, ${listing.channels.length} channel${listing.channels.length === 1 ? "" : "s"}`,
      rate ? `sample rate ${fmt(rate.value)} Hz (${rate.from})` : "no sample rate in the file",
      speed ? `shaft speed ${fmt(speed.value)} rev/min (${speed.from})` : "no shaft speed in the file",
      ...listing.skipped.map((s) => `skipped ${s.name}: ${s.reason}`),
    ].join("; ");
    plotChannel();
  });

  form.addEventListener("submit", async (ev) => {
    ev.preventDefault();
    clearErrors();
    const file = fileInput.files[0];
    if (!file) { status.textContent = "Choose a file first."; return; }
    const q = new URLSearchParams({ mode: "async", filename: file.name, preset: form.querySelector("#bearing").value });
    if (channel.value !== "") q.set("channel", channel.value);
    const fromFile = (s) => s && listing && listing[s];
    if (fsInput.value && !fromFile("sample_rate")) q.set("sample_rate", fsInput.value);
    if (rpmInput.value && !(fromFile("shaft_rpm") && Number(rpmInput.value) === listing.shaft_rpm.value)) {
      q.set("shaft_rpm", rpmInput.value);
    }
    const kl = form.querySelector("#kurtogram").value;
    if (kl) q.set("kurtogram_levels", kl);
    status.textContent = "Uploading…";
    const r = await api(`/v1/analyses?${q}`, { method: "POST", headers: { "Content-Type": "application/octet-stream" }, body: await file.arrayBuffer() });
    if (r.status === 202 || r.status === 200) { location.hash = `#/analyses/${r.body.id}`; return; }
    showProblem(r);
  });
  view.replaceChildren(h("h2", {}, "Analyse a recording"),
    h("p", { class: "muted" }, "The envelope spectrum and the DTCWT components of a measured signal, with the bearing's fault frequencies. The file's channels are listed before it is analysed."), form);
}

// ---------------------------------------------------------------- one job

async function jobView(gen, kind, id) {
  const head = h("div", {});
  const body = h("div", {});
  view.replaceChildren(head, body);
  const renderHead = (job) => {
    head.replaceChildren(
      h("h2", { id: "job-name" }, job.label || job.id),
      h("p", {},
        h("span", { class: `state-${job.state}`, id: "job-state" }, job.state), " ",
        h("progress", { max: 1, value: job.progress ?? 0, "aria-label": "progress" }), " ",
        job.state === "queued" || job.state === "running"
          ? h("button", { onclick: () => cancel(kind, id), id: "cancel" }, "Cancel")
          : h("button", { onclick: () => remove(kind, id) }, "Delete"),
        " ", h("span", { class: "muted" }, `created ${when(job.created_at)}`,
          job.stats?.wall_time ? `, solver ${fmt(job.stats.wall_time)} s, ${job.stats.accepted_steps} steps` : "")),
      ...(job.error ? [h("p", { class: "error" }, `${job.error.kind}: ${job.error.message}`)] : []));
  };
  const first = await api(`/v1/${kind}/${id}`);
  if (first.status !== 200) { view.replaceChildren(h("p", { class: "error" }, first.body.detail || "not found")); return; }
  renderHead(first.body);
  let job = first.body;
  if (!["succeeded", "failed", "cancelled"].includes(job.state)) {
    job = await follow(gen, kind, id, renderHead);
    if (!job || gen !== generation) return;
  }
  if (job.state !== "succeeded") return;
  const result = (await api(`/v1/${kind}/${id}/result`)).body;
  if (gen !== generation) return;
  renderResult(kind, id, result, body, job.label || id);
}

const FAULT = { outer_race: "outer race", inner_race: "inner race", rolling_element: "rolling element", cage: "cage" };

/** A result's headline numbers: [{ label, text, value, unit }] (cards, CSV and comparisons). */
function summaryRows(result) {
  const a = result.analysis, rows = [];
  const add = (label, value, unit, text) => rows.push({ label, value, unit, text: text ?? (typeof value === "number" ? `${fmt(value)}${unit && unit !== "-" ? " " + unit : ""}` : String(value ?? "")) });
  if (result.cage) {
    add("Mean cage speed", result.cage.mean_speed, "rad/s");
    add("Cage slip", result.cage.slip * 100, "%");
    add("Cage motion", result.cage.motion?.state ?? "", "");
  }
  if (result.frequencies) {
    const f = result.frequencies;
    add("BPFO simulated", f.simulated.bpfo, "Hz"); add("BPFO theory", f.nominal.bpfo, "Hz"); add("BPFO error", f.bpfo_error_pct, "%");
    add("BPFI simulated", f.simulated.bpfi, "Hz"); add("BPFI theory", f.nominal.bpfi, "Hz"); add("BPFI error", f.bpfi_error_pct, "%");
  }
  if (a) {
    if (a.verdict) add("Verdict", a.verdict.faults.length ? a.verdict.faults.map((f) => FAULT[f] ?? f).join(" + ") : "no fault indicated", "");
    add("Shaft frequency", a.theory.shaft_hz, "Hz");
    add("Best DTCWT level", a.best_component.level, "-");
    add("Best component kurtosis", a.best_component.kurtosis, "-");
    const detected = (a.raw || []).filter((r) => r.detected).map((r) => `${r.name}×${r.harmonic}`);
    add("Detected in the raw spectrum", detected.join(" ") || "none", "");
  }
  return rows;
}

/** Every identification table of an analysis: [[title, rows, table id, spectrum]]. */
function idSets(a) {
  const sets = [[`Identified in the raw envelope spectrum`, a.raw, "ids-raw", "raw"],
    [`Identified in the best DTCWT component (level ${a.best_component.level}, kurtosis ${fmt(a.best_component.kurtosis)})`, a.best_component.identifications, "ids-best", `level ${a.best_component.level}`]];
  for (const [k, tid, what] of [[a.kurtogram, "ids-kurtogram", "kurtogram's band"], [a.kurtogram_runner_up, "ids-kurtogram-runner-up", "kurtogram's runner-up band"]]) {
    if (k) sets.push([`Identified in the ${what} (${fmt(k.band_hz[0])}-${fmt(k.band_hz[1])} Hz, level ${fmt(k.level)}, spectral kurtosis ${fmt(k.kurtosis)})`, k.identifications, tid, `${what} ${fmt(k.band_hz[0])}-${fmt(k.band_hz[1])} Hz`]);
  }
  return sets;
}

function renderResult(kind, id, result, box, name) {
  const a = result.analysis;
  const file = slug(name);
  // the verdict's own sentence, when the service gives one, before anything else
  if (a?.verdict?.summary) box.append(h("p", { class: "verdict-summary", id: "verdict-summary" }, a.verdict.summary));
  const rows = summaryRows(result);
  box.append(h("div", { class: "cards", id: "summary" }, rows.map((r) => h("div", { class: "card" }, h("div", { class: "label" }, r.label), h("div", { class: "big" }, r.text)))));
  const downloads = h("p", { class: "downloads", id: "downloads" }, h("span", { class: "muted" }, "Download: "),
    h("button", { type: "button", "data-download": "summary-csv", onclick: () => save(csv([["quantity", "value", "unit"], ...rows.map((r) => [r.label, r.value, r.unit])]), `${file}-summary.csv`) }, "summary CSV"));
  box.append(downloads);
  if (!a) { box.append(h("p", { class: "muted" }, result.analysis_error || "No analysis.")); return; }
  downloads.append(" ", h("button", { type: "button", "data-download": "identifications-csv", onclick: () => save(csv([
    ["spectrum", "line", "harmonic", "theory_hz", "identified_hz", "error_pct", "prominence_db", "detected", "in_verdict"],
    ...idSets(a).flatMap(([, ids, , spectrum]) => ids.map((r) => [spectrum, r.name, r.harmonic, r.theory_hz, r.identified_hz, r.error_pct, r.prominence_db, r.detected, !!r.in_verdict]))]), `${file}-identifications.csv`) }, "identifications CSV"));
  if (kind === "simulations") {
    downloads.append(" ", h("span", { class: "muted" }, "the service's charts: "),
      ...["spectrum.svg", "signal.svg", "kurtosis.svg"].map((p) => h("a", { href: `/v1/simulations/${id}/plots/${p}`, class: "service-plot", target: "_blank", rel: "noopener" }, p, " ")));
  }
  if (a.verdict) {
    const v = a.verdict;
    const vrows = v.evidence.map((e) => h("tr", {},
      h("td", {}, FAULT[e.fault] ?? e.fault), h("td", {}, e.indicated ? "yes" : "no"), h("td", {}, e.p_value.toExponential(1)),
      h("td", {}, e.spectrum), h("td", {}, e.harmonics_searched ? `${e.harmonics_found}/${e.harmonics_searched}` : "-"),
      h("td", {}, e.fundamental_hz == null ? "no line in the search band" : `${fmt(e.fundamental_hz)} Hz (${fmt(e.error_pct)} %)`)));
    box.append(h("div", { class: "plot", id: "verdict" }, h("h3", {}, `Verdict (false-alarm rate ${v.false_alarm_rate} per type)`),
      scrollBox(h("table", {}, h("thead", {}, h("tr", {}, ...["fault type", "indicated", "p", "spectrum", "harmonics found", "fundamental"].map((t) => h("th", {}, t)))), h("tbody", {}, ...vrows)))));
  }
  for (const [title, ids, tid] of idSets(a)) box.append(idTable(title, ids, tid));
  if (kind === "simulations") box.append(signalPlot(id, result, name));
  box.append(spectrumPlot(kind, id, a, name));
  const kbox = h("div", { id: "kurtosis-chart" });
  const best = a.best_component.level;
  const kLegend = [{ text: "component kurtosis", color: PALETTE.bpfi }, { text: `level ${best}: the largest, analysed`, color: PALETTE.bpfo }];
  if (isFinite(a.raw_kurtosis)) kLegend.push({ text: `raw signal kurtosis (${fmt(a.raw_kurtosis)})`, color: SERIES[0] });
  box.append(h("div", { class: "plot" }, h("h3", {}, `DTCWT component kurtosis: ${name}`, " ", chartDownloads(kbox, `${file}-kurtosis`, `DTCWT component kurtosis: ${name}`)), kbox, legend(kLegend)));
  requestAnimationFrame(() => barChart(kbox, { labels: a.level_kurtosis.map((_, i) => `${i + 1}`), values: a.level_kurtosis,
    xLabel: "DTCWT level (1 = highest frequencies)", yLabel: "kurtosis (-)", highlight: best - 1, reference: a.raw_kurtosis ?? undefined }));
}

function idTable(title, ids, tid) {
  return h("div", { class: "plot" }, h("h3", {}, title),
    scrollBox(h("table", { id: tid },
      h("thead", {}, h("tr", {}, ["line", "harmonic", "theory (Hz)", "identified (Hz)", "error (%)", "prominence (dB)", "detected", "fault named"].map((c, i) => h("th", { class: i > 1 && i < 6 ? "num" : "" }, c)))),
      h("tbody", {}, ids.map((r) => h("tr", { "data-line": r.name, "data-detected": String(r.detected), "data-in-verdict": String(!!r.in_verdict) },
        h("td", {}, r.name), h("td", {}, r.harmonic), h("td", { class: "num" }, fmt(r.theory_hz)), h("td", { class: "num" }, fmt(r.identified_hz)),
        h("td", { class: "num" }, fmt(r.error_pct)), h("td", { class: "num" }, fmt(r.prominence_db)),
        h("td", { class: r.detected ? "detected" : "muted" }, r.detected ? "yes" : "no"),
        h("td", { class: r.in_verdict ? "detected" : "muted" }, r.in_verdict ? "yes" : "no")))))));
}

function signalPlot(id, result, name) {
  const chart = h("div", { id: "signal-chart" });
  const channel = h("select", { id: "channel", "aria-label": "channel" }, result.channels.map((c) => h("option", { value: c.name, selected: c.name === "outer_ring_accel_z" }, `${c.name} (${c.unit})`)));
  const end = result.start_time + (result.channels[0].samples - 1) / result.sample_rate;
  let win = [result.start_time, end];
  const readout = h("span", { class: "readout", "aria-live": "off" });
  const load = async () => {
    const q = new URLSearchParams({ channel: channel.value, from: win[0], to: win[1], max_points: 2000 });
    const r = await api(`/v1/simulations/${id}/signals?${q}`);
    if (r.status !== 200) { chart.replaceChildren(h("p", { class: "error" }, r.body.detail)); return; }
    const s = r.body;
    lineChart(chart, { x: s.data.map((_, k) => s.start_time + k * s.dt), y: s.data, xLabel: "time (s)", xUnit: "s", yUnit: s.unit,
      yLabel: `${s.channel} (${s.unit})`, title: `Time signal: ${name}`, readout, onZoom: (a, b) => { win = [a, b]; load(); } });
    info.textContent = `${fmt(win[0])} to ${fmt(win[1])} s, ${s.count} points${s.decimation > 1 ? `, decimated by ${s.decimation}` : ""}`;
  };
  const shift = (f) => { const w = win[1] - win[0]; win = [Math.max(result.start_time, win[0] + f * w), Math.min(end, win[1] + f * w)]; load(); };
  const info = h("span", { class: "muted" });
  channel.addEventListener("change", load);
  load();
  return h("div", { class: "plot" }, h("h3", {}, `Time signal: ${name}`, " ", chartDownloads(chart, `${slug(name)}-signal`, `Time signal: ${name}`)),
    h("div", { class: "controls" }, channel,
      h("button", { onclick: () => shift(-0.5) }, "◀ earlier"), h("button", { onclick: () => shift(0.5) }, "later ▶"),
      h("button", { onclick: () => { const c = (win[0] + win[1]) / 2, w = win[1] - win[0]; win = [Math.max(result.start_time, c - w), Math.min(end, c + w)]; load(); } }, "zoom out"),
      h("button", { onclick: () => { win = [result.start_time, end]; load(); } }, "reset"),
      info, h("span", { class: "muted" }, "Drag across the plot to zoom.")),
    chart, h("p", { class: "readout-line" }, readout));
}

// identifications name their lines as the engine does; markers as the API's `theory` does
const ID_NAMES = { BPFO: "bpfo", BPFI: "bpfi", BSF: "bsf", "2xBSF": "bsf2", FTF: "ftf" };
const NUMBER_OR_BLANK = (t) => (t.trim() === "" ? { value: null } : parseNumber(t));

/** The legend of a spectrum's markers and peaks. */
function spectrumLegend(markers, withPeaks) {
  const seen = new Map();
  for (const m of markers) if (!m.sideband && !seen.has(m.name)) seen.set(m.name, m.x / m.harmonic);
  const entries = [...seen].map(([n, f]) => ({ text: `${lineName(n)} ${fmt(f)} Hz and harmonics`, color: PALETTE[n], dashed: "4 3" }));
  if (markers.some((m) => m.sideband)) entries.push({ text: "BPFI ± shaft sidebands", color: PALETTE.bpfi, dashed: "1 3" });
  if (withPeaks) entries.push({ text: "identified peak, labelled with its error against theory", color: "#333", dot: true });
  return legend(entries);
}

/** Spectrum amplitudes as drawn: linear, or dB re 1 unit (zero and below left out). */
const scaled = (amplitude, db) => (db ? amplitude.map((v) => (v > 0 ? 20 * Math.log10(v) : NaN)) : amplitude);

function spectrumPlot(kind, id, a, name) {
  const chart = h("div", { id: "spectrum-chart" });
  const options = [["raw", "raw envelope"], ["best_component", `best component (level ${a.best_component.level})`],
    ...a.level_kurtosis.map((_, i) => [`level:${i + 1}`, `level ${i + 1}`])];
  const which = h("select", { id: "spectrum-kind", "aria-label": "spectrum" }, options.map(([v, l]) => h("option", { value: v }, l)));
  const scale = h("select", { id: "spectrum-scale", "aria-label": "amplitude scale" }, h("option", { value: "linear" }, "linear"), h("option", { value: "db" }, "dB"));
  const fmaxDefault = Math.round(Math.max(a.theory.bpfi, a.theory.bpfo) * 3.5);
  const fmin = h("input", { id: "fmin", type: "text", inputmode: "decimal", value: 0, size: 6, "aria-label": "lowest frequency (Hz)" });
  const fmax = h("input", { id: "fmax", type: "text", inputmode: "decimal", value: fmaxDefault, size: 6, "aria-label": "highest frequency (Hz)" });
  const info = h("span", { class: "muted", id: "spectrum-info" });
  const err = h("span", { class: "error", id: "spectrum-error", "aria-live": "polite" });
  const readout = h("span", { class: "readout", id: "spectrum-readout" });
  const headingText = h("span", { id: "spectrum-heading" });
  const heading = () => `${what()}: ${name}`;
  // built once: a redraw (zoom, range, the spectrum's reload) changes only the heading's text
  const downloads = chartDownloads(chart, `${slug(name)}-spectrum`, heading);
  const title = h("h3", {}, headingText, " ", downloads);
  const legendBox = h("div", {});
  const unit = kind === "simulations" ? "m/s²" : "unit of the signal";
  let s = null, range = null;
  const what = () => (!s ? "envelope spectrum" : s.kind === "raw" ? "raw envelope spectrum" : `level ${s.level} envelope spectrum${s.kind === "best_component" ? " (best component)" : ""}`);
  const draw = () => {
    const db = scale.value === "db";
    const x = [], y = scaled(s.amplitude, db).slice(1);
    for (let i = 1; i < s.amplitude.length; i++) x.push(i * s.df);
    const at = (f) => y[Math.max(0, Math.min(y.length - 1, Math.round(f / s.df) - 1))];
    const markers = s.markers.map((m) => ({ x: m.frequency, name: m.name, harmonic: m.harmonic, sideband: m.sideband || 0 }));
    const peaks = s.peaks.filter((p) => isFinite(p.identified_hz)).map((p) => ({
      x: p.identified_hz, y: at(p.identified_hz), name: ID_NAMES[p.name] ?? p.name.toLowerCase(),
      label: markerLabel(ID_NAMES[p.name] ?? p.name, p.harmonic), text: p.detected ? `${p.error_pct >= 0 ? "+" : ""}${fmt(p.error_pct)} %` : null }));
    headingText.textContent = heading();
    lineChart(chart, { series: [{ x, y, color: SERIES[0], name }], xLabel: "frequency (Hz)", xUnit: "Hz", yUnit: db ? "dB" : unit,
      yLabel: db ? `envelope amplitude (dB re 1 ${unit})` : `envelope amplitude (${unit})`, title: heading(), yFromZero: !db,
      // 80 dB under the highest line: the noise floor, not the numerical zeros below it
      yMin: db ? Math.max(...y.filter(isFinite)) - 80 : undefined,
      range: range || [0, s.fmax], markers, peaks, readout, onZoom: (lo, hi) => { range = [lo, hi]; fmin.value = fmt(lo); draw(); } });
    chart.dataset.kind = s.kind;
    // the drawn range, Hz: what a redraw changes
    chart.dataset.range = (range || [0, s.fmax]).map(fmt).join(" to ");
    legendBox.replaceChildren(spectrumLegend(markers, peaks.some((p) => p.text)));
    info.textContent = `bin width ${fmt(s.df)} Hz`;
  };
  const downloadCsv = async () => {
    const r = await fetch(`/v1/${kind}/${id}/spectra?${query()}`, { headers: { Accept: "text/csv", ...(tokenInput.value ? { Authorization: `Bearer ${tokenInput.value.trim()}` } : {}) } });
    if (!r.ok) { err.textContent = `CSV refused (${r.status})`; return; }
    save(await r.blob(), `${slug(name)}-spectrum-${which.value.replace(":", "-")}.csv`);
  };
  downloads.append(h("button", { type: "button", "data-download": "spectrum-csv", onclick: downloadCsv }, "CSV"));
  const query = () => {
    const [k, level] = which.value.split(":");
    const q = new URLSearchParams({ kind: k, fmax: fmax.value.trim(), harmonics: 3 });
    if (level) q.set("level", level);
    return q;
  };
  /** The typed range, or an error next to it: nothing is drawn from a guess. */
  const readRange = () => {
    const lo = NUMBER_OR_BLANK(fmin.value), hi = parseNumber(fmax.value, { blank: "enter the highest frequency in Hz" });
    err.textContent = lo.error ? `lowest frequency: ${lo.error}` : hi.error ? `highest frequency: ${hi.error}` : !(hi.value > (lo.value ?? 0)) ? "the highest frequency must exceed the lowest" : "";
    return err.textContent ? null : [lo.value ?? 0, hi.value];
  };
  const load = async () => {
    const r0 = readRange();
    if (!r0) return;
    const r = await api(`/v1/${kind}/${id}/spectra?${query()}`);
    if (r.status !== 200) { chart.replaceChildren(h("p", { class: "error" }, r.body.detail)); return; }
    s = r.body;
    range = [r0[0], Math.min(r0[1], s.fmax)];
    draw();
  };
  const pan = (f) => { if (!s) return; const [lo, hi] = range, w = hi - lo; const nlo = Math.max(0, Math.min(s.fmax - w, lo + f * w)); range = [nlo, nlo + w]; fmin.value = fmt(nlo); draw(); };
  which.addEventListener("change", load);
  fmax.addEventListener("change", load);
  fmin.addEventListener("change", () => { const r0 = readRange(); if (r0 && s) { range = [r0[0], Math.min(r0[1], s.fmax)]; draw(); } });
  scale.addEventListener("change", () => s && draw());
  load();
  return h("div", { class: "plot" }, title,
    h("div", { class: "controls" }, h("label", {}, "Spectrum ", which), h("label", {}, "scale ", scale),
      h("label", {}, "from (Hz) ", fmin), h("label", {}, "to (Hz) ", fmax),
      h("button", { type: "button", onclick: () => pan(-0.5), "aria-label": "pan to lower frequencies" }, "◀"),
      h("button", { type: "button", onclick: () => pan(0.5), "aria-label": "pan to higher frequencies" }, "▶"),
      h("button", { type: "button", id: "spectrum-reset", onclick: () => { fmin.value = 0; fmax.value = fmaxDefault; load(); } }, "reset"),
      info, err, h("span", { class: "muted" }, "Drag across the plot to zoom; hover for a readout.")),
    chart, h("p", { class: "readout-line" }, readout), legendBox);
}

// ---------------------------------------------------------------- compare jobs

async function compareView(gen, keys) {
  const jobs = [];
  for (const key of keys) {
    const [kind, id] = key.split(":");
    const [j, r] = await Promise.all([api(`/v1/${kind}/${id}`), api(`/v1/${kind}/${id}/result`)]);
    if (gen !== generation) return;
    if (j.status !== 200 || r.status !== 200) { view.replaceChildren(h("p", { class: "error" }, `${key}: ${(r.body && r.body.detail) || "not found or not finished"}`)); return; }
    jobs.push({ kind, id, name: j.body.label || id, result: r.body });
  }
  const withSpectra = jobs.filter((j) => j.result.analysis);
  const fmax = Math.round(Math.max(...withSpectra.map((j) => Math.max(j.result.analysis.theory.bpfi, j.result.analysis.theory.bpfo) * 3.5), 1));
  const spectra = await Promise.all(withSpectra.map((j) => api(`/v1/${j.kind}/${j.id}/spectra?kind=raw&fmax=${fmax}&harmonics=3`)));
  if (gen !== generation) return;
  const chart = h("div", { id: "compare-chart" });
  const readout = h("span", { class: "readout" });
  const series = spectra.map((r, k) => ({ name: withSpectra[k].name, color: SERIES[k % SERIES.length],
    x: r.body.amplitude.slice(1).map((_, i) => (i + 1) * r.body.df), y: r.body.amplitude.slice(1) }));
  // theoretical lines only when every job has the same ones (same bearing and speed, to 0.5 %)
  const bpfo = withSpectra.map((j) => j.result.analysis.theory.bpfo);
  const shared = bpfo.length > 0 && bpfo.every((f) => Math.abs(f - bpfo[0]) <= 0.005 * bpfo[0]);
  const markers = shared ? spectra[0].body.markers.map((m) => ({ x: m.frequency, name: m.name, harmonic: m.harmonic, sideband: m.sideband || 0 })) : [];
  const names = jobs.map((j) => j.name).join(" vs ");
  const title = `Raw envelope spectra: ${names}`;
  const rows = jobs.map((j) => summaryRows(j.result));
  const labels = [...new Set(rows.flat().map((r) => r.label))];
  view.replaceChildren(h("h2", {}, `Compare ${jobs.length} jobs`),
    h("div", { class: "plot" }, h("h3", {}, title, " ", chartDownloads(chart, "compare-spectra", title)), chart, h("p", { class: "readout-line" }, readout),
      legend(series.map((s) => ({ text: s.name, color: s.color }))),
      shared ? spectrumLegend(markers, false)
        : h("p", { class: "muted", id: "compare-lines" }, `No theoretical lines: the jobs' fault frequencies differ (BPFO ${bpfo.map(fmt).join(", ")} Hz); each job's page shows its own.`)),
    h("div", { class: "plot" }, h("h3", {}, "Summaries side by side"),
      scrollBox(h("table", { id: "compare-table" },
        h("thead", {}, h("tr", {}, h("th", {}, "quantity"), jobs.map((j) => h("th", {}, h("a", { href: `#/${j.kind}/${j.id}` }, j.name))))),
        h("tbody", {}, labels.map((l) => h("tr", {}, h("td", {}, l), rows.map((rs) => h("td", { class: "num" }, rs.find((r) => r.label === l)?.text ?? "-")))))))));
  const draw = (range) => lineChart(chart, { series, markers, xLabel: "frequency (Hz)", xUnit: "Hz", yUnit: "", yLabel: "envelope amplitude (unit of each signal)",
    title, yFromZero: true, range: range || [0, fmax], readout, onZoom: (a, b) => draw([a, b]) });
  draw();
}

// ---------------------------------------------------------------- studies

// Fields a study can vary from the page: [label, JSON pointer, also, unit]
const STUDY_FACTORS = {
  axial_load: ["axial load", "/operating/axial_load", [], "N"],
  radial_load: ["radial load", "/operating/radial_load", [], "N"],
  speed: ["constant shaft speed", "/operating/speed/steady_rpm", ["/operating/speed/initial_rpm"], "rev/min"],
  duration: ["duration", "/solver/duration", [], "s"],
};

async function studyForm(gen) {
  const presets = (await api("/v1/presets")).body.items.filter((p) => p.simulation);
  if (gen !== generation) return null;
  const preset = (await api(`/v1/presets/${presets[0].name}`)).body;
  const form = h("form", { novalidate: true, id: "study-form" });
  const design = h("select", { id: "study-design", name: "design" },
    h("option", { value: "grid" }, "grid over one field"), h("option", { value: "one_at_a_time" }, "one field at a time"),
    ["table2", "paper-trends", "sensitivity"].map((n) => h("option", { value: `named:${n}` }, `named design: ${n}`)));
  const factor = h("select", { id: "study-factor", name: "factor" }, Object.entries(STUDY_FACTORS).map(([k, [l, , , u]]) => h("option", { value: k }, `${l} (${u})`)));
  const status = h("p", { id: "study-status", "aria-live": "polite" });
  const problems = h("ul", { class: "error" });
  const caseSel = h("select", { id: "study-case", name: "fault_case" }, preset.fault_cases.map((c) => h("option", { value: c, selected: c === "outer" }, c)));
  const grid = h("div", { class: "grid" },
    field("study.name", "Study name", "", { text: true, range: "blank: the service names it" }),
    h("div", { class: "field" }, h("label", { for: "study-case" }, "Fault case"), caseSel),
    field("study.duration", "Duration of each run (s)", preset.scene.solver.duration, { unit: "s", range: `> 0; the preset's: ${fmt(preset.scene.solver.duration)}` }),
    h("div", { class: "field" }, h("label", { for: "study-design" }, "Design"), design),
    h("div", { class: "field factor-only" }, h("label", { for: "study-factor" }, "Field to vary"), factor),
    field("study.values", "Values (comma-separated, unit of the field)", "300, 400", { text: true, range: "two or more numbers" }));
  const sync = () => form.querySelectorAll(".factor-only, .field[data-path='study.values']").forEach((e) => { e.hidden = design.value.startsWith("named:"); });
  design.addEventListener("change", sync);
  form.append(grid, h("p", {}, h("button", { type: "submit", class: "primary" }, "Start study")), status, problems);
  form.addEventListener("submit", async (ev) => {
    ev.preventDefault();
    clearMarks(form);
    problems.replaceChildren();
    const errors = [];
    const dur = parseNumber(form.elements["study.duration"].value, { blank: `required: seconds per run (the preset's is ${fmt(preset.scene.solver.duration)})` });
    if (dur.error) errors.push(["study.duration", dur.error]);
    const body = { base: { preset: preset.name, fault_case: caseSel.value, overrides: { solver: { duration: dur.value } } } };
    const name = form.elements["study.name"].value.trim();
    if (name) body.name = name;
    if (design.value.startsWith("named:")) body.design = { type: "named", name: design.value.slice(6) };
    else {
      const parts = form.elements["study.values"].value.split(",").map((t) => t.trim());
      const parsed = parts.map((t) => parseNumber(t));
      const bad = parsed.find((p) => p.error);
      if (bad) errors.push(["study.values", bad.error]);
      else if (parsed.length < 2) errors.push(["study.values", "enter two or more values"]);
      const [label, pointer, also] = STUDY_FACTORS[factor.value];
      body.design = { type: design.value, factors: [{ name: factor.value, pointer, ...(also.length ? { also } : {}), values: parsed.map((p) => p.value) }] };
      if (!name) body.name = `${label}: ${parts.join(", ")}`;
    }
    if (errors.length) { for (const [p, m] of errors) markField(form, p, m); status.textContent = "Not started: fix the marked fields."; return; }
    status.textContent = "Starting…";
    const r = await api("/v1/studies", { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
    if (r.status === 202 || r.status === 200) { location.hash = `#/studies/${r.body.id}`; return; }
    status.textContent = r.body.detail || `refused (${r.status})`;
    problems.replaceChildren(...(r.body.errors || []).map((e) => h("li", {}, `${e.path}: ${e.message}`)));
  });
  sync();
  return form;
}

async function studiesView(gen) {
  const r = await api("/v1/studies?limit=50");
  if (gen !== generation) return;
  const items = r.body.items || [];
  const form = await studyForm(gen);
  if (!form) return;
  view.replaceChildren(h("h2", {}, "Studies"),
    h("p", { class: "muted" }, "Parameter studies (started here, with POST /v1/studies or with bearing-sim study): their table and trend plots."),
    scrollBox(h("table", { id: "studies" },
      h("thead", {}, h("tr", {}, ["study", "state", "points done", "created"].map((c) => h("th", {}, c)))),
      h("tbody", {}, items.length ? items.map((st) => h("tr", {},
        h("td", {}, h("a", { href: `#/studies/${st.id}` }, st.name)),
        h("td", { class: `state-${st.state}` }, st.state),
        h("td", {}, `${st.progress.points_done} / ${st.progress.points_total}`),
        h("td", {}, when(st.created_at)))) : h("tr", {}, h("td", { colspan: 4, class: "muted" }, "No studies yet."))))),
    h("h3", {}, "Start a study"), form);
}

/** `axial_load-inner.svg` as a reader names it. */
function plotTitle(file, study) {
  if (file === "spectra.svg") return `Envelope spectra of the points: ${study}`;
  const m = file.match(/^(.*)-(\w+)\.svg$/);
  return m ? `Fault frequencies against ${m[1].replace(/_/g, " ")}, ${m[2]} fault: ${study}` : `${file}: ${study}`;
}

async function studyView(gen, id) {
  const head = h("div", {}), body = h("div", {});
  view.replaceChildren(head, body);
  let etag = null, st = null;
  while (gen === generation) {
    const r = await api(`/v1/studies/${id}${st ? "?wait=25" : ""}`, { headers: etag ? { "If-None-Match": etag } : {} });
    if (r.status === 304) continue;
    if (r.status !== 200) { view.replaceChildren(h("p", { class: "error" }, r.body.detail || "not found")); return; }
    etag = r.headers.get("etag");
    st = r.body;
    head.replaceChildren(h("h2", {}, st.name),
      h("p", {}, h("span", { class: `state-${st.state}`, id: "study-state" }, st.state), " ",
        h("progress", { max: st.progress.points_total, value: st.progress.points_done, "aria-label": "points done" }),
        ` ${st.progress.points_done} of ${st.progress.points_total} points`));
    if (!["queued", "running"].includes(st.state)) break;
  }
  if (gen !== generation) return;
  const table = (await api(`/v1/studies/${id}/table`)).body;
  const cols = ["point", ...table.factors.map((f) => f), "fault", "state", "BPFO error (%)", "BPFI error (%)", "BPFO best (Hz)", "BPFI best (Hz)"];
  const pct = (l) => (l ? fmt(l.cage_error_pct) : "");
  const best = (l) => (l ? `${fmt(l.best.hz)}${l.best.detected ? " ✓" : ""}` : "");
  const auth = tokenInput.value ? { Authorization: `Bearer ${tokenInput.value.trim()}` } : {};
  body.append(h("div", { class: "plot" }, h("h3", {}, "Table (errors of the cage-derived frequencies against theory) ",
    h("span", { class: "downloads" }, h("button", { type: "button", "data-download": "study-csv", onclick: async () => {
      const r = await fetch(`/v1/studies/${id}/table`, { headers: { Accept: "text/csv", ...auth } });
      if (r.ok) save(await r.blob(), `${slug(st.name)}-table.csv`);
    } }, "CSV"))),
    scrollBox(h("table", { id: "study-table" },
      h("thead", {}, h("tr", {}, cols.map((c) => h("th", {}, c)))),
      h("tbody", {}, table.rows.map((row) => h("tr", {},
        h("td", {}, row.job_id ? h("a", { href: `#/simulations/${row.job_id}` }, row.index) : row.index),
        ...row.factors.map((f) => h("td", { class: "num" }, fmt(f.value))),
        h("td", {}, row.fault_case ?? ""),
        h("td", { class: `state-${row.state}` }, row.state),
        h("td", { class: "num" }, pct(row.result?.bpfo)), h("td", { class: "num" }, pct(row.result?.bpfi)),
        h("td", { class: "num" }, best(row.result?.bpfo)), h("td", { class: "num" }, best(row.result?.bpfi)))))))));
  // the plots are SVG from the service, fetched with the token and shown as images
  for (const [key, href] of Object.entries(st.links)) {
    if (!key.startsWith("plot:")) continue;
    const r = await fetch(href, { headers: auth });
    if (!r.ok || gen !== generation) continue;
    const blob = await r.blob();
    const url = URL.createObjectURL(blob);
    const file = key.slice(5);
    body.append(h("div", { class: "plot" }, h("h3", {}, plotTitle(file, st.name), " ", h("span", { class: "downloads" }, h("a", { href: url, download: `${slug(st.name)}-${file}`, class: "button" }, "SVG"))),
      h("img", { src: url, alt: plotTitle(file, st.name), class: "trend" })));
  }
}

// ---------------------------------------------------------------- routing

async function route() {
  const gen = ++generation;
  const path = location.hash.replace(/^#/, "") || "/";
  let m;
  try {
    if (path === "/" || path === "") await jobsView(gen);
    else if (path === "/new") await newView(gen);
    else if (path === "/upload") await uploadView(gen);
    else if (path === "/studies") await studiesView(gen);
    else if ((m = path.match(/^\/studies\/([\w-]+)$/))) await studyView(gen, m[1]);
    else if ((m = path.match(/^\/compare\/((?:(?:simulations|analyses):[\w-]+,?)+)$/))) await compareView(gen, m[1].split(",").filter(Boolean));
    else if ((m = path.match(/^\/(simulations|analyses)\/([\w-]+)$/))) await jobView(gen, m[1], m[2]);
    else view.replaceChildren(h("p", {}, "No such page. ", h("a", { href: "#/" }, "Jobs")));
  } catch (e) {
    if (gen === generation && !banner.textContent) showBanner(`Something went wrong: ${e.message}`);
  }
}

window.addEventListener("hashchange", route);
route();
