// The omnee demo page: all numbers come from omnee-core through ./pkg (wasm-bindgen --target web).
import init, { Demo, arc, histogram, quantile, waterlevel, version } from './pkg/omnee_wasm.js';
import { LOBE_REFERENCES } from './lobe-references.js';

const $ = (id) => document.getElementById(id);
const SEED = 2022;

// The techniques: the rows of the estimates table, each with the module's name for it
// (`Technique`: 'omnee', 'equiangular', 'mis', 'lobe', 'lobe-mis'), a short label, its colour
// from style.css, and whether it needs a lobe at x0.
const TECHNIQUES = [...document.querySelectorAll('tr[data-technique]')].map((row) => ({
  name: row.dataset.technique,
  label: row.dataset.label,
  row,
  color: getComputedStyle(row.querySelector('th')).color,
  lobe: row.dataset.lobe !== undefined,
}));
// The techniques the current problem runs: with a lobe at x0 all, else those without.
const active = () => TECHNIQUES.filter((t) => state.tilt !== undefined || !t.lobe);
const emptyHistory = () => Object.fromEntries(TECHNIQUES.map((t) => [t.name, []]));

const state = {
  x0: [-0.5, 0.0],
  x2: [0.5, 0.0],
  spec: 'hg:0.9',
  tilt: undefined, // radians with a lobe at x0, undefined without
  reference: NaN, // the module's without a lobe, else the precomputed one (or NaN)
  demo: null,
  running: true,
  history: emptyHistory(),
  rate: 0,
  samplesPerFrame: 20000,
  error: '',
};

// ---- world <-> canvas (equal aspect, origin at the centre) ----
const view = $('view');
const SCALE = 200; // pixels per world unit
const toPx = ([x, y]) => [view.width / 2 + x * SCALE, view.height / 2 - y * SCALE];
const toWorld = (px, py) => [(px - view.width / 2) / SCALE, (view.height / 2 - py) / SCALE];

function fmt(x, digits = 4) {
  if (!Number.isFinite(x)) return String(x);
  if (x !== 0 && (Math.abs(x) < 1e-3 || Math.abs(x) >= 1e5)) return x.toExponential(digits - 1);
  return x.toPrecision(digits);
}

function showError(e) {
  state.error = e ? String(e.message ?? e) : '';
  $('error').textContent = state.error;
}

// ---- the phase function controls ----
function specFromControls() {
  const g = Number($('g').value);
  switch ($('family').value) {
    case 'hg': return `hg:${g}`;
    case 'tthg': return `tthg:${g},-0.4,0.9`;
    case 'draine': return `draine:${g},1`;
    case 'ff': return 'ff:0.02,1.1';
    case 'mie': return `mie:${Number($('diameter').value)}`;
    case 'rayleigh': return 'rayleigh';
    default: return 'iso';
  }
}

// The precomputed 3-D reference with a lobe at x0 (lobe-references.js) if the problem is one of
// the table's and the tilt one of its steps, else NaN.
function lobeReference(sigmaS, sigmaA, thetaMax) {
  const t = LOBE_REFERENCES;
  const same = (a, b) => a[0] === b[0] && a[1] === b[1];
  const k = Math.round(state.tilt / t.tiltStep);
  const onStep = k / 10 === state.tilt && t.tiltStep === 0.1;
  const list = Object.hasOwn(t.references, state.spec) ? t.references[state.spec] : [];
  const match = same(state.x0, t.x0) && same(state.x2, t.x2)
    && sigmaS === t.sigmaS && sigmaA === t.sigmaA && thetaMax === t.thetaMax;
  return match && onStep && k < list.length ? list[k] : NaN;
}

