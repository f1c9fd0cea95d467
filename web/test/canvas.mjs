// The page's canvas against the host's pixels, byte for byte: Debian's Chromium loads
// web/index.html with a fixed scene and frame, and the canvas's RGBA bytes must equal those
// that the web crate's `reference` binary computes natively with the same Rust function.
// Then the animated page: its time a frame beside the host's, and an invalid edit shown
// under the text while the last good scene keeps turning. Last, the desktop renderer's
// 36-frame orbit of the demo scene opens in Chromium as an animation whose frames are the
// host's pixels.
//
// Run by .ci/web.sh after web/build.sh (or `npm test` here, which builds first). Exits 1 on
// any difference. CHROMIUM overrides the browser's path.

import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const web = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const root = path.dirname(web);
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'microray-web-'));

// `query` names the scene for the page; none means its default, web/scene.toml.
const CASES = [
  { scene: 'tests/data/lit.toml', query: 'scene=../tests/data/lit.toml&', k: 0, n: 1, degrees: 360 },
  { scene: 'web/scene.toml', query: '', k: 5, n: 36, degrees: 360 },
];

let failures = 0;
function check(ok, message) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${message}`);
  if (!ok) failures += 1;
}

if (!fs.existsSync(path.join(web, 'microray.wasm'))) {
  console.error('web/microray.wasm is missing: run bash web/build.sh first');
  process.exit(2);
}

// The page's default scene is the demo at another size; it must not drift from the demo.
{
  const demo = fs.readFileSync(path.join(root, 'examples/scenes/demo.toml'), 'utf8');
  const page = fs.readFileSync(path.join(web, 'scene.toml'), 'utf8');
  const resized = demo
    .replace(/^width = 640$/m, 'width = 320')
    .replace(/^height = 480$/m, 'height = 240');
  check(resized === page, 'web/scene.toml is examples/scenes/demo.toml at 320×240');
}

function reference(c, ...more) {
  const out = path.join(tmp, `${path.basename(c.scene)}-${c.k}.rgba`);
  const stdout = execFileSync(
    'cargo',
    [
      'run', '--release', '--quiet', '--manifest-path', path.join(web, 'Cargo.toml'),
      '--bin', 'reference', '--',
      path.join(root, c.scene), String(c.k), String(c.n), String(c.degrees), out, ...more,
    ],
    { encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] },
  );
  const [width, height] = stdout.split('\n')[0].split(' ').map(Number);
  return { width, height, rgba: fs.readFileSync(out), stdout };
}

// How two RGBA images differ: the count of differing bytes and the first differing pixels.
function compare(got, want, width) {
  let bytes = 0;
  const pixels = [];
  for (let i = 0; i < Math.max(got.length, want.length); i++) {
    if (got[i] === want[i]) continue;
    bytes += 1;
    const p = i >> 2;
    if (pixels.length < 5 && pixels.at(-1)?.p !== p) {
      const at = (b) => `[${[...b.subarray(4 * p, 4 * p + 4)]}]`;
      pixels.push({ p, text: `(${p % width}, ${Math.floor(p / width)}) canvas ${at(got)} host ${at(want)}` });
    }
  }
  return { bytes, pixels: pixels.map((x) => x.text) };
}

// The comparison itself must see a single changed byte.
{
  const a = Buffer.alloc(64, 7);
  const b = Buffer.from(a);
  b[41] ^= 1;
  check(compare(a, b, 4).bytes === 1, 'the comparison finds one changed byte');
}

// A static server for the repository, so that the page can fetch tests/data's scenes.
const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.wasm': 'application/wasm',
  '.toml': 'text/plain; charset=utf-8',
};
const server = http.createServer((req, res) => {
  const file = path.join(root, decodeURIComponent(new URL(req.url, 'http://localhost').pathname));
  if (!file.startsWith(root + path.sep)) {
    res.writeHead(403).end();
    return;
  }
  fs.readFile(file, (err, data) => {
    if (err) {
      res.writeHead(404).end();
      return;
    }
    const type = TYPES[path.extname(file)] ?? 'application/octet-stream';
    res.writeHead(200, { 'content-type': type, 'cache-control': 'no-store' }).end(data);
  });
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
const base = `http://127.0.0.1:${server.address().port}/web/index.html`;

// Flags for a machine with no network but loopback: nothing in the background, a fresh profile.
const context = await chromium.launchPersistentContext(path.join(tmp, 'profile'), {
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: [
    '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync',
  ],
});

async function open(query) {
  const page = await context.newPage();
  page.on('pageerror', (e) => console.log(`  page error: ${e.message}`));
  page.on('console', (m) => m.type() === 'error' && console.log(`  console: ${m.text()}`));
  await page.goto(base + query);
  return page;
}

