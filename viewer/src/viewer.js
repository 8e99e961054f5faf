// Fulcrum replay viewer. Bundled with three.js into viewer/dist/viewer.js
// (viewer/build.mjs) and embedded in every recorded HTML page by the C++
// writer; it reads the recording from <script id="fulcrum-recording">.
// The data format is documented in docs/recording.md.
import {
  AmbientLight, Box3, BufferAttribute, BufferGeometry, Color, DirectionalLight, DoubleSide, FrontSide, Group,
  HemisphereLight, LineBasicMaterial, LineSegments, Mesh, MeshStandardMaterial, PerspectiveCamera, Points,
  PointsMaterial, Quaternion, Scene, Vector3, WebGLRenderer,
} from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

// ---- data -----------------------------------------------------------------

function decode(base64, Type) {
  if (!base64) return new Type(0);
  const bin = atob(base64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  return new Type(bytes.buffer, 0, bytes.length / Type.BYTES_PER_ELEMENT);
}

const rec = JSON.parse(document.getElementById('fulcrum-recording').textContent);
const frameCount = rec.frames;
const bodyCount = rec.bodies.length;
const times = decode(rec.times, Float64Array);
const transforms = decode(rec.transforms, Float32Array);      // [frame][body][px py pz qx qy qz qw]
const awake = decode(rec.awake, Uint8Array);                   // [frame][body]
const bounds = decode(rec.bounds, Float32Array);               // [frame][body][min xyz, max xyz]
const contactOffsets = decode(rec.contactOffsets, Uint32Array);
const contacts = decode(rec.contacts, Float32Array);           // [point][px py pz nx ny nz depth]
const energy = decode(rec.energy, Float64Array);               // [frame][kinetic potential total]
const t0 = frameCount > 0 ? times[0] : 0;
const duration = frameCount > 0 ? times[frameCount - 1] - t0 : 0;

// ---- scene ----------------------------------------------------------------

const view = document.getElementById('view');
const renderer = new WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
view.appendChild(renderer.domElement);

const scene = new Scene();
scene.background = new Color(0x1c2028);
scene.add(new HemisphereLight(0xdfe8ff, 0x404040, 1.2));
scene.add(new AmbientLight(0xffffff, 0.25));
const sun = new DirectionalLight(0xffffff, 1.8);
scene.add(sun);

// Frame what the run starts from; lights and overlays scale with it.
const view0 = rec.start ?? rec.scene;
const center = new Vector3(...view0.center);
const radius = Math.max(view0.radius, 0.5);
sun.position.copy(center).add(new Vector3(0.6, 1.0, 0.45).multiplyScalar(radius * 4));
sun.target.position.copy(center);
scene.add(sun.target);

const camera = new PerspectiveCamera(45, 1, radius / 200, radius * 200);
camera.position.copy(center).add(new Vector3(1.2, 0.8, 1.6).normalize().multiplyScalar(radius * 2.6));
const controls = new OrbitControls(camera, renderer.domElement);
controls.target.copy(center);
controls.update();

function material(rgb, doubleSided) {
  // Double-sided parts are planes and meshes: pushed back a little so grid lines and contacts on them show.
  return new MeshStandardMaterial({ color: new Color(rgb[0], rgb[1], rgb[2]), roughness: 0.6, metalness: 0.0,
                                    side: doubleSided ? DoubleSide : FrontSide, polygonOffset: doubleSided,
                                    polygonOffsetFactor: 1, polygonOffsetUnits: 1 });
}

// Grid lines over a plane's quad (corners 0, 1, 2, 3), spaced at a round number
// of metres, so motion over the ground reads at a glance.
function planeGrid(positions) {
  const c = [0, 1, 3].map((k) => new Vector3(positions[3 * k], positions[3 * k + 1], positions[3 * k + 2]));
  const u = c[1].clone().sub(c[0]), v = c[2].clone().sub(c[0]);
  const size = u.length();
  let step = 10 ** Math.floor(Math.log10(Math.max(radius / 4, 1e-3)));
  while (size / step > 120) step *= 2;
  const lines = Math.max(1, Math.floor(size / step));
  const vertices = [];
  for (let i = 0; i <= lines; i++) {
    const a = i / lines;
    const pu = c[0].clone().addScaledVector(u, a), pv = c[0].clone().addScaledVector(v, a);
    vertices.push(...pu.toArray(), ...pu.clone().add(v).toArray(), ...pv.toArray(), ...pv.clone().add(u).toArray());
  }
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(new Float32Array(vertices), 3));
  return new LineSegments(geometry, new LineBasicMaterial({ color: 0x8a94a6, transparent: true, opacity: 0.35 }));
}