// ---- the estimator (rebuilt whenever the problem changes) ----
function rebuild() {
  state.tilt = $('lobe').checked ? Number($('tilt').value) : undefined;
  $('tilt-out').textContent = Number($('tilt').value).toFixed(1);
  for (const { row, lobe } of TECHNIQUES) row.hidden = lobe && state.tilt === undefined;
  try {
    const [sigmaS, sigmaA, thetaMax] = ['sigma-s', 'sigma-a', 'theta-max'].map((id) => Number($(id).value));
    const demo = new Demo(state.spec, state.x0[0], state.x0[1], state.x2[0], state.x2[1],
      sigmaS, sigmaA, thetaMax, SEED, state.tilt);
    if (state.demo) state.demo.free();
    state.demo = demo;
    state.reference = state.tilt === undefined ? demo.reference : lobeReference(sigmaS, sigmaA, thetaMax);
    state.history = emptyHistory();
    showError(null);
  } catch (e) {
    showError(e);
  }
  drawView();
  drawHistogram();
  updateEstimates();
}

// ---- the waterlevel view ----
function drawView() {
  const ctx = view.getContext('2d');
  ctx.clearRect(0, 0, view.width, view.height);
  const theta = Number($('theta').value);
  const xi = Number($('xi').value);
  $('theta-out').textContent = theta.toFixed(2);
  $('xi-out').textContent = xi.toFixed(2);
  // the sample cloud
  const technique = $('cloud').value;
  if (state.demo && active().some((t) => t.name === technique)) {
    const pts = state.demo.cloud(technique, 3000, 7);
    // Colours relative to the reference, or to the cloud's mean where there is none.
    let ref = state.reference;
    if (!Number.isFinite(ref)) {
      ref = 0;
      for (let i = 2; i < pts.length; i += 3) ref += pts[i] / (pts.length / 3);
    }
    for (let i = 0; i < pts.length; i += 3) {
      const r = Math.log2(Math.max(pts[i + 2], 1e-30) / ref); // 0 = the reference
      const c = Math.max(-1, Math.min(1, r / 4));
      ctx.fillStyle = c >= 0 ? `rgba(214,39,40,${0.25 + 0.5 * c})` : `rgba(31,119,180,${0.25 - 0.5 * c})`;
      const [px, py] = toPx([pts[i], pts[i + 1]]);
      ctx.fillRect(px - 1, py - 1, 2, 2);
    }
  }
  // the axis and the arc of constant θ on both sides
  const [a, b] = [toPx(state.x0), toPx(state.x2)];
  ctx.strokeStyle = '#999';
  ctx.setLineDash([4, 4]);
  ctx.beginPath(); ctx.moveTo(...a); ctx.lineTo(...b); ctx.stroke();
  ctx.setLineDash([]);
  let w;
  try {
    const pts = arc(state.x0[0], state.x0[1], state.x2[0], state.x2[1], theta, 128);
    ctx.strokeStyle = '#1a4f8b';
    ctx.lineWidth = 2;
    const half = pts.length / 2;
    for (const start of [0, half]) {
      ctx.beginPath();
      for (let i = start; i < start + half; i += 2) ctx.lineTo(...toPx([pts[i], pts[i + 1]]));
      ctx.stroke();
    }
    ctx.lineWidth = 1;
    w = waterlevel(state.x0[0], state.x0[1], state.x2[0], state.x2[1], theta, xi);
  } catch (e) {
    showError(e);
  }
  if (w) drawTriangle(ctx, w);
  for (const [p, name] of [[a, 'x₀'], [b, 'x₂']]) {
    ctx.fillStyle = '#000';
    ctx.beginPath(); ctx.arc(p[0], p[1], 6, 0, 2 * Math.PI); ctx.fill();
    ctx.font = '15px system-ui'; ctx.fillText(name, p[0] - 8, p[1] + 22);
  }
}

