// Fulcrum's JavaScript API (docs/browser.md): a small object layer over the
// C API of apps/web/fulcrum_web.cpp, compiled by scripts/build-wasm.sh into
// build-wasm/fulcrum_web.js (the Emscripten factory createFulcrumModule, with
// the WebAssembly inside). scripts/build-wasm.sh also writes this file beside
// it as build-wasm/fulcrum_api.mjs; the sandbox page bundles it.
//
//   const fulcrum = await loadFulcrum(createFulcrumModule);
//   const world = fulcrum.worldFromScene(sceneText);
//   world.step(60);
//   world.positions();  // Float32Array, 3 per body

const bodyTypes = { static: 0, kinematic: 1, dynamic: 2 };
const shapeTypes = { sphere: 0, box: 1, capsule: 2, cylinder: 3, plane: 4 };
const jointTypes = { ball: 0, hinge: 1, slider: 2, fixed: 3, distance: 4 };

export class FulcrumError extends Error {}

// Loads the WebAssembly module; `factory` is createFulcrumModule (a global
// once build-wasm/fulcrum_web.js is loaded by a <script>, or require()'d in Node).
export async function loadFulcrum(factory = globalThis.createFulcrumModule) {
  if (typeof factory !== 'function') throw new FulcrumError('loadFulcrum: createFulcrumModule is not loaded (build-wasm/fulcrum_web.js)');
  const m = await factory();
  const f = (name, ret, args) => m.cwrap(name, ret, args);
  const n = 'number', s = 'string';
  const c = {
    lastError: f('fw_last_error', s, []),
    fromScene: f('fw_world_from_scene', n, [s]),
    create: f('fw_world_create', n, [n, n, n, n, n]),
    destroy: f('fw_world_destroy', null, [n]),
    dt: f('fw_world_dt', n, [n]),
    body: f('fw_body_create', n, [n, s, n, n, n, n, n, n, n, n, n, n, n, n, n, n, n]),
    joint: f('fw_joint_create', n, [n, n, n, n, n, n, n, n, n, n, n, n, n]),
    step: f('fw_step', n, [n, n]),
    bodyCount: f('fw_body_count', n, [n]),
    state: f('fw_read_state', n, [n]),
    contacts: f('fw_read_contacts', n, [n]),
    contactCount: f('fw_contact_count', n, [n]),
    particles: f('fw_read_particles', n, [n]),
    impulse: f('fw_apply_impulse', n, [n, n, n, n, n, n, n, n]),
    velocity: f('fw_set_velocity', n, [n, n, n, n, n, n, n, n]),
    grab: f('fw_grab', n, [n, n, n, n, n]),
    grabMove: f('fw_grab_move', null, [n, n, n, n]),
    release: f('fw_release', null, [n]),
    hash: f('fw_state_hash', s, [n]),
    bodiesJson: f('fw_bodies_json', s, [n, n]),
    structureJson: f('fw_structure_json', s, [n]),
    time: f('fw_time', n, [n]),
  };
  const check = (result, what) => {
    if (result < 0 || result === 0 && what.endsWith('world')) throw new FulcrumError(`${what}: ${c.lastError()}`);
    return result;
  };
  // A view of `count` floats at `address` in the module's memory (fresh after growth).
  const floats = (address, count) => new Float32Array(m.HEAPF32.buffer, address, count);

  class World {
    constructor(handle) { this.handle = handle; }
    get dt() { return c.dt(this.handle); }
    get time() { return c.time(this.handle); }
    get bodyCount() { return c.bodyCount(this.handle); }

    // { name, type: 'dynamic'|'static'|'kinematic', shape: { type: 'box', halfExtents } | { type: 'sphere', radius }
    //   | { type: 'capsule'|'cylinder', radius, halfHeight } | { type: 'plane', normal }, position, orientation [x, y, z, w],
    //   mass, friction, restitution }; returns the body's index.
    addBody(def) {
      const shape = def.shape ?? { type: 'sphere', radius: 0.5 };
      const type = bodyTypes[def.type ?? 'dynamic'], kind = shapeTypes[shape.type];
      if (type === undefined) throw new FulcrumError(`addBody: unknown type '${def.type}'`);
      if (kind === undefined) throw new FulcrumError(`addBody: unknown shape '${shape.type}'`);
      const [a, b, cc] = shape.type === 'box' ? shape.halfExtents : shape.type === 'plane' ? shape.normal ?? [0, 1, 0]
        : [shape.radius, shape.halfHeight ?? 0, 0];
      const p = def.position ?? [0, 0, 0], q = def.orientation ?? [0, 0, 0, 1];
      return check(c.body(this.handle, def.name ?? '', type, kind, a, b, cc, ...p, ...q, def.mass ?? 0,
                          def.friction ?? 0.6, def.restitution ?? 0), 'addBody');
    }
    // { type: 'ball'|'hinge'|'slider'|'fixed'|'distance', bodyA (-1 or absent: the world), bodyB, anchor (world),
    //   axis (hinge, slider), anchorB (distance: the other end) }; returns the joint's index.
    addJoint(def) {
      const type = jointTypes[def.type];
      if (type === undefined) throw new FulcrumError(`addJoint: unknown type '${def.type}'`);
      return check(c.joint(this.handle, type, def.bodyA ?? -1, def.bodyB, ...(def.anchor ?? [0, 0, 0]), ...(def.axis ?? [0, 1, 0]),
                           ...(def.anchorB ?? def.anchor ?? [0, 0, 0])), 'addJoint');
    }
    step(count = 1) { check(c.step(this.handle, count), 'step'); }

    // 8 floats per body (position xyz, orientation xyzw, awake): a view into
    // the module's memory, valid until the next call into the module.
    stateView() { return floats(c.state(this.handle), this.bodyCount * 8); }
    positions() {
      const s = this.stateView(), out = new Float32Array((s.length / 8) * 3);
      for (let b = 0; b < s.length / 8; b++) out.set(s.subarray(8 * b, 8 * b + 3), 3 * b);
      return out;
    }
    orientations() {
      const s = this.stateView(), out = new Float32Array((s.length / 8) * 4);
      for (let b = 0; b < s.length / 8; b++) out.set(s.subarray(8 * b + 3, 8 * b + 7), 4 * b);
      return out;
    }
    // The last step's contact points: 6 floats each (point xyz, normal xyz), a view.
    contacts() { const at = c.contacts(this.handle); return floats(at, 6 * c.contactCount(this.handle)); }
    // Every rope and cloth particle, 3 floats each, a view (structure() says whose).
    particles(total) { return floats(c.particles(this.handle), 3 * total); }

    applyImpulse(body, impulse, point) { check(c.impulse(this.handle, body, ...impulse, ...point), 'applyImpulse'); }
    setVelocity(body, linear, angular = [0, 0, 0]) { check(c.velocity(this.handle, body, ...linear, ...angular), 'setVelocity'); }
    // A spring pulls the grabbed point of the body towards the target (a mouse joint).
    grab(body, point) { check(c.grab(this.handle, body, ...point), 'grab'); }
    moveGrab(target) { c.grabMove(this.handle, ...target); }
    release() { c.release(this.handle); }
    stateHash() { return c.hash(this.handle); }

    // What to draw: bodies from `first` on (name, type, shape, mass, colours, render meshes), joints, ropes and cloths.
    describeBodies(first = 0) { return JSON.parse(c.bodiesJson(this.handle, first) || '[]'); }
    structure() { return JSON.parse(c.structureJson(this.handle) || '{}'); }
    destroy() { c.destroy(this.handle); this.handle = 0; }
  }

  return {
    module: m,
    worldFromScene(text) {
      return new World(check(c.fromScene(typeof text === 'string' ? text : JSON.stringify(text)), 'worldFromScene: world'));
    },
    createWorld({ gravity = [0, -9.81, 0], dt = 1 / 60, substeps = 0 } = {}) {
      return new World(check(c.create(...gravity, dt, substeps), 'createWorld: world'));
    },
  };
}
