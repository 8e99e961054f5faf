// Step time of the WebAssembly module in headless Chromium (docs/benchmarks.md):
//   node viewer/test/sandbox-bench.mjs build-wasm/sandbox.html STEPS ROUNDS SCENE.json [SCENE.json ...]
// Loads each scene in the sandbox page (paused, nothing else stepping),
// steps it STEPS times per round and keeps the fastest round's time per step
// (this machine's noise only adds time); prints one JSON line per scene with
// the state hash after the first round, to compare with the native build.
import { readFileSync } from 'node:fs';
import { basename } from 'node:path';
import { chromium } from 'playwright-core';
import { openOfflinePage } from './offline-page.mjs';

const [pagePath, stepsArg, roundsArg, ...scenes] = process.argv.slice(2);
const steps = Number(stepsArg), rounds = Number(roundsArg);
const session = await openOfflinePage(chromium, pagePath);
try {
  const { page } = session;
  await page.waitForFunction(() => window.fulcrumSandbox?.ready, null, { timeout: 60000 });
  for (const scene of scenes) {
    const result = await page.evaluate(([text, n, r]) => {
      const s = window.fulcrumSandbox;
      s.pause();
      let best = Infinity, hash = '';
      for (let round = 0; round < r; round++) {
        s.load('bench', text);
        s.pause();
        const world = s.world;
        const t0 = performance.now();
        world.step(n);
        best = Math.min(best, (performance.now() - t0) / n);
        if (round === 0) hash = world.stateHash();
      }
      return { msPerStep: best, hash };
    }, [readFileSync(scene, 'utf8'), steps, rounds]);
    console.log(JSON.stringify({ scene: basename(scene), steps, ...result }));
  }
} finally {
  await session.close();
}