function angleMark(ctx, centre, from, to, radius, label) {
  const a0 = Math.atan2(from[1] - centre[1], from[0] - centre[0]);
  const a1 = Math.atan2(to[1] - centre[1], to[0] - centre[0]);
  let d = a1 - a0;
  while (d > Math.PI) d -= 2 * Math.PI;
  while (d < -Math.PI) d += 2 * Math.PI;
  ctx.beginPath();
  ctx.arc(centre[0], centre[1], radius, a0, a0 + d, d < 0);
  ctx.stroke();
  const mid = a0 + d / 2;
  ctx.fillText(label, centre[0] + (radius + 12) * Math.cos(mid) - 4, centre[1] + (radius + 12) * Math.sin(mid) + 5);
}

function drawTriangle(ctx, w) {
  const [a, b, c] = [toPx(state.x0), toPx(state.x2), toPx([w.x1x, w.x1y])];
  ctx.strokeStyle = '#e07000';
  ctx.lineWidth = 2;
  ctx.beginPath(); ctx.moveTo(...a); ctx.lineTo(...c); ctx.lineTo(...b); ctx.stroke();
  ctx.lineWidth = 1;
  // the continuation of x0 -> x1 beyond x1: θ is the angle between it and x1 -> x2
  const dir = [c[0] - a[0], c[1] - a[1]];
  const len = Math.hypot(...dir) || 1;
  const ext = [c[0] + (dir[0] / len) * 60, c[1] + (dir[1] / len) * 60];
  ctx.setLineDash([3, 3]);
  ctx.beginPath(); ctx.moveTo(...c); ctx.lineTo(...ext); ctx.stroke();
  ctx.setLineDash([]);
  ctx.fillStyle = '#e07000';
  ctx.font = 'italic 15px system-ui';
  angleMark(ctx, a, b, c, 34, 'α');
  angleMark(ctx, b, a, c, 34, 'β');
  angleMark(ctx, c, ext, b, 26, 'θ');
  ctx.beginPath(); ctx.arc(c[0], c[1], 5, 0, 2 * Math.PI); ctx.fill();
  ctx.fillText('x₁', c[0] + 8, c[1] - 8);
  // the foot of x1 on the axis at the talk's t
  const foot = toPx([state.x0[0] + w.t * (state.x2[0] - state.x0[0]), state.x0[1] + w.t * (state.x2[1] - state.x0[1])]);
  ctx.strokeStyle = '#e07000';
  ctx.setLineDash([2, 3]);
  ctx.beginPath(); ctx.moveTo(...c); ctx.lineTo(...foot); ctx.stroke();
  ctx.setLineDash([]);
  ctx.fillText(`t = ${w.t.toFixed(3)}`, foot[0] + 4, foot[1] + 18);
  const set = (id, x) => { $(id).textContent = fmt(x, 6); };
  set('alpha', w.alpha); set('beta', w.beta); set('theta-val', w.theta); set('t-val', w.t);
  set('d1', w.d1); set('d2', w.d2); set('s-val', w.s); set('radius', w.radius); set('xi-val', w.xi);
}

// ---- dragging x0 and x2 ----
let dragging = null;
function pointer(ev) {
  const r = view.getBoundingClientRect();
  return [(ev.clientX - r.left) * (view.width / r.width), (ev.clientY - r.top) * (view.height / r.height)];
}
view.addEventListener('pointerdown', (ev) => {
  const [px, py] = pointer(ev);
  for (const key of ['x0', 'x2']) {
    const [qx, qy] = toPx(state[key]);
    if (Math.hypot(px - qx, py - qy) < 14) {
      dragging = key;
      view.setPointerCapture(ev.pointerId);
    }
  }
});
view.addEventListener('pointermove', (ev) => {
  if (!dragging) return;
  state[dragging] = toWorld(...pointer(ev));
  rebuild();
});
view.addEventListener('pointerup', () => { dragging = null; });

