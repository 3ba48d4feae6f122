#!/usr/bin/env node
// Browser test of a run-mode page (what `tissuebench view` writes), in headless Chromium.
//
//   node tests/browser/view_test.mjs --page FILE.html [--shots DIR] [--chromium PATH]
//
// FILE.html: a page `tissuebench view RUN_DIR --out FILE.html` wrote. Exit 0 only when every
// positive check passes and every negative control is caught. See tests/browser/README.md.
import { readFileSync, writeFileSync, mkdtempSync, mkdirSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';
import {
  launch, watchPage, decodePng, diffPixels, colourStats, Checks, sleep, parseArgs,
} from './lib.mjs';

const MIN_CHANGED_PIXELS = 100;   // "the canvas changed": more pixels than this differ
const MIN_DISTINCT_COLOURS = 16;  // "not blank": at least this many (quantised) colours ...
const MIN_NON_BACKGROUND = 0.02;  // ... and this share of pixels off the most common colour
const CONFIG_OPEN = '<script id="tissuebench-config" type="application/json">';

function usage(msg) {
  if (msg) console.error(`view_test: ${msg}`);
  console.error('usage: view_test.mjs --page FILE.html [--shots DIR] [--chromium PATH]');
  process.exit(2);
}

function splitConfig(html) {
  const a = html.indexOf(CONFIG_OPEN);
  if (a < 0) throw new Error('the page has no tissuebench-config element');
  const b = html.indexOf('</script>', a + CONFIG_OPEN.length);
  return { before: html.slice(0, a + CONFIG_OPEN.length), json: html.slice(a + CONFIG_OPEN.length, b), after: html.slice(b) };
}

// JSON as the page holds it: every "<" written \u003c (viewer/README.md, "The page template").
const escapeJson = (json) => json.split('<').join('\\u003c');

// The same page with zero frames and a failed status: what a run that failed at once gives.
function zeroFramePage(html) {
  const { before, json, after } = splitConfig(html);
  const config = JSON.parse(json);
  const run = config.run;
  run.frame_times = [];
  run.status = 'failed';
  run.failure = 'at t = 0 s, step 0: test failure text (view_test zero-frame check)';
  for (const m of run.meshes) m.displacement_b64 = '';
  run.series = { time: [], columns: (run.series.columns || []).map((c) => ({ name: c.name, unit: c.unit, values: [] })) };
  return { html: before + escapeJson(JSON.stringify(config)) + after, failure: run.failure };
}

// The same page with its config JSON broken.
function corruptPage(html) {
  const { before, json, after } = splitConfig(html);
  return before + json.slice(0, 1) + '#corrupted#' + json.slice(1) + after; // not JSON any more
}

// A screenshot of the page clipped to the 3D canvas (quicker than an element screenshot,
// which waits for the element to be stable).
async function canvasShot(page, shotsDir, name) {
  const box = await page.locator('#view canvas').boundingBox();
  if (!box) throw new Error('the 3D canvas is not laid out');
  const buf = await page.screenshot({ clip: box, animations: 'allow', timeout: 20000 });
  if (shotsDir) writeFileSync(join(shotsDir, `${name}.png`), buf);
  return decodePng(buf);
}

// What the "canvas changes" and "frame advanced" checks measure, the same for the
// positive check and its negative control: two canvas shots 1 s apart, and the frame
// index sampled every 50 ms between them. Playback loops, and a 1 s run's loop lasts
// about 1 s, so the index at the two ends alone can be the same frame after a whole
// loop (CI at stop 27: frame 0 -> 0 while the canvas changed). `advanced` counts the
// changes of the index seen between the shots.
async function twoShotsApart(page, shotsDir, name) {
  const before = await hooks(page);
  const a = await canvasShot(page, shotsDir, `${name}_a`);
  let advanced = 0;
  let seen = before.frame;
  const until = Date.now() + 1000;
  while (Date.now() < until) {
    await sleep(50);
    const f = (await hooks(page)).frame;
    if (f !== seen) advanced += 1;
    seen = f;
  }
  const b = await canvasShot(page, shotsDir, `${name}_b`);
  const after = await hooks(page);
  if (after.frame !== seen) advanced += 1;
  return { before, after, changed: diffPixels(a, b), advanced };
}

async function hooks(page) {
  return page.evaluate(() => {
    const t = window.tissuebench;
    return t ? { mode: t.mode, frame: t.frame, frames: t.frames, playing: t.playing, t: t.t, errors: [...t.errors] } : null;
  });
}

function errorCheck(watch, tbState) {
  const all = [
    ...watch.consoleErrors.map((e) => `console: ${e}`),
    ...watch.pageErrors.map((e) => `page error: ${e}`),
    ...((tbState && tbState.errors) || []).map((e) => `tissuebench.errors: ${e}`),
  ];
  if (!tbState) all.push('window.tissuebench is missing');
  return { pass: all.length === 0, detail: all.length ? all.slice(0, 4).join(' | ') + (all.length > 4 ? ` (+${all.length - 4})` : '') : 'none' };
}

async function webglInfo(page) {
  return page.evaluate(() => {
    const c = document.querySelector('#view canvas');
    const gl = c && (c.getContext('webgl2') || c.getContext('webgl'));
    if (!gl) return 'no WebGL context';
    const ext = gl.getExtension('WEBGL_debug_renderer_info');
    return ext ? gl.getParameter(ext.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
  });
}

async function main() {
  let args;
  try {
    args = parseArgs(process.argv.slice(2), { page: 'value', shots: 'value', chromium: 'value' });
  } catch (e) {
    usage(e.message);
  }
  if (!args.page) usage('give --page');

  const work = mkdtempSync(join(tmpdir(), 'tb-view-test-'));
  const shotsDir = args.shots ? resolve(args.shots) : null;
  if (shotsDir) mkdirSync(shotsDir, { recursive: true });
  const pagePath = resolve(args.page);
  const html = readFileSync(pagePath, 'utf8');
  const zero = zeroFramePage(html);
  const zeroPath = join(work, 'zero_frames.html');
  writeFileSync(zeroPath, zero.html);
  const corruptPath = join(work, 'corrupt_config.html');
  writeFileSync(corruptPath, corruptPage(html));

  const checks = new Checks();
  const browser = await launch({ executablePath: args.chromium });
  try {
    // --- The page as given ---------------------------------------------------------------
    const page = await browser.context.newPage();
    const watch = watchPage(page);
    await page.goto(pathToFileURL(pagePath).href, { waitUntil: 'load', timeout: 60000 });
    let loaded = true;
    try {
      await page.waitForFunction(() => window.tissuebench && window.tissuebench.frames > 1, null, { timeout: 60000 });
    } catch (_) {
      loaded = false;
    }
    let st = await hooks(page);
    checks.record('page loads in run mode with frames > 1', loaded && st && st.mode === 'run',
      st ? `mode ${st.mode}, ${st.frames} frames` : 'window.tissuebench missing');
    if (!loaded) throw new Error('the page did not load; later checks would be meaningless');

    const renderer = await webglInfo(page);
    await sleep(300);
    const first = await canvasShot(page, shotsDir, 'playing_0');
    const cs = colourStats(first);
    checks.record('WebGL renders: canvas not blank',
      cs.distinct >= MIN_DISTINCT_COLOURS && cs.nonBackgroundShare >= MIN_NON_BACKGROUND,
      `${first.width}×${first.height}, ${cs.distinct} colours, ${(100 * cs.nonBackgroundShare).toFixed(1)}% off background; renderer: ${renderer}`);

    if (!(await hooks(page)).playing) await page.click('#play');
    await page.waitForFunction(() => window.tissuebench.playing === true, null, { timeout: 5000 }).catch(() => {});
    st = await hooks(page);
    checks.record('playback is on', st.playing === true, `playing=${st.playing}`);

    // From the first frame (the scrubber, as a user would): runs move most early on.
    await page.locator('#scrubber').fill('0');
    const play = await twoShotsApart(page, shotsDir, 'playing');
    const [a, b] = [play.before, play.after];
    checks.record('canvas changes while playing (1 s apart)', play.changed > MIN_CHANGED_PIXELS, `${play.changed} pixels differ (need > ${MIN_CHANGED_PIXELS})`);
    checks.record('frame index advanced', play.advanced > 0, `frame ${a.frame} -> ${b.frame} of ${b.frames} (t ${a.t?.toFixed(2)} -> ${b.t?.toFixed(2)} s), ${play.advanced} changes seen`);

    const ec = errorCheck(watch, await hooks(page));
    checks.record('no console error, page error or tissuebench.errors', ec.pass, ec.detail);

    // --- Negative control (a): paused, the same "canvas changes" check must fail ----------
    await page.click('#play');
    await page.waitForFunction(() => window.tissuebench.playing === false, null, { timeout: 5000 }).catch(() => {});
    await sleep(300);
    const paused = await twoShotsApart(page, shotsDir, 'paused');
    const [p0, p1] = [paused.before, paused.after];
    checks.record('paused (clicked pause): canvas changes', paused.changed > MIN_CHANGED_PIXELS,
      `${paused.changed} pixels differ; playing=${p1.playing}; frame ${p0.frame} -> ${p1.frame}`, { negative: true });
    checks.record('paused (clicked pause): frame index advanced', paused.advanced > 0,
      `frame ${p0.frame} -> ${p1.frame}, ${paused.advanced} changes seen`, { negative: true });
    await page.close();

    // --- Zero frames (a run that failed at once): rest geometry and the banner ------------
    const zpage = await browser.context.newPage();
    const zwatch = watchPage(zpage);
    await zpage.goto(pathToFileURL(zeroPath).href, { waitUntil: 'load', timeout: 60000 });
    await zpage.waitForFunction(() => window.tissuebench && window.tissuebench.mode === 'run', null, { timeout: 30000 }).catch(() => {});
    await sleep(500);
    const zst = await hooks(zpage);
    const zshot = await canvasShot(zpage, shotsDir, 'zero_frames');
    const zcs = colourStats(zshot);
    const banner = await zpage.evaluate(() => {
      const el = document.getElementById('banner');
      return el && !el.hidden && el.offsetHeight > 0 ? el.textContent : null;
    });
    checks.record('zero frames: rest geometry drawn, tissuebench.frames = 0',
      zst && zst.frames === 0 && zcs.distinct >= MIN_DISTINCT_COLOURS && zcs.nonBackgroundShare >= MIN_NON_BACKGROUND,
      `frames=${zst && zst.frames}, ${zcs.distinct} colours, ${(100 * zcs.nonBackgroundShare).toFixed(1)}% off background`);
    checks.record('zero frames: failure banner shown', !!banner && banner.includes(zero.failure), banner ? JSON.stringify(banner.slice(0, 100)) : 'no visible banner');
    const zec = errorCheck(zwatch, zst);
    checks.record('zero frames: no errors', zec.pass, zec.detail);
    await zpage.close();

    // --- Negative control (b): corrupted config JSON, the error check must fail -----------
    const cpage = await browser.context.newPage();
    const cwatch = watchPage(cpage);
    await cpage.goto(pathToFileURL(corruptPath).href, { waitUntil: 'load', timeout: 60000 });
    await cpage.waitForFunction(() => window.tissuebench && window.tissuebench.errors.length > 0, null, { timeout: 10000 }).catch(() => {});
    await sleep(300);
    const cec = errorCheck(cwatch, await hooks(cpage));
    checks.record('corrupted config JSON: no errors', cec.pass, cec.detail, { negative: true });
    await cpage.close();
  } catch (e) {
    checks.record('test ran to the end', false, e.stack || String(e));
  } finally {
    await browser.close();
    rmSync(work, { recursive: true, force: true });
  }
  checks.summary();
  process.exit(checks.ok ? 0 : 1);
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
