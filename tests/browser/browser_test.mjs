#!/usr/bin/env node
// Browser test of an `sdv view` report.
//
//   node browser_test.mjs report.html screenshot.png [--require=pedestrian,crosswalk,walkway]
//
// Opens the report in headless Chromium (/usr/bin/chromium, or $CHROMIUM) through
// playwright-core, drives the real UI (time slider, play button, keyboard, map click,
// timeline, charts), reads the state back through window.sdvView, checks the metrics
// tables, the expectations (every part of a compound one, windows) and the charts' extremes
// against the summary.json embedded in the page, prints one line per check and takes a
// full-page screenshot. Pedestrians (discs with a heading tick and a label), crosswalks (zebra
// stripes, tinted by their pedestrian signal) and walkways are checked on the map's pixels
// whenever the run has them; --require makes their absence a failure.
// Exit status 0 = all checks passed, 1 = failure.
import { chromium } from 'playwright-core';
import { pathToFileURL } from 'node:url';
import path from 'node:path';
import fs from 'node:fs';

const [file, shot, ...opts] = process.argv.slice(2);
const required = new Set(opts.filter((o) => o.startsWith('--require=')).flatMap((o) => o.slice(10).split(',')).filter(Boolean));
if (!file || !shot || opts.some((o) => !o.startsWith('--require='))) {
  console.error('usage: node browser_test.mjs report.html screenshot.png [--require=pedestrian,crosswalk,walkway]');
  process.exit(1);
}
if (!fs.existsSync(file)) {
  console.error(`FAIL  report not found: ${file}`);
  process.exit(1);
}

class CheckFailed extends Error {}
const errors = [];
let checks = 0;
const pass = (msg) => { checks++; console.log(`PASS  ${msg}`); };
const fail = (msg) => { throw new CheckFailed(msg); };
const noErrors = (where) => { if (errors.length) fail(`console/page errors (${where}):\n      ${errors.join('\n      ')}`); };
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

