// wave view: plays libwave's exported animations (docs/export.md) with three.js.
// Three forms: `morph` (one mesh, one morph target per frame, a STEP weights track),
// `nodes` (one child node per frame, its scale switched 0/1 by STEP keys) and `files`
// (index.json + one .glb per frame); plain, KHR_mesh_quantization, EXT_meshopt_compression
// (three.js's MeshoptDecoder) or Draco. The page
// reads each frame's attributes itself (three.js keeps only POSITION, NORMAL and
// COLOR_0 morph targets), so it can colour by _FOAM/_REFLECT/_REFRACT in every form.
// window.wave is the page's API for tests and scripts.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { Sky } from 'three/addons/objects/Sky.js';

const $ = (id) => document.getElementById(id);

// Where each shading value lives: the "named" layout or the "uv-maps" one
// (TEXCOORD_1 = (R, T), TEXCOORD_2 = (foam, 0)); [glTF name, component].
const SOURCES = {
  foam: [['_FOAM', 0], ['TEXCOORD_2', 0]],
  reflect: [['_REFLECT', 0], ['TEXCOORD_1', 0]],
  refract: [['_REFRACT', 0], ['TEXCOORD_1', 1]],
  color: [['COLOR_0', -1]],
};
const THREE_NAMES = { POSITION: 'position', NORMAL: 'normal', TEXCOORD_0: 'uv', TEXCOORD_1: 'uv1', TEXCOORD_2: 'uv2', COLOR_0: 'color' };
const threeName = (gltfName) => THREE_NAMES[gltfName] || gltfName.toLowerCase();

const SKY = new THREE.Color(0.78, 0.86, 0.95);
const DEEP = new THREE.Color(0.02, 0.12, 0.2);
// A perceptual-ish ramp for 0 … 1: deep blue → teal → yellow.
const RAMP = [new THREE.Color(0.05, 0.05, 0.35), new THREE.Color(0.1, 0.55, 0.6), new THREE.Color(0.98, 0.92, 0.3)];
function ramp(v, out) {
  const x = Math.min(1, Math.max(0, v)) * (RAMP.length - 1);
  const i = Math.min(RAMP.length - 2, Math.floor(x));
  return out.copy(RAMP[i]).lerp(RAMP[i + 1], x - i);
}

const dracoLoader = new DRACOLoader().setDecoderPath('draco/');
dracoLoader.setDecoderConfig({ type: 'wasm' });
const loader = new GLTFLoader().setDRACOLoader(dracoLoader).setMeshoptDecoder(MeshoptDecoder);

// ---------------------------------------------------------------------------------
// Frame sources: every form answers the same questions.
// ---------------------------------------------------------------------------------

// The water's meshes: libwave's morph and nodes files also carry the seafloor (a mesh
// named "seafloor"), which the page shows but does not animate.
const isWater = (o) => o.isMesh && o.name !== 'seafloor';

function firstMesh(root) {
  let mesh = null;
  root.traverse((o) => { if (!mesh && isWater(o)) mesh = o; });
  return mesh;
}

// A Draco or quantised frame carries its far-field skirt as a second primitive
// (docs/far-field.md), and three.js makes a group of one mesh per primitive. Joined into
// one mesh, the later primitives' copies of the seam's vertices (bit-equal positions)
// welded onto the first's, as libwave's reader does, a frame is again one mesh of the
// run's vertices. Positions are compared as float32: three.js decodes a normalised
// int16 in double, and the quantised skirt holds that value rounded to float32.
function joinPrimitives(gltf) {
  const groups = [];
  const of = (o) => gltf.parser.associations.get(o) || {};
  gltf.scene.traverse((o) => {  // a mesh's group: its children are that mesh's primitives
    if (o.isMesh || of(o).meshes === undefined) return;
    const parts = o.children.filter((c) => c.isMesh && of(c).meshes === of(o).meshes && of(c).primitives !== undefined);
    if (parts.length > 1) groups.push([o, parts]);
  });
  for (const [group, parts] of groups) {
    const first = parts[0].geometry, names = Object.keys(first.attributes);
    const values = Object.fromEntries(names.map((n) => [n, []]));
    const index = [], firstAt = new Map();
    let count = 0;
    parts.forEach((mesh, k) => {
      const g = mesh.geometry, position = g.attributes.position, remap = new Array(position.count);
      for (let v = 0; v < position.count; ++v) {
        const key = `${Math.fround(position.getX(v))},${Math.fround(position.getY(v))},${Math.fround(position.getZ(v))}`;
        if (k > 0 && firstAt.has(key)) { remap[v] = firstAt.get(key); continue; }
        if (k === 0) firstAt.set(key, count);
        remap[v] = count++;
        for (const n of names) {
          const a = g.attributes[n];
          for (let c = 0; c < a.itemSize; ++c) values[n].push(a.getComponent(v, c));
        }
      }
      for (let i = 0; i < g.index.count; ++i) index.push(remap[g.index.getX(i)]);
    });
    const geometry = new THREE.BufferGeometry();
    for (const n of names) geometry.setAttribute(n, new THREE.Float32BufferAttribute(values[n], first.attributes[n].itemSize));
    geometry.setIndex(index);
    const joined = new THREE.Mesh(geometry, parts[0].material);
    joined.name = parts[0].name;
    joined.userData.joined = true;
    for (const mesh of parts) group.remove(mesh);
    group.add(joined);
  }
  return gltf;
}

