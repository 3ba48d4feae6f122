// The 3D view: three.js renderer, camera, OrbitControls, lights and one mesh per data mesh.
// Everything 3D is drawn by three.js; this module only feeds it positions.
import {
  WebGLRenderer, Scene, PerspectiveCamera, Color, HemisphereLight, DirectionalLight, AmbientLight,
  BufferGeometry, BufferAttribute, Mesh, MeshStandardMaterial, FrontSide, BackSide, DoubleSide,
  Box3, Vector3, SRGBColorSpace, DynamicDrawUsage,
} from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

const DEFAULT_COLORS = { skin: '#e9b08f', bones: '#f1ead6' };

function toColor(c, name) {
  const color = new Color(DEFAULT_COLORS[name] || '#c8c8c8');
  try {
    if (typeof c === 'string' && c) color.set(c);
    else if (typeof c === 'number' && Number.isFinite(c)) color.setHex(c);
    else if (Array.isArray(c) && c.length >= 3) {
      const s = c.some((v) => v > 1) ? 1 / 255 : 1;
      color.setRGB(c[0] * s, c[1] * s, c[2] * s, SRGBColorSpace);
    }
  } catch (_) { /* keep the default */ }
  return color;
}

export class View3D {
  constructor(container) {
    this.container = container;
    this.renderer = new WebGLRenderer({ antialias: true, preserveDrawingBuffer: true, alpha: false });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.renderer.outputColorSpace = SRGBColorSpace;
    this.renderer.domElement.tabIndex = 0;
    container.prepend(this.renderer.domElement);

    this.scene = new Scene();
    this.scene.background = new Color('#2a323d');

    this.camera = new PerspectiveCamera(35, 1, 0.01, 100);
    this.camera.up.set(0, 0, 1); // the leg's z axis is up
    this.camera.position.set(0, -2, 0.5);
    this.scene.add(this.camera);

    const hemi = new HemisphereLight(0xf4f1ea, 0x3a4250, 1.4);
    hemi.position.set(0, 0, 1);
    this.scene.add(hemi);
    this.scene.add(new AmbientLight(0xffffff, 0.25));
    // Key and rim lights ride with the camera, so the side facing the viewer is always lit.
    const key = new DirectionalLight(0xffffff, 2.2);
    key.position.set(-0.6, 0.4, 1.0);
    this.camera.add(key);
    this.camera.add(key.target);
    key.target.position.set(0, 0, -1);
    const rim = new DirectionalLight(0xbfd4ff, 0.8);
    rim.position.set(0.8, -0.3, -0.4);
    this.camera.add(rim);
    this.camera.add(rim.target);
    rim.target.position.set(0, 0, -1);

    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.controls.screenSpacePanning = true;
    this.controls.addEventListener('change', () => { this.dirty = true; });

    this.meshes = [];      // {name, V, geometry, position (Float32Array), objects: [Mesh]}
    this.fitBox = null;
    this.dirty = true;
    this.onBeforeRender = null;

    this._resize();
    new ResizeObserver(() => this._resize()).observe(container);
    const loop = (now) => {
      requestAnimationFrame(loop);
      if (this.onBeforeRender) this.onBeforeRender(now);
      if (this.dirty) {
        this.dirty = false;
        this.renderer.render(this.scene, this.camera);
      }
    };
    requestAnimationFrame(loop);
  }

  _resize() {
    const w = Math.max(1, this.container.clientWidth);
    const h = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  }

  clearMeshes() {
    for (const m of this.meshes) {
      for (const o of m.objects) {
        this.scene.remove(o);
        o.material.dispose();
      }
      m.geometry.dispose();
    }
    this.meshes = [];
    this.dirty = true;
  }

  // base: {name, color, opacity, V, tris (Uint32Array), rest (Float32Array)} from decode.js
  addMesh(base) {
    const geometry = new BufferGeometry();
    const position = new Float32Array(base.rest);
    const attr = new BufferAttribute(position, 3);
    attr.setUsage(DynamicDrawUsage);
    geometry.setAttribute('position', attr);
    geometry.setIndex(new BufferAttribute(base.tris, 1));
    geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    const color = toColor(base.color, base.name);
    const objects = [];
    if (base.opacity < 0.999) {
      // Translucent: back faces first, then front faces, no depth writes, so what is inside
      // (the bones) shows through and the far side of the skin is seen behind the near side.
      for (const [side, order] of [[BackSide, 10], [FrontSide, 11]]) {
        const mat = new MeshStandardMaterial({
          color, roughness: 0.55, metalness: 0.0, transparent: true, opacity: base.opacity,
          depthWrite: false, side,
        });
        const mesh = new Mesh(geometry, mat);
        mesh.renderOrder = order;
        mesh.name = base.name;
        objects.push(mesh);
      }
    } else {
      const mat = new MeshStandardMaterial({ color, roughness: 0.6, metalness: 0.0, side: DoubleSide });
      const mesh = new Mesh(geometry, mat);
      mesh.name = base.name;
      objects.push(mesh);
    }
    for (const o of objects) {
      o.frustumCulled = false; // the geometry moves every frame
      this.scene.add(o);
    }
    const entry = { name: base.name, V: base.V, geometry, position, objects };
    this.meshes.push(entry);
    this.dirty = true;
    return entry;
  }

  // Positions changed in entry.position: upload and recompute normals.
  updated(entry) {
    entry.geometry.attributes.position.needsUpdate = true;
    entry.geometry.computeVertexNormals();
    this.dirty = true;
  }

  currentBox() {
    const box = new Box3();
    const v = new Vector3();
    for (const m of this.meshes) {
      const p = m.position;
      for (let i = 0; i < p.length; i += 3) box.expandByPoint(v.set(p[i], p[i + 1], p[i + 2]));
    }
    return box;
  }

  // Frames `box` from the side: the camera looks along +y (x to the right, z up).
  fit(box) {
    if (box) this.fitBox = box.clone();
    const b = this.fitBox;
    if (!b || b.isEmpty()) return;
    const center = b.getCenter(new Vector3());
    const size = b.getSize(new Vector3());
    const halfFov = (this.camera.fov * Math.PI) / 360;
    const aspect = this.camera.aspect || 1;
    const margin = 1.12;
    const distV = (size.z / 2) / Math.tan(halfFov);
    const distH = (size.x / 2) / (Math.tan(halfFov) * aspect);
    const dist = Math.max(distV, distH, 1e-3) * margin + size.y / 2;
    this.camera.position.set(center.x, center.y - dist, center.z);
    this.camera.near = Math.max(dist / 200, 1e-4);
    this.camera.far = dist * 20 + size.length() * 4;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(center);
    this.controls.update();
    this.dirty = true;
  }
}