async function run(browser) {
  const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  page.on('console', (m) => { if (m.type() === 'error') errors.push(`console.error: ${m.text()}`); });
  page.on('pageerror', (e) => errors.push(`page error: ${e.message}`));
  page.on('request', (r) => { // the report must be self-contained
    const u = r.url();
    if (!u.startsWith('file:') && !u.startsWith('data:') && !u.startsWith('blob:')) errors.push(`network request: ${u}`);
  });
  const state = () => page.evaluate(() => window.sdvView.state());

  // ---- load and readiness -------------------------------------------------------------
  const url = pathToFileURL(path.resolve(file)).href;
  const t0 = Date.now();
  await page.goto(url, { waitUntil: 'commit', timeout: 120000 });
  await page.waitForFunction(() => window.sdvView && (window.sdvView.ready === true || window.sdvView.error),
    null, { timeout: 120000, polling: 20 });
  const wallMs = Date.now() - t0;
  const info = await page.evaluate(() => ({ error: window.sdvView.error, readyAt: window.sdvView.readyAt, timings: window.sdvView.timings }));
  if (info.error) fail(`page reported an error: ${info.error}`);
  noErrors('load');
  const sizeMb = (fs.statSync(file).size / 1e6).toFixed(1);
  pass(`ready: navigation→ready ${info.readyAt} ms in page (${wallMs} ms wall clock incl. browser overhead); ` +
    `file ${sizeMb} MB, JSON.parse ${info.timings.parseMs} ms, init ${info.timings.initMs} ms, first frame ${info.timings.firstFrameMs} ms`);

  const s0 = await state();
  if (!s0 || !(s0.ticks > 1)) fail(`state() unusable: ${JSON.stringify(s0)}`);
  const view = await page.evaluate(() => window.sdvView.view());
  if (view.road) { // the initial view must show the whole road, filling the map
    const fx = (view.road.x1 - view.road.x0) * view.scale / view.width, fy = (view.road.y1 - view.road.y0) * view.scale / view.height;
    if (!(Math.max(fx, fy) > 0.5 && Math.max(fx, fy) <= 1.0)) fail(`initial view does not fit the road: road covers ${(fx * 100).toFixed(0)}% × ${(fy * 100).toFixed(0)}% of the map`);
    pass(`initial view fits the road: ${(fx * 100).toFixed(0)}% × ${(fy * 100).toFixed(0)}% of the ${view.width}×${view.height} px map`);
  }
  pass(`state(): ${s0.ticks} ticks, t ∈ [${s0.t0}, ${s0.t1}] s, ${s0.vehicles.length} vehicles at t=${s0.time}, selected ${s0.selected}`);

  // ---- time slider, driven like a user: set value + 'input' event ---------------------
  const N = s0.ticks;
  const scrubTo = async (tick) => {
    await page.locator('#slider').evaluate((el, v) => { el.value = String(v); el.dispatchEvent(new Event('input', { bubbles: true })); }, tick);
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)))); // let it render
    const st = await state();
    if (st.tick !== tick) fail(`slider set to ${tick} but page is at tick ${st.tick}`);
    return st;
  };
  let moved = null, reasons = [];
  for (const [fa, fb] of [[0.1, 0.4], [0.05, 0.3], [0.2, 0.6], [0.3, 0.7], [0.0, 0.25], [0.5, 0.9]]) {
    const a = Math.floor(fa * (N - 1)), b = Math.floor(fb * (N - 1));
    if (b <= a) continue;
    const sa = await scrubTo(a);
    const textA = await page.locator('#timeDisplay').textContent();
    const cand = sa.vehicles.filter((v) => Number.isFinite(v.speed) && Number.isFinite(v.yaw))
      .sort((p, q) => Math.abs(q.speed) - Math.abs(p.speed))[0];
    if (!cand || Math.abs(cand.speed) < 0.5) { reasons.push(`no moving vehicle at tick ${a}`); continue; }
    const sb = await scrubTo(b);
    const textB = await page.locator('#timeDisplay').textContent();
    if (textA === textB) fail(`time display did not change when scrubbing (${textA})`);
    const vb = sb.vehicles.find((v) => v.name === cand.name);
    if (!vb) { reasons.push(`${cand.name} not present at tick ${b}`); continue; }
    const dx = vb.x - cand.x, dy = vb.y - cand.y, dist = Math.hypot(dx, dy);
    const dot = (dx * Math.cos(cand.yaw) + dy * Math.sin(cand.yaw)) * Math.sign(cand.speed);
    if (dist > 1 && dot > 0) { moved = { cand, vb, a, b, sa, sb, dist, dot }; break; }
    reasons.push(`${cand.name} moved ${dist.toFixed(2)} m, dot ${dot.toFixed(2)} between ticks ${a} and ${b}`);
  }
  if (!moved) fail(`no vehicle moved in its direction of travel: ${reasons.join('; ')}`);
  pass(`slider: t=${moved.sa.time} → t=${moved.sb.time}: ${moved.cand.name} (speed ${moved.cand.speed.toFixed(2)} m/s) moved ` +
    `${moved.dist.toFixed(1)} m along its heading (dot ${moved.dot.toFixed(1)} > 0)`);
  noErrors('slider');

  // ---- slider with the mouse -------------------------------------------------------
  const box = await page.locator('#slider').boundingBox();
  await page.mouse.click(box.x + box.width * 0.75, box.y + box.height / 2);
  await sleep(50);
  const sm = await state();
  const want = 0.75 * (N - 1);
  if (Math.abs(sm.tick - want) > 0.06 * N + 2) fail(`mouse click at 75% of the slider gave tick ${sm.tick}, expected ≈ ${want.toFixed(0)}`);
  pass(`slider mouse click at 75% → tick ${sm.tick} (≈ ${want.toFixed(0)})`);

  // ---- play / pause ----------------------------------------------------------------
  await scrubTo(Math.floor(0.1 * (N - 1)));
  const before = await state();
  await page.evaluate(() => window.sdvView.resetStats());
  await page.click('#play');
  await sleep(800);
  const during = await state();
  const stats = await page.evaluate(() => window.sdvView.stats);
  if (!during.playing) fail('play button did not start playback');
  if (!(during.time > before.time)) fail(`time did not advance while playing (${before.time} → ${during.time})`);
  await page.click('#play');
  const paused = await state();
  await sleep(300);
  const later = await state();
  if (later.playing || later.tick !== paused.tick) fail('second click on play did not pause');
  if (stats.frames < 5) fail(`only ${stats.frames} frames rendered in 0.8 s of playback`);
  pass(`play: t ${before.time} → ${during.time} s after 0.8 s at 1×; ${stats.frames} frames, render ` +
    `avg ${(stats.renderMs / stats.frames).toFixed(1)} ms / max ${stats.maxRenderMs.toFixed(1)} ms; pause stops at t=${paused.time}`);

  // ---- keyboard ---------------------------------------------------------------------
  await page.evaluate(() => document.activeElement && document.activeElement.blur());
  const k0 = (await state()).tick;
  await page.keyboard.press('ArrowRight');
  await page.keyboard.press('ArrowRight');
  await page.keyboard.press('ArrowLeft');
  const k1 = (await state()).tick;
  if (k1 !== Math.min(k0 + 1, N - 1)) fail(`keyboard →→← from tick ${k0} gave ${k1}`);
  await page.keyboard.press(' ');
  await sleep(300);
  const ks = await state();
  await page.keyboard.press(' ');
  if (!ks.playing || (await state()).playing) fail('space did not toggle playback');
  pass(`keyboard: arrows step one tick (${k0} → ${k1}), space toggles play`);

  // ---- click a vehicle on the map (following the selected one and zooming in with the
  //      wheel until another vehicle is clear of its neighbours and of the overlays) -------
  await scrubTo(Math.floor(0.3 * (N - 1)));
  const map = await page.locator('#map').boundingBox();
  const overlays = await page.evaluate(() => [...document.querySelectorAll('#mapWrap .overlay')]
    .filter((e) => !e.hidden).map((e) => e.getBoundingClientRect().toJSON()));
  const clear = (p) => p.x > map.x + 10 && p.x < map.x + map.width - 10 && p.y > map.y + 10 && p.y < map.y + map.height - 10 &&
    overlays.every((o) => p.x < o.left - 8 || p.x > o.right + 8 || p.y < o.top - 8 || p.y > o.bottom + 8);
  const cur = (await state()).selected;
  let target = null;
  for (let zoom = 0; zoom < 10 && !target; zoom++) {
    const pos = await page.evaluate(() => window.sdvView.screenPositions());
    const isolated = pos.filter((p) => clear(p) && pos.every((q) => q === p || Math.hypot(q.x - p.x, q.y - p.y) > 16));
    target = isolated.find((p) => p.name !== cur) || (pos.length === 1 ? isolated[0] : null);
    if (!target) {
      if (zoom === 0) await page.click('#followChk'); // centre the selected vehicle, the others are near it
      await page.mouse.move(map.x + map.width / 2, map.y + map.height / 2);
      await page.mouse.wheel(0, -400);
      await sleep(60);
    }
  }
  if (!target) fail('map click: could not find an isolated vehicle to click, even after zooming in');
  await page.mouse.click(target.x, target.y);
  await sleep(50);
  const sel = (await state()).selected;
  if (sel !== target.name) fail(`clicked ${target.name} on the map but selected is ${sel}`);
  pass(`map click at (${target.x.toFixed(0)}, ${target.y.toFixed(0)}) selects ${target.name}`);
  await page.click('#fitBtn');

  // ---- map zoom with the wheel keeps the point under the cursor ------------------------
  const cx = map.x + map.width * 0.6, cy = map.y + map.height * 0.5;
  await page.mouse.move(cx, cy);
  const before2 = await page.evaluate(() => window.sdvView.screenPositions()[0]);
  await page.mouse.wheel(0, -300);
  await sleep(100);
  const after2 = await page.evaluate(() => window.sdvView.screenPositions()[0]);
  await page.click('#fitBtn');
  if (before2 && after2) {
    const f = Math.hypot(after2.x - cx, after2.y - cy) / Math.max(1e-6, Math.hypot(before2.x - cx, before2.y - cy));
    if (!(f > 1.2)) fail(`wheel zoom did not zoom in around the cursor (distance ratio ${f.toFixed(2)})`);
    pass(`wheel zoom around cursor: distances from the cursor scaled ×${f.toFixed(2)}; Fit restores the view`);
  }

  // ---- timeline event marker ---------------------------------------------------------
  const markers = await page.evaluate(() => window.sdvView.eventMarkers());
  if (markers.length) {
    const m = markers[0];
    await page.mouse.click(m.x, m.y);
    await sleep(50);
    const se = await state();
    if (Math.abs(se.time - m.time) > 0.05 + (s0.t1 - s0.t0) / (N - 1)) fail(`clicking event ${m.kind}@${m.time} jumped to t=${se.time}`);
    pass(`timeline: clicking event '${m.kind}' marker jumps to t=${se.time} (event at ${m.time})`);
  } else console.log('SKIP  timeline event click: run has no events');

  // ---- maneuver band on the timeline ---------------------------------------------------
  const rows = await page.locator('#tlRows').boundingBox();
  await page.mouse.click(rows.x + 130 + (rows.width - 140) * 0.5, rows.y + 5);
  await sleep(50);
  const sr = await state();
  pass(`timeline: clicking a band on row 1 → selected ${sr.selected}, t=${sr.time}`);

  // ---- chart click jumps to time -------------------------------------------------------
  const chart = await page.locator('#chart-speed').boundingBox();
  await page.mouse.click(chart.x + 42 + (chart.width - 48) * 0.5, chart.y + chart.height / 2);
  await sleep(50);
  const sc = await state();
  const mid = s0.t0 + 0.5 * (s0.t1 - s0.t0);
  if (Math.abs(sc.time - mid) > 0.03 * (s0.t1 - s0.t0) + 0.1) fail(`clicking the middle of the speed chart gave t=${sc.time}, expected ≈ ${mid}`);
  pass(`chart click at the middle → t=${sc.time} (≈ ${mid.toFixed(2)})`);

  // ---- decision panel -----------------------------------------------------------------
  const dec = await page.evaluate(() => ({
    text: document.getElementById('decision').textContent,
    rows: document.querySelectorAll('#decision .bt-row').length,
    on: document.querySelectorAll('#decision .bt-row.on').length,
  }));
  const sd = await state();
  if (sd.decision) {
    if (!dec.rows || !dec.on) fail(`decision at t=${sd.decision.time} shown without a highlighted BT path (${dec.rows} rows, ${dec.on} on path)`);
    pass(`decision panel: ${sd.decision.vehicle} plan at t=${sd.decision.time} → '${sd.decision.maneuver}', ` +
      `${dec.rows} BT nodes (${dec.on} on the chosen path), ${sd.candidatePathsDrawn} candidate paths drawn`);
  } else pass(`decision panel: ${dec.text.trim().slice(0, 80)}`);

  // ---- metrics tables: every metric of summary.json, with its unit; null as "—" --------
  const summary = await page.evaluate(() => JSON.parse(document.getElementById('sdv-data').textContent).summary);
  const metrics = summary.metrics || {};
  const PAIR_UNITS = { min_clearance: 'm', min_gap: 'm', min_lateral: 'm', min_ttc: 's', min_headway: 's' };
  const VEH_UNITS = { min_speed: 'm/s', max_speed: 'm/s', min_acc: 'm/s²', max_acc: 'm/s²', max_jerk: 'm/s³', reached_goal: '',
    fallback_used: '', plans: '', fallback_plans: '', fallback_share: '%', longest_stall_s: 's' };
  // The tables as shown: per table its column keys with the unit under the name, and per row
  // the row's key (first cell) and each cell's text and tooltip by column.
  const tables = await page.evaluate(() => [...document.querySelectorAll('#metrics table')].map((t) => ({
    cols: [...t.querySelectorAll('th[data-col]')].map((th) => ({ key: th.dataset.col, unit: (th.querySelector('.unit') || {}).textContent || '' })),
    rows: [...t.querySelectorAll('tr')].slice(1).map((tr) => ({
      key: tr.cells[0].textContent,
      cells: Object.fromEntries([...tr.querySelectorAll('td[data-col]')].map((td) => [td.dataset.col, { text: td.textContent.trim(), title: td.title }])),
    })),
  })));
  const findCell = (rowKey, col) => {
    for (const t of tables) {
      if (!t.cols.some((c) => c.key === col)) continue;
      const r = t.rows.find((x) => x.key === rowKey);
      if (r && r.cells[col]) return { cell: r.cells[col], unit: t.cols.find((c) => c.key === col).unit };
    }
    return null;
  };
  const checkCell = (what, rowKey, col, value, unit) => {
    const f = findCell(rowKey, col);
    if (!f) fail(`metrics: no '${col}' cell for ${what} ${rowKey}`);
    const wantUnit = unit ? `[${unit}]` : '';
    if (f.unit.replace(/\u00a0/g, '').trim() !== wantUnit) fail(`metrics: column '${col}' shows unit '${f.unit}', expected '${wantUnit}'`);
    const { text, title } = f.cell;
    if (value === null) {
      const why = col === 'min_ttc' ? 'never closing' : 'never measured';
      if (text !== '—' || !title.startsWith(why)) fail(`metrics: ${what} ${rowKey} ${col} is null but shows '${text}' (tooltip '${title}'), expected '—' with '${why}'`);
    } else if (typeof value === 'boolean') {
      if (text !== (value ? 'yes' : 'no')) fail(`metrics: ${what} ${rowKey} ${col} = ${value} shown as '${text}'`);
    } else {
      const shown = col === 'fallback_share' ? Number(text) / 100 : Number(text);
      if (!(Math.abs(shown - value) <= 0.005 * Math.max(1, Math.abs(value)))) fail(`metrics: ${what} ${rowKey} ${col} = ${value} shown as '${text}'`);
    }
  };
  const pairs = (metrics.pairs || []).filter(Boolean), vms = (metrics.vehicles || []).filter(Boolean);
  let cells = 0, nulls = 0;
  for (const p of pairs) {
    const key = p.vehicles.join(' ↔ ');
    for (const [col, unit] of Object.entries(PAIR_UNITS)) {
      if (!(col in p)) fail(`summary.json: pair ${key} has no ${col}`);
      checkCell('pair', key, col, p[col], unit); cells++; nulls += p[col] === null;
    }
  }
  for (const m of vms) {
    for (const [col, unit] of Object.entries(VEH_UNITS)) {
      if (!(col in m)) fail(`summary.json: vehicle ${m.vehicle} has no ${col}`);
      checkCell('vehicle', m.vehicle, col, m[col], unit); cells++; nulls += m[col] === null;
    }
  }
  pass(`metrics: ${pairs.length} pairs × ${Object.keys(PAIR_UNITS).length} and ${vms.length} vehicles × ${Object.keys(VEH_UNITS).length} ` +
    `columns with units; ${cells} cells match summary.json (${nulls} null shown as '—' with the reason as tooltip)`);

  // ---- expectations: each statement, its window, and every part of a compound one -------
  const ex = (summary.expectations || []).filter(Boolean);
  const shownEx = await page.evaluate(() => [...document.querySelectorAll('#expectations tr[data-exp]')].map((tr) => ({
    exp: Number(tr.dataset.exp), part: tr.dataset.part == null ? null : Number(tr.dataset.part), time: tr.dataset.time == null ? null : Number(tr.dataset.time),
    text: tr.textContent, expr: (tr.querySelector('.expr') || {}).textContent || '', win: (tr.querySelector('.win') || {}).textContent || '',
    measured: (tr.querySelector('.meas') || {}).textContent || '',
  })));
  const secs = (t) => `${+t.toFixed(3)} s`;
  const valueText = (p) => (p.unit === 'ratio' ? `${(100 * p.value).toFixed(1)} %` : p.unit ? ` ${p.unit}` : '');
  let partRows = 0, windows = 0;
  for (const [i, e] of ex.entries()) {
    const head = shownEx.find((r) => r.exp === i && r.part === null);
    if (!head) fail(`expectation ${i} '${e.expect}' is not shown`);
    if (!head.text.includes(e.passed ? 'PASS' : 'FAIL')) fail(`expectation '${e.expect}' does not show ${e.passed ? 'PASS' : 'FAIL'}: '${head.text}'`);
    if (e.window) {
      const a = e.window.after, b = e.window.before;
      const want = a != null && b != null ? `during ${secs(a)} .. ${secs(b)}` : a != null ? `after ${secs(a)}` : `before ${secs(b)}`;
      if (head.win !== want) fail(`expectation '${e.expect}' shows window '${head.win}', expected '${want}'`);
      windows++;
    }
    const parts = (e.parts || []).filter(Boolean);
    const single = parts.length === 1 && parts[0].holds === e.passed;
    const rows = shownEx.filter((r) => r.exp === i && r.part !== null);
    const check = (p, r, where) => { // the value (or the reason it has none) and its unit
      if ('unit' in p) {
        if (p.value === null) { if (!r.measured.includes(p.none || 'never measured')) fail(`${where}: '${p.call}' has no value but shows '${r.measured}'`); }
        else if (!r.measured.includes(valueText(p)) || !(Math.abs(parseFloat(r.measured) - (p.unit === 'ratio' ? 100 : 1) * p.value) <= 0.005 * Math.max(1, Math.abs(p.value) * (p.unit === 'ratio' ? 100 : 1)))) {
          fail(`${where}: '${p.call}' measured ${p.value} ${p.unit} but shows '${r.measured}'`);
        }
      } else if (p.time != null) {
        if (!r.measured.includes(`at ${p.time.toFixed(2)} s`) || r.time !== p.time) fail(`${where}: '${p.call}' at ${p.time} s shows '${r.measured}'`);
      } else if (p.holds && p.metric !== 'no_collision') {
        if (!r.measured.trim() || r.measured.startsWith('no ')) fail(`${where}: '${p.call}' holds but shows '${r.measured}'`);
      } else if (!r.measured.startsWith('no ')) fail(`${where}: '${p.call}' (no event) shows '${r.measured}'`);
    };
    if (single) {
      if (rows.length) fail(`expectation '${e.expect}' (a single call) lists ${rows.length} parts`);
      check(parts[0], head, 'expectation');
      continue;
    }
    if (rows.length !== parts.length) fail(`expectation '${e.expect}' has ${parts.length} parts but shows ${rows.length}`);
    parts.forEach((p, j) => {
      const r = rows.find((x) => x.part === j);
      if (!r || !r.expr.includes(p.call)) fail(`part ${j} '${p.call}' of '${e.expect}' is not shown`);
      if (!r.expr.trim().endsWith(p.holds ? 'is true' : 'is false')) fail(`part '${p.call}' holds=${p.holds} but shows '${r.expr}'`);
      check(p, r, `part ${j} of '${e.expect}'`);
      partRows++;
    });
  }
  pass(`expectations: ${ex.length} shown with their verdicts, ${partRows} parts of compound ones with truth and measured value, ${windows} windows`);
  const timed = shownEx.find((r) => r.time !== null);
  if (timed) { // a part that happened at a time (a collision, the goal) jumps there
    await page.locator(`#expectations tr[data-exp="${timed.exp}"]` + (timed.part === null ? ':not([data-part])' : `[data-part="${timed.part}"]`)).click();
    await sleep(50);
    const st = await state();
    if (Math.abs(st.time - timed.time) > 0.05 + (s0.t1 - s0.t0) / (N - 1)) fail(`clicking the expectation row at ${timed.time} s jumped to t=${st.time}`);
    pass(`expectations: clicking '${timed.expr.trim()}' (at ${timed.time} s) jumps to t=${st.time}`);
  }

  // ---- charts: the run's extremes of the selected vehicle from summary.json ----------------
  const sel2 = (await state()).selected, vm = vms.find((m) => m.vehicle === sel2);
  if (vm) {
    const ext = await page.evaluate(() => [...document.querySelectorAll('#charts .ext')].map((e) => e.textContent));
    if (!ext[0].includes('min ') || !ext[0].includes('max ') || !ext[1].includes('min ') || !ext[1].includes('max '))
      fail(`speed / acceleration charts do not show ${sel2}'s extremes: '${ext[0]}', '${ext[1]}'`);
    const num = (s, label) => Number((s.match(new RegExp(label.replace(/[|]/g, '\\$&') + ' (-?[0-9.]+)')) || [])[1]);
    for (const [s, label, v] of [[ext[0], 'min', vm.min_speed], [ext[0], 'max', vm.max_speed], [ext[1], 'min', vm.min_acc], [ext[1], 'max', vm.max_acc]]) {
      if (v !== null && !(Math.abs(num(s, label) - v) <= 0.005 * Math.max(1, Math.abs(v)))) fail(`chart head '${s}': ${label} should be ${v}`);
    }
    pass(`charts of ${sel2}: ${ext.filter(Boolean).join(' | ')} (dashed lines, from summary.json)`);
  }
  noErrors('metrics and expectations');

  await checkPedestrianAreas(page, state);
  await checkPedestrians(page, state);
  noErrors('pedestrians');

  // ---- screenshot --------------------------------------------------------------------
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  await page.screenshot({ path: shot, fullPage: true });
  pass(`screenshot written to ${shot}`);
  noErrors('end');
  pass('no console errors, page errors or network requests');
}

