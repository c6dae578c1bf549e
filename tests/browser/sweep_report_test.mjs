#!/usr/bin/env node
// Browser test of the report of a sweep directory (`sdv sweep --report`, `sdv view SWEEP_DIR`).
//
//   node sweep_report_test.mjs SWEEP_DIR/report.html screenshot.png
//   node sweep_report_test.mjs --generate KIND N DIR    (writes a synthetic sweep directory)
//
// The report must sit in its sweep directory (its links to runs/<i>/view.html are relative):
// the test reads DIR/results.csv and DIR/summary.json itself and checks the page against them.
// It opens the report in headless Chromium (/usr/bin/chromium, or $CHROMIUM) through
// playwright-core and drives the real UI: the header counts, the outcome selector (every
// outcome of a small sweep: the values of the heat-map cells or of the marks against
// results.csv, including cells shared by several variants as mean and worst), the axes, hover,
// clicking a variant without a kept run (its table row), the links to kept runs (the target
// exists and opens), the sortable table; it prints the time the page takes for large sweeps
// (bench/sweep_report_load.sh holds them to a budget). Prints one line per check and takes a
// full-page screenshot. Exit status 0 = all checks passed.
//
// --generate kinds (deterministic): grid2 (two parameters with grid levels; from 400 variants on,
// four variants share each cell), random2 (two continuous parameters), latin3 (three continuous
// parameters), line1 (one parameter with N levels). Two failed variants get a kept view.html.
import { chromium } from 'playwright-core';
import { pathToFileURL, fileURLToPath } from 'node:url';
import path from 'node:path';
import fs from 'node:fs';

const here = path.dirname(fileURLToPath(import.meta.url));

// ---- results.csv (RFC 4180) --------------------------------------------------------------
function parseCsv(text) {
  const rows = [];
  let row = [], field = '', i = 0, quoted = false;
  while (i < text.length) {
    const c = text[i];
    if (quoted) {
      if (c === '"' && text[i + 1] === '"') { field += '"'; i += 2; continue; }
      if (c === '"') { quoted = false; i++; continue; }
      field += c; i++; continue;
    }
    if (c === '"') { quoted = true; i++; continue; }
    if (c === ',') { row.push(field); field = ''; i++; continue; }
    if (c === '\n' || c === '\r') {
      if (c === '\r' && text[i + 1] === '\n') i++;
      row.push(field); field = ''; rows.push(row); row = []; i++; continue;
    }
    field += c; i++;
  }
  if (field !== '' || row.length) { row.push(field); rows.push(row); }
  return rows.filter((r) => !(r.length === 1 && r[0] === ''));
}

