// sandlight explorer: one client of the JSON API (docs/explorer.md). Plain JavaScript, SVG and
// canvas; no library, no build step. The view's state lives in the URL's hash, so a link
// reproduces it.

const $ = (id) => document.getElementById(id);
const SVG = "http://www.w3.org/2000/svg";

const state = {
  a: {}, b: {}, editing: "a", compare: false,
  incidence: 30, wavelength: 550, terrain: "flat", lat: 25, day: 110, time: 10, rays: 10000,
};
let schema = null;
let defaults = {};
let spectra = { a: null, b: null };   // answers of /api/spectrum
let mc = null;                        // {key, jobId, result} of the last finished Monte Carlo run
let measured = null;                  // {file, answer}
let refineJob = null;                 // {id, source} of the running Monte Carlo job
let previewJob = null;
let sequence = 0;                     // answers to older requests are dropped

// ---- the API ------------------------------------------------------------------------------
async function api(path, body, method = "POST") {
  const init = { method, headers: {} };
  if (body instanceof FormData) init.body = body;
  else if (body !== undefined) { init.headers["content-type"] = "application/json"; init.body = JSON.stringify(body); }
  const response = await fetch(path, init);
  const json = (response.headers.get("content-type") || "").includes("application/json");
  const data = json ? await response.json() : await response.blob();
  if (!response.ok) {
    const error = new Error(json ? data.message : response.statusText);
    error.body = json ? data : {};
    throw error;
  }
  return data;
}

const key = (sample) => JSON.stringify(sample);

// ---- the URL holds the state ---------------------------------------------------------------
function parameterValue(p, text) {
  if (p.kind === "choice") return text;
  if (text === "inf") return "inf";
  const x = Number(text);
  return Number.isFinite(x) ? x : text;   // the server names a bad value
}

function readHash() {
  // What the hash does not say takes its default, so that a link gives the same view anywhere.
  const params = new URLSearchParams(location.hash.slice(1));
  state.a = { ...defaults }; state.b = { ...defaults };
  for (const [name, value] of params) {
    const [which, parameter] = name.split(".");
    if ((which === "a" || which === "b") && parameter) {
      const p = schema.parameters.find((q) => q.name === parameter);
      if (p) state[which][parameter] = parameterValue(p, value);
    }
  }
  const number = (name, field) => { if (params.has(name)) state[field] = Number(params.get(name)); };
  number("inc", "incidence"); number("wl", "wavelength"); number("lat", "lat");
  number("day", "day"); number("time", "time"); number("rays", "rays");
  if (params.has("terrain")) state.terrain = params.get("terrain");
  state.compare = params.get("cmp") === "1";
}

function writeHash() {
  const params = new URLSearchParams();
  for (const which of ["a", "b"]) {
    if (which === "b" && !state.compare) continue;
    for (const p of schema.parameters) {
      const v = state[which][p.name];
      if (String(v) !== String(defaults[p.name])) params.set(`${which}.${p.name}`, String(v));
    }
  }
  if (state.compare) params.set("cmp", "1");
  params.set("inc", state.incidence); params.set("wl", state.wavelength);
  params.set("terrain", state.terrain); params.set("lat", state.lat); params.set("day", state.day);
  params.set("time", state.time); params.set("rays", state.rays);
  const hash = "#" + params.toString();
  history.replaceState(null, "", hash);
  $("share-link").href = location.href;
}

// ---- the sample editor ---------------------------------------------------------------------
function step(p) { return (p.high - p.low) / 200; }