try {
  for (const c of CASES) {
    const name = `${c.scene}, frame ${c.k} of ${c.n} (orbit ${c.degrees}°)`;
    const want = reference(c);
    const page = await open(`?${c.query}frame=${c.k}&frames=${c.n}&orbit=${c.degrees}&still`);
    await page.waitForFunction(() => document.body.dataset.rendered || document.body.dataset.error,
      null, { timeout: 120_000 });
    const error = await page.evaluate(() => document.body.dataset.error);
    if (error) {
      check(false, `${name}: the page failed: ${error}`);
      continue;
    }
    const got = await page.evaluate(() => {
      const canvas = document.getElementById('view');
      const ctx = canvas.getContext('2d', { colorSpace: 'srgb', willReadFrequently: true });
      const data = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
      let s = '';
      for (let i = 0; i < data.length; i += 0x8000) {
        s += String.fromCharCode(...data.subarray(i, i + 0x8000));
      }
      return { width: canvas.width, height: canvas.height, rgba: btoa(s) };
    });
    await page.close();
    const rgba = Buffer.from(got.rgba, 'base64');
    const size = `${got.width}×${got.height}`;
    if (got.width !== want.width || got.height !== want.height) {
      check(false, `${name}: canvas ${size}, host ${want.width}×${want.height}`);
      continue;
    }
    const diff = compare(rgba, want.rgba, want.width);
    check(diff.bytes === 0,
      `${name}, ${size}: ${diff.bytes} of ${want.rgba.length} bytes differ from the host's`);
    for (const p of diff.pixels) console.log(`     ${p}`);
  }

  // The animated page: its median time a frame, then an invalid edit.
  const demo = CASES[1];
  const page = await open(`?frames=${demo.n}&orbit=${demo.degrees}`);
  // Past the first frames, while the engine compiles the module's hot code.
  await page.waitForFunction(() => Number(document.body.dataset.drawn) >= 30, null,
    { timeout: 300_000 });
  const median = await page.evaluate(() => document.body.dataset.medianMs);

  const bad = (await page.inputValue('#scene')).replace('radius = 1000000.0', 'radius = -1');
  await page.fill('#scene', bad);
  await page.waitForFunction(() => document.getElementById('error').textContent !== '', null,
    { timeout: 10_000 });
  const shown = await page.textContent('#error');
  check(/^line \d+: sphere\[0\]\.radius: /.test(shown), `an invalid edit is shown: "${shown}"`);
  const drawn = Number(await page.evaluate(() => document.body.dataset.drawn));
  const goesOn = await page
    .waitForFunction((n) => Number(document.body.dataset.drawn) > n + 2, drawn, { timeout: 10_000 })
    .then(() => true, () => false);
  check(goesOn, 'the last good scene keeps turning');
  await page.close();

  // The desktop renderer's animated PNG, decoded by Chromium's own image decoder: 36 frames
  // that move, frame 5 byte for byte the host's (the page's default scene is the demo at the
  // renderer's size, so the same reference serves).
  const apng = path.join(root, 'target', 'web-test-orbit.png');
  execFileSync('cargo', [
    'run', '--release', '--quiet', '--manifest-path', path.join(root, 'Cargo.toml'),
    '--example', 'render', '--', path.join(root, 'examples/scenes/demo.toml'),
    '--frames', '36', '--width', '320', '--height', '240', '-o', apng,
  ], { stdio: ['ignore', 'ignore', 'inherit'] });
  const viewer = await open('');
  const decoded = await viewer.evaluate(async (url) => {
    const data = await (await fetch(url)).arrayBuffer();
    const decoder = new ImageDecoder({ data, type: 'image/png' });
    await decoder.tracks.ready;
    const track = decoder.tracks.selectedTrack;
    const frame = async (k) => {
      const { image } = await decoder.decode({ frameIndex: k });
      const canvas = new OffscreenCanvas(image.displayWidth, image.displayHeight);
      const ctx = canvas.getContext('2d', { colorSpace: 'srgb', willReadFrequently: true });
      ctx.drawImage(image, 0, 0);
      image.close();
      const px = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
      let s = '';
      for (let i = 0; i < px.length; i += 0x8000) s += String.fromCharCode(...px.subarray(i, i + 0x8000));
      return btoa(s);
    };
    return { animated: track.animated, frames: track.frameCount, first: await frame(0), fifth: await frame(5), middle: await frame(18) };
  }, `/target/${path.basename(apng)}`);
  await viewer.close();
  check(decoded.animated && decoded.frames === 36,
    `the renderer's orbit opens in Chromium as an animation: ${decoded.frames} frames`);
  const [first, fifth, middle] = [decoded.first, decoded.fifth, decoded.middle]
    .map((b) => Buffer.from(b, 'base64'));
  check(compare(first, middle, 320).bytes > 0, 'its frames 0 and 18 differ');
  const want = reference(CASES[1]);
  const diff = compare(fifth, want.rgba, want.width);
  check(diff.bytes === 0, `its frame 5: ${diff.bytes} of ${want.rgba.length} bytes differ from the host's`);
  fs.rmSync(apng, { force: true });

  // The host's time once the page is closed, so that the two do not share the cores.
  const host = reference(demo, '--repeat', '36').stdout.split('\n')[1];
  console.log(`time a frame, demo 320×240: Chromium ${median} ms (median of 15 frames);` +
    ` host, one thread: ${host}`);
} finally {
  await context.close();
  server.close();
  fs.rmSync(tmp, { recursive: true, force: true });
}

if (failures > 0) {
  console.log(`${failures} check(s) failed`);
  process.exit(1);
}
