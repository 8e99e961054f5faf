// Step time of the JavaScript module in Node (docs/benchmarks.md):
//   node apps/web/bench.mjs BUILD_DIR STEPS ROUNDS SCENE.json [SCENE.json ...]
// Each round builds the world anew and steps it STEPS times; the fastest
// round's milliseconds per step is kept (the first rounds also wait for V8
// to finish optimizing the WebAssembly code). One JSON line per scene, with
// the state hash, to compare with `fulcrum_web_hash SCENE STEPS ROUNDS`.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { basename, join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';

const [dirArg, stepsArg, roundsArg, ...scenes] = process.argv.slice(2);
const dir = resolve(dirArg);
const { loadFulcrum } = await import(pathToFileURL(join(dir, 'fulcrum_api.mjs')).href);
const fulcrum = await loadFulcrum(createRequire(import.meta.url)(join(dir, 'fulcrum_web.js')));
const steps = Number(stepsArg), rounds = Number(roundsArg);
for (const scene of scenes) {
  const text = readFileSync(scene, 'utf8');
  let best = Infinity, hash = '';
  for (let round = 0; round < rounds; round++) {
    const world = fulcrum.worldFromScene(text);
    const t0 = performance.now();
    world.step(steps);
    best = Math.min(best, (performance.now() - t0) / steps);
    hash = world.stateHash();
    world.destroy();
  }
  console.log(JSON.stringify({ scene: basename(scene), steps, msPerStep: best, hash }));
}
