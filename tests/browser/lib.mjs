// Shared helpers of the browser tests: Chromium launch, PNG decoding, pixel statistics, checks.
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname, resolve } from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
import { inflateSync } from 'node:zlib';

export const HERE = dirname(fileURLToPath(import.meta.url));
export const REPO = resolve(HERE, '..', '..');
export const VIEWER = join(REPO, 'viewer');

// playwright-core is a devDependency of viewer/ (npm ci there).
export function loadPlaywright() {
  const require = createRequire(join(VIEWER, 'package.json'));
  try {
    return require('playwright-core');
  } catch (e) {
    throw new Error(`playwright-core not found in ${VIEWER}/node_modules: run "npm ci" in viewer/ (${e.message})`);
  }
}

// Chromium flags: headless as root on a machine with no GPU and a closed network.
// SwiftShader (ANGLE's CPU Vulkan/GL backend) gives WebGL without a GPU.
export const CHROMIUM_ARGS = [
  '--no-sandbox',
  '--disable-gpu-sandbox',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--ignore-gpu-blocklist',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--disable-quic',
  '--no-first-run',
  '--disable-default-apps',
  '--disable-extensions',
  '--mute-audio',
];

export const VIEWPORT = { width: 900, height: 700 };

export async function launch({ executablePath = process.env.CHROMIUM || '/usr/bin/chromium' } = {}) {
  const { chromium } = loadPlaywright();
  const userDataDir = mkdtempSync(join(tmpdir(), 'tb-chromium-'));
  const context = await chromium.launchPersistentContext(userDataDir, {
    executablePath,
    headless: true,
    args: CHROMIUM_ARGS,
    viewport: VIEWPORT,
    deviceScaleFactor: 1,
    timeout: 60000,
  });
  const close = async () => {
    try {
      await context.close();
    } finally {
      rmSync(userDataDir, { recursive: true, force: true });
    }
  };
  return { context, close, userDataDir };
}

// Records console errors and page errors of a page.
export function watchPage(page) {
  const consoleErrors = [];
  const pageErrors = [];
  page.on('console', (msg) => {
    if (msg.type() === 'error') consoleErrors.push(msg.text());
  });
  page.on('pageerror', (err) => pageErrors.push(String(err && err.message ? err.message : err)));
  return { consoleErrors, pageErrors };
}

// Minimal PNG decoder (8-bit greyscale/RGB/RGBA, non-interlaced: what Chromium's screenshots are).
export function decodePng(buf) {
  const sig = [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a];
  for (let i = 0; i < 8; i++) if (buf[i] !== sig[i]) throw new Error('not a PNG');
  let pos = 8;
  let width = 0, height = 0, bitDepth = 0, colorType = 0, interlace = 0;
  const idat = [];
  while (pos < buf.length) {
    const len = buf.readUInt32BE(pos);
    const type = buf.toString('ascii', pos + 4, pos + 8);
    const data = buf.subarray(pos + 8, pos + 8 + len);
    if (type === 'IHDR') {
      width = data.readUInt32BE(0);
      height = data.readUInt32BE(4);
      bitDepth = data[8];
      colorType = data[9];
      interlace = data[12];
    } else if (type === 'IDAT') idat.push(data);
    else if (type === 'IEND') break;
    pos += 12 + len;
  }
  const channels = { 0: 1, 2: 3, 4: 2, 6: 4 }[colorType];
  if (bitDepth !== 8 || !channels || interlace !== 0)
    throw new Error(`unsupported PNG (bit depth ${bitDepth}, colour type ${colorType}, interlace ${interlace})`);
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const out = Buffer.alloc(width * height * 4);
  let prev = Buffer.alloc(stride);
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)];
    const line = Buffer.from(raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1)));
    for (let x = 0; x < stride; x++) {
      const a = x >= channels ? line[x - channels] : 0;
      const b = prev[x];
      const c = x >= channels ? prev[x - channels] : 0;
      let v = line[x];
      if (filter === 1) v += a;
      else if (filter === 2) v += b;
      else if (filter === 3) v += (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c;
        const pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        v += pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      line[x] = v & 0xff;
    }
    for (let x = 0; x < width; x++) {
      const o = (y * width + x) * 4;
      const i = x * channels;
      if (channels >= 3) {
        out[o] = line[i]; out[o + 1] = line[i + 1]; out[o + 2] = line[i + 2];
        out[o + 3] = channels === 4 ? line[i + 3] : 255;
      } else {
        out[o] = out[o + 1] = out[o + 2] = line[i];
        out[o + 3] = channels === 2 ? line[i + 1] : 255;
      }
    }
    prev = line;
  }
  return { width, height, rgba: out };
}

// Number of pixels whose largest channel difference exceeds `threshold`.
export function diffPixels(a, b, threshold = 24) {
  if (a.width !== b.width || a.height !== b.height) throw new Error('images differ in size');
  let n = 0;
  for (let i = 0; i < a.rgba.length; i += 4) {
    const d = Math.max(
      Math.abs(a.rgba[i] - b.rgba[i]),
      Math.abs(a.rgba[i + 1] - b.rgba[i + 1]),
      Math.abs(a.rgba[i + 2] - b.rgba[i + 2]),
    );
    if (d > threshold) n++;
  }
  return n;
}

// How far an image is from one colour: distinct colours (quantised) and the share of pixels
// that differ from the most common colour.
export function colourStats(img) {
  const counts = new Map();
  const px = img.width * img.height;
  for (let i = 0; i < img.rgba.length; i += 4) {
    const key = ((img.rgba[i] >> 3) << 10) | ((img.rgba[i + 1] >> 3) << 5) | (img.rgba[i + 2] >> 3);
    counts.set(key, (counts.get(key) || 0) + 1);
  }
  let top = 0;
  for (const c of counts.values()) top = Math.max(top, c);
  return { distinct: counts.size, nonBackgroundShare: 1 - top / px, pixels: px };
}

// A check list: each check prints one line; negative controls are checks that must fail.
export class Checks {
  constructor() {
    this.results = [];
  }
  record(name, pass, detail, { negative = false } = {}) {
    // For a negative control, `pass` is the result of the check under test, which must be false.
    const ok = negative ? !pass : !!pass;
    const label = negative
      ? `${ok ? 'PASS' : 'FAIL'}  [negative control] ${name}: the check ${pass ? 'passed (NOT caught)' : 'failed as it must (caught)'}`
      : `${ok ? 'PASS' : 'FAIL'}  ${name}`;
    console.log(`${label}${detail ? ' — ' + detail : ''}`);
    this.results.push({ name, ok, negative });
    return ok;
  }
  get ok() {
    return this.results.length > 0 && this.results.every((r) => r.ok);
  }
  summary() {
    const failed = this.results.filter((r) => !r.ok);
    console.log(`${this.results.length - failed.length}/${this.results.length} checks passed` +
      (failed.length ? `; failed: ${failed.map((r) => r.name).join(', ')}` : ''));
  }
}

export function sleep(ms) {
  return new Promise((r) => setTimeout(r, ms));
}

export function parseArgs(argv, spec) {
  const out = {};
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (!a.startsWith('--')) throw new Error(`unexpected argument ${a}`);
    const key = a.slice(2);
    if (!(key in spec)) throw new Error(`unknown option ${a}`);
    if (spec[key] === 'flag') out[key] = true;
    else {
      if (i + 1 >= argv.length) throw new Error(`${a} needs a value`);
      out[key] = argv[++i];
    }
  }
  return out;
}