// A frame's own attribute: the file's, even where the page replaced `color` by its own.
function baseAttribute(mesh, name) {
  const original = mesh.geometry.userData.original;
  return original && name in original ? original[name] : mesh.geometry.attributes[threeName(name)];
}

// Values of a glTF attribute of `mesh` (frame's own geometry) as a Float32Array.
function readAttribute(attr) {
  const n = attr.count, k = attr.itemSize, out = new Float32Array(n * k);
  for (let i = 0; i < n; ++i) for (let c = 0; c < k; ++c) out[i * k + c] = attr.getComponent(i, c);
  return out;
}

// Positions in glTF space: the mesh node's own transform (it undoes the
// quantisation; the frame switch is on a parent or is 1 on the visible frame). A mesh
// joined from primitives is the child of the node's group, which holds the transform.
function transformPositions(values, mesh) {
  mesh.updateMatrix();
  const m = mesh.matrix.clone(), v = new THREE.Vector3();
  if (mesh.userData.joined) {
    mesh.parent.updateMatrix();
    m.premultiply(mesh.parent.matrix);
  }
  for (let i = 0; i < values.length; i += 3) {
    v.set(values[i], values[i + 1], values[i + 2]).applyMatrix4(m);
    values[i] = v.x; values[i + 1] = v.y; values[i + 2] = v.z;
  }
  return values;
}

function describe(json) {
  const used = json.extensionsUsed || [];
  return used.includes('KHR_draco_mesh_compression') ? 'Draco'
    : used.includes('EXT_meshopt_compression') ? 'meshopt'
    : used.includes('KHR_mesh_quantization') ? 'quantised' : 'plain';
}

