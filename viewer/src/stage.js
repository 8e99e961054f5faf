// What the replay page (viewer.js) and the live sandbox (sandbox.js) draw
// alike: bodies from their render meshes (the recording's body description,
// docs/recording.md), the sky, the sun and its shadow, the checkered ground,
// overlay line buffers and the camera framing. Moved here from viewer.js
// unchanged in behaviour.
import {
  BackSide, Box3, BufferAttribute, BufferGeometry, CanvasTexture, Color, DirectionalLight, DoubleSide, FrontSide, Group,
  HemisphereLight, LineBasicMaterial, Mesh, MeshBasicMaterial, MeshStandardMaterial, Points, PointsMaterial, RepeatWrapping,
  Quaternion, SRGBColorSpace, SphereGeometry, Vector3,
} from 'three';

export const srgb = (rgb) => new Color().setRGB(rgb[0], rgb[1], rgb[2], SRGBColorSpace);

function material(rgb, doubleSided) {
  return new MeshStandardMaterial({ color: srgb(rgb), roughness: 0.55, metalness: 0.05,
                                    side: doubleSided ? DoubleSide : FrontSide });
}

function visualMaterial(rgba, doubleSided) {
  const alpha = rgba[3] ?? 1;
  return new MeshStandardMaterial({ color: srgb(rgba), roughness: 0.55, metalness: 0.05, transparent: alpha < 1,
                                    opacity: alpha, side: doubleSided ? DoubleSide : FrontSide });
}

function meshGeometry(arrays) {
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(arrays.positions, 3));
  geometry.setAttribute('normal', new BufferAttribute(arrays.normals, 3));
  geometry.setIndex(new BufferAttribute(arrays.indices, 1));
  return geometry;
}

// One group of meshes per body, added to the scene; each mesh knows its
// body's index (userData.bodyIndex, counted from `firstIndex`). A body with
// visuals (a robot link's, docs/recording.md) is drawn as them, its collision
// meshes hidden; `visualMeshes` are the recording's shared geometries.
export function buildBodies(scene, recBodies, firstIndex = 0, visualMeshes = []) {
  const visualGeometries = visualMeshes.map(meshGeometry);  // each once, however many visuals show it
  const bodies = recBodies.map((body) => {
    const group = new Group();
    group.name = body.name;
    const meshes = [];
    const local = new Box3();
    for (const part of body.parts) {
      const geometry = new BufferGeometry();
      geometry.setAttribute('position', new BufferAttribute(part.positions, 3));
      geometry.setAttribute('normal', new BufferAttribute(part.normals, 3));
      geometry.setIndex(new BufferAttribute(part.indices, 1));
      const mesh = new Mesh(geometry, material(body.color, part.doubleSided));
      mesh.position.set(...part.position);
      mesh.quaternion.set(...part.rotation);
      mesh.castShadow = body.shape !== 'plane';
      mesh.receiveShadow = true;
      group.add(mesh);
      meshes.push(mesh);
      if (body.shape !== 'plane') {
        mesh.updateMatrix();
        geometry.computeBoundingBox();
        local.union(geometry.boundingBox.clone().applyMatrix4(mesh.matrix));
      }
    }
    const visuals = [];
    for (const v of body.visuals ?? []) {
      const geometry = visualGeometries[v.mesh];
      const mesh = new Mesh(geometry, visualMaterial(v.color, visualMeshes[v.mesh].doubleSided));
      mesh.position.set(...v.position);
      mesh.quaternion.set(...v.rotation);
      mesh.scale.set(...v.scale);
      mesh.castShadow = mesh.receiveShadow = true;
      group.add(mesh);
      visuals.push(mesh);
      mesh.updateMatrix();
      if (!geometry.boundingBox) geometry.computeBoundingBox();
      local.union(geometry.boundingBox.clone().applyMatrix4(mesh.matrix));
    }
    meshes.forEach((m) => { m.visible = visuals.length === 0; });
    scene.add(group);
    const extent = local.isEmpty() ? 0 : local.getSize(new Vector3()).length() / 2;
    return { rec: body, group, meshes, awakeMaterial: meshes.map((m) => m.material), local, extent, visuals,
             sleepMaterial: body.parts.map((p) => material(body.sleepColor, p.doubleSided)), asleep: false };
  });
  bodies.forEach((b, index) => b.meshes.concat(b.visuals).forEach((m) => { m.userData.bodyIndex = firstIndex + index; }));
  return bodies;
}

