// Opening a page from file:// in Debian's headless Chromium (playwright-core),
// shared by the browser tests and the sandbox benchmark.
//   const session = await openOfflinePage(chromium, PAGE.html, report);
//   ... session.page, session.errors, session.external ...
//   await session.close();
// WebGL runs on the CPU (SwiftShader: recent Chromium only falls back to it
// when asked). Every request that is not file:, data: or blob: is refused and
// listed in `external` (the pages must work offline); page errors and console
// errors are collected in `errors`. Chromium's cold start can take tens of
// seconds on a loaded 2-core CI machine (CI once timed out at 15 s while ctest
// ran other tests beside it), so it launches with a generous timeout and
// retries once (report.launchRetries says when it did).
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';

export const chromiumPath = process.env.FULCRUM_CHROMIUM ?? '/usr/bin/chromium';

export async function openOfflinePage(chromium, pagePath, report = {}, { viewport = { width: 1280, height: 800 } } = {}) {
  const userDataDir = mkdtempSync(join(tmpdir(), 'fulcrum-chromium-'));
  const launchOptions = {
    executablePath: chromiumPath,
    headless: true,
    viewport,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
    timeout: 60000,
  };
  let context;
  const close = async () => {
    if (context) await context.close().catch(() => {});
    rmSync(userDataDir, { recursive: true, force: true });
  };
  try {
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
    return { context, page, external, errors, close };
  } catch (e) {
    await close();
    throw e;
  }
}