// One .glb/.gltf holding the whole animation (morph or nodes form).
async function gltfSource(url) {
  const gltf = joinPrimitives(await loader.loadAsync(url));
  hazeSeafloor(gltf.scene);
  const json = gltf.parser.json;
  const libwave = (json.asset.extras || {}).libwave || {};
  const clip = gltf.animations[0];
  const mixer = new THREE.AnimationMixer(gltf.scene);
  let action = null;
  if (clip) {
    action = mixer.clipAction(clip);
    action.setLoop(THREE.LoopOnce, 1);
    action.clampWhenFinished = true;
  }
  const fps = libwave.fps || 24;
  const prim = json.meshes[0].primitives[0];
  const morph = Array.isArray(prim.targets) && prim.targets.length > 0;
  const meshes = [];
  gltf.scene.traverse((o) => { if (isWater(o)) meshes.push(o); });
  // A target per frame; quantised files add NORMAL-only targets after them (a
  // normal's turn beyond ±1, weighted in by the same animation).
  const frames = morph ? prim.targets.filter((t) => t.POSITION !== undefined).length : meshes.length;
  const targetCache = new Map();  // target index → { gltf name → BufferAttribute }
  const targetAttribute = async (i, name) => {
    if (!targetCache.has(i)) targetCache.set(i, {});
    const cache = targetCache.get(i);
    if (!(name in cache)) {
      const idx = prim.targets[i][name];
      cache[name] = idx === undefined ? null : await gltf.parser.getDependency('accessor', idx);
    }
    return cache[name];
  };
  const mesh0 = meshes[0];
  const source = {
    form: morph ? 'morph' : 'nodes',
    compression: describe(json),
    fps, frames,
    object: gltf.scene,
    meshes,
    vertices: mesh0.geometry.attributes.position.count,
    triangles: mesh0.geometry.index ? mesh0.geometry.index.count / 3 : mesh0.geometry.attributes.position.count / 3,
    has: (name) => (morph ? prim.attributes[name] !== undefined : json.meshes.some((m) => m.primitives[0].attributes[name] !== undefined)),
    async load(f) { return f; },
    // Shows frame f by the file's own animation at the middle of its frame interval
    // (STEP keys sit at the largest float32 <= k / fps).
    display(f) {
      if (action) {
        action.reset();
        action.play();
        mixer.setTime((f + 0.5) / fps);
      }
      gltf.scene.updateMatrixWorld(true);
      return morph ? mesh0 : meshes.find((m) => visible(m)) || meshes[f];
    },
    // The displayed frame's values of a glTF attribute (glTF space for POSITION).
    async values(mesh, name) {
      const base = baseAttribute(mesh, name);
      if (!base) return null;
      const out = readAttribute(base);
      if (morph) {
        const w = mesh.morphTargetInfluences || [];
        for (let i = 0; i < w.length; ++i) {
          if (w[i] === 0) continue;
          const t = await targetAttribute(i, name);
          if (!t) continue;
          for (let j = 0; j < out.length; ++j) out[j] += w[i] * t.getComponent(Math.floor(j / t.itemSize), j % t.itemSize);
        }
      }
      return name === 'POSITION' ? transformPositions(out, mesh) : out;
    },
  };
  if (morph) {
    // Colours are recomputed on the CPU per frame: three must not add COLOR_0 deltas.
    const g = mesh0.geometry;
    g.userData.original = { COLOR_0: g.attributes.color };
    delete g.morphAttributes.color;
  }
  return source;
}

function visible(mesh) {
  for (let o = mesh; o; o = o.parent) if (o.scale.x === 0 && o.scale.y === 0 && o.scale.z === 0) return false;
  return true;
}

// The files form: index.json and one static .glb per frame, loaded on demand.
async function filesSource(url) {
  const index = await (await fetch(url)).json();
  const base = url.slice(0, url.lastIndexOf('/') + 1);
  const frames = index.frames.slice().sort((a, b) => a.frame - b.frame);
  const loaded = new Map();
  const group = new THREE.Group();
  const load = (f) => {
    if (!loaded.has(f)) loaded.set(f, loader.loadAsync(base + frames[f].file).then(joinPrimitives).then((g) => {
      hazeSeafloor(g.scene);
      const json = g.parser.json;
      const mesh = firstMesh(g.scene);
      return { scene: g.scene, mesh, json };
    }));
    return loaded.get(f);
  };
  const first = await load(0);
  // The loop's frame 0 carries the seafloor and the sun, the other frames the water only
  // (docs/export.md): they move to the source's group and stay while the frames'
  // scenes are swapped.
  const dressing = [];
  first.scene.traverse((o) => { if ((o.isMesh && !isWater(o)) || o.isLight) dressing.push(o); });
  for (const o of dressing) group.attach(o);
  let current = null;
  const source = {
    form: 'files',
    compression: describe(first.json),
    fps: index.fps,
    frames: frames.length,
    object: group,
    vertices: first.mesh.geometry.attributes.position.count,
    triangles: first.mesh.geometry.index.count / 3,
    has: (name) => first.json.meshes[0].primitives[0].attributes[name] !== undefined,
    load,
    display(frame, f) {
      if (current !== frame) {
        if (current) group.remove(current.scene);
        group.add(frame.scene);
        current = frame;
      }
      for (let k = 1; k <= 4 && f + k < frames.length; ++k) load(f + k);  // read ahead
      // Keep memory bounded on long loops: drop frames far behind.
      for (const key of loaded.keys()) if (Math.abs(key - f) > 32 && key !== 0) loaded.delete(key);
      group.updateMatrixWorld(true);
      return frame.mesh;
    },
    async values(mesh, name) {
      const attr = baseAttribute(mesh, name);
      if (!attr) return null;
      const out = readAttribute(attr);
      return name === 'POSITION' ? transformPositions(out, mesh) : out;
    },
  };
  return source;
}

// ---------------------------------------------------------------------------------
// The page
// ---------------------------------------------------------------------------------

