// Fulcrum's live sandbox (docs/browser.md): scenes simulated in the page by
// the WebAssembly module (build-wasm/fulcrum_web.js, through
// apps/web/fulcrum_api.js) and drawn with the replay page's code (stage.js).
// Bundled with three.js by viewer/build-sandbox.mjs into
// build-wasm/sandbox.js; scripts/build-wasm.sh writes the page beside it.
import {
  Box3, Color, Fog, LineSegments, Mesh, MeshStandardMaterial, PCFShadowMap, PerspectiveCamera, Plane, Points, Raycaster,
  Scene, Vector2, Vector3, WebGLRenderer, DoubleSide, InstancedMesh, CylinderGeometry, Matrix4, Quaternion,
  BufferGeometry, BufferAttribute,
} from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { loadFulcrum } from '../../apps/web/fulcrum_api.js';
import { addLights, buildBodies, checkerTexture, createSkyDome, drawAsGround, frameCamera, overlayLines, srgb } from './stage.js';

// A pyramid of 20 rows of unit boxes (the benchmark scene pyramid20).
function pyramid20() {
  const bodies = [{ name: 'ground', type: 'static', shape: { type: 'box', half_extents: [50, 0.5, 50] }, position: [0, -0.5, 0] }];
  for (let row = 0; row < 20; row++) {
    for (let i = 0; i < 20 - row; i++) {
      bodies.push({ name: `pyramid${bodies.length}`, shape: { type: 'box', half_extents: [0.5, 0.5, 0.5] }, mass: 1,
                    position: [i - 0.5 * (19 - row), 0.5 + row, 0] });
    }
  }
  return JSON.stringify({ world: { gravity: [0, -9.81, 0], dt: 1 / 60 }, bodies });
}

const view = document.getElementById('view');
const ui = Object.fromEntries(['scene', 'play', 'step', 'reset', 'speed', 'spawn', 'show-contacts', 'show-sleeping', 'stats', 'status',
  'file']
  .map((id) => [id, document.getElementById(id)]));

const renderer = new WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = PCFShadowMap;
view.prepend(renderer.domElement);
const camera = new PerspectiveCamera(40, 1, 0.05, 500);
const controls = new OrbitControls(camera, renderer.domElement);
controls.enableDamping = true;
controls.dampingFactor = 0.12;
const horizon = new Color(0x8d9bb0), zenith = new Color(0x1f2836);
const checker = checkerTexture();

// Everything of the scene shown now; rebuilt by load().
let live = null;
const state = { playing: true, speed: 1, steps: 0, stepMs: 0, stepMsAverage: 0, fps: 0, framesRendered: 0, contacts: 0 };

// The built-in scenes: pyramid20 and those of sandbox-scenes.js (scripts/build-wasm.sh).
function scenes() {
  return { pyramid20: pyramid20(), ...(window.FULCRUM_SCENES ?? {}) };
}

function clearScene() {
  if (!live) return;
  live.world.destroy();
  live.scene.traverse((o) => { o.geometry?.dispose?.(); });
  live = null;
}

// Builds the three.js scene for a world: bodies, ropes and cloths, overlays, camera.
function show(world, title, text) {
  const scene = new Scene();
  const bodies = buildBodies(scene, world.describeBodies(0).map(packedArrays));
  const structure = world.structure();
  const particleTotal = structure.particles.reduce((n, p) => n + p.count, 0);
  const tracks = structure.particles.map((p) => particleTrack(scene, p));

  // Framing: the bodies that move, as they start.
  const focus = new Box3(), scratch = new Box3();
  const stateView = world.stateView();
  bodies.forEach((b, i) => {
    placeBody(b, stateView, i);
    if (b.rec.type === 'static' || b.local.isEmpty()) return;
    b.group.updateMatrixWorld();
    focus.union(scratch.copy(b.local).applyMatrix4(b.group.matrixWorld));
  });
  if (focus.isEmpty()) focus.setFromCenterAndSize(new Vector3(0, 1, 0), new Vector3(4, 4, 4));
  const focusRadius = Math.max(focus.getSize(new Vector3()).length() / 2, 0.5);
  const sizes = bodies.filter((b) => b.rec.type !== 'static').map((b) => b.extent).sort((x, y) => x - y);
  const typicalSize = Math.max(sizes[sizes.length >> 1] ?? 0.5, focusRadius / 200);
  const tile = 10 ** Math.round(Math.log10(Math.max(typicalSize * 4, 0.05)));
  bodies.forEach((b) => drawAsGround(b, focusRadius * 12, tile, checker));

  const skyDome = createSkyDome(horizon, zenith);
  scene.add(skyDome);
  scene.background = horizon;
  scene.fog = new Fog(horizon, focusRadius * 3, focusRadius * 9);
  addLights(scene, focus.clone().expandByScalar(focusRadius * 0.5), focusRadius * 1.5, typicalSize);
  const maxContacts = 4096;
  const contactPoints = overlayLines(scene, maxContacts, 0xff4040, Points);
  const contactNormals = overlayLines(scene, maxContacts * 2, 0xffe066, LineSegments);
  frameCamera(camera, controls, focus, new Vector3(0.32, 0.42, 1), 0.94, focusRadius);
  skyDome.scale.setScalar(camera.far * 0.5);
  controls.update();

  live = { world, title, text, scene, bodies, tracks, particleTotal, skyDome, contactPoints, contactNormals,
           normalLength: typicalSize * 0.6, typicalSize, spawnCount: 0 };
  state.steps = 0;
  ui.stats.textContent = `${title}: ${bodies.length} bodies · ${structure.joints.length} joints · ` +
                         `${tracks.length} ropes/cloths · dt ${(world.dt * 1000).toFixed(2)} ms`;
  updateDrawing();
}