// ---- the generator of synthetic sweep directories -------------------------------------------
const g6 = (v) => (v === null ? '' : String(+v.toPrecision(6)));
function generate(kind, n, dir) {
  let seed = 12345;
  const rnd = () => { seed = (seed * 1103515245 + 12345) % 2147483648; return seed / 2147483648; };
  const params = [];
  let points = []; // one array of parameter values per variant
  let sample = { method: 'grid', count: 0, seed: 1 };
  if (kind === 'grid2') {
    const reps = n >= 400 ? 4 : 1, side = Math.max(2, Math.floor(Math.sqrt(n / reps)));
    const la = Array.from({ length: side }, (_, k) => 2 + k * 0.16), lb = Array.from({ length: side }, (_, k) => -5 + k * 0.08);
    params.push({ name: 'v2.tree.accept_gap', unit: 'm', domain: `2 m .. ${g6(la[side - 1])} m count ${side}`, values: la });
    params.push({ name: 'v2.tree.dv', unit: 'm/s', domain: `-5 m/s .. ${g6(lb[side - 1])} m/s count ${side}`, values: lb });
    for (const a of la) for (const b of lb) for (let r = 0; r < reps; r++) points.push([a, b]);
  } else if (kind === 'line1') {
    const la = Array.from({ length: n }, (_, k) => 2 + k * 8 / Math.max(1, n - 1));
    params.push({ name: 'v2.tree.accept_gap', unit: 'm', domain: `2 m .. 10 m count ${n}`, values: la });
    points = la.map((a) => [a]);
  } else if (kind === 'random2' || kind === 'latin3') {
    const dims = kind === 'random2' ? 2 : 3;
    sample = { method: kind === 'random2' ? 'random' : 'latin', count: n, seed: 7 };
    const all = [['v2.tree.accept_gap', 'm', 2, 10], ['v2.tree.dv', 'm/s', -5, -1], ['ego.speed', 'm/s', 11, 17]].slice(0, dims);
    for (const [name, unit, lo, hi] of all) params.push({ name, unit, domain: `${lo} ${unit} .. ${hi} ${unit}`, values: null });
    // Latin hypercube: each dimension a shuffled stratification
    const strata = all.map(() => { const p = Array.from({ length: n }, (_, k) => k); for (let k = n - 1; k > 0; k--) { const j = Math.floor(rnd() * (k + 1)); [p[k], p[j]] = [p[j], p[k]]; } return p; });
    for (let i = 0; i < n; i++) points.push(all.map(([, , lo, hi], d) => lo + (hi - lo) * (sample.method === 'latin' ? (strata[d][i] + rnd()) / n : rnd())));
  } else throw new Error(`unknown kind '${kind}' (grid2, random2, latin3, line1)`);
  for (const p of params) p.column = p.name + (p.unit ? `[${p.unit}]` : '');
  const expectations = [
    { id: 'e1', text: 'not collision(ego, v2)', column: 'e1', unit: null, line: 30 },
    { id: 'e2', text: 'min_ttc(ego, v2) > 1.5 s', column: 'e2[s]', unit: 's', line: 31 },
  ];
  const header = ['variant', ...params.map((p) => p.column), 'passed', 'error', 'collisions', 'min_ttc[s]', 'min_gap[m]', 'min_clearance[m]',
    'fallback_share', 'duration[s]', 'e1', 'e1_passed', 'e2[s]', 'e2_passed'];
  const lines = [header.join(',')];
  const count = { passed: 0, failed: 0, errors: 0, coll: 0, e1: 0, e2: 0 }, failed = [];
  points.forEach((pt, i) => {
    const vals = pt.map((v) => +v.toPrecision(6));
    if (i % 97 === 13) {
      lines.push([i, ...vals.map(g6), 0, `"runtime error in variant ${i}: ""v2"" left the road, at t=${(i % 20) + 0.5} s"`, ...new Array(header.length - 3 - vals.length).fill('')].join(','));
      count.errors++;
      return;
    }
    const a = pt[0], b = pt.length > 1 ? pt[1] : -3, c = pt.length > 2 ? pt[2] : 14;
    const risk = (10 - a) / 8 + (-b - 1) / 4 + (c - 14) / 6 + 0.15 * (rnd() - 0.5);
    const coll = risk > 1.45 ? 1 + (risk > 1.7 ? 1 : 0) : 0;
    const ttc = risk < 0.3 ? null : Math.max(0.1, 4.5 - 2.5 * risk);
    const gap = coll ? 0 : Math.max(0.2, 12 - 7 * risk), clr = coll ? 0 : gap * 0.4, fb = Math.max(0, Math.min(1, (risk - 0.9) * 0.25));
    const e1 = coll === 0, e2 = ttc === null || ttc > 1.5, ok = e1 && e2;
    lines.push([i, ...vals.map(g6), ok ? 1 : 0, '', coll, g6(ttc), g6(gap), g6(clr), g6(fb), g6(20 + (i % 3) * 5), '', e1 ? 1 : 0, g6(ttc), e2 ? 1 : 0].join(','));
    if (ok) count.passed++; else { count.failed++; failed.push(i); }
    count.coll += coll > 0; count.e1 += !e1; count.e2 += !e2;
  });
  fs.mkdirSync(dir, { recursive: true });
  fs.writeFileSync(path.join(dir, 'results.csv'), lines.join('\n') + '\n');
  const summary = {
    format: 'sdv-sweep/1', file: `generated/${kind}.sdv`, scenario: `generated_${kind}_${points.length}`, ir_hash: '0123456789abcdef', sample,
    parameters: params, expectations, variants: points.length, passed: count.passed, failed: count.failed, errors: count.errors,
    with_collision: count.coll, expectation_failures: { e1: count.e1, e2: count.e2 }, kept: 'failed',
  };
  fs.writeFileSync(path.join(dir, 'summary.json'), JSON.stringify(summary, null, 2) + '\n');
  const view = path.join(here, 'data', 'sweep_grid', 'runs', '4', 'view.html');
  for (const i of [failed[0], failed[failed.length - 1]].filter((v) => v !== undefined)) {
    fs.mkdirSync(path.join(dir, 'runs', String(i)), { recursive: true });
    fs.copyFileSync(view, path.join(dir, 'runs', String(i), 'view.html'));
  }
  console.log(`generated ${kind}: ${points.length} variants in ${dir} (${count.passed} passed, ${count.failed} failed, ${count.errors} errors)`);
}

if (process.argv[2] === '--generate') {
  const [kind, n, dir] = process.argv.slice(3);
  if (!kind || !n || !dir) { console.error('usage: node sweep_report_test.mjs --generate KIND N DIR'); process.exit(1); }
  generate(kind, Number(n), dir);
  process.exit(0);
}

// ---- the browser test ---------------------------------------------------------------------------
const [file, shot] = process.argv.slice(2);
if (!file || !shot) {
  console.error('usage: node sweep_report_test.mjs SWEEP_DIR/report.html screenshot.png');
  process.exit(1);
}
if (!fs.existsSync(file)) {
  console.error(`FAIL  report not found: ${file}`);
  process.exit(1);
}
const sweepDir = path.dirname(path.resolve(file));
for (const f of ['results.csv', 'summary.json']) {
  if (!fs.existsSync(path.join(sweepDir, f))) {
    console.error(`FAIL  ${f} not found next to the report (${sweepDir}): write the report into the sweep directory`);
    process.exit(1);
  }
}

class CheckFailed extends Error {}
const errors = [];
let checks = 0;
const pass = (msg) => { checks++; console.log(`PASS  ${msg}`); };
const fail = (msg) => { throw new CheckFailed(msg); };
const noErrors = (where) => { if (errors.length) fail(`console/page errors (${where}):\n      ${errors.join('\n      ')}`); };
const close = (a, b, rel = 1e-9) => Math.abs(a - b) <= rel * Math.max(1, Math.abs(a), Math.abs(b));
const sameSet = (a, b) => a.length === b.length && [...a].sort().join('|') === [...b].sort().join('|');