let renderer;
try {
  renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
} catch (e) {
  fail('WebGL is not available in this browser: ' + e.message);
}
const scene = new THREE.Scene();
// The background behind the sky, and the haze's colour: the sky's near the horizon.
scene.background = new THREE.Color(0.72, 0.79, 0.86);
const camera = new THREE.PerspectiveCamera(45, 1, 0.1, 1e6);
scene.add(new THREE.HemisphereLight(0xdde8ff, 0x203040, 1.4));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(0.4, 1, 0.3);
scene.add(sun);
// The sky (three's Sky: Preetham's daylight model) with its sun where the file's sun
// lamp points (KHR_lights_punctual: the lamp shines along its −Z, so the sun lies along
// its +Z); without a lamp in the file, the page's own light's direction. The box follows
// the camera and draws at the far plane, behind everything. Sky.js leaves its colours to
// the renderer's tone mapping, which the page does not use (it would change the water's
// and the seafloor's colours): a Reinhard curve at a fixed exposure is applied in its
// own shader instead.
const sky = new Sky();
sky.name = 'sky';
sky.scale.setScalar(1);
sky.frustumCulled = false;
sky.material.uniforms.turbidity.value = 4;
sky.material.uniforms.rayleigh.value = 1.5;
sky.material.uniforms.mieCoefficient.value = 0.004;
sky.material.uniforms.mieDirectionalG.value = 0.8;
sky.material.uniforms.skyExposure = { value: 2.0 };
sky.material.fragmentShader = sky.material.fragmentShader
  .replace('uniform float time;', 'uniform float time;\nuniform float skyExposure;')
  .replace('#include <tonemapping_fragment>',
    'gl_FragColor.rgb = gl_FragColor.rgb * skyExposure / (vec3(1.0) + gl_FragColor.rgb * skyExposure);\n#include <tonemapping_fragment>');
sky.onBeforeRender = (r, s, cam) => {
  sky.position.copy(cam.position);
  sky.scale.setScalar(0.5 * cam.far);
  sky.updateMatrixWorld();
};
scene.add(sky);
const skySun = new THREE.Vector3(0.4, 1, 0.3).normalize();
sky.material.uniforms.sunPosition.value.copy(skySun);
// The sky's sun from the first sun lamp under `root` (glTF axes, y up); false without one.
function sunFromFile(root) {
  let lamp = null;
  root.traverse((o) => { if (!lamp && o.isDirectionalLight) lamp = o; });
  if (!lamp) return false;
  lamp.updateWorldMatrix(true, false);
  const q = new THREE.Quaternion();
  lamp.getWorldQuaternion(q);
  skySun.set(0, 0, 1).applyQuaternion(q).normalize();
  sky.material.uniforms.sunPosition.value.copy(skySun);
  sun.position.copy(skySun);
  return true;
}
const controls = renderer ? new OrbitControls(camera, renderer.domElement) : null;
if (renderer) $('view').appendChild(renderer.domElement);
// Drawn on demand: when a frame, the colours, the camera, the size or the haze change,
// not on every display refresh. Redrawn sixty times a second, a paused page kept a core
// busy (software WebGL: the whole core).
let redraw = true;
function invalidate() { redraw = true; }
if (controls) controls.addEventListener('change', invalidate);
// Haze on the seafloor, as the Blender add-on's (docs/blender.md): at distance d the
// seafloor's colour mixes towards the background by a share 1 − e^{−3.912 d / V}
// (Koschmieder's law, V the visibility; 0 = off), so that the apron's land beyond the
// domain fades out instead of ending on the horizon. The water is left as it is.
const haze = { visibility: { value: 40000 }, color: { value: scene.background } };
function hazeSeafloor(root) {
  root.traverse((o) => {
    if (!o.isMesh || o.name !== 'seafloor' || o.material.userData.hazed) return;
    o.material.userData.hazed = true;
    o.material.onBeforeCompile = (shader) => {
      shader.uniforms.hazeVisibility = haze.visibility;
      shader.uniforms.hazeColor = haze.color;
      shader.vertexShader = shader.vertexShader.replace('#include <common>', '#include <common>\nvarying vec3 vHazeView;')
        .replace('#include <project_vertex>', '#include <project_vertex>\nvHazeView = mvPosition.xyz;');
      // Mixed in the working (linear) space, before tone mapping and the output
      // encoding, which the background's colour goes through too.
      shader.fragmentShader = shader.fragmentShader
        .replace('#include <common>', '#include <common>\nuniform float hazeVisibility;\nuniform vec3 hazeColor;\nvarying vec3 vHazeView;')
        .replace('#include <tonemapping_fragment>', 'if (hazeVisibility > 0.0) gl_FragColor.rgb = mix(gl_FragColor.rgb, hazeColor, ' +
          '1.0 - exp(-3.912 * length(vHazeView) / hazeVisibility));\n#include <tonemapping_fragment>');
    };
    o.material.needsUpdate = true;
  });
  return root;
}
const lit = new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide });
const unlit = new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.DoubleSide });

