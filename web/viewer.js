// The live viewer: long-polls GET /streams/ID/latest, decodes the result (frame_decode.js; both
// result forms, the faces of a POSITIONS stream fetched once and reused by their id),
// shows the mesh shaded and coloured by cluster, orbit with the mouse (OrbitControls), and an
// overlay with display fps and fqd's latency. window.fqViewer exposes the counts for tests.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { clusterColor, decodeFrame } from './frame_decode.js';

const DRACO_DIR = 'node_modules/three/examples/jsm/libs/draco/';
const state = (window.fqViewer = { frames: 0, index: 0, fps: 0, fetchMs: 0, decodeMs: 0, showMs: 0, renderMs: 0, stream: '', error: '' });
// ?replay=1 fetches and shows the latest result again and again instead of waiting for a newer
// one: it measures the viewer's own rate (fetch, decode, upload, draw) whatever fqd's rate is.
const replay = new URLSearchParams(location.search).get('replay') === '1';

const canvas = document.getElementById('view');
const picker = document.getElementById('stream');
const statsBox = document.getElementById('stats');
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x1d2126);
const camera = new THREE.PerspectiveCamera(40, 1, 1e-4, 1e4);
const controls = new OrbitControls(camera, canvas);
scene.add(new THREE.HemisphereLight(0xffffff, 0x505050, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 2.2);
camera.add(sun);  // a headlight: the lit side is always the one in view
sun.position.set(1, 1, 2);
scene.add(camera);
const material = new THREE.MeshStandardMaterial({ vertexColors: true, roughness: 0.7, metalness: 0.0, side: THREE.DoubleSide });
let mesh = null;
let framedStream = '';

function resize() {
  const w = window.innerWidth, h = window.innerHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  requestDraw();
}
window.addEventListener('resize', resize);

// Points the camera at the mesh the first time a stream is shown (not every frame: the user orbits).
function frameCamera(geometry) {
  geometry.computeBoundingSphere();
  const { center, radius } = geometry.boundingSphere;
  controls.target.copy(center);
  // From the front, a little above and to the side, so that depth shows in the shading.
  camera.position.copy(center).add(new THREE.Vector3(0.45, 0.35, 1).normalize().multiplyScalar(radius * 3));
  camera.near = radius / 100;
  camera.far = radius * 100;
  camera.updateProjectionMatrix();
  controls.update();
  framedStream = state.stream;
}

function colours(labels, count) {
  const out = new Float32Array(count * 3);
  if (!labels) return out.fill(0.8);
  const palette = new Map();
  const c = new THREE.Color();
  const rgb = [0, 0, 0];
  for (let i = 0; i < count; ++i) {
    let p = palette.get(labels[i]);
    if (!p) {
      clusterColor(labels[i], rgb, 0);
      c.setRGB(rgb[0], rgb[1], rgb[2], THREE.SRGBColorSpace);  // the PLY's sRGB bytes, in linear space
      p = [c.r, c.g, c.b];
      palette.set(labels[i], p);
    }
    out[3 * i] = p[0];
    out[3 * i + 1] = p[1];
    out[3 * i + 2] = p[2];
  }
  return out;
}

function show(frame) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(frame.positions, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(colours(frame.labels, frame.positions.length / 3), 3));
  geometry.setIndex(new THREE.BufferAttribute(frame.indices, 1));
  geometry.computeVertexNormals();
  if (mesh) {
    mesh.geometry.dispose();
    mesh.geometry = geometry;
  } else {
    mesh = new THREE.Mesh(geometry, material);
    scene.add(mesh);
  }
  if (framedStream !== state.stream) frameCamera(geometry);
  requestDraw();
}

// Display fps: frames shown over the last second, updated once per displayed frame.
const shownAt = [];
function countFrame() {
  const now = performance.now();
  shownAt.push(now);
  while (shownAt.length && shownAt[0] < now - 1000) shownAt.shift();
  state.frames += 1;
  state.fps = shownAt.length;
}

function overlay(headers) {
  statsBox.textContent =
    `display ${state.fps} fps   frames ${state.frames}\n` +
    `fqd latency ${Number(headers.get('X-Fq-Latency-Ms')).toFixed(1)} ms${headers.get('X-Fq-Late') === '1' ? ' (late)' : ''}\n` +
    `decode ${state.decodeMs.toFixed(1)} ms in the browser\n` +
    `${headers.get('X-Fq-Vertex-Count')} vertices, ${headers.get('X-Fq-Cluster-Count')} clusters, ${headers.get('X-Fq-Form')} form\n` +
    `engine ${headers.get('X-Fq-Engine')}   sequence ${headers.get('X-Fq-Sequence')}`;
}