// ---- pedestrians and pedestrian areas, checked on the map's pixels -----------------------
const frames = (page) => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
const hexRgb = (h) => { const n = parseInt(String(h).slice(1), 16); return [n >> 16 & 255, n >> 8 & 255, n & 255]; };
const dist3 = (a, b) => Math.abs(a[0] - b[0]) + Math.abs(a[1] - b[1]) + Math.abs(a[2] - b[2]);
const mean = (c) => (c[0] + c[1] + c[2]) / 3;
const lenOf = (P) => { let s = 0; for (let i = 1; i < P.length; i++) s += Math.hypot(P[i][0] - P[i - 1][0], P[i][1] - P[i - 1][1]); return s; };
function along(P, f) {
  let want = Math.min(1, Math.max(0, f)) * lenOf(P);
  for (let i = 1; i < P.length; i++) {
    const seg = Math.hypot(P[i][0] - P[i - 1][0], P[i][1] - P[i - 1][1]);
    if (want <= seg || i === P.length - 1) { const u = seg > 0 ? Math.min(1, want / seg) : 0; return [P[i - 1][0] + u * (P[i][0] - P[i - 1][0]), P[i - 1][1] + u * (P[i][1] - P[i - 1][1])]; }
    want -= seg;
  }
  return P[0];
}
/** The run's agents as embedded (world positions by tick). */
const rawAgents = (page) => page.evaluate(() => JSON.parse(document.getElementById('sdv-data').textContent).vehicles
  .map((v) => ({ name: v.name, kind: v.kind, length: v.length, width: v.width, first: v.first, x: v.x, y: v.y })));