const state = { source: null, frame: 0, playing: true, loop: true, colorBy: 'water', mesh: null, outputs: [], busy: false, error: null };

function fail(message) {
  state.error = message;
  $('error').hidden = false;
  $('error').textContent = message;
}

function resize() {
  if (!renderer) return;
  const w = window.innerWidth, h = window.innerHeight;
  renderer.setSize(w, h, false);
  renderer.domElement.style.width = w + 'px';
  renderer.domElement.style.height = h + 'px';
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  invalidate();
}
window.addEventListener('resize', resize);

// The first value of a colour source present in the file.
function sourceOf(kind) {
  return (SOURCES[kind] || []).find(([name]) => state.source.has(name));
}

async function applyColors(mesh, request = latestRequest) {
  const g = mesh.geometry, n = g.attributes.position.count;
  if (!g.userData.original) g.userData.original = {};
  if (!('COLOR_0' in g.userData.original)) g.userData.original.COLOR_0 = g.attributes.color;
  const colors = new Float32Array(3 * n), c = new THREE.Color();
  const mode = state.colorBy;
  const src = sourceOf(mode === 'water' ? 'reflect' : mode);
  const values = src ? await state.source.values(mesh, src[0]) : null;
  const k = values ? values.length / n : 0;
  for (let i = 0; i < n; ++i) {
    if (!values || mode === 'plain') c.setRGB(0.55, 0.62, 0.7);
    else if (mode === 'color') c.setRGB(values[i * k], values[i * k + 1], values[i * k + 2]);
    else if (mode === 'water') c.copy(DEEP).lerp(SKY, Math.min(1, Math.max(0, values[i * k + src[1]])));  // R · sky + T · deep
    else ramp(values[i * k + src[1]], c);
    colors[3 * i] = c.r; colors[3 * i + 1] = c.g; colors[3 * i + 2] = c.b;
  }
  if (request !== latestRequest) return;  // a newer frame is on its way
  g.setAttribute('color', new THREE.BufferAttribute(colors, 3));
  mesh.material = mode === 'water' ? unlit : lit;
  invalidate();
}

// Whitewater beside the output (/whitewater: whitewater/whitewater-NNNN.glb, one POINTS
// .glb per loop frame): white points sized in metres, swapped with the frame. Found
// once per output (frame 0's file); frames without a file show none.
const whitewater = { base: null, frames: new Set(), group: new THREE.Group(), loaded: new Map(), shown: null };
whitewater.group.name = 'whitewater';
const whitewaterMaterial = new THREE.PointsMaterial({ color: 0xf4f7f8, size: 0.25, sizeAttenuation: true });

function findWhitewater(url) {
  whitewater.loaded.clear();
  if (whitewater.shown) whitewater.group.remove(whitewater.shown);
  whitewater.shown = null;
  whitewater.base = url.slice(0, url.lastIndexOf('/') + 1) + 'whitewater/whitewater-';
  scene.add(whitewater.group);
}

function whitewaterFrame(f) {
  if (!whitewater.base || !whitewater.frames.has(f)) return Promise.resolve(null);
  if (!whitewater.loaded.has(f)) {
    const url = whitewater.base + String(f).padStart(4, '0') + '.glb';
    whitewater.loaded.set(f, loader.loadAsync(url).then((g) => {
      let points = null;
      g.scene.traverse((o) => { if (o.isPoints) points = o; });
      if (points) points.material = whitewaterMaterial;
      return points;
    }).catch(() => null));
    if (whitewater.loaded.size > 64) whitewater.loaded.delete(whitewater.loaded.keys().next().value);
  }
  return whitewater.loaded.get(f);
}

