#!/usr/bin/env node
// A stand-in for `tissuebench serve`, for developing the live page and its browser test
// without the C++ program. It speaks the live protocol of viewer/README.md with a fake leg:
// a tube whose lower half turns about the knee axis, driven by the same control ids.
//
//   node viewer/tools/mock_serve.mjs serve SCENE.yaml [--port N] [--bind ADDR] [--slow]
//
// Prints "tissuebench serve (mock): http://127.0.0.1:PORT/" once listening. SCENE.yaml is
// only echoed. --slow reports slower_than_real_time. Needs viewer/dist/viewer.js.
// Nothing here is the product; the real server is apps/tissuebench/serve.cpp.
import { createServer } from 'node:http';
import { createHash } from 'node:crypto';
import { readFileSync } from 'node:fs';
import { dirname, join, basename } from 'node:path';
import { fileURLToPath } from 'node:url';
import { assemble } from './assemble.mjs';

const VIEWER = join(dirname(fileURLToPath(import.meta.url)), '..');
const MAX_MESSAGE = 4096;
const MAX_FRAME = 65536;
const KNEE_Z = 0.5;

// ---- fake leg: a tube from z = 0 (foot) to z = 0.93 (hip), knee at z = 0.5 ----------------
function makeTube() {
  const rings = 48, around = 28;
  const rest = [];
  const tris = [];
  for (let r = 0; r < rings; r++) {
    const z = (0.93 * r) / (rings - 1);
    const radius = z > KNEE_Z ? 0.055 + 0.03 * ((z - KNEE_Z) / 0.43) : 0.035 + 0.02 * Math.sin((Math.PI * z) / KNEE_Z);
    for (let a = 0; a < around; a++) {
      const phi = (2 * Math.PI * a) / around;
      rest.push(radius * Math.cos(phi), radius * Math.sin(phi), z);
    }
  }
  for (let r = 0; r + 1 < rings; r++) {
    for (let a = 0; a < around; a++) {
      const i = r * around + a, j = r * around + ((a + 1) % around);
      tris.push(i, j, i + around, j, j + around, i + around);
    }
  }
  return { rest: new Float32Array(rest), tris: new Uint32Array(tris) };
}

const b64 = (typed) => Buffer.from(typed.buffer, typed.byteOffset, typed.byteLength).toString('base64');

// ---- minimal WebSocket (RFC 6455) server side ---------------------------------------------
function wsAccept(req, socket, onMessage, onClose) {
  const key = req.headers['sec-websocket-key'];
  const accept = createHash('sha1').update(key + '258EAFA5-E914-47DA-95CA-C5AB0DC85B11').digest('base64');
  socket.write('HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n' +
    `Sec-WebSocket-Accept: ${accept}\r\n\r\n`);
  let buf = Buffer.alloc(0);
  let parts = [];
  const client = {
    open: true,
    send(text) {
      if (!client.open) return;
      const data = Buffer.from(text, 'utf8');
      let head;
      if (data.length < 126) head = Buffer.from([0x81, data.length]);
      else if (data.length < 65536) {
        head = Buffer.alloc(4);
        head[0] = 0x81; head[1] = 126; head.writeUInt16BE(data.length, 2);
      } else {
        head = Buffer.alloc(10);
        head[0] = 0x81; head[1] = 127; head.writeBigUInt64BE(BigInt(data.length), 2);
      }
      socket.write(Buffer.concat([head, data]));
    },
    close() {
      if (!client.open) return;
      client.open = false;
      socket.end(Buffer.from([0x88, 0]));
      onClose();
    },
  };
  socket.on('data', (chunk) => {
    buf = Buffer.concat([buf, chunk]);
    for (;;) {
      if (buf.length < 2) return;
      const fin = buf[0] & 0x80, op = buf[0] & 0x0f, masked = buf[1] & 0x80;
      let len = buf[1] & 0x7f, off = 2;
      if (len === 126) { if (buf.length < 4) return; len = buf.readUInt16BE(2); off = 4; }
      else if (len === 127) { if (buf.length < 10) return; len = Number(buf.readBigUInt64BE(2)); off = 10; }
      if (len > MAX_FRAME) { client.close(); return; }
      const need = off + (masked ? 4 : 0) + len;
      if (buf.length < need) return;
      const mask = masked ? buf.subarray(off, off + 4) : null;
      const payload = Buffer.from(buf.subarray(off + (masked ? 4 : 0), need));
      if (mask) for (let i = 0; i < payload.length; i++) payload[i] ^= mask[i & 3];
      buf = buf.subarray(need);
      if (op === 8) { client.close(); return; }
      if (op === 9) { socket.write(Buffer.concat([Buffer.from([0x8a, payload.length]), payload])); continue; }
      if (op === 1 || op === 2 || op === 0) {
        parts.push(payload);
        if (fin) {
          const text = Buffer.concat(parts).toString('utf8');
          parts = [];
          onMessage(client, text);
        }
      }
    }
  });
  socket.on('close', () => { if (client.open) { client.open = false; onClose(); } });
  socket.on('error', () => {});
  return client;
}