// Places the camera (and its orbit target) to look along `direction` at
// `box`, at the distance where every corner of the box is inside the view.
export function frameCamera(camera, controls, box, direction, margin, focusRadius) {
  const centre = box.getCenter(new Vector3());
  const back = direction.clone().normalize();
  const right = camera.up.clone().cross(back).normalize();
  const up = back.clone().cross(right);
  const ty = Math.tan((camera.fov * Math.PI) / 360) * margin, tx = ty * camera.aspect;
  let distance = 0;
  for (let c = 0; c < 8; c++) {
    const corner = new Vector3(c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y, c & 4 ? box.max.z : box.min.z).sub(centre);
    const depth = corner.dot(back);
    distance = Math.max(distance, Math.abs(corner.dot(right)) / tx + depth, Math.abs(corner.dot(up)) / ty + depth);
  }
  distance = Math.max(distance, box.getSize(new Vector3()).length() * 0.6, 0.3);
  camera.position.copy(centre).addScaledVector(back, distance);
  controls.target.copy(centre);
  camera.near = distance / 200;
  camera.far = distance * 40 + focusRadius * 20;
  camera.updateProjectionMatrix();
}

// A sky dome around the camera: the fog's colour at and below the horizon
// (where the ground fades into it), darkening towards the zenith.
export function createSkyDome(horizon, zenith) {
  const geometry = new SphereGeometry(1, 32, 16);
  const p = geometry.attributes.position, colours = new Float32Array(p.count * 3), c = new Color();
  for (let k = 0; k < p.count; k++) {
    c.lerpColors(horizon, zenith, Math.max(0, p.getY(k)) ** 0.7).toArray(colours, 3 * k);
  }
  geometry.setAttribute('color', new BufferAttribute(colours, 3));
  const dome = new Mesh(geometry, new MeshBasicMaterial({ vertexColors: true, side: BackSide, fog: false,
                                                          depthWrite: false, depthTest: false }));
  dome.renderOrder = -1;
  dome.frustumCulled = false;
  return dome;
}

// A sky/ground fill and a sun whose shadow map covers the focus box.
// `turn` takes y up to the world's up (identity for a y-up world).
export function addLights(scene, focus, focusRadius, typicalSize, turn = new Quaternion()) {
  const focusCenter = focus.getCenter(new Vector3());
  const sky = new HemisphereLight(0xdde8ff, 0x4a4238, 1.1);
  sky.position.set(0, 1, 0).applyQuaternion(turn);
  scene.add(sky);
  const sun = new DirectionalLight(0xfff4e6, 3.2);
  const sunDirection = new Vector3(-0.45, 1, 0.6).applyQuaternion(turn).normalize();
  sun.position.copy(focusCenter).addScaledVector(sunDirection, focusRadius * 3);
  sun.target.position.copy(focusCenter);
  sun.castShadow = true;
  sun.shadow.mapSize.set(2048, 2048);
  {
    // The shadow camera looks along the sun at the focus box: its bounds are
    // the box's corners seen from the sun, a little grown.
    const s = sun.shadow.camera;
    sun.updateMatrixWorld();
    sun.target.updateMatrixWorld();
    s.position.copy(sun.position);
    s.lookAt(sun.target.position);
    s.updateMatrixWorld();
    const inverse = s.matrixWorld.clone().invert();
    const lightBox = new Box3();
    const grown = focus.clone().expandByScalar(typicalSize * 2);
    for (let c = 0; c < 8; c++) {
      lightBox.expandByPoint(new Vector3(c & 1 ? grown.max.x : grown.min.x, c & 2 ? grown.max.y : grown.min.y,
                                         c & 4 ? grown.max.z : grown.min.z).applyMatrix4(inverse));
    }
    s.left = lightBox.min.x; s.right = lightBox.max.x; s.bottom = lightBox.min.y; s.top = lightBox.max.y;
    s.near = Math.max(0.01, -lightBox.max.z - focusRadius); s.far = -lightBox.min.z + focusRadius;
    s.updateProjectionMatrix();
    const texel = Math.max(s.right - s.left, s.top - s.bottom) / 2048;
    sun.shadow.bias = -0.0004;
    sun.shadow.normalBias = texel * 1.5;
    sun.shadow.radius = 3;
  }
  scene.add(sun, sun.target);
  return sun;
}