const positionAt = (v, tick) => { const k = tick - v.first; return k >= 0 && k < v.x.length && v.x[k] != null ? [v.x[k], v.y[k]] : null; };
/** The first tick in `ticks` at which no agent but `except` is within `radius` m of p (or null). */
function clearTick(agents, ticks, p, radius, except) {
  return ticks.find((t) => agents.every((v) => { const q = v === except ? null : positionAt(v, t); return !q || Math.hypot(q[0] - p[0], q[1] - p[1]) > radius; })) ?? null;
}
async function lookAt(page, tick, cx, cy, scale) {
  await page.evaluate(([t, o]) => { window.sdvView.setTick(t); window.sdvView.setView(o); }, [tick, { cx, cy, scale }]);
  await frames(page);
}
const worldPixels = (page, pts) => page.evaluate((ps) => window.sdvView.pixels(ps.map((p) => { const c = window.sdvView.toClient(p[0], p[1]); return [c.x, c.y]; })), pts);
/** The tint of a signal over white stripes: which channel dominates. */
function tintOk(signal, c) {
  if (signal === 'red') return c[0] > c[1] + 30 && c[0] > c[2] + 30;
  if (signal === 'green') return c[1] > c[0] + 20 && c[1] > c[2] + 15;
  if (signal === 'yellow' || signal === 'amber') return c[0] > c[2] + 50 && c[1] > c[2] + 30;
  return true;
}

