// The lab page: submit simulations and recordings, watch jobs (long polls, no hammering),
// and look at results. Plain ES modules served by the service; no build step.

import { lineChart, barChart, fmt } from "/assets/plot.js";

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

// ---------------------------------------------------------------- jobs list

async function jobsView(gen) {
  const tbody = h("tbody");
  view.replaceChildren(
    h("h2", {}, "Jobs"),
    h("p", { class: "muted" }, "Simulations and analyses, newest first. States update as they change."),
    h("table", { id: "jobs" },
      h("thead", {}, h("tr", {}, h("th", {}, "kind"), h("th", {}, "job"), h("th", {}, "state"),
        h("th", {}, "progress"), h("th", { class: "hide-narrow" }, "created"), h("th", { class: "hide-narrow" }, "finished"), h("th", {}, ""))),
      tbody),
  );
  const rows = new Map();
  const render = (job) => {
    const kind = collection(job.kind);
    const actions = h("td", {});
    if (job.state === "queued" || job.state === "running") {
      actions.append(h("button", { onclick: () => cancel(kind, job.id), "aria-label": `cancel ${job.label}` }, "Cancel"));
    } else {
      actions.append(h("button", { onclick: () => remove(kind, job.id), "aria-label": `delete ${job.label}` }, "Delete"));
    }
    const row = h("tr", { "data-id": job.id, "data-state": job.state },
      h("td", {}, job.kind),
      h("td", {}, h("a", { href: `#/${kind}/${job.id}` }, job.label || job.id)),
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
    if (!jobs.length) tbody.append(h("tr", {}, h("td", { colspan: 7, class: "muted" }, "No jobs yet. Start a simulation or analyse a recording.")));
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

// ---------------------------------------------------------------- submit a simulation

// Form fields: [path in the scene, label with unit, factor from the shown unit to SI]
const FIELDS = [
  ["operating.speed.steady_rpm", "Steady speed (rev/min)", 1],
  ["operating.speed.initial_rpm", "Initial speed (rev/min)", 1],
  ["operating.speed.ramp_time", "Ramp time (s)", 1],
  ["operating.axial_load", "Axial load (N)", 1],
  ["operating.radial_load", "Radial load (N)", 1],
  ["solver.duration", "Duration (s)", 1],
  ["solver.rtol", "Relative tolerance (-)", 1],
];

function getPath(obj, path) {
  return path.split(".").reduce((o, k) => (o == null ? undefined : o[k]), obj);
}
function setPath(obj, path, value) {
  const keys = path.split(".");
  let o = obj;
  keys.slice(0, -1).forEach((k) => { o = o[k] ??= {}; });
  o[keys.at(-1)] = value;
}

function field(path, label, value, extra = {}) {
  const id = `f-${path.replace(/[^a-z0-9]/gi, "-")}`;
  return h("div", { class: "field", "data-path": path },
    h("label", { for: id }, label),
    extra.options
      ? h("select", { id, name: path }, extra.options.map((o) => h("option", { value: o, selected: o === value }, o)))
      : h("input", { id, name: path, type: "number", step: "any", value, required: true }),
    h("div", { class: "error", "aria-live": "polite" }));
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
  const general = h("div", { class: "grid" }, FIELDS.map(([p, l, f]) => field(p, l, getPath(scene, p) / f)),
    field("solver.integrator", "Integrator", scene.solver.integrator, { options: ["rk4_fsal", "rk4_adaptive", "rk4_fixed", "rosenbrock_w", "auto"] }),
    field("solver.fidelity", "Fidelity level", scene.solver.fidelity || "full", { options: ["full", "quasi_static_balls", "concentric_cage"] }));
  const renderFaults = () => {
    const faults = preset.fault_case_faults?.[caseSelect.value]?.faults || [];
    faultBox.replaceChildren(...faults.map((f, i) => h("fieldset", {},
      h("legend", {}, `${f.ring} race defect`),
      field(`faults[${i}].width`, "Width (mm)", f.width * 1e3),
      field(`faults[${i}].depth`, "Depth (mm)", f.depth * 1e3),
      field(`faults[${i}].angle`, "Angle (deg)", (f.angle * 180) / Math.PI),
      h("input", { type: "hidden", name: `faults[${i}].ring`, value: f.ring }))));
    update();
  };
  const body = () => {
    const overrides = {};
    for (const [p, , factor] of FIELDS) {
      const v = form.elements[p].value;
      setPath(overrides, p, v === "" ? null : Number(v) * factor);
    }
    setPath(overrides, "solver.integrator", form.elements["solver.integrator"].value);
    setPath(overrides, "solver.fidelity", form.elements["solver.fidelity"].value);
    const faults = preset.fault_case_faults?.[caseSelect.value]?.faults || [];
    if (faults.length) {
      overrides.faults = faults.map((f, i) => ({
        ring: f.ring,
        width: Number(form.elements[`faults[${i}].width`].value) * 1e-3,
        depth: Number(form.elements[`faults[${i}].depth`].value) * 1e-3,
        angle: (Number(form.elements[`faults[${i}].angle`].value) * Math.PI) / 180,
      }));
    }
    return { preset: preset.name, fault_case: caseSelect.value, overrides };
  };
  const update = () => { patch.textContent = JSON.stringify(body(), null, 2); };
  caseSelect.addEventListener("change", renderFaults);
  form.addEventListener("input", update);
  const status = h("p", { id: "submit-status", "aria-live": "polite" });
  form.addEventListener("submit", async (ev) => {
    ev.preventDefault();
    form.querySelectorAll(".field").forEach((f) => {
      f.classList.remove("invalid");
      const e = f.querySelector(".error");
      if (e) e.textContent = "";
    });
    status.textContent = "Submitting…";
    const r = await api("/v1/simulations", { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body()) });
    if (r.status === 202 || r.status === 200) {
      location.hash = `#/simulations/${r.body.id}`;
      return;
    }
    status.textContent = r.body.detail || `refused (${r.status})`;
    for (const e of r.body.errors || []) {
      const path = e.path.replace(/^scene\./, "");
      const box = form.querySelector(`.field[data-path="${CSS.escape(path)}"]`);
      if (box) {
        box.classList.add("invalid");
        box.querySelector(".error").textContent = e.message;
      }
    }
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
  view.replaceChildren(h("h2", {}, "New simulation"), form);
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
      h("h2", {}, job.label || job.id),
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
  renderResult(kind, id, result, body);
}

function renderResult(kind, id, result, box) {
  const a = result.analysis;
  const cards = h("div", { class: "cards", id: "summary" });
  const card = (label, value) => cards.append(h("div", { class: "card" }, h("div", { class: "label" }, label), h("div", { class: "big" }, value)));
  if (result.cage) {
    card("Mean cage speed", `${fmt(result.cage.mean_speed)} rad/s`);
    card("Cage slip", `${fmt(result.cage.slip * 100)} %`);
    card("Cage motion", result.cage.motion?.state ?? "");
  }
  if (result.frequencies) {
    card("BPFO simulated / theory", `${fmt(result.frequencies.simulated.bpfo)} / ${fmt(result.frequencies.nominal.bpfo)} Hz (${fmt(result.frequencies.bpfo_error_pct)} %)`);
    card("BPFI simulated / theory", `${fmt(result.frequencies.simulated.bpfi)} / ${fmt(result.frequencies.nominal.bpfi)} Hz (${fmt(result.frequencies.bpfi_error_pct)} %)`);
  }
  const FAULT = { outer_race: "outer race", inner_race: "inner race", rolling_element: "rolling element", cage: "cage" };
  if (a && a.verdict) {
    const v = a.verdict;
    card("Verdict", v.faults.length ? v.faults.map((f) => FAULT[f] ?? f).join(" + ") : "no fault indicated");
  }
  box.append(cards);
  if (!a) { box.append(h("p", { class: "muted" }, result.analysis_error || "No analysis.")); return; }
  if (a.verdict) {
    const v = a.verdict;
    const rows = v.evidence.map((e) => h("tr", {},
      h("td", {}, FAULT[e.fault] ?? e.fault), h("td", {}, e.indicated ? "yes" : "no"), h("td", {}, e.p_value.toExponential(1)),
      h("td", {}, e.spectrum), h("td", {}, e.harmonics_searched ? `${e.harmonics_found}/${e.harmonics_searched}` : "-"),
      h("td", {}, e.fundamental_hz == null ? "no line in the search band" : `${fmt(e.fundamental_hz)} Hz (${fmt(e.error_pct)} %)`)));
    box.append(h("div", { class: "plot", id: "verdict" }, h("h3", {}, `Verdict (false-alarm rate ${v.false_alarm_rate} per type)`),
      h("table", {}, h("thead", {}, h("tr", {}, ...["fault type", "indicated", "p", "spectrum", "harmonics found", "fundamental"].map((t) => h("th", {}, t)))), h("tbody", {}, ...rows))));
  }
  box.append(idTable("Identified in the raw envelope spectrum", a.raw, "ids-raw"),
    idTable(`Identified in the best DTCWT component (level ${a.best_component.level}, kurtosis ${fmt(a.best_component.kurtosis)})`, a.best_component.identifications, "ids-best"));
  if (a.kurtogram) {
    const k = a.kurtogram;
    box.append(idTable(`Identified in the kurtogram's band (${fmt(k.band_hz[0])}-${fmt(k.band_hz[1])} Hz, level ${fmt(k.level)}, spectral kurtosis ${fmt(k.kurtosis)})`, k.identifications, "ids-kurtogram"));
  }
  if (a.kurtogram_runner_up) {
    const k = a.kurtogram_runner_up;
    box.append(idTable(`Identified in the kurtogram's runner-up band (${fmt(k.band_hz[0])}-${fmt(k.band_hz[1])} Hz, level ${fmt(k.level)}, spectral kurtosis ${fmt(k.kurtosis)})`, k.identifications, "ids-kurtogram-runner-up"));
  }
  if (kind === "simulations") box.append(signalPlot(id, result));
  box.append(spectrumPlot(kind, id, a));
  const kbox = h("div", {});
  box.append(h("div", { class: "plot" }, h("h3", {}, "Kurtosis per DTCWT level"), kbox));
  barChart(kbox, { labels: a.level_kurtosis.map((_, i) => `${i + 1}`), values: a.level_kurtosis,
    xLabel: "level", yLabel: "kurtosis (-)", highlight: a.best_component.level - 1 });
}

function idTable(title, ids, tid) {
  return h("div", { class: "plot" }, h("h3", {}, title),
    h("table", { id: tid },
      h("thead", {}, h("tr", {}, ["line", "harmonic", "theory (Hz)", "identified (Hz)", "error (%)", "prominence (dB)", "detected", "fault named"].map((c, i) => h("th", { class: i > 1 && i < 6 ? "num" : "" }, c)))),
      h("tbody", {}, ids.map((r) => h("tr", { "data-line": r.name, "data-detected": String(r.detected), "data-in-verdict": String(!!r.in_verdict) },
        h("td", {}, r.name), h("td", {}, r.harmonic), h("td", { class: "num" }, fmt(r.theory_hz)), h("td", { class: "num" }, fmt(r.identified_hz)),
        h("td", { class: "num" }, fmt(r.error_pct)), h("td", { class: "num" }, fmt(r.prominence_db)),
        h("td", { class: r.detected ? "detected" : "muted" }, r.detected ? "yes" : "no"),
        h("td", { class: r.in_verdict ? "detected" : "muted" }, r.in_verdict ? "yes" : "no"))))));
}

function signalPlot(id, result) {
  const chart = h("div", { id: "signal-chart" });
  const channel = h("select", { id: "channel", "aria-label": "channel" }, result.channels.map((c) => h("option", { value: c.name, selected: c.name === "outer_ring_accel_z" }, `${c.name} (${c.unit})`)));
  const end = result.start_time + (result.channels[0].samples - 1) / result.sample_rate;
  let win = [result.start_time, end];
  const load = async () => {
    const q = new URLSearchParams({ channel: channel.value, from: win[0], to: win[1], max_points: 2000 });
    const r = await api(`/v1/simulations/${id}/signals?${q}`);
    if (r.status !== 200) { chart.replaceChildren(h("p", { class: "error" }, r.body.detail)); return; }
    const s = r.body;
    lineChart(chart, { x: s.data.map((_, k) => s.start_time + k * s.dt), y: s.data, xLabel: "time (s)",
      yLabel: `${s.channel} (${s.unit})`, onZoom: (a, b) => { win = [a, b]; load(); } });
    info.textContent = `${fmt(win[0])} to ${fmt(win[1])} s, ${s.count} points${s.decimation > 1 ? `, decimated by ${s.decimation}` : ""}`;
  };
  const shift = (f) => { const w = win[1] - win[0]; win = [Math.max(result.start_time, win[0] + f * w), Math.min(end, win[1] + f * w)]; load(); };
  const info = h("span", { class: "muted" });
  channel.addEventListener("change", load);
  load();
  return h("div", { class: "plot" }, h("h3", {}, "Time signal"),
    h("div", { class: "controls" }, channel,
      h("button", { onclick: () => shift(-0.5) }, "◀ earlier"), h("button", { onclick: () => shift(0.5) }, "later ▶"),
      h("button", { onclick: () => { const c = (win[0] + win[1]) / 2, w = win[1] - win[0]; win = [Math.max(result.start_time, c - w), Math.min(end, c + w)]; load(); } }, "zoom out"),
      h("button", { onclick: () => { win = [result.start_time, end]; load(); } }, "reset"),
      info, h("span", { class: "muted" }, "Drag across the plot to zoom.")),
    chart);
}

function spectrumPlot(kind, id, a) {
  const chart = h("div", { id: "spectrum-chart" });
  const options = [["raw", "raw envelope"], ["best_component", `best component (level ${a.best_component.level})`],
    ...a.level_kurtosis.map((_, i) => [`level:${i + 1}`, `level ${i + 1}`])];
  const which = h("select", { id: "spectrum-kind", "aria-label": "spectrum" }, options.map(([v, l]) => h("option", { value: v }, l)));
  const fmaxDefault = Math.round(Math.max(a.theory.bpfi, a.theory.bpfo) * 3.5);
  const fmax = h("input", { id: "fmax", type: "number", value: fmaxDefault, step: "any", "aria-label": "highest frequency (Hz)" });
  const info = h("span", { class: "muted", id: "spectrum-info" });
  const load = async () => {
    const [k, level] = which.value.split(":");
    const q = new URLSearchParams({ kind: k, fmax: fmax.value, harmonics: 3 });
    if (level) q.set("level", level);
    const r = await api(`/v1/${kind}/${id}/spectra?${q}`);
    if (r.status !== 200) { chart.replaceChildren(h("p", { class: "error" }, r.body.detail)); return; }
    const s = r.body;
    lineChart(chart, { x: s.amplitude.map((_, i) => i * s.df), y: s.amplitude, yFromZero: true, xLabel: "frequency (Hz)",
      yLabel: kind === "simulations" ? "envelope amplitude (m/s^2)" : "envelope amplitude (unit of the signal)",
      markers: s.markers.map((m) => ({ x: m.frequency, label: `${m.name.toUpperCase()}${m.harmonic > 1 ? "×" + m.harmonic : ""}`, cls: `marker-${m.name}` })) });
    chart.dataset.kind = s.kind;
    info.textContent = `${s.kind}${s.level ? " level " + s.level : ""}, bin width ${fmt(s.df)} Hz`;
  };
  which.addEventListener("change", load);
  fmax.addEventListener("change", load);
  load();
  return h("div", { class: "plot" }, h("h3", {}, "Envelope spectrum with the theoretical fault frequencies"),
    h("div", { class: "controls" }, h("label", {}, "Spectrum ", which), h("label", {}, "up to (Hz) ", fmax), info), chart);
}


// ---------------------------------------------------------------- studies

async function studiesView(gen) {
  const r = await api("/v1/studies?limit=50");
  if (gen !== generation) return;
  const items = r.body.items || [];
  view.replaceChildren(h("h2", {}, "Studies"),
    h("p", { class: "muted" }, "Parameter studies (submitted with POST /v1/studies or bearing-sim study): their table and trend plots."),
    h("table", { id: "studies" },
      h("thead", {}, h("tr", {}, ["study", "state", "points done", "created"].map((c) => h("th", {}, c)))),
      h("tbody", {}, items.length ? items.map((st) => h("tr", {},
        h("td", {}, h("a", { href: `#/studies/${st.id}` }, st.name)),
        h("td", { class: `state-${st.state}` }, st.state),
        h("td", {}, `${st.progress.points_done} / ${st.progress.points_total}`),
        h("td", {}, when(st.created_at)))) : h("tr", {}, h("td", { colspan: 4, class: "muted" }, "No studies yet.")))));
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
  body.append(h("div", { class: "plot" }, h("h3", {}, "Table (errors of the cage-derived frequencies against theory)"),
    h("table", { id: "study-table" },
      h("thead", {}, h("tr", {}, cols.map((c) => h("th", {}, c)))),
      h("tbody", {}, table.rows.map((row) => h("tr", {},
        h("td", {}, row.job_id ? h("a", { href: `#/simulations/${row.job_id}` }, row.index) : row.index),
        ...row.factors.map((f) => h("td", { class: "num" }, fmt(f.value))),
        h("td", {}, row.fault_case ?? ""),
        h("td", { class: `state-${row.state}` }, row.state),
        h("td", { class: "num" }, pct(row.result?.bpfo)), h("td", { class: "num" }, pct(row.result?.bpfi)),
        h("td", { class: "num" }, best(row.result?.bpfo)), h("td", { class: "num" }, best(row.result?.bpfi))))))));
  // the plots are SVG from the service, fetched with the token and shown as images
  for (const [key, href] of Object.entries(st.links)) {
    if (!key.startsWith("plot:")) continue;
    const r = await fetch(href, { headers: tokenInput.value ? { Authorization: `Bearer ${tokenInput.value.trim()}` } : {} });
    if (!r.ok || gen !== generation) continue;
    const url = URL.createObjectURL(await r.blob());
    body.append(h("div", { class: "plot" }, h("h3", {}, key.slice(5)), h("img", { src: url, alt: `trend plot ${key.slice(5)}`, class: "trend" })));
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
    else if ((m = path.match(/^\/(simulations|analyses)\/([\w-]+)$/))) await jobView(gen, m[1], m[2]);
    else view.replaceChildren(h("p", {}, "No such page. ", h("a", { href: "#/" }, "Jobs")));
  } catch (e) {
    if (gen === generation && !banner.textContent) showBanner(`Something went wrong: ${e.message}`);
  }
}

window.addEventListener("hashchange", route);
route();
