// base64 -> little-endian typed arrays, checked against the counts the data declares.
const LITTLE_ENDIAN = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;

export function base64ToBytes(b64) {
  if (typeof b64 !== 'string') throw new Error('base64 field is not a string');
  if (b64.length === 0) return new Uint8Array(0);
  if (typeof Uint8Array.fromBase64 === 'function') return Uint8Array.fromBase64(b64);
  const bin = atob(b64);
  const out = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
  return out;
}

function swapBytes(bytes, width) {
  for (let i = 0; i + width <= bytes.length; i += width) {
    for (let a = i, b = i + width - 1; a < b; a++, b--) {
      const t = bytes[a]; bytes[a] = bytes[b]; bytes[b] = t;
    }
  }
}

// Decodes `b64` into a `Ctor` array of exactly `count` elements, or throws saying what is wrong.
export function decodeTyped(b64, Ctor, count, what) {
  const bytes = base64ToBytes(b64);
  const want = count * Ctor.BYTES_PER_ELEMENT;
  if (bytes.length !== want)
    throw new Error(`${what}: ${bytes.length} bytes decoded, expected ${want} (${count} × ${Ctor.BYTES_PER_ELEMENT})`);
  if (!LITTLE_ENDIAN && Ctor.BYTES_PER_ELEMENT > 1) swapBytes(bytes, Ctor.BYTES_PER_ELEMENT);
  // A fresh Uint8Array starts at offset 0 of its own buffer, so the view is aligned;
  // copy otherwise.
  if (bytes.byteOffset % Ctor.BYTES_PER_ELEMENT !== 0) return new Ctor(bytes.slice().buffer, 0, count);
  return new Ctor(bytes.buffer, bytes.byteOffset, count);
}

function nonNegInt(v, what) {
  if (!Number.isInteger(v) || v < 0) throw new Error(`${what} is not a non-negative integer: ${JSON.stringify(v)}`);
  return v;
}

// The static part of a mesh: triangles and rest positions (run data and live hello alike).
export function decodeMeshBase(m, index) {
  if (!m || typeof m !== 'object') throw new Error(`mesh ${index} is not an object`);
  const name = typeof m.name === 'string' && m.name ? m.name : `mesh${index}`;
  const V = nonNegInt(m.vertices, `mesh ${name}: vertices`);
  const T = nonNegInt(m.triangles, `mesh ${name}: triangles`);
  const tris = decodeTyped(m.triangles_b64, Uint32Array, T * 3, `mesh ${name}: triangles_b64`);
  for (let i = 0; i < tris.length; i++) {
    if (tris[i] >= V) throw new Error(`mesh ${name}: triangle corner ${i} is vertex ${tris[i]}, only ${V} vertices`);
  }
  const rest = decodeTyped(m.rest_b64, Float32Array, V * 3, `mesh ${name}: rest_b64`);
  for (let i = 0; i < rest.length; i++) {
    if (!Number.isFinite(rest[i])) throw new Error(`mesh ${name}: rest coordinate ${i} is not finite`);
  }
  const opacity = typeof m.opacity === 'number' && Number.isFinite(m.opacity) ? Math.min(1, Math.max(0.02, m.opacity)) : 1;
  return { name, color: m.color, opacity, V, T, tris, rest };
}

// A run-data mesh's displacement for `frames` frames: int16 counts × displacement_scale.
export function decodeDisplacement(m, base, frames) {
  if (frames === 0) return { disp: null, scale: 0 };
  const scale = m.displacement_scale;
  if (typeof scale !== 'number' || !Number.isFinite(scale) || scale < 0)
    throw new Error(`mesh ${base.name}: displacement_scale is not a finite non-negative number`);
  const disp = decodeTyped(m.displacement_b64, Int16Array, frames * base.V * 3, `mesh ${base.name}: displacement_b64`);
  return { disp, scale };
}