// Requests can overlap (playback and the scrubber, files still loading): only the
// latest one may change what is shown.
let latestRequest = 0;
async function showFrame(f) {
  const s = state.source, request = ++latestRequest;
  f = Math.max(0, Math.min(s.frames - 1, Math.round(f)));
  const [loaded, points] = await Promise.all([s.load(f), whitewaterFrame(f)]);
  if (request !== latestRequest) return state.frame;
  const mesh = s.display(loaded, f);
  if (whitewater.shown !== points) {
    if (whitewater.shown) whitewater.group.remove(whitewater.shown);
    if (points) whitewater.group.add(points);
    whitewater.shown = points;
  }
  invalidate();
  state.frame = f;
  state.mesh = mesh;
  await applyColors(mesh, request);
  $('frame').value = String(f);
  $('frame-label').textContent = `${f} / ${s.frames - 1}`;
  return f;
}

// Frames the domain: the water's vertices whose rest position (TEXCOORD_0) lies in
// [0, 1]², so that a far-field skirt reaching tens or thousands of km (docs/far-field.md)
// stays in view without shrinking the coast to a dot; the far plane holds the whole.
function fitCamera(object, mesh) {
  const whole = new THREE.Box3().setFromObject(object, true);
  if (whole.isEmpty()) return;
  let box = whole;
  const uv = mesh && mesh.geometry.attributes.uv, position = mesh && mesh.geometry.attributes.position;
  if (uv && position) {
    const domain = new THREE.Box3(), v = new THREE.Vector3();
    mesh.updateWorldMatrix(true, false);
    for (let i = 0; i < position.count; ++i) {
      const u = uv.getX(i), w = uv.getY(i);
      if (u >= 0 && u <= 1 && w >= 0 && w <= 1) domain.expandByPoint(v.fromBufferAttribute(position, i).applyMatrix4(mesh.matrixWorld));
    }
    if (!domain.isEmpty()) box = domain;
  }
  const size = box.getSize(new THREE.Vector3()).length(), center = box.getCenter(new THREE.Vector3());
  camera.position.copy(center).add(new THREE.Vector3(0.15 * size, 0.45 * size, 0.75 * size));
  camera.near = size / 1000;
  camera.far = Math.max(size * 20, 2 * whole.getSize(new THREE.Vector3()).length());
  camera.updateProjectionMatrix();
  controls.target.copy(center);
  controls.update();
  invalidate();
}

async function openOutput(i) {
  const o = state.outputs[i];
  if (state.source) scene.remove(state.source.object);
  state.source = null;
  $('info').textContent = 'loading ' + o.name + '…';
  const source = o.kind === 'index' ? await filesSource(o.url) : await gltfSource(o.url);
  sunFromFile(source.object);
  findWhitewater(o.url);
  state.source = source;
  scene.add(source.object);
  invalidate();
  $('frame').max = String(source.frames - 1);
  for (const opt of $('color-by').options) {
    const present = opt.value === 'plain' || !!sourceOf(opt.value === 'water' ? 'reflect' : opt.value);
    opt.disabled = !present;
    if (!present && opt.selected) state.colorBy = 'plain';
  }
  $('color-by').value = state.colorBy;
  await showFrame(0);
  fitCamera(source.object, state.mesh);
  $('info').textContent = `${o.name}: ${source.form} form, ${source.compression}\n` +
    `${source.frames} frames at ${source.fps} fps (${(source.frames / source.fps).toFixed(2)} s)\n` +
    `${source.vertices} vertices, ${source.triangles} triangles`;
  return info();
}

function info() {
  const s = state.source;
  return s && { form: s.form, compression: s.compression, frames: s.frames, fps: s.fps, vertices: s.vertices, triangles: s.triangles,
    output: state.outputs[Number($('output').value) || 0]?.name,
    whitewater: whitewater.shown ? whitewater.shown.geometry.attributes.position.count : 0 };
}

// Playback at the file's fps; a files-form frame still loading holds the clock.
let last = performance.now(), clock = 0;
function tick(now) {
  requestAnimationFrame(tick);
  const dt = (now - last) / 1000;
  last = now;
  const s = state.source;
  if (s && state.playing && !state.busy) {
    clock += dt * s.fps;
    if (clock >= 1) {
      const steps = Math.floor(clock);
      clock -= steps;
      let next = state.frame + steps;
      if (next >= s.frames) {
        if (state.loop) next %= s.frames;
        else { next = s.frames - 1; setPlaying(false); }
      }
      state.busy = true;
      showFrame(next).finally(() => { state.busy = false; });
    }
  }
  if (renderer && redraw) {
    redraw = false;
    renderer.render(scene, camera);
  }
}

