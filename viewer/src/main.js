/*! uPlot v1.6.32 | Copyright (c) 2025 Leon Sorokin | MIT License | https://github.com/leeoniya/uPlot
 * (restated here: uPlot's own header is not kept by esbuild's legal-comment rules) */
// The tissuebench viewer: one bundle, two modes (viewer/README.md).
// Reads <script id="tissuebench-config" type="application/json"> on DOMContentLoaded.
import uplotCss from 'uplot/dist/uPlot.min.css' with { type: 'text' };
import { tb, installHooks, reportError, setLogSink } from './hooks.js';
import { View3D } from './view3d.js';
import { startRun } from './run.js';
import { startLive } from './live.js';

installHooks();

const MAX_LOG_LINES = 60;

function $(id) {
  const el = document.getElementById(id);
  if (!el) throw new Error(`the page has no #${id}`);
  return el;
}

function makeUi() {
  const ui = {
    title: $('title'), subtitle: $('subtitle'), status: $('status'), conn: $('conn'), banner: $('banner'),
    note: $('view-note'), view: $('view'), play: $('play'), scrubber: $('scrubber'), speed: $('speed'),
    time: $('time'), liveControls: $('live-controls'), reset: $('reset'), knee: $('knee-readout'),
    speedReadout: $('speed-readout'), slowWarning: $('slow-warning'), fit: $('fit'), plot: $('plot'),
    columns: $('columns'), logEl: $('log'),
    onTogglePlay: null, onStep: null, onFit: null,
  };
  ui.setTitle = (title, sub) => {
    ui.title.textContent = title;
    ui.subtitle.textContent = sub || '';
    document.title = `${title} — tissuebench`;
  };
  ui.showBanner = (text) => {
    ui.banner.textContent = text;
    ui.banner.hidden = false;
  };
  let flashTimer = null;
  ui.flashBanner = (text) => {
    ui.showBanner(text);
    clearTimeout(flashTimer);
    flashTimer = setTimeout(() => { ui.banner.hidden = true; }, 8000);
  };
  ui.showNote = (text) => {
    ui.note.textContent = text;
    ui.note.hidden = false;
  };
  ui.log = (text, cls = 'error') => {
    const lastLine = ui.logEl.lastElementChild;
    if (lastLine && lastLine.dataset.text === text) {
      // The same message again (e.g. a simulation that fails at every restart): count it.
      const n = Number(lastLine.dataset.count) + 1;
      lastLine.dataset.count = String(n);
      lastLine.textContent = `${new Date().toLocaleTimeString()}  ${text}  (×${n})`;
      return;
    }
    const line = document.createElement('div');
    line.className = cls;
    line.dataset.text = text;
    line.dataset.count = '1';
    line.textContent = `${new Date().toLocaleTimeString()}  ${text}`;
    ui.logEl.append(line);
    while (ui.logEl.childElementCount > MAX_LOG_LINES) ui.logEl.firstElementChild.remove();
    ui.logEl.hidden = false;
    ui.logEl.scrollTop = ui.logEl.scrollHeight;
  };
  return ui;
}

function readConfig() {
  const el = document.getElementById('tissuebench-config');
  if (!el) throw new Error('the page has no tissuebench-config script element');
  let config;
  try {
    config = JSON.parse(el.textContent);
  } catch (e) {
    throw new Error(`the page's config is not valid JSON (${e.message})`);
  }
  if (!config || typeof config !== 'object' || Array.isArray(config)) throw new Error('the page config is not a JSON object');
  if (config.mode !== 'run' && config.mode !== 'live') throw new Error(`unknown config mode ${JSON.stringify(config.mode)}`);
  return config;
}

function installKeys(ui, view) {
  const typing = (el) => el && (el.tagName === 'SELECT' || el.tagName === 'TEXTAREA' ||
    (el.tagName === 'INPUT' && !['range', 'checkbox', 'button'].includes(el.type)));
  document.addEventListener('keydown', (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey || typing(e.target)) return;
    if (e.code === 'Space' || e.key === ' ') {
      e.preventDefault();
      if (!e.repeat && ui.onTogglePlay) ui.onTogglePlay();
    } else if ((e.key === 'ArrowRight' || e.key === 'ArrowLeft') && e.target && e.target.type !== 'range' && ui.onStep) {
      e.preventDefault();
      ui.onStep(e.key === 'ArrowRight' ? 1 : -1);
    } else if (e.key === 'f' || e.key === 'F') {
      ui.fit.click();
    }
  });
  // A focused button or checkbox would also "click" on the space key's release: space is
  // play/pause only.
  document.addEventListener('keyup', (e) => {
    if ((e.code === 'Space' || e.key === ' ') && !typing(e.target)) e.preventDefault();
  });
  ui.fit.addEventListener('click', () => {
    if (ui.onFit) ui.onFit();
    else view.fit();
  });
}

function start() {
  let ui = null;
  try {
    const style = document.createElement('style');
    style.textContent = uplotCss;
    document.head.prepend(style); // before the page's own style, which overrides it
    ui = makeUi();
    setLogSink((text, cls) => ui.log(text, cls));
  } catch (e) {
    reportError('page', e);
    return;
  }
  let config;
  try {
    config = readConfig();
  } catch (e) {
    document.body.className = 'mode-run';
    ui.showBanner(`Viewer error: ${e.message}`);
    reportError('config', e);
    return;
  }
  tb.mode = config.mode;
  document.body.className = `mode-${config.mode}`;
  let view;
  try {
    view = new View3D(ui.view);
  } catch (e) {
    ui.showBanner(`Viewer error: WebGL is not available (${e.message || e})`);
    reportError('WebGL', e);
    return;
  }
  installKeys(ui, view);
  try {
    if (config.mode === 'run') startRun(ui, view, config.run);
    else startLive(ui, view, config);
  } catch (e) {
    ui.showBanner(`Viewer error: ${e.message || e}`);
    reportError(config.mode, e);
  }
}

if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start, { once: true });
else start();
