// Fulcrum replay viewer. Bundled with three.js into viewer/dist/viewer.js
// (viewer/build.mjs) and embedded in every recorded HTML page by the C++
// writer; it reads the recording from <script id="fulcrum-recording">.
// The data format and the controls are documented in docs/recording.md.
import {
  Box3, BoxGeometry, BufferAttribute, BufferGeometry, Color, CylinderGeometry, DoubleSide, EdgesGeometry, Fog,
  InstancedMesh, LineBasicMaterial, LineSegments, Matrix4, Mesh, MeshStandardMaterial, PCFShadowMap, PerspectiveCamera,
  Points, Quaternion, Raycaster, Scene, Vector2, Vector3, WebGLRenderer,
} from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { createCameraChoice } from './camera.js';
import { addLights, buildBodies, checkerTexture, createSkyDome, drawAsGround, frameCamera, overlayLines, srgb } from './stage.js';
import { paintTerrain } from './terrain.js';
import { createVehicles } from './vehicles.js';

// ---- data -----------------------------------------------------------------

const arrayTypes = { float32: Float32Array, float64: Float64Array, uint32: Uint32Array, uint8: Uint8Array };

function base64Bytes(text) {
  const bin = atob(text);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  return bytes;
}

// Undoes the writer's packing (src/io/html_writer.cpp, packed()): inflate,
// gather the byte planes back into elements, then undo the XOR with the
// element `xor` places earlier (front to back, each from the restored one).
async function unpack(array) {
  const Type = arrayTypes[array?.type];
  if (!Type) return new Float32Array(0);
  const stream = new Blob([base64Bytes(array.deflate)]).stream().pipeThrough(new DecompressionStream('deflate'));
  const planes = new Uint8Array(await new Response(stream).arrayBuffer());
  const size = Type.BYTES_PER_ELEMENT, n = array.length;
  if (planes.length !== n * size) throw new Error(`recording: an array inflated to ${planes.length} bytes, expected ${n * size}`);
  const bytes = new Uint8Array(n * size);
  for (let b = 0; b < size; b++) {
    for (let i = 0, at = b * n; i < n; i++) bytes[i * size + b] = planes[at + i];
  }
  const distance = array.xor * size;
  if (distance > 0) for (let i = distance; i < bytes.length; i++) bytes[i] ^= bytes[i - distance];
  return new Type(bytes.buffer);
}

// Every packed array of the document, decoded in place.
async function decodeRecording(rec) {
  const jobs = [];
  const decode = (holder, key) => jobs.push(unpack(holder[key]).then((a) => { holder[key] = a; }));
  for (const key of ['times', 'transforms', 'awake', 'bounds', 'contactOffsets', 'contacts', 'jointErrors', 'energy', 'momentum']) decode(rec, key);
  for (const body of rec.bodies) for (const part of body.parts) for (const key of ['positions', 'normals', 'indices']) decode(part, key);
  for (const mesh of rec.visualMeshes ?? []) for (const key of ['positions', 'normals', 'indices']) decode(mesh, key);
  for (const track of rec.particles ?? []) for (const key of ['indices', 'positions']) decode(track, key);
  for (const vehicle of rec.vehicles ?? []) decode(vehicle, 'poses');
  await Promise.all(jobs);
  return rec;
}

// Bodies whose names share a stem form one labelled group: the name less its
// trailing digits, less its last "_part" if it has one ("pyramid7" ->
// "pyramid", "pile_sphere0" -> "pile", "spring_chain_mass2" -> "spring_chain").
function groupOf(name) {
  const stem = name.replace(/\d+$/, '');
  const cut = stem.lastIndexOf('_');
  return (cut > 0 ? stem.slice(0, cut) : stem) || name;
}

function percentile(sorted, p) {
  if (sorted.length === 0) return 0;
  return sorted[Math.min(sorted.length - 1, Math.max(0, Math.round(p * (sorted.length - 1))))];
}

