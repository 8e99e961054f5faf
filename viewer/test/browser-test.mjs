// Headless-browser check of a recorded replay page (run by the C++ test
// tests/recording/browser_test.cpp, or by hand):
//   node viewer/test/browser-test.mjs PAGE.html SCREENSHOT.png EXPECTED_OBJECTS [--labels a,b,...] [--pick NAME]
//        [--vehicle NAME [--vehicle-times T1,T2]] [--visuals N [--visual-colors HEX,HEX,...]] [--up X,Y,Z]
// Opens the page from file:// in Debian's Chromium driven by playwright-core,
// refuses every non-file request (the page must fetch nothing), and checks the
// first impression: the viewer starts without errors or console errors, shows
// the expected number of bodies, draws a shaded picture, plays on load (the
// frame advances without a click), frames the moving bodies (their projected
// box spans more than a quarter of the view's width or height, and most of
// them are inside it), shows no debug overlay by default, labels the groups
// named by --labels, and a click on the body --pick names selects it and the
// readout shows its name. With --vehicle: the vehicle's wheels are drawn,
// spin and steer between the recording's times T1 and T2 (default 1 and 5 s),
// and the camera drop-down's "vehicle: NAME" follows it (the camera moves with
// the car and keeps it in view). Saves SCREENSHOT.png (the first view,
// playing), SCREENSHOT-picked.png (after the click) and SCREENSHOT-follow.png
// (following the vehicle). Prints one JSON line; exit 0 = pass, 1 = fail.
import { chromium } from 'playwright-core';
import { openOfflinePage } from './offline-page.mjs';

const args = process.argv.slice(2);
const option = (name) => { const i = args.indexOf(name); return i >= 0 ? args.splice(i, 2)[1] : undefined; };
const expectedLabels = option('--labels')?.split(',').filter(Boolean) ?? [];
const pickName = option('--pick');
const vehicleName = option('--vehicle');
const vehicleTimes = (option('--vehicle-times') ?? '1,5').split(',').map(Number);
const expectedVisuals = option('--visuals');
const expectedVisualColors = option('--visual-colors')?.split(',').filter(Boolean) ?? [];
const expectedUp = option('--up')?.split(',').map(Number);
const [pagePath, screenshotPath, expectedArg] = args;
if (!pagePath || !screenshotPath || !expectedArg) {
  console.error('usage: browser-test.mjs PAGE.html SCREENSHOT.png EXPECTED_OBJECTS [--labels a,b,...] [--pick NAME]');
  process.exit(2);
}
const expectedObjects = Number(expectedArg);
const failures = [];
const report = { page: pagePath, screenshot: screenshotPath };
const check = (ok, message) => { if (!ok) failures.push(message); };

// Where the viewer's camera puts world points: client pixels, and whether in view.
// Written here (not asked of the viewer) from the camera's matrices.
function projectInPage(points) {
  const camera = window.fulcrumViewer.camera;
  camera.updateMatrixWorld();
  const v = camera.matrixWorldInverse.elements, p = camera.projectionMatrix.elements;
  const rect = document.querySelector('#view canvas').getBoundingClientRect();
  const mul = (m, x) => [0, 1, 2, 3].map((r) => m[r] * x[0] + m[4 + r] * x[1] + m[8 + r] * x[2] + m[12 + r] * x[3]);
  return points.map((point) => {
    const clip = mul(p, mul(v, [...point, 1]));
    const ndc = [clip[0] / clip[3], clip[1] / clip[3]];
    return { ndc, inside: clip[3] > 0 && Math.abs(ndc[0]) <= 1 && Math.abs(ndc[1]) <= 1,
             x: rect.left + ((ndc[0] + 1) / 2) * rect.width, y: rect.top + ((1 - ndc[1]) / 2) * rect.height };
  });
}

