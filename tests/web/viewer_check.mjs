// Drives fqd's live viewer in real headless Chromium (Debian's /usr/bin/chromium through
// playwright-core): waits for a frame, checks the canvas shows a coloured mesh (pixels),
// that the frame count keeps rising, and saves a screenshot.
//   node viewer_check.mjs URL STREAM SCREENSHOT.png [--token TOKEN] [--measure SECONDS [--replay]]
// --token: fqd has [http] token_file; the page must be refused (401) before the browser logs in
// through /login?token=TOKEN, and work after it (its requests carry the login cookie).
// --measure reports the display fps over SECONDS; with --replay the page redraws the latest
// result as fast as it can (the viewer's own rate, not fqd's).
// Prints one JSON line; exit 0 when every check passed, 1 otherwise.
import { createRequire } from 'node:module';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '../../web/package.json'));
const { chromium } = require('playwright-core');

const [url, stream, screenshot, ...rest] = process.argv.slice(2);
const option = (name) => (rest.includes(name) ? rest[rest.indexOf(name) + 1] : undefined);
const measure = Number(option('--measure') || 0);
const token = option('--token');
const replay = rest.includes('--replay');
const flags = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--enable-unsafe-swiftshader'];  // WebGL on the CPU (SwiftShader): there is no GPU here

function fail(result, why) {
  result.ok = false;
  result.error = why;
  console.log(JSON.stringify(result));
  process.exit(1);
}

// Share of canvas pixels that are not the background, and the distinct colours among them.
function canvasPixels() {
  const src = document.getElementById('view');
  const c = document.createElement('canvas');
  c.width = src.width;
  c.height = src.height;
  const g = c.getContext('2d');
  g.drawImage(src, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data;
  const bg = [d[0], d[1], d[2]];
  let lit = 0;
  const colours = new Set();
  for (let i = 0; i < d.length; i += 4) {
    if (Math.abs(d[i] - bg[0]) + Math.abs(d[i + 1] - bg[1]) + Math.abs(d[i + 2] - bg[2]) > 24) {
      lit += 1;
      colours.add((d[i] >> 3) << 10 | (d[i + 1] >> 3) << 5 | (d[i + 2] >> 3));
    }
  }
  return { lit: lit / (d.length / 4), colours: colours.size };
}

const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', headless: true, args: flags });
const result = { ok: true };
try {
  const context = await browser.newContext({ viewport: { width: 960, height: 640 } });
  const page = await context.newPage();
  const logs = [];
  page.on('console', (m) => logs.push(m.text()));
  page.on('pageerror', (e) => logs.push(String(e)));
  if (token) {
    const before = await page.goto(`${url}/`);
    if (before.status() !== 401) fail(result, `the viewer answered ${before.status()} before the login, not 401`);
    const login = await page.goto(`${url}/login?token=${encodeURIComponent(token)}`);
    if (!login.ok()) fail(result, `login answered ${login.status()}`);
  }
  await page.goto(`${url}/?stream=${encodeURIComponent(stream)}${replay ? '&replay=1' : ''}`);
  try {
    await page.waitForFunction(() => window.fqViewer && window.fqViewer.frames >= 1, null, { timeout: 90000 });
  } catch (e) {
    fail(result, `no frame shown within 90 s; page log: ${logs.join(' | ')}`);
  }
  // Let a few more render-loop ticks pass so that the first frame is on the canvas.
  await page.waitForTimeout(500);
  const first = await page.evaluate(() => window.fqViewer.frames);
  Object.assign(result, await page.evaluate(canvasPixels));
  await page.screenshot({ path: screenshot });
  if (result.lit < 0.02) fail(result, `canvas is blank: ${(result.lit * 100).toFixed(2)}% of pixels lit`);
  if (result.colours < 8) fail(result, `only ${result.colours} colours: no shaded clusters`);
  try {
    await page.waitForFunction((n) => window.fqViewer.frames >= n + 3, first, { timeout: 90000 });
  } catch (e) {
    fail(result, `frame count stuck at ${await page.evaluate(() => window.fqViewer.frames)}`);
  }
  result.frames_seen = await page.evaluate(() => window.fqViewer.frames);
  if (measure > 0) {
    const t0 = await page.evaluate(() => [window.fqViewer.frames, performance.now()]);
    await page.waitForTimeout(measure * 1000);
    const t1 = await page.evaluate(() => [window.fqViewer.frames, performance.now()]);
    result.display_fps = (t1[0] - t0[0]) / ((t1[1] - t0[1]) / 1000);
    result.last_ms = await page.evaluate(() => {
      const v = window.fqViewer;
      return { fetch: v.fetchMs, decode: v.decodeMs, show: v.showMs, render: v.renderMs };
    });
  }
  result.overlay = await page.evaluate(() => document.getElementById('stats').textContent);
} finally {
  await browser.close();
}
console.log(JSON.stringify(result));