function buildEditor() {
  const box = $("parameters");
  box.replaceChildren();
  for (const p of schema.parameters) {
    const div = document.createElement("div");
    div.className = "param";
    div.id = `param-${p.name}`;
    const head = document.createElement("div");
    head.className = "name";
    const label = document.createElement("label");
    label.textContent = p.name + (p.unit ? ` [${p.unit}]` : "");
    label.title = p.description;
    label.htmlFor = `input-${p.name}`;
    head.append(label);
    const domain = document.createElement("span");
    domain.className = "domain";
    domain.textContent = p.allowed.replace("a real number in ", "");
    head.append(domain);
    div.append(head);
    if (p.kind === "choice") {
      const select = document.createElement("select");
      select.id = `input-${p.name}`;
      for (const c of p.choices) select.append(new Option(c, c));
      select.addEventListener("change", () => setParameter(p, select.value));
      div.append(select);
    } else if (p.high === "inf") {
      const number = document.createElement("input");
      number.type = "number"; number.id = `input-${p.name}`; number.min = p.low; number.step = "any";
      const infinite = document.createElement("label");
      const box2 = document.createElement("input");
      box2.type = "checkbox"; box2.id = `inf-${p.name}`;
      infinite.append(box2, " semi-infinite (∞)");
      number.addEventListener("input", () => setParameter(p, parameterValue(p, number.value)));
      box2.addEventListener("change", () => setParameter(p, box2.checked ? "inf" : 10));
      div.append(number, " ", infinite);
    } else {
      const range = document.createElement("input");
      range.type = "range"; range.id = `range-${p.name}`;
      range.min = p.low; range.max = p.high; range.step = step(p);
      const number = document.createElement("input");
      number.type = "number"; number.id = `input-${p.name}`; number.step = "any";
      range.addEventListener("input", () => setParameter(p, Number(range.value)));
      number.addEventListener("input", () => setParameter(p, parameterValue(p, number.value)));
      div.append(range, number);
    }
    const error = document.createElement("div");
    error.className = "error"; error.id = `error-${p.name}`;
    div.append(error);
    box.append(div);
  }
}

function showSample() {
  const sample = state[state.editing];
  $("editing-name").textContent = state.editing.toUpperCase();
  $("edit-a").classList.toggle("on", state.editing === "a");
  $("edit-b").classList.toggle("on", state.editing === "b");
  $("edit-b").disabled = !state.compare;
  $("compare").checked = state.compare;
  for (const p of schema.parameters) {
    const v = sample[p.name];
    const input = $(`input-${p.name}`);
    if (p.kind === "choice") input.value = v;
    else if (p.high === "inf") {
      $(`inf-${p.name}`).checked = v === "inf";
      input.disabled = v === "inf";
      if (v !== "inf" && document.activeElement !== input) input.value = v;
      if (v === "inf") input.value = "";
    } else {
      $(`range-${p.name}`).value = v;
      if (document.activeElement !== input) input.value = v;
    }
  }
}

function setParameter(p, value) {
  state[state.editing][p.name] = value;
  $("preset").value = "";
  showSample();
  schedule();
}

function clearErrors() {
  $("sample-error").textContent = "";
  for (const p of schema.parameters) {
    $(`error-${p.name}`).textContent = "";
    $(`param-${p.name}`).classList.remove("invalid");
  }
}

function showError(error) {
  // The API names the parameter: show its message beside it, or above the editor.
  const body = error.body || {};
  // "compare.x" names parameter x of sample B; the editor shows the sample being edited.
  const ofB = (body.parameter || "").startsWith("compare.");
  const name = ofB ? body.parameter.slice(8) : body.parameter;
  if (ofB !== (state.editing === "b")) {
    $("sample-error").textContent = `sample ${ofB ? "B" : "A"}: ${error.message}`;
    return;
  }
  const p = name && schema.parameters.find((q) => q.name === name);
  if (p) {
    $(`error-${name}`).textContent = body.message;
    $(`param-${name}`).classList.add("invalid");
  } else {
    $("sample-error").textContent = error.message;
    for (const q of schema.parameters) if (name && name.includes(q.name)) $(`param-${q.name}`).classList.add("invalid");
  }
}

// ---- refreshing the view -------------------------------------------------------------------
let timer = null;
function schedule() { clearTimeout(timer); timer = setTimeout(refresh, 60); }

async function refresh() {
  const mine = ++sequence;
  writeHash();
  const a = state.a, b = state.compare ? state.b : null;
  if (mc && mc.key !== key(a)) mc = null;
  const results = await Promise.allSettled([
    api("/api/spectrum", { sample: a }),
    b ? api("/api/spectrum", { sample: b }) : Promise.resolve(null),
    api("/api/colour", { sample: a, compare: b }),
  ]);
  if (mine !== sequence) return;
  clearErrors();
  // The colour request names a parameter of B as "compare.x": its error says which sample is wrong.
  const failure = results[2].status === "rejected" ? results[2] : results.find((r) => r.status === "rejected");
  if (failure) {
    showError(failure.reason);
    return;
  }
  const [sa, sb, colour] = results.map((r) => r.value);
  spectra = { a: sa, b: sb };
  showModel(sa);
  showColour(colour);
  if (measured) await uploadMeasured(measured.file);
  plotSpectrum();
  refreshBrdf(mine);
}