// ---- the histogram of θ ----
function drawHistogram() {
  const canvas = $('hist');
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  let h, hi;
  try {
    hi = Math.min(Math.PI, Math.max(0.02, quantile(state.spec, 0.995) * 1.05));
    h = histogram(state.spec, 100000, 64, hi, 11);
  } catch (e) {
    showError(e);
    return;
  }
  const bins = h.length / 2;
  const top = Math.max(...h) * 1.1 || 1;
  const [L, B, W, H] = [50, canvas.height - 30, canvas.width - 70, canvas.height - 50];
  const x = (k) => L + (k / bins) * W;
  const y = (v) => B - (v / top) * H;
  ctx.fillStyle = 'rgba(31,119,180,0.45)';
  for (let k = 0; k < bins; k++) ctx.fillRect(x(k), y(h[k]), W / bins - 1, B - y(h[k]));
  ctx.strokeStyle = '#d62728';
  ctx.lineWidth = 2;
  ctx.beginPath();
  for (let k = 0; k < bins; k++) { ctx.lineTo(x(k), y(h[bins + k])); ctx.lineTo(x(k + 1), y(h[bins + k])); }
  ctx.stroke();
  ctx.lineWidth = 1;
  ctx.strokeStyle = '#333'; ctx.fillStyle = '#333'; ctx.font = '12px system-ui';
  ctx.beginPath(); ctx.moveTo(L, B - H); ctx.lineTo(L, B); ctx.lineTo(L + W, B); ctx.stroke();
  for (let i = 0; i <= 4; i++) ctx.fillText((hi * i / 4).toFixed(3), L + (W * i) / 4 - 12, B + 16);
  ctx.fillText('θ (rad)', L + W - 40, B - 6);
  ctx.fillText(fmt(top / 1.1, 3), 4, B - H / 1.1 + 4);
  ctx.fillText(`density of θ for ${state.spec}: sampled (bars), exact (line)`, L + 10, 16);
}

// ---- live convergence ----
function updateEstimates() {
  const d = state.demo;
  const ref = state.reference;
  const known = Number.isFinite(ref);
  $('reference').textContent = d && known ? fmt(ref, 7) : '–';
  $('reference-note').textContent = state.tilt === undefined ? ''
    : known ? '3-D quadrature, precomputed (lobe-references.js)'
      : 'not precomputed for this problem: the plot shows the relative standard error';
  $('lobe-c').textContent = d && state.tilt !== undefined ? fmt(d.lobeProbability, 3) : '–';
  for (const { name, row } of active()) {
    if (!d) break;
    const e = d.estimate(name);
    const rel = Math.abs(e.mean - ref) / ref;
    const set = (cell, text) => { row.querySelector(`.${cell}`).textContent = text; };
    set('count', e.count.toLocaleString('en-US'));
    set('mean', fmt(e.mean, 6));
    set('se', fmt(e.stdError, 3));
    set('rel', known ? fmt(rel, 3) : '–');
    set('z', known && e.stdError > 0 ? ((e.mean - ref) / e.stdError).toFixed(2) : '–');
    if (e.count > 0) {
      const h = state.history[name];
      const y = known ? rel : e.stdError / Math.abs(e.mean);
      if (!h.length || e.count >= 1.1 * h[h.length - 1][0]) h.push([e.count, Math.max(y, 1e-7)]);
    }
  }
  $('rate').textContent = state.rate ? Math.round(state.rate).toLocaleString('en-US') : '–';
  drawConvergence();
}