// ---- viewer -----------------------------------------------------------------

function start(rec) {
  const frameCount = rec.frames;
  const bodyCount = rec.bodies.length;
  const { times, transforms, awake, bounds, contactOffsets, contacts, energy } = rec;
  const t0 = frameCount > 0 ? times[0] : 0;
  const duration = frameCount > 0 ? times[frameCount - 1] - t0 : 0;
  const isMoving = (body) => body.type !== 'static';
  // The world's up (against gravity; docs/recording.md): y, or z for a z-up
  // world such as a URDF robot's. The camera, the sky and the sun turn with it.
  const worldUp = new Vector3(...(rec.up ?? [0, 1, 0])).normalize();
  const upTurn = new Quaternion().setFromUnitVectors(new Vector3(0, 1, 0), worldUp);

  const view = document.getElementById('view');
  const renderer = new WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
  renderer.shadowMap.enabled = true;
  renderer.shadowMap.type = PCFShadowMap;
  view.prepend(renderer.domElement);

  const scene = new Scene();

  // ---- bodies (stage.js)
  const bodies = buildBodies(scene, rec.bodies, 0, rec.visualMeshes ?? []);
  const hasVisuals = bodies.some((b) => b.visuals.length > 0);
  const vehicleView = createVehicles(rec, bodies, srgb);  // wheels, on their chassis (vehicles.js)
  paintTerrain(bodies);                                   // heightfields as grass (terrain.js)

  // ---- ropes and cloths: fixed topology, positions rewritten every frame
  const particleTracks = (rec.particles ?? []).map((track) => {
    const count = track.count;
    const geometry = new BufferGeometry();
    const position = new BufferAttribute(new Float32Array(count * 3), 3);
    geometry.setAttribute('position', position);
    geometry.setIndex(new BufferAttribute(track.indices, 1));
    const cloth = track.kind === 'cloth';
    let object;
    if (cloth) {
      geometry.setAttribute('normal', new BufferAttribute(new Float32Array(count * 3), 3));
      object = new Mesh(geometry, new MeshStandardMaterial({ color: srgb([0.86, 0.45, 0.2]), roughness: 0.85, side: DoubleSide }));
      object.castShadow = object.receiveShadow = true;
    } else {
      // A rope: one cylinder of the particles' radius per segment.
      const segments = track.indices.length / 2;
      object = new InstancedMesh(new CylinderGeometry(1, 1, 1, 10, 1, true),
                                 new MeshStandardMaterial({ color: srgb([0.93, 0.85, 0.55]), roughness: 0.7 }), segments);
      object.castShadow = object.receiveShadow = true;
    }
    object.name = track.name;
    object.frustumCulled = false;  // the bounds change every frame
    scene.add(object);
    return { rec: track, object, geometry, position, cloth, count, frames: track.positions, box: new Box3() };
  });
  const segmentMatrix = new Matrix4(), segmentAxis = new Vector3(), segmentMid = new Vector3(), segmentTurn = new Quaternion();
  const up = new Vector3(0, 1, 0), segmentScale = new Vector3();
  function placeRopeSegments(track) {
    const x = track.position.array, index = track.rec.indices, r = Math.max(track.rec.radius, 1e-3);
    for (let s = 0; s < index.length / 2; s++) {
      const a = 3 * index[2 * s], b = 3 * index[2 * s + 1];
      segmentAxis.set(x[b] - x[a], x[b + 1] - x[a + 1], x[b + 2] - x[a + 2]);
      const length = segmentAxis.length();
      segmentMid.set((x[a] + x[b]) / 2, (x[a + 1] + x[b + 1]) / 2, (x[a + 2] + x[b + 2]) / 2);
      segmentTurn.setFromUnitVectors(up, length > 0 ? segmentAxis.divideScalar(length) : up);
      segmentMatrix.compose(segmentMid, segmentTurn, segmentScale.set(r, length, r));
      track.object.setMatrixAt(s, segmentMatrix);
    }
    track.object.instanceMatrix.needsUpdate = true;
  }

  function updateParticles(frame, alpha) {
    for (const track of particleTracks) {
      const n = track.count * 3, a = frame * n, out = track.position.array, x = track.frames;
      const b = alpha > 0 && frame + 1 < frameCount ? a + n : a;
      for (let k = 0; k < n; k++) out[k] = x[a + k] + (x[b + k] - x[a + k]) * alpha;
      track.position.needsUpdate = true;
      track.box.setFromArray(out);
      if (track.cloth) track.geometry.computeVertexNormals();
      else placeRopeSegments(track);
    }
  }

  // ---- framing: the moving bodies over the run, robustly.
  // Each moving body (and rope or cloth) contributes the box of its origin's
  // 5th to 95th percentile positions over the run, grown by its size; bodies
  // far outside the core of the others (flung away) are clipped off, and
  // static bodies and planes take no part.
  const stride = Math.max(1, Math.floor(frameCount / 300));
  const boxes = [];
  function trimmedBox(sample, grow) {
    const axes = [[], [], []];
    for (let f = 0; f < frameCount; f += stride) sample(f, axes);
    axes.forEach((a) => a.sort((x, y) => x - y));
    const box = new Box3(new Vector3(...axes.map((a) => percentile(a, 0.05))), new Vector3(...axes.map((a) => percentile(a, 0.95))));
    return box.expandByScalar(grow);
  }
  bodies.forEach((body, b) => {
    if (!isMoving(body.rec)) return;
    boxes.push(trimmedBox((f, axes) => { for (let k = 0; k < 3; k++) axes[k].push(transforms[(f * bodyCount + b) * 7 + k]); }, body.extent));
  });
  for (const track of particleTracks) {
    boxes.push(trimmedBox((f, axes) => {
      for (let p = 0; p < track.count; p += Math.max(1, track.count >> 4)) {
        for (let k = 0; k < 3; k++) axes[k].push(track.frames[(f * track.count + p) * 3 + k]);
      }
    }, track.rec.radius));
  }
  const focus = new Box3();
  if (boxes.length > 0) {
    const centres = [[], [], []];
    boxes.forEach((box) => box.getCenter(new Vector3()).toArray().forEach((v, k) => centres[k].push(v)));
    centres.forEach((c) => c.sort((x, y) => x - y));
    const core = new Box3(new Vector3(...centres.map((c) => percentile(c, 0.1))), new Vector3(...centres.map((c) => percentile(c, 0.9))));
    const sizes = bodies.filter((b) => isMoving(b.rec)).map((b) => b.extent).sort((x, y) => x - y);
    const reach = Math.max(core.getSize(new Vector3()).length(), 8 * percentile(sizes, 0.5), 1);
    const allowed = core.clone().expandByScalar(reach);
    for (const box of boxes) focus.union(box.clone().intersect(allowed));
  }
  if (focus.isEmpty()) {  // nothing moves: frame what the run starts from
    const start = rec.start ?? rec.scene;
    focus.setFromCenterAndSize(new Vector3(...start.center), new Vector3(1, 1, 1).multiplyScalar(2 * Math.max(start.radius, 0.5)));
  }
  const focusCenter = focus.getCenter(new Vector3());
  const focusSize = focus.getSize(new Vector3());
  const focusRadius = Math.max(focusSize.length() / 2, 0.5);
  const movingSizes = bodies.filter((b) => isMoving(b.rec)).map((b) => b.extent).sort((x, y) => x - y);
  const typicalSize = Math.max(percentile(movingSizes, 0.5), focusRadius / 200);

  // ---- camera: from the front, a little to the right and above, at the
  // distance where every corner of the focus box is inside the view.
  const camera = new PerspectiveCamera(40, 1, focusRadius / 500, focusRadius * 60);
  camera.up.copy(worldUp);  // before the controls, which orbit about it
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.enableDamping = true;
  controls.dampingFactor = 0.12;
  const viewDirection = new Vector3(0.32, 0.42, 1).applyQuaternion(upTurn).normalize();
  const cameraChoice = createCameraChoice({ camera, controls, bodies, vehicles: vehicleView.list, characters: rec.characters ?? [] });

  function frameBox(box, direction = viewDirection, margin = 0.94) {
    frameCamera(camera, controls, box, direction, margin, focusRadius);
    skyDome.scale.setScalar(camera.far * 0.5);
    skyDome.position.copy(camera.position);
    controls.update();
  }

  // ---- lights: a sky/ground fill and a sun whose shadow map covers the focus
  // A sky dome around the camera: the fog's colour at and below the horizon
  // (where the ground fades into it), darkening towards the zenith.
  const horizon = new Color(0x8d9bb0), zenith = new Color(0x1f2836);
  const skyDome = createSkyDome(horizon, zenith);
  skyDome.quaternion.copy(upTurn);
  scene.add(skyDome);
  scene.background = horizon;
  scene.fog = new Fog(horizon, focusRadius * 3, focusRadius * 9);
  addLights(scene, focus, focusRadius, typicalSize, upTurn);

  // ---- a ground that reads as one: planes drawn as a large checkered floor
  // (tiles of a round number of metres) fading into the horizon.
  const tile = 10 ** Math.round(Math.log10(Math.max(typicalSize * 4, 0.05)));
  const checker = checkerTexture();
  bodies.forEach((body) => drawAsGround(body, focusRadius * 12, tile, checker));

  // ---- overlays: contacts and normals, joints, AABBs; buffers sized for the busiest frame
  let maxContacts = 0;
  for (let f = 0; f < frameCount; f++) maxContacts = Math.max(maxContacts, contactOffsets[f + 1] - contactOffsets[f]);
  const dynamicLines = (vertexCount, color, PointsOrLines, extra) => overlayLines(scene, vertexCount, color, PointsOrLines, extra);
  const contactPoints = dynamicLines(maxContacts, 0xff4040, Points);
  const contactNormals = dynamicLines(maxContacts * 2, 0xffe066, LineSegments);
  const jointLines = dynamicLines(rec.joints.length * 2, 0x7cf0ff, LineSegments);
  const jointPoints = dynamicLines(rec.joints.length * 2, 0x7cf0ff, Points);
  const aabbLines = dynamicLines(bodyCount * 24, 0x9aff9a, LineSegments, { transparent: true, opacity: 0.7 });
  const normalLength = typicalSize * 0.6;  // about the size of a typical body, whatever the scene's extent

  // ---- labels: one per group of bodies (and rope or cloth) that moves
  const labelLayer = document.getElementById('labels');
  const groups = new Map();
  const member = (name) => {
    const key = groupOf(name);
    if (!groups.has(key)) groups.set(key, { key, bodies: [], tracks: [], moving: false });
    return groups.get(key);
  };
  bodies.forEach((body, b) => {
    if (body.rec.shape === 'plane') return;
    const g = member(body.rec.name);
    g.bodies.push(b);
    g.moving ||= isMoving(body.rec);
  });
  particleTracks.forEach((track) => { const g = member(track.rec.name); g.tracks.push(track); g.moving = true; });
  const labelled = [...groups.values()].filter((g) => g.moving && g.key.trim() !== '');
  const labels = labelled.length <= 40 ? labelled : [];
  for (const g of labels) {
    g.element = document.createElement('div');
    g.element.className = 'label';
    g.element.textContent = g.key.replace(/_/g, ' ');
    g.element.title = 'click: look at it';
    g.element.addEventListener('click', () => lookAt(groupBox(g)));
    labelLayer.appendChild(g.element);
    g.box = new Box3();
  }
  const scratchBox = new Box3();
  function groupBox(g) {
    g.box = g.box ?? new Box3();
    g.box.makeEmpty();
    for (const b of g.bodies) {
      const body = bodies[b];
      if (body.local.isEmpty()) continue;
      g.box.union(scratchBox.copy(body.local).applyMatrix4(body.group.matrixWorld));
    }
    for (const track of g.tracks) g.box.union(track.box);
    return g.box;
  }
  const projected = new Vector3(), labelSize = new Vector3();
  const upAbs = new Vector3(Math.abs(worldUp.x), Math.abs(worldUp.y), Math.abs(worldUp.z));
  function placeLabels() {
    const w = view.clientWidth, h = view.clientHeight;
    for (const g of labels) {
      const box = groupBox(g);
      if (box.isEmpty() || !ui.labels.checked) { g.element.style.display = 'none'; continue; }
      // Above the group's box: its centre moved along up to the box's top.
      box.getCenter(projected);
      box.getSize(labelSize);
      projected.addScaledVector(worldUp, 0.5 * labelSize.dot(upAbs)).project(camera);
      const visible = projected.z < 1 && Math.abs(projected.x) < 1.1 && Math.abs(projected.y) < 1.1;
      g.element.style.display = visible ? '' : 'none';
      if (visible) {
        g.element.style.transform =
          `translate(${((projected.x + 1) / 2) * w}px, ${((1 - projected.y) / 2) * h}px) translate(-50%, -100%) translateY(-6px)`;
      }
    }
  }

  // ---- state and controls
  const ui = {
    play: document.getElementById('play'),
    timeline: document.getElementById('timeline'),
    time: document.getElementById('time'),
    speed: document.getElementById('speed'),
    contacts: document.getElementById('show-contacts'),
    normals: document.getElementById('show-normals'),
    joints: document.getElementById('show-joints'),
    aabbs: document.getElementById('show-aabbs'),
    labels: document.getElementById('show-labels'),
    sleeping: document.getElementById('show-sleeping'),
    collision: document.getElementById('show-collision'),
    loop: document.getElementById('loop'),
    plot: document.getElementById('plot'),
    readout: document.getElementById('readout'),
  };
  document.getElementById('title').textContent = rec.title;
  document.getElementById('stats').textContent =
    `${bodyCount} bodies · ${rec.joints.length} joints · ${particleTracks.length} ropes/cloths · ` +
    `${frameCount} frames · ${duration.toFixed(2)} s`;
  document.title = rec.title;
  ui.timeline.max = String(Math.max(frameCount - 1, 0));
  // Bodies with visuals (robot links) are drawn as them; "collision shapes"
  // draws what collides instead. Offered only when some body has visuals.
  if (!hasVisuals) ui.collision.parentElement.style.display = 'none';
  function showCollision(shown) {
    for (const body of bodies) {
      if (body.visuals.length === 0) continue;
      body.meshes.forEach((m) => { m.visible = shown; });
      body.visuals.forEach((m) => { m.visible = !shown; });
    }
  }
  ui.collision.addEventListener('change', () => showCollision(ui.collision.checked));

  const state = { playing: false, time: 0, frame: 0, alpha: 0, speed: 1, framesRendered: 0, selected: -1 };

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

  const qb = new Quaternion(), va = new Vector3(), vb = new Vector3();
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
    state.alpha = alpha;
    for (let b = 0; b < bodyCount; b++) {
      const body = bodies[b];
      bodyPose(frame, alpha, b, body.group.position, body.group.quaternion);
      body.group.updateMatrixWorld();
      const asleep = ui.sleeping.checked && isMoving(body.rec) && awake[frame * bodyCount + b] === 0;
      if (asleep !== body.asleep) {
        body.asleep = asleep;
        body.meshes.forEach((m, k) => { m.material = asleep ? body.sleepMaterial[k] : body.awakeMaterial[k]; });
      }
    }
    vehicleView.update(frame, alpha);
    updateParticles(frame, alpha);
    // Contacts of the frame shown (not interpolated: they belong to a step).
    const c0 = contactOffsets[frame] ?? 0, c1 = contactOffsets[frame + 1] ?? 0;
    contactPoints.visible = ui.contacts.checked;
    contactNormals.visible = ui.contacts.checked && ui.normals.checked;
    if (contactPoints.visible) {
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
    }

    jointLines.visible = jointPoints.visible = ui.joints.checked;
    if (jointLines.visible) {
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
    }

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
    ui.time.textContent = `t = ${(t0 + state.time).toFixed(2)} s · frame ${frame + 1}/${frameCount}`;
    updateReadout();
    drawPlot();
  }

  // ---- picking: a click (not a drag) on a body selects it; the readout
  // shows its recorded state, velocities by central differences of the poses.
  const raycaster = new Raycaster();
  const pickable = bodies.flatMap((b) => (b.rec.shape === 'plane' ? [] : b.meshes.concat(b.visuals)));
  const tintable = (body) => body.awakeMaterial.concat(body.sleepMaterial, body.visuals.map((m) => m.material));
  // The selection: tinted, and outlined by its body-frame box (a child of the body, so it follows it).
  const outline = new LineSegments(new EdgesGeometry(new BoxGeometry(1, 1, 1)),
                                   new LineBasicMaterial({ color: 0xf0b24a, depthTest: false, transparent: true }));
  outline.renderOrder = 11;
  function select(index) {
    if (state.selected >= 0) tintable(bodies[state.selected]).forEach((m) => m.emissive.setHex(0));
    outline.removeFromParent();
    state.selected = index;
    if (index >= 0) {
      const body = bodies[index];
      tintable(body).forEach((m) => m.emissive.setHex(0x4a2c00));
      body.local.getCenter(outline.position);
      body.local.getSize(outline.scale).addScalar(typicalSize * 0.08);
      body.group.add(outline);
    }
    ui.readout.hidden = index < 0;
    updateReadout();
  }
  function pick(clientX, clientY) {
    const r = renderer.domElement.getBoundingClientRect();
    raycaster.setFromCamera(new Vector2(((clientX - r.left) / r.width) * 2 - 1, 1 - ((clientY - r.top) / r.height) * 2), camera);
    const hit = raycaster.intersectObjects(pickable, false)[0];
    select(hit ? hit.object.userData.bodyIndex : -1);
  }
  let down = null;
  renderer.domElement.addEventListener('pointerdown', (e) => { down = { x: e.clientX, y: e.clientY, button: e.button }; });
  renderer.domElement.addEventListener('pointerup', (e) => {
    if (down && down.button === 0 && Math.hypot(e.clientX - down.x, e.clientY - down.y) < 5) pick(e.clientX, e.clientY);
    down = null;
  });
  renderer.domElement.addEventListener('dblclick', () => { if (state.selected >= 0) lookAt(groupBox({ bodies: [state.selected], tracks: [] })); });

  const fmt = (v) => v.map((x) => (Math.abs(x) < 5e-4 ? 0 : x).toFixed(3)).join(', ');  // no "-0.000"
  function updateReadout() {
    if (state.selected < 0 || ui.readout.hidden) return;
    const b = state.selected, body = rec.bodies[b];
    const k0 = Math.max(state.frame - 1, 0), k1 = Math.min(state.frame + 1, frameCount - 1);
    const dt = k1 > k0 ? times[k1] - times[k0] : 0;
    const at = (k, c) => transforms[(k * bodyCount + b) * 7 + c];
    const velocity = [0, 1, 2].map((c) => (dt > 0 ? (at(k1, c) - at(k0, c)) / dt : 0));
    // Angular speed from the rotation between the two poses: 2 acos|q1 . q0| / dt.
    let dot = 0;
    for (let c = 3; c < 7; c++) dot += at(k1, c) * at(k0, c);
    const omega = dt > 0 ? (2 * Math.acos(Math.min(1, Math.abs(dot)))) / dt : 0;
    const p = bodies[b].group.position;
    const rows = [
      ['', `${body.type} ${body.shape}`],
      ...(body.mass > 0 ? [['mass', `${body.mass.toPrecision(4)} kg`]] : []),
      ['position', `${fmt([p.x, p.y, p.z])} m`],
      ['velocity', `${fmt(velocity)} m/s`],
      ['speed', `${Math.hypot(...velocity).toFixed(3)} m/s · ${omega.toFixed(2)} rad/s`],
      ['state', awake[state.frame * bodyCount + b] ? 'awake' : 'asleep'],
    ];
    ui.readout.replaceChildren();
    const title = document.createElement('b');
    title.textContent = body.name;
    ui.readout.append(title);
    for (const [key, value] of rows) {
      const line = document.createElement('div');
      line.textContent = key ? `${key}: ${value}` : value;
      ui.readout.append(line);
    }
  }

  // Smoothly moves the camera to look at a box (a label's group, the selection).
  let flight = null;
  function lookAt(box) {
    if (box.isEmpty()) return;
    const from = { position: camera.position.clone(), target: controls.target.clone() };
    const direction = camera.position.clone().sub(controls.target);
    const near = box.clone().expandByScalar(box.getSize(new Vector3()).length() * 0.15);
    frameBox(near, direction, 0.7);
    flight = { from, to: { position: camera.position.clone(), target: controls.target.clone() }, start: performance.now() };
    camera.position.copy(from.position);
    controls.target.copy(from.target);
  }

  // ---- energy plot
  const series = [
    { name: 'kinetic', color: '#ff7a6b', offset: 0 },
    { name: 'potential', color: '#6bb5ff', offset: 1 },
    { name: 'total', color: '#f2f2f2', offset: 2 },
  ];
  let eMin = Infinity, eMax = -Infinity;
  for (let i = 0; i < energy.length; i++) { eMin = Math.min(eMin, energy[i]); eMax = Math.max(eMax, energy[i]); }
  if (!(eMax > eMin)) { eMin -= 1; eMax += 1; }
  const plotPad = { left: 64, right: 12, top: 8, bottom: 18 };

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
    const yOf = (e) => y1 - ((e - eMin) / (eMax - eMin)) * (y1 - y0);
    g.strokeStyle = '#3a4250'; g.lineWidth = 1; g.fillStyle = '#98a1b2'; g.font = '11px system-ui, sans-serif';
    g.beginPath(); g.moveTo(x0, y0); g.lineTo(x0, y1); g.lineTo(x1, y1); g.stroke();
    g.textAlign = 'right'; g.textBaseline = 'middle';
    for (const e of [eMin, eMax]) g.fillText(`${e.toPrecision(4)} J`, x0 - 6, yOf(e));
    g.textAlign = 'center'; g.textBaseline = 'top';
    g.fillText(`${t0.toFixed(2)} s`, x0, y1 + 3); g.fillText(`${(t0 + duration).toFixed(2)} s`, x1 - 14, y1 + 3);
    for (const s of series) {
      g.strokeStyle = s.color; g.lineWidth = 1.5; g.beginPath();
      const step = Math.max(1, Math.floor(frameCount / Math.max(1, 2 * (x1 - x0))));  // ~2 samples per pixel column
      for (let f = 0; f < frameCount; f += step) {
        const x = xOf(times[f]), y = yOf(energy[f * 3 + s.offset]);
        if (f === 0) g.moveTo(x, y); else g.lineTo(x, y);
      }
      g.stroke();
    }
    g.textAlign = 'left'; g.textBaseline = 'top';
    series.forEach((s, i) => { g.fillStyle = s.color; g.fillText(s.name, x1 - 210 + i * 72, y0); });
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

  // ---- playback
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
  for (const box of [ui.contacts, ui.normals, ui.joints, ui.aabbs, ui.sleeping, ui.labels]) box.addEventListener('change', update);
  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLSelectElement) return;
    if (e.code === 'Space') { e.preventDefault(); setPlaying(!state.playing); }
    if (e.code === 'ArrowRight') { setPlaying(false); seekFrame(state.frame + 1); }
    if (e.code === 'ArrowLeft') { setPlaying(false); seekFrame(state.frame - 1); }
    if (e.code === 'Escape') select(-1);
    if (e.code === 'KeyF') { if (state.selected >= 0) lookAt(groupBox({ bodies: [state.selected], tracks: [] })); else frameBox(focus); }
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
    if (flight) {
      const u = Math.min((now - flight.start) / 600, 1), s = u * u * (3 - 2 * u);
      camera.position.lerpVectors(flight.from.position, flight.to.position, s);
      controls.target.lerpVectors(flight.from.target, flight.to.target, s);
      if (u >= 1) flight = null;
    }
    cameraChoice.update(dt);
    controls.update();
    skyDome.position.copy(camera.position);
    placeLabels();
    renderer.render(scene, camera);
    state.framesRendered++;
    requestAnimationFrame(frameLoop);
  }

  resize();
  frameBox(focus);
  update();
  placeLabels();
  renderer.render(scene, camera);
  setPlaying(true);  // open playing, looping

  // For scripts and the browser test.
  window.fulcrumViewer = {
    objectCount: bodyCount,
    meshCount: bodies.reduce((n, b) => n + b.meshes.length, 0),
    up: worldUp.toArray(),
    visualCount: bodies.reduce((n, b) => n + b.visuals.length, 0),
    visualMeshCount: (rec.visualMeshes ?? []).length,
    // Every visual as drawn now: its body, whether shown, its colour (hex,
    // sRGB), its world position and the world size of its box.
    visuals() {
      return bodies.flatMap((b) => b.visuals.map((m) => {
        m.updateMatrixWorld();
        const box = new Box3().setFromObject(m);
        return { body: b.rec.name, visible: m.visible, color: m.material.color.getHexString(), opacity: m.material.opacity,
                 position: m.getWorldPosition(new Vector3()).toArray(), size: box.getSize(new Vector3()).toArray() };
      }));
    },
    get collisionShown() { return bodies.some((b) => b.visuals.length > 0 && b.meshes.some((m) => m.visible)); },
    showCollision(shown) { ui.collision.checked = shown; showCollision(shown); },
    jointCount: rec.joints.length,
    particleSystemCount: particleTracks.length,
    vehicles: vehicleView,
    cameraChoice,
    frameCount,
    duration,
    camera,
    scene,
    renderer,
    get frame() { return state.frame; },
    get time() { return state.time; },
    get playing() { return state.playing; },
    get framesRendered() { return state.framesRendered; },
    get selected() { return state.selected >= 0 ? rec.bodies[state.selected].name : null; },
    get labels() { return labels.map((g) => g.element.textContent); },
    get overlays() {
      return { contacts: contactPoints.visible, normals: contactNormals.visible, joints: jointLines.visible, aabbs: aabbLines.visible };
    },
    // Every body's name, type and world position as drawn now.
    bodies() { return bodies.map((b) => ({ name: b.rec.name, type: b.rec.type, shape: b.rec.shape, position: b.group.position.toArray() })); },
    play() { setPlaying(true); },
    pause() { setPlaying(false); },
    seekFrame,
    seekTime,
    setSpeed(s) { state.speed = s; },
    select(name) { select(rec.bodies.findIndex((b) => b.name === name)); },
    sceneBox() { return new Box3().setFromObject(scene); },
    ready: true,
  };
  requestAnimationFrame(frameLoop);
}

function fail(error) {
  const message = document.createElement('div');
  message.className = 'error';
  message.textContent = `This replay could not be shown: ${error?.message ?? error}`;
  document.getElementById('view').append(message);
  throw error;
}

try {
  decodeRecording(JSON.parse(document.getElementById('fulcrum-recording').textContent)).then(start).catch(fail);
} catch (error) {
  fail(error);
}
