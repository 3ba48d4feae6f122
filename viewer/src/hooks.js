// window.tissuebench: the test hooks of viewer/README.md, kept up to date by the page.
const MAX_ERRORS = 200;

export const tb = {
  mode: null,
  frame: -1,            // index of the frame shown (-1: none, e.g. a run with zero frames)
  frames: 0,            // run mode: frame count; live mode: frames received since the last hello
  playing: false,
  t: null,              // time shown (s)
  knee_angle: null,     // deg: live mode the last reported; run mode the series' knee_angle at t
  real_time_factor: null,
  connected: false,
  errors: [],
};

let logSink = null;
export function setLogSink(fn) { logSink = fn; }

// Every caught error ends here: into tissuebench.errors, the console and the page's log.
export function reportError(what, err) {
  let text = String(what);
  if (err !== undefined && err !== null) {
    const detail = err && err.message ? err.message : String(err);
    text += ': ' + detail;
  }
  tb.errors.push(text);
  if (tb.errors.length > MAX_ERRORS) tb.errors.splice(0, tb.errors.length - MAX_ERRORS);
  console.error('tissuebench: ' + text);
  if (logSink) {
    try { logSink(text, 'error'); } catch (_) { /* the log must never throw */ }
  }
}

export function installHooks() {
  window.tissuebench = tb;
  window.addEventListener('error', (e) => {
    const where = e.filename ? ` (${e.filename.split('/').pop()}:${e.lineno}:${e.colno})` : '';
    reportError('uncaught error' + where, e.error || e.message);
  });
  window.addEventListener('unhandledrejection', (e) => {
    reportError('unhandled promise rejection', e.reason);
  });
}
