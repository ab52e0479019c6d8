// End-to-end test of the omnee-wasm demo page: serves omnee-wasm/web on 127.0.0.1,
// drives /usr/bin/chromium with playwright-core, moves the θ slider, drags x2, reads the
// numbers the page shows and checks them, checks the optimised module against the native
// fixture, measures the sampling throughput, tilts the light at x0 with the tilt slider and
// checks the estimates against the precomputed 3-D reference, and saves a screenshot to
// e2e/out/demo.png.
// OMNEE_WEB_DIR serves another copy of the page instead (dist/check.sh: the static
// folder that dist/build.sh makes).
// Exits non-zero on the first failed check.
import { spawn } from 'node:child_process';
import { mkdirSync, readFileSync } from 'node:fs';
import { createServer } from 'node:net';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
const web = process.env.OMNEE_WEB_DIR ? resolve(process.env.OMNEE_WEB_DIR) : join(here, '..', 'web');
const out = join(here, 'out');
const MIN_RATE = 1e6; // samples per second the demo must reach

// The fixed cases of the native and browser tests (tests/common/mod.rs) and their native
// results (tests/common/fixture.rs), read from the Rust sources: the optimised module
// (after wasm-opt) must reproduce them as the unoptimised test build does.
const common = join(here, '..', 'tests', 'common');
const rustValue = (src, name) => {
  const m = src.match(new RegExp(`pub const ${name}: [^=]+= &?([^;]+);`));
  if (!m) throw new Error(`no constant ${name} in tests/common`);
  // Rust tuples become arrays; PI and digit separators become JavaScript.
  const js = m[1].replaceAll('(', '[').replaceAll(')', ']').replaceAll('PI', 'Math.PI').replace(/(\d)_(\d)/g, '$1$2');
  return Function(`return ${js};`)();
};
const cases = readFileSync(join(common, 'mod.rs'), 'utf8');
const fixture = readFileSync(join(common, 'fixture.rs'), 'utf8');
const CASE_NAMES = ['A_SPEC', 'A_X0', 'A_X2', 'A_MEDIUM', 'B_SPEC', 'B_X0', 'B_X2', 'B_MEDIUM',
  'C_SPEC', 'C_X0', 'C_X2', 'C_MEDIUM', 'C_TILT', 'SEED', 'RUN', 'CLOUD', 'HIST', 'WATER'];
const FIXTURE_NAMES = ['A_REFERENCE', 'A_ESTIMATES', 'B_REFERENCE', 'B_ESTIMATES', 'C_ESTIMATES', 'C_PROBABILITY', 'CLOUD_OMNEE',
  'CLOUD_EQUIANGULAR', 'CLOUD_MIS', 'HISTOGRAM', 'WATERLEVEL', 'QUANTILE'];

let passed = 0;
const check = (ok, what) => {
  if (!ok) throw new Error(`check failed: ${what}`);
  passed += 1;
  console.log(`  ok: ${what}`);
};

const freePort = () => new Promise((resolve, reject) => {
  const s = createServer();
  s.once('error', reject);
  s.listen(0, '127.0.0.1', () => { const { port } = s.address(); s.close(() => resolve(port)); });
});

async function waitForServer(url) {
  for (let i = 0; i < 100; i++) {
    try { if ((await fetch(url)).ok) return; } catch { /* not up yet */ }
    await new Promise((r) => setTimeout(r, 100));
  }
  throw new Error(`server at ${url} did not come up`);
}