// The sweep as the test reads it, independently of the page.
const summary = JSON.parse(fs.readFileSync(path.join(sweepDir, 'summary.json'), 'utf8'));
const csv = parseCsv(fs.readFileSync(path.join(sweepDir, 'results.csv'), 'utf8'));
const header = csv[0], body = csv.slice(1);
const col = (name) => { const k = header.indexOf(name); if (k < 0) fail(`results.csv has no column '${name}'`); return body.map((r) => r[k]); };
const num = (s) => (s === '' ? null : Number(s));
const N = body.length;
const variants = col('variant').map(Number);
const errorsCol = col('error');
const isErr = (r) => errorsCol[r] !== '';
const params = summary.parameters;
// Outcome key → per-row value as the page should read it: a number, null (never measured) or
// undefined (run error).
function expectedValues(key) {
  const raw = key === 'collision' ? col('collisions').map((s) => (s === '' ? null : Number(s) > 0 ? 1 : 0)) : col(key).map(num);
  return raw.map((v, r) => (isErr(r) ? undefined : v));
}
const asData = (v) => (v === undefined ? 'error' : v === null ? '' : v);
const expectedOutcomes = ['passed', 'collision', 'min_ttc[s]', 'min_gap[m]', 'min_clearance[m]', 'fallback_share', 'duration[s]'];
for (const e of summary.expectations) {
  if (col(e.column).some((s) => s !== '')) expectedOutcomes.push(e.column);
  expectedOutcomes.push(e.id + '_passed');
}
// The direction in which an outcome is better (for the 'worst' of a shared cell).
function badness(key) {
  if (key === 'passed' || key.endsWith('_passed')) return (v) => (v === 0 ? 1 : 0);
  if (key === 'collision') return (v) => (v === 1 ? 1 : 0);
  if (key === 'fallback_share') return (v) => v;
  if (['min_ttc[s]', 'min_gap[m]', 'min_clearance[m]'].includes(key)) return (v) => -v;
  const e = summary.expectations.find((x) => x.column === key);
  const ops = e ? (e.text.match(/[<>]=?/g) || []) : [];
  if (ops.length === 1) return ops[0][0] === '>' ? (v) => -v : (v) => v;
  return (v) => -v; // no direction: the minimum
}
const isBool = (key) => key === 'passed' || key === 'collision' || key.endsWith('_passed');