// One group per body, whose children are the parts of its shape.
const bodies = rec.bodies.map((body) => {
  const group = new Group();
  group.name = body.name;
  const meshes = [];
  for (const part of body.parts) {
    const geometry = new BufferGeometry();
    geometry.setAttribute('position', new BufferAttribute(decode(part.positions, Float32Array), 3));
    geometry.setAttribute('normal', new BufferAttribute(decode(part.normals, Float32Array), 3));
    geometry.setIndex(new BufferAttribute(decode(part.indices, Uint32Array), 1));
    const mesh = new Mesh(geometry, material(body.color, part.doubleSided));
    mesh.position.set(...part.position);
    mesh.quaternion.set(...part.rotation);
    group.add(mesh);
    meshes.push(mesh);
    if (body.shape === 'plane') {
      const grid = planeGrid(geometry.attributes.position.array);
      grid.position.copy(mesh.position);
      grid.quaternion.copy(mesh.quaternion);
      group.add(grid);
    }
  }
  scene.add(group);
  return { group, meshes, awakeMaterial: meshes.map((m) => m.material),
           sleepMaterial: body.parts.map((p) => material(body.sleepColor, p.doubleSided)), asleep: false };
});

// Ropes (line segments) and cloths (double-sided triangles): a fixed topology
// whose positions are rewritten every frame from [frame][particle][xyz].
const particleTracks = (rec.particles ?? []).map((track) => {
  const count = track.count;
  const geometry = new BufferGeometry();
  const position = new BufferAttribute(new Float32Array(count * 3), 3);
  geometry.setAttribute('position', position);
  geometry.setIndex(new BufferAttribute(decode(track.indices, Uint32Array), 1));
  const cloth = track.kind === 'cloth';
  let object;
  if (cloth) {
    geometry.setAttribute('normal', new BufferAttribute(new Float32Array(count * 3), 3));
    object = new Mesh(geometry, new MeshStandardMaterial({ color: 0xd98c40, roughness: 0.8, metalness: 0.0, side: DoubleSide }));
  } else {
    object = new LineSegments(geometry, new LineBasicMaterial({ color: 0xf2e6a6 }));
  }
  object.name = track.name;
  object.frustumCulled = false;  // the bounds change every frame
  scene.add(object);
  return { object, geometry, position, cloth, count, frames: decode(track.positions, Float32Array) };
});

function updateParticles(frame, alpha) {
  for (const track of particleTracks) {
    const n = track.count * 3, a = frame * n, out = track.position.array, x = track.frames;
    const b = alpha > 0 && frame + 1 < frameCount ? a + n : a;
    for (let k = 0; k < n; k++) out[k] = x[a + k] + (x[b + k] - x[a + k]) * alpha;
    track.position.needsUpdate = true;
    if (track.cloth) track.geometry.computeVertexNormals();
  }
}

// Overlays: contact points and normals, joints, AABBs; buffers sized for the busiest frame.
let maxContacts = 0;
for (let f = 0; f < frameCount; f++) maxContacts = Math.max(maxContacts, contactOffsets[f + 1] - contactOffsets[f]);
function dynamicLines(vertexCount, color, PointsOrLines, extra = {}) {
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(new Float32Array(Math.max(vertexCount, 1) * 3), 3));
  geometry.setDrawRange(0, 0);
  const mat = PointsOrLines === Points
    ? new PointsMaterial({ color, size: 7, sizeAttenuation: false, depthTest: false, ...extra })
    : new LineBasicMaterial({ color, depthTest: false, ...extra });
  const object = new PointsOrLines(geometry, mat);
  object.frustumCulled = false;
  object.renderOrder = 10;
  scene.add(object);
  return object;
}
const contactPoints = dynamicLines(maxContacts, 0xff4040, Points);
const contactNormals = dynamicLines(maxContacts * 2, 0xffe066, LineSegments);
const jointLines = dynamicLines(rec.joints.length * 2, 0x7cf0ff, LineSegments);
const jointPoints = dynamicLines(rec.joints.length * 2, 0x7cf0ff, Points);
const aabbLines = dynamicLines(bodyCount * 24, 0x9aff9a, LineSegments, { transparent: true, opacity: 0.7 });
const normalLength = radius * 0.08;