function showModel(answer) {
  if (answer.covered) {
    $("model-name").textContent = `model ${answer.model}`;
    $("model-error").textContent = `(hold-out RMS error ${answer.holdout_rms.toFixed(4)}; ${answer.note})`;
    $("uncovered").hidden = true;
  } else {
    $("model-name").textContent = "no model";
    $("model-error").textContent = "";
    $("uncovered").hidden = false;
    $("uncovered").textContent = `Outside every model's domain: ${answer.reason}. Refine with Monte Carlo for this sample.`;
  }
}

function labText(c) {
  const f = (v) => v.map((x) => x.toFixed(1)).join(", ");
  return `L*a*b* D50 (${f(c.lab_d50)}) · D65 (${f(c.lab_d65)})${c.out_of_gamut ? " · outside sRGB, clipped" : ""}`;
}

function showColour(colour) {
  const one = (c, which) => {
    const mcColour = which === "a" && mc && mc.result.colour;
    const shown = c.covered ? c : mcColour;
    $(`swatch-${which}`).style.background = shown ? shown.hex : "repeating-linear-gradient(45deg,#ccc,#ccc 6px,#eee 6px,#eee 12px)";
    $(`lab-${which}`).textContent = shown ? labText(shown) + (c.covered ? "" : " (Monte Carlo)") : "no model covers this sample";
  };
  one(colour.a, "a");
  $("figure-b").hidden = !colour.b;
  if (colour.b) one(colour.b, "b");
  $("delta-e").textContent = colour.b
    ? (colour.delta_e2000 === null ? "ΔE₀₀(A, B): needs both samples covered by a model" : `ΔE₀₀(A, B) = ${colour.delta_e2000.toFixed(2)}`)
    : "";
}

// ---- the spectrum plot ---------------------------------------------------------------------
function el(name, attrs, parent) {
  const e = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (parent) parent.append(e);
  return e;
}

// A round step (1, 2 or 5 × 10ⁿ) at least `rough`, and the multiples of a step inside [lo, hi].
function niceStep(rough) {
  const power = 10 ** Math.floor(Math.log10(rough));
  return [1, 2, 5, 10].map((k) => k * power).find((k) => k >= rough * (1 - 1e-9));
}
function ticks(lo, hi, stepSize) {
  const out = [];
  for (let k = Math.ceil(lo / stepSize - 1e-9); k * stepSize <= hi + 1e-9; k++) out.push(k * stepSize);
  return out;
}

function linePlot(svg, series, xRange, yLabel, xLabel) {
  svg.replaceChildren();
  const [w, h] = [svg.viewBox.baseVal.width, svg.viewBox.baseVal.height];
  const m = { l: 52, r: 22, t: 10, b: 36 };
  let yMax = 0;
  for (const s of series) for (const y of [...s.y, ...(s.upper || [])]) if (y !== null && y > yMax) yMax = y;
  const yStep = niceStep((yMax > 0 ? yMax * 1.02 : 1) / 5);
  yMax = Math.ceil((yMax > 0 ? yMax * 1.02 : 1) / yStep) * yStep;
  const X = (x) => m.l + ((x - xRange[0]) / (xRange[1] - xRange[0])) * (w - m.l - m.r);
  const Y = (y) => h - m.b - (y / yMax) * (h - m.t - m.b);
  const axis = el("g", { class: "axis" }, svg);
  el("line", { x1: m.l, y1: h - m.b, x2: w - m.r, y2: h - m.b }, axis);
  el("line", { x1: m.l, y1: m.t, x2: m.l, y2: h - m.b }, axis);
  for (const x of ticks(xRange[0], xRange[1], niceStep((xRange[1] - xRange[0]) / 6))) {
    el("line", { x1: X(x), y1: h - m.b, x2: X(x), y2: h - m.b + 4 }, axis);
    el("text", { x: X(x), y: h - m.b + 16, "text-anchor": "middle" }, axis).textContent = Math.round(x);
  }
  const digits = Math.max(0, -Math.floor(Math.log10(yStep) + 1e-9));
  for (const y of ticks(0, yMax, yStep)) {
    el("line", { x1: m.l - 4, y1: Y(y), x2: m.l, y2: Y(y) }, axis);
    el("text", { x: m.l - 6, y: Y(y) + 4, "text-anchor": "end" }, axis).textContent = y.toFixed(digits);
  }
  el("text", { x: (m.l + w - m.r) / 2, y: h - 4, "text-anchor": "middle" }, axis).textContent = xLabel;
  el("text", { x: 12, y: (m.t + h - m.b) / 2, transform: `rotate(-90 12 ${(m.t + h - m.b) / 2})`, "text-anchor": "middle" }, axis).textContent = yLabel;
  for (const s of series) {
    const inside = (x) => x >= xRange[0] && x <= xRange[1];
    if (s.upper) {
      const up = s.x.map((x, i) => [x, s.upper[i]]).filter(([x]) => inside(x));
      const low = s.x.map((x, i) => [x, s.lower[i]]).filter(([x]) => inside(x)).reverse();
      const points = [...up, ...low].map(([x, y]) => `${X(x).toFixed(1)},${Y(Math.max(0, y)).toFixed(1)}`).join(" ");
      el("polygon", { points, fill: s.colour, "fill-opacity": 0.18, stroke: "none", class: s.name + "-band" }, svg);
    }
    let d = "";
    let pen = "M";
    s.x.forEach((x, i) => {
      const y = s.y[i];
      if (y === null || !inside(x)) { pen = "M"; return; }
      d += `${pen}${X(x).toFixed(1)},${Y(y).toFixed(1)} `;
      pen = "L";
    });
    el("path", { d, fill: "none", stroke: s.colour, "stroke-width": s.width || 2, class: s.name }, svg);
  }
}