// The module's body description has plain arrays; three.js wants typed ones.
function packedArrays(body) {
  for (const part of body.parts) {
    part.positions = new Float32Array(part.positions);
    part.normals = new Float32Array(part.normals);
    part.indices = new Uint32Array(part.indices);
  }
  return body;
}

function particleTrack(scene, p) {
  const geometry = new BufferGeometry();
  const position = new BufferAttribute(new Float32Array(p.count * 3), 3);
  geometry.setAttribute('position', position);
  geometry.setIndex(new BufferAttribute(new Uint32Array(p.indices), 1));
  const cloth = p.kind === 'cloth';
  let object;
  if (cloth) {
    geometry.setAttribute('normal', new BufferAttribute(new Float32Array(p.count * 3), 3));
    object = new Mesh(geometry, new MeshStandardMaterial({ color: srgb([0.86, 0.45, 0.2]), roughness: 0.85, side: DoubleSide }));
  } else {
    object = new InstancedMesh(new CylinderGeometry(1, 1, 1, 10, 1, true),
                               new MeshStandardMaterial({ color: srgb([0.93, 0.85, 0.55]), roughness: 0.7 }), p.indices.length / 2);
  }
  object.castShadow = object.receiveShadow = true;
  object.frustumCulled = false;
  scene.add(object);
  return { rec: p, object, geometry, position, cloth };
}

const segment = { matrix: new Matrix4(), axis: new Vector3(), mid: new Vector3(), turn: new Quaternion(),
                  up: new Vector3(0, 1, 0), scale: new Vector3() };
function placeRope(track) {
  const x = track.position.array, index = track.rec.indices, r = Math.max(track.rec.radius, 1e-3);
  for (let s = 0; s < index.length / 2; s++) {
    const a = 3 * index[2 * s], b = 3 * index[2 * s + 1];
    segment.axis.set(x[b] - x[a], x[b + 1] - x[a + 1], x[b + 2] - x[a + 2]);
    const length = segment.axis.length();
    segment.mid.set((x[a] + x[b]) / 2, (x[a + 1] + x[b + 1]) / 2, (x[a + 2] + x[b + 2]) / 2);
    segment.turn.setFromUnitVectors(segment.up, length > 0 ? segment.axis.divideScalar(length) : segment.up);
    segment.matrix.compose(segment.mid, segment.turn, segment.scale.set(r, length, r));
    track.object.setMatrixAt(s, segment.matrix);
  }
  track.object.instanceMatrix.needsUpdate = true;
}

function placeBody(body, s, i) {
  const k = 8 * i;
  body.group.position.set(s[k], s[k + 1], s[k + 2]);
  body.group.quaternion.set(s[k + 3], s[k + 4], s[k + 5], s[k + 6]);
  const asleep = ui['show-sleeping'].checked && body.rec.type === 'dynamic' && s[k + 7] === 0;
  if (asleep !== body.asleep) {
    body.asleep = asleep;
    body.meshes.forEach((m, j) => { m.material = asleep ? body.sleepMaterial[j] : body.awakeMaterial[j]; });
  }
}

