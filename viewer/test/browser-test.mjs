// Headless-browser check of a recorded replay page (run by the C++ test
// tests/recording/browser_test.cpp, or by hand):
//   node viewer/test/browser-test.mjs PAGE.html SCREENSHOT.png EXPECTED_OBJECTS
// Opens the page from file:// in Debian's Chromium driven by playwright-core,
// refuses every non-file request (the page must fetch nothing), and checks that
// the viewer starts without errors, shows the expected number of bodies, draws
// a non-blank picture, and that the timeline advances when played. Saves a
// screenshot. Prints one JSON line; exit 0 = pass, 1 = fail.
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';
import { chromium } from 'playwright-core';

const [pagePath, screenshotPath, expectedArg] = process.argv.slice(2);
if (!pagePath || !screenshotPath || !expectedArg) {
  console.error('usage: browser-test.mjs PAGE.html SCREENSHOT.png EXPECTED_OBJECTS');
  process.exit(2);
}
const expectedObjects = Number(expectedArg);
const executablePath = process.env.FULCRUM_CHROMIUM ?? '/usr/bin/chromium';
const userDataDir = mkdtempSync(join(tmpdir(), 'fulcrum-chromium-'));
const failures = [];
const report = { page: pagePath, screenshot: screenshotPath };
const check = (ok, message) => { if (!ok) failures.push(message); };

let context;
try {
  // Chromium's cold start can take tens of seconds on a loaded 2-core CI
  // machine (CI once timed out at 15 s while ctest ran other tests beside it),
  // so launch with a generous timeout and retry once before reporting failure.
  const launchOptions = {
    executablePath,
    headless: true,
    viewport: { width: 1000, height: 700 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           // WebGL on the CPU: recent Chromium only falls back to SwiftShader when asked to.
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
    timeout: 60000,
  };
  for (let attempt = 1; !context; ++attempt) {
    try {
      context = await chromium.launchPersistentContext(userDataDir, launchOptions);
    } catch (e) {
      if (attempt >= 2) throw e;
      report.launchRetries = attempt;
    }
  }
  const page = context.pages()[0] ?? await context.newPage();
  const external = [];
  await context.route('**/*', (route) => {
    const url = route.request().url();
    if (url.startsWith('file:') || url.startsWith('data:') || url.startsWith('blob:')) return route.continue();
    external.push(url);
    return route.abort();
  });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });

  await page.goto(pathToFileURL(resolve(pagePath)).href, { waitUntil: 'load', timeout: 30000 });
  await page.waitForFunction(() => window.fulcrumViewer?.ready && window.fulcrumViewer.framesRendered > 2,
                             null, { timeout: 30000 });

  const info = await page.evaluate(() => {
    const v = window.fulcrumViewer;
    return { objectCount: v.objectCount, meshCount: v.meshCount, frameCount: v.frameCount, duration: v.duration };
  });
  Object.assign(report, info);
  check(info.objectCount === expectedObjects, `objectCount ${info.objectCount}, expected ${expectedObjects}`);

  // Non-blank: copy the WebGL canvas (preserveDrawingBuffer) into a 2D canvas
  // and count pixels that differ from the background colour.
  const pixels = await page.evaluate(() => {
    const gl = document.querySelector('#view canvas');
    const c = document.createElement('canvas');
    c.width = gl.width; c.height = gl.height;
    const g = c.getContext('2d');
    g.drawImage(gl, 0, 0);
    const data = g.getImageData(0, 0, c.width, c.height).data;
    const bg = [0x1c, 0x20, 0x28];
    let differing = 0;
    const colours = new Set();
    for (let i = 0; i < data.length; i += 4) {
      if (Math.abs(data[i] - bg[0]) + Math.abs(data[i + 1] - bg[1]) + Math.abs(data[i + 2] - bg[2]) > 24) differing++;
      colours.add((data[i] >> 3) << 10 | (data[i + 1] >> 3) << 5 | (data[i + 2] >> 3));
    }
    return { width: c.width, height: c.height, fraction: differing / (data.length / 4), colours: colours.size };
  });
  report.pixels = pixels;
  check(pixels.width > 0 && pixels.height > 0, 'canvas has no size');
  check(pixels.fraction > 0.02, `canvas nearly blank: ${(100 * pixels.fraction).toFixed(2)}% non-background pixels`);
  check(pixels.colours > 16, `only ${pixels.colours} distinct colours drawn (no shading?)`);

  // The timeline advances when played.
  const before = await page.evaluate(() => ({ frame: window.fulcrumViewer.frame, time: window.fulcrumViewer.time }));
  await page.click('#play');
  await page.waitForFunction((f0) => window.fulcrumViewer.frame > f0 + 2, before.frame, { timeout: 5000 })
    .catch(() => {});
  const after = await page.evaluate(() => ({ frame: window.fulcrumViewer.frame, time: window.fulcrumViewer.time,
                                             playing: window.fulcrumViewer.playing,
                                             slider: Number(document.getElementById('timeline').value) }));
  report.timeline = { before, after };
  check(after.playing, 'not playing after clicking Play');
  check(after.time > before.time && after.frame > before.frame,
        `timeline did not advance: frame ${before.frame} -> ${after.frame}`);
  check(after.slider === after.frame, 'slider does not follow the frame');

  // Show every overlay for the screenshot, half-way through.
  await page.click('#play');
  await page.evaluate(() => {
    document.getElementById('show-aabbs').click();
    window.fulcrumViewer.seekFrame(Math.floor(window.fulcrumViewer.frameCount / 2));
  });
  await page.waitForTimeout(100);
  await page.screenshot({ path: screenshotPath });

  check(errors.length === 0, `page errors: ${errors.join(' | ')}`);
  check(external.length === 0, `the page tried to fetch: ${external.join(', ')}`);
} catch (e) {
  failures.push(String(e?.message ?? e));
} finally {
  if (context) await context.close().catch(() => {});
  rmSync(userDataDir, { recursive: true, force: true });
}
report.failures = failures;
console.log(JSON.stringify(report));
process.exit(failures.length === 0 ? 0 : 1);
