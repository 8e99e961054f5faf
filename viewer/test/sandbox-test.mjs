// Headless-browser check of the live sandbox (docs/browser.md), run by CTest
// as Browser.SandboxLive or by hand:
//   node viewer/test/sandbox-test.mjs build-wasm/sandbox.html NATIVE_HASH_TOOL SCENE.json OUT_DIR
// Opens the page from file:// in Debian's Chromium driven by playwright-core,
// refuses every non-file request (the page must work offline), and checks:
// it starts without page or console errors; the simulation advances by
// itself; a scripted mouse drag moves the grabbed body towards the pointer;
// SCENE.json stepped 300 times in the page has the state hash that the
// native build's fulcrum_web_hash prints; the page reports its step time;
// a click on the ground spawns a body; every built-in scene loads and steps.
// Screenshots go to OUT_DIR (sandbox.png, sandbox-drag.png). Prints one JSON
// line; exit 0 = pass, 1 = fail, 77 = skipped (no page, browser or package).
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromiumPath, openOfflinePage } from './offline-page.mjs';

const [pagePath, hashTool, scenePath, outDir] = process.argv.slice(2);
if (!pagePath || !hashTool || !scenePath || !outDir) {
  console.error('usage: sandbox-test.mjs SANDBOX.html NATIVE_HASH_TOOL SCENE.json OUT_DIR');
  process.exit(2);
}
const skip = (why) => { console.log(JSON.stringify({ skipped: why })); process.exit(77); };
if (!existsSync(pagePath)) skip(`${pagePath} not built (scripts/build-wasm.sh)`);
if (!existsSync(chromiumPath)) skip(`${chromiumPath} not found (scripts/install-viewer-deps.sh)`);
const viewerDir = resolve(dirname(fileURLToPath(import.meta.url)), '..');
if (!existsSync(join(viewerDir, 'node_modules', 'playwright-core'))) skip('viewer/node_modules/playwright-core missing (scripts/install-viewer-deps.sh)');
const { chromium } = await import('playwright-core');

mkdirSync(outDir, { recursive: true });
const failures = [];
const report = { page: pagePath };
const check = (ok, message) => { if (!ok) failures.push(message); };
const steps = 300;

let session;
try {
  const sceneText = readFileSync(scenePath, 'utf8');
  const nativeHash = execFileSync(hashTool, [scenePath, String(steps)], { env: { ...process.env, FULCRUM_SIMD: 'scalar' } })
    .toString().trim();
  report.nativeHash = nativeHash;

  session = await openOfflinePage(chromium, pagePath, report);
  const { page, external, errors } = session;
  await page.waitForFunction(() => window.fulcrumSandbox?.ready && window.fulcrumSandbox.framesRendered > 2, null, { timeout: 60000 });

  // It simulates by itself.
  const s0 = await page.evaluate(() => window.fulcrumSandbox.steps);
  await page.waitForFunction((n) => window.fulcrumSandbox.steps > n + 10, s0, { timeout: 30000 }).catch(() => {});
  const live = await page.evaluate(() => ({ steps: window.fulcrumSandbox.steps, playing: window.fulcrumSandbox.playing,
                                            scenes: window.fulcrumSandbox.sceneNames,
                                            profile: document.getElementById('profile').textContent }));
  report.live = { from: s0, ...live };
  check(live.playing && live.steps > s0 + 10, `the simulation did not advance: ${s0} -> ${live.steps} steps`);
  check(/step \d+\.\d+ ms/.test(live.profile) && /fps/.test(live.profile), `no step time or fps shown: '${live.profile}'`);
  await page.screenshot({ path: join(outDir, 'sandbox.png') });

  // A scripted drag: press on the top box of the pyramid, move the mouse up
  // and sideways, hold; the body follows the pointer.
  await page.evaluate(() => { window.fulcrumSandbox.load('pyramid20'); window.fulcrumSandbox.pause(); });
  const target = await page.evaluate(() => {
    const bodies = window.fulcrumSandbox.bodies();
    const top = bodies.reduce((best, b, i) => (b.type === 'dynamic' && (best < 0 || b.position[1] > bodies[best].position[1]) ? i : best), -1);
    return { index: top, position: bodies[top].position, screen: window.fulcrumSandbox.screenOf(bodies[top].position) };
  });
  report.drag = { body: target.index, from: target.position };
  check(target.screen.inside, 'the top box is not in view');
  await page.mouse.move(target.screen.x, target.screen.y);
  await page.mouse.down();
  for (let k = 1; k <= 10; k++) {
    await page.mouse.move(target.screen.x + 12 * k, target.screen.y - 10 * k);
    await page.evaluate(() => window.fulcrumSandbox.step(6));
  }
  const dragged = await page.evaluate((i) => window.fulcrumSandbox.bodies()[i].position, target.index);
  await page.screenshot({ path: join(outDir, 'sandbox-drag.png') });
  await page.mouse.up();
  report.drag.to = dragged;
  const moved = [0, 1, 2].map((k) => dragged[k] - target.position[k]);
  // Dragged up and to the right on screen: the box rises and moves along the camera's right.
  check(moved[1] > 0.5, `the dragged box did not rise: moved ${moved.map((v) => v.toFixed(2)).join(', ')} m`);
  check(Math.hypot(...moved) > 1, `the dragged box hardly moved: ${Math.hypot(...moved).toFixed(3)} m`);

  // A click (no drag) on the ground spawns a body there.
  const countBefore = await page.evaluate(() => window.fulcrumSandbox.bodies().length);
  const ground = await page.evaluate(() => window.fulcrumSandbox.screenOf([4, 0, 3]));
  await page.mouse.click(ground.x, ground.y);
  const countAfter = await page.evaluate(() => window.fulcrumSandbox.bodies().length);
  report.spawn = { before: countBefore, after: countAfter };
  check(countAfter === countBefore + 1, `a click spawned ${countAfter - countBefore} bodies, expected 1`);

  // Every built-in scene loads, draws and steps.
  report.scenes = await page.evaluate(() => window.fulcrumSandbox.sceneNames.map((name) => {
    const problem = window.fulcrumSandbox.load(name);
    if (!problem) window.fulcrumSandbox.step(5);
    return { name, problem, bodies: problem ? 0 : window.fulcrumSandbox.bodies().length };
  }));
  for (const s of report.scenes) check(!s.problem && s.bodies > 0, `built-in scene ${s.name}: ${s.problem || 'no bodies'}`);

  // The same bits as the native build: the scene stepped 300 times in the page.
  const pageHash = await page.evaluate(([text, n]) => {
    const problem = window.fulcrumSandbox.load('hash-check', text);
    if (problem) return `error: ${problem}`;
    window.fulcrumSandbox.pause();
    window.fulcrumSandbox.step(n);
    return window.fulcrumSandbox.stateHash();
  }, [sceneText, steps]);
  report.pageHash = pageHash;
  check(pageHash === nativeHash, `state hash after ${steps} steps: page ${pageHash}, native ${nativeHash}`);
  report.stepMs = await page.evaluate(() => window.fulcrumSandbox.stepMs);
  check(report.stepMs > 0, 'no step time measured');

  check(errors.length === 0, `page errors: ${errors.join(' | ')}`);
  check(external.length === 0, `the page tried to fetch: ${external.join(', ')}`);
} catch (e) {
  failures.push(String(e?.message ?? e));
} finally {
  await session?.close();
}
report.failures = failures;
console.log(JSON.stringify(report));
process.exit(failures.length === 0 ? 0 : 1);
