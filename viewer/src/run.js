// Run mode: plays a recorded leg run (viewer/README.md, "Run data").
import { Box3, Vector3 } from 'three';
import { tb, reportError } from './hooks.js';
import { decodeMeshBase, decodeDisplacement } from './decode.js';
import { Plot } from './plot.js';

const KNEE_COLUMN = 'knee_angle';

function lastAtOrBefore(times, t) {
  // index of the last times[i] <= t (0 if t is before the first)
  let lo = 0;
  let hi = times.length - 1;
  if (hi < 0) return -1;
  if (t < times[0]) return 0;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (times[mid] <= t) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

function checkTimes(raw, what) {
  if (raw === undefined) return [];
  if (!Array.isArray(raw)) throw new Error(`${what} is not an array`);
  const out = raw.map(Number);
  for (let i = 0; i < out.length; i++) {
    if (!Number.isFinite(out[i])) throw new Error(`${what}[${i}] is not a finite number`);
    if (i && out[i] < out[i - 1]) throw new Error(`${what} goes back in time at index ${i}`);
  }
  return out;
}

function fmtTime(t) {
  return t == null || !Number.isFinite(t) ? '–' : t.toFixed(2);
}

export function startRun(ui, view, run) {
  if (!run || typeof run !== 'object' || Array.isArray(run)) throw new Error('config "run" is missing or not an object');
  if (run.format !== 'tissuebench-view/1')
    reportError(`run data format is ${JSON.stringify(run.format)}, expected "tissuebench-view/1"`);

  const title = typeof run.title === 'string' && run.title ? run.title : run.scene || 'run';
  ui.setTitle(title, run.run_dir || '');
  const status = ['complete', 'failed', 'incomplete'].includes(run.status) ? run.status : String(run.status || 'unknown');
  ui.status.textContent = status;
  ui.status.className = `badge run-only ${status}`;

  let times = [];
  try {
    times = checkTimes(run.frame_times, 'frame_times');
  } catch (e) {
    reportError('run data', e);
  }
  const F = times.length;

  // Meshes: rest geometry always; frames when the displacement decodes.
  const meshes = [];
  (Array.isArray(run.meshes) ? run.meshes : []).forEach((m, i) => {
    let base;
    try {
      base = decodeMeshBase(m, i);
    } catch (e) {
      reportError('run data', e);
      return;
    }
    const entry = view.addMesh(base);
    let disp = null;
    let scale = 0;
    try {
      ({ disp, scale } = decodeDisplacement(m, base, F));
    } catch (e) {
      reportError('run data', e);
    }
    meshes.push({ entry, base, disp, scale });
  });
  if (!Array.isArray(run.meshes) || run.meshes.length === 0) reportError('run data has no meshes');

  // Frame the rest geometry and every frame's, so the moving leg stays in view.
  const box = view.currentBox();
  const v = new Vector3();
  for (const m of meshes) {
    if (!m.disp) continue;
    const { rest } = m.base;
    const n = rest.length;
    for (let f = 0; f < F; f++) {
      const off = f * n;
      const fb = new Box3();
      for (let i = 0; i < n; i += 3) {
        v.set(rest[i] + m.scale * m.disp[off + i], rest[i + 1] + m.scale * m.disp[off + i + 1], rest[i + 2] + m.scale * m.disp[off + i + 2]);
        fb.expandByPoint(v);
      }
      box.union(fb);
    }
  }
  view.fit(box);

  // Series and plot.
  const series = run.series && typeof run.series === 'object' ? run.series : {};
  let stime = [];
  try {
    stime = checkTimes(series.time, 'series.time');
  } catch (e) {
    reportError('run data', e);
  }
  const columns = [];
  const colValues = new Map();
  for (const c of Array.isArray(series.columns) ? series.columns : []) {
    if (!c || typeof c.name !== 'string') continue;
    const vals = Array.isArray(c.values) ? c.values.map((x) => (typeof x === 'number' && Number.isFinite(x) ? x : null)) : [];
    if (vals.length !== stime.length) {
      reportError(`series column ${c.name}: ${vals.length} values for ${stime.length} times`);
      continue;
    }
    columns.push({ name: c.name, unit: typeof c.unit === 'string' ? c.unit : '' });
    colValues.set(c.name, vals);
  }
  const plots = (Array.isArray(run.plots) ? run.plots : []).filter((n) => colValues.has(n));
  const plot = new Plot(ui.plot, ui.columns, {
    columns,
    selected: plots.length ? plots : columns.slice(0, 1).map((c) => c.name),
    onSeek: (t) => seekTime(t),
  });
  plot.setData(stime, colValues);
  const knee = colValues.get(KNEE_COLUMN) || null;

  // Playback.
  let frame = -1;
  let t = F ? times[0] : null;
  let playing = false;
  let speed = 1;
  let last = null;

  ui.scrubber.max = String(Math.max(0, F - 1));
  ui.scrubber.disabled = F < 2;
  ui.play.disabled = F < 2;

  const notes = [];
  if (F === 0) notes.push('no frames recorded: the rest geometry is shown');
  if (status !== 'complete') {
    const why = typeof run.failure === 'string' && run.failure ? run.failure
      : status === 'incomplete' ? 'the run did not finish (still running, killed or crashed)' : 'no reason recorded';
    ui.showBanner(`Run ${status}: ${why}` + (F === 0 ? '\n(no frames recorded: the rest geometry is shown)' : ''));
  } else if (notes.length) {
    ui.showNote(notes.join('; '));
  }

  function applyFrame(f) {
    if (f === frame || f < 0 || f >= F) return;
    frame = f;
    for (const m of meshes) {
      if (!m.disp) continue;
      const { rest } = m.base;
      const p = m.entry.position;
      const off = f * rest.length;
      const s = m.scale;
      for (let i = 0; i < rest.length; i++) p[i] = rest[i] + s * m.disp[off + i];
      view.updated(m.entry);
    }
    ui.scrubber.value = String(f);
  }

  function refresh() {
    const shownT = F && frame >= 0 ? times[frame] : null; // the time of the frame shown
    tb.frame = frame;
    tb.t = shownT;
    tb.playing = playing;
    if (knee && stime.length && shownT != null) {
      const k = knee[lastAtOrBefore(stime, shownT)];
      tb.knee_angle = k == null ? null : k;
    }
    const tEnd = F ? times[F - 1] : null;
    ui.time.textContent = F
      ? `t = ${fmtTime(shownT)} s / ${fmtTime(tEnd)} s · frame ${frame + 1}/${F}`
      : 't = – · no frames';
    ui.play.innerHTML = playing ? '&#10074;&#10074; Pause' : '&#9654; Play';
    ui.play.setAttribute('aria-pressed', playing ? 'true' : 'false');
    plot.setCursor(F ? times[Math.max(0, frame)] : null);
  }

  function seekFrame(f) {
    if (!F) return;
    f = Math.max(0, Math.min(F - 1, f | 0));
    t = times[f];
    applyFrame(f);
    refresh();
  }

  function seekTime(ts) {
    if (!F) return;
    t = Math.max(times[0], Math.min(times[F - 1], ts));
    applyFrame(lastAtOrBefore(times, t));
    refresh();
  }

  function setPlaying(p) {
    playing = !!p && F > 1;
    last = null;
    refresh();
  }

  view.onBeforeRender = (now) => {
    if (!playing) return;
    if (last === null) {
      last = now;
      return;
    }
    const dt = Math.min(0.25, Math.max(0, (now - last) / 1000));
    last = now;
    t += dt * speed;
    // Loop back to the start once the last frame has been shown for one frame interval.
    if (t > times[F - 1] + (times[F - 1] - times[F - 2])) t = times[0];
    const f = lastAtOrBefore(times, t);
    if (f !== frame) {
      applyFrame(f);
      refresh();
    }
  };

  ui.play.addEventListener('click', () => setPlaying(!playing));
  ui.scrubber.addEventListener('input', () => seekFrame(Number(ui.scrubber.value)));
  ui.speed.addEventListener('change', () => {
    const s = Number(ui.speed.value);
    speed = Number.isFinite(s) && s > 0 ? s : 1;
  });
  ui.onTogglePlay = () => setPlaying(!playing);
  ui.onStep = (d) => {
    if (!F) return;
    setPlaying(false);
    seekFrame(frame + d);
  };

  tb.frames = F;
  if (F) applyFrame(0);
  setPlaying(F > 1);
}