// ---- state ----------------------------------------------------------------

const ui = {
  play: document.getElementById('play'),
  timeline: document.getElementById('timeline'),
  time: document.getElementById('time'),
  speed: document.getElementById('speed'),
  contacts: document.getElementById('show-contacts'),
  normals: document.getElementById('show-normals'),
  joints: document.getElementById('show-joints'),
  aabbs: document.getElementById('show-aabbs'),
  sleeping: document.getElementById('show-sleeping'),
  loop: document.getElementById('loop'),
  plot: document.getElementById('plot'),
};
document.getElementById('title').textContent = rec.title;
document.getElementById('stats').textContent =
  `${bodyCount} bodies · ${rec.joints.length} joints · ${particleTracks.length} ropes/cloths · ` +
  `${frameCount} frames · ${duration.toFixed(3)} s`;
document.title = rec.title;
ui.timeline.max = String(Math.max(frameCount - 1, 0));

const state = { playing: false, time: 0, frame: 0, speed: 1, framesRendered: 0 };

// Frame k with times[k] <= t0 + t < times[k + 1], and how far between them.
function locate(t) {
  const target = t0 + t;
  let lo = 0, hi = frameCount - 1;
  if (frameCount === 0 || target <= times[0]) return [0, 0];
  if (target >= times[hi]) return [hi, 0];
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (times[mid] <= target) lo = mid; else hi = mid;
  }
  return [lo, (target - times[lo]) / (times[lo + 1] - times[lo])];
}

const qa = new Quaternion(), qb = new Quaternion(), va = new Vector3(), vb = new Vector3();
function bodyPose(frame, alpha, b, position, quaternion) {
  const i = (frame * bodyCount + b) * 7;
  position.set(transforms[i], transforms[i + 1], transforms[i + 2]);
  quaternion.set(transforms[i + 3], transforms[i + 4], transforms[i + 5], transforms[i + 6]);
  if (alpha > 0 && frame + 1 < frameCount) {
    const j = i + bodyCount * 7;
    vb.set(transforms[j], transforms[j + 1], transforms[j + 2]);
    qb.set(transforms[j + 3], transforms[j + 4], transforms[j + 5], transforms[j + 6]);
    position.lerp(vb, alpha);
    quaternion.slerp(qb, alpha);
  }
}

function worldAnchor(bodyIndex, local, out) {
  out.set(local[0], local[1], local[2]);
  if (bodyIndex >= 0) out.applyQuaternion(bodies[bodyIndex].group.quaternion).add(bodies[bodyIndex].group.position);
  return out;
}

