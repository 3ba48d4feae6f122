// Live mode: frames streamed over a WebSocket while the scene runs (viewer/README.md, "Live protocol").
import { Box3 } from 'three';
import { tb, reportError } from './hooks.js';
import { decodeMeshBase, decodeTyped } from './decode.js';
import { Plot } from './plot.js';

const SEND_INTERVAL_MS = 50;   // at most 20 messages a second
const PLOT_WINDOW_S = 10;

function fmtValue(v, step) {
  if (!Number.isFinite(v)) return '–';
  const decimals = step > 0 && step < 1 ? Math.min(4, Math.ceil(-Math.log10(step) - 1e-9)) : Math.abs(v) < 10 ? 2 : 1;
  return v.toFixed(decimals);
}

const PREFERRED_PLOTS = ['knee_angle', 'back_activation', 'front_activation', 'knee_torque'];

function defaultPlotColumns(columns) {
  const names = columns.map((c) => c.name);
  if (names.length <= 4) return names;
  const preferred = PREFERRED_PLOTS.filter((n) => names.includes(n));
  return preferred.length ? preferred : names.slice(0, 4);
}

// "1" is the unit of a plain number: not worth showing next to a value.
const shownUnit = (unit) => (unit && unit !== '1' ? unit : '');

export function startLive(ui, view, config) {
  const path = typeof config.ws === 'string' && config.ws ? config.ws : '/ws';
  if (!path.startsWith('/')) throw new Error(`config "ws" must be a path starting with "/": ${JSON.stringify(config.ws)}`);
  const url = (location.protocol === 'https:' ? 'wss:' : 'ws:') + '//' + location.host + path;

  let ws = null;
  let retryMs = 1000;
  let meshes = [];           // [{entry, V}] in hello order
  let controls = [];         // hello controls, with their input elements
  let plot = null;
  let fitted = false;
  const pending = new Map(); // control id -> value not sent yet
  let sendTimer = null;
  let lastSend = 0;

  tb.connected = false;
  tb.playing = false;
  ui.setTitle('live', url);

  function setConn(state) {
    ui.conn.textContent = state;
    ui.conn.className = `badge live-only ${state}`;
  }

  function send(obj) {
    if (!ws || ws.readyState !== WebSocket.OPEN) return false;
    ws.send(JSON.stringify(obj));
    return true;
  }

  // One message per SEND_INTERVAL_MS, the latest value of each control, round robin.
  function flush() {
    sendTimer = null;
    const first = pending.keys().next();
    if (first.done) return;
    const id = first.value;
    const value = pending.get(id);
    pending.delete(id);
    lastSend = performance.now();
    send({ type: 'set', id, value });
    if (pending.size) schedule();
  }
  function schedule() {
    if (sendTimer !== null) return;
    const wait = Math.max(0, lastSend + SEND_INTERVAL_MS - performance.now());
    sendTimer = setTimeout(flush, wait);
  }
  function queueSet(id, value) {
    pending.set(id, value);
    schedule();
  }

  function buildControls(list) {
    ui.liveControls.textContent = '';
    controls = [];
    for (const c of Array.isArray(list) ? list : []) {
      if (!c || typeof c.id !== 'string') {
        reportError('hello: a control without an id');
        continue;
      }
      const min = Number(c.min);
      const max = Number(c.max);
      if (!Number.isFinite(min) || !Number.isFinite(max) || !(max > min)) {
        reportError(`hello: control ${c.id} has no valid [min, max]`);
        continue;
      }
      const step = Number.isFinite(Number(c.step)) && Number(c.step) > 0 ? Number(c.step) : (max - min) / 1000;
      const initial = Number.isFinite(Number(c.value)) ? Math.min(max, Math.max(min, Number(c.value))) : min;
      const kind = c.kind === 'knob' ? 'knob' : 'slider';
      const unit = shownUnit(typeof c.unit === 'string' ? c.unit : '');

      const wrap = document.createElement('label');
      wrap.className = `ctl ${kind}`;
      wrap.title = `${c.id} [${min} … ${max}${unit ? ' ' + unit : ''}]`;
      const lbl = document.createElement('span');
      lbl.className = 'lbl';
      lbl.textContent = typeof c.label === 'string' && c.label ? c.label : c.id;
      const input = document.createElement('input');
      input.type = 'range';
      input.min = String(min);
      input.max = String(max);
      input.step = String(step);
      input.value = String(initial);
      input.dataset.controlId = c.id;
      input.dataset.kind = kind;
      input.setAttribute('aria-label', lbl.textContent);
      const val = document.createElement('span');
      val.className = 'val';
      const show = () => {
        val.textContent = `${fmtValue(Number(input.value), step)}${unit ? ' ' + unit : ''}`;
      };
      show();
      input.addEventListener('input', () => {
        show();
        queueSet(c.id, Number(input.value));
      });
      lbl.title = 'double-click: back to ' + initial + (unit ? ' ' + unit : '');
      lbl.addEventListener('dblclick', (e) => {
        e.preventDefault();
        input.value = String(initial);
        show();
        queueSet(c.id, Number(input.value));
      });
      wrap.append(lbl, input, val);
      ui.liveControls.append(wrap);
      controls.push({ id: c.id, initial, input, show });
    }
  }

  function onHello(msg) {
    view.clearMeshes();
    meshes = [];
    (Array.isArray(msg.meshes) ? msg.meshes : []).forEach((m, i) => {
      try {
        const base = decodeMeshBase(m, i);
        meshes.push({ entry: view.addMesh(base), V: base.V, name: base.name });
      } catch (e) {
        reportError('hello', e);
        meshes.push(null);
      }
    });
    if (!fitted) {
      // The rest box, widened behind (-x) and a little in front: the lower leg swings when
      // the knee flexes. "Fit view" frames the current geometry.
      const box = view.currentBox();
      if (!box.isEmpty()) {
        const h = box.max.z - box.min.z;
        const b = new Box3(box.min.clone(), box.max.clone());
        b.min.x -= 0.5 * h;
        b.max.x += 0.15 * h;
        view.fit(b);
        fitted = true;
      }
    }
    buildControls(msg.controls);
    const columns = (Array.isArray(msg.series) ? msg.series : [])
      .filter((s) => s && typeof s.name === 'string')
      .map((s) => ({ name: s.name, unit: typeof s.unit === 'string' ? s.unit : '' }));
    if (plot) plot.destroy();
    ui.plot.textContent = '';
    plot = new Plot(ui.plot, ui.columns, { columns, selected: defaultPlotColumns(columns), live: true });
    ui.setTitle(typeof msg.scene === 'string' && msg.scene ? `${msg.scene} (live)` : 'live', url);
    tb.frames = 0;
    tb.frame = -1;
  }

  function onFrame(msg) {
    const positions = Array.isArray(msg.positions) ? msg.positions : [];
    positions.forEach((p, i) => {
      if (!p || typeof p !== 'object') return;
      let m = meshes.find((x) => x && x.name === p.name);
      if (!m && p.name === undefined) m = meshes[i];
      if (!m) {
        reportError(`frame: positions for unknown mesh ${JSON.stringify(p.name)}`);
        return;
      }
      try {
        const pos = decodeTyped(p.b64, Float32Array, m.V * 3, `frame: mesh ${m.name} positions`);
        m.entry.position.set(pos);
        view.updated(m.entry);
      } catch (e) {
        reportError('frame', e);
      }
    });
    const t = Number(msg.t);
    tb.frames += 1;
    tb.frame = tb.frames - 1;
    tb.t = Number.isFinite(t) ? t : null;
    const knee = Number(msg.knee_angle);
    tb.knee_angle = Number.isFinite(knee) ? knee : null;
    const rtf = Number(msg.real_time_factor);
    tb.real_time_factor = Number.isFinite(rtf) ? rtf : null;
    ui.knee.textContent = `knee: ${tb.knee_angle == null ? '–' : tb.knee_angle.toFixed(1)}°`;
    ui.speedReadout.textContent = `speed: ${tb.real_time_factor == null ? '–' : tb.real_time_factor.toFixed(2)}× real time`;
    ui.slowWarning.hidden = msg.slower_than_real_time !== true;
    if (plot && Number.isFinite(t)) plot.push(t, msg.values && typeof msg.values === 'object' ? msg.values : {}, PLOT_WINDOW_S);
  }

  function onMessage(ev) {
    if (typeof ev.data !== 'string') {
      reportError('WebSocket: a binary message (the protocol is JSON text)');
      return;
    }
    let msg;
    try {
      msg = JSON.parse(ev.data);
    } catch (e) {
      reportError('WebSocket: a message that is not JSON', e);
      return;
    }
    if (!msg || typeof msg !== 'object') {
      reportError('WebSocket: a message that is not an object');
      return;
    }
    switch (msg.type) {
      case 'hello':
        if (msg.format !== 'tissuebench-live/1') reportError(`hello: format ${JSON.stringify(msg.format)}, expected "tissuebench-live/1"`);
        onHello(msg);
        break;
      case 'frame':
        onFrame(msg);
        break;
      case 'error':
        // The server refused something this page sent: a page bug, so it counts as an error.
        reportError(`server refused a message from the page: ${msg.message}`);
        break;
      case 'status':
        ui.log(`status: ${msg.message}`, msg.failed ? 'error' : 'info');
        if (msg.failed) ui.flashBanner(`Simulation: ${msg.message}`);
        break;
      default:
        reportError(`WebSocket: unknown message type ${JSON.stringify(msg.type)}`);
    }
  }

  function connect() {
    setConn('connecting');
    try {
      ws = new WebSocket(url);
    } catch (e) {
      reportError(`WebSocket ${url}`, e);
      setTimeout(connect, retryMs);
      retryMs = Math.min(10000, retryMs * 2);
      return;
    }
    ws.onopen = () => {
      retryMs = 1000;
      tb.connected = true;
      tb.playing = true;
      setConn('connected');
      ui.log(`connected to ${url}`, 'info');
    };
    ws.onmessage = onMessage;
    ws.onerror = () => reportError(`WebSocket error (${url})`);
    ws.onclose = (ev) => {
      const was = tb.connected;
      tb.connected = false;
      tb.playing = false;
      setConn('disconnected');
      if (was) ui.log(`disconnected (code ${ev.code})`, 'info');
      setTimeout(connect, retryMs);
      retryMs = Math.min(10000, retryMs * 2);
    };
  }

  // Reset: the scene back to its start; the controls keep their values (the server's rule).
  ui.reset.addEventListener('click', () => {
    send({ type: 'reset' });
    if (plot) plot.clear();
  });
  ui.onFit = () => {
    const box = view.currentBox(); // the current positions
    if (!box.isEmpty()) view.fit(box);
  };
  connect();
}
