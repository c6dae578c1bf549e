#!/usr/bin/env node
// Browser test of an `sdv view` report.
//
//   node browser_test.mjs report.html screenshot.png
//
// Opens the report in headless Chromium (/usr/bin/chromium, or $CHROMIUM) through
// playwright-core, drives the real UI (time slider, play button, keyboard, map click,
// timeline, charts), reads the state back through window.sdvView, prints one line per
// check and takes a full-page screenshot. Exit status 0 = all checks passed, 1 = failure.
import { chromium } from 'playwright-core';
import { pathToFileURL } from 'node:url';
import path from 'node:path';
import fs from 'node:fs';

const [file, shot] = process.argv.slice(2);
if (!file || !shot) {
  console.error('usage: node browser_test.mjs report.html screenshot.png');
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

  // ---- screenshot --------------------------------------------------------------------
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  await page.screenshot({ path: shot, fullPage: true });
  pass(`screenshot written to ${shot}`);
  noErrors('end');
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