async function checkPedestrianAreas(page, state) {
  const road = await page.evaluate(() => { const r = JSON.parse(document.getElementById('sdv-data').textContent).road || {}; return { crosswalks: r.crosswalks || [], walkways: r.walkways || [] }; });
  if (required.has('crosswalk') && !road.crosswalks.length) fail('road.json of this run has no crosswalks (--require=crosswalk)');
  if (required.has('walkway') && !road.walkways.length) fail('road.json of this run has no walkways (--require=walkway)');
  if (!road.crosswalks.length && !road.walkways.length) return;
  const cws = await page.evaluate(() => window.sdvView.crosswalks()), colors = await page.evaluate(() => window.sdvView.colors());
  if (cws.length !== road.crosswalks.length) fail(`viewer has ${cws.length} crosswalks, road.json ${road.crosswalks.length}`);
  const agents = await rawAgents(page), st0 = await state(), N = st0.ticks, view = await page.evaluate(() => window.sdvView.view());
  const ticks = Array.from({ length: 41 }, (_, i) => Math.round(i * (N - 1) / 40));
  for (const c of cws.slice(0, 4)) {
    const C = c.centre.length >= 2 ? c.centre : c.left.map((p, i) => along(c.right, i / (c.left.length - 1)).map((q, j) => (q + p[j]) / 2));
    const len = lenOf(C), mid = along(C, 0.5);
    const tick = clearTick(agents, ticks, mid, len / 2 + 6, null) ?? 0;
    const scale = Math.min(40, Math.max(6, 0.6 * Math.min(view.width, view.height) / Math.max(len, c.width || 3)));
    await lookAt(page, tick, mid[0], mid[1], scale);
    const n = Math.max(8, Math.ceil(len / 0.08)), pts = Array.from({ length: n + 1 }, (_, i) => along(C, 0.04 + 0.92 * i / n));
    const px = (await worldPixels(page, pts)).filter(Boolean);
    // Stripes and gaps by brightness, between the 20th and 80th percentiles (a light's marker
    // or a label on the crosswalk is a few dark samples, not a level).
    const m = px.map(mean), sorted = m.slice().sort((a, b) => a - b);
    const lo = sorted[Math.floor(0.2 * (sorted.length - 1))], hi = sorted[Math.ceil(0.8 * (sorted.length - 1))], th = (hi + lo) / 2;
    if (!(hi - lo > 25)) fail(`crosswalk ${c.name}: no stripes along its centre line at ${scale.toFixed(1)} px/m (brightness ${lo.toFixed(0)}–${hi.toFixed(0)})`);
    let changes = 0;
    for (let i = 1; i < m.length; i++) if ((m[i] > th) !== (m[i - 1] > th)) changes++;
    const stripes = Math.max(1, Math.round((lenOf(c.left) + lenOf(c.right)) / 2));
    if (changes < Math.max(2, 1.5 * stripes * 0.92 - 2)) fail(`crosswalk ${c.name}: ${changes} stripe edges along its ${len.toFixed(1)} m centre line, expected about ${2 * stripes}`);
    const bright = px.filter((p, i) => m[i] > th), avg = [0, 1, 2].map((j) => bright.reduce((a, p) => a + p[j], 0) / bright.length).map(Math.round);
    const sig = (await page.evaluate(() => window.sdvView.crosswalks()))[cws.indexOf(c)].signal;
    if (!sig) {
      if (!(Math.min(...avg) > 225)) fail(`crosswalk ${c.name} (no signal): stripes are not white: rgb(${avg})`);
      pass(`crosswalk ${c.name}: ${changes} stripe edges (≈ ${stripes} white stripes rgb(${avg})) across ${len.toFixed(1)} m at t=${(await state()).time}`);
      continue;
    }
    if (!tintOk(sig, avg)) fail(`crosswalk ${c.name}: pedestrian signal ${sig} but its stripes are rgb(${avg})`);
    // Another time when the signal differs: the tint follows it.
    let other = null;
    for (const t of ticks) {
      await page.evaluate((k) => window.sdvView.setTick(k), t);
      const s2 = (await page.evaluate(() => window.sdvView.crosswalks()))[cws.indexOf(c)].signal;
      if (s2 && s2 !== sig) { other = { t, s2 }; break; }
    }
    let also = '';
    if (other) {
      await frames(page);
      const px2 = (await worldPixels(page, pts)).filter(Boolean), m2 = px2.map(mean), s2 = m2.slice().sort((a, b) => a - b);
      const th2 = (s2[Math.floor(0.2 * (s2.length - 1))] + s2[Math.ceil(0.8 * (s2.length - 1))]) / 2;
      const b2 = px2.filter((p, i) => m2[i] > th2), avg2 = [0, 1, 2].map((j) => b2.reduce((a, p) => a + p[j], 0) / b2.length).map(Math.round);
      if (!tintOk(other.s2, avg2)) fail(`crosswalk ${c.name}: pedestrian signal ${other.s2} at tick ${other.t} but its stripes are rgb(${avg2})`);
      also = `; at tick ${other.t} '${other.s2}' → rgb(${avg2})`;
    }
    pass(`crosswalk ${c.name} (signal ${c.light}${c.inverse ? ', inverse' : ''}): ${changes} stripe edges; '${sig}' → stripes rgb(${avg})${also}`);
  }
  if (road.walkways.length) {
    const walks = await page.evaluate(() => window.sdvView.walkways()), want = hexRgb(colors.walkFill);
    let seen = 0, tried = 0;
    for (const w of walks.slice(0, 12)) {
      const a = along(w.left, 0.5), b = along(w.right, 0.5), p = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
      const tick = clearTick(agents, ticks, p, 8, null);
      if (tick === null) continue;
      tried++;
      await lookAt(page, tick, p[0], p[1], 12);
      const [c] = await worldPixels(page, [p]);
      if (c && dist3(c, want) <= 12) seen++;
    }
    const drawn = (await state()).drawn;
    if (!seen || !(drawn.walkways >= 1)) fail(`walkways: none of ${tried} sampled walkways shows the walkway fill ${colors.walkFill} at its middle`);
    pass(`walkways: ${seen} of ${tried} sampled walkways filled ${colors.walkFill} between their bounds (${walks.length} in road.json)`);
  }
  await page.evaluate(() => window.sdvView.fit());
  const st = await state();
  if (road.crosswalks.length && !(st.drawn.crosswalks >= 1)) fail('no crosswalk drawn in the fitted view');
}