// A ground that reads as one: tiles of a round number of metres.
export function checkerTexture() {
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = 128;
  const g = canvas.getContext('2d');
  g.fillStyle = '#a7afba'; g.fillRect(0, 0, 128, 128);
  g.fillStyle = '#98a0ac'; g.fillRect(0, 0, 64, 64); g.fillRect(64, 64, 64, 64);
  g.strokeStyle = 'rgba(70,78,92,0.35)'; g.lineWidth = 2; g.strokeRect(0, 0, 128, 128);
  const texture = new CanvasTexture(canvas);
  texture.wrapS = texture.wrapT = RepeatWrapping;
  texture.colorSpace = SRGBColorSpace;
  texture.anisotropy = 8;
  return texture;
}

// A plane body drawn as a large checkered floor fading into the horizon:
// its quad grown about its centre within its plane to `reach` metres, with UVs in metres.
export function drawAsGround(body, reach, tile, checker) {
  if (body.rec.shape !== 'plane') return;
  for (const mesh of body.meshes) {
    const p = mesh.geometry.attributes.position;
    const corner = (k) => new Vector3(p.getX(k), p.getY(k), p.getZ(k));
    const centre = new Vector3();
    for (let k = 0; k < p.count; k++) centre.add(corner(k));
    centre.divideScalar(p.count);
    const u = corner(1).sub(corner(0)).normalize(), v = corner(p.count - 1).sub(corner(0)).normalize();
    const grow = Math.max(1, reach / Math.max(corner(0).distanceTo(centre), 1e-6));
    const uv = new Float32Array(p.count * 2);
    for (let k = 0; k < p.count; k++) {
      const q = corner(k).sub(centre).multiplyScalar(grow).add(centre);
      p.setXYZ(k, q.x, q.y, q.z);
      uv[2 * k] = q.dot(u) / (2 * tile); uv[2 * k + 1] = q.dot(v) / (2 * tile);
    }
    mesh.geometry.setAttribute('uv', new BufferAttribute(uv, 2));
    mesh.geometry.computeBoundingSphere();
    const ground = new MeshStandardMaterial({ map: checker, roughness: 0.95, metalness: 0, side: DoubleSide,
                                              polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 });
    mesh.material = ground;
    body.awakeMaterial = body.sleepMaterial = body.meshes.map(() => ground);
  }
}

// Points or line segments rewritten every frame (contacts, joints, AABBs),
// drawn over everything; hidden until turned on.
export function overlayLines(scene, vertexCount, color, PointsOrLines, extra = {}) {
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(new Float32Array(Math.max(vertexCount, 1) * 3), 3));
  geometry.setDrawRange(0, 0);
  const mat = PointsOrLines === Points
    ? new PointsMaterial({ color, size: 6, sizeAttenuation: false, depthTest: false, ...extra })
    : new LineBasicMaterial({ color, depthTest: false, ...extra });
  const object = new PointsOrLines(geometry, mat);
  object.frustumCulled = false;
  object.renderOrder = 10;
  object.visible = false;
  scene.add(object);
  return object;
}