function setPlaying(on) {
  state.playing = on;
  $('play').classList.toggle('playing', on);  // pause bars while playing, a triangle when paused
}

$('play').addEventListener('click', () => setPlaying(!state.playing));
window.addEventListener('keydown', (e) => { if (e.code === 'Space') { setPlaying(!state.playing); e.preventDefault(); } });
$('frame').addEventListener('input', () => { setPlaying(false); showFrame(Number($('frame').value)); });
$('loop').addEventListener('change', () => { state.loop = $('loop').checked; });
$('color-by').addEventListener('change', () => { state.colorBy = $('color-by').value; if (state.mesh) applyColors(state.mesh); });
$('output').addEventListener('change', () => openOutput(Number($('output').value)).catch((e) => fail(String(e))));
$('haze').addEventListener('change', () => { window.wave.haze(1000 * (Number($('haze').value) || 0)); });

// The legend of the 0 … 1 ramp.
{
  const ctx = $('legend').getContext('2d'), c = new THREE.Color();
  for (let x = 0; x < 120; ++x) { ramp(x / 119, c); ctx.fillStyle = '#' + c.getHexString(); ctx.fillRect(x, 0, 1, 10); }
}

const ready = (async () => {
  resize();
  const list = await (await fetch('api/outputs', { cache: 'no-store' })).json();
  state.outputs = list.outputs;
  whitewater.frames = new Set(list.whitewater_frames || []);
  for (const [i, o] of list.outputs.entries()) $('output').add(new Option(o.name, String(i)));
  const wanted = new URLSearchParams(location.search).get('output');
  const i = Math.max(0, list.outputs.findIndex((o) => o.name === wanted));
  $('output').value = String(i);
  if (!renderer) throw new Error(state.error);
  const result = await openOutput(i);
  requestAnimationFrame(tick);
  return result;
})().catch((e) => { fail('cannot show this output: ' + (e && e.message ? e.message : e)); throw e; });

// The page's API (tests, scripts): everything in glTF coordinates (y up).
window.wave = {
  ready,
  info,
  get frame() { return state.frame; },
  // How many times the page has drawn (three.js counts its render calls).
  get draws() { return renderer ? renderer.info.render.frame : 0; },
  get error() { return state.error; },
  async setFrame(f) { setPlaying(false); return showFrame(f); },
  play() { setPlaying(true); },
  pause() { setPlaying(false); },
  async positions() { return Array.from(await state.source.values(state.mesh, 'POSITION')); },
  async values(kind) {
    const src = sourceOf(kind);
    if (!src) return null;
    const v = await state.source.values(state.mesh, src[0]);
    const n = state.mesh.geometry.attributes.position.count, k = v.length / n;
    return src[1] < 0 ? Array.from(v) : Array.from({ length: n }, (_, i) => v[i * k + src[1]]);
  },
  async setColor(mode) { state.colorBy = mode; $('color-by').value = mode; await applyColors(state.mesh); },
  async openOutput(name) {
    const i = state.outputs.findIndex((o) => o.name === name);
    if (i < 0) throw new Error('no output ' + name);
    $('output').value = String(i);
    return openOutput(i);
  },
  colors() { return Array.from(state.mesh.geometry.attributes.color.array); },
  // The sky's sun: the unit direction towards it (glTF axes), and whether the sky is
  // drawn; `shown` (a boolean) shows or hides it (hidden: the flat background).
  sky(shown) {
    if (shown !== undefined) {
      sky.visible = !!shown;
      invalidate();
    }
    return { sun: skySun.toArray(), shown: sky.visible };
  },
  // The haze's visibility in metres (0: off); without an argument, the current one.
  haze(visibility) {
    if (visibility !== undefined) {
      haze.visibility.value = Math.max(0, Number(visibility) || 0);
      $('haze').value = String(haze.visibility.value / 1000);
      invalidate();
    }
    return haze.visibility.value;
  },
  // Looks from `eye` at `target` (glTF axes), as the orbit controls would.
  look(eye, target) {
    camera.position.set(...eye);
    controls.target.set(...target);
    controls.update();
    invalidate();
  },
};