async function checkPedestrians(page, state) {
  const agents = await rawAgents(page), peds = agents.filter((v) => v.kind === 'pedestrian');
  if (!peds.length) { if (required.has('pedestrian')) fail('the run has no pedestrians (--require=pedestrian)'); return; }
  const options = await page.$$eval('#vehSelect option', (os) => os.map((o) => o.textContent));
  for (const p of peds) if (!options.includes(`${p.name} (pedestrian)`)) fail(`agent list has no '${p.name} (pedestrian)': ${options.join(', ')}`);
  const cws = await page.evaluate(() => window.sdvView.crosswalks());
  const ends = cws.flatMap((c) => [c.centre[0], c.centre[c.centre.length - 1]]).filter(Boolean);
  for (const p of peds.slice(0, 2)) {
    // A moment when nothing else is near it (another agent or a crosswalk's label would cover it).
    let tick = null;
    for (let i = 1; i < 20 && tick === null; i++) {
      const t = p.first + Math.floor(i * (p.x.length - 1) / 20), q = positionAt(p, t);
      if (q && clearTick(agents, [t], q, 4, p) !== null && ends.every((e) => Math.hypot(e[0] - q[0], e[1] - q[1]) > 4)) tick = t;
    }
    if (tick === null) fail(`pedestrian ${p.name}: never clear of other agents to look at`);
    const q = positionAt(p, tick), radius = Math.max(p.length, p.width) / 2, scale = 10 / radius;
    await lookAt(page, tick, q[0], q[1], scale);
    const sp = (await page.evaluate(() => window.sdvView.screenPositions())).find((e) => e.name === p.name);
    if (!sp || sp.kind !== 'pedestrian' || sp.shape !== 'disc') fail(`pedestrian ${p.name} is not drawn as a disc: ${JSON.stringify(sp)}`);
    if (Math.abs(sp.r - radius * scale) > 0.5) fail(`pedestrian ${p.name}: disc of ${sp.r} px, expected max(length, width)/2 = ${radius} m = ${radius * scale} px`);
    const col = hexRgb(sp.color), r = sp.r, dir = (a) => [Math.cos(sp.yaw + a), -Math.sin(sp.yaw + a)];
    const at = (a, d) => { const [dx, dy] = dir(a); return [sp.x + dx * d, sp.y + dy * d]; };
    const inside = [[sp.x, sp.y], at(Math.PI / 2, 0.7 * r), at(Math.PI, 0.7 * r), at(-Math.PI / 2, 0.7 * r)];
    // Corners of the disc's square away from the heading tick: outside a disc, inside a box.
    const corners = [3, 5].map((k) => at(k * Math.PI / 4, 1.3 * r));
    const tickPt = at(0, r + 0.5 * Math.max(4, 0.7 * r)), behind = at(Math.PI, r + 0.5 * Math.max(4, 0.7 * r));
    const px = await page.evaluate((ps) => window.sdvView.pixels(ps), [...inside, ...corners, tickPt, behind]);
    const bad = inside.map((_, i) => px[i]).filter((c) => !c || dist3(c, col) > 45);
    if (bad.length) fail(`pedestrian ${p.name}: disc pixels ${JSON.stringify(px.slice(0, 4))} are not its colour ${sp.color}`);
    if (corners.some((_, i) => !px[4 + i] || dist3(px[4 + i], col) <= 45)) fail(`pedestrian ${p.name}: drawn as a box, not a disc (corner pixels ${JSON.stringify(px.slice(4, 6))})`);
    if (!(mean(px[6]) < mean(px[7]) - 30)) fail(`pedestrian ${p.name}: no heading tick (pixel ahead ${px[6]}, behind ${px[7]})`);
    const st = await state();
    if (!(st.drawn.pedestrians >= 1) || !st.drawn.labels.some((l) => l === p.name || l.startsWith(p.name + ' · '))) fail(`pedestrian ${p.name}: no label among ${JSON.stringify(st.drawn.labels)}`);
    await page.evaluate((n) => window.sdvView.select(n), p.name);
    await frames(page);
    const info = await page.locator('#vehInfo').textContent();
    if (!info.includes('pedestrian') || !info.includes('⌀')) fail(`side panel of ${p.name} does not show its kind and disc: '${info}'`);
    pass(`pedestrian ${p.name} at t=${st.time}: disc ${(2 * r).toFixed(1)} px (⌀ ${2 * radius} m) in rgb(${px[0]}), heading tick, label, ` +
      `listed as '${p.name} (pedestrian)', side panel '${info.slice(0, 40)}…'`);
  }
  await page.evaluate(() => window.sdvView.fit());
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