// One long poll: the response with its body read, or null for 204 (nothing newer yet).
async function request(stream, after, facesId) {
  const t0 = performance.now();
  const res = await fetch(`streams/${encodeURIComponent(stream)}/latest?after=${after}&faces=${facesId}&wait_ms=2000`);
  if (res.status === 204) return null;
  if (!res.ok) throw new Error(`${res.status} ${await res.text()}`);
  const body = await res.arrayBuffer();
  return { stream, headers: res.headers, body, fetchMs: performance.now() - t0 };
}

// The next request is sent before the current result is decoded and drawn, so that the
// transfer overlaps the decode instead of adding to it.
function metaOf(headers) {
  return {
    form: headers.get('X-Fq-Form'),
    facesBytes: Number(headers.get('X-Fq-Faces-Bytes')),
    labelsBytes: Number(headers.get('X-Fq-Labels-Bytes')),
    sizes: headers.get('X-Fq-Chunk-Sizes').split(',').filter((s) => s !== '').map(Number),
    vertexCount: Number(headers.get('X-Fq-Vertex-Count')),
  };
}

async function pollStream(M) {
  let pending = null;
  let faces = { id: '0', indices: null };  // the faces of the last POSITIONS result shown
  for (;;) {
    const stream = state.stream;
    if (!stream) {
      await new Promise((r) => setTimeout(r, 500));
      continue;
    }
    try {
      const after = replay ? Math.max(0, state.index - 1) : state.index;
      if (faces.stream !== stream) faces = { id: '0', indices: null, stream };
      const got = await (pending || request(stream, after, faces.id));
      pending = null;
      if (!got || got.stream !== state.stream) continue;
      state.index = Number(got.headers.get('X-Fq-Index'));
      const meta = metaOf(got.headers);
      const facesId = got.headers.get('X-Fq-Faces-Id');
      // The next request says which faces this one leaves the viewer holding.
      const heldId = meta.facesBytes > 0 || facesId === faces.id ? facesId : '0';
      pending = request(stream, replay ? state.index - 1 : state.index, heldId);
      pending.catch(() => {});  // a failure is reported when it is awaited
      state.fetchMs = got.fetchMs;
      const t1 = performance.now();
      const frame = decodeFrame(M, got.body, meta, facesId === faces.id ? faces.indices : null);
      if (meta.form === 'positions') faces = { id: facesId, indices: frame.indices, stream };
      const t2 = performance.now();
      state.decodeMs = t2 - t1;
      show(frame);
      state.showMs = performance.now() - t2;
      countFrame();
      overlay(got.headers);
      state.error = '';
    } catch (e) {
      pending = null;
      faces = { id: '0', indices: null };
      state.error = String(e);
      statsBox.textContent = `stream ${stream}: ${state.error}`;
      await new Promise((r) => setTimeout(r, 1000));
    }
  }
}

// The stream list, refreshed every 2 s; ?stream=ID picks one, else the first.
async function refreshStreams() {
  try {
    const j = await (await fetch('streams')).json();
    const ids = j.streams.map((s) => s.stream);
    const current = [...picker.options].map((o) => o.value);
    if (ids.join('\n') !== current.join('\n')) {
      picker.replaceChildren(...ids.map((id) => new Option(id, id)));
      picker.value = state.stream;
    }
    const wanted = new URLSearchParams(location.search).get('stream');
    if (!state.stream && ids.length) selectStream(wanted && ids.includes(wanted) ? wanted : ids[0]);
  } catch (e) {
    statsBox.textContent = `cannot reach fqd: ${e}`;
  }
  setTimeout(refreshStreams, 2000);
}

function selectStream(id) {
  state.stream = id;
  state.index = 0;
  picker.value = id;
}
picker.addEventListener('change', () => selectStream(picker.value));

// Drawn on demand (a new frame, an orbit, a resize), not on every animation frame: a 270K-
// triangle mesh redrawn 60 times a second for nothing would take the CPU (and, in software
// WebGL, the network and decode work) away from the next frame.
let drawPending = false;
function requestDraw() {
  if (drawPending) return;
  drawPending = true;
  requestAnimationFrame(() => {
    drawPending = false;
    const t = performance.now();
    renderer.render(scene, camera);
    state.renderMs = performance.now() - t;
  });
}
controls.addEventListener('change', requestDraw);
resize();

// onModuleLoaded rather than the returned promise: the module object is itself a thenable in
// some Draco builds, which makes awaiting it loop (three's DRACOLoader does the same).
DracoDecoderModule({
  locateFile: (f) => DRACO_DIR + f,
  onModuleLoaded: (M) => {
    refreshStreams();
    pollStream(M);
  },
});