function plotSpectrum() {
  const series = [];
  const legend = [];
  const wide = mc || measured;
  const range = wide ? schema.engine_range_nm : [schema.model_wavelengths_nm[0], schema.model_wavelengths_nm.at(-1)];
  if (spectra.a && spectra.a.covered) {
    series.push({ name: "model-a", x: spectra.a.wavelengths_nm, y: spectra.a.reflectance, colour: "#b8562a" });
    legend.push(["model", `A: ${spectra.a.model}`]);
  }
  if (spectra.b && spectra.b.covered) {
    series.push({ name: "model-b", x: spectra.b.wavelengths_nm, y: spectra.b.reflectance, colour: "#6a9a2a" });
    legend.push(["b", `B: ${spectra.b.model}`]);
  }
  if (mc) {
    const r = mc.result;
    series.push({
      name: "mc", x: r.wavelengths_nm, y: r.reflectance, colour: "#2a6fb8",
      upper: r.reflectance.map((v, i) => v + 2 * r.stderr[i]), lower: r.reflectance.map((v, i) => v - 2 * r.stderr[i]),
    });
    legend.push(["mc", `A: Monte Carlo, ${r.rays.toLocaleString()} rays (band ± 2 standard errors)`]);
  }
  if (measured) {
    const m = measured.answer;
    series.push({ name: "measured", x: m.wavelengths_nm, y: m.reflectance, colour: "#222", width: 1.2 });
    legend.push(["measured", `measured: ${m.name}`]);
  }
  linePlot($("spectrum-svg"), series, range, "reflectance", "wavelength (nm)");
  $("spectrum-legend").replaceChildren(...legend.map(([cls, text]) => {
    const span = document.createElement("span");
    span.className = cls; span.textContent = "— " + text;
    return span;
  }));
}

// ---- Monte Carlo refinement ----------------------------------------------------------------
function follow(job, handlers) {
  const source = new EventSource(`/api/jobs/${job.id}/events`);
  for (const [name, handler] of Object.entries(handlers)) {
    source.addEventListener(name, (event) => handler(JSON.parse(event.data)));
  }
  for (const end of ["done", "cancelled", "failed"]) source.addEventListener(end, () => source.close());
  return source;
}

async function refine() {
  $("refine-status").textContent = "";
  const sample = { ...state.a };
  const rays = Number($("rays").value);
  state.rays = rays;
  writeHash();
  let job;
  try {
    job = await api("/api/jobs/reflectance", { sample, rays });
  } catch (error) {
    $("refine-status").textContent = error.message;
    showError(error);
    return;
  }
  $("refine-button").disabled = true;
  $("cancel-button").disabled = false;
  $("refine-progress").value = 0;
  $("refine-status").textContent = "queued";
  refineJob = job;
  const finish = (text) => {
    $("refine-button").disabled = false;
    $("cancel-button").disabled = true;
    $("refine-status").textContent = text;
    refineJob = null;
  };
  job.source = follow(job, {
    progress: (p) => { $("refine-progress").value = p.fraction; $("refine-status").textContent = `${p.state}: ${p.text}`; },
    done: (status) => {
      mc = { key: key(sample), jobId: job.id, result: status.result };
      $("refine-progress").value = 1;
      finish(`done: ${status.result.rays.toLocaleString()} rays per wavelength in ${status.result.elapsed_s.toFixed(1)} s`);
      schedule();
    },
    cancelled: () => finish("cancelled"),
    failed: (status) => finish(`failed: ${status.error.message}`),
  });
}