function update() {
  const [frame, alpha] = locate(state.time);
  state.frame = frame;
  for (let b = 0; b < bodyCount; b++) {
    const body = bodies[b];
    bodyPose(frame, alpha, b, body.group.position, body.group.quaternion);
    const asleep = ui.sleeping.checked && awake[frame * bodyCount + b] === 0;
    if (asleep !== body.asleep) {
      body.asleep = asleep;
      body.meshes.forEach((m, k) => { m.material = asleep ? body.sleepMaterial[k] : body.awakeMaterial[k]; });
    }
  }
  updateParticles(frame, alpha);
  // Contacts of the frame shown (not interpolated: they belong to a step).
  const c0 = contactOffsets[frame] ?? 0, c1 = contactOffsets[frame + 1] ?? 0;
  const pts = contactPoints.geometry.attributes.position, nrm = contactNormals.geometry.attributes.position;
  for (let c = c0, k = 0; c < c1; c++, k++) {
    const p = c * 7;
    pts.setXYZ(k, contacts[p], contacts[p + 1], contacts[p + 2]);
    nrm.setXYZ(2 * k, contacts[p], contacts[p + 1], contacts[p + 2]);
    nrm.setXYZ(2 * k + 1, contacts[p] + contacts[p + 3] * normalLength, contacts[p + 1] + contacts[p + 4] * normalLength,
               contacts[p + 2] + contacts[p + 5] * normalLength);
  }
  pts.needsUpdate = nrm.needsUpdate = true;
  contactPoints.geometry.setDrawRange(0, c1 - c0);
  contactNormals.geometry.setDrawRange(0, 2 * (c1 - c0));
  contactPoints.visible = ui.contacts.checked;
  contactNormals.visible = ui.contacts.checked && ui.normals.checked;

  const jl = jointLines.geometry.attributes.position, jp = jointPoints.geometry.attributes.position;
  rec.joints.forEach((joint, j) => {
    worldAnchor(joint.bodyA, joint.anchorA, va);
    worldAnchor(joint.bodyB, joint.anchorB, vb);
    jl.setXYZ(2 * j, va.x, va.y, va.z); jl.setXYZ(2 * j + 1, vb.x, vb.y, vb.z);
    jp.setXYZ(2 * j, va.x, va.y, va.z); jp.setXYZ(2 * j + 1, vb.x, vb.y, vb.z);
  });
  jl.needsUpdate = jp.needsUpdate = true;
  jointLines.geometry.setDrawRange(0, 2 * rec.joints.length);
  jointPoints.geometry.setDrawRange(0, 2 * rec.joints.length);
  jointLines.visible = jointPoints.visible = ui.joints.checked;

  aabbLines.visible = ui.aabbs.checked && bounds.length > 0;
  if (aabbLines.visible) {
    const al = aabbLines.geometry.attributes.position;
    let v = 0;
    for (let b = 0; b < bodyCount; b++) {
      const i = (frame * bodyCount + b) * 6;
      const lo = [bounds[i], bounds[i + 1], bounds[i + 2]], hi = [bounds[i + 3], bounds[i + 4], bounds[i + 5]];
      if (rec.bodies[b].shape === 'plane' || !(hi[0] - lo[0] < 1e6)) continue;  // infinite: nothing to draw
      for (let axis = 0; axis < 3; axis++) {                                    // 4 edges along each axis
        const u = (axis + 1) % 3, w = (axis + 2) % 3;
        for (let e = 0; e < 4; e++) {
          const p = [0, 0, 0];
          p[u] = e & 1 ? hi[u] : lo[u];
          p[w] = e & 2 ? hi[w] : lo[w];
          p[axis] = lo[axis]; al.setXYZ(v++, p[0], p[1], p[2]);
          p[axis] = hi[axis]; al.setXYZ(v++, p[0], p[1], p[2]);
        }
      }
    }
    al.needsUpdate = true;
    aabbLines.geometry.setDrawRange(0, v);
  }

  ui.timeline.value = String(frame);
  const t = frameCount > 0 ? times[frame] - t0 : 0;
  ui.time.textContent = `t = ${(t0 + state.time).toFixed(3)} s · frame ${frame + 1}/${frameCount}`;
  drawPlot();
}

// ---- energy plot ------------------------------------------------------------

const series = [
  { name: 'kinetic', color: '#ff7a6b', offset: 0 },
  { name: 'potential', color: '#6bb5ff', offset: 1 },
  { name: 'total', color: '#f2f2f2', offset: 2 },
];
let eMin = Infinity, eMax = -Infinity;
for (let i = 0; i < energy.length; i++) { eMin = Math.min(eMin, energy[i]); eMax = Math.max(eMax, energy[i]); }
if (!(eMax > eMin)) { eMin -= 1; eMax += 1; }
const plotPad = { left: 64, right: 12, top: 12, bottom: 22 };

function drawPlot() {
  const canvas = ui.plot;
  const dpr = window.devicePixelRatio || 1;
  const w = canvas.clientWidth, h = canvas.clientHeight;
  if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
    canvas.width = Math.round(w * dpr); canvas.height = Math.round(h * dpr);
  }
  const g = canvas.getContext('2d');
  g.setTransform(dpr, 0, 0, dpr, 0, 0);
  g.clearRect(0, 0, w, h);
  const x0 = plotPad.left, x1 = w - plotPad.right, y0 = plotPad.top, y1 = h - plotPad.bottom;
  const xOf = (t) => x0 + (duration > 0 ? (t - t0) / duration : 0) * (x1 - x0);
  const yOf = (e) => y1 - (e - eMin) / (eMax - eMin) * (y1 - y0);
  g.strokeStyle = '#3a4250'; g.lineWidth = 1; g.fillStyle = '#98a1b2'; g.font = '11px system-ui, sans-serif';
  g.beginPath(); g.moveTo(x0, y0); g.lineTo(x0, y1); g.lineTo(x1, y1); g.stroke();
  g.textAlign = 'right'; g.textBaseline = 'middle';
  for (const e of [eMin, (eMin + eMax) / 2, eMax]) g.fillText(`${e.toPrecision(4)} J`, x0 - 6, yOf(e));
  g.textAlign = 'center'; g.textBaseline = 'top';
  g.fillText(`${t0.toFixed(2)} s`, x0, y1 + 5); g.fillText(`${(t0 + duration).toFixed(2)} s`, x1 - 14, y1 + 5);
  for (const s of series) {
    g.strokeStyle = s.color; g.lineWidth = 1.5; g.beginPath();
    // At most ~2 samples per pixel column.
    const stride = Math.max(1, Math.floor(frameCount / Math.max(1, 2 * (x1 - x0))));
    for (let f = 0; f < frameCount; f += stride) {
      const x = xOf(times[f]), y = yOf(energy[f * 3 + s.offset]);
      if (f === 0) g.moveTo(x, y); else g.lineTo(x, y);
    }
    g.stroke();
  }
  g.textAlign = 'left'; g.textBaseline = 'top';
  series.forEach((s, i) => { g.fillStyle = s.color; g.fillText(s.name, x1 - 210 + i * 72, y1 - 16); });
  const xt = xOf(t0 + state.time);
  g.strokeStyle = '#f0b24a'; g.lineWidth = 1.5; g.beginPath(); g.moveTo(xt, y0); g.lineTo(xt, y1); g.stroke();
}

