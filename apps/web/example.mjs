// The JavaScript module in Node (docs/browser.md). After scripts/build-wasm.sh:
//   node apps/web/example.mjs [build-wasm]
// Builds a world in code (a ground, a box, a ball on a hinge), steps it,
// reads the poses as typed arrays, pushes the box, then loads a scene file
// and prints its state hash; a bad scene gives the engine's error message.
// Exit 77 when the module is not built (CTest: skipped).
import { existsSync, readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';

const dir = resolve(process.argv[2] ?? 'build-wasm');
if (!existsSync(join(dir, 'fulcrum_web.js'))) {
  console.log(`${dir}/fulcrum_web.js not built (scripts/build-wasm.sh): skipped`);
  process.exit(77);
}
const { loadFulcrum } = await import(pathToFileURL(join(dir, 'fulcrum_api.mjs')).href);
const createFulcrumModule = createRequire(import.meta.url)(join(dir, 'fulcrum_web.js'));
const fulcrum = await loadFulcrum(createFulcrumModule);

// A world from code.
const world = fulcrum.createWorld({ gravity: [0, -9.81, 0], dt: 1 / 60 });
world.addBody({ name: 'ground', type: 'static', shape: { type: 'box', halfExtents: [10, 0.5, 10] }, position: [0, -0.5, 0] });
const box = world.addBody({ name: 'box', shape: { type: 'box', halfExtents: [0.5, 0.5, 0.5] }, position: [0, 2, 0], mass: 1 });
const ball = world.addBody({ name: 'ball', shape: { type: 'sphere', radius: 0.3 }, position: [3, 3, 0], mass: 2 });
world.addJoint({ type: 'hinge', bodyB: ball, anchor: [2, 3, 0], axis: [0, 0, 1] });  // pinned to the world
world.step(120);
const p = world.positions(), q = world.orientations();
console.log(`box at y = ${p[3 * box + 1].toFixed(3)} m, orientation w = ${q[4 * box + 3].toFixed(3)}`);
const ballToPin = Math.hypot(p[3 * ball] - 2, p[3 * ball + 1] - 3, p[3 * ball + 2]);
console.log(`ball ${ballToPin.toFixed(3)} m from its hinge`);
world.applyImpulse(box, [5, 0, 0], [p[3 * box], p[3 * box + 1], p[3 * box + 2]]);
world.step(30);
console.log(`after a push, box at x = ${world.positions()[3 * box].toFixed(3)} m`);
world.destroy();

// A scene file, and its state hash after 300 steps.
const scene = fulcrum.worldFromScene(readFileSync('scenes/joints.json', 'utf8'));
scene.step(300);
console.log(`scenes/joints.json: ${scene.bodyCount} bodies, state hash after 300 steps ${scene.stateHash()}`);

// Bad input: a FulcrumError naming the field.
let refused = '';
try {
  fulcrum.worldFromScene('{"bodies": [{"shape": {"type": "sphere", "radius": -1}}]}');
} catch (e) {
  refused = e.message;
  console.log(`refused: ${refused}`);
}
const ok = Math.abs(p[3 * box + 1] - 0.5) < 0.01 && Math.abs(ballToPin - 1) < 0.01 &&
           refused.includes('bodies[0].shape.radius');
process.exit(ok ? 0 : 1);