async function cancelRefine() {
  if (refineJob) await api(`/api/jobs/${refineJob.id}`, undefined, "DELETE");
}

// ---- measured spectrum ---------------------------------------------------------------------
async function uploadMeasured(file) {
  const form = new FormData();
  form.append("file", file);
  form.append("sample", JSON.stringify(state.a));
  $("measured-error").textContent = "";
  try {
    const answer = await api("/api/measured", form);
    measured = { file, answer };
    $("rms").textContent = answer.rms === null
      ? `${answer.name}: no model wavelengths to compare`
      : `RMS(model − measured) = ${answer.rms.toFixed(4)} over ${answer.compared_nm[0]}–${answer.compared_nm.at(-1)} nm (${answer.compared_nm.length} wavelengths, ${answer.model})`;
  } catch (error) {
    measured = null;
    $("rms").textContent = "";
    $("measured-error").textContent = error.message;
  }
}

// ---- BRDF ----------------------------------------------------------------------------------
const STOPS = [[0, 0, 4], [87, 16, 110], [188, 55, 84], [249, 142, 9], [252, 255, 164]]; // inferno-like
function colourMap(t) {
  const x = Math.min(1, Math.max(0, t)) * (STOPS.length - 1);
  const i = Math.min(STOPS.length - 2, Math.floor(x));
  const f = x - i;
  const c = STOPS[i].map((v, k) => Math.round(v + f * (STOPS[i + 1][k] - v)));
  return `rgb(${c[0]},${c[1]},${c[2]})`;
}

let brdfTimer = null;
function refreshBrdf(mine) {
  clearTimeout(brdfTimer);
  brdfTimer = setTimeout(async () => {
    try {
      const answer = await api("/api/brdf", {
        sample: state.a, incidence_deg: state.incidence, wavelength_nm: state.wavelength,
      });
      if (mine !== sequence) return;
      $("brdf-error").textContent = "";
      $("brdf-note").textContent = answer.warnings.join(" ");
      drawPolar(answer);
      const p = answer.principal_plane;
      linePlot($("plane-svg"), [{ name: "plane", x: p.theta_deg, y: p.f, colour: "#b8562a" }], [-90, 90], "f (1/sr)", "view zenith θ (°)");
    } catch (error) {
      if (mine === sequence) $("brdf-error").textContent = error.message;
    }
  }, 120);
}

function drawPolar(answer) {
  const canvas = $("brdf-canvas");
  const ctx = canvas.getContext("2d");
  const { theta_deg: theta, phi_deg: phi, f } = answer.polar;
  const r0 = canvas.width / 2 - 10;
  const [cx, cy] = [canvas.width / 2, canvas.height / 2];
  let max = 0;
  for (const row of f) for (const v of row) if (v > max) max = v;
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const dt = 90 / theta.length, dp = (2 * Math.PI) / phi.length;
  theta.forEach((t, i) => {
    phi.forEach((p, j) => {
      const a = (p * Math.PI) / 180;
      ctx.beginPath();
      ctx.arc(cx, cy, ((t + dt / 2) / 90) * r0, -(a + dp / 2), -(a - dp / 2));
      ctx.arc(cx, cy, ((t - dt / 2) / 90) * r0, -(a - dp / 2), -(a + dp / 2), true);
      ctx.closePath();
      ctx.fillStyle = colourMap(f[i][j] / max);
      ctx.fill();
    });
  });
  ctx.strokeStyle = "#fff";
  ctx.beginPath(); ctx.arc(cx + (answer.incidence_deg / 90) * r0, cy, 4, 0, 2 * Math.PI); ctx.stroke();
  $("brdf-caption").textContent =
    `f(ωᵢ, ωₒ) at θᵢ = ${answer.incidence_deg}°, ${answer.wavelength_nm} nm; max ${max.toFixed(3)} sr⁻¹, albedo ${answer.albedo.toFixed(3)}; light at the white circle, φ = 0 to the right`;
}