let session;
try {
  session = await openOfflinePage(chromium, pagePath, report);
  const { page, external, errors } = session;
  await page.waitForFunction(() => window.fulcrumViewer?.ready && window.fulcrumViewer.framesRendered > 2,
                             null, { timeout: 30000 });

  const info = await page.evaluate(() => {
    const v = window.fulcrumViewer;
    return { objectCount: v.objectCount, meshCount: v.meshCount, frameCount: v.frameCount, duration: v.duration };
  });
  Object.assign(report, info);
  // The world's up (a z-up robot's page): the camera stands on it.
  if (expectedUp) {
    const up = await page.evaluate(() => ({ world: window.fulcrumViewer.up, camera: window.fulcrumViewer.camera.up.toArray() }));
    report.up = up;
    const same = (a) => a.every((x, k) => Math.abs(x - expectedUp[k]) < 1e-6);
    check(same(up.world) && same(up.camera), `up ${JSON.stringify(up)}, expected ${expectedUp}`);
  }
  check(info.objectCount === expectedObjects, `objectCount ${info.objectCount}, expected ${expectedObjects}`);

  // It plays on load: time and frame advance with no click.
  const before = await page.evaluate(() => ({ frame: window.fulcrumViewer.frame, time: window.fulcrumViewer.time }));
  await page.waitForFunction((f0) => window.fulcrumViewer.frame > f0 + 2 && window.fulcrumViewer.time > 0.5, before.frame,
                             { timeout: 15000 }).catch(() => {});
  const after = await page.evaluate(() => ({ frame: window.fulcrumViewer.frame, time: window.fulcrumViewer.time,
                                             playing: window.fulcrumViewer.playing,
                                             slider: Number(document.getElementById('timeline').value) }));
  report.autoplay = { before, after };
  check(after.playing, 'not playing on load');
  check(after.time > before.time && after.frame > before.frame + 2,
        `the timeline did not advance by itself: frame ${before.frame} -> ${after.frame}`);
  check(after.slider === after.frame, 'slider does not follow the frame');
  await page.screenshot({ path: screenshotPath });

  // Overlays are off by default: unchecked, and nothing of them drawn.
  const overlays = await page.evaluate(() => ({
    drawn: window.fulcrumViewer.overlays,
    checked: ['show-contacts', 'show-normals', 'show-joints', 'show-aabbs'].filter((id) => document.getElementById(id).checked),
  }));
  report.overlays = overlays;
  check(overlays.checked.length === 0, `overlays on by default: ${overlays.checked.join(', ')}`);
  check(Object.values(overlays.drawn).every((shown) => !shown), `overlays drawn by default: ${JSON.stringify(overlays.drawn)}`);

  // Framing: the moving bodies' projected box is a good part of the view, and
  // most of them are in it.
  await page.evaluate(() => window.fulcrumViewer.pause());
  const framing = await page.evaluate((project) => {
    const moving = window.fulcrumViewer.bodies().filter((b) => b.type !== 'static');
    const at = eval(project)(moving.map((b) => b.position));  // eslint-disable-line no-eval
    const inside = at.filter((p) => p.inside);
    const xs = inside.map((p) => p.ndc[0]), ys = inside.map((p) => p.ndc[1]);
    return { moving: moving.length, inside: inside.length,
             width: inside.length ? (Math.max(...xs) - Math.min(...xs)) / 2 : 0,
             height: inside.length ? (Math.max(...ys) - Math.min(...ys)) / 2 : 0 };
  }, `(${projectInPage})`);
  report.framing = framing;
  check(framing.inside >= 0.8 * framing.moving, `only ${framing.inside} of ${framing.moving} moving bodies in view`);
  check(framing.width > 0.25 || framing.height > 0.25,
        `moving bodies span only ${(100 * framing.width).toFixed(0)}% x ${(100 * framing.height).toFixed(0)}% of the view`);

  // A shaded picture (lighting, shadows, the ground): many distinct colours.
  const pixels = await page.evaluate(() => {
    const gl = document.querySelector('#view canvas');
    const c = document.createElement('canvas');
    c.width = gl.width; c.height = gl.height;
    const g = c.getContext('2d');
    g.drawImage(gl, 0, 0);
    const data = g.getImageData(0, 0, c.width, c.height).data;
    const colours = new Set();
    for (let i = 0; i < data.length; i += 4) colours.add((data[i] >> 3) << 10 | (data[i + 1] >> 3) << 5 | (data[i + 2] >> 3));
    return { width: c.width, height: c.height, colours: colours.size };
  });
  report.pixels = pixels;
  check(pixels.width > 0 && pixels.height > 0, 'canvas has no size');
  check(pixels.colours > 64, `only ${pixels.colours} distinct colours drawn (no shading?)`);

  // Labels: one per named group, shown.
  const labels = await page.evaluate(() => [...document.querySelectorAll('#labels .label')]
    .map((e) => ({ text: e.textContent, shown: e.style.display !== 'none' })));
  report.labels = labels.map((l) => l.text);
  for (const name of expectedLabels) {
    const label = labels.find((l) => l.text === name);
    check(label?.shown, label ? `label '${name}' hidden` : `no label '${name}'`);
  }

  // Visuals (robot links): N drawn, shown by default in place of the bodies'
  // collision shapes, in the given colours (sRGB hex); the "collision shapes"
  // toggle swaps the two and back.
  if (expectedVisuals !== undefined) {
    const visuals = await page.evaluate(() => {
      const v = window.fulcrumViewer;
      const before = { list: v.visuals(), collision: v.collisionShown,
                       toggle: getComputedStyle(document.getElementById('show-collision').parentElement).display !== 'none' };
      v.showCollision(true);
      const swapped = { shown: v.visuals().filter((x) => x.visible).length, collision: v.collisionShown };
      v.showCollision(false);
      return { count: v.visualCount, meshes: v.visualMeshCount, before, swapped,
               after: { shown: v.visuals().filter((x) => x.visible).length, collision: v.collisionShown } };
    });
    report.visuals = { count: visuals.count, meshes: visuals.meshes, colors: [...new Set(visuals.before.list.map((x) => x.color))] };
    check(visuals.count === Number(expectedVisuals), `${visuals.count} visuals drawn, expected ${expectedVisuals}`);
    check(visuals.before.list.every((x) => x.visible) && !visuals.before.collision,
          'visuals not shown by default in place of the collision shapes');
    check(visuals.before.toggle, 'no "collision shapes" toggle on a page with visuals');
    check(visuals.swapped.shown === 0 && visuals.swapped.collision, `the collision toggle did not swap: ${JSON.stringify(visuals.swapped)}`);
    check(visuals.after.shown === visuals.count && !visuals.after.collision, 'the collision toggle did not swap back');
    // Within 2 of 255 per channel: the page turns sRGB into linear and back.
    const rgb = (hex) => [0, 2, 4].map((k) => parseInt(hex.slice(k, k + 2), 16));
    const near = (a, b) => rgb(a).every((x, k) => Math.abs(x - rgb(b)[k]) <= 2);
    for (const color of expectedVisualColors) {
      check(report.visuals.colors.some((c) => near(c, color)), `no visual of colour ${color}: ${report.visuals.colors}`);
    }
  }

  // Picking: a click on the body selects it, the readout names it.
  if (pickName) {
    const target = await page.evaluate(([name, project]) => {
      const body = window.fulcrumViewer.bodies().find((b) => b.name === name);
      return body ? eval(project)([body.position])[0] : null;  // eslint-disable-line no-eval
    }, [pickName, `(${projectInPage})`]);
    report.pickAt = target;
    check(target?.inside, `body '${pickName}' not in view`);
    if (target?.inside) {
      await page.mouse.click(target.x, target.y);
      await page.waitForTimeout(100);
      const picked = await page.evaluate(() => ({ selected: window.fulcrumViewer.selected,
                                                  readout: document.getElementById('readout').hidden ? '' : document.getElementById('readout').innerText }));
      report.picked = picked;
      check(picked.selected === pickName, `clicking '${pickName}' selected ${picked.selected}`);
      check(picked.readout.includes(pickName) && /position/.test(picked.readout) && /velocity/.test(picked.readout),
            `the readout does not describe '${pickName}': ${JSON.stringify(picked.readout)}`);
      await page.screenshot({ path: screenshotPath.replace(/\.png$/, '-picked.png') });
    }
  }

  // Vehicles: wheels drawn, turning and steering; the follow camera.
  if (vehicleName) {
    const wheelsAt = (t) => page.evaluate(([name, time]) => {
      window.fulcrumViewer.pause();
      window.fulcrumViewer.seekTime(time);
      return window.fulcrumViewer.vehicles.wheels().filter((w) => w.vehicle === name);
    }, [vehicleName, t]);
    const a = await wheelsAt(vehicleTimes[0]), b = await wheelsAt(vehicleTimes[1]);
    const meshes = await page.evaluate((name) => {
      let n = 0;
      window.fulcrumViewer.scene.traverse((o) => { if (o.name.startsWith(`${name} wheel `)) n += 1; });
      return n;
    }, vehicleName);
    const spun = a.map((w, i) => Math.abs(b[i].spin - w.spin));
    const steered = a.map((w, i) => Math.abs(b[i].steer - w.steer));
    report.wheels = { count: a.length, meshes, spun, steered };
    check(a.length > 0 && meshes === a.length, `vehicle '${vehicleName}': ${a.length} wheels, ${meshes} wheel objects in the scene`);
    check(spun.every((d) => d > 0.5), `vehicle '${vehicleName}': wheels did not turn between ${vehicleTimes}: ${spun}`);
    check(steered.some((d) => d > 0.02), `vehicle '${vehicleName}': no wheel steered between ${vehicleTimes}: ${steered}`);

    // Follow: choose it in the drop-down, then look at two times.
    await page.selectOption('#camera', { label: `vehicle: ${vehicleName}` });
    const settledAt = async (t) => {
      const frames = await page.evaluate((time) => { window.fulcrumViewer.seekTime(time); return window.fulcrumViewer.framesRendered; }, t);
      // A seek is a jump, which the camera follows at once: two frames suffice.
      await page.waitForFunction((f) => window.fulcrumViewer.framesRendered >= f + 2, frames, { timeout: 20000 });
      return page.evaluate(([name, project]) => {
        const v = window.fulcrumViewer;
        const chassis = v.bodies()[v.vehicles.list.find((x) => x.name === name).body];
        return { camera: v.camera.position.toArray(), car: chassis.position, view: eval(project)([chassis.position])[0],  // eslint-disable-line no-eval
                 choice: v.cameraChoice.choice };
      }, [vehicleName, `(${projectInPage})`]);
    };
    const f1 = await settledAt(vehicleTimes[0]), f2 = await settledAt(vehicleTimes[1]);
    const dist = (p, q) => Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
    const carMoved = dist(f1.car, f2.car), cameraMoved = dist(f1.camera, f2.camera);
    const range1 = dist(f1.camera, f1.car), range2 = dist(f2.camera, f2.car);
    report.follow = { choice: f2.choice, carMoved, cameraMoved, range1, range2, inView: [f1.view.inside, f2.view.inside] };
    check(f2.choice === `vehicle: ${vehicleName}`, `camera choice is '${f2.choice}'`);
    check(carMoved > 3, `vehicle '${vehicleName}' moved only ${carMoved.toFixed(2)} m between ${vehicleTimes}`);
    check(cameraMoved > 0.5 * carMoved, `the follow camera moved ${cameraMoved.toFixed(2)} m, the car ${carMoved.toFixed(2)} m`);
    check(Math.abs(range2 - range1) < 0.25 * range1, `the follow camera's distance changed from ${range1.toFixed(2)} to ${range2.toFixed(2)} m`);
    check(f1.view.inside && f2.view.inside, `vehicle '${vehicleName}' out of the followed view`);
    await page.screenshot({ path: screenshotPath.replace(/\.png$/, '-follow.png') });
  }

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