function drawConvergence() {
  const canvas = $('conv');
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const [L, B, W, H] = [50, canvas.height - 30, canvas.width - 70, canvas.height - 50];
  const [nLo, nHi, eLo, eHi] = [2, 9, -6, 1]; // log10 ranges
  const x = (n) => L + ((Math.log10(n) - nLo) / (nHi - nLo)) * W;
  const y = (e) => B - ((Math.log10(e) - eLo) / (eHi - eLo)) * H;
  ctx.strokeStyle = '#333'; ctx.fillStyle = '#333'; ctx.font = '12px system-ui';
  ctx.beginPath(); ctx.moveTo(L, B - H); ctx.lineTo(L, B); ctx.lineTo(L + W, B); ctx.stroke();
  for (let p = nLo; p <= nHi; p++) ctx.fillText(`1e${p}`, x(10 ** p) - 10, B + 16);
  for (let p = eLo; p <= eHi; p++) ctx.fillText(`1e${p}`, 8, y(10 ** p) + 4);
  ctx.fillText(Number.isFinite(state.reference) ? 'relative error vs samples' : 'relative standard error vs samples', L + 10, 16);
  active().forEach(({ name, label, color }, t) => {
    ctx.strokeStyle = color;
    ctx.lineWidth = 2;
    ctx.beginPath();
    for (const [n, e] of state.history[name]) ctx.lineTo(x(n), Math.min(B, Math.max(B - H, y(e))));
    ctx.stroke();
    ctx.fillStyle = color;
    ctx.fillText(label, L + W - 90, 16 + 14 * t);
  });
  ctx.lineWidth = 1;
}

/** Runs `n` samples per technique in one wasm call and returns the throughput (samples/s, all techniques). */
function measure(n) {
  const t0 = performance.now();
  state.demo.run(n);
  const dt = (performance.now() - t0) / 1000;
  return (active().length * n) / Math.max(dt, 1e-6);
}

function frame() {
  if (state.running && state.demo) {
    try {
      const t0 = performance.now();
      state.demo.run(state.samplesPerFrame);
      const dt = performance.now() - t0;
      state.rate = (active().length * state.samplesPerFrame) / Math.max(dt / 1000, 1e-6);
      // aim at about 12 ms of sampling per frame
      state.samplesPerFrame = Math.max(1000, Math.min(2_000_000, Math.round(state.samplesPerFrame * (12 / Math.max(dt, 0.5)))));
      updateEstimates();
    } catch (e) {
      showError(e);
    }
  }
  requestAnimationFrame(frame);
}

// ---- wiring ----
function onPhaseControls() {
  $('g-out').textContent = Number($('g').value).toFixed(2);
  $('diameter-out').textContent = Number($('diameter').value).toFixed(1);
  $('spec').value = specFromControls();
  state.spec = $('spec').value;
  rebuild();
}

async function main() {
  // The cloud menu: one entry per technique (the first selected), then "none".
  const none = $('cloud').options[0];
  for (const { name, label } of TECHNIQUES) $('cloud').insertBefore(new Option(label, name), none);
  $('cloud').value = TECHNIQUES[0].name;
  await init();
  $('version').textContent = version();
  for (const id of ['theta', 'xi', 'cloud']) $(id).addEventListener('input', drawView);
  for (const id of ['family', 'g', 'diameter']) $(id).addEventListener('input', onPhaseControls);
  $('spec').addEventListener('change', () => { state.spec = $('spec').value.trim(); rebuild(); });
  for (const id of ['sigma-s', 'sigma-a', 'theta-max', 'lobe']) $(id).addEventListener('change', rebuild);
  // Moving the tilt turns the lobe at x0 on.
  $('tilt').addEventListener('input', () => { $('lobe').checked = true; rebuild(); });
  $('pause').addEventListener('click', () => {
    state.running = !state.running;
    $('pause').textContent = state.running ? 'pause' : 'run';
  });
  $('reset').addEventListener('click', () => { state.demo?.reset(); state.history = emptyHistory(); updateEstimates(); });
  $('g-out').textContent = Number($('g').value).toFixed(2);
  $('diameter-out').textContent = Number($('diameter').value).toFixed(1);
  rebuild();
  // for the end-to-end test: the state, the world <-> pixel map and a throughput probe
  window.omnee = { state, toPx, measure, rebuild, techniques: TECHNIQUES.map((t) => t.name), ready: true };
  requestAnimationFrame(frame);
}

main().catch((e) => showError(e));