// ---- preview -------------------------------------------------------------------------------
async function renderPreview() {
  $("preview-error").textContent = "";
  state.terrain = $("terrain").value; state.lat = Number($("latitude").value);
  state.day = Number($("day").value); state.time = Number($("time").value);
  writeHash();
  if (previewJob) await api(`/api/jobs/${previewJob.id}`, undefined, "DELETE").catch(() => {});
  let job;
  try {
    job = await api("/api/jobs/preview", {
      sample: state.a, terrain: state.terrain, latitude_deg: state.lat, day_of_year: state.day, time_h: state.time,
    });
  } catch (error) {
    $("preview-error").textContent = error.message;
    return;
  }
  previewJob = job;
  $("preview-progress").value = 0;
  follow(job, {
    image: (image) => { $("preview-img").src = image.url; },
    progress: (p) => { $("preview-progress").value = p.fraction; },
    done: () => { previewJob = null; },
    cancelled: () => { previewJob = null; },
    failed: (status) => { previewJob = null; $("preview-error").textContent = status.error.message; },
  });
}

// ---- exports -------------------------------------------------------------------------------
async function exportFile(name) {
  $("export-error").textContent = "";
  const body = { sample: state.a };
  if (name.startsWith("spectrum") && mc) body.job = mc.jobId;
  try {
    const blob = await api(`/api/export/${name}`, body);
    const link = document.createElement("a");
    link.href = URL.createObjectURL(blob);
    link.download = `sandlight-${name}`;
    document.body.append(link);
    link.click();
    link.remove();
    setTimeout(() => URL.revokeObjectURL(link.href), 10000);
  } catch (error) {
    $("export-error").textContent = error.message;
  }
}

function showControls() {
  $("incidence").value = state.incidence; $("wavelength").value = state.wavelength;
  $("incidence-value").textContent = `${state.incidence}°`; $("wavelength-value").textContent = `${state.wavelength} nm`;
  $("terrain").value = state.terrain; $("latitude").value = state.lat; $("day").value = state.day;
  $("time").value = state.time; $("rays").value = state.rays;
}

// ---- start ---------------------------------------------------------------------------------
async function start() {
  schema = await api("/api/schema", undefined, "GET");
  for (const p of schema.parameters) defaults[p.name] = p.default;
  for (const name of Object.keys(schema.presets)) $("preset").append(new Option(name, name));
  readHash();
  buildEditor();
  showControls();
  $("rays").max = schema.limits.max_rays;

  $("preset").addEventListener("change", () => {
    const name = $("preset").value;
    if (!name) return;
    state[state.editing] = { ...schema.presets[name] };
    showSample(); schedule();
    $("preset").value = name;
  });
  $("edit-a").addEventListener("click", () => { state.editing = "a"; showSample(); });
  $("edit-b").addEventListener("click", () => { state.editing = "b"; showSample(); });
  $("compare").addEventListener("change", () => {
    state.compare = $("compare").checked;
    if (!state.compare) state.editing = "a";
    showSample(); schedule();
  });
  $("reset").addEventListener("click", () => { state[state.editing] = { ...defaults }; showSample(); schedule(); });
  $("incidence").addEventListener("input", () => {
    state.incidence = Number($("incidence").value); $("incidence-value").textContent = `${state.incidence}°`; writeHash(); refreshBrdf(sequence);
  });
  $("wavelength").addEventListener("input", () => {
    state.wavelength = Number($("wavelength").value); $("wavelength-value").textContent = `${state.wavelength} nm`; writeHash(); refreshBrdf(sequence);
  });
  $("refine-button").addEventListener("click", refine);
  $("cancel-button").addEventListener("click", cancelRefine);
  $("measured-file").addEventListener("change", async () => {
    const file = $("measured-file").files[0];
    if (file) { await uploadMeasured(file); plotSpectrum(); }
  });
  $("preview-button").addEventListener("click", renderPreview);
  for (const button of document.querySelectorAll("button.export")) {
    button.addEventListener("click", () => exportFile(button.dataset.name));
  }
  window.addEventListener("hashchange", () => { readHash(); showControls(); showSample(); schedule(); });
  showSample();
  await refresh();
  document.body.dataset.ready = "1";
}

start().catch((error) => {
  document.body.dataset.ready = "error";
  $("sample-error").textContent = `the explorer could not start: ${error.message}`;
});