function seekFromPlot(event) {
  const r = ui.plot.getBoundingClientRect();
  const u = (event.clientX - r.left - plotPad.left) / (r.width - plotPad.left - plotPad.right);
  seekTime(Math.min(Math.max(u, 0), 1) * duration);
}
ui.plot.addEventListener('pointerdown', (e) => { ui.plot.setPointerCapture(e.pointerId); seekFromPlot(e); });
ui.plot.addEventListener('pointermove', (e) => { if (e.buttons & 1) seekFromPlot(e); });

// ---- playback ---------------------------------------------------------------

function setPlaying(playing) {
  state.playing = playing && frameCount > 1;
  if (state.playing && state.time >= duration) state.time = 0;
  ui.play.textContent = state.playing ? 'Pause' : 'Play';
}
function seekTime(t) { state.time = Math.min(Math.max(t, 0), duration); update(); }
function seekFrame(f) {
  const k = Math.min(Math.max(Math.round(f), 0), Math.max(frameCount - 1, 0));
  seekTime(frameCount > 0 ? times[k] - t0 : 0);
}

ui.play.addEventListener('click', () => setPlaying(!state.playing));
ui.timeline.addEventListener('input', () => { setPlaying(false); seekFrame(Number(ui.timeline.value)); });
ui.speed.addEventListener('change', () => { state.speed = Number(ui.speed.value); });
for (const box of [ui.contacts, ui.normals, ui.joints, ui.aabbs, ui.sleeping]) box.addEventListener('change', update);
window.addEventListener('keydown', (e) => {
  if (e.target instanceof HTMLSelectElement) return;
  if (e.code === 'Space') { e.preventDefault(); setPlaying(!state.playing); }
  if (e.code === 'ArrowRight') { setPlaying(false); seekFrame(state.frame + 1); }
  if (e.code === 'ArrowLeft') { setPlaying(false); seekFrame(state.frame - 1); }
});

function resize() {
  const w = view.clientWidth, h = view.clientHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
  drawPlot();
}
window.addEventListener('resize', resize);

let last = performance.now();
function frameLoop(now) {
  const dt = Math.min((now - last) / 1000, 0.1);  // a hidden tab must not jump ahead
  last = now;
  if (state.playing) {
    state.time += dt * state.speed;
    if (state.time >= duration) {
      if (ui.loop.checked) state.time = duration > 0 ? state.time % duration : 0;
      else { state.time = duration; setPlaying(false); }
    }
    update();
  }
  controls.update();
  renderer.render(scene, camera);
  state.framesRendered++;
  requestAnimationFrame(frameLoop);
}

resize();
update();
renderer.render(scene, camera);

// For scripts and the browser test.
window.fulcrumViewer = {
  objectCount: bodyCount,
  meshCount: bodies.reduce((n, b) => n + b.meshes.length, 0),
  jointCount: rec.joints.length,
  particleSystemCount: particleTracks.length,
  frameCount,
  duration,
  get frame() { return state.frame; },
  get time() { return state.time; },
  get playing() { return state.playing; },
  get framesRendered() { return state.framesRendered; },
  play() { setPlaying(true); },
  pause() { setPlaying(false); },
  seekFrame,
  seekTime,
  setSpeed(s) { state.speed = s; },
  sceneBox() { return new Box3().setFromObject(scene); },
  ready: true,
};
requestAnimationFrame(frameLoop);
