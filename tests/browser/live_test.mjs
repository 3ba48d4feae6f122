#!/usr/bin/env node
// Browser test of live mode (`tissuebench serve`), in headless Chromium.
//
//   node tests/browser/live_test.mjs --tissuebench PATH_TO_BINARY --scene SCENE.yaml [--shots DIR] [--chromium PATH]
//
// Starts `PATH_TO_BINARY serve SCENE.yaml --port 0`, reads the address it prints, opens the
// page, moves the back-muscle slider through the page's own input element and checks that the
// knee flexes; then sends hostile messages on a second WebSocket and checks that the server
// refuses each and keeps streaming. The server is killed at the end, and on failure.
// Exit 0 only when every check passes and the negative control is caught. See README.md.
import { spawn } from 'node:child_process';
import { mkdirSync, writeFileSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { launch, watchPage, Checks, sleep, parseArgs, decodePng, colourStats } from './lib.mjs';

const SLIDER_ID = 'activation.back_muscle';
const SLIDER_VALUE = '0.6';
const MOVED_DEG = 5;            // "the knee moved": more than this from its untouched value
const UNTOUCHED_S = 2;          // the untouched reading
const ACTIVE_S = 4;             // the wait after the slider moved (and the negative control's) ...
const ACTIVE_SIM_S = 1.0;       // ... and at least this much simulated time (the engine may run
const MAX_WAIT_S = 60;          //     far slower than real time), but never longer than this
const START_TIMEOUT_MS = 120000;

function usage(msg) {
  if (msg) console.error(`live_test: ${msg}`);
  console.error('usage: live_test.mjs --tissuebench PATH_TO_BINARY --scene SCENE.yaml [--shots DIR] [--chromium PATH]');
  process.exit(2);
}

// Starts the server; resolves with {child, url} once it printed its address.
function startServer(binary, scene, log) {
  const child = spawn(binary, ['serve', scene, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
  return new Promise((resolveStart, rejectStart) => {
    let out = '';
    const timer = setTimeout(() => rejectStart(new Error(`no address printed within ${START_TIMEOUT_MS / 1000} s; output: ${out.slice(-500)}`)), START_TIMEOUT_MS);
    const onData = (chunk) => {
      const text = chunk.toString();
      out += text;
      log.push(text);
      const m = out.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
      if (m) {
        clearTimeout(timer);
        resolveStart({ child, url: `http://127.0.0.1:${m[1]}/` });
      }
    };
    child.stdout.on('data', onData);
    child.stderr.on('data', (c) => log.push(c.toString()));
    child.on('error', (e) => {
      clearTimeout(timer);
      rejectStart(e);
    });
    child.on('exit', (code, signal) => {
      clearTimeout(timer);
      rejectStart(new Error(`the server exited (code ${code}, signal ${signal}) before printing its address; output: ${out.slice(-500)}`));
    });
  });
}

async function stopServer(child) {
  if (!child || child.exitCode !== null || child.signalCode !== null) return;
  const exited = new Promise((r) => child.once('exit', r));
  child.kill('SIGTERM');
  const done = await Promise.race([exited.then(() => true), sleep(5000).then(() => false)]);
  if (!done) {
    child.kill('SIGKILL');
    await Promise.race([exited, sleep(2000)]);
  }
}

async function hooks(page) {
  return page.evaluate(() => {
    const t = window.tissuebench;
    return t ? { mode: t.mode, frames: t.frames, t: t.t, knee_angle: t.knee_angle, real_time_factor: t.real_time_factor,
      connected: t.connected, errors: [...t.errors] } : null;
  });
}

// Samples tissuebench.knee_angle every 100 ms for `seconds` of wall time and, when `simSeconds`
// is given, until the simulation advanced that much (time going back, a reset, counts nothing),
// at most MAX_WAIT_S. The samples carry the wall and simulated time covered.
async function sampleKnee(page, seconds, simSeconds = 0) {
  const out = [];
  const start = Date.now();
  let sim = 0;
  let lastT = null;
  for (;;) {
    const [k, t] = await page.evaluate(() => [window.tissuebench.knee_angle, window.tissuebench.t]);
    if (typeof k === 'number' && Number.isFinite(k)) out.push(k);
    if (typeof t === 'number' && Number.isFinite(t)) {
      if (lastT !== null && t > lastT) sim += t - lastT;
      lastT = t;
    }
    const wall = (Date.now() - start) / 1000;
    if ((wall >= seconds && sim >= simSeconds) || wall >= MAX_WAIT_S) break;
    await sleep(100);
  }
  out.sim = sim;
  out.wall = (Date.now() - start) / 1000;
  return out;
}

// The check under test: did the knee move more than MOVED_DEG from `baseline`?
function moved(baseline, samples) {
  const maxDev = samples.reduce((m, k) => Math.max(m, Math.abs(k - baseline)), 0);
  return { pass: samples.length > 0 && maxDev > MOVED_DEG, maxDev };
}

const fmt = (x) => (typeof x === 'number' && Number.isFinite(x) ? x.toFixed(2) : String(x));

async function main() {
  let args;
  try {
    args = parseArgs(process.argv.slice(2), { tissuebench: 'value', scene: 'value', shots: 'value', chromium: 'value' });
  } catch (e) {
    usage(e.message);
  }
  if (!args.tissuebench || !args.scene) usage('--tissuebench and --scene are required');
  const shotsDir = args.shots ? resolve(args.shots) : null;
  if (shotsDir) mkdirSync(shotsDir, { recursive: true });

  const checks = new Checks();
  const serverLog = [];
  let server = null;
  let browser = null;
  const killOnExit = () => {
    if (server && server.child.exitCode === null) server.child.kill('SIGKILL');
  };
  process.on('exit', killOnExit);
  for (const sig of ['SIGINT', 'SIGTERM']) process.on(sig, () => { killOnExit(); process.exit(130); });

  try {
    server = await startServer(resolve(args.tissuebench), resolve(args.scene), serverLog);
    checks.record('server started and printed its address', true, server.url);

    browser = await launch({ executablePath: args.chromium });
    const page = await browser.context.newPage();
    const watch = watchPage(page);
    await page.goto(server.url, { waitUntil: 'load', timeout: 30000 });
    let ready = true;
    try {
      await page.waitForFunction(() => window.tissuebench && window.tissuebench.connected && window.tissuebench.frames >= 10,
        null, { timeout: 90000 });
    } catch (_) {
      ready = false;
    }
    let st = await hooks(page);
    checks.record('page in live mode, connected, >= 10 frames', ready && st && st.mode === 'live',
      st ? `mode ${st.mode}, connected ${st.connected}, ${st.frames} frames, t ${fmt(st.t)} s` : 'window.tissuebench missing');
    if (!ready) throw new Error('the page never got connected with frames; later checks would be meaningless');

    const shot = decodePng(await page.locator('#view canvas').screenshot());
    const cs = colourStats(shot);
    checks.record('WebGL renders the leg: canvas not blank', cs.distinct >= 16 && cs.nonBackgroundShare >= 0.01,
      `${cs.distinct} colours, ${(100 * cs.nonBackgroundShare).toFixed(1)}% off background`);
    if (shotsDir) writeFileSync(join(shotsDir, 'live_untouched.png'), await page.screenshot());

    // Untouched: the baseline, then the negative control over as long as the active wait.
    const untouched = await sampleKnee(page, UNTOUCHED_S);
    const baseline = untouched.length ? untouched[untouched.length - 1] : NaN;
    checks.record(`knee angle read over ${UNTOUCHED_S} s, controls untouched`, untouched.length >= 5 && Number.isFinite(baseline),
      `${untouched.length} samples, ${fmt(Math.min(...untouched))} … ${fmt(Math.max(...untouched))} deg, baseline ${fmt(baseline)} deg`);
    const still = await sampleKnee(page, ACTIVE_S, ACTIVE_SIM_S);
    const neg = moved(baseline, still);
    checks.record(`no slider change: knee moved > ${MOVED_DEG} deg`, neg.pass,
      `max |change| ${fmt(neg.maxDev)} deg over ${fmt(still.wall)} s (${fmt(still.sim)} s simulated)`, { negative: true });
    const baseline2 = still.length ? still[still.length - 1] : baseline;

    // The slider, through the page's own input element.
    const slider = page.locator(`input[data-control-id="${SLIDER_ID}"]`);
    const found = (await slider.count()) === 1;
    checks.record(`the page has the ${SLIDER_ID} slider`, found, found ? 'input[type=range] built from the hello' : 'not found');
    if (!found) throw new Error('no slider');
    // 0.6: the hamstrings scene's own script reaches 0.65 at 2 s; held at full
    // activation the back muscle blows that scene up (leg/include/leg/live.hpp).
    await slider.fill(SLIDER_VALUE);
    const shown = await slider.inputValue();
    checks.record(`${SLIDER_ID} set to ${SLIDER_VALUE} through the UI`, Number(shown) === Number(SLIDER_VALUE), `value ${shown}`);
    const active = await sampleKnee(page, ACTIVE_S, ACTIVE_SIM_S);
    const pos = moved(baseline2, active);
    checks.record(`slider at ${SLIDER_VALUE}: knee moved > ${MOVED_DEG} deg`, pos.pass,
      `baseline ${fmt(baseline2)} deg, last ${fmt(active[active.length - 1])} deg, max |change| ${fmt(pos.maxDev)} deg ` +
      `over ${fmt(active.wall)} s (${fmt(active.sim)} s simulated)`);
    if (shotsDir) writeFileSync(join(shotsDir, 'live_flexed.png'), await page.screenshot());

    const readout = await page.evaluate(() => {
      const el = document.getElementById('speed-readout');
      const warn = document.getElementById('slow-warning');
      return {
        text: el ? el.textContent : null,
        visible: !!el && el.offsetParent !== null && el.offsetHeight > 0,
        warning: !!warn && !warn.hidden && warn.offsetHeight > 0,
        rtf: window.tissuebench.real_time_factor,
      };
    });
    checks.record('speed readout shown', readout.visible && /^speed: \d+(\.\d+)?× real time$/.test(readout.text || ''),
      `${JSON.stringify(readout.text)}; slower-than-real-time warning ${readout.warning ? 'shown' : 'hidden'} (real_time_factor ${fmt(readout.rtf)})`);

    // Hostile messages on a second WebSocket from the page's context (same origin).
    const hostile = await page.evaluate(async () => {
      const ws = new WebSocket(`ws://${location.host}/ws`);
      const got = { errors: [], frames: 0, hello: false, closed: false };
      ws.onmessage = (e) => {
        let m;
        try { m = JSON.parse(e.data); } catch (_) { return; }
        if (m.type === 'error') got.errors.push(String(m.message));
        else if (m.type === 'frame') got.frames++;
        else if (m.type === 'hello') got.hello = true;
      };
      ws.onclose = () => { got.closed = true; };
      await new Promise((res, rej) => {
        ws.onopen = res;
        ws.onerror = () => rej(new Error('the second WebSocket failed to open'));
      });
      window.__hostile = { ws, got };
      const messages = [
        'this is not JSON {',
        JSON.stringify({ type: 'set', id: 'no.such.control', value: 0.5 }),
        JSON.stringify({ type: 'set', id: 'activation.back_muscle', value: 1e308 }),
        JSON.stringify({ type: 'set', id: 'activation.back_muscle', value: 0.5, pad: 'x'.repeat(10 * 1024) }),
      ];
      for (const m of messages) ws.send(m);
      return { sent: messages.length, sizes: messages.map((m) => m.length) };
    });
    await page.waitForFunction((n) => window.__hostile.got.errors.length >= n, hostile.sent, { timeout: 5000 }).catch(() => {});
    const framesBefore = (await hooks(page)).frames;
    const hostileFramesBefore = await page.evaluate(() => window.__hostile.got.frames);
    await sleep(2000);
    const after = await page.evaluate(() => ({ ...window.__hostile.got, errors: [...window.__hostile.got.errors] }));
    st = await hooks(page);
    checks.record('hostile messages: each answered with an error message', after.errors.length >= hostile.sent,
      `${after.errors.length} errors for ${hostile.sent} messages (sizes ${hostile.sizes.join(', ')} bytes): ${after.errors.map((e) => JSON.stringify(e.slice(0, 70))).join('; ')}`);
    checks.record('frames keep coming after the hostile messages', st.connected && st.frames > framesBefore + 10 &&
      after.frames > hostileFramesBefore && !after.closed && Number.isFinite(st.knee_angle),
      `page: ${framesBefore} -> ${st.frames} frames in 2 s, connected ${st.connected}, knee ${fmt(st.knee_angle)} deg; ` +
      `second socket: ${after.frames - hostileFramesBefore} frames, ${after.closed ? 'closed' : 'open'}`);
    await page.evaluate(() => window.__hostile.ws.close());

    const all = [...watch.consoleErrors.map((e) => `console: ${e}`), ...watch.pageErrors.map((e) => `page error: ${e}`),
      ...st.errors.map((e) => `tissuebench.errors: ${e}`)];
    checks.record('no console error, page error or tissuebench.errors on the page', all.length === 0,
      all.length ? all.slice(0, 4).join(' | ') : 'none');
  } catch (e) {
    checks.record('test ran to the end', false, e.stack || String(e));
  } finally {
    if (browser) await browser.close().catch(() => {});
    if (server) await stopServer(server.child);
  }
  if (!checks.ok && serverLog.length) console.log(`server output (last lines):\n${serverLog.join('').split('\n').slice(-15).join('\n')}`);
  checks.summary();
  process.exit(checks.ok ? 0 : 1);
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