async function run(browser) {
  const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  page.on('console', (m) => { if (m.type() === 'error') errors.push(`console.error: ${m.text()}`); });
  page.on('pageerror', (e) => errors.push(`page error: ${e.message}`));
  page.on('request', (r) => { // the report must be self-contained
    const u = r.url();
    if (!u.startsWith('file:') && !u.startsWith('data:') && !u.startsWith('blob:')) errors.push(`network request: ${u}`);
  });
  const state = () => page.evaluate(() => window.sdvSweep.state());
  const large = N > 1000;

  // ---- load and readiness ---------------------------------------------------------------
  const url = pathToFileURL(path.resolve(file)).href;
  const t0 = Date.now();
  await page.goto(url, { waitUntil: 'commit', timeout: 120000 });
  await page.waitForFunction(() => window.sdvSweep && (window.sdvSweep.ready === true || window.sdvSweep.error), null, { timeout: 120000, polling: 20 });
  const wallMs = Date.now() - t0;
  const info = await page.evaluate(() => ({ error: window.sdvSweep.error, readyAt: window.sdvSweep.readyAt, timings: window.sdvSweep.timings }));
  if (info.error) fail(`page reported an error: ${info.error}`);
  noErrors('load');
  const sizeMb = (fs.statSync(file).size / 1e6).toFixed(2);
  pass(`ready: ${N} variants, navigation→ready ${info.readyAt} ms in page (${wallMs} ms wall clock); file ${sizeMb} MB, ` +
    `JSON.parse ${info.timings.parseMs} ms, init ${info.timings.initMs} ms, render ${info.timings.renderMs} ms`);
  const s0 = await state();
  if (s0.variants !== N) fail(`page has ${s0.variants} variants, results.csv ${N}`);

  // ---- header counts: summary.json, and summary.json against results.csv ---------------------
  const badges = await page.evaluate(() => Object.fromEntries([...document.querySelectorAll('#badges .badge')].map((b) => [b.id, Number(b.dataset.n)])));
  const want = { 'cnt-variants': summary.variants, 'cnt-passed': summary.passed, 'cnt-failed': summary.failed, 'cnt-errors': summary.errors, 'cnt-collisions': summary.with_collision };
  for (const [id, n] of Object.entries(want)) if (badges[id] !== n) fail(`header badge ${id} shows ${badges[id]}, summary.json says ${n}`);
  const passedCsv = col('passed').filter((s) => s === '1').length, errCsv = errorsCol.filter((s) => s !== '').length;
  const collCsv = col('collisions').filter((s) => s !== '' && Number(s) > 0).length;
  if (summary.variants !== N || summary.passed !== passedCsv || summary.errors !== errCsv || summary.failed !== N - passedCsv - errCsv || summary.with_collision !== collCsv) {
    fail(`summary.json counts (${summary.variants}/${summary.passed}/${summary.failed}/${summary.errors}/${summary.with_collision}) ` +
      `disagree with results.csv (${N}/${passedCsv}/${N - passedCsv - errCsv}/${errCsv}/${collCsv})`);
  }
  const expShown = await page.evaluate(() => Object.fromEntries([...document.querySelectorAll('#expTable tr[data-exp]')].map((tr) => [tr.dataset.exp, { n: Number(tr.querySelector('.fails').dataset.n), text: tr.textContent }])));
  for (const e of summary.expectations) {
    const shown = expShown[e.id], n = summary.expectation_failures[e.id];
    if (!shown || shown.n !== n || !shown.text.includes(e.text)) fail(`expectation ${e.id} '${e.text}': shown ${JSON.stringify(shown)}, summary.json says ${n} failures`);
    const fromCsv = col(e.id + '_passed').filter((s, r) => s === '0' && !isErr(r)).length;
    const withErrors = col(e.id + '_passed').filter((s) => s === '0').length;
    if (n !== fromCsv && n !== withErrors) fail(`summary.json: ${e.id} fails ${n} times, results.csv ${fromCsv}`);
  }
  const meta = await page.locator('#meta').textContent();
  if (!meta.includes(summary.file) || !meta.includes(summary.ir_hash)) fail(`header meta '${meta}' lacks the file or the IR hash`);
  pass(`header: ${summary.scenario}, ${N} variants, ${summary.passed} passed, ${summary.failed} failed, ${summary.errors} errors, ` +
    `${summary.with_collision} with collision, ${summary.expectations.length} expectations with their failure counts (all agreeing with results.csv); ` +
    `sample '${await page.locator('#sampleInfo').textContent()}'`);

  // ---- outcome selector --------------------------------------------------------------------
  const options = await page.evaluate(() => [...document.querySelectorAll('#outcome option')].map((o) => o.value));
  if (!sameSet(options, expectedOutcomes) || options.length !== expectedOutcomes.length) fail(`outcome options ${JSON.stringify(options)}, expected ${JSON.stringify(expectedOutcomes)}`);
  pass(`outcome selector: ${options.join(', ')}`);
  const choose = async (key) => {
    const before = (await state()).renders, t = Date.now();
    await page.selectOption('#outcome', key);
    await page.waitForFunction((n) => window.sdvSweep.state().renders > n, before, { timeout: 60000, polling: 10 });
    const ms = Date.now() - t;
    const st = await state();
    if (st.outcome !== key) fail(`selected outcome ${key} but the page shows ${st.outcome}`);
    return ms;
  };
  const wantView = params.length === 2 && params.every((p) => Array.isArray(p.values)) ? 'heatmap'
    : params.length === 2 ? 'scatter' : params.length === 1 ? 'line' : params.length >= 3 ? 'parallel' : 'none';
  if (s0.view !== wantView) fail(`view is ${s0.view}, expected ${wantView} for ${params.length} parameters`);
  // Small sweeps: every outcome; large ones: three (each re-renders every mark).
  const toCheck = large ? ['min_ttc[s]', 'collision', 'passed'] : options;
  const switchMs = [];

  // ---- the main view ---------------------------------------------------------------------------
  let sample = null; // the SVG whose marks are hovered and clicked
  if (wantView === 'heatmap') {
    const [px, py] = params;
    if (s0.columns !== px.values.length || s0.rows !== py.values.length) fail(`heat map ${s0.rows}×${s0.columns}, levels ${py.values.length}×${px.values.length}`);
    const levelOf = (levels, v) => { let best = -1, bd = Infinity; levels.forEach((l, k) => { const d = Math.abs(l - v); if (d < bd) { bd = d; best = k; } }); return bd <= 1e-5 * Math.max(Math.abs(v), Math.abs(levels[best])) + 1e-12 ? best : -1; };
    const xs = col(px.column).map(Number), ys = col(py.column).map(Number);
    const members = new Map();
    body.forEach((_, r) => {
      const key = `${levelOf(py.values, ys[r])},${levelOf(px.values, xs[r])}`;
      if (!members.has(key)) members.set(key, []);
      members.get(key).push(r);
    });
    const shared = [...members.values()].some((m) => m.length > 1);
    const cells = () => page.evaluate(() => [...document.querySelectorAll('#heatmap .cell')].map((g) => ({
      r: Number(g.dataset.r), c: Number(g.dataset.c), x: Number(g.dataset.x), y: Number(g.dataset.y), vs: g.dataset.vs, value: g.dataset.value,
      text: (g.querySelector('text') || {}).textContent ?? null, fill: g.querySelector('rect').getAttribute('fill'),
      href: g.parentElement.tagName.toLowerCase() === 'a' ? g.parentElement.getAttribute('href') : null,
    })));
    let cs = await cells();
    if (cs.length !== px.values.length * py.values.length) fail(`${cs.length} heat-map cells, expected ${py.values.length} rows × ${px.values.length} columns`);
    const xset = new Set(cs.map((c) => c.x)), yset = new Set(cs.map((c) => c.y));
    if (xset.size !== px.values.length || !px.values.every((v) => xset.has(v)) || yset.size !== py.values.length || !py.values.every((v) => yset.has(v))) {
      fail('heat-map cell levels differ from the levels of summary.json');
    }
    if (new Set(cs.map((c) => `${c.r},${c.c}`)).size !== cs.length) fail('two heat-map cells at the same row and column');
    for (const c of cs) {
      if (px.values[c.c] !== c.x || py.values[c.r] !== c.y) fail(`cell (${c.r}, ${c.c}) has levels (${c.y}, ${c.x})`);
      const m = members.get(`${c.r},${c.c}`) || [];
      if (!sameSet((c.vs ? c.vs.split(',') : []), m.map((r) => String(variants[r])))) fail(`cell ${c.x}, ${c.y} holds variants ${c.vs}, results.csv says ${m.map((r) => variants[r])}`);
    }
    pass(`heat map: ${py.values.length} rows × ${px.values.length} columns = ${cs.length} cells at the levels of summary.json ` +
      `(${px.column} × ${py.column}), each holding the variants of results.csv${shared ? ' (several per cell)' : ''}`);

    // The value of every cell for an outcome and a summary (mean / worst) of its variants.
    const expectCell = (key, m, aggName) => {
      const ev = expectedValues(key), vals = m.map((r) => ev[r]).filter((v) => v !== undefined && v !== null);
      if (!m.length) return { value: 'none' };
      if (!vals.length) return { value: m.some((r) => ev[r] === null) ? '' : 'error' };
      if (vals.length === 1) return { value: vals[0] };
      const bad = badness(key);
      if (isBool(key)) {
        const nbad = vals.filter((v) => bad(v) > 0).length;
        if (aggName === 'worst' || nbad === 0 || nbad === vals.length) return { value: nbad ? vals.find((v) => bad(v) > 0) : vals[0] };
        return { value: vals.filter((v) => v === 1).length / vals.length, share: `${vals.filter((v) => v === 1).length}/${vals.length}` };
      }
      if (aggName === 'worst') return { value: vals.reduce((a, b) => (bad(b) > bad(a) ? b : a)) };
      return { value: vals.reduce((a, b) => a + b, 0) / vals.length };
    };
    const checkCells = async (key, aggName) => {
      const list = await cells();
      let numeric = 0, nulls = 0, errs = 0;
      for (const c of list) {
        const want = expectCell(key, members.get(`${c.r},${c.c}`) || [], aggName);
        const where = `outcome ${key} (${aggName}), cell ${px.name}=${c.x}, ${py.name}=${c.y} [variants ${c.vs}]`;
        if (typeof want.value === 'number') {
          if (!close(Number(c.value), want.value)) fail(`${where}: value ${c.value}, expected ${want.value} from results.csv`);
          numeric++;
          if (c.text !== null) {
            if (want.share) { if (c.text !== want.share) fail(`${where}: shows '${c.text}', expected '${want.share}'`); }
            else if (isBool(key)) {
              const words = key === 'collision' ? ['no', 'yes'] : ['fail', 'pass'];
              if (c.text !== words[want.value]) fail(`${where}: shows '${c.text}', expected '${words[want.value]}'`);
            } else if (!close(Number(c.text), want.value, 0.006)) fail(`${where}: shows '${c.text}' for ${want.value}`);
          }
        } else {
          if (c.value !== want.value) fail(`${where}: value '${c.value}', expected '${want.value}'`);
          if (want.value === '') { nulls++; if (c.text !== null && c.text !== '—') fail(`${where}: never measured shown as '${c.text}'`); if (c.fill !== 'url(#hatch)') fail(`${where}: never measured not hatched`); }
          if (want.value === 'error') { errs++; if (c.text !== null && c.text !== 'error') fail(`${where}: a run error shown as '${c.text}'`); }
        }
      }
      return { numeric, nulls, errs, list };
    };
    const fills = {};
    for (const key of toCheck) {
      switchMs.push(await choose(key));
      const r = await checkCells(key, 'mean');
      fills[key] = r.list.map((c) => c.fill + c.value).join();
      pass(`outcome ${key}: ${r.list.length} cells match results.csv (${r.numeric} with values, ${r.nulls} never measured (hatched), ${r.errs} run errors)` +
        (large ? `; switching took ${switchMs[switchMs.length - 1]} ms` : ''));
    }
    if (fills['passed'] === fills['min_ttc[s]']) fail('switching the outcome from passed to min_ttc did not change the cells');
    pass('switching the outcome selector changes the cells\' values and colours');
    if (shared) {
      await page.selectOption('#agg', 'worst');
      for (const key of ['min_ttc[s]', 'passed']) {
        await choose(key);
        const r = await checkCells(key, 'worst');
        pass(`shared cells, worst: outcome ${key}: ${r.list.length} cells match the worst of their variants in results.csv`);
      }
      await page.selectOption('#agg', 'mean');
    }
    // swap the axes and back
    await page.click('#swap');
    const sw = await state();
    if (sw.x !== py.column || sw.y !== px.column || sw.rows !== px.values.length || sw.columns !== py.values.length) fail(`swap axes: ${JSON.stringify(sw)}`);
    await page.click('#swap');
    pass(`swap axes: ${sw.rows} rows × ${sw.columns} columns with ${sw.x} across, and back`);

    cs = await cells();
    // kept runs: a plain link on their (single-variant) cell
    const keptCells = cs.filter((c) => c.href);
    for (const c of keptCells) {
      const v = Number(c.vs);
      if (c.href !== `runs/${v}/view.html`) fail(`cell of variant ${v} links to ${c.href}`);
      if (!s0.kept.includes(v)) fail(`cell of variant ${v} links to a run the page does not list as kept`);
      if (!fs.existsSync(path.join(sweepDir, c.href))) fail(`link target ${c.href} does not exist`);
    }
    for (const v of s0.kept) {
      if (!fs.existsSync(path.join(sweepDir, 'runs', String(v), 'view.html'))) fail(`kept variant ${v} has no runs/${v}/view.html`);
      const c = cs.find((x) => x.vs.split(',').includes(String(v)));
      if (c && c.vs.split(',').length === 1 && !c.href) fail(`the cell of kept variant ${v} is not a link`);
    }
    const keptDirs = fs.existsSync(path.join(sweepDir, 'runs')) ? fs.readdirSync(path.join(sweepDir, 'runs')).filter((d) => fs.existsSync(path.join(sweepDir, 'runs', d, 'view.html'))).map(Number).sort((a, b) => a - b) : [];
    if (!sameSet(keptDirs.map(String), s0.kept.map(String))) fail(`page lists kept runs ${s0.kept}, the directory has view.html for ${keptDirs}`);
    pass(`kept runs: ${keptCells.length} cells link to runs/<i>/view.html (${keptCells.map((c) => c.href).join(', ') || 'none'}), every target exists; ` +
      `runs without view.html are not linked`);
    sample = '#heatmap';
  } else if (wantView !== 'none') {
    const svgs = wantView === 'parallel' ? ['#pcoords', '#scatter'] : [wantView === 'line' ? '#line' : '#scatter'];
    const marksOf = (sel) => page.evaluate((s) => [...document.querySelectorAll(`${s} [data-v]`)].map((e) => ({
      v: Number(e.dataset.v), value: e.dataset.value, fill: e.getAttribute('fill') || e.getAttribute('stroke'),
      cx: Number(e.getAttribute('cx')), cy: Number(e.getAttribute('cy')),
      href: e.parentElement.tagName.toLowerCase() === 'a' ? e.parentElement.getAttribute('href') : null,
    })), sel);
    const fills = {};
    for (const key of toCheck) {
      switchMs.push(await choose(key));
      const ev = expectedValues(key);
      const byVariant = new Map(variants.map((v, r) => [v, r]));
      for (const sel of svgs) {
        const ms = await marksOf(sel);
        if (ms.length !== N) fail(`${sel}: ${ms.length} marks for ${N} variants`);
        if (new Set(ms.map((m) => m.v)).size !== N) fail(`${sel}: some variant has two marks`);
        for (const m of ms) {
          const r = byVariant.get(m.v), want = asData(ev[r]);
          if (r === undefined) fail(`${sel}: a mark for variant ${m.v}, which results.csv does not have`);
          if (typeof want === 'number' ? !close(Number(m.value), want) : m.value !== want) fail(`${sel}: outcome ${key}: variant ${m.v} has value '${m.value}', results.csv '${want}'`);
        }
        fills[key + sel] = ms.map((m) => m.fill).join();
      }
      pass(`outcome ${key}: ${svgs.map((s) => s.slice(1)).join(' and ')} ${svgs.length > 1 ? 'have' : 'has'} one mark per variant (${N}) with the value of results.csv` +
        (large ? `; switching took ${switchMs[switchMs.length - 1]} ms` : ''));
    }
    if (toCheck.includes('min_ttc[s]') && fills['passed' + svgs[0]] === fills['min_ttc[s]' + svgs[0]]) fail('switching the outcome did not recolour the marks');
    pass('switching the outcome selector recolours the marks');
    // positions follow the parameter on the x axis (scatter: x = first parameter)
    const sc = wantView === 'line' ? '#line' : '#scatter';
    const xs = col(params[0].column).map(Number), byV = new Map(variants.map((v, r) => [v, xs[r]]));
    const ms = (await marksOf(sc)).sort((a, b) => byV.get(a.v) - byV.get(b.v));
    for (let k = 1; k < ms.length; k++) if (ms[k].cx < ms[k - 1].cx - 0.11) fail(`${sc}: variant ${ms[k].v} (${params[0].name}=${byV.get(ms[k].v)}) is left of variant ${ms[k - 1].v}`);
    pass(`${sc.slice(1)}: marks are ordered along x by ${params[0].name}`);
    if (wantView !== 'line') { // choose other axes for the scatter
      const other = params.length >= 3 ? 'p2' : 'o';
      await page.selectOption('#sy', other);
      const st = await state();
      const after = await marksOf('#scatter');
      if (st.scatterY !== other || after.length !== N) fail(`scatter y = ${other}: state ${st.scatterY}, ${after.length} marks`);
      const moved = after.filter((m) => { const b = ms.find((x) => x.v === m.v); return Math.abs(b.cy - m.cy) > 0.5; }).length;
      if (!moved) fail('choosing another scatter y axis moved no mark');
      pass(`scatter axes: y = ${other} moves ${moved} of ${N} marks`);
      await page.selectOption('#sy', 'p1');
    }
    const all = await marksOf(svgs[svgs.length - 1]);
    const keptMarks = all.filter((m) => m.href);
    for (const m of keptMarks) {
      if (m.href !== `runs/${m.v}/view.html` || !fs.existsSync(path.join(sweepDir, m.href))) fail(`mark of variant ${m.v} links to ${m.href}, which does not exist`);
    }
    if (keptMarks.length !== s0.kept.length) fail(`${keptMarks.length} linked marks, ${s0.kept.length} kept runs with a report`);
    pass(`kept runs: ${keptMarks.length} marks link to runs/<i>/view.html, every target exists`);
    sample = svgs[svgs.length - 1];
  }
  if (large) {
    // Reported, not checked: the budgets (ready in 10 s, a switch in 5 s) are
    // bench/sweep_report_load.sh's, since no test depends on wall-clock speed.
    pass(`responsive with ${N} variants: outcome switches ${switchMs.join(', ')} ms`);
  }
  noErrors('main view');

  // ---- hover and click ------------------------------------------------------------------------
  // A variant mark (or single-variant cell) that is on top at its centre, in view, with or
  // without a link to a kept run; its centre in client coordinates.
  const topmost = async (svg, linked) => {
    await page.locator(svg).scrollIntoViewIfNeeded();
    return page.evaluate(([sel, k]) => {
      const all = [...document.querySelectorAll(`${sel} [data-v], ${sel} .cell[data-vs]`)].reverse();
      for (const e of all.filter((x) => x.dataset.value !== 'error').concat(all.filter((x) => x.dataset.value === 'error'))) {
        if (e.dataset.vs === '') continue;
        const b = e.getBoundingClientRect(), x = b.left + b.width / 2, y = b.top + b.height / 2;
        if (x < 0 || y < 0 || x > innerWidth || y > innerHeight) continue;
        const at = document.elementFromPoint(x, y), hit = at && at.closest('[data-v],[data-vs]');
        if (hit !== e || !!e.closest('a[href]') !== k) continue;
        const vs = (e.dataset.v ?? e.dataset.vs).split(',').map(Number);
        return { x, y, v: vs[0], vs, href: k ? e.closest('a').getAttribute('href') : null };
      }
      return null;
    }, [svg, linked]);
  };
  if (sample) {
    const t = await topmost(sample, false);
    if (!t) fail(`no variant without a kept run is clickable in ${sample}`);
    await page.mouse.move(t.x, t.y);
    const tip = await page.evaluate(() => ({ hidden: document.getElementById('tip').hidden, text: document.getElementById('tip').textContent }));
    const what = t.vs.length > 1 ? `the cell of variants ${t.vs.join(', ')}` : `variant ${t.v}`;
    if (tip.hidden || !tip.text.includes(t.vs.length > 1 ? `${t.vs.length} variants: ${t.vs.slice(0, 8).join(', ')}` : `variant ${t.v}`)) fail(`hovering ${what}: tooltip ${JSON.stringify(tip)}`);
    for (const p of params) if (!tip.text.includes(`${p.name} = `)) fail(`tooltip of ${what} lacks ${p.name}: '${tip.text}'`);
    pass(`hover on ${what}: '${tip.text.slice(0, 150)}…'`);
    await page.mouse.click(t.x, t.y);
    const st = await state();
    if (st.selected !== t.v || !sameSet(st.selectedVariants.map(String), t.vs.map(String))) fail(`clicked variant ${t.vs} (no kept run) but selected is ${st.selected} (${st.selectedVariants})`);
    const row = await page.evaluate((v) => {
      const tr = document.querySelector(`#table tr.sel[data-v="${v}"]`), w = document.getElementById('tableWrap').getBoundingClientRect();
      if (!tr) return null;
      const b = tr.getBoundingClientRect();
      return { inWrap: b.top >= w.top - 1 && b.bottom <= w.bottom + 1, onScreen: b.top >= 0 && b.bottom <= window.innerHeight };
    }, t.v);
    if (!row || !row.inWrap || !row.onScreen) fail(`clicking variant ${t.v} did not show its table row: ${JSON.stringify(row)}`);
    const marked = await page.evaluate(() => [...document.querySelectorAll('#table tr.sel')].map((tr) => Number(tr.dataset.v)));
    if (!marked.includes(t.v) || !marked.every((v) => t.vs.includes(v))) fail(`clicked ${what}: table marks ${marked}`);
    pass(`click on ${what} (no kept run): its table row${t.vs.length > 1 ? 's are' : ' is'} highlighted and scrolled into view`);
  }

  // ---- table: every variant, sortable ---------------------------------------------------------
  const st = await state();
  if (st.tableRows !== N) fail(`table has ${st.tableRows} rows, ${N} variants`);
  await page.evaluate(() => { document.getElementById('tableWrap').scrollTop = 0; });
  await page.waitForTimeout(50);
  const domRows = await page.evaluate(() => document.querySelectorAll('#table tbody tr[data-v]').length);
  if (N <= 60 && domRows !== N) fail(`table shows ${domRows} rows, ${N} variants`);
  if (N > 60 && !(domRows > 0 && domRows < N)) fail(`table renders ${domRows} of ${N} rows: expected a window`);
  const sortCheck = async (column, desc) => {
    const order = await page.evaluate(() => window.sdvSweep.tableOrder());
    const vals = col(column).map(num), byV = new Map(variants.map((v, r) => [v, vals[r]]));
    const seq = order.map((v) => byV.get(v));
    const firstNull = seq.indexOf(null);
    if (firstNull >= 0 && seq.slice(firstNull).some((v) => v !== null)) fail(`sorted by ${column}: empty cells are not last`);
    for (let k = 1; k < seq.length && seq[k] !== null; k++) if (desc ? seq[k] > seq[k - 1] : seq[k] < seq[k - 1]) fail(`sorted by ${column}${desc ? ' descending' : ''}: ${seq[k - 1]} before ${seq[k]}`);
    const shown = await page.evaluate(() => [...document.querySelectorAll('#table tbody tr[data-v]')].slice(0, 5).map((tr) => Number(tr.dataset.v)));
    if (shown.join() !== order.slice(0, 5).join()) fail(`the first rows shown (${shown}) are not the first in order (${order.slice(0, 5)})`);
  };
  await page.evaluate(() => { document.getElementById('tableWrap').scrollTop = 0; });
  await page.click('#table th[data-col="min_gap[m]"]');
  await sortCheck('min_gap[m]', false);
  await page.click('#table th[data-col="min_gap[m]"]');
  await sortCheck('min_gap[m]', true);
  await page.click('#table th[data-col="variant"]');
  await sortCheck('variant', false);
  // the rows' cells against results.csv (the rows shown)
  const shownRows = await page.evaluate(() => [...document.querySelectorAll('#table tbody tr[data-v]')].map((tr) => [...tr.cells].map((td) => td.textContent.trim())));
  for (const cells of shownRows) {
    const r = variants.indexOf(parseInt(cells[0], 10));
    header.forEach((h, k) => {
      const csvText = body[r][k], t = cells[k];
      if (h === 'error') { if (t !== csvText) fail(`table: variant ${variants[r]} error '${t}', results.csv '${csvText}'`); return; }
      if (h === 'variant') return;
      if (csvText === '') { if (t !== '—') fail(`table: variant ${variants[r]} ${h} empty in results.csv but shows '${t}'`); return; }
      if (h === 'passed' || h.endsWith('_passed')) { const w = h === 'passed' && isErr(r) ? 'error' : csvText === '1' ? 'pass' : 'fail'; if (t !== w) fail(`table: variant ${variants[r]} ${h} '${t}', expected '${w}'`); return; }
      if (!close(Number(t), Number(csvText))) fail(`table: variant ${variants[r]} ${h} '${t}', results.csv '${csvText}'`);
    });
  }
  for (const v of s0.kept) { // every kept run is linked from its table row
    await page.evaluate((x) => window.sdvSweep.select(x), v);
    const href = await page.evaluate((x) => { const a = document.querySelector(`#table tr[data-v="${x}"] a[href]`); return a && a.getAttribute('href'); }, v);
    if (href !== `runs/${v}/view.html` || !fs.existsSync(path.join(sweepDir, href))) fail(`table row of kept variant ${v} links to ${href}`);
  }
  if (N > 60) { // scrolling the window renders the last variants
    await page.evaluate(() => { const w = document.getElementById('tableWrap'); w.scrollTop = w.scrollHeight; });
    await page.waitForFunction((last) => !!document.querySelector(`#table tr[data-v="${last}"]`), variants[N - 1], { timeout: 60000 });
    await page.evaluate(() => { document.getElementById('tableWrap').scrollTop = 0; });
  }
  if (s0.kept.length) pass(`table: the rows of the kept variants ${s0.kept.join(', ')} link to their runs/<i>/view.html`);
  pass(`table: ${N} variants${N > 60 ? ` (${domRows} rows rendered at a time, the last reached by scrolling)` : ''}, ${shownRows.length} rows shown match results.csv; ` +
    'sorting by min_gap ascending / descending (empty last) and back by variant');
  noErrors('table');

  // ---- screenshot, then open a kept run through its link -----------------------------------------
  await page.evaluate(() => { window.scrollTo(0, 0); return new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))); });
  await page.screenshot({ path: shot, fullPage: !large });
  pass(`screenshot written to ${shot}`);
  noErrors('end');
  const link = sample && s0.kept.length ? await topmost(sample, true) : null;
  if (link) {
    if (!fs.existsSync(path.join(sweepDir, link.href))) fail(`link target ${link.href} does not exist`);
    await Promise.all([page.waitForURL((u) => u.href.endsWith(link.href), { timeout: 60000 }), page.mouse.click(link.x, link.y)]);
    await page.waitForFunction(() => window.sdvView && (window.sdvView.ready === true || window.sdvView.error), null, { timeout: 60000 });
    const viewErr = await page.evaluate(() => window.sdvView.error);
    if (viewErr) fail(`the kept run's report reported an error: ${viewErr}`);
    pass(`clicking kept variant ${link.v} opens ${link.href} (its sdv view report loads)`);
  }
  noErrors('kept run');
  pass('no console errors, page errors or network requests');
}

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--no-first-run'],
});
let code = 0;
try {
  await run(browser);
  console.log(`OK    ${checks} checks passed`);
} catch (e) {
  console.log(`FAIL  ${e instanceof CheckFailed ? e.message : (e && e.stack) || e}`);
  code = 1;
} finally {
  await browser.close().catch(() => {});
}
process.exit(code);