// ---- the mock scene ------------------------------------------------------------------------
function main(argv) {
  if (argv[0] !== 'serve' || !argv[1]) {
    console.error('usage: mock_serve.mjs serve SCENE.yaml [--port N] [--bind ADDR] [--slow]');
    process.exit(2);
  }
  const scene = basename(argv[1]).replace(/\.ya?ml$/, '');
  let port = 8080, bind = '127.0.0.1', slow = false;
  for (let i = 2; i < argv.length; i++) {
    if (argv[i] === '--port') port = Number(argv[++i]);
    else if (argv[i] === '--bind') bind = argv[++i];
    else if (argv[i] === '--slow') slow = true;
  }
  const page = assemble(
    readFileSync(join(VIEWER, 'src', 'page.html'), 'utf8'),
    readFileSync(join(VIEWER, 'dist', 'viewer.js'), 'utf8'),
    '{"mode":"live","ws":"/ws"}',
  );
  const tube = makeTube();
  const V = tube.rest.length / 3;
  const controls = [
    { id: 'activation.front_muscle', label: 'front muscle', kind: 'slider', min: 0, max: 1, step: 0.01, value: 0, unit: '' },
    { id: 'activation.back_muscle', label: 'back muscle', kind: 'slider', min: 0, max: 1, step: 0.01, value: 0, unit: '' },
    { id: 'joint_torque', label: 'knee torque', kind: 'knob', min: -20, max: 20, step: 0.1, value: 0, unit: 'N m' },
  ];
  const values = Object.fromEntries(controls.map((c) => [c.id, c.value]));
  const hello = JSON.stringify({
    type: 'hello', format: 'tissuebench-live/1', scene, dt: 2e-4,
    meshes: [{ name: 'skin', color: '#e9b08f', opacity: 0.6, vertices: V, triangles: tube.tris.length / 3,
      triangles_b64: b64(tube.tris), rest_b64: b64(tube.rest) }],
    controls,
    series: [{ name: 'knee_angle', unit: 'deg' }, { name: 'back_activation', unit: '1' }, { name: 'front_activation', unit: '1' }, { name: 'knee_torque', unit: 'N m' }],
  });
  const clients = new Set();
  let t = 0, angle = 0; // deg, flexion positive (the lower leg swings to -x)

  function refuse(client, why) {
    client.send(JSON.stringify({ type: 'error', message: 'message refused: ' + why }));
  }
  function onMessage(client, text) {
    if (Buffer.byteLength(text) > MAX_MESSAGE) return refuse(client, `${Buffer.byteLength(text)} bytes (at most ${MAX_MESSAGE})`);
    let j;
    try { j = JSON.parse(text); } catch (_) { return refuse(client, 'not JSON'); }
    if (!j || typeof j !== 'object' || Array.isArray(j) || typeof j.type !== 'string') return refuse(client, 'not an object with a "type" string');
    if (j.type === 'reset') {
      t = 0; angle = 0;
      for (const c of clients) c.send(JSON.stringify({ type: 'status', message: "reset to the scene's start", failed: false }));
      return;
    }
    if (j.type !== 'set') return refuse(client, `unknown type '${j.type}'`);
    const c = controls.find((x) => x.id === j.id);
    if (typeof j.value !== 'number' || !Number.isFinite(j.value)) return refuse(client, 'the value is not a finite number');
    if (!c) return refuse(client, `no control '${j.id}'`);
    if (j.value < c.min || j.value > c.max) return refuse(client, `${j.id} = ${j.value} is outside [${c.min}, ${c.max}]`);
    values[j.id] = j.value;
  }

  const pos = new Float32Array(tube.rest.length);
  const dtFrame = 1 / 30;
  setInterval(() => {
    t += dtFrame;
    const target = 130 * values['activation.back_muscle'] - 10 * values['activation.front_muscle'] + 2 * values.joint_torque;
    angle += (target - angle) * Math.min(1, dtFrame / 0.6);
    const th = (angle * Math.PI) / 180;
    for (let i = 0; i < pos.length; i += 3) {
      const x = tube.rest[i], y = tube.rest[i + 1], z = tube.rest[i + 2];
      const w = Math.min(1, Math.max(0, (KNEE_Z + 0.03 - z) / 0.06)); // blend across the knee
      const a = th * w, dz = z - KNEE_Z;
      pos[i] = x * Math.cos(a) + dz * Math.sin(a);
      pos[i + 1] = y;
      pos[i + 2] = KNEE_Z - x * Math.sin(a) + dz * Math.cos(a);
    }
    const frame = JSON.stringify({
      type: 'frame', t, real_time_factor: slow ? 0.6 : 1.0, slower_than_real_time: slow, knee_angle: angle,
      values: { knee_angle: angle, back_activation: values['activation.back_muscle'], front_activation: values['activation.front_muscle'], knee_torque: values.joint_torque },
      positions: [{ name: 'skin', b64: b64(pos) }],
    });
    for (const c of clients) c.send(frame);
  }, dtFrame * 1000);

  const server = createServer((req, res) => {
    if (req.url === '/' || req.url === '/index.html') {
      res.writeHead(200, { 'content-type': 'text/html; charset=utf-8', 'cache-control': 'no-store' });
      res.end(page);
    } else {
      res.writeHead(404, { 'content-type': 'text/plain' });
      res.end('not found\n');
    }
  });
  server.on('upgrade', (req, socket) => {
    if (req.url !== '/ws') { socket.end('HTTP/1.1 403 Forbidden\r\n\r\n'); return; }
    const client = wsAccept(req, socket, onMessage, () => clients.delete(client));
    clients.add(client);
    client.send(hello);
  });
  server.listen(port, bind, () => {
    console.log(`tissuebench serve (mock): http://${bind}:${server.address().port}/  (scene ${scene})`);
  });
  const stop = () => { server.close(); process.exit(0); };
  process.on('SIGTERM', stop);
  process.on('SIGINT', stop);
}

main(process.argv.slice(2));