// Poses, particles and contacts from the world into the drawing.
function updateDrawing() {
  const { world, bodies, tracks } = live;
  const s = world.stateView();
  bodies.forEach((b, i) => placeBody(b, s, i));
  if (tracks.length > 0) {
    const x = world.particles(live.particleTotal);
    let at = 0;
    for (const track of tracks) {
      const n = track.rec.count * 3;
      track.position.array.set(x.subarray(at, at + n));
      at += n;
      track.position.needsUpdate = true;
      if (track.cloth) track.geometry.computeVertexNormals(); else placeRope(track);
    }
  }
  const showContacts = ui['show-contacts'].checked;
  live.contactPoints.visible = live.contactNormals.visible = showContacts;
  const c = world.contacts();
  state.contacts = c.length / 6;
  if (showContacts) {
    const pts = live.contactPoints.geometry.attributes.position, nrm = live.contactNormals.geometry.attributes.position;
    const count = Math.min(c.length / 6, pts.count);
    for (let k = 0; k < count; k++) {
      const p = 6 * k, L = live.normalLength;
      pts.setXYZ(k, c[p], c[p + 1], c[p + 2]);
      nrm.setXYZ(2 * k, c[p], c[p + 1], c[p + 2]);
      nrm.setXYZ(2 * k + 1, c[p] + c[p + 3] * L, c[p + 1] + c[p + 4] * L, c[p + 2] + c[p + 5] * L);
    }
    pts.needsUpdate = nrm.needsUpdate = true;
    live.contactPoints.geometry.setDrawRange(0, count);
    live.contactNormals.geometry.setDrawRange(0, 2 * count);
  }
}

let fulcrum = null;
function load(name, text) {
  try {
    const world = fulcrum.worldFromScene(text);
    clearScene();
    show(world, name, text);
    ui.status.textContent = '';
  } catch (e) {
    ui.status.textContent = String(e.message ?? e);
  }
}

function step(count) {
  const t0 = performance.now();
  live.world.step(count);
  const ms = (performance.now() - t0) / count;
  state.steps += count;
  state.stepMs = ms;
  state.stepMsAverage = state.stepMsAverage > 0 ? state.stepMsAverage * 0.9 + ms * 0.1 : ms;
}

// ---- picking: drag a body (a spring to the pointer), throw it, or spawn a shape on a click
const raycaster = new Raycaster();
const pointer = new Vector2();
let drag = null, down = null;
function ray(clientX, clientY) {
  const r = renderer.domElement.getBoundingClientRect();
  pointer.set(((clientX - r.left) / r.width) * 2 - 1, 1 - ((clientY - r.top) / r.height) * 2);
  raycaster.setFromCamera(pointer, camera);
  return raycaster;
}
function hitBody(clientX, clientY) {
  const meshes = live.bodies.flatMap((b) => b.meshes);
  return ray(clientX, clientY).intersectObjects(meshes, false)[0];
}
renderer.domElement.addEventListener('pointerdown', (e) => {
  if (!live || e.button !== 0) return;
  down = { x: e.clientX, y: e.clientY };
  const hit = hitBody(e.clientX, e.clientY);
  const body = hit ? live.bodies[hit.object.userData.bodyIndex] : null;
  if (body && body.rec.type === 'dynamic') {
    controls.enabled = false;
    const normal = camera.getWorldDirection(new Vector3());
    drag = { body: hit.object.userData.bodyIndex, plane: new Plane().setFromNormalAndCoplanarPoint(normal, hit.point) };
    live.world.grab(drag.body, hit.point.toArray());
    renderer.domElement.setPointerCapture(e.pointerId);
  }
}, { capture: true });  // before OrbitControls' own listener: a grab does not also orbit
renderer.domElement.addEventListener('pointermove', (e) => {
  if (!drag) return;
  const target = ray(e.clientX, e.clientY).ray.intersectPlane(drag.plane, new Vector3());
  if (target) live.world.moveGrab(target.toArray());
});
renderer.domElement.addEventListener('pointerup', (e) => {
  if (drag) {  // let go: the body keeps the velocity the spring gave it (a throw)
    live.world.release();
    drag = null;
    controls.enabled = true;
  } else if (down && Math.hypot(e.clientX - down.x, e.clientY - down.y) < 5 && ui.spawn.value !== 'none') {
    spawn(e.clientX, e.clientY);
  }
  down = null;
});

// A new body dropped from above the clicked point (or in front of the camera).
function spawn(clientX, clientY) {
  const hit = ray(clientX, clientY).intersectObjects(live.bodies.flatMap((b) => b.meshes), false)[0];
  const at = hit ? hit.point.clone() : raycaster.ray.at(live.typicalSize * 10, new Vector3());
  const size = Math.max(live.typicalSize, 0.2);
  at.y += size * 3;
  const shapes = {
    box: { type: 'box', halfExtents: [size / 2, size / 2, size / 2] },
    sphere: { type: 'sphere', radius: size / 2 },
    capsule: { type: 'capsule', radius: size / 4, halfHeight: size / 3 },
  };
  const first = live.world.bodyCount;
  live.world.addBody({ name: `spawned${++live.spawnCount}`, shape: shapes[ui.spawn.value], position: at.toArray(), mass: 1 });
  live.bodies.push(...buildBodies(live.scene, live.world.describeBodies(first).map(packedArrays), first));
  updateDrawing();
}