const port = await freePort();
const server = spawn('python3', ['-m', 'http.server', '--bind', '127.0.0.1', '--directory', web, String(port)], { stdio: 'ignore' });
const url = `http://127.0.0.1:${port}/`;
let browser;
try {
  await waitForServer(url);
  browser = await chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const page = await browser.newPage({ viewport: { width: 1380, height: 1250 } });
  const problems = [];
  page.on('console', (m) => { if (m.type() === 'error') problems.push(m.text()); });
  page.on('pageerror', (e) => problems.push(String(e)));
  await page.goto(url);
  await page.waitForFunction(() => window.omnee?.ready === true, null, { timeout: 20000 });
  const num = async (id) => Number(await page.locator(`#${id}`).textContent());

  // The optimised module against the native fixture, to 1e-6 relative (tests/common/mod.rs).
  const c = Object.fromEntries(CASE_NAMES.map((n) => [n, rustValue(cases, n)]));
  const got = await page.evaluate(async (c) => {
    const m = await import('./pkg/omnee_wasm.js');
    const demo = (spec, x0, x2, k, tilt) => new m.Demo(spec, x0[0], x0[1], x2[0], x2[1], k[0], k[1], k[2], c.SEED, tilt);
    // The fixture's order of techniques (demo::TECHNIQUES in the Rust sources; without a lobe
    // at x0 the first three).
    const names = ['omnee', 'equiangular', 'mis'];
    const estimates = (d, ts) => ts.flatMap((t) => { const e = d.estimate(t); return [e.count, e.mean, e.stdError]; });
    const a = demo(c.A_SPEC, c.A_X0, c.A_X2, c.A_MEDIUM);
    const b = demo(c.B_SPEC, c.B_X0, c.B_X2, c.B_MEDIUM);
    const tilted = demo(c.C_SPEC, c.C_X0, c.C_X2, c.C_MEDIUM, c.C_TILT);
    a.run(c.RUN);
    b.run(c.RUN);
    tilted.run(c.RUN);
    const [spec, n, bins, hi] = c.HIST;
    const [x0, x2, theta, xi] = c.WATER;
    const w = m.waterlevel(x0[0], x0[1], x2[0], x2[1], theta, xi);
    const values = [[a.reference], estimates(a, names), [b.reference], estimates(b, names),
      estimates(tilted, [...names, 'lobe', 'lobe-mis']), [tilted.lobeProbability],
      ...names.map((t) => Array.from(a.cloud(t, c.CLOUD, 9))),
      Array.from(m.histogram(spec, n, bins, hi, 11)),
      ['x1x', 'x1y', 'theta', 'alpha', 'beta', 'xi', 't', 's', 'd1', 'd2', 'radius', 'cx', 'cy'].map((k) => w[k]),
      [m.quantile(c.B_SPEC, 0.9)]];
    a.free();
    b.free();
    tilted.free();
    return values;
  }, c);
  const wanted = FIXTURE_NAMES.map((name) => rustValue(fixture, name));
  const differ = [];
  FIXTURE_NAMES.forEach((name, i) => {
    if (got[i].length !== wanted[i].length) differ.push(`${name.toLowerCase()}: ${got[i].length} values, fixture ${wanted[i].length}`);
    got[i].forEach((g, k) => {
      const w = wanted[i][k];
      if (!(g === w || Math.abs(g - w) <= 1e-6 * Math.max(Math.abs(g), Math.abs(w)))) differ.push(`${name.toLowerCase()}[${k}]: ${g} vs ${w}`);
    });
  });
  const count = wanted.reduce((n, v) => n + v.length, 0);
  check(differ.length === 0, `the optimised module reproduces the ${count} native fixture values to 1e-6${differ.length ? `: ${differ.slice(0, 5).join('; ')}` : ''}`);

  // Techniques by name: the page's rows are the module's names, and any other name is refused
  // with an Error that lists them.
  const names = await page.evaluate(async () => {
    const m = await import('./pkg/omnee_wasm.js');
    const d = new m.Demo('iso', 0, 0, 1, 0, 0.1, 0.1, Math.PI, 1, 0.3);
    const refused = (name) => { try { d.estimate(name); return ''; } catch (e) { return e.message; } };
    const result = { page: window.omnee.techniques, accepted: window.omnee.techniques.map(refused),
      distance: refused('distance'), index: refused(0) };
    d.free();
    return result;
  });
  check(names.page.join() === 'omnee,equiangular,mis,lobe,lobe-mis' && names.accepted.every((e) => e === ''),
    `the page's techniques ${names.page.join(', ')} are the module's`);
  const allowed = 'syntax error in technique: unknown name; allowed: omnee, equiangular, mis, lobe, lobe-mis';
  check(names.distance === allowed && names.index === allowed, `other names are refused: "${names.distance}"`);
  const cloudMenu = await page.evaluate(() => [...document.querySelectorAll('#cloud option')].map((o) => o.value).join());
  check(cloudMenu === 'omnee,equiangular,mis,lobe,lobe-mis,', `the cloud menu lists the techniques and none (${cloudMenu})`);
  const shownRows = async () => page.evaluate(() => [...document.querySelectorAll('tr[data-technique]')]
    .filter((r) => !r.hidden).map((r) => r.dataset.technique).join());
  check(await shownRows() === 'omnee,equiangular,mis', 'without a lobe at x0 the lobe rows are hidden');

  // The waterlevel: t is the talk's formula of θ and ξ.
  const talk = (theta, xi) => Math.cos(theta - xi * theta) * Math.sin(xi * theta) / Math.sin(theta);
  const tBefore = await num('t-val');
  check(Math.abs(tBefore - talk(0.9, 0.35)) < 1e-5, `t = ${tBefore} matches sin β cos(θ−β)/sin θ at θ = 0.9, ξ = 0.35`);
  await page.locator('#theta').fill('1.3');
  await page.locator('#xi').fill('0.6');
  const [theta, xi, t] = [await num('theta-val'), await num('xi-val'), await num('t-val')];
  check(Math.abs(theta - 1.3) < 1e-9 && Math.abs(xi - 0.6) < 1e-9, `the sliders moved θ to ${theta} and ξ to ${xi}`);
  check(Math.abs(t - talk(1.3, 0.6)) < 1e-5, `t = ${t} matches the talk's formula after moving the slider`);
  const [alpha, beta] = [await num('alpha'), await num('beta')];
  check(Math.abs(alpha + beta - theta) < 1e-5 && Math.abs(beta - xi * theta) < 1e-5, `α + β = θ and β = ξθ (α = ${alpha}, β = ${beta})`);

  // Drag x2 from (0.5, 0) to (0.8, 0.3) in world units.
  const box = await page.locator('#view').boundingBox();
  const [fx, fy] = await page.evaluate(() => window.omnee.toPx(window.omnee.state.x2));
  const [tx, ty] = await page.evaluate(() => window.omnee.toPx([0.8, 0.3]));
  await page.mouse.move(box.x + fx, box.y + fy);
  await page.mouse.down();
  for (let i = 1; i <= 10; i++) await page.mouse.move(box.x + fx + ((tx - fx) * i) / 10, box.y + fy + ((ty - fy) * i) / 10);
  await page.mouse.up();
  const x2 = await page.evaluate(() => window.omnee.state.x2);
  check(Math.hypot(x2[0] - 0.8, x2[1] - 0.3) < 0.01, `x2 dragged to (${x2[0].toFixed(3)}, ${x2[1].toFixed(3)})`);
  const s = await num('s-val');
  check(Math.abs(s - Math.hypot(x2[0] + 0.5, x2[1])) < 1e-4, `the page's s = ${s} is |x2 − x0| after the drag`);
  check(Math.abs((await num('t-val')) - talk(1.3, 0.6)) < 1e-5, 't does not depend on where x0 and x2 are');

  // Bad input: a thrown error shown on the page, and the page keeps working.
  await page.locator('#spec').fill('hg:1.5');
  await page.locator('#spec').press('Enter');
  const err = await page.locator('#error').textContent();
  check(err.includes('g = 1.5') && err.includes('(-1, 1)'), `g out of range is reported: "${err}"`);
  await page.locator('#spec').fill('hg:nan');
  await page.locator('#spec').press('Enter');
  const nan = await page.locator('#error').textContent();
  check(nan.startsWith('g = NaN is out of range'), `a NaN in a spec is named: "${nan}"`);
  await page.locator('#spec').fill('hg:0.9');
  await page.locator('#spec').press('Enter');
  check((await page.locator('#error').textContent()) === '', 'a valid spec clears the error');

  // Extreme numbers from JavaScript: an Error naming the field, or finite numbers; never a trap.
  // Counts and seeds arrive as JavaScript numbers: anything but an integer in
  // range is refused with the field and the range, the number as given (not
  // taken modulo 2^32: 2^32 + 5 does not run 5 samples).
  const COUNTS = [2 ** 32 + 5, -1, NaN, 1.5, 1e30, Infinity, 2 ** 24 + 1];
  const extreme = await page.evaluate(async (COUNTS) => {
    const m = await import('./pkg/omnee_wasm.js');
    const thrown = (f) => { try { f(); return 'no error'; } catch (e) { return e instanceof Error ? e.message : 'not an Error'; } };
    const d = new m.Demo('hg:0.5', 0, 0, 1e-30, 0, 0.5e30, 0.05e30, Math.PI, 1);
    d.run(1000);
    const e = d.estimate('mis');
    const out = {
      tiny: [e.mean, e.stdError, e.relativeError],
      counts: COUNTS.map((n) => thrown(() => d.run(n))),
      ran: d.estimate('omnee').count,
      cloud: [2 ** 32 + 5, 1.5, 1e30].map((n) => thrown(() => d.cloud('omnee', n, 1))),
      histogram: [-1, 2 ** 32 + 5].map((n) => thrown(() => m.histogram('iso', n, 8, 1, 1))),
      bins: [0.5, NaN].map((n) => thrown(() => m.histogram('iso', 10, n, 1, 1))),
      segments: [2 ** 32 + 8, -8].map((n) => thrown(() => m.arc(0, 0, 1, 0, 1, n))),
      seeds: [2 ** 32, -1, 0.5, NaN].map((s) => [thrown(() => new m.Demo('iso', 0, 0, 1, 0, 0.1, 0.1, Math.PI, s)),
        thrown(() => d.cloud('omnee', 10, s)), thrown(() => m.histogram('iso', 10, 8, 1, s))]),
      seedMax: thrown(() => d.cloud('omnee', 10, 2 ** 32 - 1)),
      nan: [NaN, Infinity, -Infinity].map((x) => thrown(() => new m.Demo('iso', 0, 0, x, 0, 0.1, 0.1, Math.PI, 1))),
      sigma: thrown(() => new m.Demo('iso', 0, 0, 1, 0, NaN, 0.1, Math.PI, 1)),
      huge: thrown(() => new m.Demo('iso', 0, 0, 1e-300, 0, 5e299, 5e298, Math.PI, 1)),
      apart: thrown(() => new m.Demo('iso', -1e308, 0, 1e308, 0, 0.1, 0.1, Math.PI, 1)),
    };
    d.free();
    return out;
  }, COUNTS);
  check(extreme.tiny.every(Number.isFinite) && extreme.tiny[2] < 0.1,
    `s = 1e-30, σ × 1e30: MIS ${extreme.tiny[0].toExponential(4)} ± ${extreme.tiny[1].toExponential(2)}`);
  const refused = (m, field, x, range) => m === `${field} = ${x} is out of range; allowed: an integer in ${range}`;
  check(extreme.counts.every((m, i) => refused(m, 'n', COUNTS[i], '[1, 16777216]')),
    `counts above 2^32, negative, NaN, fractional, huge, infinite and above 2^24 are refused as given: ${extreme.counts.join(' | ')}`);
  check(extreme.ran === 1000, `no refused count ran a sample (${extreme.ran} after run(1000))`);
  check(extreme.cloud.every((m, i) => refused(m, 'n', [2 ** 32 + 5, 1.5, 1e30][i], '[1, 1048576]'))
    && extreme.histogram.every((m, i) => refused(m, 'n', [-1, 2 ** 32 + 5][i], '[1, 16777216]')),
    `cloud and histogram counts: ${extreme.cloud.join(' | ')} | ${extreme.histogram.join(' | ')}`);
  check(extreme.bins.every((m, i) => refused(m, 'bins', [0.5, NaN][i], '[1, 4096]'))
    && extreme.segments.every((m, i) => refused(m, 'segments', [2 ** 32 + 8, -8][i], '[1, 4096]')),
    `bins and segments: ${extreme.bins.join(' | ')} | ${extreme.segments.join(' | ')}`);
  check(extreme.seeds.every((ms, i) => ms.every((m) => refused(m, 'seed', [2 ** 32, -1, 0.5, NaN][i], '[0, 4294967295]')))
    && extreme.seedMax === 'no error',
    `seeds of Demo, cloud and histogram outside the integers of [0, 2^32 - 1] are refused: ${extreme.seeds.map((m) => m[0]).join(' | ')}`);
  check(extreme.nan.every((m) => m.startsWith('x2')) && extreme.sigma.startsWith('sigma_s'),
    `NaN and ∞ are named: ${extreme.nan.join(' | ')} | ${extreme.sigma}`);
  check(extreme.huge.startsWith('reference: ') && !extreme.huge.includes('NaN'), `a transfer of 1e600 is an Error: ${extreme.huge}`);
  check(extreme.apart.startsWith('x2 - x0'), `points 2e308 apart are named: ${extreme.apart}`);

  // Live convergence against the quadrature reference (θmax = π, σs = 0.2, σa = 0.05).
  await page.waitForFunction(() => window.omnee.state.demo.estimate('omnee').count >= 2e6, null, { timeout: 60000 });
  const est = await page.evaluate(() => {
    const d = window.omnee.state.demo;
    // Without a lobe at x0: the first three techniques.
    const e = Object.fromEntries(['omnee', 'equiangular', 'mis'].map((t) => {
      const e = d.estimate(t);
      return [t, { n: e.count, mean: e.mean, se: e.stdError, rel: e.relativeError }];
    }));
    return { reference: d.reference, e };
  });
  const shown = await num('reference');
  check(Math.abs(shown - est.reference) <= 1e-6 * est.reference, `the page shows the reference ${shown}`);
  for (const [t, name] of [['omnee', 'OMNEE'], ['mis', 'MIS']]) {
    const { n, mean, se, rel } = est.e[t];
    // OMNEE and MIS estimates are bounded here; 5 standard errors fail with probability < 1e-6.
    check(Math.abs(mean - est.reference) < 5 * se && rel < 0.01,
      `${name}: ${mean.toPrecision(6)} ± ${se.toExponential(2)} after ${n} samples vs reference ${est.reference.toPrecision(7)} (rel. error ${rel.toExponential(2)})`);
  }
  const [omnee, equiangular] = [est.e.omnee, est.e.equiangular];
  check(Number.isFinite(equiangular.mean) && equiangular.n === omnee.n, `equiangular ran as many samples (${equiangular.n}), estimate ${equiangular.mean.toPrecision(4)}`);
  check(omnee.se < equiangular.se, `OMNEE's standard error ${omnee.se.toExponential(2)} < equiangular's ${equiangular.se.toExponential(2)} for HG g = 0.9`);

  // Throughput: one wasm call of 3·10^5 samples (10^5 per technique), best of 20 calls:
  // the 2 cores are shared with builds, and the best call is the one that had a core.
  await page.locator('#pause').click();
  const rates = [];
  for (let i = 0; i < 20; i++) rates.push(await page.evaluate(() => window.omnee.measure(100_000)));
  const rate = Math.max(...rates);
  check(rate >= MIN_RATE, `throughput ${Math.round(rate).toLocaleString('en-US')} samples/s ≥ ${MIN_RATE.toLocaleString('en-US')}`);
  await page.locator('#pause').click();

  // The lobe at x0: the tilt slider turns it on and tilts the incoming direction. Away from the
  // table's problem (x2 was dragged) there is no reference; back at the default problem the
  // precomputed 3-D quadrature is shown and the estimates agree with it.
  const table = await page.evaluate(async () => (await import('./lobe-references.js')).LOBE_REFERENCES);
  await page.locator('#tilt').fill('0.5');
  check(await page.locator('#lobe').isChecked(), 'moving the tilt slider turns the lobe at x0 on');
  check(await shownRows() === 'omnee,equiangular,mis,lobe,lobe-mis', 'with a lobe at x0 all five techniques run');
  check((await page.locator('#reference').textContent()) === '–', 'no reference away from the precomputed problem');
  await page.evaluate(() => { window.omnee.state.x2 = [0.5, 0.0]; window.omnee.rebuild(); });
  const lobeState = await page.evaluate(() => ({ tilt: window.omnee.state.tilt, reference: window.omnee.state.reference,
    c: window.omnee.state.demo.lobeProbability }));
  const [hg09, hg098] = [table.references['hg:0.9'], table.references['hg:0.98']];
  check(lobeState.tilt === 0.5 && lobeState.reference === hg09[5],
    `at tilt ${lobeState.tilt} the reference is the table's ${hg09[5]} (got ${lobeState.reference})`);
  check(Math.abs((await num('reference')) - lobeState.reference) <= 1e-6 * lobeState.reference, 'the page shows it');
  check(lobeState.c > 0.45 && lobeState.c <= 0.5, `the recommended combination draws the lobe technique with c = ${lobeState.c}`);
  await page.waitForFunction(() => window.omnee.state.demo.estimate('lobe-mis').count >= 1e6, null, { timeout: 120000 });
  const tiltedEst = await page.evaluate(() => Object.fromEntries(window.omnee.techniques.map((t) => {
    const e = window.omnee.state.demo.estimate(t);
    return [t, { n: e.count, mean: e.mean, se: e.stdError }];
  })));
  for (const t of ['omnee', 'mis', 'lobe-mis']) {
    const { n, mean, se } = tiltedEst[t];
    const rel = Math.abs(mean - lobeState.reference) / lobeState.reference;
    check(Math.abs(mean - lobeState.reference) < 5 * se && rel < 0.02,
      `tilt 0.5, ${t}: ${mean.toPrecision(6)} ± ${se.toExponential(2)} after ${n} samples vs ${lobeState.reference.toPrecision(7)}`);
  }
  const [o, lm] = [tiltedEst.omnee, tiltedEst['lobe-mis']];
  check(2 * lm.se < o.se, `tilt 0.5: the combination's standard error ${lm.se.toExponential(2)} is below half OMNEE's ${o.se.toExponential(2)}`);
  await page.locator('#tilt').fill('1');
  const at1 = await page.evaluate(() => [window.omnee.state.tilt, window.omnee.state.reference, window.omnee.state.demo.estimate('omnee').count]);
  check(at1[0] === 1 && at1[1] === hg09[10] && at1[2] < 1e6, `tilt 1: the table's reference ${hg09[10]}, estimates restarted`);
  // The water lobe of docs/math.md §12.4, g = 0.98 (the g slider), at tilt 0.5: OMNEE alone is far noisier.
  await page.locator('#g').fill('0.98');
  await page.locator('#tilt').fill('0.5');
  const ref98 = await page.evaluate(() => window.omnee.state.reference);
  check(ref98 === hg098[5], `g = 0.98, tilt 0.5: the table's reference ${hg098[5]} (got ${ref98})`);
  await page.waitForFunction(() => window.omnee.state.demo.estimate('lobe-mis').count >= 5e5, null, { timeout: 120000 });
  const e98 = await page.evaluate(() => ['omnee', 'lobe-mis'].map((t) => window.omnee.state.demo.estimate(t)));
  check(Math.abs(e98[1].mean - ref98) < 5 * e98[1].stdError,
    `g = 0.98, tilt 0.5, lobe-mis: ${e98[1].mean.toPrecision(6)} ± ${e98[1].stdError.toExponential(2)} after ${e98[1].count} samples vs ${ref98.toPrecision(7)}`);
  check(10 * e98[1].stdError < e98[0].stdError,
    `g = 0.98, tilt 0.5: the combination's standard error ${e98[1].stdError.toExponential(2)} is below a tenth of OMNEE's ${e98[0].stdError.toExponential(2)}`);
  await page.locator('#g').fill('0.9');
  await page.locator('#lobe').uncheck();
  check(await shownRows() === 'omnee,equiangular,mis' && Number.isFinite(await num('reference')), 'unticking the lobe restores the plain problem');

  check(problems.length === 0, `no console errors${problems.length ? `: ${problems.join(' | ')}` : ''}`);
  mkdirSync(out, { recursive: true });
  await page.waitForTimeout(300);
  await page.screenshot({ path: join(out, 'demo.png'), fullPage: true });
  console.log(`e2e: screenshot ${join(out, 'demo.png')}`);
  console.log(`e2e: samples/s ${Math.round(rate)}`);
  console.log(`e2e: ${passed} passed, 0 failed`);
} catch (e) {
  console.error(String(e?.stack ?? e));
  console.log(`e2e: ${passed} passed, 1 failed`);
  process.exitCode = 1;
} finally {
  if (browser) await browser.close();
  server.kill();
}