// ---- controls
function setPlaying(playing) {
  state.playing = playing;
  ui.play.textContent = playing ? 'Pause' : 'Play';
}
ui.play.addEventListener('click', () => setPlaying(!state.playing));
ui.step.addEventListener('click', () => { setPlaying(false); step(1); updateDrawing(); });
ui.reset.addEventListener('click', () => load(live.title, live.text));
ui.speed.addEventListener('change', () => { state.speed = Number(ui.speed.value); });
ui.scene.addEventListener('change', () => load(ui.scene.value, scenes()[ui.scene.value]));
for (const box of [ui['show-contacts'], ui['show-sleeping']]) box.addEventListener('change', () => updateDrawing());
ui.file.addEventListener('change', async () => {
  const file = ui.file.files[0];
  if (file) load(file.name, await file.text());
});
window.addEventListener('dragover', (e) => e.preventDefault());
window.addEventListener('drop', async (e) => {
  e.preventDefault();
  const file = e.dataTransfer?.files?.[0];
  if (file) load(file.name, await file.text());
});
window.addEventListener('keydown', (e) => {
  if (e.target instanceof HTMLSelectElement) return;
  if (e.code === 'Space') { e.preventDefault(); setPlaying(!state.playing); }
  if (e.code === 'ArrowRight') { setPlaying(false); step(1); updateDrawing(); }
  if (e.code === 'KeyR') load(live.title, live.text);
});

function resize() {
  const w = view.clientWidth, h = view.clientHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);

// Real time: the steps due since the last frame at the chosen speed (at most
// 4 a frame, so a slow machine slows the simulation down rather than stalling).
let last = performance.now(), debt = 0, fpsFrames = 0, fpsSince = last;
function frame(now) {
  const elapsed = Math.min((now - last) / 1000, 0.1);
  last = now;
  if (live && state.playing) {
    debt += elapsed * state.speed;
    const due = Math.min(Math.floor(debt / live.world.dt), 4);
    debt = due === 4 ? 0 : debt - due * live.world.dt;
    if (due > 0) { step(due); updateDrawing(); }
  }
  if (++fpsFrames >= 20) {
    state.fps = (fpsFrames * 1000) / (now - fpsSince);
    fpsFrames = 0;
    fpsSince = now;
  }
  if (live) {
    document.getElementById('profile').textContent =
      `t = ${live.world.time.toFixed(2)} s · step ${state.stepMsAverage.toFixed(2)} ms · ${state.fps.toFixed(0)} fps · ` +
      `${state.contacts ?? 0} contacts`;
    controls.update();
    live.skyDome.position.copy(camera.position);
    renderer.render(live.scene, camera);
  }
  state.framesRendered++;
  requestAnimationFrame(frame);
}

// Where a world point is on the screen (client pixels), for scripts and the test.
function screenOf(point) {
  const r = renderer.domElement.getBoundingClientRect();
  const p = new Vector3(...point).project(camera);
  return { x: r.left + ((p.x + 1) / 2) * r.width, y: r.top + ((1 - p.y) / 2) * r.height, inside: Math.abs(p.x) < 1 && Math.abs(p.y) < 1 };
}

async function main() {
  fulcrum = await loadFulcrum(window.createFulcrumModule);
  const all = scenes();
  for (const name of Object.keys(all)) ui.scene.append(new Option(name, name));
  const first = new URLSearchParams(location.search).get('scene') ?? 'pyramid20';
  ui.scene.value = first in all ? first : 'pyramid20';
  resize();
  load(ui.scene.value, all[ui.scene.value]);
  setPlaying(true);
  window.fulcrumSandbox = {
    ready: true,
    fulcrum,
    get world() { return live.world; },
    get steps() { return state.steps; },
    get stepMs() { return state.stepMsAverage; },
    get fps() { return state.fps; },
    get framesRendered() { return state.framesRendered; },
    get playing() { return state.playing; },
    get sceneNames() { return Object.keys(scenes()); },
    camera,
    load(name, text = scenes()[name]) { load(name, text); return ui.status.textContent; },
    play() { setPlaying(true); },
    pause() { setPlaying(false); },
    step(count = 1) { step(count); updateDrawing(); },
    stateHash() { return live.world.stateHash(); },
    bodies() {
      const s = live.world.stateView();
      return live.bodies.map((b, i) => ({ name: b.rec.name, type: b.rec.type, position: [s[8 * i], s[8 * i + 1], s[8 * i + 2]] }));
    },
    screenOf,
  };
  requestAnimationFrame(frame);
}

main().catch((e) => {
  ui.status.textContent = `The sandbox could not start: ${e?.message ?? e}`;
  throw e;
});
